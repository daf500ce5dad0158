//! Pass 04: absolute coordinates. G90/G91 go away: every move's target becomes
//! absolute (in machine coordinates, since pass 02). Arcs are checked and put
//! in one form: I/J/K relative to the start; R is converted (R > 0 the short
//! arc, R < 0 the long one); a full circle needs I/J/K; the end must lie on
//! the circle. This pass also settles the feed: a feed move needs an F before
//! it, F is written on the first feed move after it changes, and a statement
//! that only sets F disappears. The lenient dialect's canned cycles
//! (`cycles.rs`) and splines (`splines.rs`) become plain moves here.

use super::{Out, Pass};
use crate::config::Config;
use crate::diag::{Diagnostic, Span};
use crate::geom::{arc_as_lines, arc_sweep, centre_from_radius, RadiusArcError};
use crate::state::{Probe, Spindle};
use crate::statement::{
    Axes, Dialect, Distance, FeedMode, Kind, Machine, Motion, MotionMode, Plane, Reference, Statement, Turns, Units,
    Value,
};

mod cycles;
mod splines;
mod tool_offsets;

pub struct Absolute {
    units: Units,
    dialect: Dialect,
    distance: Distance,
    plane: Plane,
    position: [f64; 3],
    /// F as programmed: units per minute, per revolution (G95) or the
    /// inverse of minutes (G93, one move only).
    feed: Option<f64>,
    feed_mode: FeedMode,
    /// The feed the output last said, so F is written only when it changes.
    feed_written: Option<f64>,
    /// `[machine] default_feed`, for a feed move before any F (lenient).
    default_feed: Option<f64>,
    warned_default_feed: bool,
    /// G90.1: I, J and K are absolute (pass 02 has put them in machine coordinates).
    absolute_centres: bool,
    probe: Probe,
    /// G28's point (machine zero until G28.1) and G30's, in machine coordinates.
    home: [f64; 3],
    second_reference: [f64; 3],
    /// The lenient dialect's S and T words alone: a speed and a tool waiting
    /// for the M03/M04 and M06 that use them.
    speed: Option<f64>,
    selected_tool: Option<u32>,
    cycles: cycles::CycleState,
    splines: splines::SplineState,
    /// G43 (true) or G44 (false) in force, for an H word given alone.
    tool_length: Option<bool>,
    tool_offsets: tool_offsets::ToolOffsets,
    /// Where the A, B and C words have put the rotary axes, once said.
    rotary: [Option<f64>; 3],
    warned_rotary: bool,
    /// Warnings about the statement being rewritten, given its calls after it.
    warnings: Vec<Diagnostic>,
    /// Where the arc just rewritten started, if it is a spiral (its radii
    /// differ by more than the output's arc tolerance, as LinuxCNC allows):
    /// it goes out as lines along the spiral.
    spiral_from: Option<[f64; 3]>,
}

impl Absolute {
    pub fn new(config: &Config, probe: Probe) -> Absolute {
        probe.borrow_mut().references = [[0.0; 3], config.machine.second_reference];
        Absolute {
            units: config.units,
            dialect: config.dialect.name,
            distance: Distance::Absolute,
            plane: Plane::XY,
            position: [0.0; 3],
            feed: None,
            feed_mode: FeedMode::PerMinute,
            feed_written: None,
            default_feed: config.machine.default_feed,
            warned_default_feed: false,
            absolute_centres: false,
            probe,
            home: [0.0; 3],
            second_reference: config.machine.second_reference,
            speed: None,
            selected_tool: None,
            cycles: cycles::CycleState::default(),
            splines: splines::SplineState::new(config),
            tool_length: None,
            tool_offsets: tool_offsets::ToolOffsets::default(),
            rotary: [None; 3],
            warned_rotary: false,
            warnings: Vec::new(),
            spiral_from: None,
        }
    }

    fn absolute(&self, axis: usize, v: Value) -> Value {
        match self.distance {
            Distance::Absolute => v,
            Distance::Incremental => Value { value: self.position[axis] + v.value, ..v },
        }
    }

