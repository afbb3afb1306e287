//! Files that appear whole or not at all: written under a temporary name in
//! the target's directory, renamed at the end. A target that is a symbolic
//! link is written through it (the link stays, the file it names is
//! replaced whole); a device or a pipe (`/dev/null`, `/dev/full`, a FIFO) is
//! written in place, its errors reported, never replaced by a file.

use std::fs::File;
use std::io::{self, BufWriter, Cursor, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Where an output goes: a file (written atomically, as [`AtomicFile`]), or
/// memory (a page or a notebook that wants the bytes, not a file).
#[derive(Clone, Debug)]
pub enum Target {
    /// A file.
    Path(PathBuf),
    /// A buffer, filled when the output is committed ([`MemoryFile::take`]).
    Memory(MemoryFile),
}

/// The buffer of an output made in memory.
#[derive(Clone, Debug, Default)]
pub struct MemoryFile(Arc<Mutex<Vec<u8>>>);

impl MemoryFile {
    /// An empty buffer.
    pub fn new() -> MemoryFile {
        MemoryFile::default()
    }

    /// The bytes committed to it (emptied).
    pub fn take(&self) -> Vec<u8> {
        std::mem::take(&mut *self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner))
    }

    /// How many bytes it holds.
    pub fn len(&self) -> usize {
        self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner).len()
    }

    /// Whether it holds nothing.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn put(&self, bytes: Vec<u8>) {
        *self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner) = bytes;
    }
}

impl From<&Path> for Target {
    fn from(path: &Path) -> Target {
        Target::Path(path.to_path_buf())
    }
}

impl Target {
    /// The path messages name (`<memory>` for a buffer).
    pub fn path(&self) -> &Path {
        match self {
            Target::Path(p) => p,
            Target::Memory(_) => Path::new("<memory>"),
        }
    }

    /// Where side files go: beside the file, or in the temporary directory.
    pub(crate) fn beside(&self) -> PathBuf {
        match self {
            Target::Path(p) => p.clone(),
            Target::Memory(_) => std::env::temp_dir().join("bcifs-in-memory"),
        }
    }
}

/// What an [`AtomicFile`] writes into: its temporary file (or a device), or memory.
pub enum Out {
    /// A file.
    File(BufWriter<File>),
    /// A buffer.
    Memory(Cursor<Vec<u8>>),
}

impl Write for Out {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self {
            Out::File(w) => w.write(buf),
            Out::Memory(w) => w.write(buf),
        }
    }
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        match self {
            Out::File(w) => w.write_all(buf),
            Out::Memory(w) => w.write_all(buf),
        }
    }
    fn flush(&mut self) -> io::Result<()> {
        match self {
            Out::File(w) => w.flush(),
            Out::Memory(_) => Ok(()),
        }
    }
}

impl Seek for Out {
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        match self {
            Out::File(w) => w.seek(to),
            Out::Memory(w) => w.seek(to),
        }
    }
}

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
/// and disappears if dropped before. A device or pipe is written in place.
pub struct AtomicFile {
    target: PathBuf,
    /// The temporary file renamed onto the target (`None`: written in place).
    temp: Option<PathBuf>,
    writer: Option<Out>,
    /// The buffer a memory target's bytes go to on commit.
    memory: Option<MemoryFile>,
}

/// Links followed at most (as the kernel's `ELOOP` limit).
const MAX_LINKS: usize = 40;

/// The path that writing `target` lands on: through its symbolic links to
/// the file they name, which may not exist yet (a link relative to its
/// directory resolved there).
///
/// # Errors
/// A cycle of links, or more than 40.
pub fn resolve_target(target: &Path) -> io::Result<PathBuf> {
    let mut path = target.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&path) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = std::fs::read_link(&path)?;
                path = if link.is_absolute() { link } else { directory_of(&path).join(link) };
            }
            _ => return Ok(path),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("{}: more than {MAX_LINKS} symbolic links (a cycle?)", target.display()),
    ))
}

/// Whether `path` (followed) is neither a regular file nor a directory: a
/// device or a pipe, written in place.
fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Whether `a` and `b` are the same existing file (through links and
/// other spellings of the path): an output that would overwrite an input.
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        #[cfg(unix)]
        (Ok(x), Ok(y)) => {
            use std::os::unix::fs::MetadataExt as _;
            x.dev() == y.dev() && x.ino() == y.ino()
        }
        #[cfg(not(unix))]
        (Ok(_), Ok(_)) => std::fs::canonicalize(a).ok() == std::fs::canonicalize(b).ok(),
        _ => false,
    }
}

