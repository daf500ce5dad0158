//! Pass 03: polar coordinates. In G16 (only allowed in G91) a move's words for
//! the plane's first and second axes are a radius and an angle in degrees,
//! counter-clockwise from the first axis: in G17, `X r Y a`. This pass turns
//! them into ordinary incremental steps and drops G15/G16. The axis normal to
//! the plane stays a plain increment; arcs are not allowed while G16 is on.

use super::{Out, Pass};
use crate::diag::Diagnostic;
use crate::geom::polar_step;
use crate::statement::{Distance, Kind, Plane, Statement, Value};

pub struct Polar {
    on: bool,
    distance: Distance,
    plane: Plane,
}

impl Default for Polar {
    fn default() -> Polar {
        Polar { on: false, distance: Distance::Absolute, plane: Plane::XY }
    }
}

const AXIS_LETTERS: [char; 3] = ['X', 'Y', 'Z'];

impl Pass for Polar {
    fn statement(&mut self, mut statement: Statement, out: &mut Out) {
        match &mut statement.kind {
            Kind::Polar(true) => {
                if self.distance == Distance::Incremental {
                    self.on = true;
                } else {
                    let diagnostic =
                        Diagnostic::error(statement.span, "G16 (polar coordinates) needs incremental mode")
                            .with_help("write G91 before G16: polar moves step from the current position");
                    out.error(&statement, diagnostic);
                }
                return;
            }
            Kind::Polar(false) => {
                self.on = false;
                return;
            }
            Kind::Distance(Distance::Absolute) if self.on => {
                let diagnostic = Diagnostic::error(statement.span, "G90 while polar coordinates (G16) are on")
                    .with_help("polar moves are incremental; turn them off with G15 before G90");
                out.error(&statement, diagnostic);
                return;
            }
            Kind::Cycle(_) | Kind::Home { .. } | Kind::MachineMove(_) | Kind::Spline(_) | Kind::NurbsEnd if self.on => {
                let diagnostic = Diagnostic::error(statement.span, "not allowed in polar coordinates (G16)")
                    .with_help("turn polar coordinates off with G15 first");
                out.error(&statement, diagnostic);
                return;
            }
            Kind::Distance(distance) => self.distance = *distance,
            Kind::Plane(plane) => self.plane = *plane,
            Kind::Motion(motion) if self.on => {
                if motion.mode.is_some_and(|m| m.is_arc()) && motion.moves() {
                    let diagnostic =
                        Diagnostic::error(statement.span, "arcs (G02/G03) are not allowed in polar coordinates (G16)")
                            .with_help("turn polar coordinates off with G15 before the arc");
                    out.error(&statement, diagnostic);
                    return;
                }
                let (first, second, _) = self.plane.axes();
                match (motion.target.get(first), motion.target.get(second)) {
                    (Some(r), Some(angle)) => {
                        let (a, b) = polar_step(r.value, angle.value);
                        *motion.target.slot(first) = Some(Value { value: a, span: r.span });
                        *motion.target.slot(second) = Some(Value { value: b, span: angle.span });
                    }
                    (None, None) => {}
                    (given, _) => {
                        let span = given.or(motion.target.get(second)).expect("one is given").span;
                        let (r, a) = (AXIS_LETTERS[first], AXIS_LETTERS[second]);
                        let message = format!("a polar move needs both a radius ({r}) and an angle ({a})");
                        out.error(
                            &statement,
                            Diagnostic::error(span, message).with_help(format!("write e.g. {r}1.0 {a}45")),
                        );
                        return;
                    }
                }
            }
            _ => {}
        }
        out.push(statement);
    }
}

#[cfg(test)]
mod tests {
    use crate::passes::testing::run;

    #[test]
    fn polar_moves_become_incremental_steps() {
        let got = run("G91\nG16\nG01 X2 Y90 Z-1 F10\nX1 Y0\nG15\nX1", 3);
        assert_eq!(got, ["G91", "G01 X0.0000 Y2.0000 Z-1.0000 F10.0000", "G01 X1.0000 Y0.0000", "G01 X1.0000"]);
    }

    #[test]
    fn polar_follows_the_plane() {
        // In G18 the first axis is Z and the second X: Z is the radius.
        let got = run("G18\nG91\nG16\nG00 Z2 X90", 3);
        assert_eq!(got.last().unwrap(), "G00 X2.0000 Z0.0000");
    }

    #[test]
    fn polar_errors() {
        assert_eq!(run("G16", 3), ["1:1: error: G16 (polar coordinates) needs incremental mode"]);
        let got = run("G91\nG16\nG02 X1 Y1 R1 F1", 3);
        assert_eq!(got[1], "3:1: error: arcs (G02/G03) are not allowed in polar coordinates (G16)");
        assert_eq!(run("G91\nG16\nG90", 3)[1], "3:1: error: G90 while polar coordinates (G16) are on");
        assert_eq!(run("G91\nG16\nX1", 3)[1], "3:1: error: a polar move needs both a radius (X) and an angle (Y)");
    }
}