    /// The arc's centre offsets from its start (I/J/K), or why it has none.
    /// With `spirals`, the centre of an arc whose radii differ by more than
    /// the output's tolerance (but within LinuxCNC's) stays where it was
    /// written, for the arc to go out as LinuxCNC's spiral; without, it moves
    /// to where both radii are equal. True with the offsets if the arc is
    /// such a spiral.
    fn arc_centre(
        &self,
        motion: &mut Motion,
        end: [f64; 3],
        span: Span,
        spirals: bool,
    ) -> Result<(Axes, bool), Diagnostic> {
        let (a, b, normal) = self.plane.axes();
        let letters = ['I', 'J', 'K'];
        if let Some(v) = motion.centre.get(normal) {
            // A post writing all three offsets (`K0` on a G17 arc) says nothing
            // with the third; the lenient dialect reads past it.
            if self.dialect == Dialect::Lenient && !self.absolute_centres && v.value == 0.0 {
                *motion.centre.slot(normal) = None;
            } else {
                let plane = self.plane.code();
                let message = format!("{} is not used for arcs in the {plane} plane", letters[normal]);
                return Err(Diagnostic::error(v.span, message)
                    .with_help(format!("in {plane} the centre is given by {} and {}", letters[a], letters[b])));
            }
        }
        if self.absolute_centres && motion.radius.is_none() {
            for axis in [a, b] {
                let Some(v) = motion.centre.slot(axis) else {
                    let message = format!("with G90.1 an arc needs both {} and {}: its centre", letters[a], letters[b]);
                    return Err(Diagnostic::error(span, message)
                        .with_help("absolute I/J/K give the centre's coordinates, so none may be left out"));
                };
                v.value -= self.position[axis];
            }
        }
        let start = (self.position[a], self.position[b]);
        let stop = (end[a], end[b]);
        let tolerance = self.units.arc_tolerance();
        // Messages show lengths as the output would: in machine units, rounded.
        let (u, d) = (self.units.abbreviation(), self.units.decimals());
        if let Some(r) = motion.radius {
            let ccw = motion.mode == Some(MotionMode::ArcCcw);
            let centre = centre_from_radius(start, stop, r.value, ccw, tolerance).map_err(|err| match err {
                RadiusArcError::FullCircle => Diagnostic::error(r.span, "a full circle cannot be given with R")
                    .with_help(format!("give the centre with {} and {} instead", letters[a], letters[b])),
                RadiusArcError::TooShort { chord } => Diagnostic::error(
                    r.span,
                    format!(
                        "R is too small for this arc: its end is {chord:.d$} {u} from its start, more than twice the radius ({:.d$} {u})",
                        r.value.abs()
                    ),
                )
                .with_help(format!("the radius must be at least half that distance, {:.d$} {u}", chord / 2.0)),
            })?;
            let mut offsets = Axes::default();
            *offsets.slot(a) = Some(Value { value: centre.0 - start.0, span: r.span });
            *offsets.slot(b) = Some(Value { value: centre.1 - start.1, span: r.span });
            return Ok((offsets, false));
        }
        if motion.centre.get(a).is_none() && motion.centre.get(b).is_none() {
            let message = format!("arc without a centre: give {} and {}, or R", letters[a], letters[b]);
            return Err(
                Diagnostic::error(span, message).with_help("I/J/K give the centre relative to the start; R the radius")
            );
        }
        let offset = |axis: usize| motion.centre.get(axis).map_or(0.0, |v| v.value);
        let (i, j) = (offset(a), offset(b));
        let start_radius = i.hypot(j);
        let end_radius = (stop.0 - start.0 - i).hypot(stop.1 - start.1 - j);
        if start_radius <= tolerance {
            return Err(Diagnostic::error(span, "arc radius is zero: its centre is at its start"));
        }
        let error = (start_radius - end_radius).abs();
        if error > tolerance
            && !(self.dialect == Dialect::Lenient && error <= self.linuxcnc_arc_tolerance(start_radius.max(end_radius)))
        {
            let message = format!(
                "arc end is not on the circle: radius {start_radius:.d$} {u} at the start, {end_radius:.d$} {u} at the end"
            );
            let help = format!("the two must agree within {tolerance} {u}; check the end point and the centre offsets");
            return Err(Diagnostic::error(span, message).with_help(help));
        }
        let mut offsets = motion.centre;
        if error > tolerance && !spirals {
            // Within LinuxCNC's tolerance but not the output's: the centre
            // moves onto the chord's bisector, the nearest point from which
            // start and end are equally far, so every controller takes it.
            let (cx, cy) = nearest_equidistant(start, stop, (start.0 + i, start.1 + j));
            *offsets.slot(a) = Some(Value { value: cx - start.0, span });
            *offsets.slot(b) = Some(Value { value: cy - start.1, span });
        }
        offsets.slot(a).get_or_insert(Value { value: 0.0, span });
        offsets.slot(b).get_or_insert(Value { value: 0.0, span });
        Ok((offsets, error > tolerance && spirals))
    }

    /// How far LinuxCNC lets an arc's end be off its circle: 0.002 in (or
    /// 0.02 mm) times the square root of 2 in the program's unit, or 0.1% of
    /// the larger of its two radii up to a hundred times that, whichever is
    /// larger.
    fn linuxcnc_arc_tolerance(&self, radius: f64) -> f64 {
        let program = self.probe.borrow().program_units;
        let least = match program {
            Units::Inch => 0.002,
            Units::Mm => 0.02,
        } * std::f64::consts::SQRT_2
            * program.factor_to(self.units);
        (0.001 * radius).clamp(least, 100.0 * least)
    }

