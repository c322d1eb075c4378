//! Serialized FMU state: a versioned, self-describing byte format.
//!
//! Layout (all integers little-endian):
//!
//! | bytes | content                                             |
//! |-------|-----------------------------------------------------|
//! | 8     | magic `GWSTATE\0`                                   |
//! | 4     | format version (`FORMAT_VERSION`)                   |
//! | 4     | n = length of the model GUID                        |
//! | n     | model GUID (UTF-8)                                  |
//! | 32    | SHA-256 of the payload                              |
//! | 8     | m = length of the payload                           |
//! | m     | payload: MessagePack with field names (self-describing) |
//!
//! Floats are stored bit-exactly, so a restored state continues
//! bit-identically.

use serde::{de::DeserializeOwned, Serialize};
use sha2::{Digest, Sha256};

pub const MAGIC: &[u8; 8] = b"GWSTATE\0";
// Version 2: the physics state holds lists of bodies and contacts.
// Version 3: each contact's status (open or closed, gap, last impact) and
// the energy lost in impacts.
// Version 4: each vehicle's applied force (the state's `vehicle_forces`,
// the model's inputs two per vehicle).
pub const FORMAT_VERSION: u32 = 4;

pub fn encode<T: Serialize>(guid: &str, payload: &T) -> Result<Vec<u8>, String> {
    let body = rmp_serde::to_vec_named(payload).map_err(|e| format!("cannot encode state: {e}"))?;
    let mut out = Vec::with_capacity(body.len() + 96);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(guid.len() as u32).to_le_bytes());
    out.extend_from_slice(guid.as_bytes());
    out.extend_from_slice(&Sha256::digest(&body));
    out.extend_from_slice(&(body.len() as u64).to_le_bytes());
    out.extend_from_slice(&body);
    Ok(out)
}

struct Reader<'a> {
    bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        if self.bytes.len() < n {
            return Err(format!("serialized state truncated in {what}"));
        }
        let (head, tail) = self.bytes.split_at(n);
        self.bytes = tail;
        Ok(head)
    }
    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4, what)?.try_into().unwrap()))
    }
    fn u64(&mut self, what: &str) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8, what)?.try_into().unwrap()))
    }
}

/// Decode bytes written by `encode` for the model `guid`. Foreign bytes,
/// another format version, another model and corrupted bytes are refused.
pub fn decode<T: DeserializeOwned>(guid: &str, bytes: &[u8]) -> Result<T, String> {
    let mut r = Reader { bytes };
    if r.take(8, "magic")? != MAGIC {
        return Err("not a guideway FMU state (bad magic bytes)".into());
    }
    let version = r.u32("format version")?;
    if version != FORMAT_VERSION {
        return Err(format!(
            "serialized state has format version {version}, this FMU reads version {FORMAT_VERSION}"
        ));
    }
    let n = r.u32("GUID length")? as usize;
    let their_guid = r.take(n, "GUID")?;
    if their_guid != guid.as_bytes() {
        return Err(format!(
            "serialized state belongs to model {}, this is model {guid}",
            String::from_utf8_lossy(their_guid)
        ));
    }
    let checksum = r.take(32, "checksum")?;
    let m = r.u64("payload length")?;
    if m != r.bytes.len() as u64 {
        return Err(format!(
            "serialized state payload is {} bytes, header says {m}",
            r.bytes.len()
        ));
    }
    let body = r.bytes;
    if Sha256::digest(body).as_slice() != checksum {
        return Err("serialized state is corrupted (checksum mismatch)".into());
    }
    rmp_serde::from_slice(body).map_err(|e| format!("cannot decode serialized state: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_is_bit_exact() {
        let v = (0.1f64 + 0.2, f64::MIN_POSITIVE / 3.0, -0.0f64);
        let bytes = encode("g1", &v).unwrap();
        let back: (f64, f64, f64) = decode("g1", &bytes).unwrap();
        assert_eq!(v.0.to_bits(), back.0.to_bits());
        assert_eq!(v.1.to_bits(), back.1.to_bits());
        assert_eq!(v.2.to_bits(), back.2.to_bits());
    }

    #[test]
    fn foreign_other_version_other_model_and_corrupt_bytes_are_refused() {
        let bytes = encode("g1", &1.5f64).unwrap();
        assert!(decode::<f64>("g2", &bytes).unwrap_err().contains("model"));
        assert!(decode::<f64>("g1", b"hello world, not a state")
            .unwrap_err()
            .contains("magic"));
        let mut v2 = bytes.clone();
        v2[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
        assert!(decode::<f64>("g1", &v2).unwrap_err().contains("version"));
        let mut bad = bytes.clone();
        *bad.last_mut().unwrap() ^= 1;
        assert!(decode::<f64>("g1", &bad).unwrap_err().contains("checksum"));
        for n in 0..bytes.len() {
            assert!(decode::<f64>("g1", &bytes[..n]).is_err());
        }
    }
}
