//! Each check on a program that trips it and on one that does not, with the
//! depths, lengths and times worked out by hand.

use super::*;
use ger_core::config::{Coordinates, Fixture, HolderPiece, StockConfig, Tool, ToolKind};
use ger_core::passes::testing;
use ger_core::statement::Units;
use ger_sim::Stock;

/// A 100 x 50 x 20 mm block, program zero on its top lower-left corner;
/// tool 1 a 6 mm endmill with 10 mm flutes.
fn config() -> Config {
    Config {
        units: Units::Mm,
        tools: vec![Tool { flute_length: Some(10.0), ..Tool::new(1, ToolKind::Endmill, 6.0) }],
        stock: StockConfig {
            size: Some([100.0, 50.0, 20.0]),
            origin: Some([0.0, 0.0, 20.0]),
            ..StockConfig::default()
        },
        ..Config::default()
    }
}

fn check_with(text: &str, config: &Config, allowed: &[Rule]) -> Verdict {
    let stock = Stock::from_config(config).unwrap();
    let sim = Simulation::new(stock, 0.1, 1 << 30).unwrap();
    let mut checker = Checker::new(config, sim, allowed);
    for statement in testing::statements_with(text, config) {
        checker.statement(&statement);
    }
    checker.finish()
}

fn check(text: &str) -> Verdict {
    check_with(text, &config(), &[])
}

/// `line: rule: message` for each finding.
fn found(verdict: &Verdict) -> Vec<String> {
    verdict
        .findings
        .iter()
        .map(|f| {
            format!("{}: {}: {}", f.diagnostic.span.line, f.rule.map_or("translate", Rule::name), f.diagnostic.message)
        })
        .collect()
}

const CLEAN: &str = "G21\nM03 S10000\nG00 Z5\nX10 Y10\nG01 Z-2 F100\nX50\nG00 Z5\nM05\nM30\n";

#[test]
fn a_clean_program_has_no_findings_and_its_summary_adds_up() {
    let verdict = check(CLEAN);
    assert_eq!(found(&verdict), Vec::<String>::new());
    let s = &verdict.summary;
    // Feeds: the 7 mm plunge (Z5 to Z-2) and the 40 mm cut, at 100 mm/min.
    assert!((s.cutting_distance - 47.0).abs() < 1e-9, "{}", s.cutting_distance);
    // Rapids: up 5, across to (10, 10) (sqrt 200), up 7.
    assert!((s.rapid_distance - (12.0 + 200f64.sqrt())).abs() < 1e-9, "{}", s.rapid_distance);
    // 47/100 min, and rapids of 5, 10 (the longer axis) and 7 mm at 5000 mm/min.
    let expected = 47.0 / 100.0 * 60.0 + 22.0 / 5000.0 * 60.0;
    assert!((s.run_time_seconds - expected).abs() < 1e-9, "{}", s.run_time_seconds);
    // The cut: the plunge and the slot, 3 mm either side, from Z-2 up to the top
    // (the tool's edges fall on the 0.1 mm cells' edges).
    let cut = s.cut_box.unwrap();
    let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-9);
    assert!(near(cut.min, [7.0, 7.0, -2.0]) && near(cut.max, [53.0, 13.0, 0.0]), "{cut:?}");
    let path = s.path_box.unwrap();
    assert_eq!((path.min, path.max), ([0.0, 0.0, -2.0], [50.0, 10.0, 5.0]));
    assert_eq!(
        s.tools,
        vec![ToolUse {
            number: 1,
            cutting_distance: 47.0,
            moves: 2,
            kind: Some(ToolKind::Endmill),
            diameter: Some(6.0),
            tip_angle: None,
            source: None,
            flute_length: Some(10.0),
            shank_diameter: Some(6.0),
            stick_out: None,
            holder: Vec::new(),
            unchecked: Some("holder not configured: only the shank is checked"),
        }]
    );
    let codes: Vec<(&str, u64)> = s.codes.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    assert_eq!(codes, [("G00", 3), ("G01", 2), ("M03", 1), ("M05", 1), ("M30", 1)]);
    assert!(s.problems.is_empty());
}

#[test]
fn a_rapid_into_the_stock_is_an_error_and_one_above_it_is_not() {
    let verdict = check("G21\nM03\nG00 X10 Y10 Z1\nG00 Z-1.5\nG00 Z5\nM30\n");
    assert_eq!(found(&verdict), ["4: rapid-into-stock: rapid move (G00) cuts 1.500 mm into the stock"]);
    assert!(verdict.findings[0].diagnostic.is_error());
    // Down to the floor a feed move has cut, and along it, a rapid meets nothing.
    let verdict = check("G21\nM03\nG00 X10 Y10 Z1\nG01 Z-2 F100\nX40\nG00 X10\nZ5\nM30\n");
    assert_eq!(found(&verdict), Vec::<String>::new());
}

