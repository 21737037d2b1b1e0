//! Atomic output files: written to a hidden temporary file in the target's folder and
//! renamed over the target only when complete.

use crate::IoError;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use tempfile::{NamedTempFile, TempPath};

/// A file written under a temporary name `.<name>.partial-XXXXXX` beside `path` and renamed
/// to `path` by [`AtomicFile::commit`]; dropped without `commit`, the temporary file is
/// deleted and `path` is left as it was. Writes are buffered.
#[derive(Debug)]
pub struct AtomicFile {
    file: BufWriter<NamedTempFile>,
    path: PathBuf,
}

impl AtomicFile {
    /// Creates the temporary file for `path` (creating missing parent folders).
    pub fn create(path: &Path) -> Result<Self, IoError> {
        let file = temporary_file_for(path, "")?;
        Ok(Self {
            file: BufWriter::new(file),
            path: path.to_path_buf(),
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes, syncs and renames the temporary file to the final path.
    pub fn commit(self) -> Result<(), IoError> {
        let io = |source| IoError::new(&self.path, source);
        let file = self.file.into_inner().map_err(|e| io(e.into_error()))?;
        file.as_file().sync_all().map_err(io)?;
        file.persist(&self.path).map_err(|e| io(e.error))?;
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.file.write(buf)
    }
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.file.write_all(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

impl Seek for AtomicFile {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        self.file.seek(pos)
    }
}

/// A temporary path for writers that open the file themselves (plot backends, the Rerun
/// SDK): it keeps the target's extension (backends pick the format from it), is deleted
/// when dropped, and [`AtomicPath::commit`] syncs it and renames it over the target.
#[derive(Debug)]
pub struct AtomicPath {
    temporary: TempPath,
    path: PathBuf,
}

impl AtomicPath {
    /// Reserves the temporary path for `path` (creating missing parent folders).
    pub fn create(path: &Path) -> Result<Self, IoError> {
        let suffix = path
            .extension()
            .map(|e| format!(".{}", e.to_string_lossy()))
            .unwrap_or_default();
        let temporary = temporary_file_for(path, &suffix)?.into_temp_path();
        Ok(Self {
            temporary,
            path: path.to_path_buf(),
        })
    }

    /// Where the writer writes.
    pub fn temporary(&self) -> &Path {
        &self.temporary
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Syncs the written temporary file and renames it to the final path.
    pub fn commit(self) -> Result<(), IoError> {
        let io = |source| IoError::new(&self.path, source);
        std::fs::File::open(&self.temporary)
            .and_then(|f| f.sync_all())
            .map_err(io)?;
        self.temporary.persist(&self.path).map_err(|e| io(e.error))
    }
}

/// Writes `path` atomically: `write` fills the temporary file, which replaces `path` only if
/// `write` succeeds.
pub fn write_atomically<F>(path: &Path, write: F) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let mut file = AtomicFile::create(path)?;
    write(&mut file).map_err(|e| IoError::new(path, e))?;
    file.commit()
}

/// Creates `dir` (and its parents) if it does not exist.
pub fn create_dir(dir: &Path) -> Result<(), IoError> {
    std::fs::create_dir_all(dir).map_err(|e| IoError::new(dir, e))
}

/// A new empty file `.<name>.partial-XXXXXX<suffix>` in `path`'s folder (created if
/// needed), deleted when dropped.
fn temporary_file_for(path: &Path, suffix: &str) -> Result<NamedTempFile, IoError> {
    let io = |source| IoError::new(path, source);
    let name = path.file_name().ok_or_else(|| {
        io(io::Error::new(
            io::ErrorKind::InvalidInput,
            "not a file name",
        ))
    })?;
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    create_dir(dir)?;
    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(name);
    prefix.push(".partial-");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(suffix);
    // Temporary files are private (0600) by default; an output file gets what a plain
    // `File::create` would give it, read-write for all less the umask.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    builder
        .tempfile_in(dir)
        .map_err(|e| io(without_temporary_path(e)))
}

/// The operating system's error without the temporary file's path that `tempfile` appends
/// (`… at path "…partial-…"`): the user named the final path, which the error carries.
fn without_temporary_path(e: io::Error) -> io::Error {
    let text = e.to_string();
    match text.rfind(" at path ") {
        Some(end) => io::Error::new(e.kind(), &text[..end]),
        None => e,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dropped_file_leaves_nothing_and_a_committed_one_replaces_the_target() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        std::fs::write(&path, "old").unwrap();
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"new").unwrap();
        drop(file);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        write_atomically(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        let failed = write_atomically(&path, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("disk full"))
        });
        assert!(failed.unwrap_err().to_string().contains("disk full"));
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn an_atomic_path_keeps_the_extension_and_commits() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("map.png");
        let reserved = AtomicPath::create(&path).unwrap();
        assert_eq!(reserved.temporary().extension().unwrap(), "png");
        std::fs::write(reserved.temporary(), "png bytes").unwrap();
        assert!(!path.exists());
        reserved.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "png bytes");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
