//! Differential test of cutter radius compensation: the same programs through
//! ger and through LinuxCNC's interpreter, `rs274` (Debian `linuxcnc-uspace`),
//! whose compensated path is the trusted reference. After the entry move,
//! where the two deliberately differ (ger steps out perpendicular to the first
//! move; LinuxCNC heads straight for the offset path), the paths must agree
//! move for move: same kind, same direction, ends and arc centres within
//! 0.001 mm.
//!
//! Where rs274 is missing the tests say so on the terminal and pass; with the
//! environment variable `CI` set (CI installs rs274 via
//! `.ci/setup.d/10-linuxcnc.sh`) they fail instead.

mod support;

use std::io::ErrorKind;
use std::path::Path;
use std::process::Command;

/// Millimetres.
const TOLERANCE: f64 = 0.001;
/// A 6 mm endmill: R = 3.
const TOOL_DIAMETER_MM: f64 = 6.0;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Move {
    Line { end: [f64; 3], rapid: bool },
    Arc { end: [f64; 3], centre: [f64; 2], ccw: bool },
}

/// The compensated path of `program` after the entry move, by ger and by
/// rs274; `None` (after a loud note) when rs274 is not installed outside CI.
fn both_paths(program: &str) -> Option<(Vec<Move>, Vec<Move>)> {
    let dir = tempfile::tempdir().expect("a temporary directory");
    std::fs::write(dir.path().join("part.ngc"), program).unwrap();
    let reference = rs274_path(dir.path())?;
    Some((ger_path(dir.path(), program), reference))
}

fn ger_path(dir: &Path, program: &str) -> Vec<Move> {
    let config = format!("units = \"mm\"\n[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = {TOOL_DIAMETER_MM}\n");
    std::fs::write(dir.join("ger.toml"), config).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ger"))
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .args(["run", "--config", "ger.toml", "part.ngc"])
        .output()
        .expect("ger runs");
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert!(output.status.success(), "ger failed:\n{}", String::from_utf8_lossy(&output.stderr));
    // The compensated moves carry the lines from G41/G42 (the step out) up
    // to G40 (exclusive).
    let line_of = |codes: &[&str]| {
        program
            .lines()
            .position(|l| codes.iter().any(|c| l.trim() == *c))
            .expect("G41/G42 and G40 on lines of their own") as u32
            + 1
    };
    let (on, off) = (line_of(&["G41", "G42"]), line_of(&["G40"]));
    let mut position = [0.0; 3];
    let mut moves = Vec::new();
    for line in stdout.lines() {
        let mut words = line.split_whitespace();
        let Some(n) = words.next().and_then(|w| w.strip_prefix('N')).map(|n| n.parse::<u32>().unwrap()) else {
            continue;
        };
        let code = words.next().unwrap();
        if !["G00", "G01", "G02", "G03"].contains(&code) {
            continue;
        }
        let word = |letter: char| {
            line.split_whitespace().find_map(|w| w.strip_prefix(letter).and_then(|v| v.parse::<f64>().ok()))
        };
        let start = position;
        for (axis, letter) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if let Some(v) = word(letter) {
                position[axis] = v;
            }
        }
        if !(on..off).contains(&n) {
            continue;
        }
        moves.push(match code {
            "G00" | "G01" => Move::Line { end: position, rapid: code == "G00" },
            _ => Move::Arc {
                end: position,
                centre: [start[0] + word('I').unwrap(), start[1] + word('J').unwrap()],
                ccw: code == "G03",
            },
        });
    }
    // Skip the step out and the first (lead-in) move: they are the entry.
    moves.split_off(2)
}

