//! An `f64` written as Rust's `{:?}` writes it (the CSV's number format:
//! the shortest decimal that reads back to the same bits, `0.1`, `1e-7`,
//! `-0.0`), from the shortest digits `zmij` finds: the same text at a
//! fraction of `core::fmt`'s cost (the formatting was most of a CSV
//! run's instructions).

use std::fmt::Write as _;

/// Below this magnitude (and not zero) and from `EXPONENTIAL_FROM` on,
/// `{:?}` writes a real in exponential form (`core::fmt::float`).
const EXPONENTIAL_BELOW: f64 = 1e-4;
const EXPONENTIAL_FROM: f64 = 1e16;

/// From this magnitude on, std writes the value (zmij's interval test
/// and std's could differ where a bound of the rounding interval is a
/// short decimal: an integer of 2⁵¹ or more).
const LARGE: f64 = 2251799813685248.0;

/// Append `value` to `line` as `format!("{value:?}")` would. zmij's
/// positional text (`12.34`, `0.001234`, `1234000.0`) is `{:?}`'s where
/// both write the value positionally; its exponential text (`1.234e+33`,
/// `5e-07`) is `{:?}`'s (`1.234e33`, `5e-7`) but for the exponent's sign
/// and zeros; where the two choose different forms, the digits are
/// rewritten (`rewritten`).
pub fn push_debug(line: &mut Vec<u8>, value: f64) {
    if value == 0.0 {
        let zero: &[u8] = if value.is_sign_negative() {
            b"-0.0"
        } else {
            b"0.0"
        };
        line.extend_from_slice(zero);
        return;
    }
    if std_decides(value) {
        // NaN, inf, subnormals, the large, ties (rare in a run): std's own.
        let mut text = String::new();
        let _ = write!(text, "{value:?}");
        line.extend_from_slice(text.as_bytes());
        return;
    }
    let mut buffer = zmij::Buffer::new();
    let text = buffer.format_finite(value).as_bytes();
    let magnitude = value.abs();
    let positional = (EXPONENTIAL_BELOW..EXPONENTIAL_FROM).contains(&magnitude);
    // The exponent, where there is one, is the text's last 4 or 5 bytes.
    let tail = text.len().saturating_sub(5);
    let e = (text[tail..].iter())
        .position(|&b| b == b'e')
        .map(|k| tail + k);
    match (positional, e) {
        (true, None) => line.extend_from_slice(text),
        // A sign and at least one digit after the `e`.
        (false, Some(e)) if text.len() >= e + 3 => {
            line.extend_from_slice(&text[..=e]);
            let (sign, digits) = text[e + 1..].split_at(1);
            if sign == b"-" {
                line.push(b'-');
            }
            let zeros = digits.iter().take_while(|&&d| d == b'0').count();
            line.extend_from_slice(&digits[zeros.min(digits.len() - 1)..]);
        }
        _ => rewritten(line, value, text),
    }
}

/// `value` in `{:?}`'s form from the digits of zmij's `text` of it, where
/// zmij chose the other form (a value in [1e-5, 1e-4)).
fn rewritten(line: &mut Vec<u8>, value: f64, text: &[u8]) {
    let unsigned = text.strip_prefix(b"-").unwrap_or(text);
    let Some((digits, point)) = std::str::from_utf8(unsigned).ok().and_then(decimal) else {
        let mut text = String::new();
        let _ = write!(text, "{value:?}");
        line.extend_from_slice(text.as_bytes());
        return;
    };
    if value < 0.0 {
        line.push(b'-');
    }
    let magnitude = value.abs();
    if !(EXPONENTIAL_BELOW..EXPONENTIAL_FROM).contains(&magnitude) {
        exponential(line, &digits, point);
    } else {
        positional(line, &digits, point);
    }
}

/// Whether std writes `value` (`push_debug`): where it is not a normal
/// number below `LARGE`, or where the shortest digits may be a tie between
/// two candidates, which zmij and std break differently (`1500000000000000.25`:
/// `.2` and `.3`). A tie at L digits is a value of exactly L + 1
/// significant digits (the candidates' midpoint), L ≤ 17: m·2⁻ᵏ with m odd
/// has the digits of m·5ᵏ, at least 19 where k ≥ 26 or m·5ᵏ ≥ 10¹⁸. An
/// integer below 2⁵¹ is its own shortest text, without a tie.
fn std_decides(value: f64) -> bool {
    let magnitude = value.abs();
    if !(f64::MIN_POSITIVE..LARGE).contains(&magnitude) {
        return true;
    }
    let bits = magnitude.to_bits();
    let significand = (bits & ((1 << 52) - 1)) | (1 << 52);
    let zeros = significand.trailing_zeros();
    let (odd, power) = (
        significand >> zeros,
        (bits >> 52) as i32 - 1075 + zeros as i32,
    );
    let k = -power;
    (1..26).contains(&k) && u128::from(odd) * 5u128.pow(k as u32) < 10u128.pow(18)
}

