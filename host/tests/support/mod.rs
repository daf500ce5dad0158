//! What the integration tests share: the rule for a trusted peer (rs274,
//! Chromium, the shared corpus) that this machine lacks, running a program
//! with a time limit, the corpus and its classes (`corpus`), and the
//! comparison with LinuxCNC's interpreter (`rs274`).

// Every test binary compiles all of this module and uses only part of it.
#![allow(dead_code)]

pub mod corpus;
pub mod rs274;

use std::io::{Read, Write};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A peer the test needs is missing. Under CI (the `CI` variable), which
/// installs every peer, that is a failure; elsewhere the test says loudly
/// that it did not run, and passes, so `cargo test` works on a machine
/// without the peer.
pub fn peer_missing(message: &str) {
    assert!(std::env::var_os("CI").is_none(), "{message}; CI must install it (.ci/setup.d/)");
    // Straight to stderr: the test harness hides what a passing test prints with eprintln!.
    let _ = writeln!(std::io::stderr(), "\n**********\n*** NOT RUN: {message}\n**********\n");
}

/// Runs `command` to its end and returns what it wrote, or kills it once it
/// has run for `limit` and returns `None`. Standard input is empty.
pub fn output_within(command: &mut Command, limit: Duration) -> std::io::Result<Option<Output>> {
    let mut child = command.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn()?;
    // Both pipes are drained while the child runs: one it fills would stop it.
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut pipe) = pipe {
                let _ = pipe.read_to_end(&mut bytes);
            }
            bytes
        })
    };
    let stdout = drain(child.stdout.take().map(|p| Box::new(p) as Box<dyn Read + Send>));
    let stderr = drain(child.stderr.take().map(|p| Box::new(p) as Box<dyn Read + Send>));
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait()? {
            break Some(status);
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let (stdout, stderr) = (stdout.join().unwrap_or_default(), stderr.join().unwrap_or_default());
    Ok(status.map(|status| Output { status, stdout, stderr }))
}
