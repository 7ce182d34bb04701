//! Progress reporting and cancellation of long binds, shared across threads.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};

use super::CoordError;

/// Progress and cancellation of a bind: the worker advances it, a UI or terminal reads it and
/// may cancel. Cheap to share by reference across threads.
#[derive(Debug, Default)]
pub struct BindControl {
    cancelled: AtomicBool,
    done: AtomicUsize,
    total: AtomicUsize,
    kernel_pairs: AtomicU64,
    /// Stages of a bind done in turn (a streamed bind's chunks) and the current one; the
    /// `done`/`total` fraction is progress within the current stage.
    stage: AtomicUsize,
    stage_count: AtomicUsize,
}

/// Stages of a bind under way ([`BindControl::stages`]); the control's progress covers all of
/// them until this is dropped.
pub(crate) struct Stages<'a>(&'a BindControl);

impl Stages<'_> {
    /// Progress is now in stage `k` (counting from 0).
    pub(crate) fn enter(&self, k: usize) {
        self.0.done.store(0, Ordering::Relaxed);
        self.0.stage.store(k, Ordering::Relaxed);
    }
}

impl Drop for Stages<'_> {
    fn drop(&mut self) {
        self.0.stage_count.store(0, Ordering::Relaxed);
    }
}

impl BindControl {
    /// Asks the bind to stop at its next check; it then returns [`CoordError::Cancelled`].
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether [`BindControl::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// Fraction of the work done, in [0, 1].
    pub fn progress(&self) -> f64 {
        let total = self.total.load(Ordering::Relaxed);
        let within = if total == 0 {
            0.0
        } else {
            (self.done.load(Ordering::Relaxed) as f64 / total as f64).min(1.0)
        };
        match self.stage_count.load(Ordering::Relaxed) {
            0 => within,
            count => ((self.stage.load(Ordering::Relaxed) as f64 + within) / count as f64).min(1.0),
        }
    }

    /// Splits the progress into `count` stages done in turn, until the result is dropped.
    pub(crate) fn stages(&self, count: usize) -> Stages<'_> {
        self.stage.store(0, Ordering::Relaxed);
        self.stage_count.store(count, Ordering::Relaxed);
        Stages(self)
    }

    /// Point·triangle pairs the closed-form kernels (MVC, GC) have evaluated under this
    /// control: the work of the coordinates alone, whatever else a bind does (the physical
    /// floor of a bind, in kernel evaluations).
    pub fn kernel_pairs(&self) -> u64 {
        self.kernel_pairs.load(Ordering::Relaxed)
    }

    pub(crate) fn add_kernel_pairs(&self, pairs: u64) {
        self.kernel_pairs.fetch_add(pairs, Ordering::Relaxed);
    }

    pub(crate) fn set_total(&self, total: usize) {
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    pub(crate) fn advance(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }

    pub(crate) fn check(&self) -> Result<(), CoordError> {
        if self.is_cancelled() {
            Err(CoordError::Cancelled)
        } else {
            Ok(())
        }
    }
}