#[test]
fn cutting_with_the_spindle_stopped_is_an_error() {
    let verdict = check("G21\nG00 X10 Y10 Z1\nG01 Z-1 F100\nG00 Z5\nM30\n");
    assert_eq!(found(&verdict), ["3: spindle-off: cuts the stock while the spindle is not turning"]);
    let help = verdict.findings[0].diagnostic.help.as_deref().unwrap();
    assert!(help.contains("before the first cut"), "{help}");
    // Stopped by M05: the help says where. Feed moves in the air are fine.
    let verdict = check("G21\nM03\nG00 X10 Y10 Z1\nM05\nG01 Z0.5 F100\nZ-1\nM30\n");
    assert_eq!(found(&verdict), ["6: spindle-off: cuts the stock while the spindle is not turning"]);
    assert!(verdict.findings[0].diagnostic.help.as_deref().unwrap().contains("stopped at line 4"));
    // A router's spindle switched by hand: the check is allowed away.
    let verdict = check_with("G21\nG00 X10 Y10 Z1\nG01 Z-1 F100\nM30\n", &config(), &[Rule::SpindleOff]);
    assert_eq!(found(&verdict), Vec::<String>::new());
}

#[test]
fn engaging_deeper_than_the_flutes_is_a_warning() {
    // A ramp (not a plunge) from the top down to Z-12: 12 mm of material against 10 mm flutes.
    let verdict = check("G21\nM03\nG00 X10 Y10 Z1\nG01 X60 Z-12 F100\nG00 Z5\nM30\n");
    // Down there the shank, as wide as the cutter, is against the walls the
    // flutes cut: within the clearance, on the ramp and on the way out.
    assert_eq!(
        found(&verdict),
        [
            "4: flute-length: cuts 12.000 mm deep in one pass, more than tool 1's flute length of 10.000 mm",
            "4: clearance: tool 1's shank passes within 0.500 mm of the stock",
            "5: clearance: tool 1's shank passes within 0.500 mm of the stock"
        ]
    );
    assert!(verdict.findings.iter().all(|f| !f.diagnostic.is_error()));
    // The same depth in two passes of 6: the flutes are never over-engaged,
    // though the shank still comes against the walls at the bottom.
    let verdict = check("G21\nM03\nG00 X10 Y10 Z1\nG01 X60 Z-6 F100\nX10\nX60 Z-12\nG00 Z5\nM30\n");
    assert!(verdict.findings.iter().all(|f| f.rule == Some(Rule::Clearance)), "{:?}", found(&verdict));
}

#[test]
fn plunging_a_flat_endmill_deeper_than_half_its_diameter_is_a_warning() {
    let verdict = check("G21\nM03\nG00 X10 Y10 Z1\nG01 Z-4 F100\nG00 Z5\nM30\n");
    assert_eq!(
        found(&verdict),
        ["4: plunge: plunges a flat endmill 4.000 mm straight down into material, more than 0.5 of its diameter (3.000 mm)"]
    );
    // 3 mm is the limit; a ballmill may plunge; so may a hole already there.
    assert_eq!(found(&check("G21\nM03\nG00 X10 Y10 Z1\nG01 Z-3 F100\nM30\n")), Vec::<String>::new());
    let mut ball = config();
    ball.tools[0].kind = ToolKind::Ballmill;
    assert_eq!(found(&check_with("G21\nM03\nG00 X10 Y10 Z1\nG01 Z-4 F100\nM30\n", &ball, &[])), Vec::<String>::new());
    let again = "G21\nM03\nG00 X10 Y10 Z1\nG01 Z-3 F100\nZ-6\nG00 Z5\nX10 Y10\nG01 Z-6\nM30\n";
    assert_eq!(found(&check(again)), Vec::<String>::new());
}

