//! Pass 05: cutter radius compensation. G41/G42 put the tool left/right of
//! the programmed path by its radius; this pass writes the path of the tool's
//! centre instead, so the output runs on a machine without G40/G41/G42.
//!
//! - The radius is half the diameter in the tool table: of the tool M06 last
//!   loaded (tool 1 before any), or of entry w with `G41 Dw`.
//! - Entry (the manual's way): the tool steps out by the radius,
//!   perpendicular to the start of the first move in the plane after G41/G42,
//!   so that move is cut with the offset from its start. Z moves between the
//!   two run before the step, where the tool is.
//! - Lines and arcs (helices too: Z passes through) are offset exactly. At a
//!   corner, an outside turn goes round the corner point on an arc of the
//!   tool's radius (a straight G00 when the next move is a rapid, as a rapid
//!   has no feed for an arc); an inside turn cuts both offsets where they
//!   cross.
//! - Exit: after G40 the next move in the plane goes from the offset path to
//!   its programmed end (it must be straight).
//! - What the pass writes is rounded to the output's resolution, and offset
//!   moves or corners shorter than that are left out.
//!
//! To know how a move ends, the pass must see the next move in the plane, so
//! it holds one move back, with the statements that follow it (Z moves,
//! M codes, ...) until that next move comes: memory is one move and at most
//! [`MAX_HELD`] statements, however long the program.

mod geometry;

use std::collections::VecDeque;
use std::sync::Arc;

use super::{Out, Pass};
use crate::config::Config;
use crate::diag::{Diagnostic, Origin, Span};
use crate::statement::{Axes, Dialect, Kind, Machine, Motion, MotionMode, Plane, Side, Statement, Value};
use geometry::{Corner, Point, Segment};

/// How many statements may wait behind a held move for the next move in the
/// plane; a bound on the pass's memory.
pub const MAX_HELD: usize = 1000;

#[derive(Clone, Copy, Debug)]
struct Comp {
    side: Side,
    radius: f64,
}

/// What the pass needs of a move, read as it comes in.
struct Step {
    mode: MotionMode,
    /// The programmed end.
    end: Point,
    /// Whether X or Y is written.
    in_plane: bool,
    /// `None` for a straight move of no length in the plane.
    path: Option<Segment>,
    z: Option<Value>,
    feed: Option<Value>,
}

/// A move whose end waits on the next move: where it ends depends on the
/// corner between them.
struct Held {
    /// The move as programmed: its line and call chain, for what it makes.
    statement: Statement,
    mode: MotionMode,
    z: Option<Value>,
    feed: Option<Value>,
    /// The programmed end, the corner point.
    corner: Point,
    /// The exact offset of the programmed move, before any corner cuts it.
    offset: Segment,
    /// Where the tool starts it (the offset's start, or a corner's cut).
    start: Point,
}

enum State {
    Off,
    /// G41/G42 seen; the step out waits for the first move in the plane.
    // Boxed, so that the state moves cheaply: it changes hands on every move.
    Entering {
        comp: Comp,
        at: Box<Statement>,
    },
    On {
        comp: Comp,
        held: Box<Held>,
    },
    /// G40 seen: the tool is still off the programmed path.
    Leaving,
}

pub struct CutterComp {
    /// Tool numbers and radii, in machine units.
    radii: Vec<(u32, f64)>,
    tool: u32,
    plane: Plane,
    /// The programmed position, in machine coordinates.
    position: [f64; 3],
    state: State,
    /// Statements that came after the held move, in order.
    waiting: VecDeque<Statement>,
    /// The last G40/G41/G42, to catch two on one line.
    last_code: Option<(Span, Option<Arc<Origin>>, &'static str)>,
    /// A feed that belonged to a move dropped as too short to write, for the
    /// next feed move written.
    feed_carried: Option<Value>,
    /// The output's resolution: gaps and moves below it are not written.
    resolution: f64,
    /// How the first move after G41/G42 enters: the manual's way, or LinuxCNC's.
    dialect: Dialect,
}

impl CutterComp {
    pub fn new(config: &Config) -> CutterComp {
        CutterComp {
            radii: config.tools.iter().map(|t| (t.number, t.diameter / 2.0)).collect(),
            tool: 1,
            plane: Plane::XY,
            position: [0.0; 3],
            state: State::Off,
            waiting: VecDeque::new(),
            last_code: None,
            feed_carried: None,
            resolution: 10f64.powi(-(config.units.decimals() as i32)),
            dialect: config.dialect.name,
        }
    }

