//! Cutters: the shape of a tool's lower end, as a solid of revolution.

#[cfg(test)]
use ger_core::config::HolderPiece;
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
    /// A cone cut off at `flat` from the axis: flat there, then rising
    /// `slope` per unit of radius (a holder's taper).
    Frustum { slope: f64, flat: f64 },
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
            Shape::Frustum { slope, flat } => slope * (r - flat).max(0.0),
        }
    }
}

/// Which part of a tool above its cutting edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PartKind {
    Shank,
    /// The holder's piece, counted from its face (0 first).
    Holder(u8),
}

/// A part of a tool that must not touch the stock: a solid of revolution
/// `base` above the tip, whose underside is `cutter`'s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Part {
    pub kind: PartKind,
    pub base: f64,
    pub cutter: Cutter,
}

impl Part {
    /// The parts of `tool` above its flutes, as the table describes them: the
    /// shank from the flutes up (none when the flute length is not known) to
    /// the holder's face, then the holder's pieces.
    pub fn of(tool: &Tool) -> Vec<Part> {
        let mut parts = Vec::new();
        if let Some(flutes) = tool.flute_length {
            let cutter = Cutter { radius: tool.shank() / 2.0, shape: Shape::Flat };
            parts.push(Part { kind: PartKind::Shank, base: flutes, cutter });
        }
        let mut base = tool.stick_out.unwrap_or(f64::INFINITY);
        for (i, piece) in tool.holder.iter().enumerate() {
            let (bottom, top) = piece.ends();
            // Only the underside matters: the stock is a height field, so a part
            // touches it where material is above its lowest point over a cell.
            let shape = if top > bottom {
                Shape::Frustum { slope: piece.length / ((top - bottom) / 2.0), flat: bottom / 2.0 }
            } else {
                Shape::Flat
            };
            let cutter = Cutter { radius: top.max(bottom) / 2.0, shape };
            parts.push(Part { kind: PartKind::Holder(i as u8), base, cutter });
            base += piece.length;
        }
        parts
    }

    /// The part grown by `margin` sideways and down: what comes that near
    /// the stock is within it (a square edge, where growing would round it).
    pub fn grown(&self, margin: f64) -> Part {
        let shape = match self.cutter.shape {
            Shape::Frustum { slope, flat } => Shape::Frustum { slope, flat: flat + margin },
            shape => shape,
        };
        Part { base: self.base - margin, cutter: Cutter { radius: self.cutter.radius + margin, shape }, ..*self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tool(kind: ToolKind, tip_angle: Option<f64>) -> Tool {
        Tool { tip_angle, ..Tool::new(1, kind, 2.0) }
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
        let taper = Cutter { radius: 2.0, shape: Shape::Frustum { slope: 3.0, flat: 1.0 } };
        assert_eq!((taper.profile(0.5), taper.profile(1.0), taper.profile(2.0)), (0.0, 0.0, 3.0));
    }

    #[test]
    fn a_tools_parts_stack_from_its_flutes_up() {
        let holder = vec![
            HolderPiece { diameter: None, bottom: Some(20.0), top: Some(30.0), length: 10.0 },
            HolderPiece { diameter: Some(40.0), bottom: None, top: None, length: 20.0 },
        ];
        let tool = Tool {
            flute_length: Some(8.0),
            shank_diameter: Some(6.0),
            stick_out: Some(25.0),
            holder,
            ..Tool::new(1, ToolKind::Endmill, 3.0)
        };
        let parts = Part::of(&tool);
        let flat = |radius| Cutter { radius, shape: Shape::Flat };
        assert_eq!(
            parts,
            [
                Part { kind: PartKind::Shank, base: 8.0, cutter: flat(3.0) },
                Part {
                    kind: PartKind::Holder(0),
                    base: 25.0,
                    // Rising 10 over the 5 from radius 10 to 15.
                    cutter: Cutter { radius: 15.0, shape: Shape::Frustum { slope: 2.0, flat: 10.0 } },
                },
                Part { kind: PartKind::Holder(1), base: 35.0, cutter: flat(20.0) },
            ]
        );
        // Without a flute length the shank is not known; without a stick-out, nor the holder.
        assert!(Part::of(&Tool::new(1, ToolKind::Endmill, 3.0)).is_empty());
    }
}
