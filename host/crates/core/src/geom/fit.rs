//! A curve approximated by arcs and straight lines, within a tolerance.
//!
//! Each span of the curve is cut in halves until a piece is close enough to
//! a straight line, or to a biarc: two arcs meeting with a common tangent that
//! start and end where the piece does, with its tangents there, so the path
//! stays smooth where the curve is. Whatever is written is checked both ways
//! at samples: the curve against the pieces, and the pieces against the curve.

use glam::DVec2;

use super::spline::Nurbs;

/// One move of the approximation; it starts where the one before it ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Piece {
    Line {
        end: DVec2,
    },
    /// Less than half a turn about `centre`, counter-clockwise if `ccw`.
    Arc {
        end: DVec2,
        centre: DVec2,
        ccw: bool,
    },
}

impl Piece {
    pub fn end(&self) -> DVec2 {
        match *self {
            Piece::Line { end } | Piece::Arc { end, .. } => end,
        }
    }
}

/// How closely, and with what, a curve is approximated.
#[derive(Clone, Copy, Debug)]
pub struct Fit {
    /// How far the pieces may stray from the curve, and the curve from them.
    pub tolerance: f64,
    /// No arc is tighter than this: such turns are cut into lines.
    pub min_radius: f64,
    /// An arc that bulges less than this from its chord is written as its chord.
    pub flat: f64,
    /// The most pieces one curve may become.
    pub max_pieces: usize,
}

#[derive(Debug, PartialEq)]
pub enum FitError {
    /// The curve needs more than `max_pieces` within the tolerance.
    TooManyPieces,
    /// Its numbers are too large to compute with.
    NotFinite,
}

/// Samples of the curve on each piece tried, ends included.
const SAMPLES: usize = 32;
/// How many times a span may be halved; the last halves are lines.
const MAX_DEPTH: u32 = 40;

/// The pieces that follow `curve` from its start within `fit.tolerance`.
pub fn approximate(curve: &Nurbs, fit: &Fit) -> Result<Vec<Piece>, FitError> {
    let start = DVec2::from(curve.point(curve.domain().0));
    if !start.is_finite() {
        return Err(FitError::NotFinite);
    }
    let mut fitter = Fitter { curve, fit, pieces: Vec::new(), at: start };
    for (span, a, b) in curve.spans() {
        fitter.interval(span, a, b, 0)?;
    }
    Ok(fitter.pieces)
}

struct Fitter<'a> {
    curve: &'a Nurbs,
    fit: &'a Fit,
    pieces: Vec<Piece>,
    /// Where the pieces so far end.
    at: DVec2,
}

