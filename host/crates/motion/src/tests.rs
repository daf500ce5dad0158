//! Run times worked out by hand (trapezoids and the junction formula), and
//! one figure of GRBL's own (`../shared/peers/grbl/gtime.py`), each within
//! 0.5%. The machine is the `grbl-default` preset in millimetres: X and Y
//! at 5000 mm/min and 500 mm/s², Z at 1000 mm/min and 200 mm/s², junction
//! deviation 0.01 mm, arc tolerance 0.002 mm, 16-block buffer, 250 steps/mm,
//! and no step slower than 32.768 ms.

use super::*;
use ger_core::config::Config;
use ger_core::passes::testing;

fn config(motion: &str) -> Config {
    Config::from_toml(&format!("units = \"mm\"\ndialect = \"lenient\"\n{motion}")).unwrap()
}

/// The planned time of `program` on `config`'s machine, and each tag's share.
fn plan_with(program: &str, config: &Config) -> (f64, Vec<(usize, f64)>) {
    let profile = config.motion_profile();
    let mut run = Run::new(&profile.machine, config.units);
    let mut shares: Vec<(usize, f64)> = Vec::new();
    let mut clock = |line: &usize, _start: f64, seconds: f64| match shares.last_mut() {
        Some((last, sum)) if last == line => *sum += seconds,
        _ => shares.push((*line, seconds)),
    };
    for statement in testing::statements_with(program, config) {
        let line = statement.span.line as usize;
        run.statement(&statement, line, &mut clock);
    }
    let totals = run.finish(&mut clock);
    (totals.seconds, shares)
}

fn plan(program: &str) -> f64 {
    plan_with(program, &config("")).0
}

#[track_caller]
fn within(actual: f64, expected: f64, fraction: f64) {
    let error = (actual - expected).abs() / expected;
    assert!(error <= fraction, "{actual} s, expected {expected} s ({:.3}% off)", error * 100.0);
}

#[track_caller]
fn close(actual: f64, expected: f64) {
    within(actual, expected, 0.005);
}

#[test]
fn a_line_from_rest_to_rest() {
    // 100 mm at 50 mm/s: accelerating to 50 mm/s at 500 mm/s² and braking take
    // 0.1 s each over 2.5 mm, so L/v + v/a = 2 + 0.1.
    close(plan("G21 G90\nG01 X100 F3000\n"), 2.1);
    // Along Z (1000 mm/min, 200 mm/s²), asked for 3000 mm/min: 16.667 mm/s.
    // 50 / 16.667 + 16.667 / 200 = 3 + 0.083333.
    close(plan("G21 G90\nG01 Z-50 F3000\n"), 3.083333);
}

#[test]
fn each_tick_of_the_step_timer_takes_a_cycle_more() {
    // 100 mm at F3000 is 25,000 steps at 250 steps/mm. GRBL's timer ticks 8
    // times a step below 2000 steps/s (8 mm/s), 4 below 16 mm/s, 2 below
    // 32 mm/s: each ramp takes 0.064 mm (16 steps) below 8 mm/s, 0.192 mm
    // (48) to 16 mm/s and 0.768 mm (192) to 32 mm/s, so the two ramps and
    // the rest tick 2 (16·8 + 48·4 + 192·2) + 25,000 − 2 (16 + 48 + 192) =
    // 25,896 times, each a cycle of 16 MHz longer than asked.
    let exact = 2.1;
    let planned = plan("G21 G90\nG01 X100 F3000\n");
    within(planned, exact + 25_896.0 / 16e6, 1e-9);
    // GRBL itself: 2.101623 s (the peer's README, case 01).
    within(planned, 2.101623, 5e-6);
    let without = plan_with("G21 G90\nG01 X100 F3000\n", &config("[machine.motion]\nstep_clock = 0\n")).0;
    within(without, exact, 1e-12);
}

