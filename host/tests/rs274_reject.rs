//! Parity with LinuxCNC's reject suite (`tests/interp/bad` in LinuxCNC's
//! sources): the programs in `tests/linuxcnc-bad/` are ger-dialect rewrites of
//! the ones that apply to ger (see the README there).
//!
//! - `ger_rejects_every_program`: ger refuses each of them (the expected
//!   diagnostics themselves are checked by `cases.rs` against `NAME.err`).
//! - `rs274_rejects_every_rewrite_with_linuxcncs_message`: each rewrite still
//!   means to LinuxCNC what the original did: `rs274 -g` refuses it with the
//!   message quoted on the program's first line, which reads
//!   `(LinuxCNC tests/interp/bad/NAME.ngc: MESSAGE)`. A comment cannot hold
//!   parentheses, so `{` and `}` in MESSAGE stand for `(` and `)`. As in
//!   LinuxCNC's own harness, the message is the last line but one rs274
//!   writes to standard error (the last is the offending block).
//!
//! A program whose rewrite is not LinuxCNC input with that meaning is listed
//! in `NOT_FOR_RS274`, with the reason. rs274 comes from Debian's
//! `linuxcnc-uspace`; where it is not installed the second test says so and
//! passes, except under CI (the `CI` variable), where it fails.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use support::rs274::{self, Machine};

const TIME_LIMIT: Duration = Duration::from_secs(20);

/// Rewrites rs274 does not reject with LinuxCNC's message, and why.
const NOT_FOR_RS274: &[(&str, &str)] = &[(
    "nested.ngc",
    "written with ger's subprograms (O1 ... M99, M98 P1); LinuxCNC reads those too, but checks nesting only \
     for its own O1 sub ... O1 endsub, so rs274 runs this program",
)];

const HEADER: &str = "(LinuxCNC tests/interp/bad/";

fn programs() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/linuxcnc-bad");
    let mut programs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ngc"))
        .collect();
    programs.sort();
    // The README counts 12 programs that apply, and one extra case.
    assert!(programs.len() >= 13, "tests/linuxcnc-bad/ has only {} programs", programs.len());
    programs
}

fn file_name(program: &Path) -> &str {
    program.file_name().unwrap().to_str().unwrap()
}

/// The original's file name and LinuxCNC's message, from the first line.
fn expectation(program: &Path) -> (String, String) {
    let text = std::fs::read_to_string(program).unwrap();
    let first = text.lines().next().unwrap_or_default();
    let quoted = first
        .strip_prefix(HEADER)
        .and_then(|rest| rest.strip_suffix(')'))
        .and_then(|rest| rest.split_once(": "))
        .unwrap_or_else(|| panic!("{}: the first line must read {HEADER}NAME.ngc: MESSAGE)", program.display()));
    (quoted.0.to_string(), quoted.1.replace('{', "(").replace('}', ")"))
}

#[test]
fn ger_rejects_every_program() {
    let mut accepted = Vec::new();
    for program in programs() {
        let sibling = |ext: &str| program.with_extension(ext);
        let args = std::fs::read_to_string(sibling("args")).unwrap_or_else(|_| "run".to_string());
        let mut command = Command::new(env!("CARGO_BIN_EXE_ger"));
        command.env("NO_COLOR", "1").args(args.split_whitespace());
        if sibling("toml").exists() {
            command.arg("--config").arg(sibling("toml"));
        }
        let output = command.arg(&program).output().unwrap();
        if output.status.code() != Some(1) {
            accepted.push(format!("{}: exit status {:?}", file_name(&program), output.status.code()));
        }
    }
    assert!(accepted.is_empty(), "ger accepts programs LinuxCNC rejects:\n{}", accepted.join("\n"));
}

#[test]
fn rs274_rejects_every_rewrite_with_linuxcncs_message() {
    if !rs274::available() {
        let message = "rs274 (LinuxCNC, Debian package linuxcnc-uspace) is not installed: \
                       the rewrites of LinuxCNC's reject suite were NOT checked against it";
        support::peer_missing(message);
        return;
    }
    let programs = programs();
    for (name, _) in NOT_FOR_RS274 {
        assert!(programs.iter().any(|p| file_name(p) == *name), "NOT_FOR_RS274 names {name}, which is not there");
    }
    let mut failures = Vec::new();
    for program in &programs {
        let name = file_name(program);
        let (original, expected) = expectation(program);
        if let Some((_, why)) = NOT_FOR_RS274.iter().find(|(n, _)| *n == name) {
            eprintln!("{name}: not run through rs274: {why}");
            continue;
        }
        match rs274_error(program) {
            Ok(got) if got == expected => eprintln!("{name}: rs274 rejects it as LinuxCNC's {original} expects"),
            Ok(got) => failures.push(format!("{name}: rs274 says {got:?}, LinuxCNC's {original} expects {expected:?}")),
            Err(problem) => failures.push(format!("{name}: {problem}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The message rs274 rejects `program` with, or why there is none.
fn rs274_error(program: &Path) -> Result<String, String> {
    let machine = machine(&program.with_extension("toml"));
    let output = rs274::run_as_is(program, &machine, TIME_LIMIT);
    let stderr = output.stderr;
    if output.timed_out {
        return Err("rs274 ran for too long".into());
    }
    if output.code == Some(0) {
        return Err(format!("rs274 accepts it:\n{stderr}"));
    }
    let lines: Vec<&str> = stderr.lines().collect();
    match lines.len() {
        n if n >= 2 => Ok(lines[n - 2].trim().to_string()),
        _ => Err(format!("rs274 failed without saying why:\n{stderr}")),
    }
}

/// The machine of a program's ger.toml for rs274: its tools (none without one).
fn machine(config: &Path) -> Machine {
    let Ok(text) = std::fs::read_to_string(config) else { return Machine { tools: Vec::new(), ..Machine::default() } };
    let value: toml::Value = toml::from_str(&text).unwrap();
    let mm_per_unit = match value.get("units").and_then(|u| u.as_str()) {
        Some("mm") => 1.0,
        _ => 25.4,
    };
    let tools = value.get("tools").and_then(|t| t.as_array()).map_or(&[][..], |t| t.as_slice());
    let tools = tools
        .iter()
        .map(|tool| {
            let number = tool["number"].as_integer().unwrap() as u32;
            let diameter = &tool["diameter"];
            (number, diameter.as_float().or(diameter.as_integer().map(|d| d as f64)).unwrap() * mm_per_unit)
        })
        .collect();
    Machine { tools, ..Machine::default() }
}
