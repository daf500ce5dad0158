//! Each rule of each target on a small program; the expected lines are
//! written by hand (and the GRBL ones were fed to its parser, gvalidate).

use ger_core::config::Config;
use ger_core::diag::{Diagnostic, Span};
use ger_core::passes::testing::statements_with;
use ger_core::statement::{Kind, Machine, Statement};

use super::*;

/// `program` translated on a millimetre machine with `target` (a TOML
/// value: `"grbl"` or `{ name = "grbl", ... }`), without line numbers:
/// the lines, and the notes.
fn output(target: &str, program: &str) -> (String, Vec<Diagnostic>) {
    let config = Config::from_toml(&format!("units = \"mm\"\ndialect = \"lenient\"\ntarget = {target}\n")).unwrap();
    let mut writer = Writer::new(&config, false);
    let (mut text, mut notes) = (String::new(), Vec::new());
    for statement in statements_with(program, &config) {
        writer.write(&statement, &mut text, &mut notes);
    }
    (text, notes)
}

fn lines(target: &str, program: &str) -> String {
    output(target, program).0
}

#[test]
fn generic_is_gers_own_output() {
    let config = Config::from_toml("units = \"mm\"\ndialect = \"lenient\"\n").unwrap();
    let program = "G21\nM06 T2\nM07\nG43 H1\nG01 X1 Y2.5 F100\nG04 P0.5\nM30\n";
    let mut writer = Writer::new(&config, true);
    let emitter = Emitter::new(3, true);
    let (mut text, mut notes, mut expected) = (String::new(), Vec::new(), String::new());
    for statement in statements_with(program, &config) {
        writer.write(&statement, &mut text, &mut notes);
        expected.push_str(&emitter.line(&statement));
        expected.push('\n');
    }
    assert_eq!(text, expected);
    assert!(notes.is_empty());
    assert_eq!(writer.preamble("part.nc"), ger_core::emit::preamble("part.nc", ger_core::statement::Units::Mm));
    assert_eq!(writer.postamble(), "");
}

#[test]
fn grbl_pauses_for_a_tool_change_with_the_spindle_stopped() {
    assert_eq!(lines("\"grbl\"", "M06 T2\n"), "M05\nM00 (MSG, load tool 2)\n");
    let block = "{ name = \"grbl\", tool_change = \"M05\\nG53 G00 Z0\\nM00 (tool {tool})\" }";
    assert_eq!(lines(block, "M06 T7\n"), "M05\nG53 G00 Z0\nM00 (tool 7)\n");
}

#[test]
fn grbl_writes_mist_only_when_the_board_has_it() {
    let (text, notes) = output("\"grbl\"", "M07\nM09\nM07\n");
    let note = "(M07 left out: GRBL is built without mist coolant unless [target] mist = true says otherwise)\n";
    assert_eq!(text, format!("{note}M09\n{note}"));
    assert_eq!(notes.len(), 1, "one warning for the rule: {notes:?}");
    assert!(!notes[0].is_error());
    assert_eq!(lines("{ name = \"grbl\", mist = true }", "M07\n"), "M07\n");
}

#[test]
fn grbl_applies_tool_lengths_as_dynamic_offsets() {
    let target = "{ name = \"grbl\", tool_lengths = { 1 = 12.5, 3 = 40.125 } }";
    assert_eq!(lines(target, "G43 H1\nG49\nG44 H3\nG43 H0\n"), "G43.1 Z12.5\nG49\nG43.1 Z-40.125\nG43.1 Z0\n");
    let (text, notes) = output("\"grbl\"", "G43 H2\n");
    assert_eq!(text, "(G43 H2 left out: GRBL has no tool table; give H2's length in [target] tool_lengths)\n");
    assert_eq!(notes.len(), 1);
}

#[test]
fn grbl_numbers_have_no_trailing_zeros() {
    assert_eq!(lines("\"grbl\"", "G01 X1 Y2.5 Z-0.0004 F100\nG04 P0.5\n"), "G01 X1 Y2.5 Z0 F100\nG04 P0.5\n");
}

#[test]
fn grbl_leaves_out_codes_it_does_not_have() {
    let (text, notes) = output("\"grbl\"", "M41\nM48\nM03 S1000\n");
    assert_eq!(text, "(M41 left out: GRBL has no such code)\n(M48 left out: GRBL has no such code)\nM03 S1000\n");
    assert_eq!(notes.len(), 2);
}

#[test]
fn grbl_comments_lose_its_realtime_characters() {
    let config = Config::from_toml("units = \"mm\"\ntarget = \"grbl\"\n").unwrap();
    let writer = Writer::new(&config, true);
    assert_eq!(writer.preamble("why?!~é.nc"), "(ger: translated from why.nc for GRBL)\nG21\nG90\nG17\n");
}