#[test]
fn cutting_under_the_stock_is_a_warning() {
    let allowed = [Rule::FluteLength, Rule::Plunge, Rule::Clearance];
    let verdict = check_with("G21\nM03\nG00 X10 Y10 Z1\nG01 Z-21.5 F100\nM30\n", &config(), &allowed);
    assert_eq!(found(&verdict), ["4: below-stock: cuts 1.500 mm below the bottom of the stock, into what holds it"]);
    let verdict = check_with("G21\nM03\nG00 X10 Y10 Z1\nG01 Z-20 F100\nM30\n", &config(), &allowed);
    assert_eq!(found(&verdict), Vec::<String>::new());
    // Along the hole already cut and out of it, nothing more is reported.
    let text = "G21\nM03\nG00 X10 Y10 Z1\nG01 Z-21.5 F100\nZ-21\nZ-21.5\nZ5\nM30\n";
    let verdict = check_with(text, &config(), &allowed);
    assert_eq!(found(&verdict), ["4: below-stock: cuts 1.500 mm below the bottom of the stock, into what holds it"]);
}

#[test]
fn moves_outside_the_travel_are_errors() {
    let mut config = config();
    // X 0..200, Y 0..100, Z -80..0 around machine zero.
    config.machine.travel = Some([200.0, 100.0, 80.0]);
    let verdict = check_with("G21\nG00 X150 Y20\nX210\nY-5\nM30\n", &config, &[]);
    assert_eq!(
        found(&verdict),
        [
            "3: travel: the move leaves the machine's travel: X 210.000 mm is past its upper limit, 200.000 mm",
            "4: travel: the move leaves the machine's travel: X 210.000 mm is past its upper limit, 200.000 mm; \
             Y -5.000 mm is past its lower limit, 0.000 mm",
        ]
    );
    // Home in the middle of Z: 40 up and 40 down.
    config.machine.home = Some([0.0, 0.0, 40.0]);
    let verdict = check_with("G21\nG00 X150 Z39\nZ-39\nZ41\nM30\n", &config, &[]);
    assert_eq!(
        found(&verdict),
        ["4: travel: the move leaves the machine's travel: Z 41.000 mm is past its upper limit, 40.000 mm"]
    );
}

#[test]
fn arcs_smaller_than_the_minimum_are_errors() {
    // By default twice the arc tolerance: 0.02 mm.
    let text = "G21\nM03\nG00 Z5\nG02 X0.03 I0.015 F100\nG02 X0.08 I0.025\nM30\n";
    assert_eq!(
        found(&check(text)),
        ["4: arc-radius: arc radius 0.015 mm is below the smallest the machine takes, 0.020 mm"]
    );
    let mut config = config();
    config.check.min_arc_radius = Some(0.03);
    assert_eq!(found(&check_with(text, &config, &[])).len(), 2);
}

#[test]
fn findings_come_in_program_order_and_name_the_call() {
    let text = "G21\nG00 X10 Y10 Z1\nG01 Z-1 F100\nM98 P10\nM30\nO10\nM03\nG00 Z-3\nM99\n";
    let verdict = check(text);
    assert_eq!(
        found(&verdict),
        [
            "3: spindle-off: cuts the stock while the spindle is not turning",
            "8: rapid-into-stock: rapid move (G00) cuts 2.000 mm into the stock",
        ]
    );
    assert_eq!(verdict.findings[1].diagnostic.call_chain(), ["in O10 called at line 4"]);
}

#[test]
fn past_a_hundred_a_rule_only_counts_and_batches_do_not_lose_moves() {
    // 40,000 rapids, each 0.01 mm deeper than the last, in a deep block: more
    // moves than one batch of the simulation holds.
    let mut config = config();
    config.stock =
        StockConfig { size: Some([100.0, 50.0, 500.0]), origin: Some([0.0, 0.0, 500.0]), ..StockConfig::default() };
    let mut text = String::from("G21\nM03\nG00 X10 Y10 Z1\n");
    for k in 1..=40_000 {
        text.push_str(&format!("Z{:.2}\n", -0.01 * k as f64));
    }
    text.push_str("M30\n");
    let verdict = check_with(&text, &config, &[Rule::Clearance]);
    assert_eq!(verdict.summary.problems.get("rapid-into-stock"), Some(&40_000));
    assert_eq!(verdict.findings.len(), SHOWN_PER_RULE as usize);
    assert_eq!(verdict.findings[99].diagnostic.span.line, 103);
}

/// The verdict on `program`, timed line by line, on `config`'s machine with
/// a tool 2 like its tool 1.
fn timed_with_two_tools(program: &str, mut config: Config) -> Verdict {
    config.tools.push(Tool { number: 2, ..config.tools[0].clone() });
    let stock = Stock::from_config(&config).unwrap();
    let sim = Simulation::new(stock, 1.0, 1 << 30).unwrap();
    let mut checker = Checker::new(&config, sim, &[]).timing_lines();
    for statement in testing::statements_with(program, &config) {
        checker.statement(&statement);
    }
    checker.finish()
}

