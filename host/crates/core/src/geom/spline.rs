//! Plane curves given by control points: rational B-splines (NURBS),
//! evaluated with de Boor's algorithm on homogeneous points.
//!
//! LinuxCNC's G5 is a cubic Bézier curve, G5.1 a quadratic one and G5.2/G5.3
//! a NURBS on a clamped uniform knot vector; a Bézier curve is the B-spline
//! with one span, so one type serves all three.

/// A rational B-spline in the plane.
#[derive(Clone, Debug, PartialEq)]
pub struct Nurbs {
    degree: usize,
    knots: Vec<f64>,
    /// The control points as (w x, w y, w).
    points: Vec<[f64; 3]>,
}

/// A curve's point and first derivative at one parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub point: [f64; 2],
    pub derivative: [f64; 2],
}

impl Nurbs {
    /// The Bézier curve of `points`: it starts at the first, ends at the last
    /// and is pulled towards the others; its degree is one less than their
    /// number (at least two). The parameter runs from 0 to 1.
    pub fn bezier(points: &[[f64; 2]]) -> Nurbs {
        let order = points.len();
        assert!(order >= 2, "a Bézier curve needs two points");
        let knots = (0..2 * order).map(|i| if i < order { 0.0 } else { 1.0 }).collect();
        Nurbs { degree: order - 1, knots, points: points.iter().map(|&[x, y]| [x, y, 1.0]).collect() }
    }

    /// LinuxCNC's G5.2 curve: control points `[x, y, weight]` (weights above
    /// zero) and its order (degree + 1, at least 2 and at most the number of
    /// points), on the knots 0 (`order` times), 1, 2, ..., n − order + 1, then
    /// n − order + 2 (`order` times), where n + 1 is the number of points. It
    /// starts at the first point and ends at the last.
    pub fn clamped(points: &[[f64; 3]], order: usize) -> Nurbs {
        let n = points.len() - 1;
        assert!(order >= 2 && order <= points.len(), "order {order} with {} points", points.len());
        let knots = (0..=n + order)
            .map(|i| {
                if i < order {
                    0.0
                } else if i <= n {
                    (i - order + 1) as f64
                } else {
                    (n + 2 - order) as f64
                }
            })
            .collect();
        let points = points.iter().map(|&[x, y, w]| [w * x, w * y, w]).collect();
        Nurbs { degree: order - 1, knots, points }
    }

    /// The spans where the curve is one polynomial (or ratio of two): `(index,
    /// start, end)` of the parameter, in order. The curve is smooth inside
    /// each; at their ends it may have a corner if control points coincide.
    pub fn spans(&self) -> Vec<(usize, f64, f64)> {
        (self.degree..self.points.len())
            .filter(|&j| self.knots[j] < self.knots[j + 1])
            .map(|j| (j, self.knots[j], self.knots[j + 1]))
            .collect()
    }

    /// The curve's point at parameter `t` (clamped to its range).
    pub fn point(&self, t: f64) -> [f64; 2] {
        let spans = self.spans();
        let &(span, ..) = spans.iter().find(|(_, _, end)| t < *end).unwrap_or(spans.last().expect("a span"));
        self.sample(span, t).point
    }

    /// The point and derivative at `t` of span `span`'s polynomial, which
    /// need not contain `t` (at a span's end, the derivative from inside it).
    pub fn sample(&self, span: usize, t: f64) -> Sample {
        let p = self.degree;
        // de Boor: blend the p + 1 control points of the span, one level at a time.
        let mut d: Vec<[f64; 3]> = self.points[span - p..=span].to_vec();
        let blend = |d: &mut Vec<[f64; 3]>, r: usize| {
            for i in (r..=p).rev() {
                let low = self.knots[span - p + i];
                let alpha = (t - low) / (self.knots[span + 1 + i - r] - low);
                d[i] = std::array::from_fn(|k| (1.0 - alpha) * d[i - 1][k] + alpha * d[i][k]);
            }
        };
        for r in 1..p {
            blend(&mut d, r);
        }
        let last_level = [d[p - 1], d[p]];
        blend(&mut d, p);
        // The derivative of the polynomial is p times the difference of the
        // last level's two points over the span's length.
        let length = self.knots[span + 1] - self.knots[span];
        let h = d[p];
        let dh: [f64; 3] = std::array::from_fn(|k| p as f64 * (last_level[1][k] - last_level[0][k]) / length);
        let point = [h[0] / h[2], h[1] / h[2]];
        let derivative = [(dh[0] - dh[2] * point[0]) / h[2], (dh[1] - dh[2] * point[1]) / h[2]];
        Sample { point, derivative }
    }

