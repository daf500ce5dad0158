//! The cut part against its design. The design is a closed mesh (STL); a
//! 3-axis machine sees it from above, so what it should leave is the
//! design's top surface, which [`Design::top_surface`] samples on the
//! simulation's grid (each cell centre's highest point of the mesh, found
//! by rasterising every triangle over the cells it covers). [`compare`]
//! sets it beside the simulated part cell by cell: a gouge where the part
//! is lower than the design by more than the tolerance, material left where
//! it is higher. Nothing here opens files or knows argv.

mod heat;

use std::io::{Read, Seek};

use ger_sim::{HeightField, Point};
use serde::Serialize;

pub use heat::heat_map;

/// A design: its triangles, in machine coordinates once placed.
#[derive(Clone, Debug)]
pub struct Design {
    triangles: Vec<[Point; 3]>,
}

/// A mesh that cannot be a design.
#[derive(Debug, thiserror::Error)]
pub enum DesignError {
    #[error("not an STL file ger can read: {0}")]
    Unreadable(std::io::Error),
    #[error("the mesh is not a closed surface ({0}): a design must be a solid")]
    Open(String),
    #[error("the mesh has no triangles")]
    Empty,
    #[error("the mesh has a coordinate that is not a finite number")]
    NotFinite,
}

impl Design {
    /// A binary or ASCII STL, which must be a closed surface: every edge
    /// shared by two triangles that face the same way, none of zero area.
    pub fn read<R: Read + Seek>(reader: &mut R) -> Result<Design, DesignError> {
        let mesh = stl_io::read_stl(reader).map_err(DesignError::Unreadable)?;
        if mesh.faces.is_empty() {
            return Err(DesignError::Empty);
        }
        if mesh.vertices.iter().any(|v| v.0.iter().any(|c| !c.is_finite())) {
            return Err(DesignError::NotFinite);
        }
        mesh.validate().map_err(|e| DesignError::Open(e.to_string()))?;
        let point = |i: usize| {
            let v = mesh.vertices[i].0;
            Point::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
        };
        Ok(Design { triangles: mesh.faces.iter().map(|f| f.vertices.map(point)).collect() })
    }

    /// The box of its triangles.
    pub fn bounds(&self) -> (Point, Point) {
        let mut lo = Point::splat(f64::INFINITY);
        let mut hi = Point::splat(f64::NEG_INFINITY);
        for p in self.triangles.iter().flatten() {
            (lo, hi) = (lo.min(*p), hi.max(*p));
        }
        (lo, hi)
    }

    /// Every point `p` becomes `p * scale + shift`.
    pub fn place(&mut self, scale: f64, shift: Point) {
        for p in self.triangles.iter_mut().flatten() {
            *p = *p * scale + shift;
        }
    }

    /// The design's highest point over each cell centre of `field`'s grid
    /// (row-major, `j * nx + i`), `None` where it has none.
    pub fn top_surface(&self, field: &HeightField) -> Vec<Option<f64>> {
        let (nx, ny) = (field.nx, field.ny);
        let (cx, cy, origin) = (field.cell, field.cell_y(), field.stock.min);
        let mut top = vec![None; nx * ny];
        for &[a, b, c] in &self.triangles {
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            // Seen from above, a wall has no area: its top edge is another face's.
            if area.abs() < 1e-12 {
                continue;
            }
            let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
            let first = |v: f64, o: f64, s: f64, n: usize| ((v - o) / s - 0.5).ceil().clamp(0.0, n as f64) as usize;
            let last = |v: f64, o: f64, s: f64, n: usize| ((v - o) / s - 0.5).floor().min(n as f64 - 1.0);
            let (i0, j0) = (first(lo[0], origin[0], cx, nx), first(lo[1], origin[1], cy, ny));
            let (i1, j1) = (last(hi[0], origin[0], cx, nx), last(hi[1], origin[1], cy, ny));
            if i1 < 0.0 || j1 < 0.0 {
                continue;
            }
            // A centre on an edge two triangles share belongs to both: a hair of slack.
            let slack = -1e-9;
            for j in j0..=j1 as usize {
                let y = origin[1] + (j as f64 + 0.5) * cy;
                // Only the cells the row's line crosses the triangle over (a cell either side
                // for rounding): a long thin triangle across the grid has a box of most of it.
                let (mut x_lo, mut x_hi) = (f64::INFINITY, f64::NEG_INFINITY);
                for (p, q) in [(a, b), (b, c), (c, a)] {
                    let (y_lo, y_hi) = (p[1].min(q[1]), p[1].max(q[1]));
                    if y < y_lo || y > y_hi {
                        continue;
                    }
                    // A level edge on the row's line: all of it.
                    let [u, v] = if q[1] == p[1] {
                        [p[0], q[0]]
                    } else {
                        [p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]); 2]
                    };
                    (x_lo, x_hi) = (x_lo.min(u).min(v), x_hi.max(u).max(v));
                }
                if x_lo > x_hi {
                    continue;
                }
                let from = first(x_lo, origin[0], cx, nx).saturating_sub(1).max(i0);
                let to = (last(x_hi, origin[0], cx, nx) + 1.0).min(i1);
                if to < from as f64 {
                    continue;
                }
                for i in from..=to as usize {
                    let x = origin[0] + (i as f64 + 0.5) * cx;
                    let wa = ((b[0] - x) * (c[1] - y) - (c[0] - x) * (b[1] - y)) / area;
                    let wb = ((c[0] - x) * (a[1] - y) - (a[0] - x) * (c[1] - y)) / area;
                    let wc = 1.0 - wa - wb;
                    if wa < slack || wb < slack || wc < slack {
                        continue;
                    }
                    let z = wa * a[2] + wb * b[2] + wc * c[2];
                    let cell = &mut top[j * nx + i];
                    *cell = Some(cell.map_or(z, |t: f64| t.max(z)));
                }
            }
        }
        top
    }
}

