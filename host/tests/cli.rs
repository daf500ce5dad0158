//! The command line's promises that the data-driven cases cannot state: exit
//! statuses, output files that are never half-written or clobbered (and
//! devices, FIFOs and symlinks written through, not replaced), standard
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

#[test]
fn numbers_past_any_machine_on_the_command_line_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("p.ngc"), "G01 Z-0.1 F10\n").unwrap();
    for args in [
        &["check", "p.ngc", "--memory-limit", "18446744073709551615"][..],
        &["check", "p.ngc", "--resolution", "1e-9"],
        &["render", "p.ngc", "-o", "p.png", "--zoom", "1e-300"],
        &["render", "p.ngc", "-o", "p.png", "--azimuth", "1e300"],
        &["render", "p.ngc", "-o", "p.png", "--size", "100000x10"],
        &["run", "p.ngc", "--wizard-time", "1e-300"],
        &["pulses", "p.ngc", "--steps-per-unit", "1e300"],
    ] {
        let done = ger(dir.path(), args, "");
        assert_eq!(done.status.code(), Some(2), "{args:?}: {}", text(&done.stderr));
        assert!(text(&done.stderr).contains("expected"), "{args:?}: {}", text(&done.stderr));
    }
    // Within both units' bounds, but under a millimetre machine's smallest length (1 µm).
    std::fs::write(dir.path().join("ger.toml"), "units = \"mm\"\n").unwrap();
    let done = ger(dir.path(), &["check", "p.ngc", "--resolution", "0.0001"], "");
    assert_eq!(done.status.code(), Some(2));
    assert_eq!(text(&done.stderr), "error: --resolution must be from 0.001 to 100000 mm\n");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2, "no output was written");
}

#[cfg(unix)]
mod files {
    //! `-o` by what the path is: tests make their own FIFO, pty, symlinks and
    //! modes in a temporary folder, never touching a shared system file.

    use std::ffi::CString;
    use std::io::Read;
    use std::os::unix::fs::{FileTypeExt, PermissionsExt};
    use std::os::unix::process::{CommandExt, ExitStatusExt};
    use std::path::Path;
    use std::process::{Command, ExitStatus, Stdio};
    use std::time::{Duration, Instant};

    use super::{ger, text};

    const PROGRAM: &str = "G00 X1\n";
    const TRANSLATION: &str = "(ger: translated from p.ngc)\nG20\nG90\nG17\nN1 G00 X1.0000\n";