#[test]
fn grbl_takes_line_numbers_up_to_ten_million() {
    let config = Config::from_toml("units = \"mm\"\ntarget = \"grbl\"\n").unwrap();
    let mut writer = Writer::new(&config, true);
    let (mut text, mut notes) = (String::new(), Vec::new());
    for line in [10_000_000, 10_000_001] {
        writer.write(&Statement::new(Kind::End, Span::new(line, 1, 3)), &mut text, &mut notes);
    }
    assert_eq!(text, "N10000000 M30\nM30\n");
}

/// A made-up controller whose lines hold 20 characters.
static NARROW: Profile = Profile { max_line_length: Some(20), ..profile::GRBL };

#[test]
fn a_long_line_loses_its_number_then_its_feed() {
    let config = Config::from_toml("units = \"mm\"\n").unwrap();
    let mut writer = Writer::for_profile(&NARROW, &config, true);
    let (mut text, mut notes) = (String::new(), Vec::new());
    // "N1 G01 X100 Y200 F1500" is 18 without spaces: it fits. "G01 X100 Y200 Z-3.25 F900" is 21, and 23
    // with N2: F goes to a line of its own.
    for statement in statements_with("G01 X100 Y200 F1500\nG01 X100 Y200 Z-3.25 F900\n", &config) {
        writer.write(&statement, &mut text, &mut notes);
    }
    assert_eq!(text, "N1 G01 X100 Y200 F1500\nF900\nG01 X100 Y200 Z-3.25\n");
    assert!(notes.is_empty());
    assert_eq!(length("N1 G01 X1 (a comment) Y2 ; more"), 9);
}

#[test]
fn grbl_writes_as_lines_an_arc_it_would_refuse() {
    // From (0,0) round (5.003,0) to (10,0), clockwise: 5.003 to the start, 4.997 to the end, 0.006 off,
    // which gvalidate refuses (error:33). A half turn at 0.002 mm: 2 acos(1 - 0.002/5.003) = 0.056553 rad a
    // line, pi / 0.056553 = 55.55, so 56 lines.
    let (text, notes) = output("\"grbl\"", "G01 X0 Y0 F100\nG02 X10 Y0 I5.003 J0 F200\n");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "G01 X0 Y0 F100");
    assert!(lines[1].starts_with("(an arc whose end is 0.0060 mm off its circle"), "{}", lines[1]);
    assert_eq!(lines.len(), 2 + 56);
    assert!(lines[2].ends_with(" F200"), "the feed goes on the first line: {}", lines[2]);
    assert_eq!(*lines.last().unwrap(), "G01 X10 Y0");
    for line in &lines[2..] {
        let word = |letter: char| -> f64 {
            let word = line.split(' ').find(|w| w.starts_with(letter)).unwrap();
            word[1..].parse().unwrap()
        };
        let (x, y) = (word('X'), word('Y'));
        let r = (x - 5.003).hypot(y);
        assert!((4.996..=5.0035).contains(&r), "{line}: {r}");
        assert!(y >= 0.0, "clockwise from the left of the centre goes over it: {line}");
    }
    assert_eq!(notes.len(), 1);
    // 0.004 off is taken as it is.
    assert_eq!(lines_of("G01 X0 Y0 F100\nG02 X10 Y0 I5.002 J0\n"), "G01 X0 Y0 F100\nG02 X10 Y0 I5.002 J0\n");
}

#[test]
fn grbl_gets_lines_for_a_full_circle_whose_end_rounds_past_its_start() {
    // Clockwise round the origin from (10, 0.0494) to the point on the same ray 1.0004 times as far:
    // LinuxCNC and ger turn a full circle, spiralling out by 0.004 mm. Written to 0.001, the start's
    // angle is 0.049/10 = 4.9000e-3 rad and the end's 0.049/10.004 = 4.8980e-3: 2e-6 rad ahead of the
    // start the clockwise way, which GRBL turns as a sliver (its full-circle epsilon is 5e-7 rad).
    let (text, notes) = output("\"grbl\"", "G01 X10 Y0.0494 F100\nG02 X10.004 Y0.04941976 I-10 J-0.0494\n");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "G01 X10 Y0.049 F100");
    assert!(
        lines[1].starts_with("(an arc turning 360.0 degrees whose end rounds to just past its start"),
        "{}",
        lines[1]
    );
    assert_eq!(notes.len(), 1);
    assert_eq!(*lines.last().unwrap(), "G01 X10.004 Y0.049");
    // All the way round at 0.002 mm: 2 acos(1 - 0.002/10.004) = 0.039991 rad a line, 2 pi / 0.039991 =
    // 157.1, so 158 lines; a quarter of the way, clockwise from +X, the tool is below the centre.
    assert_eq!(lines.len(), 2 + 158);
    let quarter = lines[2 + 158 / 4];
    let y: f64 = quarter.split(' ').find(|w| w.starts_with('Y')).unwrap()[1..].parse().unwrap();
    assert!(y < -9.9, "{quarter}");
}

