//! Plane geometry shared by the passes and the simulation: polar moves, arc
//! centres and sweeps here; curves given by control points (`spline`) and
//! their approximation by arcs and lines (`fit`) in their own modules.
//! Nothing here knows statements.

pub mod fit;
pub mod spline;

/// The in-plane step of a polar move: `radius` along `angle` degrees,
/// counter-clockwise from the plane's first axis.
pub fn polar_step(radius: f64, angle_degrees: f64) -> (f64, f64) {
    let (sin, cos) = angle_degrees.to_radians().sin_cos();
    (radius * cos, radius * sin)
}

/// `v` turned by `degrees` counter-clockwise: a coordinate system's XY
/// turned about its origin (G10 L2 R).
pub fn turn(v: [f64; 2], degrees: f64) -> [f64; 2] {
    let (sin, cos) = degrees.to_radians().sin_cos();
    [v[0] * cos - v[1] * sin, v[0] * sin + v[1] * cos]
}

/// Why an R-form arc has no centre.
#[derive(Debug, PartialEq)]
pub enum RadiusArcError {
    /// Start and end are the same point: a full circle needs I/J/K.
    FullCircle,
    /// The chord is longer than the diameter.
    TooShort { chord: f64 },
}

/// The centre of the arc from `start` to `end` with signed radius `r`
/// (R > 0 the short way, R < 0 the long way), turning counter-clockwise if
/// `ccw`. `tolerance` lets a chord exceed the diameter by rounding error.
pub fn centre_from_radius(
    start: (f64, f64),
    end: (f64, f64),
    r: f64,
    ccw: bool,
    tolerance: f64,
) -> Result<(f64, f64), RadiusArcError> {
    let (dx, dy) = (end.0 - start.0, end.1 - start.1);
    let chord = dx.hypot(dy);
    if chord <= tolerance * 1e-3 {
        return Err(RadiusArcError::FullCircle);
    }
    let half = chord / 2.0;
    if half > r.abs() + tolerance {
        return Err(RadiusArcError::TooShort { chord });
    }
    let height = (r * r - half * half).max(0.0).sqrt();
    // Unit normal to the left of the chord.
    let (nx, ny) = (-dy / chord, dx / chord);
    // A short counter-clockwise arc has its centre on the chord's left.
    let side = if ccw == (r > 0.0) { 1.0 } else { -1.0 };
    let mid = (start.0 + dx / 2.0, start.1 + dy / 2.0);
    Ok((mid.0 + side * height * nx, mid.1 + side * height * ny))
}

/// An end this close to its start's angle (radians) on the side the arc
/// turns towards is at it: rounding, not an arc of its own.
const SAME_ANGLE: f64 = 1e-9;

/// Where an arc about `centre` starts (radians from the plane's first axis)
/// and how far it turns (positive counter-clockwise) to reach `end`. An end
/// at the start's angle makes a full circle, as LinuxCNC turns one: whether
/// it is the start itself or off it along the radius (a spiral's end), or
/// past it by rounding ([`SAME_ANGLE`]).
pub fn arc_sweep(start: (f64, f64), end: (f64, f64), centre: (f64, f64), ccw: bool) -> (f64, f64) {
    use std::f64::consts::TAU;
    let radius = (start.0 - centre.0).hypot(start.1 - centre.1);
    let from = (start.1 - centre.1).atan2(start.0 - centre.0);
    let to = (end.1 - centre.1).atan2(end.0 - centre.0);
    let closed = (start.0 - end.0).hypot(start.1 - end.1) <= 1e-9 * radius.max(1.0);
    let turn = if ccw { to - from } else { from - to }.rem_euclid(TAU);
    let turn = if closed || turn <= SAME_ANGLE { TAU } else { turn };
    (from, if ccw { turn } else { -turn })
}