    fn folder() -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("p.ngc"), PROGRAM).unwrap();
        std::fs::write(dir.path().join("bad.ngc"), "G00 X1\nG07\n").unwrap();
        dir
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        names.sort();
        names
    }

    fn mode(path: &Path) -> u32 {
        std::fs::metadata(path).unwrap().permissions().mode() & 0o7777
    }

    fn mkfifo(path: &Path) {
        let name = CString::new(path.to_str().unwrap()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0, "mkfifo");
    }

    #[test]
    fn an_existing_output_keeps_its_mode_and_a_new_one_gets_the_umasks() {
        let dir = folder();
        let out = dir.path().join("out.ngc");
        for kept in [0o640, 0o604, 0o444] {
            std::fs::write(&out, "old\n").unwrap();
            std::fs::set_permissions(&out, std::fs::Permissions::from_mode(kept)).unwrap();
            assert_eq!(ger(dir.path(), &["run", "p.ngc", "-o", "out.ngc"], "").status.code(), Some(0));
            assert_eq!(std::fs::read_to_string(&out).unwrap(), TRANSLATION);
            assert_eq!(mode(&out), kept);
            std::fs::remove_file(&out).unwrap();
        }
        // A new file: what any program's new file gets here (0666 less the umask), not tempfile's 0600.
        std::fs::File::create(dir.path().join("probe")).unwrap();
        assert_eq!(ger(dir.path(), &["run", "p.ngc", "-o", "new.ngc"], "").status.code(), Some(0));
        assert_eq!(mode(&dir.path().join("new.ngc")), mode(&dir.path().join("probe")));
    }

    #[test]
    fn a_symlink_is_written_through_and_stays_a_link() {
        let dir = folder();
        std::fs::create_dir(dir.path().join("real")).unwrap();
        std::fs::write(dir.path().join("real/out.ngc"), "old\n").unwrap();
        std::fs::set_permissions(dir.path().join("real/out.ngc"), std::fs::Permissions::from_mode(0o640)).unwrap();
        std::os::unix::fs::symlink("real/out.ngc", dir.path().join("link.ngc")).unwrap();
        // A dangling link: writing through it makes its target, as the shell's `>` does.
        std::os::unix::fs::symlink("real/new.ngc", dir.path().join("dangling.ngc")).unwrap();
        for (link, target) in [("link.ngc", "real/out.ngc"), ("dangling.ngc", "real/new.ngc")] {
            let done = ger(dir.path(), &["run", "p.ngc", "-o", link], "");
            assert_eq!(done.status.code(), Some(0), "{}", text(&done.stderr));
            assert!(std::fs::symlink_metadata(dir.path().join(link)).unwrap().file_type().is_symlink());
            assert_eq!(std::fs::read_to_string(dir.path().join(target)).unwrap(), TRANSLATION);
        }
        assert_eq!(mode(&dir.path().join("real/out.ngc")), 0o640);
        assert_eq!(names(&dir.path().join("real")), ["new.ngc", "out.ngc"]);
        assert_eq!(names(dir.path()), ["bad.ngc", "dangling.ngc", "link.ngc", "p.ngc", "real"]);
    }

    #[test]
    fn a_fifo_is_written_directly_and_gets_nothing_from_a_failed_run() {
        let dir = folder();
        let fifo = dir.path().join("fifo");
        mkfifo(&fifo);
        for (program, status, expected) in [("p.ngc", 0, TRANSLATION), ("bad.ngc", 1, "")] {
            let reader = {
                let fifo = fifo.clone();
                std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
            };
            let done = ger(dir.path(), &["run", program, "-o", "fifo"], "");
            assert_eq!(done.status.code(), Some(status), "{}", text(&done.stderr));
            assert_eq!(reader.join().unwrap(), expected);
            assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        }
        assert_eq!(names(dir.path()), ["bad.ngc", "fifo", "p.ngc"]);
    }

    #[test]
    fn a_character_device_is_written_directly_and_stays_one() {
        // A pseudo-terminal of our own: its slave is a character device nobody else uses.
        let master = unsafe { libc::posix_openpt(libc::O_RDWR | libc::O_NOCTTY) };
        assert!(master >= 0, "posix_openpt");
        assert_eq!(unsafe { libc::grantpt(master) }, 0);
        assert_eq!(unsafe { libc::unlockpt(master) }, 0);
        let mut name = [0 as libc::c_char; 128];
        assert_eq!(unsafe { libc::ptsname_r(master, name.as_mut_ptr(), name.len()) }, 0);
        let slave = unsafe { std::ffi::CStr::from_ptr(name.as_ptr()) }.to_str().unwrap().to_string();
        let mut master = unsafe { <std::fs::File as std::os::fd::FromRawFd>::from_raw_fd(master) };
        let dir = folder();
        let done = ger(dir.path(), &["run", "p.ngc", "-o", &slave], "");
        assert_eq!(done.status.code(), Some(0), "{}", text(&done.stderr));
        assert!(std::fs::metadata(&slave).unwrap().file_type().is_char_device(), "{slave} was replaced");
        // The terminal turns each \n into \r\n; the slave is closed, so the read ends after the text.
        let mut read = Vec::new();
        let mut buffer = [0u8; 4096];
        while let Ok(n @ 1..) = master.read(&mut buffer) {
            read.extend_from_slice(&buffer[..n]);
        }
        assert_eq!(String::from_utf8(read).unwrap().replace("\r\n", "\n"), TRANSLATION);
        assert_eq!(names(dir.path()), ["bad.ngc", "p.ngc"]);
    }

    /// A folder with `long.ngc`, long enough to render that a signal comes
    /// while the temporary file is there, and an old `out.png`.
    fn long_render() -> tempfile::TempDir {
        let dir = folder();
        let mut program = String::from("G00 Z1\nG01 F1000\n");
        for i in 0..400_000 {
            program += &format!("G01 X{} Y{} Z-0.5\n", i % 100, (i / 100) % 100);
        }
        std::fs::write(dir.path().join("long.ngc"), program).unwrap();
        std::fs::write(dir.path().join("out.png"), "old").unwrap();
        dir
    }

    /// Starts the render of `long.ngc` (`prepare` runs in the child before ger) and
    /// sends `signal` once its temporary file is there.
    fn signalled_render(dir: &Path, signal: libc::c_int, prepare: fn() -> std::io::Result<()>) -> ExitStatus {
        let mut command = Command::new(env!("CARGO_BIN_EXE_ger"));
        command.current_dir(dir).args(["render", "long.ngc", "-o", "out.png", "--quiet"]);
        // SAFETY: `prepare` only changes a signal's disposition, which is safe after fork.
        unsafe { command.pre_exec(prepare) };
        let mut child = command.stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
        let started = Instant::now();
        while !names(dir).iter().any(|n| n.starts_with(".tmp")) {
            assert!(started.elapsed() < Duration::from_secs(120), "no temporary file appeared");
            std::thread::sleep(Duration::from_millis(20));
        }
        assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, signal) }, 0);
        child.wait().unwrap()
    }

    #[test]
    fn a_signal_ger_was_started_ignoring_stays_ignored() {
        // As `nohup` or a shell's `&` leave it: the render goes on to the end.
        let dir = long_render();
        let status = signalled_render(dir.path(), libc::SIGINT, || {
            // SAFETY: setting a disposition to SIG_IGN is async-signal-safe.
            unsafe { libc::signal(libc::SIGINT, libc::SIG_IGN) };
            Ok(())
        });
        assert!(status.success(), "{status:?}");
        assert!(std::fs::read(dir.path().join("out.png")).unwrap().starts_with(b"\x89PNG"));
        assert_eq!(names(dir.path()), ["bad.ngc", "long.ngc", "out.png", "p.ngc"]);
    }

    #[test]
    fn a_signal_during_a_render_removes_its_temporary_file() {
        let dir = long_render();
        for signal in [libc::SIGINT, libc::SIGTERM] {
            // Whatever the test was started with: a shell's `&` leaves SIGINT ignored.
            let status = signalled_render(dir.path(), signal, || {
                // SAFETY: setting a disposition to SIG_DFL is async-signal-safe.
                unsafe {
                    libc::signal(libc::SIGINT, libc::SIG_DFL);
                    libc::signal(libc::SIGTERM, libc::SIG_DFL);
                }
                Ok(())
            });
            assert_eq!(status.signal(), Some(signal), "{status:?}: the render ended before the signal");
            assert_eq!(names(dir.path()), ["bad.ngc", "long.ngc", "out.png", "p.ngc"]);
            assert_eq!(std::fs::read_to_string(dir.path().join("out.png")).unwrap(), "old");
        }
    }
}