    /// The first and last values of the parameter.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.points.len()])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 2], b: [f64; 2], tolerance: f64) -> bool {
        (a[0] - b[0]).abs() <= tolerance && (a[1] - b[1]).abs() <= tolerance
    }

    /// The cubic Bézier curve by its Bernstein form, written out.
    fn cubic(p: [[f64; 2]; 4], t: f64) -> [f64; 2] {
        let s = 1.0 - t;
        let b = [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t];
        std::array::from_fn(|k| (0..4).map(|i| b[i] * p[i][k]).sum())
    }

    #[test]
    fn a_bezier_curve_follows_the_bernstein_formula() {
        let p = [[0.0, 0.0], [1.0, 2.0], [3.0, -1.0], [4.0, 1.0]];
        let curve = Nurbs::bezier(&p);
        assert_eq!(curve.domain(), (0.0, 1.0));
        for k in 0..=20 {
            let t = f64::from(k) / 20.0;
            assert!(close(curve.point(t), cubic(p, t), 1e-12), "t = {t}");
        }
        // The derivative at the ends points at the inner control points: 3 (P1 − P0).
        let start = curve.sample(3, 0.0);
        assert!(close(start.derivative, [3.0, 6.0], 1e-12), "{start:?}");
        let end = curve.sample(3, 1.0);
        assert!(close(end.derivative, [3.0, 6.0], 1e-12), "{end:?}");
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let points = [[0.0, 0.0, 1.0], [1.0, 3.0, 2.0], [2.0, -1.0, 0.5], [4.0, 2.0, 1.0], [5.0, 0.0, 3.0]];
        for order in 2..=5 {
            let curve = Nurbs::clamped(&points, order);
            for (span, start, end) in curve.spans() {
                for k in 1..10 {
                    let t = start + (end - start) * f64::from(k) / 10.0;
                    let h = 1e-6;
                    let (a, b) = (curve.sample(span, t - h).point, curve.sample(span, t + h).point);
                    let numeric = [(b[0] - a[0]) / (2.0 * h), (b[1] - a[1]) / (2.0 * h)];
                    let exact = curve.sample(span, t).derivative;
                    assert!(close(numeric, exact, 1e-5), "order {order} at {t}: {numeric:?} against {exact:?}");
                }
            }
        }
    }

    #[test]
    fn linuxcnc_knots_clamp_the_ends() {
        // Five points of order 3: knots 0 0 0 1 2 3 3 3, three spans.
        let points = [[0.0, 0.0, 1.0], [1.0, 1.0, 1.0], [2.0, 0.0, 1.0], [3.0, 1.0, 1.0], [4.0, 0.0, 1.0]];
        let curve = Nurbs::clamped(&points, 3);
        assert_eq!(curve.knots, [0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0]);
        assert_eq!(curve.spans().len(), 3);
        assert_eq!(curve.domain(), (0.0, 3.0));
        assert!(close(curve.point(0.0), [0.0, 0.0], 1e-12));
        assert!(close(curve.point(3.0), [4.0, 0.0], 1e-12));
        // A uniform quadratic B-spline passes through the midpoints of its
        // inner legs at the inner knots: (P1 + P2) / 2 at u = 1.
        assert!(close(curve.point(1.0), [1.5, 0.5], 1e-12));
        assert!(close(curve.point(2.0), [2.5, 0.5], 1e-12));
    }

    #[test]
    fn weights_pull_the_curve_and_a_conic_is_exact() {
        // A quarter circle: the quadratic with weights 1, √½, 1.
        let w = 0.5f64.sqrt();
        let curve = Nurbs::clamped(&[[1.0, 0.0, 1.0], [1.0, 1.0, w], [0.0, 1.0, 1.0]], 3);
        for k in 0..=16 {
            let [x, y] = curve.point(f64::from(k) / 16.0);
            assert!((x.hypot(y) - 1.0).abs() < 1e-12, "({x}, {y})");
        }
    }
}
