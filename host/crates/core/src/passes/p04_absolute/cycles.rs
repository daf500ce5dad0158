//! Canned cycles (lenient dialect), expanded to rapids, feeds and dwells with
//! LinuxCNC's meaning: at each position the tool rapids over the hole (first
//! up to the R plane if it is below it), down to R, cuts to Z in the cycle's
//! way, and retracts to the level where the series of cycles began (G98, but
//! never below R; LinuxCNC's initial level, kept from one cycle code to the
//! next until G80 or another move) or to R (G99).
//! In G91, R is measured from the series' initial level (for every cycle
//! block of the series, as LinuxCNC and Fanuc measure it, not from where the
//! tool is after a G99 retract) and Z from R, and each of the L repeats steps
//! X/Y again. Z, R, Q and P carry over from one
//! cycle to the next, so `X10` after a `G81` drills another hole alike.

use super::Absolute;
use crate::diag::Diagnostic;
use crate::passes::Out;
use crate::state::Spindle;
use crate::statement::{Cycle, CycleCode, Distance, Kind, Machine, MotionMode, Retract, Statement, Units};

#[derive(Default)]
pub struct CycleState {
    /// G98 or G99, once the program has given one.
    pub retract: Option<Retract>,
    /// Z and R as the program wrote them (absolute ones less program zero):
    /// LinuxCNC carries the number over, read in the distance mode of the
    /// cycle that uses it.
    z: Option<f64>,
    r: Option<f64>,
    q: Option<f64>,
    p: Option<f64>,
    /// Where along the hole's axis the series of cycles began: G98 retracts there.
    pub initial: Option<f64>,
    /// The holes of the cycle block being expanded, made one at a time.
    pending: Option<Holes>,
}

impl CycleState {
    /// A move that is not a cycle's, or G80: the initial level goes, and so
    /// does R (LinuxCNC refuses the next series without one; a Fanuc starts
    /// it at its initial level).
    pub fn end_series(&mut self) {
        self.initial = None;
        self.r = None;
    }
}

/// A cycle block's holes still to drill: its L repeats share the levels
/// worked out where the block began.
struct Holes {
    statement: Statement,
    left: u32,
    /// The series' initial level.
    initial: f64,
    r_plane: f64,
    bottom: f64,
    q: Option<f64>,
    p: Option<f64>,
}

/// How far a peck backs off (G73), or stops above the last peck (G83): LinuxCNC's 0.010 in.
fn peck_clearance(units: Units) -> f64 {
    0.01 * Units::Inch.factor_to(units)
}

/// The most pecks one hole may take: a hole's moves are made at once, so a
/// Q far too small for the depth is an error, not an endless expansion.
pub const MAX_PECKS: f64 = 10_000.0;

