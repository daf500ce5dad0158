//! The manual's "Test Pulses": the step/direction signals a stepper
//! controller would get for the translated program.
//!
//! Positions are whole steps (`round(coordinate * steps_per_unit)`). A line
//! of n steps on its longest axis takes n ticks; at tick k an axis moving d
//! steps steps when round(k d / n) goes up (Bresenham's rule, in integers).
//! An arc is followed through points at most half a step apart, and a tick
//! steps every axis whose rounded position changed.

use crate::{Point, Segment};

/// One tick: which axes step, and the direction lines (true: positive).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pulse {
    pub step: [bool; 3],
    pub dir: [bool; 3],
}

#[derive(Clone, Debug)]
pub struct Pulser {
    steps_per_unit: f64,
    /// Where the motors are, in steps.
    pub position: [i64; 3],
    dir: [bool; 3],
    /// Steps taken on each axis.
    pub steps: [u64; 3],
}

impl Pulser {
    /// At machine zero, every direction line positive.
    pub fn new(steps_per_unit: f64) -> Pulser {
        Pulser { steps_per_unit, position: [0; 3], dir: [true; 3], steps: [0; 3] }
    }

    fn steps_at(&self, p: Point) -> [i64; 3] {
        p.to_array().map(|x| (x * self.steps_per_unit).round() as i64)
    }

    /// Emits the ticks of `segment`; stops early (returning false) when `emit` does.
    pub fn segment(&mut self, segment: &Segment, mut emit: impl FnMut(Pulse) -> bool) -> bool {
        match segment {
            Segment::Line { to, .. } => {
                let start = self.position;
                let target = self.steps_at(*to);
                let delta: [i64; 3] = std::array::from_fn(|a| target[a] - start[a]);
                let n = delta.iter().map(|d| d.unsigned_abs()).max().unwrap_or(0) as i128;
                for k in 1..=n {
                    // round(k d / n) for each axis, halves away from zero.
                    let at = |k: i128, d: i64| {
                        let d = d as i128;
                        (2 * k * d.abs() + n) / (2 * n) * d.signum()
                    };
                    let next: [i64; 3] = std::array::from_fn(|a| start[a] + at(k, delta[a]) as i64);
                    if !self.tick(next, &mut emit) {
                        return false;
                    }
                }
                true
            }
            Segment::Arc { .. } => {
                let length = segment.length() * self.steps_per_unit;
                let n = ((2.0 * length).ceil() as usize).max(1);
                for k in 1..=n {
                    let p = if k == n { segment.to() } else { segment.at(k as f64 / n as f64) };
                    let next = self.steps_at(p);
                    if next != self.position && !self.tick(next, &mut emit) {
                        return false;
                    }
                }
                true
            }
        }
    }

    fn tick(&mut self, next: [i64; 3], emit: &mut impl FnMut(Pulse) -> bool) -> bool {
        let delta: [i64; 3] = std::array::from_fn(|a| next[a] - self.position[a]);
        let step = delta.map(|d| d != 0);
        let dir: [bool; 3] = std::array::from_fn(|a| if step[a] { delta[a] > 0 } else { self.dir[a] });
        if !emit(Pulse { step, dir }) {
            return false;
        }
        for (steps, d) in self.steps.iter_mut().zip(delta) {
            *steps += d.unsigned_abs();
        }
        self.dir = dir;
        self.position = next;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ticks(segments: &[Segment], spu: f64) -> (Vec<Pulse>, Pulser) {
        let mut pulser = Pulser::new(spu);
        let mut out = Vec::new();
        for s in segments {
            pulser.segment(s, |p| {
                out.push(p);
                true
            });
        }
        (out, pulser)
    }

    fn bits(p: &Pulse) -> String {
        p.step.iter().map(|s| if *s { '1' } else { '0' }).collect()
    }

    #[test]
    fn a_line_steps_its_long_axis_every_tick_and_the_others_evenly() {
        // 1 x 0.5 at 10 steps per unit: 10 ticks, X every tick, Y on ticks 1, 3, 5, 7, 9
        // (round(k * 5 / 10) goes up at k = 1, 3, 5, 7, 9).
        let line = Segment::Line { from: Point::ZERO, to: Point::new(1.0, 0.5, 0.0) };
        let (out, pulser) = ticks(&[line], 10.0);
        let shown: Vec<String> = out.iter().map(bits).collect();
        assert_eq!(shown, ["110", "100", "110", "100", "110", "100", "110", "100", "110", "100"]);
        assert_eq!(pulser.steps, [10, 5, 0]);
        assert_eq!(pulser.position, [10, 5, 0]);
    }

    #[test]
    fn going_back_sets_the_direction_line() {
        let a = Segment::Line { from: Point::ZERO, to: Point::new(0.0, 0.0, -0.3) };
        let b = Segment::Line { from: Point::new(0.0, 0.0, -0.3), to: Point::new(0.2, 0.0, -0.3) };
        let (out, pulser) = ticks(&[a, b], 10.0);
        assert_eq!(out.len(), 5);
        assert_eq!(out[0], Pulse { step: [false, false, true], dir: [true, true, false] });
        assert_eq!(out[4], Pulse { step: [true, false, false], dir: [true, true, false] });
        assert_eq!(pulser.steps, [2, 0, 3]);
    }

    #[test]
    fn a_full_circle_takes_as_many_steps_as_its_extent_and_returns() {
        // Radius 1 at 100 steps per unit: each axis travels 4 radii = 400 steps.
        let circle = Segment::Arc {
            from: Point::new(1.0, 0.0, 0.0),
            to: Point::new(1.0, 0.0, 0.0),
            centre: Point::ZERO,
            plane: ger_core::statement::Plane::XY,
            radius: 1.0,
            start: 0.0,
            sweep: std::f64::consts::TAU,
        };
        let mut pulser = Pulser::new(100.0);
        pulser.position = [100, 0, 0];
        let mut count = 0;
        pulser.segment(&circle, |p| {
            assert!(p.step.iter().any(|s| *s));
            count += 1;
            true
        });
        assert_eq!(pulser.steps, [400, 400, 0]);
        assert_eq!(pulser.position, [100, 0, 0]);
        assert!(count <= 800, "{count}");
    }
}