#[test]
fn after_a_stop_the_step_timer_first_runs_out_its_last_period() {
    // Two 2 mm lines at F600 (10 mm/s), a speed change between them that
    // GRBL waits for the first to stop at. Each: ramps of 0.1 mm, 0.02 s
    // each, 1.8 mm at 10 mm/s: 0.22 s; its timer ticks 8 times a step for
    // the first and last 16 steps (below 8 mm/s), 4 times for the other
    // 468: 2128 ticks, 0.133 ms. Braking to the stop, GRBL's last 10 ms segment steps at
    // its mean speed, 2.5 mm/s, 625 steps/s, 8 ticks a step: the timer is
    // left ticking every 0.2 ms, and the second line starts a tick late.
    let planned = plan("G21 G90\nM3 S1000\nG01 X2 F600\nS2000\nG01 X4\nM5\n");
    within(planned, 2.0 * (0.22 + 2128.0 / 16e6) + 0.0002, 1e-9);
    // GRBL itself (gtime.py): 0.440432 s.
    within(planned, 0.440432, 1e-4);
}

#[test]
fn a_line_too_short_to_reach_its_feed() {
    // 2 mm, but reaching 50 mm/s takes 2.5 mm each way: up to the middle and
    // down again, 2 sqrt(L / a) = 2 sqrt(2 / 500).
    close(plan("G21 G90\nG01 X2 F3000\n"), 0.126491);
}

#[test]
fn a_feed_below_the_slowest_step_runs_at_the_slowest_step() {
    // GRBL's slowest step is 8 ticks of 65,536 cycles at 16 MHz: 32.768 ms.
    // 1 mm at 250 steps/mm is 250 steps: 8.192 s at F5 (which would be
    // 12 s) and at F2 alike, as GRBL itself times it (gtime.py).
    close(plan("G21 G90\nG01 X1 F5\n"), 8.192);
    close(plan("G21 G90\nG01 X1 F2\n"), 8.192);
    // On a diagonal the axis that steps most sets the pace: X's 250 steps.
    close(plan("G21 G90\nG01 X1 Y0.5 F2\n"), 8.192);
    // Above it, the feed: 1 mm at F10 is 6 s (and a third of a millisecond of ramps).
    close(plan("G21 G90\nG01 X1 F10\n"), 6.0);
    // A controller without that floor runs F5 as asked: 12 s.
    close(plan_with("G21 G90\nG01 X1 F5\n", &config("[machine.motion]\nslowest_step_rate = 0\n")).0, 12.0);
}

#[test]
fn a_rapid_runs_each_axis_at_its_limit() {
    // G00 X100 Y100: 141.42 mm; X and Y may each go 83.33 mm/s, so along the
    // diagonal 117.85 mm/s, and accelerate 500 mm/s² each, so 707.1 mm/s²:
    // L/v + v/a = 1.2 + 0.16667.
    close(plan("G21 G90\nG00 X100 Y100\n"), 1.366667);
    // Z alone: 1000 mm/min and 200 mm/s²: 10 / 16.667 + 16.667 / 200.
    close(plan("G21 G90\nG00 Z10\n"), 0.683333);
}

/// Two 50 mm lines at 50 mm/s meeting at `degrees` between them (180: straight on).
fn corner(degrees: f64) -> f64 {
    let turn = (180.0 - degrees).to_radians();
    let (x, y) = (50.0 + 50.0 * turn.cos(), 50.0 * turn.sin());
    // Exact ends: no steps' grid to round them to, and no step timer's cycles.
    let config = config("[machine.motion]\nsteps_per_unit = [1e6, 1e6, 1e6]\nstep_clock = 0\n");
    plan_with(&format!("G21 G90\nG01 X50 Y0 F3000\nX{x:.6} Y{y:.6}\n"), &config).0
}

/// A line of 50 mm at 50 mm/s from `entry` to `exit` (mm/s) accelerating at
/// `a`, reaching its feed: (v - vi)/a + (v - vo)/a + the rest at v.
fn trapezoid_by_hand(entry: f64, exit: f64, a: f64) -> f64 {
    let v: f64 = 50.0;
    let ramps = (v * v - entry * entry) / (2.0 * a) + (v * v - exit * exit) / (2.0 * a);
    (v - entry) / a + (v - exit) / a + (50.0 - ramps) / v
}

