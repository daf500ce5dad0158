//! The exact lower envelope of a tool swept along a move, cell by cell.
//!
//! For a cell centre P, the tool's lowest point over P while it moves is
//! `min over t of z(t) + profile(|P - C(t)|)`, where C(t) is the tool's axis
//! in XY and z(t) its tip. Along a line every profile here (flat, ball, cone)
//! makes that a convex function of t on the interval where P is under the
//! tool, so its minimum is found in closed form: where the derivative
//! vanishes, clamped to the interval. Along an arc at constant Z it is the
//! arc's nearest point to P; along a helix with a flat tool, the end of the
//! interval where Z is lowest. (The simulation splits helices cut by ball
//! and cone tools, and arcs in the XZ and YZ planes, into short lines.)

use std::f64::consts::{PI, TAU};

use super::path::Point;
use super::tool::{Cutter, Shape};

/// A line whose squared XY length is at most this goes straight down or up.
const PLUNGE: f64 = 1e-24;

/// A move ready to cut: its geometry and its tool.
#[derive(Clone, Copy, Debug)]
pub struct Cut {
    pub geometry: Geometry,
    pub cutter: Cutter,
    /// The XY box the tool covers during the move.
    pub lo: [f64; 2],
    pub hi: [f64; 2],
}

#[derive(Clone, Copy, Debug)]
pub enum Geometry {
    /// From `a` along `d` (t in [0, 1]); `l2` is the squared XY length.
    Line { a: Point, d: Point, l2: f64 },
    /// An arc in the XY plane, Z from `z0` changing by `dz`.
    Arc { c: [f64; 2], r: f64, start: f64, sweep: f64, z0: f64, dz: f64 },
}

/// A cut's shape and place but for its height, bit for bit (see [`Cut::key`]).
pub type Key = [u64; 12];

impl Cut {
    /// The line from `a` to `b`, written one way whichever way the tool goes
    /// (a plunge and its retract, a move and its return: the same swept
    /// volume), so that a repeat is the same cut to the bit.
    pub fn line(a: Point, b: Point, cutter: Cutter) -> Cut {
        let (mut a, b) = if b.to_array() < a.to_array() { (b, a) } else { (a, b) };
        let mut d = b - a;
        let mut l2 = d.truncate().length_squared();
        if l2 <= PLUNGE {
            // Straight down or up: only where the tip goes lowest matters.
            a.z += d.z.min(0.0);
            (d, l2) = (Point::ZERO, 0.0);
        }
        let r = cutter.radius;
        Cut {
            geometry: Geometry::Line { a, d, l2 },
            cutter,
            lo: [a[0].min(a[0] + d[0]) - r, a[1].min(a[1] + d[1]) - r],
            hi: [a[0].max(a[0] + d[0]) + r, a[1].max(a[1] + d[1]) + r],
        }
    }

    /// The lowest the tool's tip goes during the move: no cell under it ends lower.
    #[inline]
    pub fn floor(&self) -> f64 {
        match self.geometry {
            Geometry::Line { a, d, .. } => a[2] + d[2].min(0.0),
            Geometry::Arc { z0, dz, .. } => z0 + dz.min(0.0),
        }
    }

    /// What makes the cut what it is but its height, and that height (the
    /// Z it is written from): of two cuts with the same key, the one written
    /// higher lowers no cell below what the other leaves, rounding included
    /// (every height the kernel gives is that Z plus terms the two share).
    pub fn key(&self) -> (Key, f64) {
        let (kind, g, z) = match self.geometry {
            Geometry::Line { a, d, .. } => (0, [a[0], a[1], d[0], d[1], d[2], 0.0, 0.0], a[2]),
            Geometry::Arc { c, r, start, sweep, z0, dz } => (1, [c[0], c[1], r, start, sweep, dz, 0.0], z0),
        };
        let (shape, slope, flat) = match self.cutter.shape {
            Shape::Flat => (0, 0.0, 0.0),
            Shape::Ball => (1, 0.0, 0.0),
            Shape::Cone { slope } => (2, slope, 0.0),
            Shape::Frustum { slope, flat } => (3, slope, flat),
        };
        let mut key = [kind, 0, 0, 0, 0, 0, 0, 0, self.cutter.radius.to_bits(), shape, slope.to_bits(), flat.to_bits()];
        for (k, v) in key[1..8].iter_mut().zip(g) {
            *k = v.to_bits();
        }
        (key, z)
    }