/// A 100 mm line at 50 mm/s from rest to rest on the grbl-default profile
/// (X at 500 mm/s²): 2 + 50 / 500 = 2.1 s, and the 25,896 ticks of GRBL's
/// step timer a cycle late each at 16 MHz (ger-motion's tests work both out).
const LINE: f64 = 2.1 + 25_896.0 / 16e6;
/// After a stop the machine stands at (a tool change), the next move waits
/// out the step timer's period, 0.2 ms at the end of such a line.
const RESTART: f64 = 0.0002;

#[test]
fn the_planned_time_is_counted_by_tool_by_call_and_by_line() {
    // Five such lines, each from rest to rest (each turns back on the last,
    // or follows a tool change).
    let program = "G21\nG01 X100 F3000\nM98 P10\nM06 T2\nM98 P10\nM30\nO10\nG01 X0\nG01 X100\nM99\n";
    let verdict = timed_with_two_tools(program, config());
    let planned = &verdict.summary.planned;
    let near = |a: f64, b: f64| (a - b).abs() < 1e-6;
    let total = 5.0 * LINE + RESTART;
    assert!(near(planned.seconds, total), "{planned:?}");
    assert_eq!(planned.moving.map(|[a, b]| (near(a, 0.0), near(b, total))), Some((true, true)), "{planned:?}");
    let tools: Vec<(u32, f64)> = planned.tools.iter().map(|t| (t.number, t.seconds)).collect();
    assert!(tools.len() == 2 && tools[0].0 == 1 && near(tools[0].1, 3.0 * LINE), "{tools:?}");
    assert!(tools[1].0 == 2 && near(tools[1].1, 2.0 * LINE + RESTART), "{tools:?}");
    let calls: Vec<(&str, u32, f64)> = planned.calls.iter().map(|c| (c.name.as_str(), c.line, c.seconds)).collect();
    assert!(calls.len() == 2 && calls.iter().all(|c| c.0 == "O10"), "{calls:?}");
    assert!(near(calls[0].2, 2.0 * LINE) && near(calls[1].2, 2.0 * LINE + RESTART), "{calls:?}");
    assert_eq!((calls[0].1, calls[1].1), (3, 5));
    // Each line is reached when the one before it is done; the call lines
    // hold their subprogram's moves.
    let expected = [0.0, 0.0, LINE, 3.0 * LINE, 3.0 * LINE, total];
    assert_eq!(verdict.line_times.len(), expected.len(), "{:?}", verdict.line_times);
    assert!(verdict.line_times.iter().zip(expected).all(|(a, b)| near(*a, b)), "{:?}", verdict.line_times);
    // The profile is said: grbl-default, as no [machine.motion] is given.
    assert_eq!((planned.profile.preset, planned.profile.configured), ("grbl-default", false));
    assert_eq!(planned.profile.machine.max_rate, [5000.0, 5000.0, 1000.0]);
}

#[test]
fn the_lenient_dialects_calls_are_timed_as_pass_00s_are() {
    // The same five lines, in LinuxCNC's o-word sub and a Fanuc program
    // that the interpreter stage runs: each call's time is its two lines',
    // counted at the call's line, which is reached when the line before it
    // is done.
    let program = "o10 sub\nG01 X0\nG01 X100\no10 endsub\nG21\nG01 X100 F3000\no10 call\nM06 T2\nM98 P20\nM30\n\
                   O20\nG01 X0\nG01 X100\nM99\n";
    let mut config = config();
    config.dialect.name = ger_core::statement::Dialect::Lenient;
    let verdict = timed_with_two_tools(program, config);
    let near = |a: f64, b: f64| (a - b).abs() < 1e-6;
    assert!(near(verdict.summary.planned.seconds, 5.0 * LINE + RESTART), "{:?}", verdict.summary.planned);
    let calls: Vec<(&str, u32, f64)> =
        verdict.summary.planned.calls.iter().map(|c| (c.name.as_str(), c.line, c.seconds)).collect();
    assert_eq!(calls.len(), 2, "{calls:?}");
    assert!(calls[0].0.eq_ignore_ascii_case("o10") && calls[0].1 == 7 && near(calls[0].2, 2.0 * LINE), "{calls:?}");
    assert!(calls[1].0 == "O20" && calls[1].1 == 9 && near(calls[1].2, 2.0 * LINE + RESTART), "{calls:?}");
    let (call, tool_change, fanuc_call) = (verdict.line_times[6], verdict.line_times[7], verdict.line_times[8]);
    let reached = [(call, LINE), (tool_change, 3.0 * LINE), (fanuc_call, 3.0 * LINE)];
    assert!(reached.iter().all(|&(a, b)| near(a, b)), "{:?}", verdict.line_times);
}

