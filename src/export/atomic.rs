//! Files that appear whole or not at all: written under a temporary name in
//! the target's directory, renamed at the end.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

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
    target.with_file_name(format!(".{name}.{tag}.{}.{n}.tmp", std::process::id()))
}

impl AtomicFile {
    /// Starts writing `target`.
    ///
    /// # Errors
    /// The temporary file cannot be created (e.g. missing directory).
    pub fn create(target: &Path) -> io::Result<AtomicFile> {
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
        std::fs::rename(&self.temp, &self.target)
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some() {
            let _ = std::fs::remove_file(&self.temp);
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