impl Fitter<'_> {
    fn interval(&mut self, span: usize, a: f64, b: f64, depth: u32) -> Result<(), FitError> {
        let samples: Vec<DVec2> = (0..=SAMPLES)
            .map(|k| self.curve.sample(span, a + (b - a) * k as f64 / SAMPLES as f64).point.into())
            .collect();
        // Distances square coordinates: beyond this they overflow.
        if !samples.iter().all(|v| v.abs().max_element() < 1e150) {
            return Err(FitError::NotFinite);
        }
        let end = samples[SAMPLES];
        let line = [Piece::Line { end }];
        if depth >= MAX_DEPTH || self.fits(&line, &samples) {
            return self.push(&line);
        }
        let tangents = (self.tangent(span, a, b), self.tangent(span, b, a));
        if let (Some(start_tangent), Some(end_tangent)) = tangents {
            if let Some(biarc) = self.biarc(start_tangent, end, end_tangent) {
                if self.fits(&biarc, &samples) {
                    return self.push(&biarc);
                }
            }
        }
        let middle = (a + b) / 2.0;
        self.interval(span, a, middle, depth + 1)?;
        self.interval(span, middle, b, depth + 1)
    }

    fn push(&mut self, pieces: &[Piece]) -> Result<(), FitError> {
        for piece in pieces {
            let end = piece.end();
            if let Piece::Arc { centre, .. } = piece {
                if !centre.is_finite() {
                    return Err(FitError::NotFinite);
                }
            } else if end == self.at {
                continue;
            }
            if self.pieces.len() >= self.fit.max_pieces {
                return Err(FitError::TooManyPieces);
            }
            self.pieces.push(*piece);
            self.at = end;
        }
        Ok(())
    }

    /// The unit tangent at `t`, heading along the curve; where the derivative
    /// vanishes (coinciding control points), the direction to a point just
    /// inside the piece, towards `other` (its other end).
    fn tangent(&self, span: usize, t: f64, other: f64) -> Option<DVec2> {
        let sample = self.curve.sample(span, t);
        let (point, derivative) = (DVec2::from(sample.point), DVec2::from(sample.derivative));
        let along = if other > t { 1.0 } else { -1.0 };
        let size = point.distance(self.curve.sample(span, other).point.into());
        if derivative.length() * (other - t).abs() > 1e-9 * size {
            return unit(derivative);
        }
        let near = DVec2::from(self.curve.sample(span, t + (other - t) * 1e-4).point);
        unit(along * (near - point))
    }

    /// Two arcs from `self.at` (leaving along `t0`) to `end` (arriving along
    /// `t1`), meeting with a common tangent. The two tangent lengths are made
    /// equal, which fixes the point where they meet.
    fn biarc(&self, t0: DVec2, end: DVec2, t1: DVec2) -> Option<[Piece; 2]> {
        let start = self.at;
        let (v, t) = (end - start, t0 + t1);
        let (vt, vv) = (v.dot(t), v.dot(v));
        // |v − d t| = 2 d, solved for d > 0 in the form that stays exact as
        // the tangents become parallel.
        let q = vt + (vt * vt + 2.0 * (1.0 - t0.dot(t1)) * vv).sqrt();
        let d = vv / q;
        if !(d > 0.0 && d.is_finite()) {
            return None;
        }
        let (q0, q1) = (start + d * t0, end - d * t1);
        let joint = (q0 + q1) / 2.0;
        let joint_tangent = unit(q1 - q0)?;
        Some([self.arc(start, t0, joint)?, self.arc(joint, joint_tangent, end)?])
    }

    /// The arc from `from`, leaving along `tangent`, to `to`; a line where it is
    /// as good as straight; none if it is half a turn or more, or too tight.
    fn arc(&self, from: DVec2, tangent: DVec2, to: DVec2) -> Option<Piece> {
        let chord = to - from;
        let length = chord.length();
        if length == 0.0 {
            return Some(Piece::Line { end: to });
        }
        // The angle between the tangent and the chord is half the arc's turn.
        let cos_half_turn = tangent.dot(chord) / length;
        if cos_half_turn <= 0.0 {
            return None;
        }
        let left = tangent.perp();
        let side = left.dot(chord);
        if side == 0.0 {
            return Some(Piece::Line { end: to });
        }
        // The centre is on the left normal, as far from `from` as from `to`.
        let offset = length * length / (2.0 * side);
        let radius = offset.abs();
        if radius * (1.0 - cos_half_turn) <= self.fit.flat {
            return Some(Piece::Line { end: to });
        }
        if radius < self.fit.min_radius {
            return None;
        }
        let centre = from + offset * left;
        Some(Piece::Arc { end: to, centre, ccw: offset > 0.0 })
    }

    /// Whether `pieces`, from `self.at`, stay within the tolerance of the
    /// curve through `samples`, and it of them.
    fn fits(&self, pieces: &[Piece], samples: &[DVec2]) -> bool {
        // A margin for what the curve does between samples.
        let tolerance = 0.9 * self.fit.tolerance;
        let mut starts = Vec::with_capacity(pieces.len());
        let mut at = self.at;
        for piece in pieces {
            starts.push(at);
            at = piece.end();
        }
        let near_pieces = |p: DVec2| {
            pieces.iter().zip(&starts).any(|(piece, &start)| distance_to_piece(p, start, piece) <= tolerance)
        };
        if !samples.iter().all(|&p| near_pieces(p)) {
            return false;
        }
        let near_curve = |p: DVec2| samples.windows(2).any(|leg| distance_to_segment(p, leg[0], leg[1]) <= tolerance);
        pieces
            .iter()
            .zip(&starts)
            .all(|(piece, &start)| (1..8).all(|k| near_curve(point_on(piece, start, k as f64 / 8.0))))
    }
}