/// A temporary path beside `target` (beside the file its links name; in
/// the system's temporary directory for a device), unique to this process and call.
pub(crate) fn temp_path(target: &Path, tag: &str) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let name = target.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "out".into());
    let resolved = resolve_target(target).unwrap_or_else(|_| target.to_path_buf());
    let beside = if is_special(&resolved) { std::env::temp_dir().join(&name) } else { resolved };
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let path = beside.with_file_name(format!(".{name}.{tag}.{}.{n}.tmp", std::process::id()));
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
    let target = &resolve_target(target)?;
    if is_special(target) {
        return Ok(());
    }
    if target.is_dir() {
        return fail(format!(
            "{} is a directory: give a file name (for example {}/out.png)",
            target.display(),
            target.display()
        ));
    }
    let dir = directory_of(target);
    if dir.exists() && !dir.is_dir() {
        return fail(format!("{} is a file, not a directory", dir.display()));
    }
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
        let target = resolve_target(target)?;
        if is_special(&target) {
            let file = std::fs::OpenOptions::new().write(true).open(&target)?;
            let writer = Some(Out::File(BufWriter::with_capacity(1 << 20, file)));
            return Ok(AtomicFile { target, temp: None, writer, memory: None });
        }
        sweep_stale(&target);
        let temp = temp_path(&target, "partial");
        let file = match File::create(&temp) {
            Ok(file) => file,
            Err(e) => {
                forget(&temp);
                return Err(e);
            }
        };
        let writer = Some(Out::File(BufWriter::with_capacity(1 << 20, file)));
        Ok(AtomicFile { target, temp: Some(temp), writer, memory: None })
    }

    /// Starts writing `target`: a file as [`AtomicFile::create`], or a buffer.
    ///
    /// # Errors
    /// As [`AtomicFile::create`].
    pub fn create_in(target: &Target) -> io::Result<AtomicFile> {
        match target {
            Target::Path(path) => AtomicFile::create(path),
            Target::Memory(buffer) => Ok(AtomicFile {
                target: target.path().to_path_buf(),
                temp: None,
                writer: Some(Out::Memory(Cursor::new(Vec::new()))),
                memory: Some(buffer.clone()),
            }),
        }
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut Out {
        self.writer.as_mut().expect("not committed")
    }

    /// Flushes, syncs and renames the file into place.
    ///
    /// # Errors
    /// Any write, sync or rename error (the target is then untouched).
    pub fn commit(mut self) -> io::Result<()> {
        let w = self.writer.take().expect("not committed");
        let mut w = match w {
            Out::Memory(bytes) => {
                if let Some(buffer) = &self.memory {
                    buffer.put(bytes.into_inner());
                }
                return Ok(());
            }
            Out::File(w) => w,
        };
        let Some(temp) = self.temp.take() else {
            // A device or pipe: its write errors (ENOSPC of /dev/full) are the answer.
            return w.flush();
        };
        let written = w.flush().and_then(|()| w.get_ref().sync_all());
        drop(w);
        let renamed = written.and_then(|()| std::fs::rename(&temp, &self.target));
        if renamed.is_err() {
            // Nothing half-written stays: the temporary goes with the failed write or rename.
            let _ = std::fs::remove_file(&temp);
        }
        forget(&temp);
        renamed
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some()
            && let Some(temp) = self.temp.take()
        {
            let _ = std::fs::remove_file(&temp);
            forget(&temp);
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
        match out.writer() {
            Out::File(main) => {
                main.flush()?;
                io::copy(&mut reader, main.get_mut())?;
            }
            Out::Memory(main) => {
                io::copy(&mut reader, main)?;
            }
        }
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
    write_to(&Target::from(target), bytes)
}

/// Writes `bytes` to `target`: a file atomically, or a buffer.
///
/// # Errors
/// Any I/O error; a file target is then untouched.
pub fn write_to(target: &Target, bytes: &[u8]) -> io::Result<()> {
    let mut f = AtomicFile::create_in(target)?;
    f.writer().write_all(bytes)?;
    f.commit()
}