    /// Rewrites a move in place. `Ok(false)`: it only set the feed, drop it.
    /// With `spirals` (the lenient dialect's arcs that run once), an arc may
    /// be LinuxCNC's spiral, left in `spiral_from` to go out as lines.
    fn motion(&mut self, motion: &mut Motion, span: Span, spirals: bool) -> Result<bool, Diagnostic> {
        let mode = motion.mode.expect("pass 00 gives every move its mode");
        let given_feed = motion.feed.take();
        if let Some(f) = given_feed {
            self.feed = Some(f.value);
        }
        if !motion.moves() {
            return Ok(false);
        }
        let feed = match mode {
            MotionMode::Rapid => None,
            _ => Some(self.feed_rate(mode, given_feed, span)?),
        };
        let mut end = self.position;
        for (axis, end) in end.iter_mut().enumerate() {
            if let Some(v) = motion.target.slot(axis) {
                *v = self.absolute(axis, *v);
                *end = v.value;
            }
        }
        if mode.is_arc() {
            let spirals = spirals && self.dialect == Dialect::Lenient;
            let (centre, spiral) = self.arc_centre(motion, end, span, spirals)?;
            motion.centre = centre;
            if spiral {
                self.spiral_from = Some(self.position);
            }
            motion.radius = None;
            // An arc states both of its plane's axes, whatever was written.
            let (a, b, _) = self.plane.axes();
            for axis in [a, b] {
                motion.target.slot(axis).get_or_insert(Value { value: end[axis], span });
            }
        }
        if let Some(feed) = feed {
            let feed = match feed {
                Feed::PerMinute(feed) => feed,
                Feed::InverseTime(f) => f * self.move_length(motion, end),
            };
            if Some(feed) != self.feed_written {
                self.feed_written = Some(feed);
                motion.feed = Some(Value { value: feed, span });
            }
        }
        self.position = end;
        self.splines.series = None;
        Ok(true)
    }

    /// The feed of a feed move, in units per minute or (G93) as the inverse
    /// of its time in minutes, which needs the move's length.
    fn feed_rate(&mut self, mode: MotionMode, given: Option<Value>, span: Span) -> Result<Feed, Diagnostic> {
        let code = mode.code();
        match self.feed_mode {
            FeedMode::InverseTime => {
                let f = given.ok_or_else(|| {
                    Diagnostic::error(span, format!("{code} in inverse time (G93) needs its own F"))
                        .with_help("in G93 every feed move says how fast it runs: F is one over its time in minutes")
                })?;
                if f.value <= 0.0 {
                    return Err(zero_feed(code, span));
                }
                Ok(Feed::InverseTime(f.value))
            }
            _ if self.feed == Some(0.0) => Err(zero_feed(code, span)),
            FeedMode::PerRevolution => {
                let feed = self.feed.ok_or_else(|| no_feed(code, span))?;
                match self.speed.filter(|s| *s > 0.0) {
                    Some(speed) => Ok(Feed::PerMinute(feed * speed)),
                    None => Err(Diagnostic::error(
                        span,
                        format!("{code} in feed per revolution (G95) with no spindle speed"),
                    )
                    .with_help("give the speed with S before the move, e.g. M03 S1000")),
                }
            }
            FeedMode::PerMinute => match (self.feed, self.default_feed) {
                (Some(feed), _) => Ok(Feed::PerMinute(feed)),
                (None, Some(default)) if self.dialect == Dialect::Lenient => {
                    if !std::mem::replace(&mut self.warned_default_feed, true) {
                        let (u, d) = (self.units.abbreviation(), self.units.decimals());
                        let message = format!("{code} move before any feed rate (F): it runs at [machine] default_feed, {default:.d$} {u}/min");
                        let help = "give the feed in the program, e.g. F300, to say what it should be";
                        self.warnings.push(Diagnostic::warning(span, message).with_help(help));
                    }
                    Ok(Feed::PerMinute(default))
                }
                (None, _) => Err(no_feed(code, span)),
            },
        }
    }

    /// How far a move to `end` goes: along its arc (and helix) for an arc.
    fn move_length(&self, motion: &Motion, end: [f64; 3]) -> f64 {
        let start = self.position;
        if !motion.mode.is_some_and(MotionMode::is_arc) {
            return (0..3).map(|axis| (end[axis] - start[axis]).powi(2)).sum::<f64>().sqrt();
        }
        let (a, b, normal) = self.plane.axes();
        let offset = |axis: usize| motion.centre.get(axis).map_or(0.0, |v| v.value);
        let centre = (start[a] + offset(a), start[b] + offset(b));
        let ccw = motion.mode == Some(MotionMode::ArcCcw);
        let (_, sweep) = arc_sweep((start[a], start[b]), (end[a], end[b]), centre, ccw);
        let radius = offset(a).hypot(offset(b));
        (radius * sweep).hypot(end[normal] - start[normal])
    }

    /// A, B and C words: dropped while the axis stays where the first put it.
    fn rotary(&mut self, words: &[Option<Value>; 3]) -> Result<(), Diagnostic> {
        for (axis, word) in words.iter().enumerate() {
            let Some(word) = word else { continue };
            let letter = ["A", "B", "C"][axis];
            let at = self.rotary[axis];
            let to = match (self.distance, at) {
                (Distance::Incremental, _) => at.unwrap_or(0.0) + word.value,
                (Distance::Absolute, _) => word.value,
            };
            match at {
                Some(at) if at != to => {
                    let message = format!("the {letter} axis would turn from {at} to {to}: ger's machines have 3 axes");
                    return Err(Diagnostic::error(word.span, message)
                        .with_help("this program is for a machine with a rotary axis"));
                }
                None if self.distance == Distance::Incremental && to != 0.0 => {
                    let message = format!("the {letter} axis would turn by {to}: ger's machines have 3 axes");
                    return Err(Diagnostic::error(word.span, message)
                        .with_help("this program is for a machine with a rotary axis"));
                }
                _ => self.rotary[axis] = Some(to),
            }
            if !std::mem::replace(&mut self.warned_rotary, true) {
                let message = format!("{letter}{} is dropped: a 3-axis machine has no rotary axis", word.value);
                let help = "the program is read while its A, B and C stay where they are; a word that would turn one is an error";
                self.warnings.push(Diagnostic::warning(word.span, message).with_help(help));
            }
        }
        Ok(())
    }
}

