//! Arcs as a controller reads them: GRBL's end-radius check, the full turn
//! it makes of an arc whose end is at its start's angle, and an arc written
//! as lines when it would be refused.
//!
//! Points are in the arc's plane: `[first, second, normal]` (see
//! `Plane::axes`), counter-clockwise from first to second.

use std::f64::consts::TAU;

use crate::profile::ArcCheck;

/// GRBL takes an end this close to its start's angle (radians) as a full
/// circle; ger keeps a margin over it.
const FULL_TURN_ANGLE: f64 = 1e-6;

/// GRBL works in 32-bit floats, whose steps are 0.06 µm at a metre: an arc
/// is judged against its limits less this many millimetres.
const MARGIN_MM: f64 = 0.0002;

/// Whether the controller refuses the arc from `start` round `centre` to
/// `end`, whose lengths are `mm_per_unit` millimetres each (25.4 in inches).
pub fn refused(check: &ArcCheck, start: [f64; 3], centre: [f64; 2], end: [f64; 3], mm_per_unit: f64) -> bool {
    let radius = (start[0] - centre[0]).hypot(start[1] - centre[1]) * mm_per_unit;
    let end_radius = (end[0] - centre[0]).hypot(end[1] - centre[1]) * mm_per_unit;
    let off = (end_radius - radius).abs();
    off > check.most_mm - MARGIN_MM || (off > check.mm - MARGIN_MM && off > check.fraction * radius - MARGIN_MM)
}

/// The angle the arc turns through, positive, as a controller reads its
/// words: an end at the start's angle (within [`FULL_TURN_ANGLE`]) is a full turn.
pub fn sweep(start: [f64; 3], centre: [f64; 2], end: [f64; 3], clockwise: bool) -> f64 {
    let from = (start[1] - centre[1]).atan2(start[0] - centre[0]);
    let to = (end[1] - centre[1]).atan2(end[0] - centre[0]);
    let turn = if clockwise { from - to } else { to - from };
    let turn = turn.rem_euclid(TAU);
    if turn < FULL_TURN_ANGLE || TAU - turn < FULL_TURN_ANGLE {
        TAU
    } else {
        turn
    }
}

