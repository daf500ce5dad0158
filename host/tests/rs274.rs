//! Differential test: ger against LinuxCNC's interpreter, `rs274`.
//!
//! Every program in `tests/differential/` is translated by ger and run by
//! `rs274 -g`; the moves each produces (kind, end point, arc centre and turn,
//! feed) are put in machine coordinates in millimetres and compared one by
//! one. rs274 reports positions relative to the active offsets and in the
//! program's current unit, so its offsets and unit changes are followed here.
//!
//! Programs in `tests/differential/lenient/` use the lenient dialect's codes
//! (canned cycles, G28/G30, G53, G10) and are run with `--lenient`; there
//! dwells and spindle starts and stops are compared too. LinuxCNC writes
//! zero-length moves that ger leaves out, so those are not compared.
//!
//! rs274 comes from Debian's `linuxcnc-uspace`. Where it is not installed the
//! test says so and passes, except under CI (the `CI` variable), where a
//! missing peer is a failure: CI installs it.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;

const TOLERANCE_MM: f64 = 0.002;

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    Rapid,
    Feed,
    /// Centre in machine coordinates, and the turn: +1 counter-clockwise, -1 clockwise.
    Arc {
        centre: [f64; 3],
        turn: i32,
    },
    Dwell(f64),
    /// +1 clockwise, -1 counter-clockwise, 0 stopped.
    Spindle(i32),
}

#[derive(Debug)]
struct Move {
    kind: Kind,
    end: [f64; 3],
    /// mm/min; none for rapids.
    feed: Option<f64>,
    /// Where the move came from, for messages.
    source: String,
}

#[derive(Clone, Copy)]
enum Plane {
    XY,
    ZX,
    YZ,
}

impl Plane {
    /// The plane's first and second axes and its normal, as both programs order them.
    fn axes(self) -> [usize; 3] {
        match self {
            Plane::XY => [0, 1, 2],
            Plane::ZX => [2, 0, 1],
            Plane::YZ => [1, 2, 0],
        }
    }
}

fn rs274_available() -> bool {
    Command::new("rs274").arg("-h").output().is_ok()
}

