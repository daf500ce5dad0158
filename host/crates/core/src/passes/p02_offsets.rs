//! Pass 02: work offsets. G52, G54..G59 and G92 move program zero (the PRZ);
//! this pass adds the current PRZ to every absolute coordinate, so the output
//! is relative to machine zero, and drops the offset statements. In the
//! lenient dialect it also takes G10 L2/L20 (which rewrite the work-offsets
//! table), and puts canned cycles, splines and G28/G30's intermediate points
//! in machine coordinates; G53 moves are in them already.
//!
//! A coordinate system may be turned about its origin (G10 L2 R, LinuxCNC's
//! rotation): program X and Y are then turned by its angle before program
//! zero is added, so every move's XY (its target, an arc's centre, a cycle's
//! hole, a spline's control points) comes out turned. Plain G-code has no
//! rotation, but a turned line is a line and a turned arc an arc, so the
//! output says the same path. Machine coordinates (G53, G28/G30's reference
//! point) are not turned, as in LinuxCNC.
//!
//! None of these codes may be used in polar (G16), incremental (G91) or
//! cutter comp (G41/G42) mode. G92 and G10 L20 need the tool's position: they
//! read it from the probe, which pass 04 keeps (passes 01-04 have no
//! look-ahead, so it is the position before this statement).

use super::{Out, Pass};
use crate::config::{WorkOffsets, WORK_OFFSETS};
use crate::diag::Diagnostic;
use crate::geom::turn;
use crate::state::{Probe, COORDINATE_SYSTEMS};
use crate::statement::{Axes, Dialect, Distance, Frame, Kind, MotionMode, Offset, Plane, Reference, Statement, Value};