    fn radius(&self, entry: u32) -> Option<f64> {
        self.radii.iter().find(|(n, _)| *n == entry).map(|(_, r)| *r)
    }

    fn is_on(&self) -> bool {
        matches!(self.state, State::Entering { .. } | State::On { .. })
    }

    /// Writes a statement, or keeps it behind the held move.
    fn pass(&mut self, statement: Statement, out: &mut Out) {
        if let State::On { comp, .. } = self.state {
            if self.waiting.len() >= MAX_HELD {
                let message = format!(
                    "more than {MAX_HELD} statements between two moves in the XY plane with cutter radius compensation on"
                );
                let help = "ger holds them until the next move shows how the last one ends; cancel the compensation (G40) around them";
                out.error(&statement, Diagnostic::error(statement.span, message).with_help(help));
                self.end_held(out);
                self.state = State::Entering { comp, at: Box::new(statement.clone()) };
            } else {
                self.waiting.push_back(statement);
                return;
            }
        }
        self.write(statement, out);
    }

    /// Writes a statement; a feed move gets the feed of a move dropped before it.
    fn write(&mut self, mut statement: Statement, out: &mut Out) {
        if let Kind::Motion(m) = &mut statement.kind {
            if m.mode != Some(MotionMode::Rapid) && m.feed.is_none() {
                m.feed = self.feed_carried.take();
            }
        }
        out.push(statement);
    }

    /// Writes a move along the tool's path, made by `statement`.
    fn write_move(&mut self, statement: &Statement, motion: Motion, out: &mut Out) {
        self.write(moving(statement, motion), out);
    }

    /// `value` as it will be written, rounded to the output's resolution:
    /// the pass hands on what the machine will get, so that an arc's centre
    /// is measured from where the tool will really be. (Round numbers are
    /// also the emitter's fast path: unrounded ones made formatting a third
    /// of the cost of compensation.)
    fn snap(&self, value: f64) -> f64 {
        (value / self.resolution).round() * self.resolution
    }

    fn value(&self, statement: &Statement, value: f64) -> Option<Value> {
        Some(Value { value: self.snap(value), span: statement.span })
    }

    /// A straight move to `to`, at the Z the tool is at unless `z` says.
    fn line_to(&self, statement: &Statement, mode: MotionMode, to: Point, z: Option<Value>) -> Motion {
        Motion {
            mode: Some(mode),
            target: Axes { x: self.value(statement, to.x), y: self.value(statement, to.y), z },
            ..Motion::default()
        }
    }

    /// Turns G41/G42 on: checks, then waits for the first move to step out.
    fn comp_on(&mut self, statement: Statement, side: Side, radius: Radius, out: &mut Out) {
        let code = if side == Side::Left { "G41" } else { "G42" };
        let refuse = |out: &mut Out, message: String, help: &str| {
            out.error(&statement, Diagnostic::error(statement.span, message).with_help(help));
        };
        if self.plane != Plane::XY {
            let message =
                format!("cannot turn cutter radius compensation on out of the XY plane ({} is on)", self.plane.code());
            return refuse(out, message, "compensation works in the XY plane: select it with G17 first");
        }
        if self.is_on() {
            return refuse(
                out,
                format!("cannot turn cutter radius compensation on ({code}) when it is already on"),
                "cancel it with G40 first, then turn it on again (to change side or tool)",
            );
        }
        let d = match radius {
            // A cutter of no size (LinuxCNC's G41.1 D0) cuts the path as written.
            Radius::Given(radius) if radius <= 0.0 => return,
            Radius::Given(radius) => {
                self.state = State::Entering { comp: Comp { side, radius }, at: Box::new(statement) };
                return;
            }
            Radius::FromTable(d) => d,
        };
        // D0 is "no tool" (LinuxCNC): a radius of zero, so the path is cut as written.
        if d == Some(0) {
            return;
        }
        let entry = d.unwrap_or(self.tool);
        let Some(radius) = self.radius(entry) else {
            let (message, help) = match d {
                Some(d) => (
                    format!("tool table entry {d} (D{d}) does not exist"),
                    "D names a tool in the tool table (the [[tools]] of ger.toml) whose radius to use".to_string(),
                ),
                None => (
                    format!("the loaded tool, T{entry}, is not in the tool table: its radius is unknown"),
                    format!("add tool {entry} to the [[tools]] of ger.toml, or name an entry with {code} D<tool>"),
                ),
            };
            return refuse(out, message, &help);
        };
        self.state = State::Entering { comp: Comp { side, radius }, at: Box::new(statement) };
    }

