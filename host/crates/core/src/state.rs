//! The machine state where the program has got to, as the passes see it.
//!
//! Passes 01-04 each write the part of it they own while statements go
//! through them; pass 00 reads it when it meets a wizard call, to tell the
//! wizard where it is called from. That works because the pipeline pulls one
//! statement at a time and passes 01-04 have no look-ahead: by the time pass
//! 00 reads the next statement, everything before it has gone through them.

use std::cell::RefCell;
use std::rc::Rc;

use crate::config::{Config, ToolKind};
use crate::statement::{Distance, Plane, Units};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spindle {
    Off,
    Clockwise(Option<f64>),
    CounterClockwise(Option<f64>),
}

/// Everything in machine units and machine coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// Written by pass 01, as is `polar`.
    pub program_units: Units,
    /// G16 in force: the plane's second axis word is an angle.
    pub polar: bool,
    /// Program zero in machine coordinates; written by pass 02.
    pub prz: [f64; 3],
    /// How far the coordinate system is turned about program zero (G10 L2
    /// R), degrees counter-clockwise in XY; written by pass 02.
    pub rotation: f64,
    /// Written by pass 04, as are the rest.
    pub position: [f64; 3],
    pub distance: Distance,
    pub plane: Plane,
    pub feed: Option<f64>,
    pub spindle: Spindle,
    /// The spindle speed last given, whether it turns or not.
    pub speed: Option<f64>,
    /// The tool M06 last loaded (tool 1 until then).
    pub tool: u32,
    /// The work offset last selected: 1 for G54 to 9 for G59.3 (and on for
    /// the extended ones); written by pass 02.
    pub system: u8,
    /// G54 to G59.3's origins (machine coordinates) and rotations; written
    /// by pass 02, as are the two after.
    pub work_offsets: [[f64; 3]; COORDINATE_SYSTEMS],
    pub rotations: [f64; COORDINATE_SYSTEMS],
    /// The G52/G92 offset, along the coordinate system's axes, and whether
    /// it is in force (LinuxCNC keeps it after G92.2, for G92.3).
    pub g92: [f64; 3],
    pub g92_in_force: bool,
    /// G28's and G30's points, in machine coordinates; written by pass 04.
    pub references: [[f64; 3]; 2],
}

/// The coordinate systems whose parameters LinuxCNC keeps: G54 to G59.3.
pub const COORDINATE_SYSTEMS: usize = 9;

pub type Probe = Rc<RefCell<Snapshot>>;

pub fn probe(machine_units: Units) -> Probe {
    Rc::new(RefCell::new(Snapshot {
        program_units: machine_units,
        polar: false,
        prz: [0.0; 3],
        rotation: 0.0,
        position: [0.0; 3],
        distance: Distance::Absolute,
        plane: Plane::XY,
        feed: None,
        spindle: Spindle::Off,
        speed: None,
        tool: 1,
        system: 1,
        work_offsets: [[0.0; 3]; COORDINATE_SYSTEMS],
        rotations: [0.0; COORDINATE_SYSTEMS],
        g92: [0.0; 3],
        g92_in_force: false,
        references: [[0.0; 3]; 2],
    }))
}

/// A tool as a wizard sees it: its diameter in the program's units.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolInfo {
    pub number: u32,
    pub kind: ToolKind,
    pub diameter: f64,
}

/// What a wizard is told about the place it is called from, in the units and
/// coordinates the program uses there.
#[derive(Clone, Debug, PartialEq)]
pub struct CallState {
    pub units: Units,
    /// The tool's position in program coordinates (after G52/G54..G59/G92).
    pub position: [f64; 3],
    pub distance: Distance,
    pub plane: Plane,
    pub feed: Option<f64>,
    pub spindle: Spindle,
    /// `None` when the loaded tool is not in the tool table.
    pub tool: Option<ToolInfo>,
    pub tool_number: u32,
    /// The line of the call.
    pub line: u32,
    /// The stock block's box in program coordinates and units at the call,
    /// when `[stock]` gives its size.
    pub stock: Option<[[f64; 3]; 2]>,
}

/// Where the program has got to, in its own units, for the parameters that
/// read it (LinuxCNC's #5420-#5422, Fanuc's #5001-#5003 and #4001-#4120).
#[derive(Clone, Debug, PartialEq)]
pub struct Place {
    /// The tool in program coordinates (after G52/G54..G59/G92).
    pub position: [f64; 3],
    /// The tool in machine coordinates.
    pub machine: [f64; 3],
    /// 1 for G54 to 9 for G59.3, and on for the extended ones.
    pub system: u8,
    pub units: Units,
    pub distance: Distance,
    pub plane: Plane,
    pub feed: Option<f64>,
    pub spindle: Spindle,
    /// The spindle speed last given, whether it turns or not.
    pub speed: Option<f64>,
    pub tool: u32,
    /// The coordinate systems' origins in machine coordinates, and their
    /// rotations in degrees. These three are in the machine's units, not
    /// the program's: LinuxCNC keeps its parameters so (a G20 program on a
    /// mm machine reads G54's X in mm).
    pub work_offsets: [[f64; 3]; COORDINATE_SYSTEMS],
    pub rotations: [f64; COORDINATE_SYSTEMS],
    pub g92: [f64; 3],
    pub g92_in_force: bool,
    /// G28's and G30's points, in machine coordinates.
    pub references: [[f64; 3]; 2],
}

