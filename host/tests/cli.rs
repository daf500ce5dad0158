//! The command line's promises that the data-driven cases cannot state: exit
//! statuses, output files that are never half-written or clobbered, standard
//! input, and the lexer's and parser's views.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

fn ger(dir: &Path, args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(stdin.as_bytes()).unwrap();
    child.wait_with_output().unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).unwrap()
}

#[test]
fn usage_errors_exit_with_2_and_program_errors_with_1() {
    let dir = tempfile::tempdir().unwrap();
    assert_eq!(ger(dir.path(), &[], "").status.code(), Some(2));
    assert_eq!(ger(dir.path(), &["run", "--stage", "9", "x.ngc"], "").status.code(), Some(2));
    assert_eq!(ger(dir.path(), &["run", "--units", "furlong", "x.ngc"], "").status.code(), Some(2));
    let missing = ger(dir.path(), &["run", "missing.ngc"], "");
    assert_eq!(missing.status.code(), Some(1));
    assert!(text(&missing.stderr).starts_with("error: cannot read missing.ngc:"), "{}", text(&missing.stderr));
    std::fs::write(dir.path().join("bad.ngc"), "G01 X1\n").unwrap();
    assert_eq!(ger(dir.path(), &["run", "bad.ngc"], "").status.code(), Some(1));
}

#[test]
fn a_failed_run_leaves_no_output_file_and_clobbers_none() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.ngc"), "G00 X1\nG07\n").unwrap();
    let failed = ger(dir.path(), &["run", "bad.ngc", "-o", "new.ngc"], "");
    assert_eq!(failed.status.code(), Some(1));
    assert!(!dir.path().join("new.ngc").exists());

    std::fs::write(dir.path().join("kept.ngc"), "precious\n").unwrap();
    ger(dir.path(), &["run", "bad.ngc", "-o", "kept.ngc"], "");
    assert_eq!(std::fs::read_to_string(dir.path().join("kept.ngc")).unwrap(), "precious\n");
    // Nor does it leave its temporary file behind.
    let mut names: Vec<String> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    assert_eq!(names, ["bad.ngc", "kept.ngc"]);
}

#[test]
fn a_good_run_writes_the_whole_output_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("good.ngc"), "G00 X1\n").unwrap();
    std::fs::write(dir.path().join("out.ngc"), "old\n").unwrap();
    let done = ger(dir.path(), &["run", "good.ngc", "-o", "out.ngc"], "");
    assert_eq!(done.status.code(), Some(0));
    assert!(done.stdout.is_empty());
    let written = std::fs::read_to_string(dir.path().join("out.ngc")).unwrap();
    assert_eq!(written, "(ger: translated from good.ngc)\nG20\nG90\nG17\nN1 G00 X1.0000\n");
}

#[test]
fn standard_input_is_read_with_a_dash() {
    let dir = tempfile::tempdir().unwrap();
    let done = ger(dir.path(), &["translate", "-", "--units", "mm"], "G20\nG00 X1\n");
    assert_eq!(text(&done.stdout), "(ger: translated from <stdin>)\nG21\nG90\nG17\nN2 G00 X25.400\n");
    // Diagnostics quote the lines of standard input too.
    let failed = ger(dir.path(), &["run", "-"], "G00 X1\nG00 F5\n");
    assert!(text(&failed.stderr).contains(" --> <stdin>:2:5\n  |\n2 | G00 F5\n"), "{}", text(&failed.stderr));
}

#[test]
fn the_lexer_and_parser_can_be_watched() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("p.ngc"), "N10 G01 X1 (cut); Y2\n").unwrap();
    let tokens = text(&ger(dir.path(), &["tokens", "p.ngc"], "").stdout);
    let expected =
        "1:5\tword     G1\n1:9\tword     X1\n1:12\tcomment  \"cut\"\n1:17\tend\n1:19\tword     Y2\n1:21\tend\n";
    assert_eq!(tokens, expected);
    let parsed = text(&ger(dir.path(), &["parse", "p.ngc"], "").stdout);
    assert_eq!(parsed, "N1 G01 X1.0000\nN1 Y2.0000\n");
}

#[test]
fn check_reports_only() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("ok.ngc"), "G01 X1 F10\n").unwrap();
    // (Cut with the default tool, which check would warn about: allowed here.)
    let clean = ger(dir.path(), &["check", "--allow", "default-tool", "ok.ngc"], "");
    assert_eq!(clean.status.code(), Some(0));
    assert!(
        text(&clean.stdout).starts_with("ok.ngc: no problems found\n  cut       none\n"),
        "{}",
        text(&clean.stdout)
    );
    assert!(clean.stderr.is_empty());
    std::fs::write(dir.path().join("bad.ngc"), "G01 X1\n").unwrap();
    let bad = ger(dir.path(), &["check", "bad.ngc"], "");
    assert_eq!(bad.status.code(), Some(1));
    assert!(text(&bad.stdout).starts_with("bad.ngc: 1 error\n"), "{}", text(&bad.stdout));
    assert!(text(&bad.stderr).starts_with("error: G01 move before any feed rate (F)\n --> bad.ngc:1:1\n"));
}