#[test]
fn corners_are_taken_at_the_junction_deviations_speed() {
    // v² = a δ s / (1 - s), s = sin(θ/2), θ the angle between the lines, a
    // the acceleration X and Y allow along the corner's direction (from the
    // first line's direction to the second's), δ = 0.01 mm.
    //
    // 90°: s = sin 45° = 0.707107; the corner points at 135°, where X and Y
    // each take 500 mm/s² for 707.107 along it: v² = 707.107 × 0.01 ×
    // 0.707107 / 0.292893 = 17.0711, v = 4.13171 mm/s. The second line is
    // along Y: 500 mm/s².
    let v90 = 4.13171;
    close(corner(90.0), trapezoid_by_hand(0.0, v90, 500.0) + trapezoid_by_hand(v90, 0.0, 500.0));
    within(trapezoid_by_hand(0.0, v90, 500.0) * 2.0, 2.184156, 1e-5);
    // 135° (a turn of 45°): s = sin 67.5° = 0.923880; the corner points at
    // 112.5°, (-0.382683, 0.923880), for 500 / 0.923880 = 541.196 mm/s²:
    // v² = 541.196 × 0.01 × 0.923880 / 0.076120 = 65.6853, v = 8.10465. The
    // second line is at 45°: 707.107 mm/s².
    let v135 = 8.10465;
    close(corner(135.0), trapezoid_by_hand(0.0, v135, 500.0) + trapezoid_by_hand(v135, 0.0, 707.107));
    // 45° (a turn of 135°): s = sin 22.5° = 0.382683; the corner points at
    // 157.5°, (-0.923880, 0.382683): 541.196 mm/s²; v² = 541.196 × 0.01 ×
    // 0.382683 / 0.617317 = 3.35495, v = 1.83165. The second line is at 135°.
    let v45 = 1.83165;
    close(corner(45.0), trapezoid_by_hand(0.0, v45, 500.0) + trapezoid_by_hand(v45, 0.0, 707.107));
    // 180°, straight on: no corner, one 100 mm line (2.1 s).
    close(corner(180.0), 2.1);
    // Straight back (0°): a stop, two lines from rest to rest.
    close(corner(0.0), 2.0 * 1.1);
}

#[test]
fn a_square_as_grbls_peer_readme_works_it_out() {
    // Case 03 of the GRBL peer: four 50 mm sides, three 90° corners at 4.13171 mm/s.
    close(plan("G21 G90\nG01 X50 F3000\nY50\nX0\nY0\n"), 4.352468);
}

#[test]
fn the_machine_can_always_stop_at_the_end_of_the_buffer() {
    // planner_blocks = 3: two blocks held, so each new 1 mm block must be
    // able to stop at its own end: no block enters faster than v² = 2 a L =
    // 1000 (31.62 mm/s). The first accelerates from rest to that (a
    // triangle: 31.62 / 500 = 0.063246 s), each after it from 31.62 mm/s up
    // to v² = a L + 1000 = 1500 (38.73 mm/s) and back (2 × 7.1068 / 500 =
    // 0.028427 s), the last brakes to rest (0.063246 s).
    let config = config("[machine.motion]\nplanner_blocks = 3\n");
    let program: String = (1..=10).map(|i| format!("G01 X{i} F3000\n")).collect();
    let (seconds, _) = plan_with(&format!("G21 G90\n{program}"), &config);
    close(seconds, 2.0 * 0.063246 + 8.0 * 0.028427);
    // With GRBL's 16 the ten are one 10 mm line: 10 / 50 + 0.1 s.
    close(plan(&format!("G21 G90\n{program}")), 0.3);
}

