//! Offset geometry for cutter radius compensation, in the XY plane: the exact
//! offset of a line or an arc, and how the offsets of two moves join at the
//! corner between them.
//!
//! Everything here is pure arithmetic on points; the pass decides what to do
//! with the answers (which moves to write, which errors to report).

use std::f64::consts::{PI, TAU};

use crate::geom::arc_sweep;
use crate::statement::Side;

/// Below this, a length is rounding noise (machine units are inches or mm).
const NOISE: f64 = 1e-9;

/// LinuxCNC's tolerance for concave corners (`TOLERANCE_CONCAVE_CORNER`),
/// radians: a corner that turns back on itself to within this is rounded
/// like an outside corner.
const REVERSAL: f64 = 0.05;

/// A point or a vector in the plane (glam's: `perp_dot` is the z of the 3D
/// cross product, > 0 when the other turns left; `perp` a quarter turn
/// counter-clockwise).
pub type Point = glam::DVec2;

/// The unit normal on the tool's side of a path running along `tangent`.
pub fn normal(side: Side, tangent: Point) -> Point {
    match side {
        Side::Left => tangent.perp(),
        Side::Right => -tangent.perp(),
    }
}

/// `angle` brought into (-π, π].
fn principal(angle: f64) -> f64 {
    let a = angle.rem_euclid(TAU);
    if a > PI {
        a - TAU
    } else {
        a
    }
}

/// A move's path in the plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    Line {
        start: Point,
        end: Point,
    },
    /// `sweep` is the angle turned, in radians, >= 0; a full circle (2π)
    /// ends where it starts, which is why the angle is kept and not derived.
    Arc {
        start: Point,
        end: Point,
        centre: Point,
        ccw: bool,
        sweep: f64,
    },
}

/// An arc on the tool's side whose radius is not larger than the tool's:
/// the tool does not fit in it.
#[derive(Debug, PartialEq)]
pub struct TooTight {
    pub arc_radius: f64,
}

impl Segment {
    /// The arc from `start` to `end` about `centre`; a full circle when the
    /// end is at the start's angle (see [`arc_sweep`]).
    pub fn arc(start: Point, end: Point, centre: Point, ccw: bool) -> Segment {
        let (_, sweep) = arc_sweep(start.into(), end.into(), centre.into(), ccw);
        Segment::Arc { start, end, centre, ccw, sweep: sweep.abs() }
    }

    pub fn start(&self) -> Point {
        match *self {
            Segment::Line { start, .. } | Segment::Arc { start, .. } => start,
        }
    }

    pub fn end(&self) -> Point {
        match *self {
            Segment::Line { end, .. } | Segment::Arc { end, .. } => end,
        }
    }

    /// How far the path runs.
    pub fn length(&self) -> f64 {
        match *self {
            Segment::Line { start, end } => start.distance(end),
            Segment::Arc { start, centre, sweep, .. } => start.distance(centre) * sweep,
        }
    }

    /// The unit direction of travel at `p`, a point of the path.
    fn tangent_at(&self, p: Point) -> Point {
        match *self {
            Segment::Line { start, end } => (end - start).normalize(),
            Segment::Arc { centre, ccw, .. } => {
                let t = (p - centre).perp().normalize();
                if ccw {
                    t
                } else {
                    -t
                }
            }
        }
    }

    pub fn start_tangent(&self) -> Point {
        self.tangent_at(self.start())
    }

    pub fn end_tangent(&self) -> Point {
        self.tangent_at(self.end())
    }

    /// The path of the centre of a tool of radius `r` kept on `side` of this
    /// one: a parallel line, or an arc about the same centre with its radius
    /// grown or shrunk by `r`.
    pub fn offset(&self, side: Side, r: f64) -> Result<Segment, TooTight> {
        let shift = |p: Point| p + normal(side, self.tangent_at(p)) * r;
        match *self {
            Segment::Line { start, end } => Ok(Segment::Line { start: shift(start), end: shift(end) }),
            Segment::Arc { start, end, centre, ccw, sweep } => {
                // Left of a counter-clockwise arc is towards its centre.
                let inside = ccw == (side == Side::Left);
                let arc_radius = start.distance(centre);
                if inside && arc_radius - r <= NOISE {
                    return Err(TooTight { arc_radius });
                }
                Ok(Segment::Arc { start: shift(start), end: shift(end), centre, ccw, sweep })
            }
        }
    }

