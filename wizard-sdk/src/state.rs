//! The machine state at a call, as plain Rust types.

use crate::__bindings::ger::wizard::types as wit;
use crate::block::{g, Statement};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    Mm,
    Inch,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distance {
    Absolute,
    Incremental,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    XY,
    ZX,
    YZ,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spindle {
    Off,
    Clockwise(Option<f64>),
    CounterClockwise(Option<f64>),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolKind {
    Endmill,
    Ballmill,
    Drill,
    CenterDrill,
}

/// A tool from the tool table, in the program's units.
#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    pub number: u32,
    pub kind: ToolKind,
    pub diameter: f64,
    pub flute_length: Option<f64>,
    pub tip_angle: Option<f64>,
}

/// Where the program is at the call, in its units and coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    pub units: Units,
    /// X, Y, Z in program coordinates.
    pub position: [f64; 3],
    pub distance: Distance,
    pub plane: Plane,
    pub feed: Option<f64>,
    pub spindle: Spindle,
    /// The loaded tool, `None` if it is not in the tool table.
    pub tool: Option<Tool>,
    pub tool_number: u32,
    /// The line of the call.
    pub line: u32,
}

impl State {
    /// The loaded tool, or an error a wizard can return as it is.
    pub fn require_tool(&self) -> Result<&Tool, String> {
        self.tool
            .as_ref()
            .ok_or_else(|| format!("tool T{} is not in the tool table, so its diameter is unknown", self.tool_number))
    }

    /// The loaded tool, which must cut sideways (not a drill): `job` says
    /// what needs it, e.g. "a pocket needs an end mill".
    pub fn require_cutter(&self, job: &str) -> Result<&Tool, String> {
        let tool = self.require_tool()?;
        if matches!(tool.kind, ToolKind::Drill | ToolKind::CenterDrill) {
            return Err(format!("T{} is a drill; {job}", tool.number));
        }
        Ok(tool)
    }

    /// `moves`, written in absolute coordinates, as a call may return them
    /// whatever its distance mode: between G90 and G91 when the call was
    /// made in G91, so the program goes on as it was.
    pub fn in_absolute(&self, moves: Vec<Statement>) -> Vec<Statement> {
        if self.distance == Distance::Absolute {
            return moves;
        }
        let mut out = Vec::with_capacity(moves.len() + 2);
        out.push(g(90).into());
        out.extend(moves);
        out.push(g(91).into());
        out
    }
}

impl From<wit::Tool> for Tool {
    fn from(t: wit::Tool) -> Tool {
        Tool {
            number: t.number,
            kind: match t.kind {
                wit::ToolKind::Endmill => ToolKind::Endmill,
                wit::ToolKind::Ballmill => ToolKind::Ballmill,
                wit::ToolKind::Drill => ToolKind::Drill,
                wit::ToolKind::CenterDrill => ToolKind::CenterDrill,
            },
            diameter: t.diameter,
            flute_length: t.flute_length,
            tip_angle: t.tip_angle,
        }
    }
}

impl From<wit::Units> for Units {
    fn from(units: wit::Units) -> Units {
        match units {
            wit::Units::Mm => Units::Mm,
            wit::Units::Inch => Units::Inch,
        }
    }
}

/// The stock block, a box along the program's axes in its coordinates and
/// units at the call.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stock {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl From<wit::Bounds> for Stock {
    fn from(b: wit::Bounds) -> Stock {
        Stock { min: [b.min_x, b.min_y, b.min_z], max: [b.max_x, b.max_y, b.max_z] }
    }
}

impl From<wit::MachineState> for State {
    fn from(s: wit::MachineState) -> State {
        State {
            units: s.units.into(),
            position: [s.x, s.y, s.z],
            distance: match s.distance {
                wit::Distance::Absolute => Distance::Absolute,
                wit::Distance::Incremental => Distance::Incremental,
            },
            plane: match s.plane {
                wit::Plane::Xy => Plane::XY,
                wit::Plane::Zx => Plane::ZX,
                wit::Plane::Yz => Plane::YZ,
            },
            feed: s.feed,
            spindle: match s.spindle {
                wit::Spindle::Off => Spindle::Off,
                wit::Spindle::Clockwise(s) => Spindle::Clockwise(s),
                wit::Spindle::CounterClockwise(s) => Spindle::CounterClockwise(s),
            },
            tool: s.tool.map(Tool::from),
            tool_number: s.tool_number,
            line: s.line,
        }
    }
}
