//! The cut stock as a closed triangle mesh, and as binary STL.
//!
//! The top surface has a vertex at every cell centre (those on the border
//! moved out to the stock's edge, so the mesh has the stock's size); four
//! walls join the border to the bottom, and the bottom is a fan around its
//! centre. Every edge belongs to exactly two triangles, which face outwards.

use std::io::{self, Write};

use ger_sim::{HeightField, Point};

/// The X of vertex column `i` (Y likewise with `y`).
fn coord(i: usize, n: usize, lo: f64, hi: f64) -> f64 {
    if i == 0 {
        lo
    } else if i == n - 1 {
        hi
    } else {
        lo + (i as f64 + 0.5) * (hi - lo) / n as f64
    }
}

/// The mesh's vertices and triangles, computed on the fly.
pub struct Mesh<'f> {
    field: &'f HeightField,
    /// The lowest a top vertex may be: just above the bottom, so that a cut
    /// through the stock leaves no zero-area wall.
    floor: f64,
}

impl<'f> Mesh<'f> {
    pub fn new(field: &'f HeightField) -> Mesh<'f> {
        let floor = field.bottom() + (field.top() - field.bottom()) * 1e-4;
        Mesh { field, floor }
    }

    /// The top surface's vertex (i, j).
    #[inline]
    pub fn top(&self, i: usize, j: usize) -> Point {
        let f = self.field;
        let s = &f.stock;
        Point::new(coord(i, f.nx, s.min[0], s.max[0]), coord(j, f.ny, s.min[1], s.max[1]), f.get(i, j).max(self.floor))
    }

    /// The border's vertices, counter-clockwise seen from above.
    fn border(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let (nx, ny) = (self.field.nx, self.field.ny);
        let bottom = (0..nx - 1).map(|i| (i, 0));
        let right = (0..ny - 1).map(move |j| (nx - 1, j));
        let top = (1..nx).rev().map(move |i| (i, ny - 1));
        let left = (1..ny).rev().map(|j| (0, j));
        bottom.chain(right).chain(top).chain(left)
    }

    pub fn triangle_count(&self) -> u64 {
        let (nx, ny) = (self.field.nx as u64, self.field.ny as u64);
        2 * (nx - 1) * (ny - 1) + 3 * 2 * ((nx - 1) + (ny - 1))
    }

    /// Calls `f` with every triangle, its vertices counter-clockwise seen from outside.
    pub fn for_each(&self, mut f: impl FnMut([Point; 3])) {
        let (nx, ny) = (self.field.nx, self.field.ny);
        for j in 0..ny - 1 {
            let mut a = self.top(0, j);
            let mut d = self.top(0, j + 1);
            for i in 0..nx - 1 {
                let (b, c) = (self.top(i + 1, j), self.top(i + 1, j + 1));
                // Split along the diagonal that keeps the surface closest to the cells.
                if (a[2] - c[2]).abs() <= (b[2] - d[2]).abs() {
                    f([a, b, c]);
                    f([a, c, d]);
                } else {
                    f([a, b, d]);
                    f([b, c, d]);
                }
                (a, d) = (b, c);
            }
        }
        let z0 = self.field.bottom();
        let s = &self.field.stock;
        let centre = ((s.min + s.max) / 2.0).with_z(z0);
        let corners: Vec<(usize, usize)> = self.border().collect();
        for (k, &(i, j)) in corners.iter().enumerate() {
            let (qi, qj) = corners[(k + 1) % corners.len()];
            let (pt, qt) = (self.top(i, j), self.top(qi, qj));
            let (pb, qb) = (pt.with_z(z0), qt.with_z(z0));
            f([pb, qb, qt]);
            f([pb, qt, pt]);
            f([centre, qb, pb]);
        }
    }

    /// Writes the mesh as binary STL.
    pub fn write_stl(&self, out: impl Write) -> io::Result<()> {
        let mut out = io::BufWriter::with_capacity(1 << 16, out);
        let mut header = [0u8; 80];
        let title = b"ger: simulated stock";
        header[..title.len()].copy_from_slice(title);
        out.write_all(&header)?;
        let count = u32::try_from(self.triangle_count())
            .map_err(|_| io::Error::other("too many triangles for an STL file: use a coarser --resolution"))?;
        out.write_all(&count.to_le_bytes())?;
        let mut result = Ok(());
        let mut record = [0u8; 50];
        self.for_each(|[a, b, c]| {
            if result.is_err() {
                return;
            }
            let n = normal(a, b, c);
            for (k, v) in [n, a, b, c].iter().flat_map(|p| p.to_array()).enumerate() {
                record[k * 4..k * 4 + 4].copy_from_slice(&(v as f32).to_le_bytes());
            }
            result = out.write_all(&record);
        });
        result?;
        out.flush()
    }
}

/// The unit normal of a counter-clockwise triangle.
pub fn normal(a: Point, b: Point, c: Point) -> Point {
    let n = (b - a).cross(c - a);
    let len = n.length();
    if len == 0.0 {
        Point::ZERO
    } else {
        n / len
    }
}
