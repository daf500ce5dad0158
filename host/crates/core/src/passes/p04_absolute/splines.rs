//! Splines (lenient dialect), with LinuxCNC's meaning, become arcs and lines
//! within `[machine] spline_tolerance`, at the feed in force, in the XY plane
//! at the tool's Z:
//!
//! - `G5 I J P Q X Y`: the cubic Bézier curve from the tool to X Y, its first
//!   control point I J from the start and its second P Q from the end. I and
//!   J may be left out on a G5 that follows another: the first control point
//!   then mirrors the second of the one before, so the path stays smooth.
//! - `G5.1 I J X Y`: the quadratic Bézier curve, its control point I J from the start.
//! - `G5.2 X Y P L`, then lines of `X Y P`, then `G5.3`: the NURBS whose
//!   first control point is where the tool is (with the weight of a P given
//!   without X and Y on the first line, else 1), then each X Y with its
//!   weight P, of order L (default 3; the last L given counts), on
//!   LinuxCNC's knots. It is drawn at G5.3. As in LinuxCNC, every point is
//!   measured from where the curve starts in G91, not from the point before.
//!
//! What LinuxCNC does silently is an error here: a move inside a NURBS (it
//! drops the NURBS), or a NURBS never ended.

use super::{Absolute, Feed};
use crate::config::Config;
use crate::diag::Diagnostic;
use crate::geom::fit::{approximate, Fit, FitError, Piece};
use crate::geom::spline::Nurbs;
use crate::passes::Out;
use crate::statement::{
    Axes, FeedMode, Kind, Motion, MotionMode, Plane, Spline, SplineCode, Statement, Value, MAX_NURBS_POINTS,
};

/// The most moves one curve may become.
const MAX_PIECES: usize = 100_000;

pub struct SplineState {
    fit: Fit,
    /// For messages: the tolerance as configured.
    tolerance: f64,
    /// While the last move was a G5: its second control point from its end,
    /// mirrored, which a G5 without I and J takes as its first.
    pub series: Option<[f64; 2]>,
    nurbs: Option<OpenNurbs>,
}

enum OpenNurbs {
    Collecting {
        /// The statement that began it, for messages.
        start: Statement,
        /// `[x, y, weight]` in machine coordinates.
        points: Vec<[f64; 3]>,
        order: usize,
    },
    /// Refused at its start: its other lines and its G5.3 go quietly.
    Refused,
}

impl SplineState {
    pub fn new(config: &Config) -> SplineState {
        let units = config.units;
        let resolution = 10f64.powi(-(units.decimals() as i32));
        let tolerance = config.spline_tolerance();
        let fit = Fit {
            // Rounding the output moves an arc's ends and centre each by up
            // to half a unit of its last decimal in X and in Y.
            tolerance: tolerance - resolution * std::f64::consts::SQRT_2,
            // Below the arc tolerance a radius reads as zero; below
            // [check] min_arc_radius the controller is said to refuse it.
            min_radius: tolerance.max(config.min_arc_radius()).max(2.0 * units.arc_tolerance()),
            flat: resolution / 2.0,
            max_pieces: MAX_PIECES,
        };
        SplineState { fit, tolerance, series: None, nurbs: None }
    }
}

impl Absolute {
    pub(super) fn spline(&mut self, spline: &Spline, statement: &Statement, out: &mut Out) -> Result<(), Diagnostic> {
        if let Some(f) = spline.feed {
            self.feed = Some(f.value);
        }
        let code = spline.code.expect("pass 00 gives every spline its code");
        if code == SplineCode::Nurbs {
            return self.nurbs_point(spline, statement);
        }
        let series = self.splines.series.take();
        self.ready(code, statement)?;
        let start = [self.position[0], self.position[1]];
        let end = [
            spline.target.x.map_or(start[0], |x| self.absolute(0, x).value),
            spline.target.y.map_or(start[1], |y| self.absolute(1, y).value),
        ];
        let offset = |from: [f64; 2], [i, j]: [f64; 2]| [from[0] + i, from[1] + j];
        let first = match (pair(&spline.first), series) {
            (Some(given), _) => offset(start, given),
            (None, Some(mirrored)) => offset(start, mirrored),
            (None, None) => {
                return Err(Diagnostic::error(
                    statement.span,
                    "G05 without I and J must follow another G05, whose end it continues smoothly",
                )
                .with_help("give the first control point with I and J, relative to the start"))
            }
        };
        let curve = match code {
            SplineCode::Cubic => {
                let second = pair(&spline.second).expect("the parser requires P and Q on a G05");
                Nurbs::bezier(&[start, first, offset(end, second), end])
            }
            _ => Nurbs::bezier(&[start, first, end]),
        };
        self.draw(code, &curve, end, statement, out)?;
        if code == SplineCode::Cubic {
            let [p, q] = pair(&spline.second).expect("the parser requires P and Q on a G05");
            self.splines.series = Some([-p, -q]);
        }
        Ok(())
    }

