//! How long a translated program takes on a machine: a motion planner as
//! GRBL describes its own (trapezoidal acceleration, junction deviation,
//! look-ahead over the planner's buffer, arcs run as short lines), driven by
//! the statements after pass 05.
//!
//! A [`Run`] follows the statements in order, as the machine would receive
//! them, and tells a [`Clock`] the time of each block as it leaves the
//! planner's buffer, with the tag the caller gave its statement. Memory is
//! the buffer: nothing grows with the program.

mod planner;

pub use ger_core::config::Machine;
use ger_core::statement::{Kind, Machine as Code, Statement, Units};
use ger_sim::{Segment, Step, Walker};
pub use planner::{Clock, Planner, Speed};

/// The slowest feed GRBL runs at (its `MINIMUM_FEED_RATE`), in millimetres per minute.
const MIN_FEED_MM: f64 = 1.0;

/// A program being timed, statement by statement.
#[derive(Debug)]
pub struct Run<T> {
    planner: Planner<T>,
    walker: Walker,
    arc_tolerance: f64,
    tool_change_time: f64,
    dwell_multiple: f64,
    /// Units per minute.
    feed: Option<f64>,
    /// The spindle's code (M03, M04, M05) and speed.
    spindle: (Code, Option<f64>),
    /// Mist and flood.
    coolant: (bool, bool),
}

/// What a run took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Totals {
    /// From the start to the end: moves, dwells and tool changes.
    pub seconds: f64,
    /// When the first move started and the last ended (what GRBL's own
    /// clock counts), if anything moved.
    pub moving: Option<(f64, f64)>,
}

impl<T: Clone> Run<T> {
    /// A run on `machine`, whose numbers are in `units`, from machine zero.
    pub fn new(machine: &Machine, units: Units) -> Run<T> {
        Run {
            planner: Planner::new(machine, MIN_FEED_MM * Units::Mm.factor_to(units)),
            walker: Walker::new(),
            arc_tolerance: machine.arc_tolerance,
            tool_change_time: machine.tool_change_time,
            dwell_multiple: machine.dwell_multiple,
            feed: None,
            spindle: (Code::SpindleOff, None),
            coolant: (false, false),
        }
    }

    /// Follows one statement, tagging its time with `tag`; blocks that
    /// leave the planner meanwhile are timed on `clock`.
    pub fn statement(&mut self, statement: &Statement, tag: T, clock: &mut impl Clock<T>) {
        match &statement.kind {
            Kind::Motion(motion) => {
                if let Some(feed) = motion.feed {
                    self.feed = Some(feed.value);
                }
            }
            Kind::Dwell(seconds) => {
                let seconds = seconds.max(0.0);
                let seconds = if self.dwell_multiple > 0.0 {
                    (seconds / self.dwell_multiple).ceil() * self.dwell_multiple
                } else {
                    seconds
                };
                self.planner.wait(seconds, tag, clock);
                return;
            }
            Kind::Machine { code, s, .. } => {
                match code {
                    Code::ToolChange => self.planner.wait(self.tool_change_time, tag.clone(), clock),
                    // A change to the spindle or the coolant waits for the moves before it (GRBL's sync).
                    Code::SpindleCw | Code::SpindleCcw | Code::SpindleOff => {
                        let spindle = (*code, if *code == Code::SpindleOff { None } else { *s });
                        if std::mem::replace(&mut self.spindle, spindle) != spindle {
                            self.planner.stop(clock);
                        }
                    }
                    Code::Mist | Code::Flood | Code::CoolantOff => {
                        let coolant = match code {
                            Code::Mist => (true, self.coolant.1),
                            Code::Flood => (self.coolant.0, true),
                            _ => (false, false),
                        };
                        if std::mem::replace(&mut self.coolant, coolant) != coolant {
                            self.planner.stop(clock);
                        }
                    }
                    Code::Pause => self.planner.stop(clock),
                    _ => {}
                }
            }
            Kind::ToolLength { .. } | Kind::ToolLengthCancel | Kind::End => self.planner.stop(clock),
            _ => {}
        }
        let Some(Step::Move(step)) = self.walker.step(statement) else { return };
        let speed = if step.rapid { Speed::Rapid } else { Speed::Feed(self.feed.unwrap_or(0.0)) };
        match step.segment {
            Segment::Line { to, .. } => self.planner.push(to, speed, tag, clock),
            arc @ Segment::Arc { radius, sweep, .. } => {
                let lines = arc_lines(radius, sweep, self.arc_tolerance);
                for i in 1..lines {
                    self.planner.push(arc.at(i as f64 / lines as f64), speed, tag.clone(), clock);
                }
                self.planner.push(arc.to(), speed, tag, clock);
            }
        }
    }

    /// Runs what is left in the buffer to a stop: the program's time.
    pub fn finish(mut self, clock: &mut impl Clock<T>) -> Totals {
        self.planner.stop(clock);
        Totals { seconds: self.planner.elapsed(), moving: self.planner.moving() }
    }
}

/// How many lines an arc of `radius` through `sweep` radians is run as: as
/// many as chords that stray at most `tolerance` from it span its length
/// (GRBL's rule), at least one, at most 2^20.
pub fn arc_lines(radius: f64, sweep: f64, tolerance: f64) -> usize {
    // A chord whose middle is `tolerance` inside the circle is 2 sqrt(tol (2r - tol)) long.
    let half_chord = (tolerance * (2.0 * radius - tolerance)).sqrt();
    // A radius below half the tolerance makes it NaN: one line.
    if half_chord.is_nan() || half_chord <= 0.0 {
        return 1;
    }
    let lines = (0.5 * sweep.abs() * radius / half_chord).floor();
    (lines as usize).clamp(1, 1 << 20)
}

#[cfg(test)]
mod tests;
