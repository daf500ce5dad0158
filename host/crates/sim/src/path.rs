//! The tool's path: translated statements (after pass 05) to geometric moves.
//!
//! A [`Walker`] follows the machine through the statement stream: where the
//! tool is, the active plane, and which tool is loaded. It turns each move
//! into a [`Move`] (a line or an arc from where the tool was), and each tool
//! change into a [`Step::Tool`].

use std::f64::consts::TAU;

use ger_core::diag::Span;
use ger_core::geom::arc_sweep;
use ger_core::statement::{Kind, Machine, MotionMode, Plane, Statement};

/// A point or a vector in machine coordinates.
pub type Point = glam::DVec3;

/// A piece of the tool's path, in machine coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    Line {
        from: Point,
        to: Point,
    },
    /// An arc (a helix when the normal axis moves) in `plane`.
    Arc {
        from: Point,
        to: Point,
        /// The centre, in the plane's two axes (the normal coordinate is unused).
        centre: Point,
        plane: Plane,
        radius: f64,
        /// The start angle, in the plane's axes (first to second is positive).
        start: f64,
        /// Signed: positive counter-clockwise (G03), negative clockwise (G02).
        sweep: f64,
    },
}

impl Segment {
    pub fn from(&self) -> Point {
        match *self {
            Segment::Line { from, .. } | Segment::Arc { from, .. } => from,
        }
    }

    pub fn to(&self) -> Point {
        match *self {
            Segment::Line { to, .. } | Segment::Arc { to, .. } => to,
        }
    }

    /// The point at `t` in [0, 1] along the segment.
    pub fn at(&self, t: f64) -> Point {
        match *self {
            Segment::Line { from, to } => from + t * (to - from),
            Segment::Arc { from, to, centre, plane, radius, start, sweep } => {
                let (a, b, n) = plane.axes();
                let angle = start + t * sweep;
                let mut p = Point::ZERO;
                p[a] = centre[a] + radius * angle.cos();
                p[b] = centre[b] + radius * angle.sin();
                p[n] = from[n] + t * (to[n] - from[n]);
                p
            }
        }
    }

    /// The length of the path (a helix's included).
    pub fn length(&self) -> f64 {
        match *self {
            Segment::Line { from, to } => from.distance(to),
            Segment::Arc { from, to, plane, radius, sweep, .. } => {
                let n = plane.axes().2;
                (radius * sweep).hypot(to[n] - from[n])
            }
        }
    }

    /// How many straight pieces follow this segment within `tolerance` (1 for a line).
    pub fn pieces(&self, tolerance: f64) -> usize {
        match *self {
            Segment::Line { .. } => 1,
            Segment::Arc { radius, sweep, .. } => {
                if radius <= tolerance {
                    return 1;
                }
                // The sagitta of a chord spanning `step` radians is r (1 - cos(step / 2)).
                let step = 2.0 * (1.0 - tolerance / radius).acos();
                ((sweep.abs() / step).ceil() as usize).clamp(1, 1 << 20)
            }
        }
    }

    /// The axis-aligned box the segment's points lie in.
    pub fn bounds(&self) -> (Point, Point) {
        let (from, to) = (self.from(), self.to());
        let (mut lo, mut hi) = (from.min(to), from.max(to));
        if let Segment::Arc { centre, plane, radius, start, sweep, .. } = *self {
            let (a, b, _) = plane.axes();
            // The extremes along the plane's axes that the arc passes.
            for k in 0..4 {
                let angle = k as f64 * TAU / 4.0;
                if passes(start, sweep, angle) {
                    let (axis, sign) = [(a, 1.0), (b, 1.0), (a, -1.0), (b, -1.0)][k];
                    let v = centre[axis] + sign * radius;
                    lo[axis] = lo[axis].min(v);
                    hi[axis] = hi[axis].max(v);
                }
            }
        }
        (lo, hi)
    }
}

/// Whether an arc from `start` through `sweep` radians passes `angle`.
pub fn passes(start: f64, sweep: f64, angle: f64) -> bool {
    let along = (sweep.signum() * (angle - start)).rem_euclid(TAU);
    along <= sweep.abs()
}

/// A move of the tool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    pub segment: Segment,
    pub rapid: bool,
    pub span: Span,
}

/// What a statement does to the tool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step {
    Move(Move),
    /// M06 Tw: tool `number` is loaded.
    Tool {
        number: u32,
        span: Span,
    },
}

/// Follows the machine through translated statements.
#[derive(Clone, Debug)]
pub struct Walker {
    position: Point,
    plane: Plane,
    mode: MotionMode,
}

impl Default for Walker {
    fn default() -> Walker {
        Walker::new()
    }
}

impl Walker {
    /// At machine zero, in G17, with no tool loaded.
    pub fn new() -> Walker {
        Walker { position: Point::ZERO, plane: Plane::XY, mode: MotionMode::Rapid }
    }

    pub fn position(&self) -> Point {
        self.position
    }