    /// The X intervals of row `y` the tool may reach (conservative): for a
    /// line one, for an arc the ring it sweeps, which a row may cross twice.
    #[inline]
    pub fn row(&self, y: f64) -> [Option<(f64, f64)>; 2] {
        let r = self.cutter.radius;
        match self.geometry {
            Geometry::Line { a, d, .. } => {
                let (t0, t1) = if d[1].abs() < 1e-12 {
                    if (y - a[1]).abs() > r {
                        return [None, None];
                    }
                    (0.0, 1.0)
                } else {
                    let (u, v) = ((y - r - a[1]) / d[1], (y + r - a[1]) / d[1]);
                    (u.min(v).max(0.0), u.max(v).min(1.0))
                };
                if t0 > t1 {
                    return [None, None];
                }
                let (x0, x1) = (a[0] + t0 * d[0], a[0] + t1 * d[0]);
                [Some((x0.min(x1) - r, x0.max(x1) + r)), None]
            }
            Geometry::Arc { c, r: ra, .. } => {
                // A hair wider than the ring, so that rounding loses no cell on its edge.
                let slack = 1e-9 * (ra + r);
                let (outer, inner, dy) = (ra + r + slack, ra - r - slack, y - c[1]);
                if dy.abs() > outer {
                    return [None, None];
                }
                let clip = |lo: f64, hi: f64| {
                    let (lo, hi) = (lo.max(self.lo[0]), hi.min(self.hi[0]));
                    (lo <= hi).then_some((lo, hi))
                };
                let xo = (outer * outer - dy * dy).sqrt();
                if inner > dy.abs() {
                    let xi = (inner * inner - dy * dy).sqrt();
                    [clip(c[0] - xo, c[0] - xi), clip(c[0] + xi, c[0] + xo)]
                } else {
                    [clip(c[0] - xo, c[0] + xo), None]
                }
            }
        }
    }

    /// The lowest point of the tool over (px, py) during the move; infinity
    /// where the tool never passes over it.
    #[inline]
    pub fn low(&self, px: f64, py: f64) -> f64 {
        match self.geometry {
            Geometry::Line { a, d, l2 } => line_low(a, d, l2, &self.cutter, px, py),
            Geometry::Arc { c, r, start, sweep, z0, dz } => arc_low(c, r, start, sweep, z0, dz, &self.cutter, px, py),
        }
    }
}

#[inline(always)]
fn line_low(a: Point, d: Point, l2: f64, cutter: &Cutter, px: f64, py: f64) -> f64 {
    let r = cutter.radius;
    let r2 = r * r;
    let (ux, uy) = (px - a[0], py - a[1]);
    let dz = d[2];
    if l2 <= PLUNGE {
        // A plunge (or a move along Z only).
        let e2 = ux * ux + uy * uy;
        if e2 > r2 {
            return f64::INFINITY;
        }
        return a[2] + dz.min(0.0) + cutter.profile(e2.sqrt());
    }
    // t0: where the axis passes closest to P; e2: that distance squared.
    let t0 = (ux * d[0] + uy * d[1]) / l2;
    let e2 = (ux * ux + uy * uy - t0 * t0 * l2).max(0.0);
    if e2 > r2 {
        return f64::INFINITY;
    }
    let w = ((r2 - e2) / l2).sqrt();
    let (lo, hi) = ((t0 - w).max(0.0), (t0 + w).min(1.0));
    if lo > hi {
        return f64::INFINITY;
    }
    let descending = if dz < 0.0 { hi } else { lo };
    let at = |t: f64| {
        let (qx, qy) = (ux - t * d[0], uy - t * d[1]);
        a[2] + t * dz + cutter.profile((qx * qx + qy * qy).sqrt().min(r))
    };
    let t = match cutter.shape {
        Shape::Flat => descending,
        _ if dz == 0.0 => t0.clamp(lo, hi),
        // d/dt [dz t - sqrt(R^2 - e^2 - s^2 L^2)] = 0 at s = -dz sqrt(R^2 - e^2) / (L sqrt(L^2 + dz^2)).
        Shape::Ball => (t0 - dz * (r2 - e2).sqrt() / (l2.sqrt() * (l2 + dz * dz).sqrt())).clamp(lo, hi),
        Shape::Cone { slope } => cone_low(slope, e2, l2, dz, t0, descending).clamp(lo, hi),
        // Convex, as max(flat, cone) is: its minimum is the cone's own, or an
        // end of where the flat bottom is over P, or an end of [lo, hi].
        Shape::Frustum { slope, flat } => {
            let mut best = at(lo).min(at(hi)).min(at(cone_low(slope, e2, l2, dz, t0, descending).clamp(lo, hi)));
            if e2 <= flat * flat {
                let w = ((flat * flat - e2) / l2).sqrt();
                best = best.min(at((t0 - w).clamp(lo, hi))).min(at((t0 + w).clamp(lo, hi)));
            }
            return best;
        }
    };
    at(t)
}