    /// G40: the held move ends on its own offset; the next move leaves it.
    fn comp_off(&mut self, out: &mut Out) {
        match self.state {
            State::Off | State::Leaving => {}
            State::Entering { .. } => self.state = State::Off,
            State::On { .. } => {
                self.end_held(out);
                self.state = State::Leaving;
            }
        }
    }

    /// Checks for a second G40/G41/G42 on the line of the last one.
    fn one_per_line(&mut self, statement: &Statement, code: &'static str, out: &mut Out) -> bool {
        let seen = self.last_code.replace((statement.span, statement.origin.clone(), code));
        match seen {
            Some((span, origin, first))
                if span.line == statement.span.line && span.col < statement.span.col && origin == statement.origin =>
            {
                let message = format!("{first} and {code} on one line: they are codes of the same group");
                let help = "only one of G40, G41 and G42 may be used on a line";
                out.error(statement, Diagnostic::error(statement.span, message).with_help(help));
                false
            }
            _ => true,
        }
    }

    /// The held move ends on its own offset, perpendicular to its end, and
    /// what waited behind it is written.
    fn end_held(&mut self, out: &mut Out) {
        let state = std::mem::replace(&mut self.state, State::Off);
        if let State::On { held, .. } = state {
            let end = held.offset.end();
            self.write_held(&held, end, None, out);
        }
        while let Some(statement) = self.waiting.pop_front() {
            self.write(statement, out);
        }
    }

    /// Writes the held move along its offset from its start to `end`, or
    /// reports a gouge if that runs backwards. `next` is the line of the move
    /// that cut it short, for the message.
    fn write_held(&mut self, held: &Held, end: Point, next: Option<u32>, out: &mut Out) {
        let Some(path) = held.offset.trimmed(held.start, end) else {
            let message = "cutter radius compensation would gouge the part: this move is too short for the tool";
            let help = match next {
                Some(line) => format!(
                    "at the inside corner with line {line} the tool's path would have to run this move backwards, \
                     cutting into the part; lengthen the move or use a smaller tool"
                ),
                None => "the tool's path would run this move backwards; lengthen it or use a smaller tool".to_string(),
            };
            out.error(&held.statement, Diagnostic::error(held.statement.span, message).with_help(help));
            return;
        };
        let statement = &held.statement;
        let motion = match path {
            // An arc too short to write as one (it would read back as a
            // full circle) is as good as straight.
            Segment::Arc { start, centre, ccw, .. } if path.length() >= 2.0 * self.resolution => Motion {
                mode: Some(if ccw { MotionMode::ArcCcw } else { MotionMode::ArcCw }),
                target: Axes { x: self.value(statement, end.x), y: self.value(statement, end.y), z: held.z },
                centre: Axes {
                    x: self.value(statement, centre.x - self.snap(start.x)),
                    y: self.value(statement, centre.y - self.snap(start.y)),
                    z: None,
                },
                radius: None,
                feed: held.feed,
                turns: None,
            },
            _ if path.length() < self.resolution / 2.0 && held.z.is_none() => {
                if held.feed.is_some() {
                    self.feed_carried = held.feed;
                }
                return;
            }
            _ => {
                let mode = if held.mode == MotionMode::Rapid { MotionMode::Rapid } else { MotionMode::Linear };
                Motion { feed: held.feed, ..self.line_to(statement, mode, end, held.z) }
            }
        };
        self.write_move(statement, motion, out);
    }

    /// Follows a move to its end; what the pass needs of it.
    fn advance(&mut self, motion: &Motion) -> Step {
        let mode = motion.mode.expect("pass 00 gives every move its mode");
        let start = Point::new(self.position[0], self.position[1]);
        for axis in 0..3 {
            if let Some(v) = motion.target.get(axis) {
                self.position[axis] = v.value;
            }
        }
        let end = Point::new(self.position[0], self.position[1]);
        Step {
            mode,
            end,
            in_plane: motion.target.x.is_some() || motion.target.y.is_some(),
            path: segment(mode, motion, start, end),
            z: motion.target.z,
            feed: motion.feed,
        }
    }

