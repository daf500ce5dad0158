//! The browser test of `ger view`: the real server on a copy of
//! `host/examples/pocket.ngc`, and a real headless Chromium driving the page
//! (`tests/e2e/view.mjs`, with playwright-core from `tests/e2e/package-lock.json`).
//!
//! It needs node, npm and Chromium (`/usr/bin/chromium`, or `GER_CHROMIUM`).
//! Without them it says loudly that it did not run, and under CI it fails
//! (`support::peer_missing`).
//! `UPDATE_SCREENSHOT=1` writes the screenshot to `host/docs/view.png`, the one the
//! README shows.

mod support;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// Kills the server however the test ends.
struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn runs(program: &str, arg: &str) -> bool {
    Command::new(program).arg(arg).stdout(Stdio::null()).stderr(Stdio::null()).status().is_ok_and(|s| s.success())
}

/// What the test needs and this machine lacks, if anything.
fn missing(chromium: &Path) -> Vec<String> {
    let mut missing = Vec::new();
    if !chromium.is_file() {
        missing.push(format!("Chromium at {}", chromium.display()));
    }
    for tool in ["node", "npm"] {
        if !runs(tool, "--version") {
            missing.push(tool.to_string());
        }
    }
    missing
}

#[test]
fn the_page_in_chromium() {
    let chromium = std::env::var_os("GER_CHROMIUM").map_or_else(|| PathBuf::from("/usr/bin/chromium"), PathBuf::from);
    let missing = missing(&chromium);
    if !missing.is_empty() {
        support::peer_missing(&format!(
            "the browser test of `ger view` needs {} (Debian: apt-get install chromium nodejs npm): it did NOT run",
            missing.join(", ")
        ));
        return;
    }

    let e2e = root().join("tests/e2e");
    if !e2e.join("node_modules/playwright-core").is_dir() {
        let status = Command::new("npm")
            .args(["ci", "--no-audit", "--no-fund"])
            .current_dir(&e2e)
            .status()
            .expect("npm could not be started");
        assert!(status.success(), "`npm ci` in tests/e2e failed: {status}");
    }

    // The server edits and saves its program: give it a copy.
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("pocket.ngc");
    std::fs::copy(root().join("host/examples/pocket.ngc"), &program).unwrap();
    // The examples' machine, and a vise jaw beside the pocket's stock (X 7.5 to 87.5), which the page draws.
    let config = std::fs::read_to_string(root().join("host/examples/ger.toml")).unwrap();
    let jaw = "\n[[fixtures]]\nname = \"jaw\"\nmin = [100, 10, -12]\nmax = [110, 40, 4]\n";
    std::fs::write(dir.path().join("ger.toml"), config + jaw).unwrap();
    // Its own part as its design, for the design layer (coarse: the page remakes it at each edit).
    let render = Command::new(env!("CARGO_BIN_EXE_ger"))
        .current_dir(dir.path())
        .args(["render", "pocket.ngc", "-o", "pocket.stl", "-q", "--resolution", "0.4", "--wizards"])
        .arg(root().join("wizards"))
        .status()
        .expect("ger render could not be started");
    assert!(render.success(), "ger render pocket.ngc failed");

    let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
        .arg("view")
        .arg(&program)
        .arg("--wizards")
        .arg(root().join("wizards"))
        .args(["--port", "0", "--design", "pocket.stl"])
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .spawn()
        .expect("ger view could not be started");
    let stdout = child.stdout.take().unwrap();
    let server = Server(child);

    // The first line names the page; the rest of stdout is drained so the
    // server never blocks on a full pipe.
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut reader = BufReader::new(stdout);
        let mut line = String::new();
        let _ = reader.read_line(&mut line);
        let _ = tx.send(line);
        let _ = std::io::copy(&mut reader, &mut std::io::sink());
    });
    let first = rx.recv_timeout(Duration::from_secs(60)).expect("ger view printed nothing in 60 s");
    let url = first
        .trim()
        .strip_prefix("ger view: ")
        .unwrap_or_else(|| panic!("ger view's first line is not `ger view: URL`: {first:?}"))
        .to_string();

    let screenshot = if std::env::var("UPDATE_SCREENSHOT").is_ok_and(|v| v == "1") {
        root().join("host/docs/view.png")
    } else {
        Path::new(env!("CARGO_TARGET_TMPDIR")).join("view.png")
    };
    let status = Command::new("node")
        .arg("view.mjs")
        .arg(&url)
        .arg(&screenshot)
        .arg(&program)
        .current_dir(&e2e)
        .env("GER_CHROMIUM", &chromium)
        .status()
        .expect("node could not be started");
    drop(server);
    assert!(status.success(), "the browser test failed (its output is above): {status}");
    assert!(screenshot.is_file(), "no screenshot at {}", screenshot.display());
}
