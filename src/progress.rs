//! Progress of long computations, reported through a callback: the library
//! draws nothing; the command line turns reports into a bar on a terminal.

use std::fmt;
use std::sync::Arc;

/// A callback told how far a long computation is: `report(done, total)`
/// after each step, and `report(total, total)` when it ends. Cheap to
/// clone; called from the thread that drives the computation.
///
/// ```
/// use std::sync::atomic::{AtomicU64, Ordering};
/// use std::sync::Arc;
/// let seen = Arc::new(AtomicU64::new(0));
/// let s = seen.clone();
/// let progress = bcifs::Progress::new(move |done, _total| s.store(done, Ordering::Relaxed));
/// progress.report(3, 10);
/// assert_eq!(seen.load(Ordering::Relaxed), 3);
/// ```
#[derive(Clone)]
pub struct Progress(Arc<dyn Fn(u64, u64) + Send + Sync>);

impl Progress {
    /// A progress callback.
    pub fn new(report: impl Fn(u64, u64) + Send + Sync + 'static) -> Progress {
        Progress(Arc::new(report))
    }

    /// Reports `done` steps of `total`.
    pub fn report(&self, done: u64, total: u64) {
        (self.0)(done, total);
    }
}

impl fmt::Debug for Progress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Progress(..)")
    }
}

/// Steps of one computation, reported to an optional [`Progress`].
pub(crate) struct Steps<'a> {
    progress: Option<&'a Progress>,
    done: u64,
    total: u64,
}

impl<'a> Steps<'a> {
    /// Starts a computation of `total` steps (reports `0 / total`).
    pub(crate) fn new(progress: Option<&'a Progress>, total: u64) -> Steps<'a> {
        if let Some(p) = progress {
            p.report(0, total);
        }
        Steps { progress, done: 0, total }
    }

    /// One more step done.
    pub(crate) fn step(&mut self) {
        self.done = (self.done + 1).min(self.total);
        if let Some(p) = self.progress
            && self.done < self.total
        {
            p.report(self.done, self.total);
        }
    }
}

impl Drop for Steps<'_> {
    /// The computation ended (or failed): `total / total`.
    fn drop(&mut self) {
        if let Some(p) = self.progress {
            p.report(self.total, self.total);
        }
    }
}

/// A flag that stops a long computation: a web server sets it when its
/// request goes away, the command line when it gets Ctrl-C. Cheap to clone
/// (the clones share the flag); the library checks it between phases and
/// at every batch it writes, then stops with a "cancelled" error, leaving
/// no file half-written.
///
/// ```
/// let cancel = bcifs::Cancel::new();
/// let handle = cancel.clone();
/// assert!(!cancel.is_cancelled());
/// handle.cancel();
/// assert!(cancel.is_cancelled());
/// ```
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<std::sync::atomic::AtomicBool>);

thread_local! {
    /// The flag [`Cancel::scope`] installed on this thread.
    static AMBIENT: std::cell::RefCell<Option<Cancel>> = const { std::cell::RefCell::new(None) };
}

impl Cancel {
    /// A flag not set.
    pub fn new() -> Cancel {
        Cancel::default()
    }

    /// Asks the computations that hold a clone to stop.
    pub fn cancel(&self) {
        self.0.store(true, std::sync::atomic::Ordering::Relaxed);
    }

    /// Whether [`Cancel::cancel`] was called on this flag or a clone.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Runs `work` with this flag as the calling thread's ambient one: the
    /// steps that take no flag of their own (a subdivision step in memory)
    /// look at it every few thousand items and stop with an
    /// [`std::io::ErrorKind::Interrupted`] error once it is set. The thread's
    /// earlier ambient flag is back when `work` returns (or panics).
    ///
    /// ```
    /// let cancel = bcifs::Cancel::new();
    /// cancel.cancel();
    /// let cube = bcifs::mesh::PolyMesh::cube();
    /// let job = bcifs::mesh::Subdivision {
    ///     scheme: bcifs::mesh::Scheme::CatmullClark,
    ///     depth: 6,
    ///     weights: None,
    ///     memory_limit: 1 << 30,
    /// };
    /// assert!(cancel.scope(|| cube.subdivided(&job, false)).is_err());
    /// assert!(cube.subdivided(&job, false).is_ok());
    /// ```
    pub fn scope<T>(&self, work: impl FnOnce() -> T) -> T {
        struct Restore(Option<Cancel>);
        impl Drop for Restore {
            fn drop(&mut self) {
                AMBIENT.with(|a| a.replace(self.0.take()));
            }
        }
        let _restore = Restore(AMBIENT.with(|a| a.replace(Some(self.clone()))));
        work()
    }

    /// The calling thread's ambient flag ([`Cancel::scope`]), if any.
    pub(crate) fn ambient() -> Option<Cancel> {
        AMBIENT.with(|a| a.borrow().clone())
    }

    /// An [`std::io::ErrorKind::Interrupted`] error once the flag is set:
    /// how writers stop.
    ///
    /// # Errors
    /// The flag is set.
    pub fn check_io(&self) -> std::io::Result<()> {
        if self.is_cancelled() {
            Err(std::io::Error::new(std::io::ErrorKind::Interrupted, "cancelled"))
        } else {
            Ok(())
        }
    }
}

/// A size in bytes as people read it: `512 bytes`, `12 KiB`, `340 MiB`,
/// `2.5 GiB` (what error messages about memory and disk say).
///
/// ```
/// assert_eq!(bcifs::bytes_text(1 << 20), "1 MiB");
/// assert_eq!(bcifs::bytes_text(5 << 29), "2.5 GiB");
/// ```
pub fn bytes_text(bytes: u128) -> String {
    const KIB: u128 = 1 << 10;
    match bytes {
        b if b < KIB => format!("{b} bytes"),
        b if b < KIB << 10 => format!("{} KiB", b.div_ceil(KIB)),
        b if b < KIB << 20 => format!("{} MiB", b.div_ceil(KIB << 10)),
        b if b < KIB << 50 => format!("{:.1} GiB", b as f64 / (1u64 << 30) as f64),
        // Past 2^60 bytes (an exbibyte) the figure only says "too much" (a deep tree's count overflows).
        _ => "more than an exbibyte (2^60 bytes)".into(),
    }
}