enum Feed {
    PerMinute(f64),
    InverseTime(f64),
}

fn no_feed(code: &str, span: Span) -> Diagnostic {
    Diagnostic::error(span, format!("{code} move before any feed rate (F)"))
        .with_help(format!("give the feed on this move or before it, e.g. {code} ... F10"))
}

/// A feed move at F0, which LinuxCNC refuses too.
fn zero_feed(code: &str, span: Span) -> Diagnostic {
    Diagnostic::error(span, format!("{code} move at a feed rate of zero (F0)"))
        .with_help(format!("give the feed on this move or before it, e.g. {code} ... F10"))
}

/// The point nearest `centre` on the perpendicular bisector of `start` and `end`.
/// The most pieces a spiral is cut into, whatever its size: a spiral
/// LinuxCNC takes is at most a few mm off a circle, so only an absurdly
/// large one (a radius of kilometres) would need more.
const MOST_SPIRAL_PIECES: usize = 100_000;

fn nearest_equidistant(start: (f64, f64), end: (f64, f64), centre: (f64, f64)) -> (f64, f64) {
    let mid = ((start.0 + end.0) / 2.0, (start.1 + end.1) / 2.0);
    let (dx, dy) = (end.0 - start.0, end.1 - start.1);
    let chord2 = dx * dx + dy * dy;
    if chord2 == 0.0 {
        return centre;
    }
    // Remove the part of (centre - mid) that runs along the chord.
    let along = ((centre.0 - mid.0) * dx + (centre.1 - mid.1) * dy) / chord2;
    (centre.0 - along * dx, centre.1 - along * dy)
}

impl Pass for Absolute {
    fn statement(&mut self, statement: Statement, out: &mut Out) {
        self.close_nurbs_before(&statement, out);
        let origin = statement.origin.clone();
        let moves = match &statement.kind {
            Kind::Motion(motion) | Kind::MachineMove(motion) => motion.moves(),
            Kind::Home { .. } | Kind::Cycle(_) | Kind::Spline(_) | Kind::NurbsEnd => true,
            _ => false,
        };
        self.rewrite(statement, out);
        if moves {
            self.tool_offsets.moved();
        }
        for warning in self.warnings.drain(..) {
            out.report(warning.with_origin(origin.clone()));
        }
        self.update_probe();
    }

    fn resume(&mut self, out: &mut Out) -> bool {
        let more = self.next_hole(out);
        if more {
            self.update_probe();
        }
        more
    }

    fn finish(&mut self, out: &mut Out) {
        self.unfinished_nurbs(out);
    }
}

impl Absolute {
    fn update_probe(&self) {
        let mut probe = self.probe.borrow_mut();
        probe.position = self.position;
        probe.distance = self.distance;
        probe.plane = self.plane;
        probe.feed = self.feed;
    }