impl Absolute {
    /// Reads a cycle block: its words (carried over from the cycle before
    /// where not given) and levels. The holes are made by [`Absolute::next_hole`].
    pub(super) fn cycle(&mut self, cycle: &Cycle, statement: &Statement) -> Result<(), Diagnostic> {
        let code = cycle.code.code();
        // The hole runs along the plane's normal: Z in G17, Y in G18, X in G19.
        let n = self.plane.axes().2;
        // Pass 02 has put absolute levels in machine coordinates.
        let zero = match self.distance {
            Distance::Absolute => self.probe.borrow().prz[n],
            Distance::Incremental => 0.0,
        };
        let sticky = &mut self.cycles;
        let given = |v: Option<crate::statement::Value>, keep: &mut Option<f64>, zero: f64| {
            if let Some(v) = v {
                *keep = Some(v.value - zero);
            }
            keep.map(|number| number + zero)
        };
        let z = given(cycle.target.get(n), &mut sticky.z, zero);
        let initial = sticky.initial.unwrap_or(self.position[n]);
        if cycle.r.is_none() && sticky.r.is_none() {
            // Fanuc and Haas read an R not given as the initial level (in
            // G91 its distance from there, 0): the hole is fed from where the
            // tool is. LinuxCNC refuses the block.
            sticky.r = Some(match self.distance {
                Distance::Absolute => initial - zero,
                Distance::Incremental => 0.0,
            });
            let (u, d) = (self.units.abbreviation(), self.units.decimals());
            let message = format!(
                "{code} has no R word: it feeds from the level where it starts, {depth_axis}{:.d$} {u}",
                initial - zero,
                depth_axis = ["X", "Y", "Z"][n]
            );
            let help = format!(
                "as a Fanuc or Haas reads it; write R (e.g. {code} ... R0.1) for a rapid down to the R level first"
            );
            self.warnings.push(Diagnostic::warning(statement.span, message).with_help(help));
        }
        let r = given(cycle.r, &mut sticky.r, zero);
        let q = given(cycle.q, &mut sticky.q, 0.0);
        let p = given(cycle.p, &mut sticky.p, 0.0);
        if let Some(f) = cycle.feed {
            self.feed = Some(f.value);
        }
        let missing = |what: &str| {
            Diagnostic::error(statement.span, format!("{code} needs {what}"))
                .with_help(format!("write e.g. {code} X.. Y.. Z-1 R0.1 F10 (Q for pecking, P for dwelling)"))
        };
        let depth = ["X", "Y", "Z"][n];
        let (z, r) = (
            z.ok_or_else(|| {
                missing(&format!("{} {depth} word: the bottom of the hole", if n == 0 { "an" } else { "a" }))
            })?,
            r.expect("an R not given is the initial level"),
        );
        let q = match cycle.code {
            CycleCode::Peck | CycleCode::ChipBreak => Some(q.ok_or_else(|| missing("a Q word: the peck depth"))?),
            _ => None,
        };
        let p = match cycle.code {
            // Without P, no dwell, as a Fanuc or Haas (LinuxCNC requires it for G82, G86 and G89).
            CycleCode::DrillDwell | CycleCode::BoreSpindleStop | CycleCode::BoreDwell => Some(p.unwrap_or(0.0)),
            CycleCode::Tap | CycleCode::TapLeft => p,
            _ => None,
        };
        if self.feed.is_none_or(|feed| feed <= 0.0) {
            let before = if self.feed.is_none() { "before any feed rate (F)" } else { "at a feed rate of zero (F0)" };
            return Err(Diagnostic::error(statement.span, format!("{code} {before}"))
                .with_help(format!("give the feed on the cycle, e.g. {code} ... F10")));
        }
        if self.cycles.retract.is_none() {
            // LinuxCNC starts in G99; a Fanuc or Haas in G98. Said once.
            self.cycles.retract = Some(Retract::RPlane);
            let message =
                format!("{code} with neither G98 nor G99 given: it retracts to R between holes, as LinuxCNC starts");
            let help = "a Fanuc or Haas starts in G98 (back to the initial level): write G98 or G99 to say which";
            self.warnings.push(Diagnostic::warning(statement.span, message).with_help(help));
        }
        self.cycles.initial = Some(initial);
        let (r_plane, bottom) = match self.distance {
            Distance::Absolute => (r, z),
            Distance::Incremental => (initial + r, initial + r + z),
        };
        if bottom > r_plane {
            return Err(Diagnostic::error(statement.span, format!("{code}: the bottom {depth} is above the R plane"))
                .with_help(format!("{depth} is the bottom of the hole and must be below R")));
        }
        if let Some(q) = q.filter(|q| (r_plane - bottom) / q > MAX_PECKS) {
            let (u, d) = (self.units.abbreviation(), self.units.decimals());
            let message = format!(
                "{code}: pecks of {q:.d$} {u} down {:.d$} {u} make more than {MAX_PECKS} pecks",
                r_plane - bottom
            );
            return Err(
                Diagnostic::error(statement.span, message).with_help("Q is the depth of each peck: give a larger one")
            );
        }
        // L0 (Fanuc's K0) keeps the cycle's words and drills nothing.
        if cycle.repeat > 0 {
            let statement = statement.clone();
            self.cycles.pending = Some(Holes { statement, left: cycle.repeat, initial, r_plane, bottom, q, p });
        }
        Ok(())
    }

