//! Running a command as a child and measuring what it took: its CPU time
//! and peak memory, read from `wait4`'s resource usage so that no other
//! test's children count, with a wall-clock limit for one that hangs.

use std::fs::File;
use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

pub struct Finished {
    /// The exit status, or `None` when a signal ended it (or the limit did).
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
    /// User and system time.
    pub cpu: Duration,
    pub peak_rss_kib: u64,
    /// The wall-clock limit ran out and the child was killed.
    pub timed_out: bool,
}

/// Runs `command` to its end (killing it after `wall_limit`), its standard
/// output and error going to files so that neither pipe can fill and block it.
pub fn run(command: &mut Command, wall_limit: Duration) -> Finished {
    let out = tempfile::tempfile().unwrap();
    let err = tempfile::tempfile().unwrap();
    // Reaped by wait4 below, which gives the usage std's wait does not.
    #[allow(clippy::zombie_processes)]
    let pid = command
        .stdin(Stdio::null())
        .stdout(out.try_clone().unwrap())
        .stderr(err.try_clone().unwrap())
        .spawn()
        .unwrap()
        .id() as libc::pid_t;
    let started = Instant::now();
    let mut timed_out = false;
    let mut status = 0;
    // SAFETY: rusage is plain data that wait4 fills in.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: pid is our own child, not yet reaped; the pointers are to live locals.
        let reaped = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if reaped == pid {
            break;
        }
        assert!(reaped == 0, "wait4 failed: {}", std::io::Error::last_os_error());
        if started.elapsed() > wall_limit && !timed_out {
            timed_out = true;
            // SAFETY: signalling our own child.
            unsafe { libc::kill(pid, libc::SIGKILL) };
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let time = |t: libc::timeval| Duration::new(t.tv_sec as u64, t.tv_usec as u32 * 1000);
    // Lossily: rs274 echoes the program's comments, which may not be UTF-8.
    let read = |mut file: File| {
        use std::io::Seek;
        let mut bytes = Vec::new();
        file.rewind().unwrap();
        file.read_to_end(&mut bytes).unwrap();
        String::from_utf8_lossy(&bytes).into_owned()
    };
    Finished {
        code: libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status)),
        stdout: read(out),
        stderr: read(err),
        cpu: time(usage.ru_utime) + time(usage.ru_stime),
        peak_rss_kib: usage.ru_maxrss as u64,
        timed_out,
    }
}
