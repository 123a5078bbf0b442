//! Interruptions leave nothing behind. Every output is written to a
//! temporary sibling and renamed into place when whole (`output.rs`,
//! `video.rs`); those temporaries and the ffmpeg encoding a video are
//! registered here, and SIGINT (Ctrl-C), SIGTERM or SIGHUP removes the
//! files, kills ffmpeg, and ends the command by the signal's default action
//! (the shell sees 130, 143 or 129), as a program interrupted should.

use std::path::{Path, PathBuf};
use std::process::Child;
use std::sync::{Arc, Mutex, MutexGuard};

static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
static CHILDREN: Mutex<Vec<Arc<Mutex<Child>>>> = Mutex::new(Vec::new());

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// A temporary file an interruption must remove.
pub fn watch(path: &Path) {
    lock(&TEMPORARIES).push(path.to_path_buf());
}

/// The file was published or removed: nothing to do for it any more.
pub fn forget(path: &Path) {
    lock(&TEMPORARIES).retain(|p| p != path);
}

/// A child process an interruption must kill.
pub fn watch_child(child: &Arc<Mutex<Child>>) {
    lock(&CHILDREN).push(child.clone());
}

pub fn forget_child(child: &Arc<Mutex<Child>>) {
    lock(&CHILDREN).retain(|c| !Arc::ptr_eq(c, child));
}

/// Kill the children and remove the temporaries (what an interruption does).
fn clean_up() {
    for child in lock(&CHILDREN).drain(..) {
        let mut c = lock(&child);
        let _ = c.kill();
        let _ = c.wait();
    }
    for path in lock(&TEMPORARIES).drain(..) {
        let _ = std::fs::remove_file(path);
    }
}

/// Handle SIGINT, SIGTERM and SIGHUP on a thread of their own.
#[cfg(unix)]
pub fn install() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            clean_up();
            let name = match signal {
                SIGINT => "SIGINT",
                SIGTERM => "SIGTERM",
                _ => "SIGHUP",
            };
            eprintln!("\ninterrupted ({name}): stopped, its unfinished files removed");
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            std::process::exit(128 + signal);
        }
    });
}

/// Elsewhere Ctrl-C ends the process as it always does.
#[cfg(not(unix))]
pub fn install() {}