    /// Drills the next hole of the cycle block being expanded; false when
    /// there is none. In G91 each repeat steps X/Y again.
    pub(super) fn next_hole(&mut self, out: &mut Out) -> bool {
        let Some(mut holes) = self.cycles.pending.take() else { return false };
        let Kind::Cycle(cycle) = &holes.statement.kind else { unreachable!("holes come from a cycle") };
        let statement = &holes.statement;
        let (a, b, n) = self.plane.axes();
        let (r_plane, bottom) = (holes.r_plane, holes.bottom);
        let mut over_hole = self.position;
        for axis in [a, b] {
            if let Some(v) = cycle.target.get(axis) {
                over_hole[axis] = self.absolute(axis, v).value;
            }
        }
        let clear = match self.cycles.retract.unwrap_or(Retract::RPlane) {
            Retract::Initial => holes.initial.max(r_plane),
            Retract::RPlane => r_plane,
        };
        let at = |depth: f64| {
            let mut point = over_hole;
            point[n] = depth;
            point
        };
        if self.position[n] < r_plane {
            let mut up = self.position;
            up[n] = r_plane;
            self.rapid_to(up, statement, out);
        }
        self.rapid_to(at(self.position[n].max(r_plane)), statement, out);
        self.rapid_to(at(r_plane), statement, out);
        let clearance = peck_clearance(self.units);
        match cycle.code {
            CycleCode::Drill => self.move_to(MotionMode::Linear, at(bottom), statement, out),
            CycleCode::DrillDwell => {
                self.move_to(MotionMode::Linear, at(bottom), statement, out);
                self.dwell(holes.p, statement, out);
            }
            CycleCode::Peck | CycleCode::ChipBreak => {
                let q = holes.q.expect("checked with the block");
                let mut depth = r_plane;
                loop {
                    let next = (depth - q).max(bottom);
                    self.move_to(MotionMode::Linear, at(next), statement, out);
                    if next <= bottom {
                        break;
                    }
                    if cycle.code == CycleCode::Peck {
                        self.rapid_to(at(r_plane), statement, out);
                    }
                    self.rapid_to(at(next + clearance), statement, out);
                    depth = next;
                }
            }
            CycleCode::Bore => {
                self.move_to(MotionMode::Linear, at(bottom), statement, out);
                self.move_to(MotionMode::Linear, at(r_plane), statement, out);
            }
            CycleCode::BoreSpindleStop => {
                self.move_to(MotionMode::Linear, at(bottom), statement, out);
                self.dwell(holes.p, statement, out);
                let restart = self.probe.borrow().spindle;
                self.spindle(Machine::SpindleOff, None, statement, out);
                self.rapid_to(at(clear), statement, out);
                match restart {
                    Spindle::Clockwise(s) => self.spindle(Machine::SpindleCw, s, statement, out),
                    Spindle::CounterClockwise(s) => self.spindle(Machine::SpindleCcw, s, statement, out),
                    Spindle::Off => {}
                }
            }
            CycleCode::BoreDwell => {
                self.move_to(MotionMode::Linear, at(bottom), statement, out);
                self.dwell(holes.p, statement, out);
                self.move_to(MotionMode::Linear, at(clear), statement, out);
            }
            // LinuxCNC's G84: feed in, reverse the spindle, dwell, feed out
            // all the way to the retract level, turn the spindle back.
            CycleCode::Tap | CycleCode::TapLeft => {
                let (inward, outward) = match cycle.code {
                    CycleCode::Tap => (Machine::SpindleCw, Machine::SpindleCcw),
                    _ => (Machine::SpindleCcw, Machine::SpindleCw),
                };
                let speed = match self.probe.borrow().spindle {
                    Spindle::Clockwise(s) | Spindle::CounterClockwise(s) => s,
                    Spindle::Off => None,
                };
                self.move_to(MotionMode::Linear, at(bottom), statement, out);
                self.spindle(outward, speed, statement, out);
                self.dwell(holes.p, statement, out);
                self.move_to(MotionMode::Linear, at(clear), statement, out);
                self.spindle(inward, speed, statement, out);
            }
        }
        self.rapid_to(at(clear), statement, out);
        holes.left -= 1;
        if holes.left > 0 {
            self.cycles.pending = Some(holes);
        }
        true
    }

