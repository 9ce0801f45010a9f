//! The temporaries a write stages (`.NAME.polyturn-PID.tmp`) are removed if
//! the command is interrupted while they exist: Ctrl-C (SIGINT), SIGTERM,
//! SIGHUP (the terminal closed, an SSH session dropped) or SIGQUIT (Ctrl-\),
//! say while a FIFO waits for its reader. The handler only unlinks paths
//! made ready beforehand (unlink(2) is async-signal-safe, signal-safety(7)),
//! then dies of the same signal with its default action, so that the shell
//! sees the command interrupted, not ended.

use std::ffi::{c_char, CString};
use std::os::unix::ffi::OsStrExt;
use std::path::Path;
use std::sync::atomic::{AtomicPtr, Ordering};

/// A command writes a few files; more than this many at once are still
/// written, only not removed on a signal.
const SLOTS: usize = 16;
static TEMPS: [AtomicPtr<c_char>; SLOTS] = [const { AtomicPtr::new(std::ptr::null_mut()) }; SLOTS];
const SIGNALS: [libc::c_int; 4] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP, libc::SIGQUIT];

extern "C" fn on_signal(sig: libc::c_int) {
    for slot in &TEMPS {
        let p = slot.load(Ordering::SeqCst);
        if !p.is_null() {
            // SAFETY: a NUL-terminated path this module keeps alive while set
            unsafe { libc::unlink(p) };
        }
    }
    // SAFETY: both are async-signal-safe; the default action ends the process
    unsafe {
        libc::signal(sig, libc::SIG_DFL);
        libc::raise(sig);
    }
}

/// While it lives, SIGINT, SIGTERM, SIGHUP and SIGQUIT remove the temporaries `add`ed (a
/// signal the process ignores stays ignored); dropped, the handlers are
/// what they were.
pub struct Guard {
    old: Vec<(libc::c_int, libc::sigaction)>,
    mine: Vec<usize>,
}

impl Guard {
    pub fn new() -> Guard {
        let mut old = Vec::new();
        for sig in SIGNALS {
            // SAFETY: sigaction with zeroed structs is how the old action is
            // read and a plain handler installed (sa_flags 0: no SA_SIGINFO)
            unsafe {
                let mut was: libc::sigaction = std::mem::zeroed();
                libc::sigaction(sig, std::ptr::null(), &mut was);
                if was.sa_sigaction == libc::SIG_IGN {
                    continue;
                }
                let mut act: libc::sigaction = std::mem::zeroed();
                act.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
                libc::sigemptyset(&mut act.sa_mask);
                libc::sigaction(sig, &act, std::ptr::null_mut());
                old.push((sig, was));
            }
        }
        Guard { old, mine: Vec::new() }
    }

    /// `path` is removed if a signal comes before the guard is dropped.
    pub fn add(&mut self, path: &Path) {
        let Ok(c) = CString::new(path.as_os_str().as_bytes()) else { return };
        let p = c.into_raw();
        let free = TEMPS
            .iter()
            .position(|s| s.compare_exchange(std::ptr::null_mut(), p, Ordering::SeqCst, Ordering::SeqCst).is_ok());
        match free {
            Some(i) => self.mine.push(i),
            // SAFETY: `p` came from into_raw just above and was not stored
            None => drop(unsafe { CString::from_raw(p) }),
        }
    }
}

impl Drop for Guard {
    fn drop(&mut self) {
        for (sig, was) in &self.old {
            // SAFETY: puts back the action read in `new`
            unsafe { libc::sigaction(*sig, was, std::ptr::null_mut()) };
        }
        for &i in &self.mine {
            let p = TEMPS[i].swap(std::ptr::null_mut(), Ordering::SeqCst);
            if !p.is_null() {
                // SAFETY: stored by `add` from into_raw, taken out once here
                drop(unsafe { CString::from_raw(p) });
            }
        }
    }
}
