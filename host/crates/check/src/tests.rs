//! Each check on a program that trips it and on one that does not, with the
//! depths, lengths and times worked out by hand.

use super::*;
use ger_core::config::{StockConfig, Tool, ToolKind};
use ger_core::passes::testing;
use ger_core::statement::Units;
use ger_sim::Stock;

/// A 100 x 50 x 20 mm block, program zero on its top lower-left corner;
/// tool 1 a 6 mm endmill with 10 mm flutes.
fn config() -> Config {
    Config {
        units: Units::Mm,
        tools: vec![Tool {
            number: 1,
            kind: ToolKind::Endmill,
            diameter: 6.0,
            flute_length: Some(10.0),
            tip_angle: None,
        }],
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
            source: None
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
    assert_eq!(
        found(&verdict),
        ["4: flute-length: cuts 12.000 mm deep in one pass, more than tool 1's flute length of 10.000 mm"]
    );
    assert!(!verdict.findings[0].diagnostic.is_error());
    // The same depth in two passes of 6.
    let verdict = check("G21\nM03\nG00 X10 Y10 Z1\nG01 X60 Z-6 F100\nX10\nX60 Z-12\nG00 Z5\nM30\n");
    assert_eq!(found(&verdict), Vec::<String>::new());
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
    let allowed = [Rule::FluteLength, Rule::Plunge];
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
    let verdict = check_with(&text, &config, &[]);
    assert_eq!(verdict.summary.problems.get("rapid-into-stock"), Some(&40_000));
    assert_eq!(verdict.findings.len(), SHOWN_PER_RULE as usize);
    assert_eq!(verdict.findings[99].diagnostic.span.line, 103);
}

#[test]
fn the_planned_time_is_counted_by_tool_by_call_and_by_line() {
    // Five 100 mm lines at 50 mm/s, each from rest to rest (each turns back
    // on the last, or follows a tool change): 2 + 50 / 500 = 2.1 s each. The
    // grbl-default profile: X at 500 mm/s².
    let program = "G21\nG01 X100 F3000\nM98 P10\nM06 T2\nM98 P10\nM30\nO10\nG01 X0\nG01 X100\nM99\n";
    let mut config = config();
    config.tools.push(Tool { number: 2, ..config.tools[0].clone() });
    let stock = Stock::from_config(&config).unwrap();
    let sim = Simulation::new(stock, 1.0, 1 << 30).unwrap();
    let mut checker = Checker::new(&config, sim, &[]).timing_lines();
    for statement in testing::statements_with(program, &config) {
        checker.statement(&statement);
    }
    let verdict = checker.finish();
    let planned = &verdict.summary.planned;
    let near = |a: f64, b: f64| (a - b).abs() < 1e-6;
    assert!(near(planned.seconds, 5.0 * 2.1), "{planned:?}");
    assert_eq!(planned.moving.map(|[a, b]| (near(a, 0.0), near(b, 10.5))), Some((true, true)), "{planned:?}");
    let tools: Vec<(u32, f64)> = planned.tools.iter().map(|t| (t.number, t.seconds)).collect();
    assert!(tools.len() == 2 && tools[0].0 == 1 && near(tools[0].1, 6.3), "{tools:?}");
    assert!(tools[1].0 == 2 && near(tools[1].1, 4.2), "{tools:?}");
    let calls: Vec<(&str, u32, f64)> = planned.calls.iter().map(|c| (c.name.as_str(), c.line, c.seconds)).collect();
    assert!(calls.len() == 2 && calls.iter().all(|c| c.0 == "O10" && near(c.2, 4.2)), "{calls:?}");
    assert_eq!((calls[0].1, calls[1].1), (3, 5));
    // Each line is reached when the one before it is done; the call lines
    // hold their subprogram's moves.
    let expected = [0.0, 0.0, 2.1, 6.3, 6.3, 10.5];
    assert_eq!(verdict.line_times.len(), expected.len(), "{:?}", verdict.line_times);
    assert!(verdict.line_times.iter().zip(expected).all(|(a, b)| near(*a, b)), "{:?}", verdict.line_times);
    // The profile is said: grbl-default, as no [machine.motion] is given.
    assert_eq!((planned.profile.preset, planned.profile.configured), ("grbl-default", false));
    assert_eq!(planned.profile.max_rate, [5000.0, 5000.0, 1000.0]);
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