#[test]
fn statements_from_calls_belong_to_the_outermost_call() {
    use ger_core::diag::{Origin, Span};
    use std::sync::Arc;
    // A wizard called at line 3 of subprogram O200, which the program calls at line 12.
    let subprogram = Arc::new(Origin { what: "O200".into(), call: Span::new(12, 1, 4), parent: None });
    let wizard = Arc::new(Origin { what: "Pocket".into(), call: Span::new(3, 1, 6), parent: Some(subprogram) });
    let mut statement = Statement::new(ger_core::statement::Kind::End, Span::new(3, 1, 6));
    assert_eq!(outermost_line(&statement), 3);
    statement.origin = Some(wizard);
    assert_eq!(outermost_line(&statement), 12);
}

/// A slot cut 2 mm a pass to Z-12 by a 6 mm endmill with 10 mm flutes on an
/// 8 mm shank: from Z-10 the shank's bottom (10 mm above the tip) is level
/// with the top, its ring 3 to 4 mm from the axis over uncut material.
const DEEP_SLOT: &str = "G21\nM03 S10000\nG00 X20 Y25 Z1\nG01 Z-2 F100\nX60\nZ-4\nX20\nZ-6\nX60\nZ-8\nX20\n\
                         Z-10\nX60\nZ-12\nX20\nG00 Z5\nM30\n";

#[test]
fn a_shank_wider_than_the_cutter_rubs_the_walls_of_a_slot_deeper_than_the_flutes() {
    let mut config = config();
    config.tools[0].shank_diameter = Some(8.0);
    let verdict = check_with(DEEP_SLOT, &config, &[]);
    // At Z-10 the shank is 0 mm from the top (within the 0.5 mm clearance);
    // at Z-12 it is 2 mm into it, on the way along and on the way out.
    assert_eq!(
        found(&verdict),
        [
            "12: clearance: tool 1's shank passes within 0.500 mm of the stock",
            "13: clearance: tool 1's shank passes within 0.500 mm of the stock",
            "14: collision: tool 1's shank goes 2.000 mm into the stock",
            "15: collision: tool 1's shank goes 2.000 mm into the stock",
            "16: collision: tool 1's shank goes 2.000 mm into the stock in a rapid move (G00)",
        ]
    );
    assert!(verdict.findings[2].diagnostic.is_error() && !verdict.findings[0].diagnostic.is_error());
    // With 15 mm flutes the shank stays 3 mm above the top.
    config.tools[0].flute_length = Some(15.0);
    assert_eq!(found(&check_with(DEEP_SLOT, &config, &[])), Vec::<String>::new());
    // Both checks can be allowed away, by name.
    config.tools[0].flute_length = Some(10.0);
    assert_eq!(found(&check_with(DEEP_SLOT, &config, &[Rule::Collision, Rule::Clearance])), Vec::<String>::new());
}

/// Tool 2, a 20 mm endmill, clears two slots 24 mm deep (Y 0 to 20 and 30 to
/// 50), leaving a 10 mm rib between; tool 1 then runs down the first slot's
/// middle at the bottom, its 30 mm holder 15 mm round the axis reaching
/// Y 25, over the rib.
const BESIDE_A_RIB: &str = "G21\nM06 T2\nM03 S10000\nG00 X10 Y10 Z1\nG01 Z-8 F100\nX90\nZ-16\nX10\nZ-24\nX90\n\
                            G00 Z1\nX10 Y40\nG01 Z-8\nX90\nZ-16\nX10\nZ-24\nX90\nG00 Z5\nM06 T1\nG00 X20 Y10 Z1\n\
                            G01 Z-24\nX80\nG00 Z5\nM30\n";

fn holder_config(stick_out: f64) -> Config {
    let mut config = config();
    config.stock.size = Some([100.0, 50.0, 40.0]);
    config.stock.origin = Some([0.0, 0.0, 40.0]);
    config.tools = vec![
        Tool {
            flute_length: Some(20.0),
            stick_out: Some(stick_out),
            holder: vec![HolderPiece { diameter: Some(30.0), bottom: None, top: None, length: 40.0 }],
            ..Tool::new(1, ToolKind::Endmill, 6.0)
        },
        Tool { flute_length: Some(40.0), ..Tool::new(2, ToolKind::Endmill, 20.0) },
    ];
    config
}

