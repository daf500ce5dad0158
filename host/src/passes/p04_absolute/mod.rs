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
use crate::geom::{centre_from_radius, RadiusArcError};
use crate::state::{Probe, Spindle};
use crate::statement::{Axes, Distance, Kind, Machine, Motion, MotionMode, Plane, Reference, Statement, Units, Value};

mod cycles;
mod splines;

pub struct Absolute {
    units: Units,
    distance: Distance,
    plane: Plane,
    position: [f64; 3],
    feed: Option<f64>,
    /// The feed the output last said, so F is written only when it changes.
    feed_written: Option<f64>,
    probe: Probe,
    /// G30's point, in machine coordinates.
    second_reference: [f64; 3],
    /// The lenient dialect's S and T words alone: a speed and a tool waiting
    /// for the M03/M04 and M06 that use them.
    speed: Option<f64>,
    selected_tool: Option<u32>,
    cycles: cycles::CycleState,
    splines: splines::SplineState,
}

impl Absolute {
    pub fn new(config: &Config, probe: Probe) -> Absolute {
        Absolute {
            units: config.units,
            distance: Distance::Absolute,
            plane: Plane::XY,
            position: [0.0; 3],
            feed: None,
            feed_written: None,
            probe,
            second_reference: config.machine.second_reference,
            speed: None,
            selected_tool: None,
            cycles: cycles::CycleState::default(),
            splines: splines::SplineState::new(config),
        }
    }

    /// F for a feed move that starts here: the feed in force, if the output
    /// has not said it yet.
    fn feed_word(&mut self, span: Span) -> Option<Value> {
        if self.feed == self.feed_written {
            return None;
        }
        self.feed_written = self.feed;
        self.feed.map(|value| Value { value, span })
    }

    fn absolute(&self, axis: usize, v: Value) -> Value {
        match self.distance {
            Distance::Absolute => v,
            Distance::Incremental => Value { value: self.position[axis] + v.value, ..v },
        }
    }

    /// The arc's centre offsets from its start (I/J/K), or why it has none.
    fn arc_centre(&self, motion: &Motion, end: [f64; 3], span: Span) -> Result<Axes, Diagnostic> {
        let (a, b, normal) = self.plane.axes();
        let letters = ['I', 'J', 'K'];
        if let Some(v) = motion.centre.get(normal) {
            let plane = self.plane.code();
            let message = format!("{} is not used for arcs in the {plane} plane", letters[normal]);
            return Err(Diagnostic::error(v.span, message)
                .with_help(format!("in {plane} the centre is given by {} and {}", letters[a], letters[b])));
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
            return Ok(offsets);
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
        if (start_radius - end_radius).abs() > tolerance {
            let message = format!(
                "arc end is not on the circle: radius {start_radius:.d$} {u} at the start, {end_radius:.d$} {u} at the end"
            );
            let help = format!("the two must agree within {tolerance} {u}; check the end point and the centre offsets");
            return Err(Diagnostic::error(span, message).with_help(help));
        }
        let mut offsets = motion.centre;
        offsets.slot(a).get_or_insert(Value { value: 0.0, span });
        offsets.slot(b).get_or_insert(Value { value: 0.0, span });
        Ok(offsets)
    }

    /// Rewrites a move in place. `Ok(false)`: it only set the feed, drop it.
    fn motion(&mut self, motion: &mut Motion, span: Span) -> Result<bool, Diagnostic> {
        let mode = motion.mode.expect("pass 00 gives every move its mode");
        if let Some(f) = motion.feed {
            self.feed = Some(f.value);
        }
        if !motion.moves() {
            return Ok(false);
        }
        if mode != MotionMode::Rapid && self.feed.is_none() {
            let diagnostic = Diagnostic::error(span, format!("{} move before any feed rate (F)", mode.code()))
                .with_help(format!("give the feed on this move or before it, e.g. {} ... F10", mode.code()));
            return Err(diagnostic);
        }
        let mut end = self.position;
        for (axis, end) in end.iter_mut().enumerate() {
            if let Some(v) = motion.target.slot(axis) {
                *v = self.absolute(axis, *v);
                *end = v.value;
            }
        }
        if mode.is_arc() {
            motion.centre = self.arc_centre(motion, end, span)?;
            motion.radius = None;
            // An arc states both of its plane's axes, whatever was written.
            let (a, b, _) = self.plane.axes();
            for axis in [a, b] {
                motion.target.slot(axis).get_or_insert(Value { value: end[axis], span });
            }
        }
        motion.feed = if mode == MotionMode::Rapid { None } else { self.feed_word(span) };
        self.position = end;
        self.splines.series = None;
        Ok(true)
    }
}

impl Pass for Absolute {
    fn statement(&mut self, statement: Statement, out: &mut Out) {
        self.close_nurbs_before(&statement, out);
        self.rewrite(statement, out);
        let mut probe = self.probe.borrow_mut();
        probe.position = self.position;
        probe.distance = self.distance;
        probe.plane = self.plane;
        probe.feed = self.feed;
    }

    fn finish(&mut self, out: &mut Out) {
        self.unfinished_nurbs(out);
    }
}

impl Absolute {
    fn rewrite(&mut self, mut statement: Statement, out: &mut Out) {
        if let Kind::Cycle(cycle) = &statement.kind {
            if let Err(diagnostic) = self.cycle(cycle, &statement, out) {
                out.error(&statement, diagnostic);
            }
            return;
        }
        let drawn = match &statement.kind {
            Kind::Spline(spline) => Some(self.spline(spline, &statement, out)),
            Kind::NurbsEnd => Some(self.nurbs_end(&statement, out)),
            _ => None,
        };
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
            Kind::Motion(motion) => match self.motion(motion, statement.span) {
                Ok(true) => {}
                Ok(false) => return,
                Err(diagnostic) => return out.error(&statement, diagnostic),
            },
            Kind::ToolLength { z, h, .. } => {
                *h = h.or(Some(self.probe.borrow().tool));
                if let Some(z) = z {
                    *z = self.absolute(2, *z);
                    self.position[2] = z.value;
                }
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
                self.cycles.retract = *retract;
                return;
            }
            Kind::Home { reference, via } => {
                let (reference, via) = (*reference, *via);
                return self.home(reference, via, &statement, out);
            }
            Kind::MachineMove(motion) => {
                // Machine coordinates are absolute whatever G90/G91 says.
                let distance = std::mem::replace(&mut self.distance, Distance::Absolute);
                let result = self.motion(motion, statement.span);
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
        if mode != MotionMode::Rapid {
            motion.feed = self.feed_word(statement.span);
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
            Reference::Home => [0.0; 3],
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
    fn a_repeated_plane_is_dropped() {
        assert_eq!(run("G17\nG18\nG18\nG17", 4), ["G18", "G17"]);
    }
}
