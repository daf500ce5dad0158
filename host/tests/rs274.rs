//! Differential test: ger against LinuxCNC's interpreter, `rs274`.
//!
//! Every program in `tests/differential/` is translated by ger and run by
//! `rs274 -g`; the moves each produces (kind, end point, arc centre and turn,
//! feed, dwells, spindle changes) are put in machine coordinates in
//! millimetres and compared one by one (`support/rs274.rs`). Programs in
//! `tests/differential/lenient/` use the lenient dialect's codes (canned
//! cycles, G28/G30, G53, G10) and are run with `--lenient`.
//!
//! The other tests here check the comparison itself, on inputs whose moves
//! are worked out by hand.
//!
//! rs274 comes from Debian's `linuxcnc-uspace`. Where it is not installed the
//! test says so and passes, except under CI (the `CI` variable), where a
//! missing peer is a failure: CI installs it.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use support::rs274::{self, Kind, Machine, Moves, TOLERANCE_MM};

const TIME_LIMIT: Duration = Duration::from_secs(20);

fn rs274_missing() -> bool {
    if rs274::available() {
        return false;
    }
    let message = "rs274 (LinuxCNC, Debian package linuxcnc-uspace) is not installed: \
                   the differential test against it did NOT run";
    support::peer_missing(message);
    true
}