pub struct Offsets {
    /// G54..G59.3 and the extended offsets, in machine coordinates.
    table: Vec<[f64; 3]>,
    /// Each entry's rotation about its origin, degrees counter-clockwise in XY.
    rotations: Vec<f64>,
    /// Machine coordinates of program zero.
    prz: [f64; 3],
    /// The rotation of the coordinate system in force (that of `system`).
    rotation: f64,
    /// The table entry program zero comes from, if it does (not after G52/G92).
    entry_in_force: Option<u8>,
    /// The coordinate system last selected (G54 until another): G92.1-G92.3
    /// put program zero back on it.
    system: u8,
    /// The G52/G92 offset from that system, as LinuxCNC keeps it for G92.3,
    /// along the system's own (turned) axes.
    kept_g92: [f64; 3],
    /// Whether that offset is in force: from G52/G92 (or G92.3) to
    /// G92.1/G92.2, LinuxCNC's #5210.
    g92_in_force: bool,
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
        let offsets = Offsets {
            table: (1..=WORK_OFFSETS).map(|entry| table.entry(entry as u8)).collect(),
            rotations: vec![0.0; WORK_OFFSETS],
            prz: [0.0; 3],
            rotation: 0.0,
            entry_in_force: None,
            system: 1,
            kept_g92: [0.0; 3],
            g92_in_force: false,
            absolute_centres: false,
            dialect,
            plane: Plane::XY,
            distance: Distance::Absolute,
            polar: false,
            comp: false,
            probe,
        };
        offsets.publish();
        offsets
    }

    /// Tells the probe the table and the G52/G92 offset, which LinuxCNC's
    /// parameters #5210-#5213 and #5221-#5390 read.
    fn publish(&self) {
        let mut probe = self.probe.borrow_mut();
        for (entry, (origin, rotation)) in self.table.iter().zip(&self.rotations).take(COORDINATE_SYSTEMS).enumerate() {
            probe.work_offsets[entry] = *origin;
            probe.rotations[entry] = *rotation;
        }
        probe.g92 = self.kept_g92;
        probe.g92_in_force = self.g92_in_force;
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

    fn rotated(&self) -> bool {
        self.rotation.rem_euclid(360.0) != 0.0
    }

    /// Moves a target from program to machine coordinates: absolute ones are
    /// turned about program zero and moved by it, steps (G91) only turned.
    /// In a turned system a target with X or Y gets both, since each of the
    /// machine's moves with either; the one not written is where the tool is.
    fn to_machine(&self, axes: Axes) -> Axes {
        let absolute = self.distance == Distance::Absolute;
        let mut machine = match absolute {
            true => axes.map(|axis, v| v + self.prz[axis]),
            false => axes,
        };
        let Some(span) = axes.x.or(axes.y).map(|v| v.span).filter(|_| self.rotated()) else {
            return machine;
        };
        let at = self.program_position();
        let given = |axis: usize, otherwise: f64| axes.get(axis).map_or(otherwise, |v| v.value);
        let (x, y) = match absolute {
            true => (given(0, at[0]), given(1, at[1])),
            false => (given(0, 0.0), given(1, 0.0)),
        };
        let [x, y] = turn([x, y], self.rotation);
        let origin = if absolute { [self.prz[0], self.prz[1]] } else { [0.0; 2] };
        machine.x = Some(Value { value: x + origin[0], span: axes.x.map_or(span, |v| v.span) });
        machine.y = Some(Value { value: y + origin[1], span: axes.y.map_or(span, |v| v.span) });
        machine
    }

    /// I and J from an arc's start (or, in G90.1, the centre's program
    /// coordinates, which need both), turned with the system.
    fn centre_to_machine(&self, centre: Axes) -> Axes {
        let mut machine = match self.absolute_centres {
            true => centre.map(|axis, v| v + self.prz[axis]),
            false => centre,
        };
        let Some(span) = centre.x.or(centre.y).map(|v| v.span).filter(|_| self.rotated()) else {
            return machine;
        };
        if self.absolute_centres && (centre.x.is_none() || centre.y.is_none()) {
            // Pass 04 says that G90.1 needs both.
            return centre;
        }
        let given = |axis: usize| centre.get(axis).map_or(0.0, |v| v.value);
        let [i, j] = turn([given(0), given(1)], self.rotation);
        let origin = if self.absolute_centres { [self.prz[0], self.prz[1]] } else { [0.0; 2] };
        machine.x = Some(Value { value: i + origin[0], span: centre.x.map_or(span, |v| v.span) });
        machine.y = Some(Value { value: j + origin[1], span: centre.y.map_or(span, |v| v.span) });
        machine
    }

    /// Where the tool is, in program coordinates.
    fn program_position(&self) -> [f64; 3] {
        let position = self.probe.borrow().position;
        let [x, y] = turn([position[0] - self.prz[0], position[1] - self.prz[1]], -self.rotation);
        [x, y, position[2] - self.prz[2]]
    }

    fn set_prz(&mut self, prz: [f64; 3], entry: Option<u8>) {
        self.prz = prz;
        self.entry_in_force = entry;
        {
            let mut probe = self.probe.borrow_mut();
            probe.prz = prz;
            probe.rotation = self.rotation;
        }
        self.publish();
    }

    /// Machine coordinates of program zero `offset` along the axes of the system in force.
    fn in_system(&self, offset: [f64; 3]) -> [f64; 3] {
        let system = self.table[usize::from(self.system - 1)];
        let [x, y] = turn([offset[0], offset[1]], self.rotation);
        [system[0] + x, system[1] + y, system[2] + offset[2]]
    }

    /// What makes a turned coordinate system's output uncertain, if anything:
    /// a plane other than XY turns out of every plane G-code can name.
    fn refused_when_rotated(&self, statement: &Statement) -> Option<Diagnostic> {
        if !self.rotated() {
            return None;
        }
        let plane_move = match &statement.kind {
            Kind::Motion(motion) => motion.mode.is_some_and(MotionMode::is_arc) && motion.moves(),
            Kind::Cycle(_) => true,
            _ => false,
        };
        let span = statement.span;
        let angle = self.rotation;
        if plane_move && self.plane != Plane::XY {
            let message = format!(
                "cannot use {} in a coordinate system turned by {angle}° (G10 R): turned about Z, its plane is none that G-code names",
                self.plane.code()
            );
            return Some(Diagnostic::error(span, message).with_help("select G17 in a turned coordinate system"));
        }
        if self.polar && matches!(statement.kind, Kind::Motion(_)) {
            let message =
                format!("cannot move in polar coordinates (G16) in a coordinate system turned by {angle}° (G10 R)");
            return Some(Diagnostic::error(span, message).with_help("turn polar coordinates off with G15"));
        }
        if let Kind::Home { reference, via } = &statement.kind {
            if via.x.is_some() || via.y.is_some() {
                let code = if *reference == Reference::Home { "G28" } else { "G30" };
                let message = format!(
                    "cannot name X or Y on {code} in a coordinate system turned by {angle}° (G10 R): LinuxCNC sends them to the reference point's coordinates along the turned axes, which is not the reference point"
                );
                let help = format!("write {code} alone, or with Z only, or move with G53 first");
                return Some(Diagnostic::error(span, message).with_help(help));
            }
        }
        None
    }
}