/// How the part and its design differ, in machine units.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    pub tolerance: f64,
    /// The side of a cell.
    pub cell: f64,
    /// The area the design covers, where the part is judged.
    pub judged_area: f64,
    /// Cut below the design by more than the tolerance.
    pub gouge: Deviation,
    /// Left above the design by more than the tolerance.
    pub left: Deviation,
}

/// Where the part is off its design one way, beyond the tolerance.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Deviation {
    /// The most it is off by (0 when it nowhere is), and where: the cell's centre.
    pub worst: f64,
    pub at: Option<[f64; 2]>,
    /// The area of the cells off by more than the tolerance.
    pub area: f64,
    /// The volume between the part and the design over those cells.
    pub volume: f64,
    /// For gouges: the lines of the moves that cut below the design there
    /// (filled by the caller, who has the moves, from [`Judged::gouged`]),
    /// when one program cut the part; empty for a job (see `cut_by`).
    pub lines: Vec<u32>,
    /// For gouges: those lines by program, in the order the programs ran;
    /// only the programs that gouged.
    pub cut_by: Vec<ProgramLines>,
}

/// The lines of one program.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ProgramLines {
    /// The program's name, as the report names it.
    pub file: String,
    pub lines: Vec<u32>,
}

/// What each cell is, for the heat map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The design has nothing over it.
    Unjudged = 0,
    Within = 1,
    Gouged = 2,
    Left = 3,
}

/// At most this many gouged cells are kept for finding the moves that cut them: the deepest.
pub const GOUGE_SAMPLES: usize = 256;

/// The part `field` against the design's top surface `design` (from
/// [`Design::top_surface`]): the comparison, each cell's verdict, and the
/// deepest gouged cells (centre, and the height below which a cut there gouges).
pub fn compare(field: &HeightField, design: &[Option<f64>], tolerance: f64) -> Judged {
    let area = field.cell * field.cell_y();
    let mut comparison = Comparison {
        tolerance,
        cell: field.cell,
        judged_area: 0.0,
        gouge: Deviation::default(),
        left: Deviation::default(),
    };
    let mut verdicts = vec![Verdict::Unjudged; field.nx * field.ny];
    let mut gouged = Vec::new();
    for j in 0..field.ny {
        for i in 0..field.nx {
            let Some(want) = design[j * field.nx + i] else { continue };
            comparison.judged_area += area;
            let have = field.get(i, j);
            let off = have - want;
            let (deviation, verdict) = if off < -tolerance {
                gouged.push((-off, field.centre(i, j), want - tolerance));
                (&mut comparison.gouge, Verdict::Gouged)
            } else if off > tolerance {
                (&mut comparison.left, Verdict::Left)
            } else {
                verdicts[j * field.nx + i] = Verdict::Within;
                continue;
            };
            verdicts[j * field.nx + i] = verdict;
            deviation.area += area;
            deviation.volume += off.abs() * area;
            if off.abs() > deviation.worst {
                deviation.worst = off.abs();
                deviation.at = Some(field.centre(i, j));
            }
        }
    }
    gouged.sort_by(|a, b| b.0.total_cmp(&a.0));
    gouged.truncate(GOUGE_SAMPLES);
    Judged { comparison, verdicts, gouged: gouged.into_iter().map(|(_, at, below)| (at, below)).collect() }
}

/// [`compare`]'s answer.
pub struct Judged {
    pub comparison: Comparison,
    /// Row-major, as the design's top surface.
    pub verdicts: Vec<Verdict>,
    /// The deepest gouged cells: each centre, and the height a move must go
    /// below there to have gouged it.
    pub gouged: Vec<([f64; 2], f64)>,
}

#[cfg(test)]
mod tests;