#[test]
fn ger_moves_like_rs274() {
    if rs274_missing() {
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/differential");
    let config = dir.join("ger.toml");
    let machine = machine(&config);
    let strict = programs_in(&dir);
    let lenient = programs_in(&dir.join("lenient"));
    assert!(strict.len() >= 5 && lenient.len() >= 2, "the differential programs are missing");
    let runs = strict.iter().map(|p| (p, false)).chain(lenient.iter().map(|p| (p, true)));
    let failures = disagreements(runs, &config, &machine);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// LinuxCNC keeps the coordinate systems', G92's and G28/G30's parameters
/// in the machine's unit, and rs274's machine is in inches: the programs
/// that read them run on an inch machine on both sides.
#[test]
fn machine_unit_parameters_read_like_rs274() {
    if rs274_missing() {
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/differential/inch-machine");
    let programs = programs_in(&dir);
    assert!(!programs.is_empty(), "the inch machine's programs are missing");
    let failures = disagreements(programs.iter().map(|p| (p, true)), &dir.join("ger.toml"), &Machine::default());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn programs_in(dir: &Path) -> Vec<PathBuf> {
    let mut programs: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ngc"))
        .collect();
    programs.sort();
    programs
}

/// Each program (and whether it is lenient) run by both on `machine`: what disagrees.
fn disagreements<'a>(runs: impl Iterator<Item = (&'a PathBuf, bool)>, config: &Path, machine: &Machine) -> Vec<String> {
    let mut failures = Vec::new();
    for (program, is_lenient) in runs {
        let name = program.file_name().unwrap().to_string_lossy();
        let peer = rs274::moves(program, machine, TIME_LIMIT)
            .unwrap_or_else(|refusal| panic!("rs274 refuses {name}: {refusal:?}"));
        match rs274::compare(&ger_moves(program, config, is_lenient), &peer, TOLERANCE_MM) {
            Ok(agreement) => eprintln!("{name}: {} moves agree", agreement.moves),
            Err(disagreement) => failures.push(format!("{name}: {disagreement}")),
        }
    }
    failures
}

/// The machine of a ger.toml in mm (the tests' machine is in mm): its
/// G54..G59 table and G30 point.
fn machine(config: &Path) -> Machine {
    let text = std::fs::read_to_string(config).unwrap();
    let value: toml::Value = toml::from_str(&text).unwrap();
    assert_eq!(value["units"].as_str(), Some("mm"));
    let triple = |entry: &toml::Value| -> [f64; 3] { std::array::from_fn(|i| entry[i].as_float().unwrap()) };
    let work_offsets = (54..=59).map(|n| triple(&value["offsets"][&format!("G{n}")])).collect();
    Machine { work_offsets, g30: triple(&value["machine"]["g30"]), ..Machine::default() }
}

fn ger_moves(program: &Path, config: &Path, lenient: bool) -> Moves {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ger"));
    command.arg("run").arg(program).arg("--config").arg(config);
    if lenient {
        command.arg("--lenient");
    }
    let output = command.output().unwrap();
    assert!(
        output.status.success(),
        "ger failed on {}:\n{}",
        program.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    Moves::from_ger(&String::from_utf8(output.stdout).unwrap())
}

/// The moves of canonical calls as rs274 prints them, one a line.
fn canon(calls: &[&str]) -> Moves {
    let text: String = calls.iter().enumerate().map(|(i, call)| format!("{:5} {call}\n", i + 1)).collect();
    Moves::from_rs274(&text)
}

fn ends(moves: &Moves) -> Vec<[f64; 3]> {
    moves.iter().filter_map(|m| m.end).collect()
}

fn assert_close(got: &[[f64; 3]], expected: &[[f64; 3]]) {
    assert_eq!(got.len(), expected.len(), "{got:?} against {expected:?}");
    for (g, e) in got.iter().zip(expected) {
        assert!(g.iter().zip(e).all(|(a, b)| (a - b).abs() < 1e-9), "{got:?} against {expected:?}");
    }
}

#[test]
fn rs274_positions_are_turned_into_machine_millimetres() {
    // In inches, G55 at (1, 2, 0) in, a G92 shift of (0.5, 0, 0) in, the
    // frame turned by 90 degrees and a tool 1 in long: the program point
    // (1, 0, 0) is (1.5, 0) after G92, (0, 1.5) turned, (1, 3.5, 1) in in
    // the machine, (25.4, 88.9, 25.4) mm.
    let moves = canon(&[
        "N..... USE_LENGTH_UNITS(CANON_UNITS_INCHES)",
        "N10    SET_G5X_OFFSET(2, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        "N11    SET_G92_OFFSET(0.5000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        "N12    SET_XY_ROTATION(90.0000)",
        "N13    USE_TOOL_LENGTH_OFFSET(0.0000 0.0000 1.0000, 0.0000 0.0000 0.0000, 0.0000 0.0000 0.0000)",
        "N14    STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        // Back in mm, the offsets stay where they are in the machine.
        "N15    USE_LENGTH_UNITS(CANON_UNITS_MM)",
        "N16    STRAIGHT_FEED(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    ]);
    assert_close(&ends(&moves), &[[25.4, 88.9, 25.4], [25.4, 50.8 + 12.7, 25.4]]);
    let lines: Vec<Option<u32>> = moves.iter().map(|m| m.line).collect();
    assert_eq!(lines, [Some(14), Some(16)]);
}

#[test]
fn rs274_arcs_in_every_plane_and_feeds_in_their_unit() {
    // G18: ARC_FEED's first axis is Z and its second X; G19: Y, then Z.
    let moves = canon(&[
        "N1     SET_FEED_RATE(10.0000)",
        "N2     SELECT_PLANE(CANON_PLANE_XZ)",
        "N3     ARC_FEED(1.0000, 2.0000, 0.0000, 1.0000, -1, 5.0000, 0.0000, 0.0000, 0.0000)",
        "N4     USE_LENGTH_UNITS(CANON_UNITS_INCHES)",
        "N5     SELECT_PLANE(CANON_PLANE_YZ)",
        "N6     ARC_FEED(1.0000, 0.0000, 0.0000, 0.0000, 2, 0.0000, 0.0000, 0.0000, 0.0000)",
        "N7     SET_FEED_RATE(10.0000)",
        "N8     STRAIGHT_FEED(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    ]);
    let all: Vec<&rs274::Move> = moves.iter().collect();
    assert_eq!(all[0].kind, Kind::Arc { centre: [1.0, 0.0, 0.0], turn: -1 });
    assert_close(&[all[0].end.unwrap()], &[[2.0, 5.0, 1.0]]);
    // Turn 2: once round about the centre (back to Y5 Z1), then on to the
    // end, ger's way of writing it. From angle atan(1/5) (Y5 Z1) to 0 (Y25.4
    // Z0) counter-clockwise, then a whole turn: X, the helix, falls from 2 to
    // 0 over 2π - atan(0.2) + 2π, 2π of it in the first turn.
    assert_eq!(all[1].kind, Kind::Arc { centre: [0.0, 0.0, 0.0], turn: 1 });
    let tau = std::f64::consts::TAU;
    assert_close(&[all[1].end.unwrap()], &[[2.0 - 2.0 * tau / (2.0 * tau - 0.2f64.atan()), 5.0, 1.0]]);
    assert_eq!(all[2].kind, Kind::Arc { centre: [0.0, 0.0, 0.0], turn: 1 });
    assert_close(&[all[2].end.unwrap()], &[[0.0, 25.4, 0.0]]);
    // F10 in mm holds after G20 until F is given again, in inches.
    let feeds: Vec<Option<f64>> = all.iter().map(|m| m.feed).collect();
    assert_eq!(feeds, [Some(10.0), Some(10.0), Some(10.0), Some(254.0)]);
}

#[test]
fn rs274_feeds_per_revolution_and_synchronised_become_per_minute() {
    // G95 F0.1 mm a turn at 500 rpm: 50 mm/min. G33 K1.5 at 500 rpm: 750 mm/min,
    // as rs274 prints them.
    let moves = canon(&[
        "N1     SET_SPINDLE_SPEED(0, 500.0000)",
        "N2     SET_FEED_MODE(0, 1)",
        "N3     SET_FEED_RATE(0.1000)",
        "N4     STRAIGHT_FEED(30.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        "N5     SET_FEED_MODE(0, 0)",
        "N6     SET_FEED_RATE(0.0000)",
        "N7     START_SPEED_FEED_SYNC(1.500000,0)",
        "N8     STRAIGHT_FEED(30.0000, 0.0000, -10.0000, 0.0000, 0.0000, 0.0000)",
        "N9     STOP_SPEED_FEED_SYNCH()",
        // G33.1 K1.25: a rigid tap to Z-5 and back, at 625 mm/min.
        "N10    START_SPEED_FEED_SYNC(1.250000,0)",
        "N10    RIGID_TAP(30.0000, 0.0000, -5.0000)",
        "N10    STOP_SPEED_FEED_SYNCH()",
    ]);
    let feeds: Vec<f64> = moves.iter().map(|m| m.feed.unwrap()).collect();
    assert!((feeds[0] - 50.0).abs() < 1e-9 && (feeds[1] - 750.0).abs() < 1e-9, "{feeds:?}");
    let tap = moves.iter().last().unwrap();
    assert_eq!((&tap.kind, tap.end, tap.feed), (&Kind::Tap, Some([30.0, 0.0, -5.0]), Some(625.0)));
}

#[test]
fn spindle_commands_that_change_nothing_are_left_out() {
    let moves = canon(&[
        "N2     STOP_SPINDLE_TURNING(0)",
        "N3     START_SPINDLE_CLOCKWISE(0)",
        "N6     START_SPINDLE_CLOCKWISE(0)",
        "N7     DWELL(0.5000)",
        // G84 at the bottom of the hole: a stop, then the reverse.
        "N8     STOP_SPINDLE_TURNING(0)",
        "N8     START_SPINDLE_COUNTERCLOCKWISE(0)",
        "N9     DWELL(0.2500)",
        "N10    STOP_SPINDLE_TURNING(0)",
    ]);
    let kinds: Vec<&Kind> = moves.iter().map(|m| &m.kind).collect();
    let expected = [&Kind::Spindle(1), &Kind::Dwell(0.5), &Kind::Spindle(-1), &Kind::Dwell(0.25), &Kind::Spindle(0)];
    assert_eq!(kinds, expected);
}

#[test]
fn moves_that_go_nowhere_on_one_side_are_passed_over() {
    // rs274 moves to where the tool is (line 1); ger, rounding to 0.001 mm,
    // makes a move of 0.001 mm (line 3) that rs274 does not.
    let peer = canon(&[
        "N1     STRAIGHT_TRAVERSE(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        "N2     STRAIGHT_TRAVERSE(0.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)",
        "N4     STRAIGHT_TRAVERSE(5.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)",
    ]);
    let ger = Moves::from_ger("G21\nN2 G00 Z1.000\nN3 G00 Z1.001\nN4 G00 X5.000 Z1.000\n");
    assert_eq!(rs274::compare(&ger, &peer, TOLERANCE_MM).unwrap().moves, 2);
    // A dwell of no time on one side is passed over too.
    let with_dwell = Moves::from_ger("G21\nN2 G00 Z1.000\nN3 G04 P0.000\nN4 G00 X5.000 Z1.000\n");
    assert_eq!(rs274::compare(&with_dwell, &peer, TOLERANCE_MM).unwrap().moves, 2);
    // A move that does go somewhere is not passed over.
    let ger = Moves::from_ger("G21\nN2 G00 Z1.000\nN3 G00 Z1.500\nN4 G00 X5.000 Z1.000\n");
    assert!(rs274::compare(&ger, &peer, TOLERANCE_MM).is_err());
}

#[test]
fn ger_output_is_read_as_a_controller_runs_it() {
    // A G43 with Z after a G01 moves at the feed; M06 stops the spindle;
    // the arc's centre is relative to its start.
    let output = "(ger: translated from part.ngc)\nG21\nG90\nG17\nN2 M03 S1000\nN3 G01 X10.000 F100.000\n\
                  N4 G43 Z5.000 H1\nN5 M06 T2\nN6 G02 X20.000 Y0.000 I5.000 J0.000\nN7 G00 Z10.000\n";
    let moves = Moves::from_ger(output);
    let kinds: Vec<&Kind> = moves.iter().map(|m| &m.kind).collect();
    let arc = Kind::Arc { centre: [15.0, 0.0, 0.0], turn: -1 };
    assert_eq!(kinds, [&Kind::Spindle(1), &Kind::Feed, &Kind::Feed, &Kind::Spindle(0), &arc, &Kind::Rapid]);
    assert_close(&ends(&moves), &[[10.0, 0.0, 0.0], [10.0, 0.0, 5.0], [20.0, 0.0, 5.0], [20.0, 0.0, 10.0]]);
    let lines: Vec<u32> = moves.iter().map(|m| m.line.unwrap()).collect();
    assert_eq!(lines, [2, 3, 4, 5, 6, 7]);
    // In inches every length is turned into mm.
    let inches = Moves::from_ger("(ger)\nG20\nG90\nG17\nN1 G01 X1.0000 F10.0000\n");
    let first = inches.iter().next().unwrap();
    assert_eq!((first.end, first.feed), (Some([25.4, 0.0, 0.0]), Some(254.0)));
}

#[test]
fn the_comparison_tells_rapids_from_feeds_and_names_both_sides() {
    let ger = Moves::from_ger("G21\nN2 G00 X1.000\nN3 G00 Z-1.000\n");
    let peer = canon(&[
        "N2     STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        "N3     SET_FEED_RATE(100.0000)",
        "N3     STRAIGHT_FEED(1.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)",
    ]);
    let disagreement = rs274::compare(&ger, &peer, TOLERANCE_MM).unwrap_err();
    assert_eq!(
        disagreement.to_string(),
        "a rapid where rs274 has a feed: ger move 2, line 3 `N3 G00 Z-1.000`; \
         rs274 move 2, line 3 `STRAIGHT_FEED(1.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)`"
    );
    assert!(rs274::compare(&peer, &ger, TOLERANCE_MM).is_err(), "a feed where the peer has a rapid differs too");
}

#[test]
fn end_points_agree_within_the_tolerance_beyond_the_printed_rounding() {
    // ger prints mm to 0.001 (rounding by up to 0.0005), rs274 to 0.0001
    // (0.00005): 0.002 mm more is allowed, 0.00255 mm in all.
    let peer = canon(&[
        "N1     SET_FEED_RATE(100.0000)",
        "N1     STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    ]);
    let at = |x: &str| Moves::from_ger(&format!("G21\nN1 G01 X{x} F100.000\n"));
    assert!(rs274::compare(&at("1.002"), &peer, TOLERANCE_MM).is_ok());
    assert!(rs274::compare(&at("0.998"), &peer, TOLERANCE_MM).is_ok());
    let disagreement = rs274::compare(&at("1.003"), &peer, TOLERANCE_MM).unwrap_err();
    assert!(disagreement.what.starts_with("end points differ by 0.0030 mm"), "{disagreement}");
}

#[test]
fn a_spline_stands_for_the_moves_ger_made_for_its_lines() {
    // rs274 prints a G5.2 ... G5.3 spline (lines 3-6) with the line of its G5.3.
    let peer = canon(&[
        "N2     STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        "N2     SET_FEED_RATE(100.0000)",
        "N6     NURBS_FEED(4, ...)",
        "N7     STRAIGHT_FEED(10.0000, 4.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
    ]);
    let ger = |lines: &str| Moves::from_ger(&format!("G21\nN2 G00 X1.000\n{lines}N7 G01 X10.000 Y4.000\n"));
    let spline = "N3 G01 X5.000 Y5.000 F100.000\nN4 G03 X6.000 Y3.000 I3.000 J-3.000\n";
    assert_eq!(rs274::compare(&ger(spline), &peer, TOLERANCE_MM).unwrap().moves, 3);
    let none = rs274::compare(&ger("N5 F100.000\n"), &peer, TOLERANCE_MM).unwrap_err();
    assert_eq!(none.what, "rs274 runs a spline where ger does not");
    let slow = rs274::compare(&ger("N3 G01 X5.000 Y5.000 F90.000\n"), &peer, TOLERANCE_MM).unwrap_err();
    assert!(slow.what.starts_with("feeds differ along a spline"), "{slow}");
}

#[test]
fn every_line_is_numbered_for_rs274() {
    let program = b"%\nG21\n  /G0 X1\nN0010 G1 X2 F5\nn 20.5 X3\n\n(comment)\r\nM2\n%\n";
    let expected = "%\nG20\nN2 G21\n  /N3 G0 X1\nN4 G1 X2 F5\nN5 X3\n\nN7 (comment)\r\nN8 M2\n%\n";
    assert_eq!(String::from_utf8(rs274::numbered(program, "G20")).unwrap(), expected);
    // Without an opening %, the first line goes first.
    assert_eq!(String::from_utf8(rs274::numbered(b"\nG0 X1\nM2", "G21")).unwrap(), "G21\n\nN2 G0 X1\nN3 M2");
}

/// Through rs274 itself: with offsets, a rotated frame and inches, a G53
/// move still ends at the machine coordinates it names.
#[test]
fn rs274_g53_moves_end_at_their_machine_coordinates() {
    if rs274_missing() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("g53.ngc");
    std::fs::write(
        &program,
        "G20 G90\nG10 L2 P1 X1 Y2 Z-1 R30\nG54\nG0 X1 Y1\nG92 X0 Y0 Z0\nG53 G0 X0.5 Y-1 Z-2\nG21\n\
         G53 G1 X10 Y20 Z-30 F100\nG91 G28 Z0\nM2\n",
    )
    .unwrap();
    let moves = rs274::moves(&program, &Machine { g28: [0.0, 0.0, 7.0], ..Machine::default() }, TIME_LIMIT).unwrap();
    let got = ends(&moves);
    // The G54 move's end worked out by hand: (1, 1) turned by 30 degrees, plus the origin.
    let (sin, cos) = 30f64.to_radians().sin_cos();
    // Z is not named, so it stays at machine zero.
    let first = [(1.0 + cos - sin) * 25.4, (2.0 + sin + cos) * 25.4, 0.0];
    // G28's intermediate point is where the tool is: a move that goes nowhere.
    let expected = [first, [12.7, -25.4, -50.8], [10.0, 20.0, -30.0], [10.0, 20.0, -30.0], [10.0, 20.0, 7.0]];
    assert_eq!(got.len(), expected.len(), "{moves:?}");
    for (g, e) in got.iter().zip(&expected) {
        // rs274 prints 4 decimals of an inch.
        assert!(g.iter().zip(e).all(|(a, b)| (a - b).abs() < 0.003), "{got:?} against {expected:?}");
    }
}