impl Snapshot {
    /// The place as the program's parameters read it.
    pub fn place(&self, machine_units: Units) -> Place {
        let to_program = machine_units.factor_to(self.program_units);
        Place {
            position: self.program_position(machine_units),
            machine: self.position.map(|v| v * to_program),
            system: self.system,
            units: self.program_units,
            distance: self.distance,
            plane: self.plane,
            feed: self.feed.map(|f| f * to_program),
            spindle: self.spindle,
            speed: self.speed,
            tool: self.tool,
            work_offsets: self.work_offsets,
            rotations: self.rotations,
            g92: self.g92,
            g92_in_force: self.g92_in_force,
            references: self.references,
        }
    }

    /// The tool's position in program coordinates (after G52/G54..G59/G92)
    /// and units: what LinuxCNC's #5420-#5422 read.
    pub fn program_position(&self, machine_units: Units) -> [f64; 3] {
        self.in_program(self.position, machine_units)
    }

    /// A point in machine coordinates as the program reads it.
    fn in_program(&self, machine: [f64; 3], machine_units: Units) -> [f64; 3] {
        let to_program = machine_units.factor_to(self.program_units);
        let from_zero: [f64; 3] = std::array::from_fn(|axis| machine[axis] - self.prz[axis]);
        // Along the coordinate system's own axes, turned back by its rotation.
        let [x, y] = crate::geom::turn([from_zero[0], from_zero[1]], -self.rotation);
        let program = [x, y, from_zero[2]];
        program.map(|v| v * to_program)
    }

    pub fn call_state(&self, config: &Config, line: u32) -> CallState {
        let to_program = config.units.factor_to(self.program_units);
        let tool = config.tool(self.tool).map(|t| ToolInfo {
            number: t.number,
            kind: t.kind,
            diameter: t.diameter * to_program,
        });
        CallState {
            units: self.program_units,
            position: self.program_position(config.units),
            distance: self.distance,
            plane: self.plane,
            feed: self.feed.map(|f| f * to_program),
            spindle: self.spindle,
            tool,
            tool_number: self.tool,
            line,
            stock: config.stock.block().map(|block| self.box_in_program(block, config.units)),
        }
    }

    /// The box along the program's axes around `block` (machine
    /// coordinates and units): its corners as the program reads them.
    fn box_in_program(&self, block: [[f64; 3]; 2], machine_units: Units) -> [[f64; 3]; 2] {
        let mut found = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
        for corner in 0..8 {
            let machine = std::array::from_fn(|axis| block[(corner >> axis) & 1][axis]);
            let program = self.in_program(machine, machine_units);
            for axis in 0..3 {
                found[0][axis] = found[0][axis].min(program[axis]);
                found[1][axis] = found[1][axis].max(program[axis]);
            }
        }
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wizard_is_told_its_position_along_the_turned_axes() {
        let probe = probe(Units::Inch);
        {
            let mut snapshot = probe.borrow_mut();
            snapshot.prz = [10.0, 0.0, 0.0];
            snapshot.rotation = 90.0;
            snapshot.position = [10.0, 1.0, 2.0];
        }
        let state = probe.borrow().call_state(&Config::default(), 1);
        // One along machine Y from program zero is one along X turned 90°.
        let [x, y, z] = state.position;
        assert!((x - 1.0).abs() < 1e-12 && y.abs() < 1e-12 && z == 2.0, "{:?}", state.position);
    }

    #[test]
    fn a_wizard_is_told_the_stock_in_its_own_coordinates_and_units() {
        let config = Config::from_toml("units = \"mm\"\n[stock]\nsize = [100, 50, 20]\n").unwrap();
        let probe = probe(Units::Mm);
        {
            let mut snapshot = probe.borrow_mut();
            snapshot.program_units = Units::Inch;
            snapshot.prz = [10.0, 5.0, 0.0];
        }
        // Program zero on the block's top lower-left corner, then G54 10 mm
        // along X and 5 along Y: the block from -10, -5, -20 to 90, 45, 0 mm.
        let [min, max] = probe.borrow().call_state(&config, 1).stock.unwrap();
        let expected = [[-10.0, -5.0, -20.0], [90.0, 45.0, 0.0]].map(|corner| corner.map(|mm| mm / 25.4));
        for (got, want) in [min, max].iter().flatten().zip(expected.iter().flatten()) {
            assert!((got - want).abs() < 1e-12, "{min:?} {max:?}");
        }
        assert_eq!(probe.borrow().call_state(&Config::default(), 1).stock, None);
    }
}