/// The arc as lines no further than `tolerance` from it, ending exactly at
/// `end`, turning `turn` radians (positive) the way the arc goes: see
/// [`ger_core::geom::arc_as_lines`]. At most `most` lines.
pub fn as_lines(
    start: [f64; 3],
    centre: [f64; 2],
    end: [f64; 3],
    (turn, clockwise): (f64, bool),
    tolerance: f64,
    most: usize,
) -> Vec<[f64; 3]> {
    let signed = if clockwise { -turn } else { turn };
    ger_core::geom::arc_as_lines(start, centre, end, signed, tolerance, most)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::GRBL;
    use std::f64::consts::PI;

    fn check() -> ArcCheck {
        GRBL.arc_check.unwrap()
    }

    #[test]
    fn an_end_off_its_circle_is_refused_past_both_of_grbls_limits() {
        // From (0,0) round (c,0) to (10,0): the end is 10 - c from the centre, the start c.
        // Checked with gvalidate: c = 5.002 is ok (0.004 off), 5.003 is error:33 (0.006 off, over 0.005 mm
        // and over 0.1% of 5.003).
        let arc = |c: f64, end: f64| refused(&check(), [0.0; 3], [c, 0.0], [end, 0.0, 0.0], 1.0);
        assert!(!arc(5.002, 10.0));
        assert!(arc(5.003, 10.0));
        // A radius of 50: 0.04 off is under 0.1% (0.05), ok; 0.08 off is refused (gvalidate agrees).
        assert!(!arc(50.02, 100.0));
        assert!(arc(50.04, 100.0));
        // Over 0.5 mm is refused whatever the radius: r = 1000, 0.6 off (0.06%).
        assert!(arc(1000.3, 2000.0));
        // A margin of 0.2 µm: 0.0049 mm off on a radius of 1 is refused, 0.0047 is not.
        assert!(refused(&check(), [0.0; 3], [1.0, 0.0], [2.0049, 0.0, 0.0], 1.0));
        assert!(!refused(&check(), [0.0; 3], [1.0, 0.0], [2.0047, 0.0, 0.0], 1.0));
        // Inches are judged in millimetres: 0.0002 in off is 0.00508 mm.
        assert!(refused(&check(), [0.0; 3], [0.1, 0.0], [0.2002, 0.0, 0.0], 25.4));
        assert!(!refused(&check(), [0.0; 3], [0.1, 0.0], [0.2002, 0.0, 0.0], 1.0));
    }

    #[test]
    fn sweeps_turn_the_way_of_the_arc() {
        let quarter = sweep([1.0, 0.0, 0.0], [0.0, 0.0], [0.0, 1.0, 0.0], false);
        assert!((quarter - TAU / 4.0).abs() < 1e-12);
        let three_quarters = sweep([1.0, 0.0, 0.0], [0.0, 0.0], [0.0, 1.0, 0.0], true);
        assert!((three_quarters - 0.75 * TAU).abs() < 1e-12);
        // An end at the start is a full turn, and so is one 5e-7 rad past it (GRBL's epsilon).
        assert_eq!(sweep([1.0, 0.0, 0.0], [0.0, 0.0], [1.0, 0.0, 0.0], true), TAU);
        let near = [(5e-7f64).cos(), (5e-7f64).sin(), 0.0];
        assert_eq!(sweep([1.0, 0.0, 0.0], [0.0, 0.0], near, false), TAU);
    }

    #[test]
    fn lines_stay_within_tolerance_and_end_at_the_end() {
        // A half circle of radius 10 at 0.002: each chord may turn 2 acos(1 - 0.0002) = 0.040000 rad,
        // so pi / 0.04 = 78.5 -> 79 lines.
        let lines = as_lines([10.0, 0.0, 0.0], [0.0, 0.0], [-10.0, 0.0, -1.0], (PI, false), 0.002, 10_000);
        assert_eq!(lines.len(), 79);
        assert_eq!(*lines.last().unwrap(), [-10.0, 0.0, -1.0]);
        let mut previous = [10.0, 0.0, 0.0];
        for point in &lines {
            assert!((point[0].hypot(point[1]) - 10.0).abs() < 1e-9);
            // The chord's middle is no further than the tolerance inside the circle.
            let middle = [(previous[0] + point[0]) / 2.0, (previous[1] + point[1]) / 2.0];
            assert!(10.0 - middle[0].hypot(middle[1]) <= 0.002 + 1e-12);
            assert!(point[1] >= -1e-9, "counter-clockwise from +X to -X goes through +Y");
            previous = *point;
        }
        // Z moves evenly: halfway round, half the depth.
        let half = lines[39];
        assert!((half[2] - (-40.0 / 79.0)).abs() < 1e-12);
    }

    #[test]
    fn an_end_off_the_circle_makes_a_spiral() {
        // Radius 1 at the start, 1.01 at the end, a quarter turn clockwise: the radius grows evenly.
        let lines = as_lines([1.0, 0.0, 0.0], [0.0, 0.0], [0.0, -1.01, 0.0], (PI / 2.0, true), 0.002, 100);
        let n = lines.len();
        let middle = lines[n / 2 - 1];
        let t = (n / 2) as f64 / n as f64;
        assert!((middle[0].hypot(middle[1]) - (1.0 + 0.01 * t)).abs() < 1e-9);
        assert!(middle[1] < 0.0);
        assert_eq!(as_lines([1.0, 0.0, 0.0], [0.0, 0.0], [0.0, -1.01, 0.0], (PI / 2.0, true), 1e-9, 5).len(), 5);
    }
}