    fn motion(&mut self, mut statement: Statement, mut step: Step, out: &mut Out) {
        match std::mem::replace(&mut self.state, State::Off) {
            State::Off => self.write(statement, out),
            State::Leaving if !step.in_plane => {
                self.state = State::Leaving;
                self.write(statement, out);
            }
            State::Leaving => {
                if step.mode.is_arc() {
                    let message = "the move after G40 must be a straight line, not an arc";
                    let help = "it takes the tool from the offset path back to the programmed one; \
                                add a G01 move before the arc";
                    return out.error(&statement, Diagnostic::error(statement.span, message).with_help(help));
                }
                // Both axes, since the tool is off the programmed path in both.
                let (x, y) = (self.value(&statement, step.end.x), self.value(&statement, step.end.y));
                if let Kind::Motion(motion) = &mut statement.kind {
                    (motion.target.x, motion.target.y) = (x, y);
                }
                self.write(statement, out);
            }
            State::Entering { comp, at } => {
                let Some(path) = step.path else {
                    // Nothing to step out along yet: Z moves run where the tool is.
                    self.state = State::Entering { comp, at };
                    return self.write(statement, out);
                };
                let Some(offset) = self.offset(&statement, &path, comp, out) else {
                    self.state = State::Entering { comp, at };
                    return;
                };
                // LinuxCNC (and Fanuc's start-up) cut a straight first move
                // from where the tool is to its offset path's end (or where
                // that path meets the next move's): the lenient dialect does
                // too. The manual steps out first.
                // A first arc runs from where the tool is to its offset's
                // end about a centre moved along the end's radius, so that
                // both ends are on it (LinuxCNC's arc entry).
                if self.dialect == Dialect::Lenient {
                    let entry = match path {
                        Segment::Line { start, .. } => Some((start, offset)),
                        Segment::Arc { start, centre, ccw, .. } => {
                            let end = offset.end();
                            let along = (end - centre).normalize();
                            let chord = end - start;
                            let shift = ((end - centre).dot(end - centre) - (start - centre).dot(start - centre))
                                / (2.0 * along.dot(chord));
                            shift.is_finite().then(|| (start, Segment::arc(start, end, centre + along * shift, ccw)))
                        }
                    };
                    if let Some((start, entry)) = entry {
                        let held = Box::new(hold(statement, step, entry, start));
                        self.state = State::On { comp, held };
                        return;
                    }
                }
                // The step out runs at the first move's speed: a rapid, or
                // a feed move taking the feed the first move brings.
                let (step_mode, step_feed) = match step.mode {
                    MotionMode::Rapid => (MotionMode::Rapid, None),
                    _ => (MotionMode::Linear, step.feed.take()),
                };
                let step_out = Motion { feed: step_feed, ..self.line_to(&at, step_mode, offset.start(), None) };
                self.write_move(&at, step_out, out);
                let held = Box::new(hold(statement, step, offset, offset.start()));
                self.state = State::On { comp, held };
            }
            State::On { comp, held } => {
                let Some(path) = step.path else {
                    self.state = State::On { comp, held };
                    return self.z_only(statement, step, out);
                };
                let Some(offset) = self.offset(&statement, &path, comp, out) else {
                    self.state = State::On { comp, held };
                    self.end_held(out);
                    self.state = State::Entering { comp, at: Box::new(statement) };
                    return;
                };
                self.turn(held, comp, statement, step, offset, out);
            }
        }
    }

    /// A move with no length in the plane, while a move is held: only its Z
    /// matters (its X and Y are the programmed point, not the tool's).
    fn z_only(&mut self, mut statement: Statement, step: Step, out: &mut Out) {
        if step.z.is_none() {
            if step.feed.is_some() {
                self.feed_carried = step.feed;
            }
            return;
        }
        if let Kind::Motion(motion) = &mut statement.kind {
            (motion.target.x, motion.target.y) = (None, None);
        }
        self.pass(statement, out);
    }

    /// The move's offset, or the error that the tool does not fit in its arc.
    fn offset(&self, statement: &Statement, path: &Segment, comp: Comp, out: &mut Out) -> Option<Segment> {
        match path.offset(comp.side, comp.radius) {
            Ok(offset) => Some(offset),
            Err(tight) => {
                let message = format!(
                    "the tool's radius ({:.4}) is not less than this arc's ({:.4}), which the tool runs inside",
                    comp.radius, tight.arc_radius
                );
                let help = "with G41 the tool is inside counter-clockwise arcs, with G42 inside clockwise ones; \
                            use a smaller tool or a larger arc";
                out.error(statement, Diagnostic::error(statement.span, message).with_help(help));
                None
            }
        }
    }

