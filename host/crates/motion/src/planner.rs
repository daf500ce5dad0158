//! The planner: straight blocks in, each block's time out, as a controller
//! with look-ahead runs them.
//!
//! Each block accelerates, cruises and decelerates (a trapezoid, or a
//! triangle when it is too short to reach its speed). Its speed and
//! acceleration are the most every axis allows along its direction. Two
//! blocks meet at the speed Sonny Jeon's junction deviation gives: the
//! speed at which a circle tangent to both, whose edge comes within the
//! junction deviation of the corner, can be followed at the acceleration
//! the axes allow along the corner's direction. The planner holds the last
//! few blocks (the controller's buffer) and plans them so that the machine
//! can stop at the end of the last one: a reverse pass from it lowers each
//! entry speed to what the blocks after it can brake from, a forward pass
//! lowers each to what the blocks before it can reach. A block leaves the
//! buffer, and its time is known, when a new block needs its place.

use std::collections::VecDeque;

use ger_core::config::Machine;
use ger_sim::Point;

/// Where a block's time is counted: the caller's tag, when it starts (seconds
/// from the program's start) and how long it takes.
pub trait Clock<T> {
    fn tick(&mut self, tag: &T, start: f64, seconds: f64);
}

impl<T, F: FnMut(&T, f64, f64)> Clock<T> for F {
    fn tick(&mut self, tag: &T, start: f64, seconds: f64) {
        self(tag, start, seconds)
    }
}

/// Below this cosine two blocks run on in a straight line; above its
/// negative one turns back on the other.
const STRAIGHT: f64 = 0.999999;

/// A straight move in the buffer.
#[derive(Clone, Debug)]
struct Block<T> {
    length: f64,
    /// Units per second squared, along the block.
    acceleration: f64,
    /// Units per second.
    nominal: f64,
    /// The slowest the controller steps it, units per second.
    slowest: f64,
    /// Steps of the axis that steps most, per unit along it.
    steps_per_unit: f64,
    /// The most the entry speed may be (squared): the junction's, and neither block's nominal.
    max_entry_sqr: f64,
    /// The most it may be for the machine to stop at the end of the buffer (squared).
    braking_sqr: f64,
    /// As planned (squared).
    entry_sqr: f64,
    tag: T,
}

/// The speeds at which blocks are planned, and the clock they run on.
#[derive(Debug)]
pub struct Planner<T> {
    /// Units per second.
    max_rate: [f64; 3],
    acceleration: [f64; 3],
    junction_deviation: f64,
    /// Steps per unit of each axis: blocks run between whole steps.
    steps: Point,
    /// Where the last block ends, on the steps' grid.
    position: Point,
    /// How many blocks the buffer holds: one less than the controller's
    /// buffer, as GRBL's ring keeps one slot empty to tell full from empty.
    capacity: usize,
    /// The slowest a feed move goes, units per second.
    min_feed: f64,
    /// The slowest the controller steps the axis that steps most, steps per second (0: any speed).
    slowest_step_rate: f64,
    /// The step timer's clock, Hz (0: exact timing).
    step_clock: f64,
    /// The step timer of the machine standing after a stop.
    standing: Option<Standing>,
    /// The timer's period at the end of the last block run (0: not known).
    last_period: f64,
    blocks: VecDeque<Block<T>>,
    /// The last block's direction and nominal speed, while the machine has not stopped since.
    previous: Option<(Point, f64)>,
    /// The time the blocks executed so far take.
    clock: f64,
    /// When the first block started and the last one ended.
    moving: Option<(f64, f64)>,
}

/// How fast a block is asked to go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Speed {
    /// As fast as the axes go (G00).
    Rapid,
    /// A feed, units per minute.
    Feed(f64),
}

