//! Wizards end to end through the library: real components from `wizards/`
//! and `tests/wizards/guests/`, built on first use, run by the wasmtime
//! runtime inside the real pipeline. Expectations come from geometry and
//! from what each test wizard is written to do, not from recorded output.

use std::path::{Path, PathBuf};

use ger::config::Config;
use ger::emit::Emitter;
use ger::expand::{Limits, WasmWizards};
use ger::passes::{translate, Event, Library, Options, LAST_STAGE};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
}

/// The program's output lines and its diagnostics.
fn run(dir: &str, config: &Config, program: &str) -> (Vec<String>, Vec<String>) {
    let mut wizards = WasmWizards::new(&repo(dir), config, Limits::default(), Some(Box::new(|_: &str| {})));
    let emitter = Emitter::new(4, false);
    let options = Options { config, stage: LAST_STAGE, wizards: &mut wizards };
    let (mut lines, mut diagnostics) = (Vec::new(), Vec::new());
    for event in translate(program.as_bytes(), Library::empty(), options) {
        match event {
            Event::Statement(s) => lines.push(emitter.line(&s)),
            Event::Diagnostic(d) => diagnostics.push(format!("{d}\n{}", d.help.clone().unwrap_or_default())),
        }
    }
    (lines, diagnostics)
}

fn mm(tools: &str) -> Config {
    Config::from_toml(&format!("units = \"mm\"\n{tools}")).unwrap()
}

/// A move as (G code, start, end), tracking position over the output.
fn moves(lines: &[String]) -> Vec<(u32, [f64; 3], [f64; 3])> {
    let mut at = [0.0; 3];
    let mut mode = 0;
    let mut out = Vec::new();
    for line in lines {
        let mut to = at;
        let mut moved = false;
        for word in line.split_whitespace() {
            let (letter, value) = word.split_at(1);
            let Ok(value) = value.parse::<f64>() else { continue };
            match letter {
                "G" if value < 4.0 => mode = value as u32,
                "X" | "Y" | "Z" => {
                    to["XYZ".find(letter).unwrap()] = value;
                    moved = true;
                }
                _ => {}
            }
        }
        if moved {
            out.push((mode, at, to));
            at = to;
        }
    }
    out
}

fn distance_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 == 0.0 { 0.0 } else { (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0) };
    ((p[0] - a[0] - t * dx).powi(2) + (p[1] - a[1] - t * dy).powi(2)).sqrt()
}

#[test]
fn pocket_stays_inside_covers_the_floor_and_never_goes_too_deep() {
    let (x0, y0, length, width, depth, d) = (10.0, -5.0, 75.0, 30.0, 10.0, 6.0);
    let config = mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6.0\n");
    let program = format!("G21 G90\nG00 X{x0} Y{y0} Z0\nF300\nPocket {length} {width} {depth} 4\nM30\n");
    let (lines, diagnostics) = run("wizards", &config, &program);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let moves = moves(&lines);
    let r = d / 2.0;
    let eps = 1e-3;
    let (xa, xb, ya, yb) = (x0 + r, x0 + length - r, y0 + r, y0 + width - r);
    for (mode, a, b) in &moves {
        assert!(a[2] >= -depth - eps && b[2] >= -depth - eps, "below DEPTH: {a:?} -> {b:?}");
        if *mode == 1 {
            for p in [a, b] {
                assert!(p[0] >= xa - eps && p[0] <= xb + eps && p[1] >= ya - eps && p[1] <= yb + eps, "{p:?}");
            }
        }
    }
    // Rasterize the tool along the feed moves at full depth: every point of
    // the pocket a round tool can reach (within r of the inset rectangle)
    // must be cut; only the corners' fillets are left.
    let floor: Vec<_> = moves
        .iter()
        .filter(|(mode, a, b)| *mode == 1 && (a[2] + depth).abs() < eps && (b[2] + depth).abs() < eps)
        .map(|(_, a, b)| ([a[0], a[1]], [b[0], b[1]]))
        .collect();
    assert!(!floor.is_empty(), "nothing cut at full depth");
    let step = 0.2;
    let (mut checked, mut missed) = (0, Vec::new());
    for i in 0..=(length / step) as usize {
        for j in 0..=(width / step) as usize {
            let p = [x0 + i as f64 * step, y0 + j as f64 * step];
            let nearest = [p[0].clamp(xa, xb), p[1].clamp(ya, yb)];
            if distance_to_segment(p, nearest, nearest) > r - eps {
                continue; // a corner fillet: no round tool reaches it
            }
            checked += 1;
            if !floor.iter().any(|(a, b)| distance_to_segment(p, *a, *b) <= r + eps) {
                missed.push(p);
            }
        }
    }
    assert!(checked > 50_000, "{checked}");
    assert!(missed.is_empty(), "{} points not cut, e.g. {:?}", missed.len(), &missed[..missed.len().min(5)]);
    // Three levels of at most 4: 4, 8, 10.
    let levels: std::collections::BTreeSet<i64> =
        moves.iter().filter(|m| m.0 == 1).map(|m| (m.2[2] * 1000.0).round() as i64).collect();
    assert_eq!(levels.into_iter().collect::<Vec<_>>(), [-10_000, -8_000, -4_000]);
}