#[test]
fn a_holder_that_reaches_over_a_rib_hits_it() {
    // The holder's face is 22 mm above the tip: at Z-24 it is 2 mm under the rib's top.
    let verdict = check_with(BESIDE_A_RIB, &holder_config(22.0), &[]);
    assert_eq!(
        found(&verdict),
        [
            "22: collision: tool 1's holder goes 2.000 mm into the stock",
            "23: collision: tool 1's holder goes 2.000 mm into the stock",
            "24: collision: tool 1's holder goes 2.000 mm into the stock in a rapid move (G00)",
        ]
    );
    // 26 mm out, it passes 2 mm over the rib.
    assert_eq!(found(&check_with(BESIDE_A_RIB, &holder_config(26.0), &[])), Vec::<String>::new());
}

/// A clamp 20 x 20 mm and 8 mm high on the block's top, over Y 40 to 60.
fn clamp(coordinates: Coordinates) -> Fixture {
    Fixture {
        name: "clamp".to_string(),
        min: Some([40.0, 40.0, 0.0]),
        max: Some([60.0, 60.0, 8.0]),
        centre: None,
        diameter: None,
        height: None,
        coordinates,
    }
}

#[test]
fn a_rapid_through_a_clamp_is_an_error_naming_it() {
    let mut config = config();
    config.fixtures = vec![clamp(Coordinates::Program)];
    // Across at Z5: the tip 3 mm under the clamp's top.
    let low = "G21\nM03 S10000\nG00 Z5\nX10 Y45\nX90\nG00 Z10\nM30\n";
    let verdict = check_with(low, &config, &[]);
    assert_eq!(
        found(&verdict),
        ["5: fixture: tool 1 in a rapid move (G00): its cutting edge goes 3.000 mm into fixture \"clamp\""]
    );
    assert!(verdict.findings[0].diagnostic.is_error());
    // At Z10 it passes 2 mm over it.
    let high = "G21\nM03 S10000\nG00 Z10\nX10 Y45\nX90\nM30\n";
    assert_eq!(found(&check_with(high, &config, &[])), Vec::<String>::new());
    // A bolt's head, 10 across and 6 high at (50, 20): the 6 mm tool along
    // Y20 at Z4 meets it with the flat of its tip, 2 mm down; along Y28.1 it
    // clears it by a tenth (the tool's edge at 25.1, the bolt's at 25), within
    // the 0.5 mm clearance; along Y28.7, by 0.7, beyond it.
    config.fixtures = vec![Fixture {
        name: "bolt".to_string(),
        min: None,
        max: None,
        centre: Some([50.0, 20.0, 0.0]),
        diameter: Some(10.0),
        height: Some(6.0),
        coordinates: Coordinates::Program,
    }];
    let verdict = check_with("G21\nG00 Z4\nX10 Y20\nX90\nM30\n", &config, &[]);
    assert_eq!(
        found(&verdict),
        ["4: fixture: tool 1 in a rapid move (G00): its cutting edge goes 2.000 mm into fixture \"bolt\""]
    );
    assert_eq!(
        found(&check_with("G21\nG00 Z4\nX10 Y28.1\nX90\nM30\n", &config, &[])),
        ["4: clearance: tool 1 in a rapid move (G00): its cutting edge passes within 0.500 mm of fixture \"bolt\""]
    );
    assert_eq!(found(&check_with("G21\nG00 Z4\nX10 Y28.7\nX90\nM30\n", &config, &[])), Vec::<String>::new());
}

#[test]
fn a_fixture_in_program_coordinates_moves_with_g54() {
    // G54 puts program zero at machine X100: the program's X10 to X90 is the machine's 110 to 190,
    // and the clamp, given from G54's zero, is at the machine's 140 to 160.
    let mut config = config();
    config.offsets.g54 = Some([100.0, 0.0, 0.0]);
    config.fixtures = vec![clamp(Coordinates::Program)];
    let text = "G21 G54\nG00 Z5\nX10 Y45\nX90\nM30\n";
    assert_eq!(found(&check_with(text, &config, &[])).len(), 1);
    // The same clamp at machine X40 to 60 is not in the way.
    config.fixtures = vec![clamp(Coordinates::Machine)];
    assert_eq!(found(&check_with(text, &config, &[])), Vec::<String>::new());
}