/// Where a cone rising `slope` per unit of radius goes lowest over P along a
/// line (unclamped): d/dt [dz t + k sqrt(e^2 + s^2 L^2)] = 0 at
/// s = -dz e / (L sqrt(k^2 L^2 - dz^2)), unless the move descends more
/// steeply than the cone's side.
#[inline(always)]
fn cone_low(slope: f64, e2: f64, l2: f64, dz: f64, t0: f64, descending: f64) -> f64 {
    let kl2 = slope * slope * l2;
    if kl2 <= dz * dz {
        descending
    } else {
        t0 - dz * e2.sqrt() / (l2.sqrt() * (kl2 - dz * dz).sqrt())
    }
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn arc_low(c: [f64; 2], ra: f64, start: f64, sweep: f64, z0: f64, dz: f64, cutter: &Cutter, px: f64, py: f64) -> f64 {
    let r = cutter.radius;
    let (vx, vy) = (px - c[0], py - c[1]);
    let rho2 = vx * vx + vy * vy;
    let rho = rho2.sqrt();
    if rho > ra + r || rho < ra - r {
        return f64::INFINITY;
    }
    // Under the tool while the axis is within `alpha` of P's angle.
    let alpha =
        if rho * ra <= 1e-300 { PI } else { ((rho2 + ra * ra - r * r) / (2.0 * rho * ra)).clamp(-1.0, 1.0).acos() };
    let (total, sigma) = (sweep.abs(), sweep.signum());
    let beta = (sigma * (vy.atan2(vx) - start)).rem_euclid(TAU);
    let mut best = f64::INFINITY;
    for k in [-1.0, 0.0, 1.0] {
        let nearest = beta + k * TAU;
        let (lo, hi) = ((nearest - alpha).max(0.0), (nearest + alpha).min(total));
        if lo > hi {
            continue;
        }
        let psi = if dz == 0.0 {
            nearest.clamp(lo, hi)
        } else if dz < 0.0 {
            hi
        } else {
            lo
        };
        let theta = start + sigma * psi;
        let dist = (vx - ra * theta.cos()).hypot(vy - ra * theta.sin()).min(r);
        let t = if total > 0.0 { psi / total } else { 0.0 };
        best = best.min(z0 + t * dz + cutter.profile(dist));
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute(cut: &Cut, p: [f64; 2], at: impl Fn(f64) -> Point) -> f64 {
        let mut best = f64::INFINITY;
        let n = 200_000;
        for k in 0..=n {
            let c = at(k as f64 / n as f64);
            let d = (p[0] - c[0]).hypot(p[1] - c[1]);
            if d <= cut.cutter.radius {
                best = best.min(c[2] + cut.cutter.profile(d));
            }
        }
        best
    }

    const SHAPES: [Shape; 5] = [
        Shape::Flat,
        Shape::Ball,
        Shape::Cone { slope: 0.6 },
        Shape::Frustum { slope: 0.6, flat: 0.3 },
        Shape::Frustum { slope: 3.0, flat: 0.5 },
    ];

    #[test]
    fn lines_match_a_dense_search() {
        let moves =
            [([0.0, 0.0, 0.0], [3.0, 1.0, -1.0]), ([1.0, 1.0, -2.0], [-1.0, 2.0, 0.5]), ([0.0; 3], [2.0, 0.0, 0.0])];
        for shape in SHAPES {
            let cutter = Cutter { radius: 0.8, shape };
            for (a, b) in moves {
                let (a, b) = (Point::from(a), Point::from(b));
                let cut = Cut::line(a, b, cutter);
                for p in [[0.5, 0.3], [1.5, 0.9], [2.9, 1.2], [-0.5, 0.0], [0.0, 1.5], [1.0, 0.79]] {
                    let exact = cut.low(p[0], p[1]);
                    let dense = brute(&cut, p, |t| a + t * (b - a));
                    assert!(
                        (exact - dense).abs() < 1e-4 || (exact.is_infinite() && dense.is_infinite()),
                        "{shape:?} {a:?}->{b:?} at {p:?}: {exact} vs {dense}"
                    );
                }
            }
        }
    }

    #[test]
    fn arcs_match_a_dense_search() {
        for (shape, dz) in [
            (Shape::Flat, -1.0),
            (Shape::Flat, 0.7),
            (Shape::Ball, 0.0),
            (Shape::Cone { slope: 0.6 }, 0.0),
            (Shape::Frustum { slope: 2.0, flat: 0.2 }, 0.0),
        ] {
            let cutter = Cutter { radius: 0.5, shape };
            for (start, sweep) in [(0.3, 2.0), (1.0, -4.0), (-2.0, TAU)] {
                let cut = Cut {
                    geometry: Geometry::Arc { c: [1.0, 1.0], r: 2.0, start, sweep, z0: 0.0, dz },
                    cutter,
                    lo: [-2.0; 2],
                    hi: [4.0; 2],
                };
                for p in [[3.0, 1.2], [1.0, 3.3], [-0.8, 0.8], [1.0, 1.0], [2.2, 2.2], [1.0, -0.6]] {
                    let exact = cut.low(p[0], p[1]);
                    let dense = brute(&cut, p, |t| {
                        let a = start + t * sweep;
                        Point::new(1.0 + 2.0 * a.cos(), 1.0 + 2.0 * a.sin(), t * dz)
                    });
                    assert!(
                        (exact - dense).abs() < 1e-4 || (exact.is_infinite() && dense.is_infinite()),
                        "{shape:?} {start} {sweep} at {p:?}: {exact} vs {dense}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_retract_is_its_plunge_and_a_move_back_is_the_move() {
        let cutter = Cutter { radius: 0.5, shape: Shape::Ball };
        for (a, b) in [([1.0, 2.0, 3.0], [1.0, 2.0, -1.0]), ([0.0, 0.0, 0.0], [2.0, -1.0, -0.5])] {
            let (a, b) = (Point::from(a), Point::from(b));
            let (there, back) = (Cut::line(a, b, cutter), Cut::line(b, a, cutter));
            assert_eq!(there.key(), back.key());
            for p in [[1.0, 2.0], [1.2, 2.3], [1.0, 0.0], [0.5, -0.3]] {
                assert_eq!(there.low(p[0], p[1]).to_bits(), back.low(p[0], p[1]).to_bits(), "{a:?}-{b:?} at {p:?}");
            }
        }
        // Straight down: where the tip goes lowest, whatever the height it came from.
        let plunge = Cut::line(Point::new(1.0, 2.0, 3.0), Point::new(1.0, 2.0, -1.0), cutter);
        assert_eq!(plunge.key().1, -1.0);
        assert_eq!(plunge.low(1.0, 2.0), -1.0);
        assert_eq!(plunge.floor(), -1.0);
    }

    #[test]
    fn an_arcs_rows_hold_every_point_it_cuts_and_not_the_ring_inside() {
        let cutter = Cutter { radius: 0.4, shape: Shape::Ball };
        for (start, sweep) in [(0.3, 2.0), (1.0, -4.0), (-2.0, TAU), (0.0, 1e-9)] {
            let cut = Cut {
                geometry: Geometry::Arc { c: [1.0, 1.0], r: 2.0, start, sweep, z0: 0.0, dz: -0.5 },
                cutter,
                lo: [-1.4; 2],
                hi: [3.4; 2],
            };
            for j in 0..=240 {
                let y = -1.4 + j as f64 * 0.02;
                let rows = cut.row(y);
                for i in 0..=240 {
                    let x = -1.4 + i as f64 * 0.02;
                    let inside = rows.iter().flatten().any(|&(lo, hi)| lo <= x && x <= hi);
                    if cut.low(x, y).is_finite() {
                        assert!(inside, "{start} {sweep}: ({x}, {y}) is cut but in no row interval {rows:?}");
                    }
                    if (x - 1.0).hypot(y - 1.0) < 2.0 - 0.4 - 1e-6 {
                        assert!(!inside, "{start} {sweep}: ({x}, {y}) is inside the ring but in {rows:?}");
                    }
                }
            }
        }
    }
}
