//! Files that appear whole or not at all: written under a temporary name in
//! the target's directory, renamed at the end.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The temporary files this process is writing, so that an interrupted
/// run can remove them ([`remove_temporary_files`]).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Removes the temporary files of the writes in progress (a command line
/// calls it when interrupted by SIGINT, SIGTERM or SIGHUP): their targets
/// keep their old content.
pub fn remove_temporary_files() {
    for path in live().drain(..) {
        let _ = std::fs::remove_file(path);
    }
}

/// A temporary file is gone (renamed into place or removed).
pub(crate) fn forget(path: &Path) {
    live().retain(|p| p != path);
}

/// The directory a target is written in (`.` for a bare file name).
fn directory_of(target: &Path) -> &Path {
    match target.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// Removes the temporary files left in the directory of `target` by
/// processes that no longer run (`.NAME.TAG.PID.N.tmp` with a dead PID,
/// whatever `NAME`): an earlier run killed by SIGKILL or SIGXFSZ, which
/// no handler could clean up.
fn sweep_stale(target: &Path) {
    let Ok(entries) = std::fs::read_dir(directory_of(target)) else { return };
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = file.strip_prefix('.').and_then(|r| r.strip_suffix(".tmp")) else { continue };
        let parts: Vec<&str> = rest.rsplitn(4, '.').collect();
        // Reversed: N, PID, TAG, NAME.
        let [n, pid, tag, _name] = parts[..] else { continue };
        if !matches!(tag, "partial" | "elements" | "vertices" | "normals") || n.parse::<u64>().is_err() {
            continue;
        }
        let Ok(pid) = pid.parse::<u32>() else { continue };
        let alive = pid == std::process::id() || Path::new(&format!("/proc/{pid}")).exists();
        if !alive && Path::new("/proc/self").exists() {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// A file being written; it replaces `target` only on [`AtomicFile::commit`],
/// and disappears if dropped before.
pub struct AtomicFile {
    target: PathBuf,
    temp: PathBuf,
    writer: Option<BufWriter<File>>,
}

/// A temporary path beside `target`, unique to this process and call.
pub(crate) fn temp_path(target: &Path, tag: &str) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let name = target.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "out".into());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let path = target.with_file_name(format!(".{name}.{tag}.{}.{n}.tmp", std::process::id()));
    live().push(path.clone());
    path
}

/// Checks, before any work, that `target` can be written: not a
/// directory, in a directory that exists. Nothing is created.
///
/// # Errors
/// An [`io::Error`] that says which of these fails.
pub fn check_target(target: &Path) -> io::Result<()> {
    let fail = |what: String| Err(io::Error::new(io::ErrorKind::InvalidInput, what));
    if target.as_os_str().is_empty() {
        return fail("the output path is empty".into());
    }
    if target.is_dir() {
        return fail(format!(
            "{} is a directory: give a file name (for example {}/out.png)",
            target.display(),
            target.display()
        ));
    }
    let dir = directory_of(target);
    if !dir.is_dir() {
        return fail(format!("the directory {} does not exist", dir.display()));
    }
    if std::fs::metadata(dir).is_ok_and(|m| m.permissions().readonly()) {
        return fail(format!("the directory {} is not writable", dir.display()));
    }
    Ok(())
}

impl AtomicFile {
    /// Starts writing `target`.
    ///
    /// # Errors
    /// The temporary file cannot be created (e.g. missing directory).
    pub fn create(target: &Path) -> io::Result<AtomicFile> {
        check_target(target)?;
        sweep_stale(target);
        let temp = temp_path(target, "partial");
        let file = File::create(&temp)?;
        Ok(AtomicFile { target: target.to_path_buf(), temp, writer: Some(BufWriter::with_capacity(1 << 20, file)) })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("not committed")
    }

    /// Flushes, syncs and renames the file into place.
    ///
    /// # Errors
    /// Any write, sync or rename error (the target is then untouched).
    pub fn commit(mut self) -> io::Result<()> {
        let mut w = self.writer.take().expect("not committed");
        w.flush()?;
        w.get_ref().sync_all()?;
        drop(w);
        let renamed = std::fs::rename(&self.temp, &self.target);
        if renamed.is_err() {
            // Nothing half-written stays: the temporary goes with the failed rename.
            let _ = std::fs::remove_file(&self.temp);
        }
        forget(&self.temp);
        renamed
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some() {
            let _ = std::fs::remove_file(&self.temp);
            forget(&self.temp);
        }
    }
}

/// A temporary side file beside a target: the part of a file that must
/// come after something known only at the end (an OBJ's elements after all
/// vertices, an OFF's vertices after the counts of its header). It is
/// appended to the target by [`Spool::append_to`] and removed whatever happens.
pub(crate) struct Spool {
    path: PathBuf,
    writer: Option<BufWriter<File>>,
}

impl Spool {
    /// A new side file of `target`, tagged `tag`.
    pub(crate) fn create(target: &Path, tag: &str) -> io::Result<Spool> {
        let path = temp_path(target, tag);
        let writer = match File::create(&path) {
            Ok(file) => BufWriter::with_capacity(1 << 20, file),
            Err(e) => {
                forget(&path);
                return Err(e);
            }
        };
        Ok(Spool { path, writer: Some(writer) })
    }

    /// The writer.
    pub(crate) fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("not appended")
    }

    /// Empties the side file, to be written again from its start.
    pub(crate) fn clear(&mut self) -> io::Result<()> {
        self.writer = None;
        self.writer = Some(BufWriter::with_capacity(1 << 20, File::create(&self.path)?));
        Ok(())
    }

    /// The side file opened for reading from its start, what was written
    /// so far flushed first (writing may go on after).
    pub(crate) fn reader(&mut self) -> io::Result<File> {
        self.writer().flush()?;
        File::open(&self.path)
    }

    /// Appends the side file to `out` (file to file: the kernel copies) and removes it.
    pub(crate) fn append_to(mut self, out: &mut AtomicFile) -> io::Result<()> {
        let mut w = self.writer.take().expect("append once");
        w.flush()?;
        drop(w);
        let mut reader = File::open(&self.path)?;
        let main = out.writer();
        main.flush()?;
        io::copy(&mut reader, main.get_mut())?;
        Ok(())
    }
}

impl Drop for Spool {
    fn drop(&mut self) {
        self.writer.take();
        let _ = std::fs::remove_file(&self.path);
        forget(&self.path);
    }
}

/// Writes `bytes` to `target` atomically.
///
/// # Errors
/// Any I/O error; the target is then untouched.
pub fn write_atomic(target: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut f = AtomicFile::create(target)?;
    f.writer().write_all(bytes)?;
    f.commit()
}
