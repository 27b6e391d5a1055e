//! SIGINT, SIGTERM and SIGHUP (what Ctrl-C, `timeout`, schedulers and a closed terminal
//! send), in three cases:
//! - before the render's first batch of samples is done (loading the scene, opening the
//!   device, building the kernels, and the first batch, in which lavapipe compiles them, for
//!   seconds, and a guided render trains its guide): the command ends at once and writes
//!   nothing; one line says so and every existing output stays as it was;
//! - while it renders after that: the render stops after the current batch, the command
//!   writes what it rendered (and its checkpoint) and exits with 128 + the signal's number;
//!   after SIGINT (Ctrl-C) the image goes beside each output (`out.partial.png`), leaving a
//!   finished image there as it was, while SIGTERM and SIGHUP (a scheduler's stop) write
//!   the outputs;
//! - a second signal, at any time: the command aborts at once. The temporary files of the
//!   writes in progress are removed, so every output is either as it was or completely
//!   written (outputs are only ever replaced by renaming a finished file over them).

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Mutex, Once};

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};

use crate::image_io::output::abort_pending_writes;

/// Set when a signal asks the render to stop.
pub static STOP_REQUESTED: AtomicBool = AtomicBool::new(false);
/// Set (by `run_job`, through `JobOptions::started`) once the render's first batch is done:
/// from then on a first signal stops the render after the batch instead of ending the
/// command.
pub static RENDERING: AtomicBool = AtomicBool::new(false);
/// The first signal received (0 while none was).
static SIGNAL: AtomicI32 = AtomicI32::new(0);
/// What a stop before the first sample leaves alone, for its line (e.g. "'out.png'").
static OUTPUTS: Mutex<String> = Mutex::new(String::new());
/// What a stop leaves of a sequence, for the end of its line (`set_frames_left`); empty
/// for one image.
static FRAMES_LEFT: Mutex<String> = Mutex::new(String::new());

/// Records which frame of a sequence (`render --frames`) renders now: a stop's line then
/// ends with the frame that stopped and those that remain ("; frame 7 of 0..10 stopped:
/// frames 7..10 remain (--frames 7..10 --skip-existing renders them)").
pub fn set_frames_left(frame: u32, frames: &std::ops::Range<u32>) {
    let left = frame..frames.end;
    let remain = match left.len() {
        1 => format!("frame {frame} remains"),
        _ => format!("frames {}..{} remain", left.start, left.end),
    };
    *FRAMES_LEFT.lock().unwrap_or_else(|e| e.into_inner()) = format!(
        "; frame {frame} of {}..{} stopped: {remain} (--frames {}..{} --skip-existing renders them)",
        frames.start, frames.end, left.start, left.end
    );
}

/// The end of a stop's line in a sequence (`set_frames_left`); empty for one image.
pub fn frames_left() -> String {
    FRAMES_LEFT
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .clone()
}

/// Installs the handlers (once per process); `outputs` names the files the command would
/// write, for the line a stop before the first sample prints.
pub fn install(outputs: &[&std::path::Path]) -> anyhow::Result<()> {
    let names: Vec<String> = outputs
        .iter()
        .map(|p| format!("'{}'", p.display()))
        .collect();
    *OUTPUTS.lock().unwrap_or_else(|e| e.into_inner()) = names.join(", ");
    static INSTALLED: Once = Once::new();
    let mut result = Ok(());
    INSTALLED.call_once(|| {
        result = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])
            .map(|mut signals| {
                std::thread::spawn(move || {
                    for signal in signals.forever() {
                        handle(signal);
                    }
                });
            })
            .map_err(|e| anyhow::anyhow!("cannot install the signal handlers: {e}"));
    });
    result
}

/// What a signal does (on the handlers' thread, not in a signal handler: it may print).
fn handle(signal: i32) {
    let first = SIGNAL
        .compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst)
        .is_ok();
    if !first {
        let _stopped = abort_pending_writes();
        eprintln!(
            "vkpath: aborted by a second signal ({}): files being written were discarded, finished ones are complete",
            name(signal)
        );
        signal_hook::low_level::exit(128 + signal);
    }
    if !RENDERING.load(Ordering::SeqCst) {
        let _stopped = abort_pending_writes();
        eprintln!("{}", nothing_written_line(signal));
        signal_hook::low_level::exit(128 + signal);
    }
    STOP_REQUESTED.store(true, Ordering::SeqCst);
}

/// The line of a stop before the first sample: nothing written, the outputs as they were.
fn nothing_written_line(signal: i32) -> String {
    let outputs = OUTPUTS.lock().unwrap_or_else(|e| e.into_inner()).clone();
    format!(
        "vkpath: stopped by {} before the first sample: nothing written ({} left as it was){}",
        name(signal),
        if outputs.is_empty() {
            "every file"
        } else {
            &outputs
        },
        frames_left()
    )
}

/// Ends the command after a stop that came before the render's first sample (the signal
/// arrived between building the renderer and its first batch): prints the same line as a
/// stop during set-up and exits with 128 + the signal's number, having written nothing.
pub fn exit_with_nothing_written() -> ! {
    let signal = SIGNAL.load(Ordering::SeqCst);
    let signal = if signal == 0 { SIGINT } else { signal };
    eprintln!("{}", nothing_written_line(signal));
    std::process::exit(128 + signal);
}

/// The signal that stopped the render, if one did: (its name, the exit status 128 + number).
pub fn received() -> Option<(&'static str, i32)> {
    match SIGNAL.load(Ordering::SeqCst) {
        0 => None,
        signal => Some((name(signal), 128 + signal)),
    }
}

/// Whether the first signal was SIGINT (Ctrl-C): a person stopped the render, whose image
/// then goes beside the outputs instead of over them.
pub fn interrupted() -> bool {
    SIGNAL.load(Ordering::SeqCst) == SIGINT
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stop_in_a_sequence_says_which_frame_stopped_and_which_remain() {
        set_frames_left(7, &(0..10));
        assert_eq!(
            frames_left(),
            "; frame 7 of 0..10 stopped: frames 7..10 remain (--frames 7..10 --skip-existing renders them)"
        );
        set_frames_left(9, &(0..10));
        assert!(frames_left().contains("stopped: frame 9 remains (--frames 9..10"));
        assert!(nothing_written_line(SIGINT).ends_with(&frames_left()));
    }
}
