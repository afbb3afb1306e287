//! Long calls on a worker thread, the GIL released, stopped by Ctrl-C.

use pyo3::prelude::*;

use crate::err;

/// How long an interrupted call that writes a file waits for its work to
/// notice the cancellation (the writer removes its temporary file) before it
/// raises anyway.
const FILE_GRACE: std::time::Duration = std::time::Duration::from_millis(800);

/// How long an interrupted call that returns arrays waits for its work to
/// stop: evaluations, chaos games, sweeps, subdivision steps and the copies
/// into arrays look at the flag every few thousand items; a longer phase
/// (zeroing a large buffer) ends in the background, its result dropped, so
/// that Ctrl-C raises within a tenth of a second.
const ARRAY_GRACE: std::time::Duration = std::time::Duration::from_millis(60);

/// Runs `work` on a worker thread, the GIL released, while this thread
/// forwards its progress to `progress` (a callable taking `done, total`:
/// tqdm's `update` fits through a small lambda) and checks for Ctrl-C every
/// 20 ms: on KeyboardInterrupt the work is cancelled through the
/// [`bcifs::render::Cancel`] it was given and the exception raised once it
/// stops, or after [`ARRAY_GRACE`].
pub(crate) fn cancellable<T: Send + 'static>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(bcifs::render::Cancel, Option<bcifs::render::Progress>) -> T + Send + 'static,
) -> PyResult<T> {
    cancellable_within(py, progress, ARRAY_GRACE, work)
}

/// [`cancellable`] for a call that writes a file: on Ctrl-C it waits up to
/// [`FILE_GRACE`] for the writer to remove its temporary file.
pub(crate) fn cancellable_writing<T: Send + 'static>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(bcifs::render::Cancel, Option<bcifs::render::Progress>) -> T + Send + 'static,
) -> PyResult<T> {
    cancellable_within(py, progress, FILE_GRACE, work)
}

/// How long an interrupted search (a fit) has to hand back its best answer so far.
const SEARCH_GRACE: std::time::Duration = std::time::Duration::from_secs(5);

/// [`cancellable`] for a search that answers with its best so far when
/// stopped (a fit): on Ctrl-C its work is cancelled and, when it answers
/// within [`SEARCH_GRACE`], the answer is returned instead of raising.
pub(crate) fn interruptible<T: Send + 'static>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(bcifs::render::Cancel, Option<bcifs::render::Progress>) -> T + Send + 'static,
) -> PyResult<T> {
    cancellable_inner(py, progress, SEARCH_GRACE, true, work)
}

/// The body of [`cancellable`] and [`cancellable_writing`]: on Ctrl-C, the
/// work is cancelled and waited for up to `grace`.
fn cancellable_within<T: Send + 'static>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    grace: std::time::Duration,
    work: impl FnOnce(bcifs::render::Cancel, Option<bcifs::render::Progress>) -> T + Send + 'static,
) -> PyResult<T> {
    cancellable_inner(py, progress, grace, false, work)
}

/// On Ctrl-C, the work is cancelled and waited for up to `grace`; with
/// `keep`, what it returned in that time is the answer, else the exception.
fn cancellable_inner<T: Send + 'static>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    grace: std::time::Duration,
    keep: bool,
    work: impl FnOnce(bcifs::render::Cancel, Option<bcifs::render::Progress>) -> T + Send + 'static,
) -> PyResult<T> {
    let cancel = bcifs::render::Cancel::new();
    let (tx, rx) = std::sync::mpsc::channel::<(u64, u64)>();
    let reporter = progress.is_some().then(|| {
        let tx = std::sync::Mutex::new(tx);
        bcifs::render::Progress::new(move |done, total| {
            let _ = tx.lock().map(|t| t.send((done, total)));
        })
    });
    let rx = std::sync::Mutex::new(rx);
    let worker_cancel = cancel.clone();
    let handle = std::thread::spawn(move || work(worker_cancel, reporter));
    // Signals are looked at every 20 ms: Ctrl-C stops a call within a tenth of a second.
    let wait = std::time::Duration::from_millis(20);
    while !handle.is_finished() {
        let message = py.detach(|| rx.lock().ok().and_then(|r| r.recv_timeout(wait).ok()));
        let mut interrupted = None;
        if let (Some((done, total)), Some(callback)) = (message, progress)
            && let Err(e) = callback.call1((done, total))
        {
            interrupted = Some(e);
        }
        if interrupted.is_none()
            && let Err(e) = py.check_signals()
        {
            interrupted = Some(e);
        }
        if let Some(e) = interrupted {
            cancel.cancel();
            let started = std::time::Instant::now();
            py.detach(|| {
                while !handle.is_finished() && started.elapsed() < grace {
                    std::thread::sleep(std::time::Duration::from_millis(10));
                }
            });
            if keep && handle.is_finished() {
                return py.detach(|| handle.join()).map_err(|_| err("the computation panicked"));
            }
            return Err(e);
        }
    }
    let result = py.detach(|| handle.join()).map_err(|_| err("the computation panicked"))?;
    // The reports sent between the last poll and the end (the last one says the work is done).
    if let (Some(callback), Ok(rx)) = (progress, rx.lock()) {
        for (done, total) in rx.try_iter() {
            callback.call1((done, total))?;
        }
    }
    Ok(result)
}