/// An arc as lines no further than `tolerance` from it, from `start` (not
/// included) to `end` (included) about `centre`, turning `sweep` radians
/// (positive counter-clockwise) in its plane (points are `[first, second,
/// normal]`): a spiral from the start's radius to the end's, as LinuxCNC
/// moves an arc whose end is off its circle, the radius and the normal axis
/// changing evenly with the angle. At most `most` lines.
pub fn arc_as_lines(
    start: [f64; 3],
    centre: [f64; 2],
    end: [f64; 3],
    sweep: f64,
    tolerance: f64,
    most: usize,
) -> Vec<[f64; 3]> {
    let from = (start[1] - centre[1]).atan2(start[0] - centre[0]);
    let radius = (start[0] - centre[0]).hypot(start[1] - centre[1]);
    let end_radius = (end[0] - centre[0]).hypot(end[1] - centre[1]);
    let largest = radius.max(end_radius);
    // A chord of angle a strays r(1 - cos(a/2)) from its circle.
    let step =
        if tolerance >= largest { std::f64::consts::FRAC_PI_2 } else { 2.0 * (1.0 - tolerance / largest).acos() };
    let count = ((sweep.abs() / step).ceil() as usize).clamp(1, most.max(1));
    (1..=count)
        .map(|i| {
            if i == count {
                return end;
            }
            let t = i as f64 / count as f64;
            let angle = from + sweep * t;
            let r = radius + (end_radius - radius) * t;
            [centre[0] + r * angle.cos(), centre[1] + r * angle.sin(), start[2] + (end[2] - start[2]) * t]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: (f64, f64), b: (f64, f64)) -> bool {
        (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12
    }

    #[test]
    fn polar_steps_turn_counter_clockwise_from_the_first_axis() {
        assert!(close(polar_step(2.0, 0.0), (2.0, 0.0)));
        assert!(close(polar_step(2.0, 90.0), (0.0, 2.0)));
        let (x, y) = polar_step(1.0, 30.0);
        assert!((x - 3f64.sqrt() / 2.0).abs() < 1e-12 && (y - 0.5).abs() < 1e-12);
    }

    #[test]
    fn radius_picks_the_short_or_long_arc_on_the_correct_side() {
        // Quarter circle about the origin from (1,0) to (0,1).
        let ccw_short = centre_from_radius((1.0, 0.0), (0.0, 1.0), 1.0, true, 1e-4).unwrap();
        assert!(close(ccw_short, (0.0, 0.0)));
        // The same points, clockwise the short way: centre at (1,1).
        let cw_short = centre_from_radius((1.0, 0.0), (0.0, 1.0), 1.0, false, 1e-4).unwrap();
        assert!(close(cw_short, (1.0, 1.0)));
        // Long way round flips the side.
        let ccw_long = centre_from_radius((1.0, 0.0), (0.0, 1.0), -1.0, true, 1e-4).unwrap();
        assert!(close(ccw_long, (1.0, 1.0)));
        let cw_long = centre_from_radius((1.0, 0.0), (0.0, 1.0), -1.0, false, 1e-4).unwrap();
        assert!(close(cw_long, (0.0, 0.0)));
    }

    #[test]
    fn arcs_sweep_the_way_they_turn() {
        use std::f64::consts::{FRAC_PI_2, PI, TAU};
        // From (1,0) to (0,1) about the origin: a quarter counter-clockwise, three quarters clockwise.
        let (from, sweep) = arc_sweep((1.0, 0.0), (0.0, 1.0), (0.0, 0.0), true);
        assert!(from.abs() < 1e-12 && (sweep - FRAC_PI_2).abs() < 1e-12);
        assert!((arc_sweep((1.0, 0.0), (0.0, 1.0), (0.0, 0.0), false).1 + 3.0 * FRAC_PI_2).abs() < 1e-12);
        assert!((arc_sweep((1.0, 0.0), (-1.0, 0.0), (0.0, 0.0), true).1 - PI).abs() < 1e-12);
        assert_eq!(arc_sweep((1.0, 0.0), (1.0, 0.0), (0.0, 0.0), false).1, -TAU);
    }

    #[test]
    fn an_end_at_the_starts_angle_makes_a_full_circle() {
        use std::f64::consts::TAU;
        // From 7.063 below the centre to 7.062 below it: the end is off the
        // start along the radius, at its angle. LinuxCNC turns a full
        // circle (spiralling in by 0.001); so does GRBL.
        assert_eq!(arc_sweep((0.0, -7.063), (0.0, -7.062), (0.0, 0.0), true).1, TAU);
        assert_eq!(arc_sweep((0.0, -7.063), (0.0, -7.064), (0.0, 0.0), false).1, -TAU);
        // Past the start by rounding, either way round.
        let (sin, cos) = (1e-12f64).sin_cos();
        assert_eq!(arc_sweep((2.0, 0.0), (2.0 * cos, 2.0 * sin), (0.0, 0.0), true).1, TAU);
        assert_eq!(arc_sweep((2.0, 0.0), (2.0 * cos, -2.0 * sin), (0.0, 0.0), false).1, -TAU);
        // Short of the start by as little: all but a full circle.
        assert!(TAU - arc_sweep((2.0, 0.0), (2.0 * cos, -2.0 * sin), (0.0, 0.0), true).1 < 1e-11);
        // A microradian past it is a short arc of its own.
        let (sin, cos) = (1e-6f64).sin_cos();
        assert!((arc_sweep((2.0, 0.0), (2.0 * cos, 2.0 * sin), (0.0, 0.0), true).1 - 1e-6).abs() < 1e-12);
    }

    #[test]
    fn radius_errors() {
        assert_eq!(centre_from_radius((0.0, 0.0), (0.0, 0.0), 1.0, true, 1e-4), Err(RadiusArcError::FullCircle));
        assert_eq!(
            centre_from_radius((0.0, 0.0), (3.0, 0.0), 1.0, true, 1e-4),
            Err(RadiusArcError::TooShort { chord: 3.0 })
        );
        // A half circle whose chord is the diameter plus rounding noise still works.
        let centre = centre_from_radius((0.0, 0.0), (2.00001, 0.0), 1.0, true, 1e-4).unwrap();
        assert!((centre.0 - 1.000005).abs() < 1e-9 && centre.1.abs() < 1e-9);
    }
}