    /// The corner between the held move and the next one: writes the held
    /// move, what waited behind it and the way round the corner, and holds
    /// the next move.
    fn turn(
        &mut self,
        mut held: Box<Held>,
        comp: Comp,
        statement: Statement,
        mut step: Step,
        offset: Segment,
        out: &mut Out,
    ) {
        let corner = geometry::corner(held.corner, &held.offset, &offset, comp.side, 2.0 * self.resolution);
        let Some(corner) = corner else {
            let message = "cutter radius compensation would gouge the part: the tool cannot follow this inside corner";
            let help = format!(
                "the tool's paths along this move and the one before it (line {}) never meet: \
                 it cannot touch one without cutting into the other; use a smaller tool",
                held.statement.span.line
            );
            out.error(&statement, Diagnostic::error(statement.span, message).with_help(help));
            self.state = State::On { comp, held };
            self.end_held(out);
            self.state = State::Entering { comp, at: Box::new(statement) };
            return;
        };
        let (held_end, start) = match corner {
            Corner::Smooth => (held.offset.end(), held.offset.end()),
            Corner::Around { from, to, .. } => (from, to),
            Corner::Cut(at) => (at, at),
        };
        self.write_held(&held, held_end, Some(statement.span.line), out);
        while let Some(waiting) = self.waiting.pop_front() {
            self.write(waiting, out);
        }
        if let Corner::Around { from, to, ccw } = corner {
            let round = if step.mode == MotionMode::Rapid {
                self.line_to(&statement, MotionMode::Rapid, to, None)
            } else {
                // Round the programmed corner, at the tool's radius from it.
                let centre = held.corner;
                Motion {
                    mode: Some(if ccw { MotionMode::ArcCcw } else { MotionMode::ArcCw }),
                    centre: Axes {
                        x: self.value(&statement, centre.x - self.snap(from.x)),
                        y: self.value(&statement, centre.y - self.snap(from.y)),
                        z: None,
                    },
                    // The corner is the start of this move: it runs at its feed.
                    feed: step.feed.take(),
                    ..self.line_to(&statement, step.mode, to, None)
                }
            };
            self.write_move(&statement, round, out);
        }
        // The next move takes the held one's place (and its box).
        *held = hold(statement, step, offset, start);
        self.state = State::On { comp, held };
    }
}

/// The move of `statement` held, with the tool starting it at `start`.
fn hold(statement: Statement, step: Step, offset: Segment, start: Point) -> Held {
    Held { statement, mode: step.mode, z: step.z, feed: step.feed, corner: step.end, offset, start }
}

/// A move made by `statement` (which keeps its line and call chain).
fn moving(statement: &Statement, motion: Motion) -> Statement {
    statement.with_kind(Kind::Motion(Box::new(motion)))
}

/// The move's path in the plane; `None` for a straight move that does not
/// move in it.
fn segment(mode: MotionMode, motion: &Motion, start: Point, end: Point) -> Option<Segment> {
    if mode.is_arc() {
        let offset = |v: Option<Value>| v.map_or(0.0, |v| v.value);
        let centre = start + Point::new(offset(motion.centre.x), offset(motion.centre.y));
        Some(Segment::arc(start, end, centre, mode == MotionMode::ArcCcw))
    } else if start.distance(end) > 0.0 {
        Some(Segment::Line { start, end })
    } else {
        None
    }
}

/// Where compensation's radius comes from.
enum Radius {
    /// A tool table entry (G41/G42's D), or the loaded tool's.
    FromTable(Option<u32>),
    /// Given by the program (G41.1/G42.1's D, halved), in machine units.
    Given(f64),
}

impl Pass for CutterComp {
    fn statement(&mut self, mut statement: Statement, out: &mut Out) {
        match &mut statement.kind {
            Kind::CutterComp { side, d, diameter } => {
                let (side, d, diameter) = (*side, *d, diameter.map(|v| v.value));
                let code = match (side, diameter) {
                    (Side::Left, None) => "G41",
                    (Side::Right, None) => "G42",
                    (Side::Left, Some(_)) => "G41.1",
                    (Side::Right, Some(_)) => "G42.1",
                };
                if self.one_per_line(&statement, code, out) {
                    let radius = match diameter {
                        Some(diameter) => Radius::Given(diameter / 2.0),
                        None => Radius::FromTable(d),
                    };
                    self.comp_on(statement, side, radius, out);
                }
            }
            Kind::CutterCompCancel => {
                if self.one_per_line(&statement, "G40", out) {
                    self.comp_off(out);
                }
            }
            Kind::Plane(plane) if self.is_on() && *plane != Plane::XY => {
                // The passes before took the switch: follow it, with
                // compensation off, so what comes next is read as they read it.
                self.comp_off(out);
                self.plane = *plane;
                let message = format!("cannot switch to the {} plane with cutter radius compensation on", plane.code());
                out.error(&statement, Diagnostic::error(statement.span, message).with_help("cancel it with G40 first"));
            }
            Kind::Plane(plane) => {
                self.plane = *plane;
                self.pass(statement, out);
            }
            Kind::Motion(motion) => {
                let step = self.advance(motion);
                self.motion(statement, step, out);
            }
            Kind::Machine { code: Machine::ToolChange, t, .. } => {
                // The radius in use stays until G40, as in LinuxCNC; a new
                // G41/G42 takes the new tool's.
                self.tool = t.unwrap_or(self.tool);
                self.pass(statement, out);
            }
            Kind::SetToolTable { tool, radius: Some(radius), .. } => {
                // As in LinuxCNC, the compensation in force keeps its radius;
                // the next G41/G42 with this tool (or D) takes the new one.
                let (tool, radius) = (*tool, radius.value);
                self.radii.retain(|(n, _)| *n != tool);
                self.radii.push((tool, radius));
                self.pass(statement, out);
            }
            Kind::End => {
                self.comp_off(out);
                self.state = State::Off;
                out.push(statement);
            }
            _ => self.pass(statement, out),
        }
    }

