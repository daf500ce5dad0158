//! `CirclePocket DIAMETER DEPTH [STEPDOWN] [RAMP] [ALLOWANCE]`: clears a
//! round pocket.
//!
//! The pocket is centred on the current XY, its top at the current Z. The
//! tool goes down to each level (STEPDOWN apart, the last exactly at DEPTH)
//! by a helix no steeper than RAMP degrees around the centre, then spirals
//! out in rings at most 60% of its diameter apart, the last of them
//! ALLOWANCE (default 0) short of the wall. With an allowance, a finishing
//! pass then cuts the wall exactly, joined to the last ring by tangent arcs
//! (lead-in and lead-out), so it leaves no mark where it starts and ends.
//! The rings run counter-clockwise, which is climb milling inside a pocket
//! with the spindle turning clockwise (M03). Afterwards the tool is back at
//! the call's position, in the call's modes.

use ger_wizard_sdk::contour::{Contour, Heights, Side};
use ger_wizard_sdk::*;

/// Rings are at most this fraction of the diameter apart, so neighbouring
/// passes overlap and leave no ridges.
const MAX_STEPOVER: f64 = 0.6;
/// The helix's radius, as a fraction of the tool's: at most the tool's own,
/// so the helix leaves no core standing at the centre.
const HELIX: f64 = 0.5;
/// Below this fraction of the tool's radius a helix is too tight to cut.
const SMALLEST_HELIX: f64 = 0.1;

pub struct CirclePocket;

impl Wizard for CirclePocket {
    fn describe() -> Description {
        Description::new(
            "CirclePocket",
            "clears a round pocket centred on the current position, from its top",
            "CirclePocket DIAMETER DEPTH [STEPDOWN] [RAMP] [ALLOWANCE]",
        )
        .param("DIAMETER", "the pocket's diameter")
        .param("DEPTH", "depth below the current Z")
        .optional("STEPDOWN", "depth of cut per level (default: the tool's diameter)")
        .optional("RAMP", "steepest helix into each level, in degrees (default 3)")
        .optional("ALLOWANCE", "what the rings leave on the wall for the finishing pass (default 0)")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let diameter = args.positive(0)?;
        let depth = args.positive(1)?;
        let tool = state.require_cutter("a pocket needs an end mill")?;
        let stepdown = args.optional_positive(2)?.unwrap_or(tool.diameter);
        let ramp = args.optional_positive(3)?.unwrap_or(entry::DEFAULT_ENTRY_ANGLE);
        let allowance = args.optional_non_negative(4)?.unwrap_or(0.0);
        let r = tool.diameter / 2.0;
        let outer = diameter / 2.0 - r;
        if outer < SMALLEST_HELIX * r {
            return Err(format!(
                "the pocket (diameter {diameter}) leaves the tool (T{}, diameter {}) no room to helix down: \
                 it needs a pocket of at least {}",
                tool.number,
                tool.diameter,
                tool.diameter + 2.0 * SMALLEST_HELIX * r
            ));
        }
        if allowance > MAX_STEPOVER * tool.diameter {
            return Err(format!(
                "ALLOWANCE {allowance} is more than a ring's stepover ({}): the finishing pass would cut a full slot",
                MAX_STEPOVER * tool.diameter
            ));
        }
        if allowance >= outer - outer.min(HELIX * r) {
            return Err(format!(
                "ALLOWANCE {allowance} leaves the rings no room in a pocket of diameter {diameter} with this tool (T{})",
                tool.number
            ));
        }
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling CirclePocket")?;
        let cut = Cut { tool_diameter: tool.diameter, stepdown, ramp, allowance, feed };
        plan(state.position, diameter, depth, &cut).map(|moves| state.in_absolute(moves))
    }
}

/// How the pocket is cut.
pub struct Cut {
    pub tool_diameter: f64,
    pub stepdown: f64,
    /// The steepest helix, in degrees.
    pub ramp: f64,
    /// What the rings leave on the wall for the finishing pass.
    pub allowance: f64,
    pub feed: f64,
}

/// The tool path; lengths in program units, `centre` the top of the pocket's axis.
pub fn plan(centre: [f64; 3], diameter: f64, depth: f64, cut: &Cut) -> Result<Vec<Statement>, String> {
    let [cx, cy, top] = centre;
    let r = cut.tool_diameter / 2.0;
    let (wall, a) = (diameter / 2.0 - r, cut.allowance);
    let helix = wall.min(HELIX * r);
    // Rings from the helix's out to the allowance, evenly apart.
    let outer = wall - a;
    let rings = ((outer - helix) / (MAX_STEPOVER * cut.tool_diameter)).ceil() as u32;
    // The finishing pass round the wall from its east point, joined by leads
    // of the tool's radius (inside the wall's circle) that start and end `a`
    // in from that point's tangent.
    let finishing = Contour::circle([cx, cy], [cx + wall, cy], false);
    let lead = r.max(a).min(wall);
    let levels = entry::levels(top, depth, cut.stepdown);

    let mut out = vec![comment(format!(
        "CirclePocket {diameter} x {depth}: {} levels, a helix of radius {helix:.4} and {rings} rings{}, tool diameter {}",
        levels.len(),
        if a > 0.0 { " and a finishing pass" } else { "" },
        cut.tool_diameter
    ))];
    let start = [cx + helix, cy];
    out.push(g0().xy(start[0], start[1]).into());
    let mut above = top;
    for &z in &levels {
        out.extend(entry::helix([cx, cy], start, above, z, cut.ramp, false, cut.feed)?);
        for ring in 1..=rings {
            let radius = helix + (outer - helix) * f64::from(ring) / f64::from(rings);
            out.push(g1().xy(cx + radius, cy).into());
            out.push(g3().xy(cx + radius, cy).i(-radius).j(0.0).into());
        }
        if a > 0.0 {
            let lap = finishing.length();
            let (from, lead_in) = finishing.lead_in(0.0, lead, a, Side::Left)?;
            let (lead_out, _) = finishing.lead_out(lap, lead, a, Side::Left)?;
            out.push(g1().xy(from[0], from[1]).into());
            out.push(lead_in);
            out.extend(finishing.follow(0.0, lap, &Heights::level(z))?);
            out.push(lead_out);
        }
        // Back in over what is cut, to the helix's start for the next level.
        out.push(g1().xy(start[0], start[1]).into());
        above = z;
    }
    out.push(g0().z(top).into());
    out.push(g0().xy(cx, cy).into());
    Ok(out)
}

export_wizard!(CirclePocket);
