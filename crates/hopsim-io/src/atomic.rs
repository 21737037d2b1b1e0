//! Atomic output files: written to a hidden temporary file in the target's folder and
//! renamed over the target only when complete.

use crate::IoError;
use std::collections::BTreeSet;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use tempfile::{NamedTempFile, TempPath};

/// Every temporary file that exists now (created, neither committed nor dropped), so that a
/// process ending on a signal can delete them ([`remove_temporary_files`]).
static LIVE: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());

fn live() -> std::sync::MutexGuard<'static, BTreeSet<PathBuf>> {
    LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Deletes every temporary output file of this process that is not committed yet. For a
/// process about to exit on a signal: its outputs are then left as they were before.
pub fn remove_temporary_files() {
    for path in std::mem::take(&mut *live()) {
        let _ = std::fs::remove_file(path);
    }
}

/// A temporary file's registration in [`LIVE`]; dropping it unregisters the path.
#[derive(Debug)]
struct Registered(PathBuf);

impl Registered {
    fn new(path: &Path) -> Self {
        live().insert(path.to_path_buf());
        Registered(path.to_path_buf())
    }
}

impl Drop for Registered {
    fn drop(&mut self) {
        live().remove(&self.0);
    }
}

/// A file written under a temporary name `.<name>.partial-<pid>-XXXXXX` beside `path` and renamed
/// to `path` by [`AtomicFile::commit`]; dropped without `commit`, the temporary file is
/// deleted and `path` is left as it was. Writes are buffered.
#[derive(Debug)]
pub struct AtomicFile {
    file: BufWriter<NamedTempFile>,
    path: PathBuf,
    _registered: Registered,
}

