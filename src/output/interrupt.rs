//! Interrupted runs (SIGINT, SIGTERM) and the staging directories they leave.
//!
//! Results are written into a staging sibling `.NAME.partial-PID` of the output
//! directory ([`super::Results`]). A run stopped by a signal would leave it
//! behind: [`install`] blocks SIGINT and SIGTERM in the process (before any
//! worker thread exists, so every thread inherits the mask) and waits for them
//! on a thread of its own, which removes every staging directory still
//! registered, has the caller say so and exits with `128 + signal` (130 for
//! SIGINT, 143 for SIGTERM). A run killed outright (SIGKILL, a timeout's kill,
//! a power cut) cannot clean up: the next run writing beside the same output
//! removes the staging directories of processes that no longer exist.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Staging directories of this process not yet committed or removed.
static STAGING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Registers a staging directory to remove if the run is interrupted.
pub(super) fn register(path: &Path) {
    if let Ok(mut list) = STAGING.lock() {
        list.push(path.to_path_buf());
    }
}

/// Forgets a staging directory (committed or removed).
pub(super) fn unregister(path: &Path) {
    if let Ok(mut list) = STAGING.lock() {
        list.retain(|p| p != path);
    }
}

/// Handles SIGINT and SIGTERM as described in the module docs; `report` is
/// told the signal's name and how many partial results were removed, before
/// the process exits. Call it first in `main`, before any thread is started.
#[cfg(unix)]
pub fn install(report: fn(signal: &str, removed: usize)) {
    // SAFETY: plain libc calls on a local, initialised signal set; the mask is
    // set before any other thread exists.
    unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        libc::sigaddset(&mut set, libc::SIGINT);
        libc::sigaddset(&mut set, libc::SIGTERM);
        if libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut()) != 0 {
            return;
        }
        std::thread::spawn(move || loop {
            let mut signal = 0;
            if libc::sigwait(&set, &mut signal) != 0 {
                continue;
            }
            // Hold the lock until exit: no staging directory is registered or
            // committed meanwhile.
            let list = STAGING.lock().unwrap_or_else(|e| e.into_inner());
            for path in list.iter() {
                let _ = std::fs::remove_dir_all(path);
            }
            let name = if signal == libc::SIGINT {
                "SIGINT"
            } else {
                "SIGTERM"
            };
            report(name, list.len());
            std::process::exit(128 + signal);
        });
    }
}

/// Without Unix signals, nothing to install.
#[cfg(not(unix))]
pub fn install(_report: fn(signal: &str, removed: usize)) {}

/// Whether process `pid` exists.
#[cfg(unix)]
fn alive(pid: i32) -> bool {
    // SAFETY: signal 0 only checks that the process exists and may be signalled.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

#[cfg(not(unix))]
fn alive(_pid: i32) -> bool {
    true
}

/// Removes the staging directories `.NAME.partial-PID` beside `dir` whose
/// process no longer exists; returns each with its process.
pub(super) fn clear_stale(dir: &Path) -> Vec<(PathBuf, i32)> {
    let mut removed = Vec::new();
    let Some(name) = dir.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return removed;
    };
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let prefix = format!(".{name}.partial-");
    let Ok(entries) = std::fs::read_dir(&parent) else {
        return removed;
    };
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let Some(pid) = file
            .strip_prefix(&prefix)
            .and_then(|p| p.parse::<i32>().ok())
        else {
            continue;
        };
        if pid > 0 && pid as u32 != std::process::id() && !alive(pid) {
            let path = entry.path();
            if std::fs::remove_dir_all(&path).is_ok() {
                removed.push((path, pid));
            }
        }
    }
    removed
}
