//! The toolpath as straight pieces, for a viewer that draws lines: arcs are
//! split into chords, and a path too long to draw is thinned by merging
//! pieces that lie within a tolerance of a straighter path. Only what is
//! drawn is thinned; the simulation always takes every move.

use glam::Vec3;

use ger_sim::{Move, Point, Segment};

/// What a piece of the path is, by the numbers the viewer's format uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum PieceKind {
    Rapid = 0,
    Line = 1,
    Arc = 2,
}

/// A straight piece of the toolpath, in machine coordinates, and the output
/// line (0-based) of the move it is part of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    pub from: [f32; 3],
    pub to: [f32; 3],
    pub line: u32,
    pub kind: PieceKind,
}

fn narrow(p: Point) -> [f32; 3] {
    p.as_vec3().to_array()
}

/// Appends the pieces of move `m` (made by output line `line`): a line is one
/// piece, an arc as many chords as keep within `tolerance` of it.
pub fn split(m: &Move, line: u32, tolerance: f64, out: &mut Vec<Piece>) {
    let kind = match (m.rapid, m.segment) {
        (true, _) => PieceKind::Rapid,
        (false, Segment::Line { .. }) => PieceKind::Line,
        (false, Segment::Arc { .. }) => PieceKind::Arc,
    };
    let n = m.segment.pieces(tolerance);
    let mut from = m.segment.from();
    for k in 1..=n {
        // The last chord ends exactly where the move does.
        let to = if k == n { m.segment.to() } else { m.segment.at(k as f64 / n as f64) };
        out.push(Piece { from: narrow(from), to: narrow(to), line, kind });
        from = to;
    }
}

/// Pieces merged by runs: within a run of consecutive, connected pieces of
/// one kind, the kept points are a subset of the run's such that every point
/// left out lies within `tolerance` of the merged piece that replaces it
/// (Douglas-Peucker). A merged piece keeps the output line of its first piece.
pub fn decimate(pieces: &[Piece], tolerance: f64) -> Vec<Piece> {
    let mut out = Vec::with_capacity(pieces.len() / 4);
    let mut start = 0;
    while start < pieces.len() {
        let mut end = start + 1;
        // Runs are also cut at CHUNK pieces: Douglas-Peucker's worst case is
        // quadratic in the run's length, and a cut costs only one kept point.
        while end < pieces.len()
            && end - start < CHUNK
            && pieces[end].kind == pieces[start].kind
            && pieces[end].from == pieces[end - 1].to
        {
            end += 1;
        }
        simplify(&pieces[start..end], tolerance, &mut out);
        start = end;
    }
    out
}

const CHUNK: usize = 4096;

/// Douglas-Peucker over the connected run `run`, its points being each
/// piece's start and the last piece's end.
fn simplify(run: &[Piece], tolerance: f64, out: &mut Vec<Piece>) {
    let point = |i: usize| if i < run.len() { run[i].from } else { run[run.len() - 1].to };
    let mut keep = vec![false; run.len() + 1];
    keep[0] = true;
    keep[run.len()] = true;
    let mut stack = vec![(0, run.len())];
    while let Some((a, b)) = stack.pop() {
        let (mut far, mut index) = (0.0, 0);
        for i in a + 1..b {
            let d = distance_to_segment(point(i), point(a), point(b));
            if d > far {
                (far, index) = (d, i);
            }
        }
        if far > tolerance {
            keep[index] = true;
            stack.push((a, index));
            stack.push((index, b));
        }
    }
    let mut from = 0;
    for (i, kept) in keep.iter().enumerate().skip(1) {
        if *kept {
            out.push(Piece { from: point(from), to: point(i), line: run[from].line, kind: run[from].kind });
            from = i;
        }
    }
}