    fn finish(&mut self, out: &mut Out) {
        self.comp_off(out);
    }
}

#[cfg(test)]
mod tests {
    //! The pass on small programs (tool 1: diameter 0.25 in, so R = 0.125),
    //! with the expected points worked out by hand in the comments.

    use super::MAX_HELD;
    use crate::config::{Config, Tool, ToolKind};
    use crate::passes::testing::{run, run_with};

    fn comp(text: &str) -> Vec<String> {
        run(text, 5)
    }

    #[test]
    fn entry_steps_out_perpendicular_to_the_first_move() {
        // The first move runs +X from (-1,0): left is +Y, right -Y. The step
        // out is a feed move, so it takes the first move's F.
        assert_eq!(
            comp("G00 X-1\nG41\nG01 X0 F10\nM30"),
            ["G00 X-1.0000", "G01 X-1.0000 Y0.1250 F10.0000", "G01 X0.0000 Y0.1250", "M30"]
        );
        assert_eq!(
            comp("G00 X-1\nG42\nG00 X0\nM30"),
            ["G00 X-1.0000", "G00 X-1.0000 Y-0.1250", "G00 X0.0000 Y-0.1250", "M30"]
        );
    }

    #[test]
    fn z_moves_and_codes_wait_behind_the_held_move_in_order() {
        // +X to (0,0), then +Y: a left turn with the tool left, an inside
        // corner cut where y = 0.125 meets x = -0.125.
        assert_eq!(
            comp("G00 X-1\nG41\nG01 X0 F10\nG00 Z1\nM05\nG01 Y1\nM30"),
            [
                "G00 X-1.0000",
                "G01 X-1.0000 Y0.1250 F10.0000",
                "G01 X-0.1250 Y0.1250",
                "G00 Z1.0000",
                "M05",
                "G01 X-0.1250 Y1.0000",
                "M30"
            ]
        );
        // Before the first move in the plane, Z moves run where the tool is.
        assert_eq!(
            comp("G41\nG01 Z-1 F10\nX1\nM30"),
            ["G01 Z-1.0000 F10.0000", "G01 X0.0000 Y0.1250", "G01 X1.0000 Y0.1250", "M30"]
        );
    }

    #[test]
    fn helices_are_offset_in_the_plane_and_keep_their_z() {
        // A full CCW circle of radius 1 about the origin, from (1,0), going
        // down: left of it is inside (radius 0.875), right outside (1.125).
        assert_eq!(
            comp("G00 X1\nG41\nG03 I-1 Z-0.5 F10\nM30"),
            ["G00 X1.0000", "G01 X0.8750 Y0.0000 F10.0000", "G03 X0.8750 Y0.0000 Z-0.5000 I-0.8750 J0.0000", "M30"]
        );
        assert_eq!(comp("G00 X1\nG42\nG03 I-1 Z-0.5 F10\nM30")[2], "G03 X1.1250 Y0.0000 Z-0.5000 I-1.1250 J0.0000");
    }

    #[test]
    fn outside_corners_go_round_at_the_next_moves_feed_or_straight_for_a_rapid() {
        // +X to (1,0) then +Y, tool right: outside, counter-clockwise round
        // (1,0) from (1,-0.125) to (1.125,0): I 0, J 0.125.
        assert_eq!(
            comp("G42\nG01 X1 F10\nY1 F20\nM30"),
            [
                "G01 X0.0000 Y-0.1250 F10.0000",
                "G01 X1.0000 Y-0.1250",
                "G03 X1.1250 Y0.0000 I0.0000 J0.1250 F20.0000",
                "G01 X1.1250 Y1.0000",
                "M30"
            ]
        );
        // A rapid after the corner has no feed for an arc: a straight rapid.
        assert_eq!(
            comp("G42\nG00 X1\nY1\nM30"),
            ["G00 X0.0000 Y-0.1250", "G00 X1.0000 Y-0.1250", "G00 X1.1250 Y0.0000", "G00 X1.1250 Y1.0000", "M30"]
        );
    }

