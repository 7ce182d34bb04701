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
        if total == 0 {
            0.0
        } else {
            (self.done.load(Ordering::Relaxed) as f64 / total as f64).min(1.0)
        }
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