    fn rewrite(&mut self, mut statement: Statement, out: &mut Out) {
        if let Kind::Motion(motion) = &mut statement.kind {
            match motion.turns.take() {
                // Haas's and Fadal's L: the block again, from where it ended.
                Some(Turns::Repeated(times)) => {
                    for _ in 0..times {
                        self.rewrite(statement.clone(), out);
                    }
                    return;
                }
                Some(Turns::Around(turns)) if turns > 1 => return self.arc_around(statement, turns, out),
                _ => {}
            }
        }
        if let Kind::Cycle(cycle) = &statement.kind {
            if let Err(diagnostic) = self.cycle(cycle, &statement) {
                out.error(&statement, diagnostic);
            }
            return;
        }
        let drawn = match &statement.kind {
            Kind::Spline(spline) => Some(self.spline(spline, &statement, out)),
            Kind::NurbsEnd => Some(self.nurbs_end(&statement, out)),
            _ => None,
        };
        // Any move but a cycle's ends the series of cycles (LinuxCNC's initial level goes).
        let moves = match &statement.kind {
            Kind::Motion(motion) | Kind::MachineMove(motion) => motion.moves(),
            Kind::Home { .. } | Kind::CycleCancel => true,
            _ => drawn.is_some(),
        };
        if moves {
            self.cycles.end_series();
        }
        if let Some(result) = drawn {
            if let Err(diagnostic) = result {
                out.error(&statement, diagnostic);
            }
            return;
        }
        match &mut statement.kind {
            Kind::Distance(distance) => {
                self.distance = *distance;
                return;
            }
            // The output starts in G17; repeating the plane in force says nothing.
            Kind::Plane(plane) if std::mem::replace(&mut self.plane, *plane) == *plane => return,
            Kind::Motion(motion) => match self.motion(motion, statement.span, true) {
                Ok(true) => {
                    if let Some(start) = self.spiral_from.take() {
                        return self.spiral(start, &statement, out);
                    }
                }
                Ok(false) => return,
                Err(diagnostic) => return out.error(&statement, diagnostic),
            },
            Kind::ToolLength { positive, h } => {
                *h = h.or(Some(self.probe.borrow().tool));
                self.tool_length = Some(*positive);
                self.tool_offsets.apply(h.unwrap_or(0), *positive);
            }
            Kind::ToolLengthCancel => {
                self.tool_length = None;
                self.tool_offsets.cancel();
            }
            Kind::SetToolTable { tool, offsets, .. } => {
                self.tool_offsets.write(*tool, [0, 1, 2].map(|axis| offsets.get(axis).map(|v| v.value)));
            }
            Kind::SetToolTableFrom(from) => {
                let frame = from.frame.expect("pass 02 says which coordinate system");
                match self.tool_offsets.entry_from(from.tool, self.position, from.target, frame, statement.span) {
                    Ok(offsets) => {
                        statement.kind =
                            Kind::SetToolTable { tool: from.tool, offsets: Box::new(offsets), radius: from.radius }
                    }
                    Err(diagnostic) => return out.error(&statement, diagnostic),
                }
            }
            Kind::ToolLengthRegister(h) => {
                let h = *h;
                let positive = match (self.tool_length, h) {
                    (Some(positive), _) => positive,
                    (None, 0) => return,
                    (None, h) => {
                        let message =
                            format!("H{h} with no G43 in force: it is written as G43 H{h}, as Fadal applies it");
                        let help = "write G43 with it: a Fanuc would ignore this H";
                        self.warnings.push(Diagnostic::warning(statement.span, message).with_help(help));
                        true
                    }
                };
                return self.rewrite(statement.with_kind(Kind::ToolLength { positive, h: Some(h) }), out);
            }
            Kind::FeedMode(mode) => {
                // Leaving inverse time, LinuxCNC asks for a new F: the last one was a time.
                if std::mem::replace(&mut self.feed_mode, *mode) == FeedMode::InverseTime
                    && *mode != FeedMode::InverseTime
                {
                    self.feed = None;
                }
                return;
            }
            Kind::ArcCentres(distance) => {
                self.absolute_centres = *distance == Distance::Absolute;
                return;
            }
            Kind::SetReference(reference) => {
                match reference {
                    Reference::Home => self.home = self.position,
                    Reference::Second => self.second_reference = self.position,
                }
                self.probe.borrow_mut().references = [self.home, self.second_reference];
                return;
            }
            Kind::Rotary(words) => {
                if let Err(diagnostic) = self.rotary(words) {
                    out.error(&statement, diagnostic);
                }
                return;
            }
            Kind::Machine { code, s, t } => {
                // A speed or tool given alone before (lenient dialect) is used here.
                if matches!(code, Machine::SpindleCw | Machine::SpindleCcw) {
                    *s = s.or(self.speed);
                    self.speed = *s;
                }
                if *code == Machine::ToolChange {
                    *t = t.or(self.selected_tool.take());
                }
                let mut probe = self.probe.borrow_mut();
                probe.speed = s.or(probe.speed);
                match code {
                    Machine::SpindleCw => probe.spindle = Spindle::Clockwise(*s),
                    Machine::SpindleCcw => probe.spindle = Spindle::CounterClockwise(*s),
                    Machine::SpindleOff => probe.spindle = Spindle::Off,
                    Machine::ToolChange => probe.tool = t.unwrap_or(probe.tool),
                    _ => {}
                }
            }
            Kind::SpindleSpeed(speed) => {
                self.speed = Some(*speed);
                self.probe.borrow_mut().speed = self.speed;
                // A new speed while the spindle turns is said with its direction.
                let code = match self.probe.borrow().spindle {
                    Spindle::Clockwise(_) => Machine::SpindleCw,
                    Spindle::CounterClockwise(_) => Machine::SpindleCcw,
                    Spindle::Off => return,
                };
                let kind = Kind::Machine { code, s: Some(*speed), t: None };
                return self.rewrite(statement.with_kind(kind), out);
            }
            Kind::ToolSelect(tool) => {
                self.selected_tool = Some(*tool);
                return;
            }
            Kind::CycleRetract(retract) => {
                self.cycles.retract = Some(*retract);
                return;
            }
            Kind::CycleCancel => return,
            Kind::Home { reference, via } => {
                let (reference, via) = (*reference, **via);
                return self.home(reference, via, &statement, out);
            }
            Kind::MachineMove(motion) => {
                // Machine coordinates are absolute whatever G90/G91 says.
                let distance = std::mem::replace(&mut self.distance, Distance::Absolute);
                let result = self.motion(motion, statement.span, false);
                self.distance = distance;
                let motion = std::mem::take(motion);
                match result {
                    Ok(true) => return out.push(statement.with_kind(Kind::Motion(motion))),
                    Ok(false) => return,
                    Err(diagnostic) => return out.error(&statement, diagnostic),
                }
            }
            _ => {}
        }
        out.push(statement);
    }

