//! Nothing endless, nothing unbounded, nothing non-finite: inputs that once
//! made ger loop, grow without bound or write `inf`, run through the real
//! binary with their CPU time and peak memory measured.

#[path = "support/process.rs"]
mod process;

use std::path::Path;
use std::process::Command;
use std::time::Duration;

fn ger(dir: &Path, args: &[&str]) -> process::Finished {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ger"));
    command.args(args).current_dir(dir).env("NO_COLOR", "1");
    process::run(&mut command, Duration::from_secs(120))
}

fn program(dir: &Path, name: &str, text: &str) -> String {
    std::fs::write(dir.join(name), text).unwrap();
    name.to_string()
}

#[test]
fn white_space_of_every_kind_ends_a_wizard_argument() {
    // A lone CR, VT, a no-break space and an em space after a wizard's
    // argument made the lexer loop forever, allocating.
    let dir = tempfile::tempdir().unwrap();
    for (i, space) in ["\r", "\u{b}", "\u{a0}", "\u{2003}"].into_iter().enumerate() {
        let file = program(dir.path(), &format!("p{i}.ngc"), &format!("G21\nPocket 10{space}20 3\nM30\n"));
        for command in ["tokens", "parse", "run"] {
            let run = ger(dir.path(), &[command, &file, "--no-build"][..if command == "run" { 3 } else { 2 }]);
            assert!(!run.timed_out && run.cpu < Duration::from_secs(10), "{command} {space:?}: {:?}", run.cpu);
            assert!(run.peak_rss_kib < 200_000, "{command} {space:?}: {} KiB", run.peak_rss_kib);
            assert!(matches!(run.code, Some(0 | 1)), "{command} {space:?}: {:?}\n{}", run.code, run.stderr);
        }
    }
}

#[test]
fn a_canned_cycle_repeated_many_times_streams() {
    // G81 ... L1000000 was expanded into memory at once (790 MB). Now its
    // holes are made one at a time: memory stays flat while the output grows.
    let dir = tempfile::tempdir().unwrap();
    let file = program(dir.path(), "l.ngc", "G21\nG00 Z5\nG91 G81 X1 Z-1 R1 L200000 F100\nG90 G80\nM30\n");
    let run = ger(dir.path(), &["run", &file, "--lenient", "--units", "mm", "-o", "out.ngc"]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let output = std::fs::read_to_string(dir.path().join("out.ngc")).unwrap();
    // Each hole: over it (X), down to R, feed to the bottom, back up.
    assert_eq!(output.lines().filter(|l| l.contains("G01 Z")).count(), 200_000);
    assert!(output.contains("G00 X200000.000"), "the last hole is at X200000");
    assert!(run.peak_rss_kib < 60_000, "peak {} KiB", run.peak_rss_kib);
}

#[test]
fn a_peck_depth_far_too_small_is_an_error_not_an_endless_expansion() {
    let dir = tempfile::tempdir().unwrap();
    let file = program(dir.path(), "q.ngc", "G21\nG00 Z5\nG83 X0 Y0 Z-100 R1 Q0.000001 F100\nM30\n");
    let run = ger(dir.path(), &["run", &file, "--lenient", "--units", "mm"]);
    assert_eq!(run.code, Some(1));
    assert!(
        run.stderr.contains("error: G83: pecks of 0.000 mm down 101.000 mm make more than 10000 pecks"),
        "{}",
        run.stderr
    );
}

#[test]
fn numbers_too_large_for_an_f64_are_errors_at_the_word() {
    // 310 digits read as inf: `ger run` wrote `G00 Xinf` with exit 0 and
    // `ger render` panicked in the height field.
    let dir = tempfile::tempdir().unwrap();
    let huge = format!("1{}", "0".repeat(310));
    let file = program(dir.path(), "big.ngc", &format!("G21\nG00 X{huge}\nG01 X1 F1\nM30\n"));
    for args in [vec!["run", &file], vec!["check", &file], vec!["render", &file, "-o", "big.png"]] {
        let run = ger(dir.path(), &args);
        assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains("--> big.ngc:2:5"), "{args:?}: {}", run.stderr);
        assert!(!run.stdout.contains("inf") && !run.stdout.contains("NaN"), "{args:?}: {}", run.stdout);
    }
    assert!(!dir.path().join("big.png").exists());
}