/// The distance from `p` to the segment from `a` to `b`.
fn distance_to_segment(p: [f32; 3], a: [f32; 3], b: [f32; 3]) -> f64 {
    let wide = |q: [f32; 3]| Vec3::from(q).as_dvec3();
    let (d, v) = (wide(b) - wide(a), wide(p) - wide(a));
    let length2 = d.length_squared();
    let t = if length2 > 0.0 { (v.dot(d) / length2).clamp(0.0, 1.0) } else { 0.0 };
    (v - t * d).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ger_core::diag::Span;
    use ger_core::statement::Plane;

    fn feed(segment: Segment) -> Move {
        Move { segment, rapid: false, span: Span::default() }
    }

    #[test]
    fn a_line_is_one_piece_and_an_arc_keeps_within_the_tolerance() {
        let mut out = Vec::new();
        split(&feed(Segment::Line { from: Point::ZERO, to: Point::new(1.0, 2.0, 3.0) }), 7, 0.1, &mut out);
        assert_eq!(out, [Piece { from: [0.0; 3], to: [1.0, 2.0, 3.0], line: 7, kind: PieceKind::Line }]);

        // A half circle of radius 10 about the origin, from (10, 0) to (-10, 0), counter-clockwise.
        let arc = Segment::Arc {
            from: Point::new(10.0, 0.0, 0.0),
            to: Point::new(-10.0, 0.0, 0.0),
            centre: Point::ZERO,
            plane: Plane::XY,
            radius: 10.0,
            start: 0.0,
            sweep: std::f64::consts::PI,
        };
        out.clear();
        split(&feed(arc), 3, 0.05, &mut out);
        assert!(out.len() > 10, "{} chords", out.len());
        assert_eq!(out[0].from, [10.0, 0.0, 0.0]);
        assert_eq!(out.last().unwrap().to, [-10.0, 0.0, 0.0]);
        for piece in &out {
            assert_eq!((piece.line, piece.kind), (3, PieceKind::Arc));
            // A chord's middle is as far inside the circle as the chord strays: its sagitta.
            let mid = [(piece.from[0] + piece.to[0]) / 2.0, (piece.from[1] + piece.to[1]) / 2.0];
            let sagitta = 10.0 - f64::from(mid[0].hypot(mid[1]));
            assert!((0.0..=0.05 + 1e-5).contains(&sagitta), "sagitta {sagitta}");
        }
    }

    /// `n` feeds along X from 0 to `n`, one unit each, the line of each its index.
    fn straight(n: usize) -> Vec<Piece> {
        (0..n)
            .map(|i| Piece {
                from: [i as f32, 0.0, 0.0],
                to: [(i + 1) as f32, 0.0, 0.0],
                line: i as u32,
                kind: PieceKind::Line,
            })
            .collect()
    }

    #[test]
    fn a_straight_run_of_many_pieces_becomes_a_few() {
        let merged = decimate(&straight(10_000), 0.1);
        // One piece a chunk of CHUNK pieces: 10,000 / 4096, rounded up.
        assert_eq!(merged.len(), 3);
        assert_eq!(merged[0].from, [0.0; 3]);
        assert_eq!(merged[2].to, [10_000.0, 0.0, 0.0]);
        assert_eq!(merged.iter().map(|p| p.line).collect::<Vec<_>>(), [0, 4096, 8192]);
        for pair in merged.windows(2) {
            assert_eq!(pair[0].to, pair[1].from);
        }
    }

    #[test]
    fn kinds_are_never_merged_and_gaps_are_kept() {
        let mut pieces = straight(4);
        pieces[2].kind = PieceKind::Rapid;
        pieces[3].from = [3.0, 5.0, 0.0];
        let merged = decimate(&pieces, 0.1);
        let kept: Vec<(u32, PieceKind)> = merged.iter().map(|p| (p.line, p.kind)).collect();
        assert_eq!(kept, [(0, PieceKind::Line), (2, PieceKind::Rapid), (3, PieceKind::Line)]);
        assert_eq!(merged[0].to, [2.0, 0.0, 0.0]);
    }

    #[test]
    fn a_curve_decimated_stays_within_the_tolerance() {
        // A quarter circle of radius 100 in 2,000 chords: far finer than the tolerance.
        let point = |k: usize| {
            let a = k as f64 / 2000.0 * std::f64::consts::FRAC_PI_2;
            [(100.0 * a.cos()) as f32, (100.0 * a.sin()) as f32, 0.0]
        };
        let pieces: Vec<Piece> = (0..2000)
            .map(|k| Piece { from: point(k), to: point(k + 1), line: k as u32, kind: PieceKind::Arc })
            .collect();
        let tolerance = 0.5;
        let merged = decimate(&pieces, tolerance);
        assert!(merged.len() < 100 && merged.len() > 4, "{} pieces", merged.len());
        // Every original point lies within the tolerance of the merged path...
        for k in 0..=2000 {
            let near = merged.iter().map(|m| distance_to_segment(point(k), m.from, m.to)).fold(f64::MAX, f64::min);
            assert!(near <= tolerance, "point {k} is {near} away");
        }
        // ...which is made of the original points, in order.
        for m in &merged {
            assert_eq!(m.from, point(m.line as usize));
        }
    }
}