    /// This path made to run from `from` to `to`, two points on its line or
    /// circle near its ends (a corner may cut it short or, rarely, lengthen
    /// it); `None` when that would run it backwards, which means the tool
    /// would cut into the part.
    pub fn trimmed(&self, from: Point, to: Point) -> Option<Segment> {
        match *self {
            Segment::Line { start, end } => {
                let along = (to - from).dot((end - start).normalize());
                (along >= -NOISE).then_some(Segment::Line { start: from, end: to })
            }
            Segment::Arc { start, end, centre, ccw, sweep } => {
                // Angles turned in the arc's own direction.
                let turn = |p: Point, q: Point| {
                    let a = principal((q - centre).to_angle() - (p - centre).to_angle());
                    if ccw {
                        a
                    } else {
                        -a
                    }
                };
                let sweep = sweep - turn(start, from) + turn(end, to);
                (sweep * start.distance(centre) >= -NOISE).then_some(Segment::Arc {
                    start: from,
                    end: to,
                    centre,
                    ccw,
                    sweep: sweep.max(0.0),
                })
            }
        }
    }

    /// Whether `p`, a point of this path's line or circle, lies on the path
    /// itself, between its ends.
    fn passes_through(&self, p: Point) -> bool {
        match *self {
            Segment::Line { start, end } => {
                let length = start.distance(end);
                let along = (p - start).dot(end - start) / length.max(NOISE);
                (-NOISE..=length + NOISE).contains(&along)
            }
            Segment::Arc { start, centre, ccw, sweep, .. } => {
                let radius = start.distance(centre).max(NOISE);
                let turned = (p - centre).to_angle() - (start - centre).to_angle();
                let turned = (if ccw { turned } else { -turned }).rem_euclid(TAU);
                let slack = NOISE / radius;
                turned <= sweep + slack || turned >= TAU - slack
            }
        }
    }

    /// Where the full line or circle of this path crosses the other's: none,
    /// one or two points.
    fn crossings(&self, other: &Segment) -> [Option<Point>; 2] {
        match (*self, *other) {
            (Segment::Line { start: p, end: p2 }, Segment::Line { start: q, end: q2 }) => {
                let (d, e) = (p2 - p, q2 - q);
                let det = d.perp_dot(e);
                if det.abs() <= NOISE * d.length() * e.length() {
                    return [None, None];
                }
                [Some(p + d * ((q - p).perp_dot(e) / det)), None]
            }
            (Segment::Line { start, end }, Segment::Arc { centre, start: on, .. })
            | (Segment::Arc { centre, start: on, .. }, Segment::Line { start, end }) => {
                let d = (end - start).normalize();
                let foot = start + d * (centre - start).dot(d);
                let radius = on.distance(centre);
                let h2 = radius * radius - foot.distance(centre).powi(2);
                if h2 < 0.0 {
                    return [None, None];
                }
                let h = h2.sqrt();
                [Some(foot - d * h), Some(foot + d * h)]
            }
            (Segment::Arc { centre: c1, start: on1, .. }, Segment::Arc { centre: c2, start: on2, .. }) => {
                let (r1, r2) = (on1.distance(c1), on2.distance(c2));
                let d = c1.distance(c2);
                if d <= NOISE {
                    return [None, None];
                }
                // Along the line of centres to the chord, then either way along it.
                let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
                let h2 = r1 * r1 - a * a;
                if h2 < 0.0 {
                    return [None, None];
                }
                let u = (c2 - c1) * (1.0 / d);
                let mid = c1 + u * a;
                let h = h2.sqrt();
                [Some(mid + u.perp() * h), Some(mid - u.perp() * h)]
            }
        }
    }
}

/// How the tool gets from the offset of one move to the offset of the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Corner {
    /// The offsets meet (the moves continue each other smoothly): the first
    /// ends where the second starts.
    Smooth,
    /// An outside corner: the tool goes round the corner point on an arc of
    /// its own radius, from the end of the first offset to the start of the
    /// second.
    Around { from: Point, to: Point, ccw: bool },
    /// An inside corner: both offsets are cut short where they cross.
    Cut(Point),
}