/// G59.3's place in the table: LinuxCNC's touch-off fixture (G10 L11).
const G59_3: usize = 8;

impl Pass for Offsets {
    fn statement(&mut self, mut statement: Statement, out: &mut Out) {
        let comp_refuses = |code: &str| {
            Diagnostic::error(statement.span, format!("cannot use {code} with cutter radius compensation (G41/G42) on"))
                .with_help("cancel it with G40 first")
        };
        if let Some(diagnostic) = self.refused_when_rotated(&statement) {
            return out.error(&statement, diagnostic);
        }
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
                self.g92_in_force = match code {
                    Offset::G52 | Offset::G92 | Offset::G92Restore => true,
                    Offset::G92Cancel { .. } => false,
                    Offset::WorkOffset(_) => self.g92_in_force,
                };
                let given = [0, 1, 2].map(|axis| axes.get(axis).map_or(0.0, |v| v.value));
                let position = self.probe.borrow().position;
                let system = self.table[usize::from(self.system - 1)];
                match code {
                    Offset::G52 | Offset::G92 if self.dialect == Dialect::Lenient => {
                        // As LinuxCNC and Fanuc: an axis given sets its own offset (G52's from
                        // the coordinate system's origin; G92's so the tool reads as given), the
                        // axes not given keep theirs.
                        let [x, y] = turn([position[0] - system[0], position[1] - system[1]], -self.rotation);
                        let reads = [x, y, position[2] - system[2]];
                        for (axis, read) in reads.into_iter().enumerate() {
                            if let Some(v) = axes.get(axis) {
                                self.kept_g92[axis] = if *code == Offset::G52 { v.value } else { read - v.value };
                            }
                        }
                        self.set_prz(self.in_system(self.kept_g92), None);
                    }
                    Offset::G52 | Offset::G92 => {
                        let prz = match code {
                            Offset::G52 => given,
                            _ => {
                                // The tool reads as given along the turned axes.
                                let [x, y] = turn([given[0], given[1]], self.rotation);
                                [position[0] - x, position[1] - y, position[2] - given[2]]
                            }
                        };
                        let [x, y] = turn([prz[0] - system[0], prz[1] - system[1]], -self.rotation);
                        self.kept_g92 = [x, y, prz[2] - system[2]];
                        self.set_prz(prz, None);
                    }
                    Offset::WorkOffset(entry) => {
                        self.system = *entry;
                        self.probe.borrow_mut().system = *entry;
                        self.rotation = self.rotations[usize::from(*entry - 1)];
                        if self.dialect == Dialect::Lenient && self.entry_in_force.is_none() {
                            // LinuxCNC and Fanuc: a G52/G92 offset in force moves every coordinate system.
                            self.set_prz(self.in_system(self.kept_g92), None);
                        } else {
                            self.set_prz(self.table[usize::from(*entry - 1)], Some(*entry));
                        }
                    }
                    Offset::G92Cancel { keep } => {
                        if !*keep {
                            self.kept_g92 = [0.0; 3];
                        }
                        self.set_prz(system, Some(self.system));
                    }
                    Offset::G92Restore => self.set_prz(self.in_system(self.kept_g92), None),
                }
                return;
            }
            // The system the coordinates are in: the one in force (L10), or
            // G59.3 (L11, whose G92 LinuxCNC leaves out).
            Kind::SetToolTableFrom(from) => {
                from.frame = Some(match from.fixture {
                    true => Frame { origin: self.table[G59_3], rotation: self.rotations[G59_3] },
                    false => Frame { origin: self.prz, rotation: self.rotation },
                });
            }
            Kind::SetWorkOffset { entry, axes, relative, rotation } => {
                if self.comp {
                    return out.error(&statement, comp_refuses("G10"));
                }
                let entry = if *entry == 0 { self.system } else { *entry };
                let index = usize::from(entry - 1);
                let position = self.probe.borrow().position;
                if *relative {
                    // Where the tool is along the entry's own axes, with the
                    // coordinates given in place of its own.
                    let (origin, angle) = (self.table[index], self.rotations[index]);
                    let [x, y] = turn([position[0] - origin[0], position[1] - origin[1]], -angle);
                    let reads = [x, y, position[2] - origin[2]];
                    let reads: [f64; 3] = std::array::from_fn(|axis| axes.get(axis).map_or(reads[axis], |v| v.value));
                    let [x, y] = turn([reads[0], reads[1]], angle);
                    self.table[index] = [position[0] - x, position[1] - y, position[2] - reads[2]];
                } else {
                    for (axis, value) in self.table[index].iter_mut().enumerate() {
                        if let Some(v) = axes.get(axis) {
                            *value = v.value;
                        }
                    }
                }
                if let Some(r) = rotation {
                    self.rotations[index] = r.value;
                }
                if entry == self.system {
                    self.rotation = self.rotations[index];
                    match self.entry_in_force {
                        Some(e) if e == entry => self.set_prz(self.table[index], Some(entry)),
                        None if self.dialect == Dialect::Lenient => self.set_prz(self.in_system(self.kept_g92), None),
                        _ => self.set_prz(self.prz, self.entry_in_force),
                    }
                }
                self.publish();
                return;
            }
            Kind::ArcCentres(distance) => self.absolute_centres = *distance == Distance::Absolute,
            Kind::Motion(motion) => {
                motion.target = self.to_machine(motion.target);
                motion.centre = self.centre_to_machine(motion.centre);
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
                    let code = if *reference == Reference::Home { "G28" } else { "G30" };
                    return out.error(&statement, comp_refuses(code));
                }
                **via = self.to_machine(**via);
            }
            Kind::MachineMove(_) if self.comp => return out.error(&statement, comp_refuses("G53")),
            // As in LinuxCNC ("Cannot convert spline with cutter radius compensation").
            Kind::Spline(spline) if self.comp => {
                let code = spline.code.map_or("G5.2", |c| c.code());
                return out.error(&statement, comp_refuses(code));
            }
            Kind::NurbsEnd if self.comp => return out.error(&statement, comp_refuses("G5.3")),
            Kind::Spline(spline) => {
                spline.target = self.to_machine(spline.target);
                // Control points from the start or the end are steps: turned, not moved.
                let distance = std::mem::replace(&mut self.distance, Distance::Incremental);
                for step in [&mut spline.first, &mut spline.second] {
                    if step.x.is_some() && step.y.is_some() {
                        *step = self.to_machine(*step);
                    }
                }
                self.distance = distance;
            }
            _ => {}
        }
        out.push(statement);
    }
}