impl AtomicFile {
    /// Creates the temporary file for `path` (creating missing parent folders).
    pub fn create(path: &Path) -> Result<Self, IoError> {
        let target = output_target(path)?;
        let file = temporary_file_for(&target, path, "")?;
        Ok(Self {
            _registered: Registered::new(file.path()),
            file: BufWriter::new(file),
            path: target,
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes, syncs and renames the temporary file to the final path.
    pub fn commit(self) -> Result<(), IoError> {
        let path = self.path.clone();
        self.persist_as(&path)
    }

    /// Flushes, syncs and renames the temporary file to the [`partial_path`] of the final
    /// path (what was written before a run stopped early); returns that path. The final
    /// path is left as it was.
    pub fn commit_partial(self) -> Result<PathBuf, IoError> {
        let partial = partial_path(&self.path);
        self.commit_as(&partial)
    }

    /// Flushes, syncs and renames the temporary file to `path` instead of the final path
    /// (which is left as it was); returns the file written (the target of a link at `path`).
    pub fn commit_as(self, path: &Path) -> Result<PathBuf, IoError> {
        let target = output_target(path)?;
        self.persist_as(&target)?;
        Ok(target)
    }

    fn persist_as(self, path: &Path) -> Result<(), IoError> {
        let io = |source| IoError::new(path, source);
        let file = self.file.into_inner().map_err(|e| io(e.into_error()))?;
        file.as_file().sync_all().map_err(io)?;
        file.persist(path).map_err(|e| io(e.error))?;
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
    _registered: Registered,
}

impl AtomicPath {
    /// Reserves the temporary path for `path` (creating missing parent folders).
    pub fn create(path: &Path) -> Result<Self, IoError> {
        let suffix = path
            .extension()
            .map(|e| format!(".{}", e.to_string_lossy()))
            .unwrap_or_default();
        let target = output_target(path)?;
        let temporary = temporary_file_for(&target, path, &suffix)?.into_temp_path();
        Ok(Self {
            _registered: Registered::new(&temporary),
            temporary,
            path: target,
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
        let path = self.path.clone();
        self.persist_as(&path)
    }

    /// Syncs the written temporary file and renames it to the [`partial_path`] of the
    /// final path; returns that path. The final path is left as it was.
    pub fn commit_partial(self) -> Result<PathBuf, IoError> {
        let partial = output_target(&partial_path(&self.path))?;
        self.persist_as(&partial)?;
        Ok(partial)
    }

    fn persist_as(self, path: &Path) -> Result<(), IoError> {
        let io = |source| IoError::new(path, source);
        std::fs::File::open(&self.temporary)
            .and_then(|f| f.sync_all())
            .map_err(io)?;
        self.temporary.persist(path).map_err(|e| io(e.error))
    }
}

/// Where the output `path` of a run that stopped early is kept: `.partial` before the
/// extension (`out/robbit.mcap` → `out/robbit.partial.mcap`, `run` → `run.partial`), a
/// name that cannot be mistaken for the complete output.
pub fn partial_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    let name = match path.extension() {
        Some(ext) => format!("{stem}.partial.{}", ext.to_string_lossy()),
        None => format!("{stem}.partial"),
    };
    path.with_file_name(name)
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

/// Creates `dir` (and its parents) if it does not exist; a file where a folder is needed
/// is named in the error.
pub fn create_dir(dir: &Path) -> Result<(), IoError> {
    std::fs::create_dir_all(dir).map_err(|e| {
        // The nearest existing ancestor that is not a folder, if any, is the cause.
        let blocker = dir
            .ancestors()
            .find(|a| std::fs::metadata(a).is_ok_and(|m| !m.is_dir()));
        match blocker {
            Some(file) => IoError::new(
                dir,
                io::Error::new(
                    io::ErrorKind::NotADirectory,
                    format!("cannot create this folder: `{}` is a file", file.display()),
                ),
            ),
            None => IoError::new(dir, e),
        }
    })
}

/// The file an output to `path` replaces: `path` itself, or the regular file a symbolic
/// link at `path` points to (the link stays). Anything else that exists there (a folder, a
/// device, a FIFO, a socket) is not ours to replace and is refused.
fn output_target(path: &Path) -> Result<PathBuf, IoError> {
    let Ok(meta) = std::fs::metadata(path) else {
        return Ok(path.to_path_buf());
    };
    if !meta.is_file() {
        let kind = file_kind(&meta.file_type());
        let message = format!(
            "is {kind}, not a regular file; outputs are written only to regular files (give a file path)"
        );
        return Err(IoError::new(
            path,
            io::Error::new(io::ErrorKind::InvalidInput, message),
        ));
    }
    let is_link = std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
    if is_link {
        return std::fs::canonicalize(path).map_err(|e| IoError::new(path, e));
    }
    Ok(path.to_path_buf())
}

/// What a non-regular file is, in words.
fn file_kind(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// Characters of the target's name kept in the temporary name, so that a long legal name
/// (up to the usual 255 bytes) still leaves room for the `.partial-<pid>-XXXXXX` decoration.
const TEMPORARY_NAME_CHARS: usize = 64;

/// A new empty file `.<name>.partial-<pid>-XXXXXX<suffix>` in `target`'s folder (created if
/// needed; `<name>` cut to [`TEMPORARY_NAME_CHARS`] characters), deleted when dropped.
/// Errors name `named`, the path the user gave.
fn temporary_file_for(target: &Path, named: &Path, suffix: &str) -> Result<NamedTempFile, IoError> {
    let io = |source| IoError::new(named, source);
    let name = target.file_name().ok_or_else(|| {
        io(io::Error::new(
            io::ErrorKind::InvalidInput,
            "not a file name",
        ))
    })?;
    let dir = match target.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    create_dir(dir)?;
    let short: String = name
        .to_string_lossy()
        .chars()
        .take(TEMPORARY_NAME_CHARS)
        .collect();
    remove_stale_temporary_files(dir, &short);
    let prefix = format!(".{short}.partial-{}-", std::process::id());
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

/// Deletes the temporary files `.<short>.partial-<pid>-…` in `dir` of processes that no
/// longer run: what a run killed without a chance to clean up (`SIGKILL`, a power cut)
/// left behind. A file of a live process (another run writing the same output) stays.
fn remove_stale_temporary_files(dir: &Path, short: &str) {
    let prefix = format!(".{short}.partial-");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(rest) = name.to_str().and_then(|n| n.strip_prefix(&prefix)) else {
            continue;
        };
        let pid = rest.split('-').next().and_then(|p| p.parse::<u32>().ok());
        if pid.is_some_and(|pid| !process_runs(pid)) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Whether process `pid` exists (on other systems than Unix: assumed so).
fn process_runs(pid: u32) -> bool {
    #[cfg(unix)]
    {
        let Ok(pid) = libc::pid_t::try_from(pid) else {
            return true;
        };
        // SAFETY: signal 0 only checks that the process exists; nothing is sent.
        let found = unsafe { libc::kill(pid, 0) } == 0;
        found || io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
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

    /// A FIFO or a folder at the output path is refused and left as it was; a link to a
    /// regular file is written through (the link stays); a 250-character name works; a
    /// file where a folder is needed is named.
    #[cfg(unix)]
    #[test]
    fn only_regular_files_are_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let err = write_atomically(&fifo, |w| w.write_all(b"x")).unwrap_err();
            assert!(err.to_string().contains("FIFO"), "{err}");
            let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
            assert!(std::os::unix::fs::FileTypeExt::is_fifo(&kind));
        }
        let err = AtomicPath::create(dir.path()).unwrap_err();
        assert!(err.to_string().contains("a folder"), "{err}");

        let real = dir.path().join("real.txt");
        std::fs::write(&real, "old").unwrap();
        let link = dir.path().join("link.txt");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_atomically(&link, |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());

        let long = dir.path().join(format!("{}.csv", "n".repeat(246)));
        write_atomically(&long, |w| w.write_all(b"long")).unwrap();
        assert_eq!(std::fs::read_to_string(&long).unwrap(), "long");

        let err = write_atomically(&real.join("x.mcap"), |w| w.write_all(b"x")).unwrap_err();
        assert!(err.to_string().contains("real.txt` is a file"), "{err}");
    }

    #[test]
    fn a_partial_commit_goes_beside_the_target_under_a_partial_name() {
        assert_eq!(
            partial_path(Path::new("out/robbit.mcap")),
            Path::new("out/robbit.partial.mcap")
        );
        assert_eq!(partial_path(Path::new("run")), Path::new("run.partial"));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("run.csv");
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"half").unwrap();
        let kept = file.commit_partial().unwrap();
        assert_eq!(kept, dir.path().join("run.partial.csv"));
        assert_eq!(std::fs::read_to_string(&kept).unwrap(), "half");
        let reserved = AtomicPath::create(&dir.path().join("run.rrd")).unwrap();
        std::fs::write(reserved.temporary(), "rrd").unwrap();
        assert_eq!(
            reserved.commit_partial().unwrap(),
            dir.path().join("run.partial.rrd")
        );
        assert!(!path.exists() && !dir.path().join("run.rrd").exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
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