/// rs274's canonical moves between "compensation on" and "off", after its
/// entry move; `None` when rs274 is missing and this is not CI.
fn rs274_path(dir: &Path) -> Option<Vec<Move>> {
    // rs274 without an INI file reads the tool table in inches.
    std::fs::write(dir.join("tools.tbl"), format!("T1 P1 D{:.12}\n", TOOL_DIAMETER_MM / 25.4)).unwrap();
    // rs274 maps the tool table to $HOME/.tool.mmap and truncates it as it
    // starts: runs sharing a HOME crash each other (SIGBUS). One each.
    let rs274 =
        Command::new("rs274").current_dir(dir).env("HOME", dir).args(["-t", "tools.tbl", "-g", "part.ngc"]).output();
    let output = match rs274 {
        Ok(output) => output,
        Err(err) if err.kind() == ErrorKind::NotFound => {
            let message = "rs274 (LinuxCNC, Debian package linuxcnc-uspace) is not installed: \
                           ger's cutter comp was NOT compared with LinuxCNC";
            support::peer_missing(message);
            return None;
        }
        Err(err) => panic!("cannot run rs274: {err}"),
    };
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "rs274 failed ({}):\n{stdout}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    let mut on = false;
    let mut moves = Vec::new();
    for line in stdout.lines() {
        if line.contains("cutter radius compensation on") {
            on = true;
        } else if line.contains("cutter radius compensation off") {
            on = false;
        }
        let Some((name, args)) = line.split_once('(') else { continue };
        let name = name.split_whitespace().last().unwrap_or("");
        let args: Vec<f64> = args.trim_end_matches(')').split(',').filter_map(|a| a.trim().parse().ok()).collect();
        if !on {
            continue;
        }
        match name {
            "STRAIGHT_FEED" | "STRAIGHT_TRAVERSE" => {
                moves.push(Move::Line { end: [args[0], args[1], args[2]], rapid: name == "STRAIGHT_TRAVERSE" })
            }
            // ARC_FEED(end x, end y, centre x, centre y, turns (+ CCW), end z, ...)
            "ARC_FEED" => moves.push(Move::Arc {
                end: [args[0], args[1], args[5]],
                centre: [args[2], args[3]],
                ccw: args[4] > 0.0,
            }),
            _ => {}
        }
    }
    assert!(!moves.is_empty(), "rs274 wrote no compensated moves:\n{stdout}");
    // Skip the entry move.
    Some(moves.split_off(1))
}

/// Compares the two paths move for move and prints the largest deviation.
fn compare(program: &str) {
    let Some((ger, reference)) = both_paths(program) else { return };
    assert_eq!(
        ger.len(),
        reference.len(),
        "different numbers of moves after the entry:\nger:    {ger:?}\nrs274:  {reference:?}"
    );
    let mut worst: f64 = 0.0;
    for (i, (g, r)) in ger.iter().zip(&reference).enumerate() {
        let deviation = match (g, r) {
            (Move::Line { end: a, rapid: ra }, Move::Line { end: b, rapid: rb }) if ra == rb => distance(a, b),
            (Move::Arc { end: a, centre: ca, ccw: da }, Move::Arc { end: b, centre: cb, ccw: db }) if da == db => {
                distance(a, b).max(distance(ca, cb))
            }
            _ => panic!("move {i} differs in kind:\nger:   {g:?}\nrs274: {r:?}"),
        };
        assert!(deviation <= TOLERANCE, "move {i} is {deviation:.4} mm off:\nger:   {g:?}\nrs274: {r:?}");
        worst = worst.max(deviation);
    }
    // Shown with --nocapture, for the record.
    println!("{} moves compared; largest deviation {worst:.5} mm", ger.len());
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt()
}

/// A program in the shape both interpreters read: mm, tool 1 loaded, a
/// lead-in from `start`, the contour, G40 on its own line and back out.
fn program(start: &str, comp: &str, contour: &str) -> String {
    format!(
        "(differential test)\nG21\nG17\nG90\nM06 T1\nG00 Z5\nG00 {start}\nG01 Z-1 F100\n\
         {comp}\n{contour}\nG40\nG01 {start}\nG00 Z5\nM30\n"
    )
}