    /// A curve needs the XY plane and a feed, as in LinuxCNC.
    fn ready(&mut self, code: SplineCode, statement: &Statement) -> Result<(), Diagnostic> {
        if self.plane != Plane::XY {
            let code = code.code();
            return Err(Diagnostic::error(
                statement.span,
                format!("splines must be in the XY plane: {code} draws in X and Y"),
            )
            .with_help(format!("select it with G17 before the {code}")));
        }
        self.curve_feed(code, statement).map(|_| ())
    }

    /// The feed per minute a curve's moves run at: the one in force (or
    /// `[machine] default_feed`). A feed per move (G93) or per revolution
    /// (G95) would have to be shared out among the moves: refused.
    fn curve_feed(&mut self, code: SplineCode, statement: &Statement) -> Result<f64, Diagnostic> {
        let code = code.code();
        if self.feed_mode != FeedMode::PerMinute {
            return Err(Diagnostic::error(
                statement.span,
                format!("{code} is accepted only with feeds per minute (G94)"),
            )
            .with_help("its arcs and lines share one feed; write G94 and F in units per minute before it"));
        }
        match self.feed_rate(MotionMode::Linear, None, statement.span) {
            Ok(Feed::PerMinute(feed)) => Ok(feed),
            _ => Err(Diagnostic::error(statement.span, format!("{code} move before any feed rate (F)"))
                .with_help(format!("give the feed on this line or before it, e.g. {code} ... F10"))),
        }
    }

    fn nurbs_point(&mut self, spline: &Spline, statement: &Statement) -> Result<(), Diagnostic> {
        let point = spline.target.x.zip(spline.target.y).map(|(x, y)| {
            let weight = spline.weight.expect("the parser requires P with X and Y").value;
            [self.absolute(0, x).value, self.absolute(1, y).value, weight]
        });
        let Some(open) = &mut self.splines.nurbs else {
            if let Err(diagnostic) = self.ready(SplineCode::Nurbs, statement) {
                self.splines.nurbs = Some(OpenNurbs::Refused);
                return Err(diagnostic);
            }
            // The tool's position is the first control point.
            let start_weight = if point.is_none() { spline.weight.map_or(1.0, |p| p.value) } else { 1.0 };
            let mut points = vec![[self.position[0], self.position[1], start_weight]];
            points.extend(point);
            let order = spline.order.unwrap_or(3) as usize;
            self.splines.nurbs = Some(OpenNurbs::Collecting { start: statement.clone(), points, order });
            return Ok(());
        };
        let OpenNurbs::Collecting { points, order, .. } = open else { return Ok(()) };
        if let Some(l) = spline.order {
            *order = l as usize;
        }
        match (point, spline.weight) {
            (Some(_), _) if points.len() >= MAX_NURBS_POINTS => {
                self.splines.nurbs = Some(OpenNurbs::Refused);
                Err(Diagnostic::error(
                    statement.span,
                    format!("a NURBS may have at most {MAX_NURBS_POINTS} control points"),
                )
                .with_help("end it with G5.3 and go on with another G5.2"))
            }
            (Some(point), _) => {
                points.push(point);
                Ok(())
            }
            (None, Some(p)) => Err(Diagnostic::error(p.span, "P without X and Y sets the weight of the start only")
                .with_help("it goes on the NURBS's first line; give this point's X and Y with its P")),
            (None, None) => Ok(()),
        }
    }

    pub(super) fn nurbs_end(&mut self, statement: &Statement, out: &mut Out) -> Result<(), Diagnostic> {
        match self.splines.nurbs.take() {
            None => Err(Diagnostic::error(statement.span, "G5.3 without a G5.2 before it")
                .with_help("G5.2 starts a NURBS, lines of X Y P give its control points, and G5.3 ends and draws it")),
            Some(OpenNurbs::Refused) => Ok(()),
            Some(OpenNurbs::Collecting { points, order, .. }) => {
                if points.len() < order {
                    let given = points.len() - 1;
                    return Err(Diagnostic::error(
                        statement.span,
                        format!(
                            "a NURBS of order {order} needs at least {order} control points; this one has {} (the start and {given} more)",
                            points.len()
                        ),
                    )
                    .with_help("give more control points, or a lower order with L (3 at least)"));
                }
                let [x, y, _] = points[points.len() - 1];
                self.draw(SplineCode::Nurbs, &Nurbs::clamped(&points, order), [x, y], statement, out)
            }
        }
    }

    /// Moves of any other kind abandon a NURBS still open (LinuxCNC drops it
    /// without a word): say so, at the move.
    pub(super) fn close_nurbs_before(&mut self, statement: &Statement, out: &mut Out) {
        let interrupts = match &statement.kind {
            Kind::Motion(motion) | Kind::MachineMove(motion) => motion.moves(),
            Kind::Spline(spline) => spline.code != Some(SplineCode::Nurbs),
            Kind::Cycle(_) | Kind::Home { .. } | Kind::End => true,
            _ => false,
        };
        if !interrupts {
            return;
        }
        if let Some(OpenNurbs::Collecting { start, .. }) = self.splines.nurbs.take() {
            let line = start.span.line;
            let message = if statement.kind == Kind::End {
                format!("the program ends inside the NURBS begun at line {line}, which is never drawn")
            } else {
                format!("this comes inside the NURBS begun at line {line}, which has no G5.3 yet")
            };
            let diagnostic = Diagnostic::error(statement.span, message)
                .with_help("end the NURBS with G5.3 before anything else moves");
            out.error(statement, diagnostic);
        }
    }