#[test]
fn a_program_kept_in_a_file_of_its_own_is_called_by_its_number() {
    // As a Haas keeps O1002 in its memory, a file beside the program holds it.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("main.nc"), "O1001\nG21\nG00 X0 Y0\nM98 P1002 L2\nM30\n").unwrap();
    std::fs::write(dir.path().join("bracket_o1002.nc"), "O1002 (a step)\nG91 G01 X5 F100\nG90\nM99\n").unwrap();
    // A file whose name has the number but whose program is another is not it.
    std::fs::write(dir.path().join("O1002-old.nc"), "O7\nG00 X99\nM99\n").unwrap();
    let output = ger(dir.path(), &["run", "main.nc", "--lenient", "--units", "mm"], "");
    assert!(output.status.success(), "{}", text(&output.stderr));
    let moves: Vec<String> = text(&output.stdout).lines().filter(|l| l.contains("G01")).map(String::from).collect();
    // Its lines carry the call's line, as a wizard's do.
    assert_eq!(moves, ["N4 G01 X5.000 F100.000", "N4 G01 X10.000"]);
    // The strict dialect keeps to the manual: subprograms are in the program.
    let output = ger(dir.path(), &["run", "main.nc", "--units", "mm"], "");
    assert!(text(&output.stderr).contains("error: M98 calls O1002, which is not in the program"));
}

#[test]
fn g65_and_m98_run_a_program_in_a_file_of_its_own_with_the_parameters_of_the_call() {
    // A Fanuc macro kept by number: G65's X, Y, Z arrive in #24, #25, #26; M98 sees #100 as set before it.
    let dir = tempfile::tempdir().unwrap();
    let main = "O1\nG21 G90 F100\nG65 P9001 X10 Y20 Z-1\n#100 = 3\nM98 P9002\n#100 = 4\nM98 P9002\nM30\n";
    std::fs::write(dir.path().join("main.nc"), main).unwrap();
    std::fs::write(dir.path().join("O9001.nc"), "O9001 (HOLE)\nG00 X#24 Y#25\nG01 Z#26\nG00 Z1\nM99\n").unwrap();
    std::fs::write(dir.path().join("O9002.nc"), "%\nO9002\nG01 X#100\nM99\n%\n").unwrap();
    let output = ger(dir.path(), &["run", "main.nc", "--lenient", "--units", "mm"], "");
    assert!(output.status.success(), "{}", text(&output.stderr));
    let moves: Vec<String> = text(&output.stdout).lines().filter(|l| l.contains(" G0")).map(String::from).collect();
    // Its lines carry the call's line, as M98's from files do.
    assert_eq!(
        moves,
        ["N3 G00 X10.000 Y20.000", "N3 G01 Z-1.000 F100.000", "N3 G00 Z1.000", "N5 G01 X3.000", "N7 G01 X4.000"]
    );
}
