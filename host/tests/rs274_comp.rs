//! Differential test of cutter radius compensation: the same programs through
//! ger and through LinuxCNC's interpreter, `rs274` (Debian `linuxcnc-uspace`),
//! whose compensated path is the trusted reference. After the entry move,
//! where the two deliberately differ (ger steps out perpendicular to the first
//! move; LinuxCNC heads straight for the offset path), the paths must agree
//! move for move (`support/rs274.rs`): same kind, same direction, same feed,
//! ends and arc centres within 0.001 mm beyond the printed rounding.
//!
//! Where rs274 is missing the tests say so on the terminal and pass; with the
//! environment variable `CI` set (CI installs rs274 via
//! `.ci/setup.d/10-linuxcnc.sh`) they fail instead.

mod support;

use std::process::Command;
use std::time::Duration;

use support::rs274::{self, Machine, Moves};

/// Millimetres, on top of the rounding of the printed digits.
const TOLERANCE: f64 = 0.001;
/// A 6 mm endmill: R = 3.
const TOOL_DIAMETER_MM: f64 = 6.0;
const TIME_LIMIT: Duration = Duration::from_secs(20);

/// The compensated path of `program` after the entry move, by ger and by
/// rs274; `None` (after a loud note) when rs274 is not installed outside CI.
fn both_paths(program: &str) -> Option<(Moves, Moves)> {
    if !rs274::available() {
        let message = "rs274 (LinuxCNC, Debian package linuxcnc-uspace) is not installed: \
                       ger's cutter comp was NOT compared with LinuxCNC";
        support::peer_missing(message);
        return None;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    let part = dir.path().join("part.ngc");
    std::fs::write(&part, program).unwrap();
    let line_of = |codes: &[&str]| {
        program
            .lines()
            .position(|l| codes.iter().any(|c| l.trim() == *c))
            .expect("G41/G42 and G40 on lines of their own") as u32
            + 1
    };
    let (on, off) = (line_of(&["G41", "G42"]), line_of(&["G40"]));
    let machine = Machine { tools: vec![(1, TOOL_DIAMETER_MM)], ..Machine::default() };
    let reference = rs274::moves(&part, &machine, TIME_LIMIT).unwrap_or_else(|e| panic!("rs274 failed: {e:?}"));
    // rs274 prints a compensated move when it reads the block after it: the
    // path is what it prints for the lines after G41/G42 up to G40's. Its
    // first move is the entry.
    let reference = reference.select(|line| line > on && line <= off, 1);
    // ger's compensated moves carry the lines from G41/G42 (the step out) up
    // to G40 (exclusive); the step out and the first (lead-in) move are the entry.
    let ger = ger_path(dir.path()).select(|line| (on..off).contains(&line), 2);
    Some((ger, reference))
}

fn ger_path(dir: &std::path::Path) -> Moves {
    let config = format!("units = \"mm\"\n[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = {TOOL_DIAMETER_MM}\n");
    std::fs::write(dir.join("ger.toml"), config).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ger"))
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .args(["run", "--config", "ger.toml", "part.ngc"])
        .output()
        .expect("ger runs");
    assert!(output.status.success(), "ger failed:\n{}", String::from_utf8_lossy(&output.stderr));
    Moves::from_ger(&String::from_utf8(output.stdout).unwrap())
}

/// Compares the two paths move for move and prints the largest difference.
fn compare(program: &str) {
    let Some((ger, reference)) = both_paths(program) else { return };
    assert!(!reference.is_empty(), "rs274 wrote no compensated moves");
    match rs274::compare(&ger, &reference, TOLERANCE) {
        // Shown with --nocapture, for the record.
        Ok(agreement) => {
            println!("{} moves compared; largest difference {:.5} mm", agreement.moves, agreement.largest_difference)
        }
        Err(disagreement) => panic!("{disagreement}"),
    }
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
