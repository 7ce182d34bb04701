//! Progress reporting and cancellation of long binds, shared across threads.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use super::CoordError;

/// Progress and cancellation of a bind: the worker advances it, a UI or terminal reads it and
/// may cancel. Cheap to share by reference across threads.
#[derive(Debug, Default)]
pub struct BindControl {
    cancelled: AtomicBool,
    done: AtomicUsize,
    total: AtomicUsize,
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
