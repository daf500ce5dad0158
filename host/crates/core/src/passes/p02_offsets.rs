//! Pass 02: work offsets. G52, G54..G59 and G92 move program zero (the PRZ);
//! this pass adds the current PRZ to every absolute coordinate, so the output
//! is relative to machine zero, and drops the offset statements. In the
//! lenient dialect it also takes G10 L2/L20 (which rewrite the work-offsets
//! table), and puts canned cycles, splines and G28/G30's intermediate points
//! in machine coordinates; G53 moves are in them already.
//!
//! None of these codes may be used in polar (G16), incremental (G91) or
//! cutter comp (G41/G42) mode. G92 and G10 L20 need the tool's position: they
//! read it from the probe, which pass 04 keeps (passes 01-04 have no
//! look-ahead, so it is the position before this statement).

use super::{Out, Pass};
use crate::config::{WorkOffsets, WORK_OFFSETS};
use crate::diag::Diagnostic;
use crate::state::Probe;
use crate::statement::{Axes, Dialect, Distance, Kind, Offset, Plane, Statement};

pub struct Offsets {
    /// G54..G59.3 and the extended offsets, in machine coordinates.
    table: Vec<[f64; 3]>,
    /// Machine coordinates of program zero.
    prz: [f64; 3],
    /// The table entry program zero comes from, if it does (not after G52/G92).
    entry_in_force: Option<u8>,
    /// The coordinate system last selected (G54 until another): G92.1-G92.3
    /// put program zero back on it.
    system: u8,
    /// The G52/G92 offset from that system, as LinuxCNC keeps it for G92.3.
    kept_g92: [f64; 3],
    /// G90.1: I, J and K are absolute, so they move with program zero.
    absolute_centres: bool,
    /// The lenient dialect changes program zero in G91, as LinuxCNC does.
    dialect: Dialect,
    /// Canned cycles drill along the plane's normal.
    plane: Plane,
    distance: Distance,
    polar: bool,
    comp: bool,
    probe: Probe,
}

impl Offsets {
    pub fn new(table: &WorkOffsets, dialect: Dialect, probe: Probe) -> Offsets {
        Offsets {
            table: (1..=WORK_OFFSETS).map(|entry| table.entry(entry as u8)).collect(),
            prz: [0.0; 3],
            entry_in_force: None,
            system: 1,
            kept_g92: [0.0; 3],
            absolute_centres: false,
            dialect,
            plane: Plane::XY,
            distance: Distance::Absolute,
            polar: false,
            comp: false,
            probe,
        }
    }

    fn mode_forbidding_offsets(&self) -> Option<(&'static str, &'static str)> {
        if self.polar {
            Some(("polar coordinates (G16) are on", "turn them off with G15 first"))
        } else if self.distance == Distance::Incremental && self.dialect == Dialect::Strict {
            Some(("incremental mode (G91) is on", "switch to absolute mode with G90 first"))
        } else if self.comp {
            Some(("cutter radius compensation (G41/G42) is on", "cancel it with G40 first"))
        } else {
            None
        }
    }

    /// Moves absolute coordinates from program to machine coordinates.
    fn to_machine(&self, axes: Axes) -> Axes {
        match self.distance {
            Distance::Absolute => axes.map(|axis, v| v + self.prz[axis]),
            Distance::Incremental => axes,
        }
    }

    fn set_prz(&mut self, prz: [f64; 3], entry: Option<u8>) {
        self.prz = prz;
        self.entry_in_force = entry;
        self.probe.borrow_mut().prz = prz;
    }
}