/// The significant digits (no leading or trailing zeros) and the decimal
/// point's place p (the value is 0.d₁d₂… × 10^p) of zmij's text of a
/// positive finite non-zero value (`12.34`, `0.001234`, `1234000.0`,
/// `1.234e+33`, `5e-07`); `None` for any other text.
fn decimal(text: &str) -> Option<(Digits, i32)> {
    let (mantissa, exponent) = match text.split_once('e') {
        Some((mantissa, exponent)) => (mantissa, exponent.parse::<i32>().ok()?),
        None => (text, 0),
    };
    let mut digits = Digits::default();
    let mut point = None;
    for &byte in mantissa.as_bytes() {
        match byte {
            b'.' if point.is_none() => point = Some(digits.len as i32),
            // A leading zero after the point moves it left (0.00123).
            b'0' if digits.len == 0 => point = point.map(|p| p - 1),
            b'0'..=b'9' => digits.push(byte)?,
            _ => return None,
        }
    }
    let point = point.unwrap_or(digits.len as i32) + exponent;
    digits.trim_trailing_zeros();
    (digits.len > 0).then_some((digits, point))
}

/// The significant digits of a value (an `f64`'s shortest has at most
/// 17; a positional text pads them with zeros).
#[derive(Default)]
struct Digits {
    bytes: [u8; 32],
    len: usize,
}

impl Digits {
    /// Append a digit; `None` where there is no room.
    fn push(&mut self, byte: u8) -> Option<()> {
        *self.bytes.get_mut(self.len)? = byte;
        self.len += 1;
        Some(())
    }

    fn trim_trailing_zeros(&mut self) {
        while self.len > 0 && self.bytes[self.len - 1] == b'0' {
            self.len -= 1;
        }
    }

    fn as_slice(&self) -> &[u8] {
        &self.bytes[..self.len]
    }
}

/// d₁[.d₂…]e<p − 1>, as `{:?}` writes a tiny or huge value.
fn exponential(line: &mut Vec<u8>, digits: &Digits, point: i32) {
    let digits = digits.as_slice();
    line.push(digits[0]);
    if digits.len() > 1 {
        line.push(b'.');
        line.extend_from_slice(&digits[1..]);
    }
    line.push(b'e');
    line.extend_from_slice(itoa::Buffer::new().format(point - 1).as_bytes());
}

/// The digits with the point in its place and at least one digit after
/// it (`0.00123`, `12.5`, `1200.0`), as `{:?}` writes the others.
fn positional(line: &mut Vec<u8>, digits: &Digits, point: i32) {
    let digits = digits.as_slice();
    let n = digits.len() as i32;
    if point <= 0 {
        line.extend_from_slice(b"0.");
        line.extend(std::iter::repeat_n(b'0', (-point) as usize));
        line.extend_from_slice(digits);
    } else if point < n {
        let (whole, fraction) = digits.split_at(point as usize);
        line.extend_from_slice(whole);
        line.push(b'.');
        line.extend_from_slice(fraction);
    } else {
        line.extend_from_slice(digits);
        line.extend(std::iter::repeat_n(b'0', (point - n) as usize));
        line.extend_from_slice(b".0");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_chacha::rand_core::{RngCore, SeedableRng};

    fn text(value: f64) -> String {
        let mut line = Vec::new();
        push_debug(&mut line, value);
        String::from_utf8(line).expect("ASCII")
    }

    /// Every value written is std's `{:?}` text, byte for byte (std's
    /// formatter is the reference): the limits of both forms and their
    /// neighbours, powers of ten, the specials, subnormals, and a million
    /// random bit patterns and random short decimals.
    #[test]
    fn every_value_is_written_as_debug_writes_it() {
        let mut values = vec![
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            f64::EPSILON,
            5e-324,
            -5e-324,
            f64::from_bits(0x000f_ffff_ffff_ffff), // the largest subnormal
            0.1,
            0.3,
            1.0 / 3.0,
            123456789012345680.0,
            9007199254740993.0,
            1500000000000000.0 + 0.25, // a tie: `.2` or `.3`
            1.0 + 2f64.powi(-17),
            0.5 + 2f64.powi(-18),
            LARGE,
            f64::from_bits(LARGE.to_bits() - 1),
        ];
        // Short binary fractions: the ties' kind.
        for k in 1..40 {
            for odd in [1u64, 3, 12345, 999_999_999, (1 << 52) + 1, (1 << 53) - 1] {
                let x = odd as f64 * 2f64.powi(-k);
                values.extend([x, x * 1e3, x + 1.0, x + 4201.0]);
            }
        }
        for e in -324..=308 {
            let p: f64 = format!("1e{e}").parse().expect("a power of ten");
            for x in [p, 1.5 * p, 9.999999999999999 * p, 0.99999 * p] {
                values.extend([x, -x, f64::from_bits(x.to_bits() + 1)]);
                values.push(f64::from_bits(x.to_bits().saturating_sub(1)));
            }
        }
        for limit in [EXPONENTIAL_BELOW, EXPONENTIAL_FROM] {
            for step in 0..4u64 {
                values.push(f64::from_bits(limit.to_bits() + step));
                values.push(f64::from_bits(limit.to_bits() - step));
            }
        }
        let mut random = rand_chacha::ChaCha8Rng::seed_from_u64(29);
        for _ in 0..1_000_000 {
            values.push(f64::from_bits(random.next_u64()));
            let mantissa = (random.next_u64() % 100_000) as f64;
            let exponent = (random.next_u64() % 40) as i32 - 20;
            values.push(mantissa * 10f64.powi(exponent));
        }
        for value in values {
            assert_eq!(
                text(value),
                format!("{value:?}"),
                "bits {:#x}",
                value.to_bits()
            );
        }
    }
}
