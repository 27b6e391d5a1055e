//! SIGINT, SIGTERM and SIGHUP (what Ctrl-C, `timeout`, schedulers and a closed terminal
//! send) stop a render after the current batch: the command then writes what it rendered
//! (and its checkpoint) and exits with 128 + the signal's number. Further signals while it
//! writes are ignored until the (atomic) write is complete.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::Once;

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};

/// Set when a signal asks the render to stop.
pub static STOP_REQUESTED: AtomicBool = AtomicBool::new(false);
/// The first signal received (0 while none was).
static SIGNAL: AtomicI32 = AtomicI32::new(0);

/// Installs the handlers (once per process).
pub fn install() -> anyhow::Result<()> {
    static INSTALLED: Once = Once::new();
    let mut result = Ok(());
    INSTALLED.call_once(|| {
        result = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])
            .map(|mut signals| {
                std::thread::spawn(move || {
                    for signal in signals.forever() {
                        let _ =
                            SIGNAL.compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst);
                        STOP_REQUESTED.store(true, Ordering::SeqCst);
                    }
                });
            })
            .map_err(|e| anyhow::anyhow!("cannot install the signal handlers: {e}"));
    });
    result
}

/// The signal that stopped the render, if one did: (its name, the exit status 128 + number).
pub fn received() -> Option<(&'static str, i32)> {
    match SIGNAL.load(Ordering::SeqCst) {
        0 => None,
        signal => Some((name(signal), 128 + signal)),
    }
}

/// A signal's name.
fn name(signal: i32) -> &'static str {
    match signal {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        _ => "a signal",
    }
}