    #[test]
    fn after_g40_the_next_move_goes_back_to_the_programmed_point() {
        // The held move ends on its offset; Z alone leaves the tool there; the
        // next move in the plane writes both axes, as the tool is off in both.
        assert_eq!(
            comp("G41\nG01 X1 F10\nG40\nZ1\nY2\nM30"),
            ["G01 X0.0000 Y0.1250 F10.0000", "G01 X1.0000 Y0.1250", "G01 Z1.0000", "G01 X1.0000 Y2.0000", "M30"]
        );
        assert_eq!(
            comp("G41\nG01 X1 F10\nG40\nG03 X2 Y1 I0 J1\nM30")[2],
            "4:1: error: the move after G40 must be a straight line, not an arc"
        );
    }

    #[test]
    fn the_radius_stays_until_g40_and_d_names_an_entry() {
        let tool = |number, diameter| Tool::new(number, ToolKind::Endmill, diameter);
        let config = Config { tools: vec![tool(1, 0.25), tool(2, 0.5)], ..Config::default() };
        // M06 T2 while on keeps R 0.125; the next G41 takes tool 2's 0.25,
        // or tool 1's again with D1.
        let got = run_with("G41\nG01 X1 F10\nM06 T2\nX2\nG40\nG41\nX3\nG40\nG41 D1\nX4\nM30", &config, 5);
        assert_eq!(
            got,
            [
                "G01 X0.0000 Y0.1250 F10.0000",
                "G01 X1.0000 Y0.1250",
                "M06 T2",
                "G01 X2.0000 Y0.1250",
                "G01 X2.0000 Y0.2500",
                "G01 X3.0000 Y0.2500",
                "G01 X3.0000 Y0.1250",
                "G01 X4.0000 Y0.1250",
                "M30"
            ]
        );
    }

    #[test]
    fn comp_is_refused_out_of_the_xy_plane_and_the_plane_cannot_switch() {
        assert_eq!(
            comp("G18\nG41\nM30"),
            ["G18", "2:1: error: cannot turn cutter radius compensation on out of the XY plane (G18 is on)", "M30"]
        );
        // The held move is finished first, on its own offset.
        assert_eq!(
            comp("G41\nG01 X1 F10\nG19\nM30"),
            [
                "G01 X0.0000 Y0.1250 F10.0000",
                "G01 X1.0000 Y0.1250",
                "3:1: error: cannot switch to the G19 plane with cutter radius compensation on",
                "M30"
            ]
        );
    }

    #[test]
    fn comp_is_turned_on_once_with_a_known_tool() {
        assert_eq!(
            comp("G41\nG42\nM30")[0],
            "2:1: error: cannot turn cutter radius compensation on (G42) when it is already on"
        );
        assert_eq!(comp("G41 D3")[0], "1:1: error: tool table entry 3 (D3) does not exist");
        // D0 is no tool, as in LinuxCNC: the path is cut as written.
        assert_eq!(comp("G41 D0\nG01 X1 F1\nY1\nG40\nM30"), ["G01 X1.0000 F1.0000", "G01 Y1.0000", "M30"]);
        assert_eq!(
            comp("M06 T4\nG41"),
            ["M06 T4", "2:1: error: the loaded tool, T4, is not in the tool table: its radius is unknown"]
        );
    }

    #[test]
    fn a_radius_written_with_g10_l1_is_taken_by_the_next_g41() {
        // Tool 4 is not in the table until G10 L1 writes it, R 0.2: G41 on a move along +X puts the
        // tool 0.2 to its left. A later write changes the next compensation, not the one in force.
        let lenient = Config { dialect: crate::statement::Dialect::Lenient.into(), ..Config::default() };
        assert_eq!(
            run_with("G10 L1 P4 R0.2\nM06 T4\nG41\nG01 X1 F10\nX2\nG10 L1 P4 R0.3\nX3\nG40\nG01 X4 Y0\nG41 D4\nG01 X5\nX6\nG40\nM30", &lenient, 5),
            [
                "G10 L1 P4 R0.2000",
                "M06 T4",
                "G01 X1.0000 Y0.2000 F10.0000",
                "G01 X2.0000 Y0.2000",
                "G10 L1 P4 R0.3000",
                "G01 X3.0000 Y0.2000",
                "G01 X4.0000 Y0.0000",
                "G01 X5.0000 Y0.3000",
                "G01 X6.0000 Y0.3000",
                "M30"
            ]
        );
    }