#[test]
fn arcs_run_as_lines_within_the_arc_tolerance() {
    // A half circle of 10 mm: chords within 0.002 mm are 2 sqrt(0.002 ×
    // 19.998) = 0.39996 mm, so π × 10 / 0.39996 = 78.5: 78 lines.
    assert_eq!(arc_lines(10.0, std::f64::consts::PI, 0.002), 78);
    assert_eq!(arc_lines(10.0, -std::f64::consts::PI, 0.002), 78);
    // Each line's middle strays r (1 - cos(sweep / 2n)) from the arc: the
    // count rounds down, as GRBL's, so one line more would be within the
    // tolerance, and these stray at most ((n + 1) / n)² of it.
    for (radius, sweep) in [(0.5, 6.2), (3.0, 1.0), (250.0, 3.0)] {
        let n = arc_lines(radius, sweep, 0.002) as f64;
        let strays = |lines: f64| radius * (1.0 - (sweep / (2.0 * lines)).cos());
        assert!(strays(n + 1.0) <= 0.002, "{radius} {sweep} {n}");
        assert!(strays(n) <= 0.002 * ((n + 1.0) / n).powi(2), "{radius} {sweep} {n}");
    }
    // Smaller than the tolerance: one line.
    assert_eq!(arc_lines(0.0005, 3.0, 0.002), 1);
    // A circle of 10 mm at 50 mm/s: its 157 lines meet at 2.3°, which
    // 150 mm/s could take, so it runs at its feed: 2π × 10 / 50 + 50 / 500.
    // After a rapid to its start, from rest to rest.
    close(plan("G21 G90\nG00 X10\nG04 P0\nG03 X10 Y0 I-10 J0 F3000\n"), time_of_rapid(10.0) + 1.356637);
}

/// A rapid of `length` mm along X from rest to rest: L / 83.33 + 83.33 / 500.
fn time_of_rapid(length: f64) -> f64 {
    let v = 5000.0 / 60.0;
    length / v + v / 500.0
}

#[test]
fn a_small_circle_as_grbl_runs_it() {
    // Circles of 0.5 mm at 50 mm/s: 35 lines meeting at 10.3°, each corner
    // slower than the feed, and the steps' grid bends each line a little.
    // GRBL's own planner and stepper (`gtime.py`) take 0.512873 s.
    let circle = "G02 X0.5 Y0 I-0.5 J0 F3000\n";
    let program = format!("G21 G90\nG01 X0.5 Y0 F3000\nG04 P0\n{}", circle.repeat(4));
    close(plan(&program), 0.512873);
}

#[test]
fn a_dwell_stops_then_waits() {
    // Case 05 of the GRBL peer: two 10 mm lines at 10 mm/s (10 / 10 + 10 /
    // 500 each) and half a second between them.
    close(plan("G21 G90\nG01 X10 F600\nG04 P0.5\nX0\n"), 2.54);
    // GRBL waits in steps of 50 ms: 0.01 s is 0.05 s; as programmed, 0.01 s.
    close(plan("G21 G90\nG01 X10 F600\nG04 P0.01\nX0\n"), 2.04 + 0.05);
    let exact = config("[machine.motion]\ndwell_multiple = 0\n");
    close(plan_with("G21 G90\nG01 X10 F600\nG04 P0.01\nX0\n", &exact).0, 2.04 + 0.01);
}

#[test]
fn the_spindle_coolant_and_tool_changes_stop_the_machine() {
    // Two 10 mm lines at 50 mm/s: 0.5 s in one go, 0.6 s with a stop between.
    close(plan("G21 G90\nG01 X10 F3000\nX20\n"), 0.5);
    for between in ["M03 S1000", "M08", "G43 H1", "M00"] {
        close(plan(&format!("G21 G90\nG01 X10 F3000\n{between}\nX20\n")), 0.6);
    }
    // The same state again is no change.
    close(plan("G21 G90\nM03 S1000\nG01 X10 F3000\nM03 S1000\nX20\n"), 0.5);
    close(plan("G21 G90\nG01 X10 F3000\nM05\nX20\n"), 0.5);
    // A tool change takes its time.
    let config = config("[machine.motion]\ntool_change_time = 12.5\n");
    let (seconds, shares) = plan_with("G21 G90\nG01 X10 F3000\nM06 T2\nX20\n", &config);
    close(seconds, 0.6 + 12.5);
    assert_eq!(shares.iter().map(|(line, _)| *line).collect::<Vec<_>>(), [2, 3, 4]);
    close(shares[1].1, 12.5);
}

#[test]
fn an_inch_machine_plans_the_same_moves_in_inches() {
    let inch = Config::from_toml("dialect = \"lenient\"\n").unwrap();
    // 100 mm as 3.937 in at 3000 mm/min.
    let (seconds, _) = plan_with("G20 G90\nG01 X3.937008 F118.110236\n", &inch);
    close(seconds, 2.1);
}