    /// At the end of the program, a NURBS still open was never drawn.
    pub(super) fn unfinished_nurbs(&mut self, out: &mut Out) {
        if let Some(OpenNurbs::Collecting { start, .. }) = self.splines.nurbs.take() {
            let diagnostic = Diagnostic::error(start.span, "this NURBS has no G5.3 to end it, so it is never drawn")
                .with_help("end its control points with G5.3");
            out.error(&start, diagnostic);
        }
    }

    /// Arcs and lines along `curve`, the last one ending exactly at `end`.
    fn draw(
        &mut self,
        code: SplineCode,
        curve: &Nurbs,
        end: [f64; 2],
        statement: &Statement,
        out: &mut Out,
    ) -> Result<(), Diagnostic> {
        let feed = self.curve_feed(code, statement)?;
        let (u, d) = (self.units.abbreviation(), self.units.decimals());
        let pieces = approximate(curve, &self.splines.fit).map_err(|err| match err {
            FitError::TooManyPieces => Diagnostic::error(
                statement.span,
                format!(
                    "this curve needs more than {MAX_PIECES} moves to stay within the spline tolerance ({:.d$} {u})",
                    self.splines.tolerance
                ),
            )
            .with_help("raise [machine] spline_tolerance in ger.toml"),
            FitError::NotFinite => {
                Diagnostic::error(statement.span, "this curve's coordinates are too large to compute")
            }
        })?;
        let last = pieces.len().saturating_sub(1);
        for (k, piece) in pieces.iter().enumerate() {
            let to = if k == last { end } else { piece.end().to_array() };
            let (mode, centre) = match *piece {
                Piece::Line { .. } => (MotionMode::Linear, None),
                Piece::Arc { centre, ccw: true, .. } => (MotionMode::ArcCcw, Some(centre.to_array())),
                Piece::Arc { centre, ccw: false, .. } => (MotionMode::ArcCw, Some(centre.to_array())),
            };
            self.cut(mode, to, centre, feed, statement, out);
        }
        Ok(())
    }

    /// A line or an arc in the XY plane from the tool's position to `end`,
    /// written as pass 04 writes every move: an arc with both X and Y and its
    /// centre by I and J from the start; F where the output has not said it.
    fn cut(
        &mut self,
        mode: MotionMode,
        end: [f64; 2],
        centre: Option<[f64; 2]>,
        feed: f64,
        statement: &Statement,
        out: &mut Out,
    ) {
        if centre.is_none() && end == [self.position[0], self.position[1]] {
            return;
        }
        let at = |value: f64| Some(Value { value, span: statement.span });
        let mut motion = Motion { mode: Some(mode), ..Motion::default() };
        for (axis, &to) in end.iter().enumerate() {
            if centre.is_some() || to != self.position[axis] {
                *motion.target.slot(axis) = at(to);
            }
        }
        if let Some(centre) = centre {
            motion.centre = Axes { x: at(centre[0] - self.position[0]), y: at(centre[1] - self.position[1]), z: None };
        }
        if Some(feed) != self.feed_written {
            self.feed_written = Some(feed);
            motion.feed = at(feed);
        }
        self.position[0] = end[0];
        self.position[1] = end[1];
        out.push(statement.with_kind(Kind::Motion(Box::new(motion))));
    }
}

/// Two offsets given together (I J, P Q), if both are.
fn pair(axes: &Axes) -> Option<[f64; 2]> {
    axes.x.zip(axes.y).map(|(x, y)| [x.value, y.value])
}

#[cfg(test)]
mod tests {
    use crate::config::Config;
    use crate::passes::testing::run_with;
    use crate::statement::{Dialect, MAX_NURBS_POINTS};

    fn lenient(text: &str) -> Vec<String> {
        run_with(text, &Config { dialect: Dialect::Lenient.into(), ..Config::default() }, 4)
    }

    #[test]
    fn a_nurbs_keeps_at_most_so_many_points() {
        // The start is the first control point, so this many lines is one too many.
        let points: String = (0..MAX_NURBS_POINTS).map(|i| format!("X{i} Y{} P1\n", i % 2)).collect();
        let got = lenient(&format!("F10\nG5.2 {points}G5.3\nG01 X0"));
        let line = MAX_NURBS_POINTS + 1;
        assert_eq!(
            got,
            [
                format!("{line}:1: error: a NURBS may have at most {MAX_NURBS_POINTS} control points"),
                "G01 X0.0000 F10.0000".into()
            ]
        );
    }

    #[test]
    fn a_cubic_on_its_chord_is_one_line_and_the_feed_is_written_once() {
        // Control points at thirds of the chord: the curve is the chord.
        let got = lenient("G05 I1 J0 P-1 Q0 X3 Y0 F20\nG5.1 I1 J1 X5 Y2");
        assert_eq!(got, ["G01 X3.0000 F20.0000", "G01 X5.0000 Y2.0000"]);
    }
}