#[test]
fn pocket_refuses_a_tool_wider_than_the_pocket_and_keeps_incremental_mode() {
    let config = mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 12.0\n");
    let (_, diagnostics) = run("wizards", &config, "G21\nF100\nPocket 20 10 3\nM30\n");
    assert_eq!(diagnostics.len(), 1);
    assert!(
        diagnostics[0]
            .starts_with("3:1: error: wizard `Pocket`: the tool (T1, diameter 12) is wider than the pocket (20 x 10)"),
        "{diagnostics:?}"
    );
    assert!(diagnostics[0].contains("usage: Pocket LENGTH WIDTH DEPTH [STEPDOWN]"), "{diagnostics:?}");

    let config = mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 2.0\n");
    let (lines, diagnostics) = run("wizards", &config, "G21 G91\nF100\nPocket 4 4 1\nX5\nM30\n");
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    // Pocket leaves the tool where it found it (X0), in G91: X5 is 5 from
    // there, in the G00 that Pocket's last move left modal.
    assert_eq!(lines[lines.len() - 2], "G00 X5.0000");
}

#[test]
fn a_wizard_sees_the_machine_state_at_its_call() {
    let tools = "[[tools]]\nnumber = 2\nkind = \"drill\"\ndiameter = 0.25\nflute_length = 1.0\ntip_angle = 118.0\n";
    let config = Config::from_toml(&format!("units = \"inch\"\n{tools}")).unwrap();
    let program = "G21\nG52 X25.4\nM06 T2\nG00 X10 Y5 Z2\nM03 S1200\nG18 G91\nF250\nEcho\nM30\n";
    let (_, diagnostics) = run("tests/wizards/guests", &config, program);
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    let seen = &diagnostics[0];
    assert!(seen.starts_with("8:1: error: wizard `Echo`: State { units: Mm, position: ["), "{seen}");
    for part in [
        "distance: Incremental",
        "plane: ZX",
        "feed: Some(250.0",
        "spindle: Clockwise(Some(1200.0))",
        "tool: Some(Tool { number: 2, kind: Drill, diameter: 6.35",
        "flute_length: Some(25.4",
        "tip_angle: Some(118.0)",
        "tool_number: 2",
        "line: 8",
        "find_tool(2) = Some(Tool { number: 2, kind: Drill, diameter: 6.35",
        "find_tool(9) = None",
    ] {
        assert!(seen.contains(part), "{part} not in {seen}");
    }
    let position = &seen[seen.find("position: [").unwrap() + 11..];
    let position: Vec<f64> = position[..position.find(']').unwrap()].split(", ").map(|v| v.parse().unwrap()).collect();
    for (got, expected) in position.iter().zip([10.0, 5.0, 2.0]) {
        assert!((got - expected).abs() < 1e-9, "{position:?}");
    }
}