    /// What `statement` does; `None` for anything that moves nothing and changes no tool.
    pub fn step(&mut self, statement: &Statement) -> Option<Step> {
        match &statement.kind {
            Kind::Plane(plane) => {
                self.plane = *plane;
                None
            }
            Kind::Machine { code: Machine::ToolChange, t, .. } => {
                t.map(|number| Step::Tool { number, span: statement.span })
            }
            Kind::Motion(motion) => {
                self.mode = motion.mode.unwrap_or(self.mode);
                if !motion.moves() {
                    return None;
                }
                let from = self.position;
                let mut to = from;
                for axis in 0..3 {
                    if let Some(v) = motion.target.get(axis) {
                        to[axis] = v.value;
                    }
                }
                self.position = to;
                let segment = if self.mode.is_arc() {
                    self.arc(from, to, motion.centre.get(self.plane.axes().0), motion.centre.get(self.plane.axes().1))
                } else {
                    Segment::Line { from, to }
                };
                Some(Step::Move(Move { segment, rapid: self.mode == MotionMode::Rapid, span: statement.span }))
            }
            _ => None,
        }
    }

    fn arc(
        &self,
        from: Point,
        to: Point,
        i: Option<ger_core::statement::Value>,
        j: Option<ger_core::statement::Value>,
    ) -> Segment {
        let (a, b, _) = self.plane.axes();
        let mut centre = from;
        centre[a] += i.map_or(0.0, |v| v.value);
        centre[b] += j.map_or(0.0, |v| v.value);
        let radius = (from[a] - centre[a]).hypot(from[b] - centre[b]);
        if radius == 0.0 {
            return Segment::Line { from, to };
        }
        let ccw = self.mode == MotionMode::ArcCcw;
        let (start, sweep) = arc_sweep((from[a], from[b]), (to[a], to[b]), (centre[a], centre[b]), ccw);
        Segment::Arc { from, to, centre, plane: self.plane, radius, start, sweep }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ger_core::passes::testing;

    fn steps(text: &str) -> Vec<Step> {
        let mut walker = Walker::new();
        testing::statements(text).iter().filter_map(|s| walker.step(s)).collect()
    }

    fn close(a: Point, b: Point) -> bool {
        a.distance(b) < 1e-9
    }

    #[test]
    fn lines_start_where_the_tool_is() {
        let steps = steps("G20\nG00 X1 Y2\nG01 Z-1 F100\n");
        let Step::Move(first) = steps[0] else { panic!() };
        assert!(first.rapid);
        assert_eq!(first.segment, Segment::Line { from: Point::ZERO, to: Point::new(1.0, 2.0, 0.0) });
        let Step::Move(second) = steps[1] else { panic!() };
        assert!(!second.rapid);
        assert_eq!(second.segment, Segment::Line { from: Point::new(1.0, 2.0, 0.0), to: Point::new(1.0, 2.0, -1.0) });
    }

    #[test]
    fn arcs_turn_the_right_way_and_full_circles_close() {
        let steps = steps("G20\nG00 X1\nG03 X0 Y1 I-1 J0 F10\nG02 X0 Y1 I0 J-1 Z-1\n");
        let Step::Move(ccw) = steps[1] else { panic!() };
        let Segment::Arc { sweep, radius, .. } = ccw.segment else { panic!() };
        assert!((sweep - TAU / 4.0).abs() < 1e-12 && (radius - 1.0).abs() < 1e-12);
        assert!(close(ccw.segment.at(0.5), Point::new(0.5f64.sqrt(), 0.5f64.sqrt(), 0.0)));
        let Step::Move(circle) = steps[2] else { panic!() };
        let Segment::Arc { sweep, .. } = circle.segment else { panic!() };
        assert!((sweep + TAU).abs() < 1e-12);
        assert!(close(circle.segment.at(0.5), Point::new(0.0, -1.0, -0.5)));
        assert!((circle.segment.length() - (TAU).hypot(1.0)).abs() < 1e-9);
        let (lo, hi) = circle.segment.bounds();
        assert!(close(lo, Point::new(-1.0, -1.0, -1.0)) && close(hi, Point::new(1.0, 1.0, 0.0)));
    }

    #[test]
    fn tool_changes_are_steps() {
        assert_eq!(steps("M06 T3\n"), [Step::Tool { number: 3, span: Span::new(1, 1, 6) }]);
    }

    #[test]
    fn arcs_in_other_planes_use_that_planes_axes() {
        // G18: Z then X; an arc from X1 to X-1 through Z1 turns from Z to X... clockwise seen from +Y.
        let steps = steps("G20\nG00 X1\nG18\nG02 X-1 I-1 K0 F10\n");
        let Step::Move(arc) = steps[1] else { panic!() };
        let mid = arc.segment.at(0.5);
        assert!((mid[0]).abs() < 1e-9 && (mid[2].abs() - 1.0).abs() < 1e-9, "{mid:?}");
        assert_eq!(arc.segment.pieces(0.001), (std::f64::consts::PI / (2.0 * (1.0f64 - 0.001).acos())).ceil() as usize);
    }
}
