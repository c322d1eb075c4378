//! Output files written whole or not at all: each is written to a temporary
//! file in its own directory and renamed onto its path only when complete,
//! so a failed or interrupted command never leaves a partial file in place
//! of the previous good one (the rename is atomic within a directory).

use std::fs::File;
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

/// An output file being written: a temporary file beside `path`, created
/// at once, so that an unwritable place is known before any work is done.
/// Dropped without `commit`, the temporary file is removed.
pub struct Staged {
    path: PathBuf,
    temp: NamedTempFile,
}

impl Staged {
    /// Stage `path`: refuse a directory, or a parent that is not a writable
    /// directory.
    pub fn new(path: &Path) -> Result<Staged, String> {
        let cannot = |why: String| format!("cannot write {}: {why}", path.display());
        if path.is_dir() {
            return Err(cannot("it is a directory".into()));
        }
        let dir = parent_dir(path);
        if !dir.is_dir() {
            return Err(cannot(format!("{} is not a directory", dir.display())));
        }
        let name = path
            .file_name()
            .map_or("output".into(), |n| n.to_string_lossy());
        // Same extension as the final file: the plot's encoder picks the
        // format from it.
        let suffix = path
            .extension()
            .map_or(String::new(), |e| format!(".{}", e.to_string_lossy()));
        let temp = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(&suffix)
            .tempfile_in(dir)
            .map_err(|e| cannot(e.to_string()))?;
        Ok(Staged {
            path: path.to_path_buf(),
            temp,
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Where the content goes until `commit`.
    pub fn temp_path(&self) -> &Path {
        self.temp.path()
    }

    /// A handle on the temporary file, for writing.
    pub fn file(&self) -> Result<File, String> {
        self.temp
            .as_file()
            .try_clone()
            .map_err(|e| format!("cannot write {}: {e}", self.path.display()))
    }

    /// Move the written file onto its path.
    pub fn commit(self) -> Result<PathBuf, String> {
        let path = self.path.clone();
        self.commit_as(&path)
    }

    /// Move the written file onto `path` instead (e.g. `<path>.incomplete`).
    pub fn commit_as(self, path: &Path) -> Result<PathBuf, String> {
        let cannot = |e: String| format!("cannot write {}: {e}", path.display());
        // tempfile creates files readable by the owner only; an output is
        // an ordinary file.
        set_mode_0644(self.temp.path()).map_err(|e| cannot(e.to_string()))?;
        self.temp
            .persist(path)
            .map_err(|e| cannot(e.error.to_string()))?;
        Ok(path.to_path_buf())
    }
}

#[cfg(unix)]
fn set_mode_0644(path: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o644))
}

#[cfg(not(unix))]
fn set_mode_0644(_: &Path) -> std::io::Result<()> {
    Ok(())
}

/// The directory a file path is in (`.` for a bare file name).
pub fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    }
}

/// Whether two paths name the same file, existing or not: the same inode if
/// both exist (hard links, symbolic links), else the same canonical
/// directory and file name.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    match (resolved(a), resolved(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// The canonical path of `path`, or of its directory joined with its name
/// when the file does not exist yet.
fn resolved(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let dir = parent_dir(path).canonicalize().ok()?;
    Some(dir.join(path.file_name()?))
}

/// Refuse an output path equal to an input or to another output. Each
/// entry is (what it is, e.g. `--out`, its path).
pub fn check_distinct(inputs: &[(&str, &Path)], outputs: &[(&str, &Path)]) -> Result<(), String> {
    for (k, (what, path)) in outputs.iter().enumerate() {
        for (input, input_path) in inputs {
            if same_file(path, input_path) {
                return Err(format!(
                    "{what} {} is the {input} {}: it would be overwritten; choose another path",
                    path.display(),
                    input_path.display()
                ));
            }
        }
        for (other, other_path) in &outputs[..k] {
            if same_file(path, other_path) {
                return Err(format!(
                    "{what} {} is the same file as {other} {}: one would overwrite the other",
                    path.display(),
                    other_path.display()
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_committed_file_replaces_the_old_one_and_an_abandoned_one_leaves_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        std::fs::write(&path, "old").unwrap();
        let staged = Staged::new(&path).unwrap();
        std::fs::write(staged.temp_path(), "new, abandoned").unwrap();
        drop(staged);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "temp removed"
        );

        let staged = Staged::new(&path).unwrap();
        std::fs::write(staged.temp_path(), "new").unwrap();
        staged.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
    }

    #[test]
    fn the_same_file_is_recognised_through_other_spellings() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.toml");
        std::fs::write(&a, "x").unwrap();
        let other_spelling = dir.path().join(".").join("a.toml");
        assert!(same_file(&a, &other_spelling));
        let missing = dir.path().join("b.csv");
        assert!(same_file(&missing, &dir.path().join("./b.csv")));
        assert!(!same_file(&a, &missing));
        let err = check_distinct(&[("scene", &a)], &[("--out", &other_spelling)]).unwrap_err();
        assert!(err.contains("is the scene"), "{err}");
        let err = check_distinct(&[], &[("--out", &missing), ("--summary", &missing)]).unwrap_err();
        assert!(err.contains("same file as --out"), "{err}");
    }
}