fn lines_of(program: &str) -> String {
    lines("\"grbl\"", program)
}

#[test]
fn grbl_gets_a_line_for_an_arc_whose_end_rounds_onto_its_start() {
    // 0.0004 long, the short way round a centre 0.01 below: written X0, at the start, which GRBL would
    // take as a full circle.
    let text = lines_of("G01 X0 Y0 F100\nG02 X0.0004 Y0 I0.0002 J-0.01\n");
    assert_eq!(text, "G01 X0 Y0 F100\nG01 X0 Y0\n");
    // The long way round, it is a full circle within rounding, and stays one.
    let text = lines_of("G01 X0 Y0 F100\nG03 X0.0004 Y0 I0.0002 J-0.01\n");
    assert_eq!(text, "G01 X0 Y0 F100\nG03 X0 Y0 I0 J-0.01\n");
    // A full circle stays one.
    let text = lines_of("G01 X0 Y0 F100\nG03 X0 Y0 I5 J0\n");
    assert_eq!(text, "G01 X0 Y0 F100\nG03 X0 Y0 I5 J0\n");
}

#[test]
fn fanuc_frames_the_program_and_numbers_it() {
    let config = Config::from_toml("units = \"mm\"\n[target]\nname = \"fanuc\"\nprogram_number = 42\n").unwrap();
    let mut writer = Writer::new(&config, true);
    assert_eq!(
        writer.preamble("parts/bracket v2.nc"),
        "%\nO0042 (BRACKET V2.NC)\n(GER TRANSLATED FROM PARTS BRACKET V2.NC FOR FANUC)\nG21\nG90\nG17\n"
    );
    assert_eq!(writer.postamble(), "%\n");
    let (mut text, mut notes) = (String::new(), Vec::new());
    writer.write(&Statement::new(Kind::Dwell(0.5), Span::new(7, 1, 3)), &mut text, &mut notes);
    let change = Kind::Machine { code: Machine::ToolChange, s: None, t: Some(3) };
    writer.write(&Statement::new(change, Span::new(99_999, 1, 3)), &mut text, &mut notes);
    writer.write(&Statement::new(Kind::End, Span::new(100_000, 1, 3)), &mut text, &mut notes);
    assert_eq!(text, "N7 G04 X0.500\nN99999 M06 T3\nM30\n");
}

#[test]
fn linuxcnc_and_mach3_have_no_spindle_ranges() {
    assert_eq!(lines("\"linuxcnc\"", "M40\nM48\n"), "(M40 left out: LinuxCNC has no such code)\nM48\n");
    assert_eq!(lines("\"mach3\"", "M41\nM06 T1\n"), "(M41 left out: Mach3 has no such code)\nM06 T1\n");
    let config = Config::from_toml("units = \"inch\"\ntarget = \"mach3\"\n").unwrap();
    assert_eq!(
        Writer::new(&config, true).preamble("a.nc"),
        "(ger: translated from a.nc for Mach3)\nG20\nG90\nG17\nG91.1\n"
    );
}

#[test]
fn a_target_the_config_cannot_name_is_an_error_there() {
    let err = Config::from_toml("target = \"haas\"\n").unwrap_err();
    assert!(err.message.contains("target must be one of generic, grbl, linuxcnc, fanuc, mach3"), "{}", err.message);
    assert_eq!(err.span.line, 1);
    let err = Config::from_toml("[target]\nname = \"fanuc\"\nprogram_number = 10000\n").unwrap_err();
    assert!(err.message.contains("program_number"), "{}", err.message);
    assert_eq!(err.span.line, 3);
    let err = Config::from_toml("units = \"mm\"\n[target]\nname = \"grbl\"\ntool_lengths = { 4 = nan }\n").unwrap_err();
    assert!(err.message.contains("H4 must be within ±1000 mm"), "{}", err.message);
    assert!(Config::from_toml("[target]\nname = \"grbl\"\ntool_change = \"M00 (é)\"\n").is_err());
}

#[test]
fn a_tool_table_write_goes_only_to_controllers_that_read_g10_l1() {
    let program = "G10 L1 P2 Z-1 R3\n";
    assert_eq!(lines("\"linuxcnc\"", program), "G10 L1 P2 Z-1.000 R3.000\n");
    for (target, label) in [("\"grbl\"", "GRBL"), ("\"fanuc\"", "Fanuc"), ("\"mach3\"", "Mach3")] {
        let (text, notes) = output(target, program);
        let why = format!(
            "G10 L1 left out: {label} does not take LinuxCNC's tool table write; set tool 2's length on the controller"
        );
        assert!(text.to_ascii_uppercase().starts_with("(G10 L1 LEFT OUT"), "{target}: {text}");
        assert_eq!(text.lines().count(), 1, "{target}: {text}");
        assert_eq!(notes.len(), 1, "{target}: {notes:?}");
        assert!(notes[0].message.contains(&why), "{target}: {notes:?}");
    }
}