    /// An arc rewritten by [`Absolute::motion`] that is a spiral, from
    /// `start`: it goes out as straight feeds along the spiral LinuxCNC
    /// runs, its radius changing evenly with the angle from the start's to
    /// the end's (and its helix's height too), no further than the output's
    /// arc tolerance from it, as no controller's G02/G03 draws a spiral.
    fn spiral(&mut self, start: [f64; 3], arc: &Statement, out: &mut Out) {
        let Kind::Motion(motion) = &arc.kind else { unreachable!("a spiral is an arc") };
        let (a, b, normal) = self.plane.axes();
        let offset = |axis: usize| motion.centre.get(axis).map_or(0.0, |v| v.value);
        let end = self.position;
        let ccw = motion.mode == Some(MotionMode::ArcCcw);
        let centre = [start[a] + offset(a), start[b] + offset(b)];
        let (_, sweep) = arc_sweep((start[a], start[b]), (end[a], end[b]), (centre[0], centre[1]), ccw);
        let points = arc_as_lines(
            [start[a], start[b], start[normal]],
            centre,
            [end[a], end[b], end[normal]],
            sweep,
            // Half the tolerance: the written digits' rounding has the rest.
            self.units.arc_tolerance() / 2.0,
            MOST_SPIRAL_PIECES,
        );
        for (k, point) in points.into_iter().enumerate() {
            let mut target = Axes::default();
            for (axis, value) in [(a, point[0]), (b, point[1]), (normal, point[2])] {
                *target.slot(axis) = Some(Value { value, span: arc.span });
            }
            let feed = if k == 0 { motion.feed } else { None };
            let line = Motion { mode: Some(MotionMode::Linear), target, feed, ..Motion::default() };
            out.push(arc.with_kind(Kind::Motion(Box::new(line))));
        }
    }

    /// LinuxCNC's `G02 ... P n`: the arc goes round n - 1 more times before
    /// it ends, its helix spread evenly over the whole turn. It comes out as
    /// n - 1 full circles about its centre and then the arc as written, each
    /// descending its share.
    fn arc_around(&mut self, statement: Statement, turns: u32, out: &mut Out) {
        let start = self.position;
        let mut arc = statement.clone();
        let Kind::Motion(motion) = &mut arc.kind else { unreachable!("an arc's turns") };
        match self.motion(motion, statement.span, false) {
            Ok(true) => {}
            Ok(false) => return,
            Err(diagnostic) => return out.error(&statement, diagnostic),
        }
        let end = self.position;
        let (a, b, normal) = self.plane.axes();
        let offset = |axis: usize| motion.centre.get(axis).map_or(0.0, |v| v.value);
        let centre = (start[a] + offset(a), start[b] + offset(b));
        let ccw = motion.mode == Some(MotionMode::ArcCcw);
        let (_, sweep) = arc_sweep((start[a], start[b]), (end[a], end[b]), centre, ccw);
        let whole = sweep.abs() + std::f64::consts::TAU * f64::from(turns - 1);
        let mut feed = motion.feed.take();
        for turn in 1..turns {
            let mut circle =
                Motion { mode: motion.mode, centre: motion.centre, feed: feed.take(), ..Motion::default() };
            let depth = start[normal] + (end[normal] - start[normal]) * std::f64::consts::TAU * f64::from(turn) / whole;
            for (axis, value) in [(a, start[a]), (b, start[b]), (normal, depth)] {
                *circle.target.slot(axis) = Some(Value { value, span: statement.span });
            }
            out.push(statement.with_kind(Kind::Motion(Box::new(circle))));
        }
        motion.feed = feed;
        out.push(arc);
    }

    /// A rapid move to `target` (machine coordinates), if it goes anywhere.
    fn rapid_to(&mut self, target: [f64; 3], statement: &Statement, out: &mut Out) {
        self.move_to(MotionMode::Rapid, target, statement, out);
    }

    /// A straight move in machine coordinates, written only when it moves.
    fn move_to(&mut self, mode: MotionMode, target: [f64; 3], statement: &Statement, out: &mut Out) {
        let mut motion = Motion { mode: Some(mode), ..Motion::default() };
        for (axis, (&to, &from)) in target.iter().zip(&self.position).enumerate() {
            if to != from {
                *motion.target.slot(axis) = Some(Value { value: to, span: statement.span });
            }
        }
        if !motion.moves() {
            return;
        }
        if mode != MotionMode::Rapid && self.feed != self.feed_written {
            self.feed_written = self.feed;
            motion.feed = self.feed.map(|value| Value { value, span: statement.span });
        }
        self.position = target;
        self.splines.series = None;
        out.push(statement.with_kind(Kind::Motion(Box::new(motion))));
    }

    /// G28/G30: through the intermediate point, then to the reference, for
    /// the axes given (all three if none).
    fn home(&mut self, reference: Reference, via: Axes, statement: &Statement, out: &mut Out) {
        let mut through = self.position;
        for (axis, through) in through.iter_mut().enumerate() {
            if let Some(v) = via.get(axis) {
                *through = self.absolute(axis, v).value;
            }
        }
        self.rapid_to(through, statement, out);
        let point = match reference {
            Reference::Home => self.home,
            Reference::Second => self.second_reference,
        };
        let mut target = through;
        for axis in 0..3 {
            if via.is_empty() || via.get(axis).is_some() {
                target[axis] = point[axis];
            }
        }
        self.rapid_to(target, statement, out);
    }
}

#[cfg(test)]
mod tests {
    use crate::config::Config;
    use crate::passes::testing::{run, run_with};
    use crate::statement::Units;

    #[test]
    fn incremental_moves_become_absolute() {
        let got = run("G01 X1 Y1 F10\nG91\nX1\nY-2 Z-0.5\nG90\nX0", 4);
        assert_eq!(got, ["G01 X1.0000 Y1.0000 F10.0000", "G01 X2.0000", "G01 Y-1.0000 Z-0.5000", "G01 X0.0000"]);
    }