/// `v` scaled to length 1, unless it has no direction.
fn unit(v: DVec2) -> Option<DVec2> {
    let length = v.length();
    (length > 0.0 && length.is_finite()).then(|| v / length)
}

fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let length_squared = ab.dot(ab);
    let t = if length_squared == 0.0 { 0.0 } else { ((p - a).dot(ab) / length_squared).clamp(0.0, 1.0) };
    p.distance(a + t * ab)
}

/// How far an arc piece turns from its start, in radians (0 to 2π), and the
/// angle of `p` from the start in the same sense.
fn turns(start: DVec2, centre: DVec2, end: DVec2, ccw: bool, p: DVec2) -> (f64, f64) {
    let angle = |q: DVec2| {
        let (u, w) = (start - centre, q - centre);
        let turn = u.perp_dot(w).atan2(u.dot(w));
        let turn = if ccw { turn } else { -turn };
        if turn < 0.0 {
            turn + std::f64::consts::TAU
        } else {
            turn
        }
    };
    (angle(end), angle(p))
}

/// The distance from `p` to a piece that starts at `start`.
fn distance_to_piece(p: DVec2, start: DVec2, piece: &Piece) -> f64 {
    match *piece {
        Piece::Line { end } => distance_to_segment(p, start, end),
        Piece::Arc { end, centre, ccw } => {
            let (sweep, at) = turns(start, centre, end, ccw, p);
            if at <= sweep {
                (p.distance(centre) - start.distance(centre)).abs()
            } else {
                p.distance(start).min(p.distance(end))
            }
        }
    }
}

