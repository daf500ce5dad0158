//! Cutters: the shape of a tool's lower end, as a solid of revolution.

use ger_core::config::{Tool, ToolKind};

/// The profile of a tool's lower end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// Endmill: flat bottom.
    Flat,
    /// Ballmill: a hemisphere of the tool's radius.
    Ball,
    /// Drill and centre drill: a cone rising `slope` per unit of radius
    /// (1 / tan of half the tip angle), a cylinder above it.
    Cone { slope: f64 },
}

/// A tool as the simulation sees it: radius and profile, in machine units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cutter {
    pub radius: f64,
    pub shape: Shape,
}

/// A drill's point when the table does not say: 118 degrees.
pub const DEFAULT_TIP_ANGLE: f64 = 118.0;

impl Cutter {
    pub fn new(tool: &Tool) -> Cutter {
        let radius = tool.diameter / 2.0;
        let shape = match tool.kind {
            ToolKind::Endmill => Shape::Flat,
            ToolKind::Ballmill => Shape::Ball,
            ToolKind::Drill | ToolKind::CenterDrill => {
                let half = tool.tip_angle.unwrap_or(DEFAULT_TIP_ANGLE).to_radians() / 2.0;
                Shape::Cone { slope: 1.0 / half.tan() }
            }
        };
        Cutter { radius, shape }
    }

    /// How far above its tip the tool's lower surface is at distance `r`
    /// (at most the radius) from its axis.
    #[inline(always)]
    pub fn profile(&self, r: f64) -> f64 {
        match self.shape {
            Shape::Flat => 0.0,
            Shape::Ball => self.radius - (self.radius * self.radius - r * r).max(0.0).sqrt(),
            Shape::Cone { slope } => slope * r,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tool(kind: ToolKind, tip_angle: Option<f64>) -> Tool {
        Tool { number: 1, kind, diameter: 2.0, flute_length: None, tip_angle }
    }

    #[test]
    fn profiles() {
        let flat = Cutter::new(&tool(ToolKind::Endmill, None));
        assert_eq!((flat.profile(0.0), flat.profile(1.0)), (0.0, 0.0));
        let ball = Cutter::new(&tool(ToolKind::Ballmill, None));
        assert_eq!((ball.profile(0.0), ball.profile(1.0)), (0.0, 1.0));
        let drill = Cutter::new(&tool(ToolKind::Drill, Some(90.0)));
        assert!((drill.profile(1.0) - 1.0).abs() < 1e-12);
        let default = Cutter::new(&tool(ToolKind::CenterDrill, None));
        assert!((default.profile(1.0) - 1.0 / 59f64.to_radians().tan()).abs() < 1e-12);
    }
}