#[cfg(test)]
mod tests {
    use crate::config::{Config, WorkOffsets};
    use crate::passes::testing::{run, run_with};
    use crate::statement::Dialect;

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
    fn lenient_g52_and_g92_set_the_axes_they_name() {
        // As rs274 runs it: at (2, 3, 4), G92 X0 Y0 puts program zero at (2, 3, 0); G92 Z10 then
        // moves Z's alone (the tool at program (1, 1, 1), machine (3, 4, 1): zero at Z -9); G52 X5
        // sets X's offset from G54's origin (0) and keeps Y's and Z's. The offset moves G55 (origin
        // (100, 50, -10)) too; after G92.1, G52 X1 is 1 from G55's origin, and stays in G54.
        let offsets = crate::config::WorkOffsets { g55: Some([100.0, 50.0, -10.0]), ..Default::default() };
        let config = Config { offsets, dialect: Dialect::Lenient.into(), ..Config::default() };
        let got = run_with(
            "G00 X2 Y3 Z4\nG92 X0 Y0\nG00 X1 Y1 Z1\nG92 Z10\nG00 X0 Y0 Z0\nG52 X5\nG00 X0 Y0 Z0\nG55\nG00 X0 Y0 Z0\n\
             G92.1\nG52 X1\nG00 X0 Y0 Z0\nG54\nG00 X0 Y0 Z0",
            &config,
            2,
        );
        assert_eq!(
            got,
            [
                "G00 X2.0000 Y3.0000 Z4.0000",
                "G00 X3.0000 Y4.0000 Z1.0000",
                "G00 X2.0000 Y3.0000 Z-9.0000",
                "G00 X5.0000 Y3.0000 Z-9.0000",
                "G00 X105.0000 Y53.0000 Z-19.0000",
                "G00 X101.0000 Y50.0000 Z-10.0000",
                "G00 X1.0000 Y0.0000 Z0.0000"
            ]
        );
    }

    #[test]
    fn g92_follows_polar_moves() {
        // Polar move of 2 at 90 degrees from (0,0): the tool is at (0, 2).
        let got = run("G91\nG16\nG00 X2 Y90\nG15\nG90\nG92 X0 Y0\nG00 X1 Y0", 2);
        assert_eq!(got.last().unwrap(), "G00 X1.0000 Y2.0000");
    }