#[test]
fn hostile_wizards_get_clear_diagnostics_and_ger_keeps_working() {
    let program = "G21 G90 G01 F100\nSpin\nHog\nSnoop\nCrash\nChatter\nGarbage\nRecurse\nNest 1\nM30\n";
    // The first run builds the guests from source (a minute on a fresh
    // machine); what is timed below is the calls alone.
    run("tests/wizards/guests", &mm(""), program);
    let started = std::time::Instant::now();
    let (lines, diagnostics) = run("tests/wizards/guests", &mm(""), program);
    let expected = [
        ("2:1: error: wizard `Spin` did not finish within 1 s and was stopped", ""),
        ("3:1: error: wizard `Hog` needed more than 64 MiB of memory and was stopped", "memory allocation"),
        ("4:1: error: wizard `Snoop` panicked", "open /etc/passwd"),
        ("5:1: error: wizard `Crash` panicked", "boom: the wizard gave up"),
        ("6:1: error: wizard `Chatter` wrote more than 64 KiB of output and was stopped", "its stdout (last 12 of"),
        ("7:1: error: wizard `Garbage` returned a bad statement (#2): `%` is not a G-code letter (A-Z)", ""),
        ("8:1: error: wizard calls nest deeper than 16: `Recurse` recurses without end", ""),
    ];
    assert_eq!(diagnostics.len(), expected.len(), "{diagnostics:#?}");
    for (diagnostic, (start, detail)) in diagnostics.iter().zip(expected) {
        assert!(diagnostic.starts_with(start), "{diagnostic}\nshould start with {start}");
        assert!(diagnostic.contains(detail), "{diagnostic}\nshould contain {detail}");
    }
    // The file was not read: the sandbox has no directories.
    assert!(diagnostics[2].contains("No such file or directory") && !diagnostics[2].contains("root:"));
    // Crash's stdout is shown too.
    assert!(diagnostics[3].contains("its stdout:\n  about to give up"), "{}", diagnostics[3]);
    // After all that, a good wizard still runs, and the program goes on.
    assert!(lines.ends_with(&["G01 X1.0000".into(), "G01 X0.0000".into(), "M30".into()]), "{lines:?}");
    // Spin's 1 s is the only long wait: nothing hung (a generous bound, for a loaded machine).
    assert!(started.elapsed().as_secs() < 60, "{:?}", started.elapsed());
}

#[test]
fn limits_are_the_runtimes_to_set() {
    let limits = Limits { time: std::time::Duration::from_millis(200), memory: 8 << 20, ..Limits::default() };
    let config = mm("");
    // Build the two guests first (slow on a fresh machine): only the calls are timed.
    run("tests/wizards/guests", &config, "Spin\nHog\n");
    let mut wizards = WasmWizards::new(&repo("tests/wizards/guests"), &config, limits, Some(Box::new(|_: &str| {})));
    let options = Options { config: &config, stage: LAST_STAGE, wizards: &mut wizards };
    let started = std::time::Instant::now();
    let diagnostics: Vec<String> = translate("Spin\nHog\n".as_bytes(), Library::empty(), options)
        .filter_map(|e| match e {
            Event::Diagnostic(d) => Some(d.message),
            Event::Statement(_) => None,
        })
        .collect();
    assert_eq!(
        diagnostics,
        [
            "wizard `Spin` did not finish within 0.2 s and was stopped",
            "wizard `Hog` needed more than 8 MiB of memory and was stopped"
        ]
    );
    assert!(started.elapsed().as_millis() < 5_000, "{:?}", started.elapsed());
}

#[test]
fn a_missing_wizard_lists_the_ones_there_are() {
    let (_, diagnostics) = run("tests/wizards/guests", &mm(""), "Pocket 1 2 3\n");
    assert!(diagnostics[0].starts_with("1:1: error: no wizard named `Pocket` in "), "{diagnostics:?}");
    assert!(diagnostics[0].contains("chatter, crash, echo"), "{diagnostics:?}");
}

fn ger(args: &[&str], stdin: &str, target_dir: &Path) -> (String, String, i32) {
    use std::io::Write;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(args)
        .env("NO_COLOR", "1")
        // Share compiled dependencies with the test wizards' builds.
        .env("CARGO_TARGET_DIR", target_dir)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(stdin.as_bytes()).unwrap();
    let output = child.wait_with_output().unwrap();
    let text = |b: Vec<u8>| String::from_utf8(b).unwrap();
    (text(output.stdout), text(output.stderr), output.status.code().unwrap_or(-1))
}