impl<T> Planner<T> {
    /// A planner for `machine`, whose numbers are in one unit; `min_feed`
    /// (units per minute) is the slowest any feed runs.
    pub fn new(machine: &Machine, min_feed: f64) -> Planner<T> {
        Planner {
            max_rate: machine.max_rate.map(|v| v / 60.0),
            acceleration: machine.acceleration,
            junction_deviation: machine.junction_deviation,
            steps: Point::from_array(machine.steps_per_unit),
            position: Point::ZERO,
            capacity: machine.planner_blocks.saturating_sub(1).max(1),
            min_feed: min_feed / 60.0,
            slowest_step_rate: machine.slowest_step_rate,
            step_clock: machine.step_clock,
            standing: None,
            last_period: 0.0,
            blocks: VecDeque::with_capacity(machine.planner_blocks),
            previous: None,
            clock: 0.0,
            moving: None,
        }
    }

    /// The time of everything executed so far.
    pub fn elapsed(&self) -> f64 {
        self.clock
    }

    /// When the first block started and the last executed one ended, if any moved.
    pub fn moving(&self) -> Option<(f64, f64)> {
        self.moving
    }

    /// Plans a straight move to `target`, from where the last ended, as the
    /// controller moves: to the nearest whole step of each axis. Blocks
    /// that leave the buffer to make room are timed on `clock`. A move of
    /// no steps is no block.
    pub fn push(&mut self, target: Point, speed: Speed, tag: T, clock: &mut impl Clock<T>) {
        let target = (target * self.steps).round() / self.steps;
        let delta = target - self.position;
        let length = delta.length();
        // Also NaN and infinity: no block.
        if !(length.is_finite() && length > 0.0) {
            return;
        }
        self.position = target;
        let unit = delta / length;
        let fastest = limit(self.max_rate, unit);
        let nominal = match speed {
            Speed::Rapid => fastest,
            Speed::Feed(feed) => (feed / 60.0).max(self.min_feed).min(fastest),
        };
        let acceleration = limit(self.acceleration, unit);
        let steps = (delta * self.steps).abs().max_element();
        let slowest = self.slowest_step_rate * length / steps;
        let max_entry_sqr = match self.previous {
            None => 0.0,
            Some((previous, previous_nominal)) => {
                let junction = self.junction_sqr(previous, unit);
                junction.min(previous_nominal * previous_nominal).min(nominal * nominal)
            }
        };
        if self.blocks.len() >= self.capacity {
            self.execute_front(clock);
        }
        self.previous = Some((unit, nominal));
        let block = Block {
            length,
            acceleration,
            nominal,
            slowest,
            steps_per_unit: steps / length,
            max_entry_sqr,
            braking_sqr: 0.0,
            entry_sqr: max_entry_sqr,
            tag,
        };
        self.blocks.push_back(block);
        self.replan();
    }

    /// Runs every block in the buffer to a stop.
    pub fn stop(&mut self, clock: &mut impl Clock<T>) {
        if self.blocks.is_empty() {
            return;
        }
        while !self.blocks.is_empty() {
            self.execute_front(clock);
        }
        self.previous = None;
        if self.last_period > 0.0 {
            self.standing = Some(Standing { period: self.last_period, seconds: 0.0 });
        }
    }

    /// Stops, then waits `seconds` (a dwell, a tool change).
    pub fn wait(&mut self, seconds: f64, tag: T, clock: &mut impl Clock<T>) {
        self.stop(clock);
        if seconds > 0.0 {
            clock.tick(&tag, self.clock, seconds);
            self.clock += seconds;
            if let Some(standing) = &mut self.standing {
                standing.seconds += seconds;
            }
        }
    }

    /// The fastest two blocks may meet at (squared), from `previous`'s
    /// direction into `unit`'s.
    fn junction_sqr(&self, previous: Point, unit: Point) -> f64 {
        // The cosine of the angle between the reversed previous direction and this one.
        let cos_theta = -previous.dot(unit);
        if cos_theta > STRAIGHT {
            return 0.0;
        }
        if cos_theta < -STRAIGHT {
            return f64::INFINITY;
        }
        let sin_half = (0.5 * (1.0 - cos_theta)).sqrt();
        let towards = (unit - previous).normalize_or_zero();
        let acceleration = limit(self.acceleration, towards);
        acceleration * self.junction_deviation * sin_half / (1.0 - sin_half)
    }

