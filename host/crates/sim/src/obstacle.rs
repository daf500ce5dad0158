//! What holds the stock (vise jaws, clamps, bolts): solids no part of the
//! tool may touch, judged on the simulation's grid with the same swept
//! volumes as a cut.

use ger_core::config::{Config, Coordinates, Fixture};
use rayon::prelude::*;

use super::{each_cut, Guard, Point, Segment, Simulation};

/// A fixture, in machine coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Solid {
    Box {
        min: Point,
        max: Point,
    },
    /// Standing upright on `bottom`.
    Cylinder {
        centre: [f64; 2],
        radius: f64,
        bottom: f64,
        top: f64,
    },
}

impl Solid {
    /// A `[[fixtures]]` entry where the simulation is: in machine coordinates.
    pub fn of(fixture: &Fixture, config: &Config) -> Solid {
        let shift = match fixture.coordinates {
            Coordinates::Program => Point::from(config.offsets.entry(1)),
            Coordinates::Machine => Point::ZERO,
        };
        match (fixture.min, fixture.max, fixture.centre) {
            (Some(min), Some(max), _) => Solid::Box { min: Point::from(min) + shift, max: Point::from(max) + shift },
            (_, _, centre) => {
                let centre = Point::from(centre.unwrap_or_default()) + shift;
                let (radius, height) = (fixture.diameter.unwrap_or_default() / 2.0, fixture.height.unwrap_or_default());
                Solid::Cylinder { centre: [centre[0], centre[1]], radius, bottom: centre[2], top: centre[2] + height }
            }
        }
    }

    /// Every fixture of `config`.
    pub fn fixtures(config: &Config) -> Vec<Solid> {
        config.fixtures.iter().map(|f| Solid::of(f, config)).collect()
    }

    /// Its XY box, bottom and top.
    pub fn bounds(&self) -> (Point, Point) {
        match *self {
            Solid::Box { min, max } => (min, max),
            Solid::Cylinder { centre: [x, y], radius, bottom, top } => {
                (Point::new(x - radius, y - radius, bottom), Point::new(x + radius, y + radius, top))
            }
        }
    }

    /// Grown by `by` on every side and on top: what a tool within `by` of
    /// it enters (a square edge where growing would round it).
    pub fn grown(&self, by: f64) -> Solid {
        match *self {
            Solid::Box { min, max } => Solid::Box { min: min - Point::splat(by), max: max + Point::splat(by) },
            Solid::Cylinder { centre, radius, bottom, top } => {
                Solid::Cylinder { centre, radius: radius + by, bottom: bottom - by, top: top + by }
            }
        }
    }

    /// Whether it stands over the point (x, y).
    pub fn covers(&self, x: f64, y: f64) -> bool {
        match *self {
            Solid::Box { min, max } => (min[0]..=max[0]).contains(&x) && (min[1]..=max[1]).contains(&y),
            Solid::Cylinder { centre, radius, .. } => (x - centre[0]).hypot(y - centre[1]) <= radius,
        }
    }
}

/// How far a tool went into a solid: the most its top is above the tool's
/// lowest point over one cell, and which part of the tool (by its index in
/// the parts given) was lowest there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrusion {
    pub depth: f64,
    pub part: usize,
}

impl Simulation {
    /// Whether the tool, as `parts` (the cutting edge a part like the others,
    /// with its base 0), touches `solid` moving along `segment`: over each
    /// cell of the simulation's grid (extended past the stock as far as
    /// need be) under the solid, the tool's lowest point against the
    /// solid's top. The tool reaches up without end, so passing under a
    /// solid is going through it.
    pub fn intrusion(&self, solid: &Solid, segment: &Segment, parts: &[Guard]) -> Option<Intrusion> {
        let (lo, hi) = segment.bounds();
        let (s_lo, s_hi) = solid.bounds();
        let reach = parts.iter().map(|p| p.cutter.radius).fold(0.0, f64::max);
        let lowest = parts.iter().map(|p| lo[2] + p.base).fold(f64::INFINITY, f64::min);
        if lowest >= s_hi[2] {
            return None;
        }
        // The cells of the grid (its origin the stock's corner) whose centres lie in both boxes.
        let (x_lo, x_hi) = ((lo[0] - reach).max(s_lo[0]), (hi[0] + reach).min(s_hi[0]));
        let (y_lo, y_hi) = ((lo[1] - reach).max(s_lo[1]), (hi[1] + reach).min(s_hi[1]));
        if x_lo > x_hi || y_lo > y_hi {
            return None;
        }
        let field = &self.field;
        let (cx, cy, origin) = (field.cell, field.cell_y(), field.stock.min);
        let first = |lo: f64, o: f64, c: f64| ((lo - o) / c - 0.5).ceil() as i64;
        let last = |hi: f64, o: f64, c: f64| ((hi - o) / c - 0.5).floor() as i64;
        let (i0, i1) = (first(x_lo, origin[0], cx), last(x_hi, origin[0], cx));
        let (j0, j1) = (first(y_lo, origin[1], cy), last(y_hi, origin[1], cy));
        if i0 > i1 || j0 > j1 {
            return None;
        }
        let mut cuts = Vec::new();
        for (n, part) in parts.iter().enumerate() {
            each_cut(segment, &part.cutter, part.base, self.tolerance, |cut| cuts.push((n, cut)));
        }
        let top = s_hi[2];
        (j0..=j1)
            .into_par_iter()
            .filter_map(|j| {
                let y = origin[1] + (j as f64 + 0.5) * cy;
                let mut worst: Option<Intrusion> = None;
                for i in i0..=i1 {
                    let x = origin[0] + (i as f64 + 0.5) * cx;
                    if !solid.covers(x, y) {
                        continue;
                    }
                    for &(part, ref cut) in &cuts {
                        let depth = top - cut.low(x, y);
                        if depth > 0.0 && worst.is_none_or(|w| depth > w.depth) {
                            worst = Some(Intrusion { depth, part });
                        }
                    }
                }
                worst
            })
            // The deepest, and of equal ones the lowest part, whichever thread found it.
            .reduce_with(|a, b| if b.depth > a.depth || (b.depth == a.depth && b.part < a.part) { b } else { a })
    }
}