const SQUARE_CW: &str = "G01 X0 Y0\nY30\nX50\nY0\nX0";
const SQUARE_CCW: &str = "G01 X0 Y0\nX50\nY30\nX0\nY0";
const SQUARE_CCW_FROM_MIDDLE: &str = "G01 X25 Y0\nX50\nY30\nX0\nY0\nX25";
const SQUARE_CW_FROM_MIDDLE: &str = "G01 X25 Y0\nX0\nY30\nX50\nY0\nX25";

#[test]
fn square_outside_g41_clockwise() {
    compare(&program("X-20 Y-20", "G41", SQUARE_CW));
}

#[test]
fn square_outside_g42_counter_clockwise() {
    compare(&program("X-20 Y-20", "G42", SQUARE_CCW));
}

#[test]
fn square_inside_g41_counter_clockwise() {
    compare(&program("X25 Y15", "G41", SQUARE_CCW_FROM_MIDDLE));
}

#[test]
fn square_inside_g42_clockwise() {
    compare(&program("X25 Y15", "G42", SQUARE_CW_FROM_MIDDLE));
}

// A 50 x 30 rectangle with corners of radius 5: arcs tangent to the sides;
// inside, the tool (R 3) runs inside the corner arcs.
const ROUNDED_CW: &str =
    "G01 X0 Y5\nY25\nG02 X5 Y30 I5 J0\nG01 X45\nG02 X50 Y25 I0 J-5\nG01 Y5\nG02 X45 Y0 I-5 J0\nG01 X5\nG02 X0 Y5 I0 J5";
const ROUNDED_CCW: &str =
    "G01 X0 Y25\nY5\nG03 X5 Y0 I5 J0\nG01 X45\nG03 X50 Y5 I0 J5\nG01 Y25\nG03 X45 Y30 I-5 J0\nG01 X5\nG03 X0 Y25 I0 J-5";
const ROUNDED_CCW_FROM_MIDDLE: &str = "G01 X25 Y0\nX45\nG03 X50 Y5 I0 J5\nG01 Y25\nG03 X45 Y30 I-5 J0\nG01 X5\n\
                                       G03 X0 Y25 I0 J-5\nG01 Y5\nG03 X5 Y0 I5 J0\nG01 X25";
const ROUNDED_CW_FROM_MIDDLE: &str = "G01 X25 Y0\nX5\nG02 X0 Y5 I0 J5\nG01 Y25\nG02 X5 Y30 I5 J0\nG01 X45\n\
                                      G02 X50 Y25 I0 J-5\nG01 Y5\nG02 X45 Y0 I-5 J0\nG01 X25";

#[test]
fn rounded_rectangle_outside_g41_clockwise() {
    compare(&program("X-10 Y5", "G41", ROUNDED_CW));
}

#[test]
fn rounded_rectangle_outside_g42_counter_clockwise() {
    compare(&program("X-10 Y25", "G42", ROUNDED_CCW));
}

#[test]
fn rounded_rectangle_inside_g41_counter_clockwise() {
    compare(&program("X25 Y15", "G41", ROUNDED_CCW_FROM_MIDDLE));
}

#[test]
fn rounded_rectangle_inside_g42_clockwise() {
    compare(&program("X25 Y15", "G42", ROUNDED_CW_FROM_MIDDLE));
}

/// Acute corners (outside arcs of more than a quarter turn), a line meeting
/// an arc at an angle, and a helix: the arc goes down 1 mm.
#[test]
fn triangle_with_a_helical_arc_outside() {
    compare(&program("X-20 Y-10", "G41", "G01 X0 Y0\nX20 Y40\nX40 Y0\nG02 X0 Y0 I-20 J15 Z-2"));
}

/// Two arcs meeting at sharp points: arc-arc corners, outside (G42, round the
/// points) and inside (G41, cut where the offset circles cross).
#[test]
fn lens_of_two_arcs_outside_and_inside() {
    let lens = "G01 X0 Y0\nG03 X40 Y0 I20 J15\nG03 X0 Y0 I-20 J-15";
    compare(&program("X-20 Y0", "G42", lens));
    compare(&program("X-20 Y0", "G41", lens));
}
