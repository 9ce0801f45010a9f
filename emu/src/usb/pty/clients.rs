//! Who has the pty's terminal side open: its opens and closes as inotify(7)
//! reports them on the terminal's path (IN_OPEN, IN_CLOSE_WRITE,
//! IN_CLOSE_NOWRITE), counted. The emulator's own terminal fd was opened
//! before the watch began, so it is never counted. Without inotify (not
//! Linux, or the watch refused) every moment counts as one client.

pub struct Clients {
    fd: libc::c_int,
    open: u32,
}

/// What the events since last asked say.
pub struct Seen {
    /// somebody opened the terminal (a new client)
    pub arrived: bool,
    /// the last client closed it
    pub emptied: bool,
    /// how many have it open now
    pub open: u32,
}

impl Clients {
    /// No watch: always one client.
    pub fn everyone() -> Clients {
        Clients { fd: -1, open: 1 }
    }
}

#[cfg(target_os = "linux")]
impl Clients {
    pub fn watch(path: &str) -> Clients {
        let Ok(c) = std::ffi::CString::new(path) else { return Clients::everyone() };
        // SAFETY: a fresh inotify fd (non-blocking) and a watch on a NUL-terminated path
        unsafe {
            let fd = libc::inotify_init1(libc::IN_NONBLOCK | libc::IN_CLOEXEC);
            let mask = libc::IN_OPEN | libc::IN_CLOSE_WRITE | libc::IN_CLOSE_NOWRITE;
            if fd < 0 || libc::inotify_add_watch(fd, c.as_ptr(), mask) < 0 {
                if fd >= 0 {
                    libc::close(fd);
                }
                return Clients::everyone();
            }
            Clients { fd, open: 0 }
        }
    }

    /// Reads every event waiting (never blocks).
    pub fn seen(&mut self) -> Seen {
        let (mut arrived, mut emptied) = (false, false);
        // events are 16 bytes and a name (none for a watched file itself)
        let mut buf = [0u8; 4096];
        while self.fd >= 0 {
            // SAFETY: reads at most buf.len() bytes into buf
            let n = unsafe { libc::read(self.fd, buf.as_mut_ptr().cast(), buf.len()) };
            if n <= 0 {
                break;
            }
            let mut at = 0;
            while at + 16 <= n as usize {
                let word =
                    |i: usize| u32::from_ne_bytes([buf[at + i], buf[at + i + 1], buf[at + i + 2], buf[at + i + 3]]);
                let (mask, len) = (word(4), word(12) as usize);
                if mask & libc::IN_OPEN != 0 {
                    self.open += 1;
                    arrived = true;
                }
                if mask & (libc::IN_CLOSE_WRITE | libc::IN_CLOSE_NOWRITE) != 0 {
                    self.open = self.open.saturating_sub(1);
                    emptied |= self.open == 0;
                }
                at += 16 + len;
            }
        }
        Seen { arrived, emptied, open: self.open }
    }
}

#[cfg(not(target_os = "linux"))]
impl Clients {
    pub fn watch(_: &str) -> Clients {
        Clients::everyone()
    }

    pub fn seen(&mut self) -> Seen {
        Seen { arrived: false, emptied: false, open: self.open }
    }
}

impl Drop for Clients {
    fn drop(&mut self) {
        if self.fd >= 0 {
            // SAFETY: the inotify fd is this struct's own, closed once
            unsafe { libc::close(self.fd) };
        }
    }
}