/// The point a fraction `f` of the way along a piece that starts at `start`.
fn point_on(piece: &Piece, start: DVec2, f: f64) -> DVec2 {
    match *piece {
        Piece::Line { end } => start + f * (end - start),
        Piece::Arc { end, centre, ccw } => {
            let (sweep, _) = turns(start, centre, end, ccw, end);
            let angle = if ccw { f * sweep } else { -f * sweep };
            centre + DVec2::from_angle(angle).rotate(start - centre)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Inch defaults: 0.001 in, less the output's rounding.
    const FIT: Fit = Fit { tolerance: 0.0009, min_radius: 0.001, flat: 0.00005, max_pieces: 100_000 };

    /// The curve's equation, written independently of `Nurbs`: the rational
    /// B-spline by the Cox-de Boor recursion on its basis functions.
    fn basis(i: usize, order: usize, u: f64, knots: &[f64], last: bool) -> f64 {
        if order == 1 {
            let inside = knots[i] <= u && u < knots[i + 1];
            // The last span is closed at its end so that the curve reaches it.
            let at_end = last && u == knots[i + 1] && knots[i] < knots[i + 1];
            return if inside || at_end { 1.0 } else { 0.0 };
        }
        let left = knots[i + order - 1] - knots[i];
        let right = knots[i + order] - knots[i + 1];
        let mut value = 0.0;
        if left > 0.0 {
            value += (u - knots[i]) / left * basis(i, order - 1, u, knots, last);
        }
        if right > 0.0 {
            value += (knots[i + order] - u) / right * basis(i + 1, order - 1, u, knots, last);
        }
        value
    }

    struct Equation {
        points: Vec<[f64; 3]>,
        order: usize,
        knots: Vec<f64>,
    }

    impl Equation {
        fn bezier(points: &[[f64; 2]]) -> Equation {
            let order = points.len();
            let knots = (0..2 * order).map(|i| if i < order { 0.0 } else { 1.0 }).collect();
            Equation { points: points.iter().map(|p| [p[0], p[1], 1.0]).collect(), order, knots }
        }

        /// LinuxCNC's knots, as its documentation and `knot_vector_creator` give them.
        fn linuxcnc(points: &[[f64; 3]], order: usize) -> Equation {
            let n = points.len() - 1;
            let knots = (0..=n + order)
                .map(|i| match i {
                    i if i < order => 0.0,
                    i if i <= n => (i + 1 - order) as f64,
                    _ => (n + 2 - order) as f64,
                })
                .collect();
            Equation { points: points.to_vec(), order, knots }
        }

        fn at(&self, f: f64) -> DVec2 {
            let (low, high) = (self.knots[0], self.knots[self.knots.len() - 1]);
            let u = low + f * (high - low);
            let (mut x, mut y, mut w) = (0.0, 0.0, 0.0);
            for (i, p) in self.points.iter().enumerate() {
                let b = basis(i, self.order, u, &self.knots, f == 1.0) * p[2];
                x += b * p[0];
                y += b * p[1];
                w += b;
            }
            DVec2::new(x / w, y / w)
        }
    }

    /// The largest distance from the curve to the path, and from the path to
    /// the curve, by dense sampling of both; a point's distance to the curve
    /// is refined from the nearest sample by a ternary search on the parameter.
    fn deviation(equation: &Equation, pieces: &[Piece]) -> (f64, f64) {
        const N: usize = 4000;
        let curve: Vec<DVec2> = (0..=N).map(|k| equation.at(k as f64 / N as f64)).collect();
        let mut starts = vec![curve[0]];
        for piece in pieces {
            starts.push(piece.end());
        }
        let to_path = |p: DVec2| {
            pieces.iter().zip(&starts).map(|(piece, &s)| distance_to_piece(p, s, piece)).fold(f64::INFINITY, f64::min)
        };
        let curve_to_path = curve.iter().map(|&p| to_path(p)).fold(0.0, f64::max);
        let to_curve = |p: DVec2| {
            let nearest = (0..=N).min_by(|&a, &b| p.distance(curve[a]).total_cmp(&p.distance(curve[b]))).unwrap();
            let (mut low, mut high) =
                (nearest.saturating_sub(1) as f64 / N as f64, (nearest + 1).min(N) as f64 / N as f64);
            for _ in 0..60 {
                let (a, b) = (low + (high - low) / 3.0, high - (high - low) / 3.0);
                if p.distance(equation.at(a)) < p.distance(equation.at(b)) {
                    high = b;
                } else {
                    low = a;
                }
            }
            p.distance(equation.at((low + high) / 2.0)).min(p.distance(curve[nearest]))
        };
        let path_to_curve = pieces
            .iter()
            .zip(&starts)
            .flat_map(|(piece, &s)| (0..=20).map(move |k| point_on(piece, s, f64::from(k) / 20.0)))
            .map(to_curve)
            .fold(0.0, f64::max);
        (curve_to_path, path_to_curve)
    }

    fn check(equation: &Equation, curve: &Nurbs) -> Vec<Piece> {
        let pieces = approximate(curve, &FIT).unwrap();
        let last = pieces.last().expect("pieces").end();
        let end = equation.at(1.0);
        assert!(last.distance(end) < 1e-9, "ends at {last:?}, not {end:?}");
        let (curve_to_path, path_to_curve) = deviation(equation, &pieces);
        assert!(curve_to_path <= FIT.tolerance, "the curve strays {curve_to_path} from the path");
        assert!(path_to_curve <= FIT.tolerance, "the path strays {path_to_curve} from the curve");
        for piece in &pieces {
            if let Piece::Arc { centre, .. } = piece {
                assert!(centre.is_finite());
            }
        }
        let radii_ok = pieces.iter().zip(std::iter::once(equation.at(0.0)).chain(pieces.iter().map(Piece::end))).all(
            |(piece, start)| match piece {
                Piece::Arc { centre, end, .. } => {
                    let (r0, r1) = (start.distance(*centre), end.distance(*centre));
                    (r0 - r1).abs() < 1e-9 && r0 >= FIT.min_radius
                }
                Piece::Line { .. } => true,
            },
        );
        assert!(radii_ok, "an arc's ends are off its circle, or it is too tight: {pieces:?}");
        pieces
    }

    #[test]
    fn cubics_of_every_shape_stay_within_the_tolerance() {
        let shapes: [[[f64; 2]; 4]; 5] = [
            // An S.
            [[0.0, 0.0], [1.0, 0.0], [-0.5, 1.0], [1.0, 1.0]],
            // A loop: the curve crosses itself.
            [[0.0, 0.0], [3.0, 2.0], [-1.0, 2.0], [2.0, 0.0]],
            // A cusp: the control legs cross so that the curve stops and turns back.
            [[0.0, 0.0], [2.0, 1.0], [0.0, 1.0], [2.0, 0.0]],
            // A long shallow arch, 10 in wide.
            [[0.0, 0.0], [3.0, 0.5], [7.0, 0.5], [10.0, 0.0]],
            // First control point on the start: the tangent comes from the second.
            [[0.0, 0.0], [0.0, 0.0], [1.0, 1.0], [2.0, 0.0]],
        ];
        for shape in shapes {
            check(&Equation::bezier(&shape), &Nurbs::bezier(&shape));
        }
    }

    #[test]
    fn quadratics_stay_within_the_tolerance() {
        for shape in [[[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]], [[0.0, 0.0], [5.0, 0.1], [-1.0, 0.2]]] {
            check(&Equation::bezier(&shape), &Nurbs::bezier(&shape));
        }
    }

    #[test]
    fn nurbs_of_several_orders_and_weights_stay_within_the_tolerance() {
        let points = [
            [0.0, 0.0, 1.0],
            [1.0, 2.0, 2.0],
            [2.0, -1.0, 0.5],
            [3.5, 1.5, 1.0],
            [4.0, 0.0, 3.0],
            [5.0, 2.0, 1.0],
            [6.0, 0.0, 1.0],
        ];
        for order in 3..=6 {
            check(&Equation::linuxcnc(&points, order), &Nurbs::clamped(&points, order));
        }
        // gcode-rs's sample: order 3, the start weighted 1 and the next point 2.
        let sample = [[0.0, 0.0, 1.0], [3.53, -1.5, 2.0], [5.33, -11.01, 1.0], [3.52, -24.0, 1.0], [0.0, -29.56, 1.0]];
        check(&Equation::linuxcnc(&sample, 3), &Nurbs::clamped(&sample, 3));
    }

    #[test]
    fn a_straight_curve_is_one_line() {
        let shape = [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]];
        assert_eq!(approximate(&Nurbs::bezier(&shape), &FIT).unwrap(), [Piece::Line { end: DVec2::new(3.0, 3.0) }]);
    }

    #[test]
    fn a_circular_arc_is_found_exactly() {
        // The quarter circle of radius 2 about the origin, as a rational
        // quadratic: the biarc of a circular arc is two arcs of that circle.
        let w = 0.5f64.sqrt();
        let points = [[2.0, 0.0, 1.0], [2.0, 2.0, w], [0.0, 2.0, 1.0]];
        let pieces = check(&Equation::linuxcnc(&points, 3), &Nurbs::clamped(&points, 3));
        assert_eq!(pieces.len(), 2, "{pieces:?}");
        for piece in pieces {
            let Piece::Arc { centre, ccw, .. } = piece else { panic!("{piece:?} is not an arc") };
            assert!(ccw && centre.length() < 1e-9, "{piece:?}");
        }
    }

    #[test]
    fn a_curve_that_goes_nowhere_is_no_pieces() {
        let shape = [[1.0, 1.0]; 4];
        assert_eq!(approximate(&Nurbs::bezier(&shape), &FIT).unwrap(), []);
    }

    #[test]
    fn tight_turns_are_lines_not_tiny_arcs() {
        // A cusp: its neighbourhood turns tighter than any radius.
        let shape = [[0.0, 0.0], [2.0, 1.0], [0.0, 1.0], [2.0, 0.0]];
        let fit = Fit { min_radius: 0.05, ..FIT };
        let pieces = approximate(&Nurbs::bezier(&shape), &fit).unwrap();
        let mut start = DVec2::ZERO;
        for piece in &pieces {
            if let Piece::Arc { centre, .. } = piece {
                assert!(start.distance(*centre) >= 0.05, "{piece:?}");
            }
            start = piece.end();
        }
        assert!(pieces.iter().any(|p| matches!(p, Piece::Line { .. })));
    }

    #[test]
    fn huge_numbers_and_too_many_pieces_are_errors() {
        let huge = [[0.0, 0.0], [1e300, 1e300], [-1e300, 1e300], [1.0, 0.0]];
        assert_eq!(approximate(&Nurbs::bezier(&huge), &FIT), Err(FitError::NotFinite));
        let wide = [[0.0, 0.0], [1000.0, 2000.0], [2000.0, -2000.0], [3000.0, 0.0]];
        let fit = Fit { max_pieces: 10, ..FIT };
        assert_eq!(approximate(&Nurbs::bezier(&wide), &fit), Err(FitError::TooManyPieces));
    }
}