    #[test]
    fn r_arcs_become_ijk_short_and_long() {
        // Quarter circle about the origin from (1,0) to (0,1), short way CCW.
        let got = run("G00 X1\nG03 X0 Y1 R1 F10\nG00 X1 Y0\nG03 X0 Y1 R-1", 4);
        assert_eq!(got[1], "G03 X0.0000 Y1.0000 I-1.0000 J0.0000 F10.0000");
        // Long way CCW: centre at (1,1), I=0 J=1 from (1,0).
        assert_eq!(got[3], "G03 X0.0000 Y1.0000 I0.0000 J1.0000");
    }

    #[test]
    fn full_circles_and_helices() {
        let got = run("G00 X1\nG02 I-1 Z-0.25 F5", 4);
        assert_eq!(got[1], "G02 X1.0000 Y0.0000 Z-0.2500 I-1.0000 J0.0000 F5.0000");
        assert_eq!(run("G00 X1\nG02 X1 R1 F5", 4)[1], "2:8: error: a full circle cannot be given with R");
    }

    #[test]
    fn an_arc_goes_round_p_times_or_runs_l_times() {
        use crate::statement::Dialect;
        let lenient = Config { dialect: Dialect::Lenient.into(), units: Units::Mm, ..Config::default() };
        // LinuxCNC's P3: from (10, 0) a half circle about the origin to
        // (-10, 0) going round two more times, Z 0 to -5 over 2.5 turns:
        // each full turn takes 2 mm, the half turn the last 1 mm.
        let got = run_with(
            "G0 X10
G03 X-10 I-10 Z-5 P3 F100",
            &lenient,
            4,
        );
        assert_eq!(
            got[1..],
            [
                "G03 X10.000 Y0.000 Z-2.000 I-10.000 J0.000 F100.000",
                "G03 X10.000 Y0.000 Z-4.000 I-10.000 J0.000",
                "G03 X-10.000 Y0.000 Z-5.000 I-10.000 J0.000",
            ]
        );
        // Haas's and Fadal's L3 in G91: a full circle dropping 0.2 mm, three times.
        let got = run_with(
            "G0 X10
G91 G02 I-10 Z-0.2 L3 F100",
            &lenient,
            4,
        );
        assert_eq!(
            got[1..],
            [
                "G02 X10.000 Y0.000 Z-0.200 I-10.000 J0.000 F100.000",
                "G02 X10.000 Y0.000 Z-0.400 I-10.000 J0.000",
                "G02 X10.000 Y0.000 Z-0.600 I-10.000 J0.000",
            ]
        );
        assert!(run_with("G02 I1 P0 F1", &lenient, 4)[0].ends_with("P on G02 is the times it goes round: 1 to 10000"));
        assert!(run_with("G02 I1 P2 L2 F1", &lenient, 4)[0]
            .contains("takes P (turns, LinuxCNC) or L (repeats, Haas), not both"));
    }

    #[test]
    fn arcs_in_other_planes_use_their_own_centre_words() {
        // G18 (ZX): from (0,0,0) a half circle to Z2 about Z1.
        let got = run("G18\nG02 Z2 K1 F1", 4);
        assert_eq!(got, ["G18", "G02 X0.0000 Z2.0000 I0.0000 K1.0000 F1.0000"]);
        assert_eq!(run("G19\nG02 Y2 I1 F1", 4)[1], "2:8: error: I is not used for arcs in the G19 plane");
    }

    #[test]
    fn arc_errors() {
        assert_eq!(
            run("G02 X1 Y0 I0.3 F1", 4),
            ["1:1: error: arc end is not on the circle: radius 0.3000 in at the start, 0.7000 in at the end"]
        );
        assert_eq!(run("G02 X1 F1", 4), ["1:1: error: arc without a centre: give I and J, or R"]);
        assert_eq!(
            run("G02 X3 R1 F1", 4),
            ["1:8: error: R is too small for this arc: its end is 3.0000 in from its start, more than twice the radius (1.0000 in)"]
        );
    }

    #[test]
    fn feed_is_required_once_and_written_when_it_changes() {
        assert_eq!(run("G01 X1", 4), ["1:1: error: G01 move before any feed rate (F)"]);
        let got = run("F20\nG00 X1\nG01 X2\nX3 F20\nX4 F30\nG00 X0\nG01 X1", 4);
        assert_eq!(
            got,
            [
                "G00 X1.0000",
                "G01 X2.0000 F20.0000",
                "G01 X3.0000",
                "G01 X4.0000 F30.0000",
                "G00 X0.0000",
                "G01 X1.0000"
            ]
        );
    }

    #[test]
    fn f0_is_a_feed_of_zero_that_no_feed_move_may_run_at() {
        // As rs274: `F0` alone is taken; a feed move, an arc or a cycle at it is refused.
        let lenient =
            Config { dialect: crate::statement::Dialect::Lenient.into(), units: Units::Mm, ..Config::default() };
        let got = run_with("G21 F0 G64\nG00 X1\nG01 X2\nG02 X4 I1\nG81 X5 Z-1 R1\nF10\nG01 X3", &lenient, 4);
        assert_eq!(
            got,
            [
                "G00 X1.000",
                "3:1: error: G01 move at a feed rate of zero (F0)",
                "4:1: error: G02 move at a feed rate of zero (F0)",
                "5:1: error: G81 at a feed rate of zero (F0)",
                "G01 X3.000 F10.000"
            ]
        );
        // The GER dialect keeps F a speed: zero is an error where it is written.
        assert_eq!(run("F0", 4), ["1:1: error: the feed rate must be greater than zero"]);
    }

