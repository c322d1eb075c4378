//! Reading an input file the user names (scene, profile table, changelog,
//! vehicle FMU): regular files only, never more than a stated number of
//! bytes, so that a named pipe, a device such as `/dev/zero` or a growing
//! file can neither hang a command nor take its memory.

use std::io::Read;
use std::path::Path;

/// Largest FMU read to wire an SSP system (its model description is all
/// that is used; an FMU with large resources is still far below this).
pub const MAX_FMU_BYTES: u64 = 1_000_000_000;

/// Largest changelog `release` reads.
pub const MAX_CHANGELOG_BYTES: u64 = 10_000_000;

/// The bytes of `path`, refused (naming the path and the rule, never its
/// contents) if it is not a regular file or holds more than `limit` bytes.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let shown = path.display();
    check_regular(path).map_err(|why| format!("cannot read {shown}: {why}"))?;
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
    let opened = file
        .metadata()
        .map_err(|e| format!("cannot read {shown}: {e}"))?;
    if !opened.is_file() {
        return Err(format!("cannot read {shown}: it is not a regular file"));
    }
    if opened.len() > limit {
        return Err(too_large(path, opened.len(), limit));
    }
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read {shown}: {e}"))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(path, bytes.len() as u64, limit));
    }
    Ok(bytes)
}

/// Refuse (saying why) a path that is not a regular file. Checked before
/// opening: opening a named pipe blocks until a writer comes, for ever if
/// none does.
pub fn check_regular(path: &Path) -> Result<(), String> {
    let kind = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if kind.is_file() {
        Ok(())
    } else {
        Err(
            "it is not a regular file (a directory, named pipe, socket or device); give the \
             path of a file"
                .into(),
        )
    }
}

/// `read_bounded` as UTF-8 text.
pub fn read_text_bounded(path: &Path, limit: u64) -> Result<String, String> {
    String::from_utf8(read_bounded(path, limit)?)
        .map_err(|e| format!("cannot read {}: not UTF-8 text ({e})", path.display()))
}

fn too_large(path: &Path, bytes: u64, limit: u64) -> String {
    format!(
        "cannot read {}: it holds {bytes} bytes or more, above the limit of {limit} bytes",
        path.display()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_read_and_devices_directories_and_large_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.txt");
        std::fs::write(&file, "abc").unwrap();
        assert_eq!(read_bounded(&file, 3).unwrap(), b"abc");
        assert!(read_bounded(&file, 2)
            .unwrap_err()
            .contains("limit of 2 bytes"));
        assert!(read_bounded(dir.path(), 10)
            .unwrap_err()
            .contains("not a regular file"));
        let zero = read_bounded(Path::new("/dev/zero"), 10).unwrap_err();
        assert!(zero.contains("not a regular file"), "{zero}");
    }
}
