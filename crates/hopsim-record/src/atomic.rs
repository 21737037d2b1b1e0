//! Atomic output files: everything is written to a hidden temporary file in the target's
//! folder and renamed over the target only when complete, so a failed or interrupted run
//! never leaves a file that looks complete (and never clobbers a good one half-way).

use crate::RecordError;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

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
    pub fn create(path: &Path) -> Result<Self, RecordError> {
        let file = temporary_file_for(path)?;
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
    pub fn commit(self) -> Result<(), RecordError> {
        let io = |source| RecordError::io(&self.path, source);
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

/// Writes `path` atomically: `write` fills the temporary file, which replaces `path` only if
/// `write` succeeds.
pub fn write_atomically<F>(path: &Path, write: F) -> Result<(), RecordError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let mut file = AtomicFile::create(path)?;
    write(&mut file).map_err(|e| RecordError::io(path, e))?;
    file.commit()
}

/// A new empty file `.<name>.partial-XXXXXX` in `path`'s folder (created if needed), deleted
/// when dropped; [`NamedTempFile::into_temp_path`] serves writers that open it themselves.
pub(crate) fn temporary_file_for(path: &Path) -> Result<NamedTempFile, RecordError> {
    let io = |source| RecordError::io(path, source);
    let name = path
        .file_name()
        .ok_or_else(|| RecordError::format(path, "not a file name"))?;
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir).map_err(io)?;
    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(name);
    prefix.push(".partial-");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix);
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