#[test]
fn ger_moves_like_rs274() {
    if !rs274_available() {
        let message = "rs274 (LinuxCNC, Debian package linuxcnc-uspace) is not installed: \
                       the differential test against it did NOT run";
        support::peer_missing(message);
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/differential");
    let config = dir.join("ger.toml");
    let machine = machine(&config);
    let programs_in = |dir: &Path| -> Vec<PathBuf> {
        let mut programs: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "ngc"))
            .collect();
        programs.sort();
        programs
    };
    let strict = programs_in(&dir);
    let lenient = programs_in(&dir.join("lenient"));
    assert!(strict.len() >= 5 && lenient.len() >= 2, "the differential programs are missing");
    let runs = strict.iter().map(|p| (p, false)).chain(lenient.iter().map(|p| (p, true)));
    let mut failures = Vec::new();
    for (program, is_lenient) in runs {
        let ger = moving(ger_moves(program, &config, is_lenient));
        let peer = moving(rs274_moves(program, &machine));
        if let Err(problem) = compare(&ger, &peer) {
            failures.push(format!("{}: {problem}", program.file_name().unwrap().to_string_lossy()));
        } else {
            eprintln!("{}: {} moves agree", program.display(), ger.len());
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Drops moves that go nowhere: LinuxCNC writes some (a retract to where the
/// tool is), ger does not.
fn moving(moves: Vec<Move>) -> Vec<Move> {
    let mut at = [0.0; 3];
    let mut kept = Vec::new();
    for m in moves {
        let stays =
            matches!(m.kind, Kind::Rapid | Kind::Feed) && m.end.iter().zip(at).all(|(a, b)| (a - b).abs() < 1e-9);
        if !m.end[0].is_nan() {
            at = m.end;
        }
        if !stays {
            kept.push(m);
        }
    }
    kept
}

fn compare(ger: &[Move], peer: &[Move]) -> Result<(), String> {
    if ger.len() != peer.len() {
        return Err(format!("ger made {} moves, rs274 {}\nger: {ger:#?}\nrs274: {peer:#?}", ger.len(), peer.len()));
    }
    for (g, p) in ger.iter().zip(peer) {
        let close = |a: &[f64; 3], b: &[f64; 3]| a.iter().zip(b).all(|(a, b)| (a - b).abs() <= TOLERANCE_MM);
        let same_kind = match (&g.kind, &p.kind) {
            (Kind::Arc { centre: c1, turn: t1 }, Kind::Arc { centre: c2, turn: t2 }) => t1 == t2 && close(c1, c2),
            (a, b) => a == b,
        };
        let same_feed = match (g.feed, p.feed) {
            (Some(a), Some(b)) => (a - b).abs() <= TOLERANCE_MM,
            (a, b) => a.is_none() && b.is_none(),
        };
        let same_end = g.end[0].is_nan() && p.end[0].is_nan() || close(&g.end, &p.end);
        let same_kind =
            same_kind || matches!((&g.kind, &p.kind), (Kind::Dwell(a), Kind::Dwell(b)) if (a - b).abs() < 1e-9);
        if !same_kind || !same_end || !same_feed {
            let show = |m: &Move| format!("{}\n      -> {:?}, end {:?}, feed {:?}", m.source, m.kind, m.end, m.feed);
            return Err(format!("moves differ:\n  {}\n  {}", show(g), show(p)));
        }
    }
    Ok(())
}

/// The machine of a ger.toml, in mm (the tests' machine is in mm): the
/// G54..G59 table, then the G30 point.
fn machine(config: &Path) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(config).unwrap();
    let value: toml::Value = toml::from_str(&text).unwrap();
    assert_eq!(value["units"].as_str(), Some("mm"));
    let triple = |entry: &toml::Value| -> [f64; 3] { std::array::from_fn(|i| entry[i].as_float().unwrap()) };
    let mut rows: Vec<[f64; 3]> = (54..=59).map(|n| triple(&value["offsets"][&format!("G{n}")])).collect();
    rows.push(triple(&value["machine"]["g30"]));
    rows
}

fn ger_moves(program: &Path, config: &Path, lenient: bool) -> Vec<Move> {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ger"));
    command.arg("run").arg(program).arg("--config").arg(config);
    if lenient {
        command.arg("--lenient");
    }
    let output = command.output().unwrap();
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert!(
        output.status.success(),
        "ger failed on {}:\n{}",
        program.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    let mut moves = Vec::new();
    let mut position = [0.0; 3];
    let mut plane = Plane::XY;
    let mut feed = None;
    for line in stdout.lines().filter(|l| l.starts_with('N')) {
        let words: Vec<(char, f64)> = line
            .split_whitespace()
            .skip(1)
            .map(|w| (w.chars().next().unwrap(), w[1..].parse::<f64>().unwrap()))
            .collect();
        let word = |letter: char| words.iter().find(|(l, _)| *l == letter).map(|(_, v)| *v);
        let code = words[0];
        if let Some(f) = word('F') {
            feed = Some(f);
        }
        let event = |kind: Kind| Move { kind, end: [f64::NAN; 3], feed: None, source: format!("ger: {line}") };
        match code {
            ('G', 4.0) => moves.push(event(Kind::Dwell(word('P').unwrap()))),
            ('M', 3.0) => moves.push(event(Kind::Spindle(1))),
            ('M', 4.0) => moves.push(event(Kind::Spindle(-1))),
            // M30 stops the spindle, as LinuxCNC's canonical output says.
            ('M', 5.0) | ('M', 30.0) => moves.push(event(Kind::Spindle(0))),
            ('G', 17.0) => plane = Plane::XY,
            ('G', 18.0) => plane = Plane::ZX,
            ('G', 19.0) => plane = Plane::YZ,
            ('G', g) if g <= 3.0 => {
                let start = position;
                for (axis, letter) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                    if let Some(v) = word(letter) {
                        position[axis] = v;
                    }
                }
                let kind = match g as u32 {
                    0 => Kind::Rapid,
                    1 => Kind::Feed,
                    n => {
                        let [a, b, normal] = plane.axes();
                        let offsets = [word('I'), word('J'), word('K')];
                        let mut centre = start;
                        for axis in [a, b] {
                            centre[axis] += offsets[axis].unwrap_or(0.0);
                        }
                        centre[normal] = 0.0;
                        Kind::Arc { centre, turn: if n == 2 { -1 } else { 1 } }
                    }
                };
                let feed = if kind == Kind::Rapid { None } else { feed };
                moves.push(Move { kind, end: position, feed, source: format!("ger: {line}") });
            }
            _ => {}
        }
    }
    moves
}

fn rs274_moves(program: &Path, machine: &[[f64; 3]]) -> Vec<Move> {
    // rs274 reads the offsets table from a var file, in inches, and writes it
    // back when it exits: give it a fresh one each time.
    let scratch = tempfile::tempdir().unwrap();
    let var = scratch.path().join("ger.var");
    let mut text = String::new();
    let (table, g30) = machine.split_at(6);
    // rs274 wants its parameters in ascending order: G30's point (5181..) first.
    for (axis, value) in g30[0].iter().enumerate() {
        text.push_str(&format!("{}\t{:.6}\n", 5181 + axis, value / 25.4));
    }
    for (i, entry) in table.iter().enumerate() {
        for (axis, value) in entry.iter().enumerate() {
            text.push_str(&format!("{}\t{:.6}\n", 5221 + 20 * i + axis, value / 25.4));
        }
    }

    std::fs::write(&var, text).unwrap();
    // rs274 truncates $HOME/.tool.mmap when it starts: a home of its own keeps runs apart.
    let output =
        Command::new("rs274").env("HOME", scratch.path()).arg("-g").arg("-v").arg(&var).arg(program).output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !stdout
            .lines()
            .chain(stderr.lines())
            .any(|l| !l.contains("N.....") && !l.trim().is_empty() && l != "executing"),
        "rs274 reported a problem with {}:\n{stdout}{stderr}",
        program.display()
    );

    let mut moves = Vec::new();
    let mut mm_per_unit = 1.0;
    let mut g5x = [0.0; 3];
    let mut g92 = [0.0; 3];
    let mut plane = Plane::XY;
    let mut feed = None;
    for line in stdout.lines() {
        let Some(call) = line.split("N..... ").nth(1) else { continue };
        let (name, args) = call.split_once('(').unwrap_or((call, ")"));
        let args: Vec<&str> = args.trim_end_matches(')').split(',').map(str::trim).collect();
        let number = |i: usize| args[i].parse::<f64>().unwrap();
        let machine = |p: [f64; 3], g5x: &[f64; 3], g92: &[f64; 3]| -> [f64; 3] {
            std::array::from_fn(|axis| (p[axis] + g5x[axis] + g92[axis]) * mm_per_unit)
        };
        match name {
            "USE_LENGTH_UNITS" => {
                let new = if args[0] == "CANON_UNITS_INCHES" { 25.4 } else { 1.0 };
                // Offsets are kept in the current unit: rescale them.
                for offset in [&mut g5x, &mut g92] {
                    *offset = offset.map(|v| v * mm_per_unit / new);
                }
                mm_per_unit = new;
            }
            "SET_G5X_OFFSET" => g5x = [number(1), number(2), number(3)],
            "SET_G92_OFFSET" => g92 = [number(0), number(1), number(2)],
            "SELECT_PLANE" => {
                plane = match args[0] {
                    "CANON_PLANE_XY" => Plane::XY,
                    "CANON_PLANE_XZ" => Plane::ZX,
                    _ => Plane::YZ,
                }
            }
            "SET_FEED_RATE" => feed = Some(number(0) * mm_per_unit),
            "DWELL" => {
                moves.push(Move { kind: Kind::Dwell(number(0)), end: [f64::NAN; 3], feed: None, source: call.into() })
            }
            "START_SPINDLE_CLOCKWISE" | "START_SPINDLE_COUNTERCLOCKWISE" | "STOP_SPINDLE_TURNING" => {
                let turn = match name {
                    "START_SPINDLE_CLOCKWISE" => 1,
                    "START_SPINDLE_COUNTERCLOCKWISE" => -1,
                    _ => 0,
                };
                moves.push(Move { kind: Kind::Spindle(turn), end: [f64::NAN; 3], feed: None, source: call.into() });
            }
            // What follows the end (a spindle stop, resets) is LinuxCNC's, not the program's.
            "PROGRAM_END" => break,
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" => {
                let end = machine([number(0), number(1), number(2)], &g5x, &g92);
                let (kind, feed) = if name == "STRAIGHT_TRAVERSE" { (Kind::Rapid, None) } else { (Kind::Feed, feed) };
                moves.push(Move { kind, end, feed, source: format!("rs274: {call}") });
            }
            "ARC_FEED" => {
                let [a, b, normal] = plane.axes();
                let mut end = [0.0; 3];
                end[a] = number(0);
                end[b] = number(1);
                end[normal] = number(5);
                let mut centre = [0.0; 3];
                centre[a] = number(2);
                centre[b] = number(3);
                let end = machine(end, &g5x, &g92);
                let mut centre = machine(centre, &g5x, &g92);
                centre[normal] = 0.0;
                let turn = number(4).signum() as i32;
                moves.push(Move { kind: Kind::Arc { centre, turn }, end, feed, source: format!("rs274: {call}") });
            }
            _ => {}
        }
    }
    moves
}
