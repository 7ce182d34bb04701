//! A progress line on the terminal while long work runs on another thread.

use std::io::{IsTerminal as _, Write as _};
use std::time::{Duration, Instant};

use starcages_core::BindControl;

/// Runs `work` while printing `label` and a percentage to standard error, when it is a
/// terminal and the work takes more than half a second.
pub fn with_progress<T: Send>(
    label: &str,
    control: &BindControl,
    work: impl FnOnce() -> T + Send,
) -> T {
    if !std::io::stderr().is_terminal() {
        return work();
    }
    let done = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|scope| {
        scope.spawn(|| {
            let start = Instant::now();
            let mut shown = false;
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(100));
                if start.elapsed() > Duration::from_millis(500) {
                    crate::note_inline!("\r{label}: {:5.1}%", 100.0 * control.progress());
                    std::io::stderr().flush().ok();
                    shown = true;
                }
            }
            if shown {
                crate::note!("\r{label}: done in {:.2} s", start.elapsed().as_secs_f64());
            }
        });
        let result = work();
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        result
    })
}
