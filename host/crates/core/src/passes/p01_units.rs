//! Pass 01: units. G20/G21 say what unit the program is written in; this pass
//! converts every length (X Y Z, I J K, R, F, G52/G92 values, G43/G44 Z) to
//! the machine's unit and drops the G20/G21 statements; splines' points and
//! offsets are lengths too. Until the program says
//! otherwise it is taken to be in the machine's unit. In polar mode (G16) the
//! word for the plane's second axis is an angle, and stays as it is. The units
//! may not change while cutter radius compensation (G41/G42) is on: the radius
//! is in force.

use super::{Out, Pass};
use crate::diag::Diagnostic;
use crate::state::Probe;
use crate::statement::{self, Kind, Plane, Statement, Value};

pub struct Units {
    machine: statement::Units,
    program: statement::Units,
    polar: bool,
    plane: Plane,
    /// G41/G42 in force (until G40).
    comp: bool,
    probe: Probe,
}

impl Units {
    pub fn new(machine: statement::Units, probe: Probe) -> Units {
        Units { machine, program: machine, polar: false, plane: Plane::XY, comp: false, probe }
    }
}

impl Pass for Units {
    fn statement(&mut self, mut statement: Statement, out: &mut Out) {
        let factor = self.program.factor_to(self.machine);
        let scale = |v: &mut Option<Value>| {
            if let Some(v) = v {
                v.value *= factor;
            }
        };
        match &mut statement.kind {
            Kind::CutterComp { diameter, .. } => {
                scale(diameter);
                self.comp = true;
            }
            Kind::CutterCompCancel => self.comp = false,
            Kind::Units(units) if self.comp && *units != self.program => {
                let message =
                    format!("cannot change units ({}) with cutter radius compensation (G41/G42) on", units.code());
                out.error(&statement, Diagnostic::error(statement.span, message).with_help("cancel it with G40 first"));
                return;
            }
            Kind::Units(units) => {
                self.program = *units;
                self.probe.borrow_mut().program_units = *units;
                return;
            }
            Kind::Polar(on) => {
                self.polar = *on;
                self.probe.borrow_mut().polar = *on;
            }
            Kind::Plane(plane) => self.plane = *plane,
            Kind::Motion(m) if factor != 1.0 => {
                let angle = if self.polar { Some(self.plane.axes().1) } else { None };
                m.target = m.target.map(|axis, v| if Some(axis) == angle { v } else { v * factor });
                m.centre = m.centre.map(|_, v| v * factor);
                scale(&mut m.radius);
                scale(&mut m.feed);
            }
            Kind::Offset { axes, .. } | Kind::SetWorkOffset { axes, .. } | Kind::Home { via: axes, .. } => {
                **axes = axes.map(|_, v| v * factor)
            }
            Kind::SetToolTable { offsets, radius, .. } => {
                **offsets = offsets.map(|_, v| v * factor);
                scale(radius);
            }
            Kind::SetToolTableFrom(from) => {
                from.target = from.target.map(|_, v| v * factor);
                scale(&mut from.radius);
            }
            Kind::MachineMove(m) => {
                m.target = m.target.map(|_, v| v * factor);
                scale(&mut m.feed);
            }
            // A NURBS weight is not a length; G5's P and Q (in `second`) are.
            Kind::Spline(spline) => {
                for axes in [&mut spline.target, &mut spline.first, &mut spline.second] {
                    *axes = axes.map(|_, v| v * factor);
                }
                scale(&mut spline.feed);
            }
            Kind::Cycle(cycle) => {
                cycle.target = cycle.target.map(|_, v| v * factor);
                scale(&mut cycle.r);
                scale(&mut cycle.q);
                scale(&mut cycle.feed);
            }
            _ => {}
        }
        out.push(statement);
    }
}

#[cfg(test)]
mod tests {
    use crate::config::Config;
    use crate::passes::testing::{run, run_with};
    use crate::statement;

    #[test]
    fn millimetres_become_inches_on_an_inch_machine() {
        // G43's Z is a move in the mode in force, converted like any other.
        let got = run("G21\nG01 X25.4 Y-12.7 F254\nG02 X50.8 R12.7\nG52 X2.54\nG00\nG43 Z5.08 H1\nG20\nG01 X1", 1);
        assert_eq!(
            got,
            [
                "G01 X1.0000 Y-0.5000 F10.0000",
                "G02 X2.0000 R0.5000",
                "G52 X0.1000",
                "G00",
                "G43 H1",
                "G00 Z0.2000",
                "G01 X1.0000",
            ]
        );
    }

    #[test]
    fn polar_angles_are_not_lengths() {
        // 25.4 mm at 90 degrees: one inch along Y.
        assert_eq!(run("G21\nG91\nG16\nG01 X25.4 Y90 F25.4", 3), ["G91", "G01 X0.0000 Y1.0000 F1.0000"]);
        // In G18 the angle is the X word.
        assert_eq!(run("G21\nG18\nG91\nG16\nG00 Z25.4 X90", 3).last().unwrap(), "G00 X1.0000 Z0.0000");
    }

    #[test]
    fn inches_become_millimetres_on_a_mm_machine() {
        let config = Config { units: statement::Units::Mm, ..Config::default() };
        let got = run_with("G20\nG03 X1 Y1 I1 J0.5 F10", &config, 1);
        assert_eq!(got, ["G03 X25.400 Y25.400 I25.400 J12.700 F254.000"]);
        assert_eq!(run_with("G01 X1 F10", &config, 1), ["G01 X1.000 F10.000"]);
    }

    #[test]
    fn lenient_g70_and_g71_are_inches_and_millimetres_alone() {
        // Siemens, Fagor and Heidenhain's ISO programs: G70 inches, G71 millimetres. With a lathe
        // cycle's words they are one, refused; strict reads neither.
        let lenient =
            Config { units: statement::Units::Mm, dialect: statement::Dialect::Lenient.into(), ..Config::default() };
        let got = run_with("G70\nG01 X1 Y-0.5 F10\nG71\nG01 X1", &lenient, 1);
        assert_eq!(got, ["G01 X25.400 Y-12.700 F254.000", "G01 X1.000"]);
        assert_eq!(
            run_with("G71 P10 Q20 D1", &lenient, 1),
            ["1:1: error: G71 with words is a lathe's finishing or roughing cycle, which a mill does not run"]
        );
        assert_eq!(run("G71", 1), ["1:1: error: G71 is not a code ger knows"]);
    }

    #[test]
    fn a_tool_table_entry_is_written_in_the_machines_unit() {
        let lenient =
            Config { units: statement::Units::Mm, dialect: statement::Dialect::Lenient.into(), ..Config::default() };
        assert_eq!(run_with("G20\nG10 L1 P2 Z-0.5 R0.125", &lenient, 1), ["G10 L1 P2 Z-12.700 R3.175"]);
    }

    #[test]
    fn units_cannot_change_with_cutter_comp_on() {
        let got = run("G41\nG20\nG21\nG01 X1 F10\nG40\nG21\nG01 X25.4", 1);
        assert_eq!(
            got,
            [
                "G41",
                "3:1: error: cannot change units (G21) with cutter radius compensation (G41/G42) on",
                "G01 X1.0000 F10.0000",
                "G40",
                "G01 X1.0000"
            ]
        );
    }
}
