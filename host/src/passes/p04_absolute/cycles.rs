//! Canned cycles (lenient dialect), expanded to rapids, feeds and dwells with
//! LinuxCNC's meaning: at each position the tool rapids over the hole (first
//! up to the R plane if it is below it), down to R, cuts to Z in the cycle's
//! way, and retracts to where it started (G98, but never below R) or to R (G99).
//! In G91, R is measured from the Z where the cycle starts and Z from R, and
//! each of the L repeats steps X/Y again. Z, R, Q and P carry over from one
//! cycle to the next, so `X10` after a `G81` drills another hole alike.

use super::Absolute;
use crate::diag::Diagnostic;
use crate::passes::Out;
use crate::state::Spindle;
use crate::statement::{Cycle, CycleCode, Distance, Kind, Machine, MotionMode, Retract, Statement, Units};

#[derive(Default)]
pub struct CycleState {
    pub retract: Retract,
    z: Option<f64>,
    r: Option<f64>,
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
    pub(super) fn cycle(&mut self, cycle: &Cycle, statement: &Statement, out: &mut Out) -> Result<(), Diagnostic> {
        let code = cycle.code.code();
        let sticky = &mut self.cycles;
        let given = |v: Option<crate::statement::Value>, keep: &mut Option<f64>| {
            if let Some(v) = v {
                *keep = Some(v.value);
            }
            *keep
        };
        let z = given(cycle.target.z, &mut sticky.z);
        let r = given(cycle.r, &mut sticky.r);
        let q = given(cycle.q, &mut sticky.q);
        let p = given(cycle.p, &mut sticky.p);
        if let Some(f) = cycle.feed {
            self.feed = Some(f.value);
        }
        let missing = |what: &str| {
            Diagnostic::error(statement.span, format!("{code} needs {what}"))
                .with_help(format!("write e.g. {code} X.. Y.. Z-1 R0.1 F10 (Q for pecking, P for dwelling)"))
        };
        let (z, r) = (
            z.ok_or_else(|| missing("a Z word: the bottom of the hole"))?,
            r.ok_or_else(|| missing("an R word: the plane it starts from"))?,
        );
        let q = match cycle.code {
            CycleCode::Peck | CycleCode::ChipBreak => Some(q.ok_or_else(|| missing("a Q word: the peck depth"))?),
            _ => None,
        };
        let p = match cycle.code {
            CycleCode::DrillDwell | CycleCode::BoreSpindleStop | CycleCode::BoreDwell => {
                Some(p.ok_or_else(|| missing("a P word: the dwell in seconds"))?)
            }
            CycleCode::Tap | CycleCode::TapLeft => p,
            _ => None,
        };
        if self.feed.is_none() {
            return Err(Diagnostic::error(statement.span, format!("{code} before any feed rate (F)"))
                .with_help(format!("give the feed on the cycle, e.g. {code} ... F10")));
        }
        // Pass 00 streams the L repeats, one cycle statement each; L0
        // (Fanuc's K0) keeps the cycle's words and drills nothing.
        debug_assert!(cycle.repeat <= 1);
        if cycle.repeat == 1 {
            let start_z = self.position[2];
            let (r_plane, bottom) = match self.distance {
                Distance::Absolute => (r, z),
                Distance::Incremental => (start_z + r, start_z + r + z),
            };
            if bottom > r_plane {
                return Err(Diagnostic::error(statement.span, format!("{code}: the bottom Z is above the R plane"))
                    .with_help("Z is the bottom of the hole and must be below R"));
            }
            let mut over_hole = self.position;
            for (axis, coordinate) in over_hole.iter_mut().enumerate().take(2) {
                if let Some(v) = cycle.target.get(axis) {
                    *coordinate = self.absolute(axis, v).value;
                }
            }
            let clear = match self.cycles.retract {
                Retract::Initial => start_z.max(r_plane),
                Retract::RPlane => r_plane,
            };
            let at = |z: f64| [over_hole[0], over_hole[1], z];
            if start_z < r_plane {
                let up = [self.position[0], self.position[1], r_plane];
                self.rapid_to(up, statement, out);
            }
            let travel_z = start_z.max(r_plane);
            self.rapid_to(at(travel_z), statement, out);
            self.rapid_to(at(r_plane), statement, out);
            let clearance = peck_clearance(self.units);
            match cycle.code {
                CycleCode::Drill => self.move_to(MotionMode::Linear, at(bottom), statement, out),
                CycleCode::DrillDwell => {
                    self.move_to(MotionMode::Linear, at(bottom), statement, out);
                    self.dwell(p, statement, out);
                }
                CycleCode::Peck | CycleCode::ChipBreak => {
                    let q = q.expect("checked above");
                    if (r_plane - bottom) / q > MAX_PECKS {
                        let (u, d) = (self.units.abbreviation(), self.units.decimals());
                        let message = format!(
                            "{code}: pecks of {q:.d$} {u} down {:.d$} {u} make more than {MAX_PECKS} pecks",
                            r_plane - bottom
                        );
                        return Err(Diagnostic::error(statement.span, message)
                            .with_help("Q is the depth of each peck: give a larger one"));
                    }
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
                    self.dwell(p, statement, out);
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
                    self.dwell(p, statement, out);
                    self.move_to(MotionMode::Linear, at(clear), statement, out);
                }
                // LinuxCNC's G84: feed in, reverse the spindle, dwell, feed out, turn it back.
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
                    self.dwell(p, statement, out);
                    self.move_to(MotionMode::Linear, at(r_plane), statement, out);
                    self.spindle(inward, speed, statement, out);
                }
            }
            self.rapid_to(at(clear), statement, out);
        }
        Ok(())
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