#[test]
fn a_new_wizard_builds_and_runs_unchanged_and_is_listed() {
    let dir = tempfile::tempdir().unwrap();
    let wizards = dir.path().to_str().unwrap();
    let target = repo("tests/wizards/guests/target/cargo");
    let (out, err, status) = ger(&["wizard", "new", "Square", "--wizards", wizards], "", &target);
    assert_eq!(status, 0, "{out}{err}");
    assert!(out.contains("created") && dir.path().join("square/src/lib.rs").is_file(), "{out}");
    let (_, err, status) = ger(&["wizard", "new", "Sq1", "--wizards", wizards], "", &target);
    assert_eq!(status, 1);
    assert!(err.contains("`Sq1` cannot be a wizard's name"), "{err}");

    // `ger run` builds it (its .wasm is missing) and runs it.
    let program = "G21 G90\nG00 X0 Y0 Z0\nF100\nSquare 10 1\nM30\n";
    let (out, err, status) =
        ger(&["run", "--units", "mm", "--no-line-numbers", "--wizards", wizards, "-"], program, &target);
    assert_eq!(status, 0, "{err}");
    let body: Vec<&str> = out.lines().skip_while(|l| !l.starts_with("G00 X0")).skip(1).collect();
    assert_eq!(
        body,
        ["G01 Z-1.000 F100.000", "G01 X10.000", "G01 Y10.000", "G01 X0.000", "G01 Y0.000", "G00 Z0.000", "M30"]
    );

    let (out, err, status) = ger(&["wizard", "list", "--wizards", wizards], "", &target);
    assert_eq!(status, 0, "{err}");
    assert!(out.starts_with("Square SIDE DEPTH"), "{out}");
    assert!(out.contains("(square, Rust)") && out.contains("SIDE         side of the square"), "{out}");

    // --no-build: a missing .wasm is an error that says how to build it.
    std::fs::remove_file(dir.path().join("square.wasm")).unwrap();
    let (_, err, status) = ger(&["check", "--no-build", "--wizards", wizards, "-"], program, &target);
    assert_eq!(status, 1);
    assert!(err.contains("wizard `Square` is not built") && err.contains("ger wizard build"), "{err}");
}

#[test]
fn watch_translates_again_when_the_program_or_a_wizard_changes() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().unwrap();
    let wizards = dir.path().join("wizards");
    std::fs::create_dir(&wizards).unwrap();
    // Built by an earlier use if need be.
    run("wizards", &mm(""), "BoltCircle 1 1 1\nPocket 1 1 1\n");
    // `Ww` is BoltCircle at first, then Pocket: the same call, another wizard.
    std::fs::copy(repo("wizards/boltcircle.wasm"), wizards.join("ww.wasm")).unwrap();
    let program = dir.path().join("p.ngc");
    std::fs::write(&program, "G21\nF100\nWw 10 20 1\nM30\n").unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["run", "--units", "mm", "--no-line-numbers", "--watch", "--wizards"])
        .arg(&wizards)
        .arg(&program)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let stdout = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(stdout).lines() {
            if tx.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    let next_run = || -> Vec<String> {
        let mut lines = Vec::new();
        while let Ok(line) = rx.recv_timeout(std::time::Duration::from_secs(30)) {
            let done = line == "M30";
            lines.push(line);
            if done {
                break;
            }
        }
        lines
    };
    // Ten holes on a circle of diameter 20, the first at angle 0.
    let first = next_run();
    assert!(first.contains(&"G00 X10.000 Y0.000".to_string()), "{first:?}");
    std::fs::write(&program, "G21\nF100\nX3\nWw 10 20 1\nM30\n").unwrap();
    let second = next_run();
    assert!(second.contains(&"G00 X13.000 Y0.000".to_string()), "{second:?}");
    // Pocket 10 x 20 x 1: rows along X, stepping in Y, which BoltCircle never does.
    // Later than the run's own writes, which the watcher lets pass.
    std::thread::sleep(std::time::Duration::from_millis(500));
    std::fs::copy(repo("wizards/pocket.wasm"), wizards.join("ww.wasm")).unwrap();
    let third = next_run();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(third.iter().any(|l| l.starts_with("G01 Y")), "{third:?}");
    assert!(!third.contains(&"G00 X13.000 Y0.000".to_string()), "{third:?}");
}
