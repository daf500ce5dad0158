//! End-to-end cases: every `NAME.ngc` under the repository's `tests/` folder
//! (but `tests/differential/`, which rs274 judges) is run through the real
//! `ger` binary and compared with the files beside it:
//!
//! - `NAME.out`: the expected standard output (absent: must be empty);
//! - `NAME.err`: the expected standard error (absent: must be empty); the
//!   exit status must be 1 when it holds an `error:` line, 0 otherwise;
//! - `NAME.args` (optional): the command and options, default `run`; the
//!   program's file name is added last;
//! - `NAME.toml` (optional): the machine, passed with `--config`.
//!
//! The expectations were worked out by hand, not blessed from the binary.
//! `UPDATE_EXPECT=1 cargo test --test cases` rewrites them from the actual
//! output, for reviewing a deliberate change with `git diff`.

use std::path::{Path, PathBuf};
use std::process::Command;

use libtest_mimic::{Arguments, Failed, Trial};

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests");
    let mut programs = Vec::new();
    collect(&root, &mut programs);
    programs.sort();
    let trials = programs
        .into_iter()
        .map(|program| {
            let name = program.strip_prefix(&root).unwrap().with_extension("").display().to_string();
            Trial::test(name, move || run_case(&program))
        })
        .collect();
    libtest_mimic::run(&Arguments::from_args(), trials).exit();
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            // Those programs are judged by LinuxCNC's rs274 instead (host/tests/rs274.rs).
            if path.file_name().is_some_and(|n| n != "differential") {
                collect(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "ngc") {
            out.push(path);
        }
    }
}

fn run_case(program: &Path) -> Result<(), Failed> {
    let dir = program.parent().unwrap();
    let file_name = program.file_name().unwrap();
    let sibling = |ext: &str| program.with_extension(ext);
    let args = std::fs::read_to_string(sibling("args")).unwrap_or_else(|_| "run".to_string());
    let mut command = Command::new(env!("CARGO_BIN_EXE_ger"));
    command.current_dir(dir).env("NO_COLOR", "1").args(args.split_whitespace());
    if sibling("toml").exists() {
        command.arg("--config").arg(sibling("toml").file_name().unwrap());
    }
    let output = command.arg(file_name).output()?;
    let stdout = String::from_utf8(output.stdout)?;
    let stderr = String::from_utf8(output.stderr)?;

    if std::env::var_os("UPDATE_EXPECT").is_some() {
        update(&sibling("out"), &stdout)?;
        update(&sibling("err"), &stderr)?;
        return Ok(());
    }
    let expected_out = std::fs::read_to_string(sibling("out")).unwrap_or_default();
    let expected_err = std::fs::read_to_string(sibling("err")).unwrap_or_default();
    let mut problems = Vec::new();
    if stdout != expected_out {
        problems.push(format!("stdout differs:\n--- expected\n{expected_out}--- actual\n{stdout}"));
    }
    if stderr != expected_err {
        problems.push(format!("stderr differs:\n--- expected\n{expected_err}--- actual\n{stderr}"));
    }
    let expected_status = if expected_err.lines().any(|l| l.starts_with("error")) { 1 } else { 0 };
    if output.status.code() != Some(expected_status) {
        problems.push(format!("exit status {:?}, expected {expected_status}", output.status.code()));
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("\n").into())
    }
}

fn update(path: &Path, actual: &str) -> std::io::Result<()> {
    if actual.is_empty() {
        match std::fs::remove_file(path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(e),
            _ => Ok(()),
        }
    } else {
        std::fs::write(path, actual)
    }
}