    #[test]
    fn every_arc_linuxcnc_refuses_for_its_radii_is_refused() {
        // LinuxCNC refuses a centre-format arc whose radii at the start and
        // the end differ by more than 2 * 0.001 in * sqrt 2 (G20) or
        // 2 * 0.01 mm * sqrt 2 (G21) and by more than 0.1% of the larger, or
        // by more than 100 times that whatever the radius: the least error it
        // refuses is just over 0.002828 in or 0.02828 mm. ger's limit, 0.0005 in
        // or 0.01 mm in the machine's unit, is under both in either unit, so
        // whatever LinuxCNC refuses, ger refuses. Here arcs of radius about 1
        // (so 0.1% is far below the error) with radii differing by just over
        // that least error, in both program units on both machines.
        for machine in [Units::Inch, Units::Mm] {
            let config = Config { units: machine, ..Default::default() };
            for (code, least) in [("G20", 0.002 * 2f64.sqrt()), ("G21", 0.02 * 2f64.sqrt())] {
                // From X0 to X2 about X=i: r1 = i, r2 = 2 - i, so r2 - r1 = 1.0002 * least.
                let i = 1.0 - 0.5001 * least;
                let program = format!("{code}\nG00 X0 Y0\nG02 X2 I{i:.10} F1");
                let got = run_with(&program, &config, 4);
                let refused = got.iter().any(|l| l.contains("error: arc end is not on the circle"));
                assert!(refused, "{program} on a {machine:?} machine: {got:?}");
            }
        }
    }

    #[test]
    fn the_lenient_dialect_takes_an_arc_within_a_thousandth_of_its_larger_radius_as_linuxcncs_spiral() {
        // LinuxCNC's relative error is the radii's difference over the larger
        // of the two. About (999.5, 0) from the origin to (2000, 0): radii
        // 999.5 and 1000.5, 1 mm apart, a thousandth of 1000.5 less a hair
        // (under the 100 x 0.0283 mm cap): LinuxCNC takes it, and runs a
        // spiral whose radius grows evenly with the angle, clockwise over the
        // top, Z going down with it. 2000.002 makes the radii 1.002 apart, over
        // a thousandth of 1000.502: refused.
        use crate::statement::Dialect;
        let lenient = Config { dialect: Dialect::Lenient.into(), units: Units::Mm, ..Config::default() };
        let arc = |end: &str| run_with(&format!("G21 G17\nG00 X0 Y0 Z0\nG02 X{end} Z-2 I999.5 F100"), &lenient, 4);
        let taken = arc("2000");
        let points: Vec<[f64; 3]> = taken[1..]
            .iter()
            .map(|line| {
                assert!(line.starts_with("G01 "), "{taken:?}");
                let word = |l: char| line.split(' ').find_map(|w| w.strip_prefix(l)).unwrap().parse::<f64>().unwrap();
                [word('X'), word('Y'), word('Z')]
            })
            .collect();
        assert!(points.len() > 100, "{taken:?}");
        assert_eq!(points.last(), Some(&[2000.0, 0.0, -2.0]));
        let mut last = [0.0, 0.0, 0.0];
        for p in points {
            let angle = p[1].atan2(p[0] - 999.5);
            let turned = std::f64::consts::PI - angle;
            let radius = 999.5 + turned / std::f64::consts::PI;
            // On the spiral (to the output's 3 decimals), at the height it has come down to.
            assert!(((p[0] - 999.5).hypot(p[1]) - radius).abs() < 0.001, "{p:?}");
            assert!((p[2] + 2.0 * turned / std::f64::consts::PI).abs() < 0.001, "{p:?}");
            // A chord's middle no further than the output's 0.01 mm from the spiral.
            let middle = [(p[0] + last[0]) / 2.0, (p[1] + last[1]) / 2.0];
            let (mid_angle, mid_radius) = (middle[1].atan2(middle[0] - 999.5), (middle[0] - 999.5).hypot(middle[1]));
            let on_spiral = 999.5 + (std::f64::consts::PI - mid_angle) / std::f64::consts::PI;
            assert!((mid_radius - on_spiral).abs() <= 0.01, "{last:?} -> {p:?}");
            assert!(p[1] >= 0.0, "clockwise from the left goes over the top: {p:?}");
            last = p;
        }
        let refused = arc("2000.002");
        assert!(refused.iter().any(|l| l.contains("error: arc end is not on the circle")), "{refused:?}");
        // Radii within the output's tolerance (0.008 apart) leave the arc an arc, as written.
        let near = run_with("G21 G17\nG00 X0 Y0\nG02 X2 I1.004 F100", &lenient, 4);
        assert!(near[1].starts_with("G02 X2.000 Y0.000 I1.004 J0.000"), "{near:?}");
    }

    #[test]
    fn a_repeated_plane_is_dropped() {
        assert_eq!(run("G17\nG18\nG18\nG17", 4), ["G18", "G17"]);
    }
}