    fn dwell(&mut self, seconds: Option<f64>, statement: &Statement, out: &mut Out) {
        if let Some(seconds) = seconds.filter(|s| *s > 0.0) {
            out.push(statement.with_kind(Kind::Dwell(seconds)));
        }
    }

    fn spindle(&mut self, code: Machine, s: Option<f64>, statement: &Statement, out: &mut Out) {
        self.rewrite(statement.with_kind(Kind::Machine { code, s, t: None }), out);
    }
}

#[cfg(test)]
mod tests {
    use crate::config::{Config, WorkOffsets};
    use crate::passes::testing::run_with;
    use crate::statement::{Dialect, Units};

    #[test]
    fn g98_retracts_to_where_the_series_began_until_g80() {
        // As rs274 runs it: the G99 series ends at R2, and the G98 series
        // after G80 begins there, so the G82 with R5 retracts to R5 and the
        // next hole, with R1, to Z2, where the series began (not to Z5,
        // where its block began).
        let config = Config { units: Units::Mm, dialect: Dialect::Lenient.into(), ..Config::default() };
        let program = "G00 Z10\nG99 G81 X1 Z-2 R2 F100\nG80\nG98 G81 X2 Z-2 R1\nG82 X3 Z-2 R5 P1\nX4 R1";
        let got = run_with(program, &config, 4);
        let retracts: Vec<&str> = got
            .iter()
            .zip(got.iter().skip(1))
            .filter(|(_, next)| next.starts_with("G00 X"))
            .map(|(r, _)| r.as_str())
            .collect();
        // Before each hole: the start, the G99 retract, the climb to R5, its retract.
        assert_eq!(retracts, ["G00 Z10.000", "G00 Z2.000", "G00 Z5.000", "G00 Z5.000"]);
        assert_eq!(got.last().unwrap(), "G00 Z2.000");
    }

    #[test]
    fn a_series_without_r_feeds_from_its_initial_level_as_a_fanuc_does() {
        // From Z5: no R, so R is Z5 (G90) or 0 from there (G91): each hole is
        // fed from Z5 and the retract is to Z5. G82 with no P does not dwell.
        // After G80 the next series starts at its own level, not at the R before.
        let config = Config { units: Units::Mm, dialect: Dialect::Lenient.into(), ..Config::default() };
        let program =
            "G00 Z5\nG98 G82 X1 Z-2 F100\nX2\nG80\nG00 Z3\nG91 G81 X1 Z-4\nG90 G80\nG81 X9 Z-1 R2\nG80\nG81 X8 Z-1";
        let got = run_with(program, &config, 4);
        let warnings = got.iter().filter(|l| l.contains("warning: G8")).count();
        let moves: Vec<&str> = got.iter().filter(|l| l.starts_with('G')).map(String::as_str).collect();
        assert_eq!(
            moves,
            [
                "G00 Z5.000",
                "G00 X1.000",
                "G01 Z-2.000 F100.000",
                "G00 Z5.000",
                "G00 X2.000",
                "G01 Z-2.000",
                "G00 Z5.000",
                "G00 Z3.000",
                "G00 X3.000",
                "G01 Z-1.000",
                "G00 Z3.000",
                "G00 X9.000",
                "G00 Z2.000",
                "G01 Z-1.000",
                "G00 Z3.000",
                "G00 X8.000",
                "G01 Z-1.000",
                "G00 Z3.000",
            ],
            "{got:?}"
        );
        // One warning a series that has no R: three.
        assert_eq!(warnings, 3, "{got:?}");
    }

