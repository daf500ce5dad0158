//! What the integration tests share: the rule for a trusted peer (rs274,
//! Chromium, the shared corpus) that this machine lacks, running a program
//! with a time limit (`process`), the corpus and its classes (`corpus`), and
//! the comparison with LinuxCNC's interpreter (`rs274`).

// Every test binary compiles all of this module and uses only part of it.
#![allow(dead_code)]

pub mod corpus;
pub mod process;
pub mod rs274;

use std::io::Write;

/// A peer the test needs is missing. Under CI (the `CI` variable), which
/// installs every peer, that is a failure; elsewhere the test says loudly
/// that it did not run, and passes, so `cargo test` works on a machine
/// without the peer.
pub fn peer_missing(message: &str) {
    assert!(std::env::var_os("CI").is_none(), "{message}; CI must install it (.ci/setup.d/)");
    // Straight to stderr: the test harness hides what a passing test prints with eprintln!.
    let _ = writeln!(std::io::stderr(), "\n**********\n*** NOT RUN: {message}\n**********\n");
}
