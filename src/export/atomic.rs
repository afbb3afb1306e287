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

/// Removes the temporary files of `target` left by processes that no longer
/// run (`.NAME.TAG.PID.N.tmp` with a dead PID): an earlier interrupted run.
fn sweep_stale(target: &Path) {
    let (Some(dir), Some(name)) = (target.parent(), target.file_name()) else { return };
    let dir = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
    let prefix = format!(".{}.", name.to_string_lossy());
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = file.strip_prefix(&prefix).and_then(|r| r.strip_suffix(".tmp")) else { continue };
        let parts: Vec<&str> = rest.split('.').collect();
        let [tag, pid, n] = parts[..] else { continue };
        if !matches!(tag, "partial" | "elements") || n.parse::<u64>().is_err() {
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

impl AtomicFile {
    /// Starts writing `target`.
    ///
    /// # Errors
    /// The temporary file cannot be created (e.g. missing directory).
    pub fn create(target: &Path) -> io::Result<AtomicFile> {
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

/// Writes `bytes` to `target` atomically.
///
/// # Errors
/// Any I/O error; the target is then untouched.
pub fn write_atomic(target: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut f = AtomicFile::create(target)?;
    f.writer().write_all(bytes)?;
    f.commit()
}