    /// The reverse pass from the newest block, which must be able to stop,
    /// then the forward pass from the oldest, whose entry is fixed.
    fn replan(&mut self) {
        let n = self.blocks.len();
        // Back to the oldest block whose braking limit does not change.
        let mut exit_sqr = 0.0;
        let mut from = 0;
        for i in (1..n).rev() {
            let block = &mut self.blocks[i];
            let braking = block.max_entry_sqr.min(exit_sqr + 2.0 * block.acceleration * block.length);
            if i < n - 1 && braking == block.braking_sqr {
                from = i;
                break;
            }
            block.braking_sqr = braking;
            exit_sqr = braking;
        }
        // The oldest block has started: its entry stays.
        for i in from.max(1)..n {
            let before = &self.blocks[i - 1];
            let reachable = before.entry_sqr + 2.0 * before.acceleration * before.length;
            let block = &mut self.blocks[i];
            block.entry_sqr = block.braking_sqr.min(reachable);
        }
    }

    /// The oldest block runs: from its entry to the next block's.
    fn execute_front(&mut self, clock: &mut impl Clock<T>) {
        let Some(block) = self.blocks.pop_front() else { return };
        let exit_sqr = self.blocks.front().map_or(0.0, |next| next.entry_sqr);
        // The planner plans the speed asked; the step generator goes no
        // slower than its slowest step. A block asked slower than that runs
        // at that speed all along (its ramps are below it); in one asked
        // faster, what its ramps spend below it is a few microseconds.
        let shape = Trapezoid::new(block.length, block.acceleration, block.nominal, block.entry_sqr, exit_sqr);
        let (mut seconds, period) = if block.nominal < block.slowest {
            // The slowest step is a whole number of the timer's ticks already.
            (block.length / block.slowest, 0.0)
        } else if self.step_clock > 0.0 {
            let late = shape.timer_ticks(block.steps_per_unit) / self.step_clock;
            (shape.seconds() + late, shape.last_period(block.steps_per_unit, self.step_clock))
        } else {
            (shape.seconds(), 0.0)
        };
        // Started again after a stop, the step timer first runs out the
        // period it was left with, as it went on counting meanwhile.
        if let Some(standing) = self.standing.take() {
            seconds += standing.period - standing.seconds % standing.period;
        }
        self.last_period = period;
        clock.tick(&block.tag, self.clock, seconds);
        let start = self.moving.map_or(self.clock, |(start, _)| start);
        self.clock += seconds;
        self.moving = Some((start, self.clock));
    }
}

/// The most a quantity (a rate, an acceleration) may be along `unit` when
/// each axis's share may be at most `axes`.
fn limit(axes: [f64; 3], unit: Point) -> f64 {
    let mut most = f64::INFINITY;
    for (axis, &limit) in axes.iter().enumerate() {
        let share = unit[axis].abs();
        if share > 0.0 {
            most = most.min(limit / share);
        }
    }
    most
}

/// The step timer of a machine standing after a stop.
#[derive(Clone, Copy, Debug)]
struct Standing {
    /// Its period, seconds, as the last block left it.
    period: f64,
    /// How long the machine has stood (a dwell).
    seconds: f64,
}

/// GRBL's step generator runs a block as segments of 10 ms, each at a
/// steady step rate...
const SEGMENT_SECONDS: f64 = 0.01;
/// ...and each of at least 1.25 steps: a slow end makes its last one longer.
const SEGMENT_LEAST_STEPS: f64 = 1.25;