    #[test]
    fn without_g98_or_g99_a_series_retracts_to_r_as_linuxcnc_starts() {
        // As rs274 runs it with no startup codes: from Z5, back to R1 after each hole; said once.
        let config = Config { units: Units::Mm, dialect: Dialect::Lenient.into(), ..Config::default() };
        let got = run_with("G00 Z5\nG81 X1 Z-2 R1 F100\nX2\nG80\nG81 X3 Z-2 R1", &config, 4);
        let moves: Vec<&str> = got.iter().filter(|l| l.starts_with('G')).map(String::as_str).collect();
        assert_eq!(
            moves,
            [
                "G00 Z5.000",
                "G00 X1.000",
                "G00 Z1.000",
                "G01 Z-2.000 F100.000",
                "G00 Z1.000",
                "G00 X2.000",
                "G01 Z-2.000",
                "G00 Z1.000",
                "G00 X3.000",
                "G01 Z-2.000",
                "G00 Z1.000",
            ]
        );
        assert_eq!(got.iter().filter(|l| l.contains("neither G98 nor G99")).count(), 1, "{got:?}");
    }

    #[test]
    fn in_g91_r_is_measured_from_where_the_series_began() {
        // As rs274 runs it: from Z0.25, every hole of the G99 series (a bare X1, the cycle written
        // again, its L2 repeats) has R at 0.5 and its bottom at -0.5, though the tool waits at R
        // between them; the G98 series from Z0.25 again, R0.5 on its second block, goes to 0.75 and
        // cuts to -0.25.
        let config = Config { dialect: Dialect::Lenient.into(), ..Config::default() };
        let program =
            "F40\nG90 G0 X0 Y0 Z0.25\nG91 G99 G81 X1 Z-1.0 R0.25\nX1\nG81 X1 Z-1.0 R0.25\nG81 X1 Z-1.0 R0.25 L2\n\
                       G90 G0 Z0.25\nG91 G98 G81 X1 Z-1 R0.25\nG81 X1 Z-1 R0.5\nG90 G80";
        let got = run_with(program, &config, 4);
        let levels = |prefix: &str| got.iter().filter(|l| l.starts_with(prefix)).cloned().collect::<Vec<_>>();
        let bottoms = ["G01 Z-0.5000 F40.0000", "G01 Z-0.5000", "G01 Z-0.5000", "G01 Z-0.5000", "G01 Z-0.5000"];
        assert_eq!(levels("G01 Z"), [bottoms.as_slice(), &["G01 Z-0.5000", "G01 Z-0.2500"]].concat());
        assert_eq!(got[got.len() - 4..], ["G00 Z0.7500", "G00 X7.0000", "G01 Z-0.2500", "G00 Z0.7500"]);
    }

    #[test]
    fn carried_over_levels_are_the_numbers_written_read_in_the_new_distance_mode() {
        // G55's Z is -10. The first hole's R2 and Z-3 carry over to a G91
        // cycle as +2 and -3 from where it starts (program Z15): rs274 goes
        // to program Z17 and cuts to Z14, machine Z7 and Z4.
        let offsets = WorkOffsets { g55: Some([100.0, 50.0, -10.0]), ..Default::default() };
        let config = Config { offsets, units: Units::Mm, dialect: Dialect::Lenient.into(), ..Config::default() };
        let program = "G55\nG00 X1 Y1 Z15\nG98 G81 X5 Y5 Z-3 R2 F100\nG91 G81 X1 Y1 L2\nG90 G80";
        let got = run_with(program, &config, 4);
        assert_eq!(
            got[got.len() - 7..],
            [
                "G00 Z7.000",
                "G00 X106.000 Y56.000",
                "G01 Z4.000",
                "G00 Z7.000",
                "G00 X107.000 Y57.000",
                "G01 Z4.000",
                "G00 Z7.000"
            ]
        );
    }
}