    #[test]
    fn linuxcncs_g41_1_and_g42_1_take_the_cutters_diameter_from_the_program() {
        // The lenient dialect's G41.1 D0.4: a cutter 0.4 across, so 0.2 to the
        // left of a move along +X, whatever the tool table says; G42.1 D0.6 in
        // a G21 program on this inch machine: 0.6 mm is 0.0236 in, half of it
        // 0.0118 to the right. D0 cuts the path as written.
        let lenient = Config { dialect: crate::statement::Dialect::Lenient.into(), ..Config::default() };
        let program = "G41.1 D0.4\nG01 X1 F10\nX2\nG40\nG01 X3 Y0\nG21\nG42.1 D0.6\nG01 X101.6\nG40\nG01 X127 Y0\n\
                       G41.1 D0\nG01 X152.4\nG40\nM30";
        assert_eq!(
            run_with(program, &lenient, 5),
            [
                "G01 X1.0000 Y0.2000 F10.0000",
                "G01 X2.0000 Y0.2000",
                "G01 X3.0000 Y0.0000",
                "G01 X4.0000 Y-0.0118",
                "G01 X5.0000 Y0.0000",
                "G01 X6.0000",
                "M30"
            ]
        );
        // D is needed, and the strict dialect (the GER manual's) has no G41.1.
        assert_eq!(run_with("G41.1\nM30", &lenient, 5), ["1:1: error: G41.1 needs D: the cutter's diameter", "M30"]);
        assert!(comp("G41.1 D0.4").iter().any(|l| l.contains("error: G41.1")), "{:?}", comp("G41.1 D0.4"));
    }

    #[test]
    fn two_codes_of_the_group_on_one_line_but_not_one_code_run_twice() {
        assert_eq!(comp("G41 G40"), ["1:5: error: G41 and G40 on one line: they are codes of the same group"]);
        // A subprogram of one line run twice is the same code twice, not two.
        assert_eq!(comp("M98 P100 L2\nM30\nO100\nG40\nM99"), ["M30"]);
    }

    #[test]
    fn the_tool_must_fit_inside_concave_arcs() {
        // CCW arc of radius 0.1 from (0.1,0): G41 runs inside it.
        assert_eq!(
            comp("G00 X0.1\nG41\nG03 X0 Y0.1 I-0.1 J0 F10")[1],
            "3:1: error: the tool's radius (0.1250) is not less than this arc's (0.1000), which the tool runs inside"
        );
        // With G42 it runs outside: radius 0.225.
        assert_eq!(comp("G00 X0.1\nG42\nG03 X0 Y0.1 I-0.1 J0 F10")[2], "G03 X0.0000 Y0.2250 I-0.2250 J0.0000");
    }

    #[test]
    fn gouges_are_refused() {
        // A U 0.2 wide for a tool 0.25 wide: the offsets of the two long
        // sides (y = 0.125 and y = 0.075) leave the short side running down.
        assert_eq!(
            comp("G41\nG01 X1 F10\nY0.2\nX0\nM30")[2],
            "3:1: error: cutter radius compensation would gouge the part: this move is too short for the tool"
        );
        // +X to (1,0), then a left turn into a CCW arc of radius 0.2 about
        // (0.8,0): its inside offset (radius 0.075) never reaches y = 0.125.
        assert_eq!(
            comp("G41\nG01 X1 F10\nG03 X0.8 Y0.2 I-0.2 J0\nM30")[1],
            "3:1: error: cutter radius compensation would gouge the part: the tool cannot follow this inside corner"
        );
    }

    #[test]
    fn statements_waiting_behind_a_move_are_bounded() {
        let mut program = String::from("G41\nG01 X1 F10\n");
        program.push_str(&"M05\n".repeat(MAX_HELD + 1));
        program.push_str("X2\nM30\n");
        let got = comp(&program);
        let errors: Vec<_> = got.iter().filter(|l| l.contains("error")).collect();
        assert_eq!(errors.len(), 1, "{errors:?}");
        let line = MAX_HELD + 3;
        assert!(errors[0].starts_with(&format!("{line}:1: error: more than {MAX_HELD} statements")), "{}", errors[0]);
    }
}