/// The ticks per step of GRBL's step smoothing (AMASS), from the step rate
/// (steps per second of the axis that steps most) up: once a step from 8
/// kHz, twice from 4 kHz, four times from 2 kHz, eight times below.
const TICKS_PER_STEP: [(f64, f64); 4] = [(0.0, 8.0), (2000.0, 4.0), (4000.0, 2.0), (8000.0, 1.0)];

fn ticks_per_step(rate: f64) -> f64 {
    TICKS_PER_STEP.iter().rev().find(|(from, _)| rate >= *from).map_or(8.0, |t| t.1)
}

/// A block's speeds: up from its entry to its peak, on at the peak, down
/// to its exit.
struct Trapezoid {
    entry: f64,
    peak: f64,
    exit: f64,
    acceleration: f64,
    /// The length run at the peak.
    cruising: f64,
}

impl Trapezoid {
    /// A block of `length` from an entry speed to an exit speed (both
    /// squared), accelerating and braking at `acceleration`, no faster than
    /// `nominal`.
    fn new(length: f64, acceleration: f64, nominal: f64, entry_sqr: f64, exit_sqr: f64) -> Trapezoid {
        let nominal_sqr = nominal * nominal;
        let ramps = (2.0 * nominal_sqr - entry_sqr - exit_sqr) / (2.0 * acceleration);
        let (peak_sqr, cruising) = if ramps <= length {
            (nominal_sqr, length - ramps)
        } else {
            // Never reaches its speed: up to a peak, straight back down.
            ((acceleration * length + 0.5 * (entry_sqr + exit_sqr)).max(entry_sqr.max(exit_sqr)), 0.0)
        };
        let (entry, peak, exit) = (entry_sqr.sqrt(), peak_sqr.sqrt(), exit_sqr.sqrt());
        Trapezoid { entry, peak, exit, acceleration, cruising }
    }

    fn seconds(&self) -> f64 {
        let cruise = if self.cruising > 0.0 { self.cruising / self.peak } else { 0.0 };
        (self.peak - self.entry) / self.acceleration + (self.peak - self.exit) / self.acceleration + cruise
    }

    /// How often a timer stepping the block at `steps_per_unit` ticks, as
    /// GRBL's does with its step smoothing.
    fn timer_ticks(&self, steps_per_unit: f64) -> f64 {
        // A ramp covers (high² - low²) / 2a of its length between two speeds.
        let ramp = |a: f64, b: f64| {
            let (low, high) = (a.min(b), a.max(b));
            let bands = TICKS_PER_STEP.iter().zip(TICKS_PER_STEP.iter().skip(1).map(|t| t.0).chain([f64::INFINITY]));
            bands
                .map(|(&(from, ticks), to)| {
                    let (from, to) = ((from / steps_per_unit).clamp(low, high), (to / steps_per_unit).clamp(low, high));
                    ticks * (to * to - from * from) / (2.0 * self.acceleration)
                })
                .sum::<f64>()
        };
        let cruise = self.cruising * ticks_per_step(self.peak * steps_per_unit);
        steps_per_unit * (ramp(self.entry, self.peak) + cruise + ramp(self.peak, self.exit))
    }

    /// The step timer's period in the last segment of a block that brakes
    /// to a stop, seconds, on a clock of `clock` Hz: that segment's steady
    /// rate is its mean speed. 0 for a block that does not stop.
    fn last_period(&self, steps_per_unit: f64, clock: f64) -> f64 {
        if self.exit > 0.0 {
            return 0.0;
        }
        let braking = (self.peak - self.exit) / self.acceleration;
        let least = (2.0 * SEGMENT_LEAST_STEPS / (self.acceleration * steps_per_unit)).sqrt();
        let last = SEGMENT_SECONDS.max(least).min(braking);
        let rate = steps_per_unit * self.acceleration * last / 2.0;
        if rate.is_nan() || rate <= 0.0 {
            return 0.0;
        }
        (clock / (ticks_per_step(rate) * rate)).round() / clock
    }
}