    fn lenient(text: &str, stage: u8) -> Vec<String> {
        run_with(text, &Config { dialect: Dialect::Lenient.into(), ..Config::default() }, stage)
    }

    #[test]
    fn a_turned_system_turns_targets_about_its_origin() {
        // Turned 90°, (x, y) is (-y, x) from the origin (10, 20). The tool
        // starts at machine zero, program (-20, 10): X1 keeps that Y.
        let got = lenient("G10 L2 P1 X10 Y20 R90\nG54\nG00 X1\nG01 X1 Y2 Z-1 F10\nG91 X3\nG90 Y0", 2);
        assert_eq!(
            got,
            [
                "G00 X0.0000 Y21.0000",
                "G01 X8.0000 Y21.0000 Z-1.0000 F10.0000",
                "G91",
                "G01 X0.0000 Y3.0000",
                "G90",
                "G01 X10.0000 Y24.0000"
            ]
        );
    }

    #[test]
    fn a_turned_arc_is_an_arc_with_its_centre_turned() {
        // From program (1, 0) (machine (0, 1)) clockwise round program zero to (0, -1):
        // in machine coordinates from (0, 1) round (0, 0) to (1, 0).
        let got = lenient("G10 L2 P1 R90\nG54\nG00 X1 Y0\nG02 X0 Y-1 I-1 J0 F10\nG90.1\nG03 X1 Y0 I0 J0", 4);
        assert_eq!(
            got,
            [
                "G00 X0.0000 Y1.0000",
                "G02 X1.0000 Y0.0000 I0.0000 J-1.0000 F10.0000",
                "G03 X0.0000 Y1.0000 I-1.0000 J0.0000"
            ]
        );
    }

    #[test]
    fn machine_coordinates_are_not_turned() {
        let got = lenient("G10 L2 P1 X5 R90\nG54\nG53 G00 X1 Y2\nG28\nG91 G28 Z1", 4);
        assert_eq!(got, ["G00 X1.0000 Y2.0000", "G00 X0.0000 Y0.0000", "G00 Z1.0000", "G00 Z0.0000"]);
    }

    #[test]
    fn g92_and_g10_l20_read_along_the_turned_axes() {
        // At machine (0, 1), program (1, 0): G92 makes it program zero.
        let got = lenient("G10 L2 P1 R90\nG54\nG00 X1\nG92 X0 Y0\nG00 X1\nG92.1\nG00 X1", 4);
        assert_eq!(got, ["G00 X0.0000 Y1.0000", "G00 X0.0000 Y2.0000", "G00 X0.0000 Y1.0000"]);
        // LinuxCNC's own test: turned 45° at machine zero, L20 X-1 puts the
        // origin at (0.7071, 0.7071), where program zero then is.
        let got = lenient("G10 L2 P1 R45\nG54\nG10 L20 P1 X-1\nG00 X0", 4);
        assert_eq!(got, ["G00 X0.7071 Y0.7071"]);
        assert_eq!(lenient("G10 L20 P1 R45", 4)[0], "1:12: error: R is not allowed with G10 L20");
    }

    #[test]
    fn another_system_has_its_own_rotation() {
        // G55 turned 90°: program (1, 0) is machine (0, 1). G54 is not
        // turned until R180 makes program (2, -1) of machine (2, 1), and X2
        // goes to program (2, -1), machine (-2, 1).
        let got = lenient("G10 L2 P2 R90\nG55\nG00 X1 Y0\nG54\nX2\nG10 L2 P0 R180\nX2", 4);
        assert_eq!(got, ["G00 X0.0000 Y1.0000", "G00 X2.0000", "G00 X-2.0000 Y1.0000"]);
    }

    #[test]
    fn what_a_turn_would_take_out_of_plain_g_code_is_refused() {
        let got = lenient("G10 L2 P1 R30\nG54\nG18\nG02 X1 Z1 I1 F10", 4);
        assert!(got[1].starts_with("4:1: error: cannot use G18 in a coordinate system turned by 30°"), "{got:?}");
        let got = lenient("G10 L2 P1 R30\nG54\nG28 X1", 4);
        assert!(got[0].starts_with("3:1: error: cannot name X or Y on G28 in a coordinate system turned"), "{got:?}");
        // A turn of a whole number of turns turns nothing.
        let got = lenient("G10 L2 P1 R360\nG54\nG18\nG02 X1 Z1 I1 F10\nG28 X1", 4);
        assert_eq!(got, ["G18", "G02 X1.0000 Z1.0000 I1.0000 K0.0000 F10.0000", "G00 X0.0000"]);
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