/// The corner at `at` (the programmed point where one move ends and the next
/// starts) between `a` and `b`, the offsets of the two moves for a tool on
/// `side`. Offsets whose ends are within `gap` of each other
/// join as they are: the corner is too small to matter. `None`: an inside
/// corner whose offsets never cross, so no tool position touches both moves
/// without cutting into one of them.
pub fn corner(at: Point, a: &Segment, b: &Segment, side: Side, gap: f64) -> Option<Corner> {
    if a.end().distance(b.start()) <= gap {
        return Some(Corner::Smooth);
    }
    let (before, after) = (a.end_tangent(), b.start_tangent());
    let towards_tool = match side {
        Side::Left => before.perp_dot(after),
        Side::Right => -before.perp_dot(after),
    };
    // A turn towards the tool's side is an inside corner. A move that turns
    // back on the one before, to within REVERSAL of a full reversal either
    // way, is judged as LinuxCNC judges it (its concave-corner tolerance):
    // an inside corner where the tool runs outside the arc that follows, else
    // outside, the tool going round the corner's point (round the end of a
    // slot).
    let near_reversal = towards_tool.atan2(before.dot(after)).abs() > PI - REVERSAL;
    let inside = if near_reversal {
        matches!(*b, Segment::Arc { ccw, .. } if ccw != (side == Side::Left))
    } else {
        towards_tool > NOISE
    };
    if !inside {
        return Some(Corner::Around { from: a.end(), to: b.start(), ccw: side == Side::Right });
    }
    // Where the offsets themselves cross, if they do: both cut short. Else
    // where their lines or circles do, nearest the corner.
    let crossings = a.crossings(b);
    let nearest =
        |points: &mut dyn Iterator<Item = Point>| points.min_by(|p, q| p.distance(at).total_cmp(&q.distance(at)));
    let on_both =
        nearest(&mut crossings.into_iter().flatten().filter(|p| a.passes_through(*p) && b.passes_through(*p)));
    Some(Corner::Cut(on_both.or_else(|| nearest(&mut crossings.into_iter().flatten()))?))
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: f64 = 0.25;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    fn line(x0: f64, y0: f64, x1: f64, y1: f64) -> Segment {
        Segment::Line { start: p(x0, y0), end: p(x1, y1) }
    }

    fn arc(start: (f64, f64), end: (f64, f64), centre: (f64, f64), ccw: bool) -> Segment {
        Segment::arc(p(start.0, start.1), p(end.0, end.1), p(centre.0, centre.1), ccw)
    }

    fn near(a: Point, b: Point) -> bool {
        a.distance(b) < 1e-12
    }

    #[track_caller]
    fn assert_near(a: Point, b: (f64, f64)) {
        assert!(near(a, p(b.0, b.1)), "{a:?} is not ({}, {})", b.0, b.1);
    }

    /// The corner at `at` between two programmed moves, offset by R.
    fn join(a: &Segment, b: &Segment, side: Side) -> Option<Corner> {
        let at = a.end();
        corner(at, &a.offset(side, R).unwrap(), &b.offset(side, R).unwrap(), side, 1e-6)
    }

    #[track_caller]
    fn assert_cut(corner: Option<Corner>, expected: (f64, f64)) {
        match corner {
            Some(Corner::Cut(x)) => assert_near(x, expected),
            other => panic!("expected a cut at {expected:?}, got {other:?}"),
        }
    }

    #[track_caller]
    fn assert_around(corner: Option<Corner>, from: (f64, f64), to: (f64, f64), ccw: bool) {
        match corner {
            Some(Corner::Around { from: f, to: t, ccw: c }) => {
                assert_near(f, from);
                assert_near(t, to);
                assert_eq!(c, ccw, "direction");
            }
            other => panic!("expected an arc round the corner, got {other:?}"),
        }
    }

    #[test]
    fn lines_shift_to_the_tool_side() {
        // Along +X, left is +Y and right is -Y.
        let l = line(0.0, 0.0, 2.0, 0.0);
        assert_eq!(l.offset(Side::Left, R), Ok(line(0.0, 0.25, 2.0, 0.25)));
        assert_eq!(l.offset(Side::Right, R), Ok(line(0.0, -0.25, 2.0, -0.25)));
        // Along the diagonal (1,1)/√2, left is (-1,1)/√2.
        let d = line(0.0, 0.0, 1.0, 1.0).offset(Side::Left, R).unwrap();
        let k = R / 2f64.sqrt();
        assert_near(d.start(), (-k, k));
        assert_near(d.end(), (1.0 - k, 1.0 + k));
    }

    #[test]
    fn arcs_keep_their_centre_and_grow_or_shrink() {
        // Quarter circle of radius 1 about the origin, (1,0) to (0,1), CCW.
        let a = arc((1.0, 0.0), (0.0, 1.0), (0.0, 0.0), true);
        assert!((a.length() - PI / 2.0).abs() < 1e-12);
        // Left of a CCW arc is inside: radius 0.75.
        let left = a.offset(Side::Left, R).unwrap();
        assert_near(left.start(), (0.75, 0.0));
        assert_near(left.end(), (0.0, 0.75));
        let right = a.offset(Side::Right, R).unwrap();
        assert_near(right.start(), (1.25, 0.0));
        assert_near(right.end(), (0.0, 1.25));
        // The same arc clockwise (from (0,1) to (1,0)): now right is inside.
        let cw = arc((0.0, 1.0), (1.0, 0.0), (0.0, 0.0), false);
        assert_near(cw.offset(Side::Right, R).unwrap().start(), (0.0, 0.75));
        assert_near(cw.offset(Side::Left, R).unwrap().end(), (1.25, 0.0));
    }

    #[test]
    fn a_full_circle_turns_all_the_way() {
        let c = arc((1.0, 0.0), (1.0, 0.0), (0.0, 0.0), false);
        assert!(matches!(c, Segment::Arc { sweep, .. } if sweep == TAU));
        let o = c.offset(Side::Left, R).unwrap();
        assert_near(o.start(), (1.25, 0.0));
        assert_near(o.end(), (1.25, 0.0));
    }

    #[test]
    fn the_tool_must_fit_inside_an_arc() {
        let small = arc((0.2, 0.0), (0.0, 0.2), (0.0, 0.0), true);
        assert_eq!(small.offset(Side::Left, R), Err(TooTight { arc_radius: 0.2 }));
        // Exactly the tool's radius is not enough either: the tool would pivot.
        let equal = arc((0.25, 0.0), (0.0, 0.25), (0.0, 0.0), true);
        assert!(equal.offset(Side::Left, R).is_err());
        // Outside the arc any radius works.
        assert_near(small.offset(Side::Right, R).unwrap().start(), (0.45, 0.0));
    }

    #[test]
    fn line_line_outside_corners_go_round_the_corner_point() {
        // Along +X to (1,0), then up: a left turn; with the tool right, outside.
        let a = line(0.0, 0.0, 1.0, 0.0);
        let b = line(1.0, 0.0, 1.0, 1.0);
        assert_around(join(&a, &b, Side::Right), (1.0, -0.25), (1.25, 0.0), true);
        // Along +X, then down: a right turn; with the tool left, outside, clockwise.
        let down = line(1.0, 0.0, 1.0, -1.0);
        assert_around(join(&a, &down, Side::Left), (1.0, 0.25), (1.25, 0.0), false);
    }

    #[test]
    fn line_line_inside_corners_cut_where_the_offsets_cross() {
        // Along +X, then up, tool left: the offsets y = 0.25 and x = 0.75 cross.
        let a = line(0.0, 0.0, 1.0, 0.0);
        let b = line(1.0, 0.0, 1.0, 1.0);
        assert_cut(join(&a, &b, Side::Left), (0.75, 0.25));
        // Along +X, then down, tool right: y = -0.25 and x = 0.75.
        let down = line(1.0, 0.0, 1.0, -1.0);
        assert_cut(join(&a, &down, Side::Right), (0.75, -0.25));
        // A 45° turn left, tool left: y = 0.25 meets the diagonal's offset
        // x - y = 1 - R√2, at x = 1.25 - 0.25√2.
        let diagonal = line(1.0, 0.0, 2.0, 1.0);
        assert_cut(join(&a, &diagonal, Side::Left), (1.25 - R * 2f64.sqrt(), 0.25));
    }

    #[test]
    fn a_reversal_goes_round_the_end() {
        let a = line(0.0, 0.0, 1.0, 0.0);
        let back = line(1.0, 0.0, 0.0, 0.0);
        assert_around(join(&a, &back, Side::Left), (1.0, 0.25), (1.0, -0.25), false);
        assert_around(join(&a, &back, Side::Right), (1.0, -0.25), (1.0, 0.25), true);
    }

    #[test]
    fn a_turn_back_within_linuxcncs_tolerance_goes_round_the_point() {
        // Along -X into (0,0), then back out heading 2° above +X: a 178° turn
        // to the right, towards a tool on the right (above the line, at y = R).
        // rs274 moves so on linuxcnc-interp/crazy-paths, line 106.
        let a = line(10.0, 0.0, 0.0, 0.0);
        let (sin, cos) = 2f64.to_radians().sin_cos();
        // A clockwise arc of radius 3 leaving (0,0) along (cos, sin): its
        // centre is 3 to the right of that, and the tool runs inside it.
        let inside_arc = arc((0.0, 0.0), (3.0 * sin - 3.0, -3.0 * cos), (3.0 * sin, -3.0 * cos), false);
        // LinuxCNC goes round the point, counter-clockwise, to R along the
        // arc's radius towards its centre.
        assert_around(join(&a, &inside_arc, Side::Right), (0.0, R), (R * sin, -R * cos), true);
        // With the tool on the left it runs outside that arc: an inside corner,
        // cut where the offsets (y = -R, and the circle of radius 3 + R) cross
        // on both, before the corner (the other crossing is past the line's end).
        let x = 3.0 * sin + ((3.0 + R).powi(2) - (3.0 * cos - R).powi(2)).sqrt();
        assert_cut(join(&a, &inside_arc, Side::Left), (x, -R));
        // So does a line back out.
        let back = line(0.0, 0.0, 5.0 * cos, 5.0 * sin);
        assert_around(join(&a, &back, Side::Right), (0.0, R), (R * sin, -R * cos), true);
        // Past the tolerance (a 170° turn) it is an inside corner, whose offsets cross far back along the line.
        let (sin, cos) = 10f64.to_radians().sin_cos();
        let steep = line(0.0, 0.0, 5.0 * cos, 5.0 * sin);
        // The offsets, y = R and the line at R from the one through (0,0) along (cos, sin), cross at x = R (1 + cos) / sin.
        assert_cut(join(&a, &steep, Side::Right), (R * (1.0 + cos) / sin, R));
    }

    #[test]
    fn tangent_continuations_have_no_corner() {
        // A line along +X into a CCW quarter circle about (1,1): tangent at (1,0).
        let a = line(0.0, 0.0, 1.0, 0.0);
        let b = arc((1.0, 0.0), (2.0, 1.0), (1.0, 1.0), true);
        assert_eq!(join(&a, &b, Side::Left), Some(Corner::Smooth));
        assert_eq!(join(&a, &b, Side::Right), Some(Corner::Smooth));
        // Two collinear lines.
        assert_eq!(join(&a, &line(1.0, 0.0, 3.0, 0.0), Side::Left), Some(Corner::Smooth));
        // A CW arc into a CCW one (an S bend), tangent at (1,0) going +X.
        let s1 = arc((0.0, -1.0), (1.0, 0.0), (1.0, -1.0), false);
        let s2 = arc((1.0, 0.0), (2.0, 1.0), (1.0, 1.0), true);
        assert_eq!(join(&s1, &s2, Side::Right), Some(Corner::Smooth));
    }

    #[test]
    fn line_arc_corners() {
        // Along +X to (1,0), then a CCW half circle about (2,0) to (3,0), which
        // starts going -Y: a right turn.
        let a = line(0.0, 0.0, 1.0, 0.0);
        let b = arc((1.0, 0.0), (3.0, 0.0), (2.0, 0.0), true);
        // Tool left: outside, clockwise round (1,0) from (1,0.25) to the
        // arc's offset start: left of the arc is inside, radius 0.75, at (1.25,0).
        assert_around(join(&a, &b, Side::Left), (1.0, 0.25), (1.25, 0.0), false);
        // Tool right: inside. The offset line y = -0.25 crosses the circle of
        // radius 1.25 about (2,0) at x = 2 - √(1.25² - 0.25²) = 2 - √1.5.
        assert_cut(join(&a, &b, Side::Right), (2.0 - 1.5f64.sqrt(), -0.25));
    }

    #[test]
    fn arc_line_corners() {
        // A CCW quarter circle about the origin from (1,0) to (0,1) ends going
        // -X; then a line going -Y back down: a left turn.
        let a = arc((1.0, 0.0), (0.0, 1.0), (0.0, 0.0), true);
        let b = line(0.0, 1.0, 0.0, 0.0);
        // Tool left: inside. Circle of radius 0.75 meets x = 0.25 (left of -Y
        // is +X) at y = √(0.75² - 0.25²) = √0.5.
        assert_cut(join(&a, &b, Side::Left), (0.25, 0.5f64.sqrt()));
        // Tool right: outside, counter-clockwise from (0,1.25) to (-0.25,1).
        assert_around(join(&a, &b, Side::Right), (0.0, 1.25), (-0.25, 1.0), true);
    }

    #[test]
    fn arc_arc_corners() {
        // CCW about (-1,0) from (-1,-1) to (0,0), ending going +Y; then CW about
        // (1,0) from (0,0) to (1,1), starting going +Y: tangent (an S bend).
        let a = arc((-1.0, -1.0), (0.0, 0.0), (-1.0, 0.0), true);
        let b = arc((0.0, 0.0), (1.0, 1.0), (1.0, 0.0), false);
        assert_eq!(join(&a, &b, Side::Left), Some(Corner::Smooth));

        // A real corner: then CCW about (0,1) from (0,0) to (1,1), starting
        // going +X: a right turn.
        let b = arc((0.0, 0.0), (1.0, 1.0), (0.0, 1.0), true);
        // Tool left (inside both circles): outside corner, clockwise round
        // (0,0) from (-0.25,0) to (0,0.25).
        assert_around(join(&a, &b, Side::Left), (-0.25, 0.0), (0.0, 0.25), false);
        // Tool right: inside. The circles of radius 1.25 about (-1,0) and (0,1)
        // cross on y = -x (equal radii): (x+1)² + x² = 1.5625, that is
        // 2x² + 2x - 0.5625 = 0; the root near the corner is the positive one.
        let x = (-2.0 + (4.0f64 + 8.0 * 0.5625).sqrt()) / 4.0;
        assert_cut(join(&a, &b, Side::Right), (x, -x));
    }

    #[test]
    fn inside_corners_that_never_cross_are_refused() {
        // Along +X to (1,0), then a left turn into a CCW quarter circle of
        // radius 0.3 about (0.7,0), up to (0.7,0.3). Tool left, inside both:
        // the line's offset y = 0.25 and the arc's, a circle of radius 0.05
        // about (0.7,0), never meet. The tool cannot touch the arc without
        // cutting into the line.
        let a = line(0.0, 0.0, 1.0, 0.0);
        let b = arc((1.0, 0.0), (0.7, 0.3), (0.7, 0.0), true);
        assert_eq!(join(&a, &b, Side::Left), None);
    }

    #[test]
    fn trimming_keeps_direction_or_says_backwards() {
        let l = line(0.0, 0.0, 1.0, 0.0);
        assert_eq!(l.trimmed(p(0.25, 0.0), p(0.75, 0.0)), Some(line(0.25, 0.0, 0.75, 0.0)));
        assert_eq!(l.trimmed(p(0.75, 0.0), p(0.25, 0.0)), None);
        // A CCW quarter about the origin cut to the middle 30°..60°.
        let a = arc((1.0, 0.0), (0.0, 1.0), (0.0, 0.0), true);
        let (s, c) = (0.5, 3f64.sqrt() / 2.0);
        match a.trimmed(p(c, s), p(s, c)) {
            Some(Segment::Arc { sweep, ccw: true, .. }) => assert!((sweep - PI / 6.0).abs() < 1e-12),
            other => panic!("{other:?}"),
        }
        // Start cut past the end: backwards.
        assert_eq!(a.trimmed(p(s, c), p(c, s)), None);
        // A full circle cut 30° short at its end still turns 330°.
        let full = arc((1.0, 0.0), (1.0, 0.0), (0.0, 0.0), true);
        match full.trimmed(p(1.0, 0.0), p(c, -s)) {
            Some(Segment::Arc { sweep, .. }) => assert!((sweep - 11.0 * PI / 6.0).abs() < 1e-12),
            other => panic!("{other:?}"),
        }
    }
}