impl Pass for Offsets {
    fn statement(&mut self, mut statement: Statement, out: &mut Out) {
        let comp_refuses = |code: &str| {
            Diagnostic::error(statement.span, format!("cannot use {code} with cutter radius compensation (G41/G42) on"))
                .with_help("cancel it with G40 first")
        };
        match &mut statement.kind {
            Kind::Distance(distance) => self.distance = *distance,
            // Pass 03 refuses G16 outside G91; a refused G16 leaves polar off.
            Kind::Polar(on) => self.polar = *on && self.distance == Distance::Incremental,
            Kind::CutterComp { .. } => self.comp = true,
            Kind::CutterCompCancel => self.comp = false,
            Kind::Offset { code, axes } => {
                if let Some((why, help)) = self.mode_forbidding_offsets() {
                    let message = format!("cannot change program zero while {why}");
                    out.error(&statement, Diagnostic::error(statement.span, message).with_help(help));
                    return;
                }
                let given = |axis: usize| axes.get(axis).map_or(0.0, |v| v.value);
                let position = self.probe.borrow().position;
                let system = self.table[usize::from(self.system - 1)];
                match code {
                    Offset::G52 | Offset::G92 => {
                        let prz = match code {
                            Offset::G52 => [given(0), given(1), given(2)],
                            _ => std::array::from_fn(|axis| position[axis] - given(axis)),
                        };
                        self.kept_g92 = std::array::from_fn(|axis| prz[axis] - system[axis]);
                        self.set_prz(prz, None);
                    }
                    Offset::WorkOffset(entry) => {
                        self.system = *entry;
                        self.set_prz(self.table[usize::from(*entry - 1)], Some(*entry));
                    }
                    Offset::G92Cancel { keep } => {
                        if !*keep {
                            self.kept_g92 = [0.0; 3];
                        }
                        self.set_prz(system, Some(self.system));
                    }
                    Offset::G92Restore => {
                        let prz = std::array::from_fn(|axis| system[axis] + self.kept_g92[axis]);
                        self.set_prz(prz, None);
                    }
                }
                return;
            }
            Kind::SetWorkOffset { entry, axes, relative } => {
                if self.comp {
                    return out.error(&statement, comp_refuses("G10"));
                }
                let entry = if *entry == 0 { self.system } else { *entry };
                let position = self.probe.borrow().position;
                let row = &mut self.table[usize::from(entry - 1)];
                for (axis, value) in row.iter_mut().enumerate() {
                    if let Some(v) = axes.get(axis) {
                        *value = if *relative { position[axis] - v.value } else { v.value };
                    }
                }
                if self.entry_in_force == Some(entry) {
                    self.set_prz(self.table[usize::from(entry - 1)], Some(entry));
                }
                return;
            }
            Kind::ArcCentres(distance) => self.absolute_centres = *distance == Distance::Absolute,
            Kind::Motion(motion) => {
                motion.target = self.to_machine(motion.target);
                if self.absolute_centres {
                    motion.centre = motion.centre.map(|axis, v| v + self.prz[axis]);
                }
            }
            Kind::Plane(plane) => self.plane = *plane,
            Kind::Cycle(cycle) => {
                cycle.target = self.to_machine(cycle.target);
                // R is a level along the hole, like its bottom: Z in G17, Y in G18, X in G19.
                if let (Distance::Absolute, Some(r)) = (self.distance, &mut cycle.r) {
                    r.value += self.prz[self.plane.axes().2];
                }
            }
            Kind::Home { reference, via } => {
                if self.comp {
                    let code = if *reference == crate::statement::Reference::Home { "G28" } else { "G30" };
                    return out.error(&statement, comp_refuses(code));
                }
                *via = self.to_machine(*via);
            }
            Kind::MachineMove(_) if self.comp => return out.error(&statement, comp_refuses("G53")),
            // As in LinuxCNC ("Cannot convert spline with cutter radius compensation").
            Kind::Spline(spline) if self.comp => {
                let code = spline.code.map_or("G5.2", |c| c.code());
                return out.error(&statement, comp_refuses(code));
            }
            Kind::NurbsEnd if self.comp => return out.error(&statement, comp_refuses("G5.3")),
            Kind::Spline(spline) => spline.target = self.to_machine(spline.target),
            _ => {}
        }
        out.push(statement);
    }
}

#[cfg(test)]
mod tests {
    use crate::config::{Config, WorkOffsets};
    use crate::passes::testing::{run, run_with};

    #[test]
    fn g52_moves_program_zero_and_omitted_axes_are_zero() {
        let got = run("G52 X2 Y-4 Z1\nG00 X1 Y1 Z0\nG52 X1\nG00 X0 Y0 Z0\nG52\nX0", 2);
        assert_eq!(got, ["G00 X3.0000 Y-3.0000 Z1.0000", "G00 X1.0000 Y0.0000 Z0.0000", "G00 X0.0000"]);
    }

    #[test]
    fn g54_to_g59_use_the_table() {
        let offsets = WorkOffsets { g54: Some([1.0, 2.0, 3.0]), g59: Some([-1.0, 0.0, 0.5]), ..Default::default() };
        let config = Config { offsets, ..Config::default() };
        let got = run_with("G54\nG00 X1 Y1 Z1\nG59\nX1\nG55\nX1", &config, 2);
        assert_eq!(got, ["G00 X2.0000 Y3.0000 Z4.0000", "G00 X0.0000", "G00 X1.0000"]);
    }

    #[test]
    fn g92_makes_the_current_position_read_as_given() {
        // The tool is at (2, 3, 0); G92 X0 Y0 makes that program zero.
        let got = run("G00 X2 Y3\nG92 X0 Y0\nG00 X1 Y1\nG91\nX1\nG90\nG92 X10\nX10", 2);
        assert_eq!(got, ["G00 X2.0000 Y3.0000", "G00 X3.0000 Y4.0000", "G91", "G00 X1.0000", "G90", "G00 X4.0000"]);
    }

    #[test]
    fn g92_follows_polar_moves() {
        // Polar move of 2 at 90 degrees from (0,0): the tool is at (0, 2).
        let got = run("G91\nG16\nG00 X2 Y90\nG15\nG90\nG92 X0 Y0\nG00 X1 Y0", 2);
        assert_eq!(got.last().unwrap(), "G00 X1.0000 Y2.0000");
    }

    #[test]
    fn offsets_are_refused_in_incremental_polar_and_comp_modes() {
        assert_eq!(
            run("G91\nG52 X1", 2)[1],
            "2:1: error: cannot change program zero while incremental mode (G91) is on"
        );
        assert_eq!(
            run("G91\nG16\nG54", 2)[2],
            "3:1: error: cannot change program zero while polar coordinates (G16) are on"
        );
        // A G16 refused for want of G91 does not count as polar mode.
        assert_eq!(run("G16\nG54\nX1", 2), ["G16", "G00 X1.0000"]);
    }
}
