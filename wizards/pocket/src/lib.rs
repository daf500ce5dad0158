//! `Pocket LENGTH WIDTH DEPTH [STEPDOWN] [RAMP]`: clears a rectangular pocket.
//!
//! The pocket's lower-left corner is at the current XY and its top at the
//! current Z. The tool goes down to each level (STEPDOWN apart, the last
//! exactly at DEPTH) by a ramp along the first row, no steeper than RAMP
//! degrees (along Y when the pocket is only the tool's length), never
//! straight down; the level is cleared by a zigzag along X whose rows are at
//! most 60% of the tool's diameter apart, then a finishing pass along the walls. The tool's centre
//! stays inset from the walls by its radius, so it cuts exactly to them.
//! Afterwards the tool is back at the call's position, in the call's modes.

use ger_wizard_sdk::*;

/// Rows of the zigzag are at most this fraction of the diameter apart, so
/// neighbouring passes overlap and leave no ridges.
const MAX_STEPOVER: f64 = 0.6;

pub struct Pocket;

impl Wizard for Pocket {
    fn describe() -> Description {
        Description::new(
            "Pocket",
            "clears a rectangular pocket from the current position (its lower-left corner, at its top)",
            "Pocket LENGTH WIDTH DEPTH [STEPDOWN] [RAMP]",
        )
        .param("LENGTH", "size along X")
        .param("WIDTH", "size along Y")
        .param("DEPTH", "depth below the current Z")
        .optional("STEPDOWN", "depth of cut per level (default: the tool's diameter)")
        .optional("RAMP", "steepest entry into each level, in degrees (default 3)")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let length = args.positive(0)?;
        let width = args.positive(1)?;
        let depth = args.positive(2)?;
        let tool = state.require_cutter("a pocket needs an end mill")?;
        let stepdown = args.optional_positive(3)?.unwrap_or(tool.diameter);
        let ramp = args.optional_positive(4)?.unwrap_or(entry::DEFAULT_ENTRY_ANGLE);
        let d = tool.diameter;
        if d > length || d > width {
            return Err(format!(
                "the tool (T{}, diameter {d}) is wider than the pocket ({length} x {width})",
                tool.number
            ));
        }
        if d == length && d == width {
            return Err(format!(
                "the pocket is the tool's size (T{}, diameter {d}): there is no room to ramp down; drill it",
                tool.number
            ));
        }
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling Pocket")?;
        let cut = Cut { diameter: d, stepdown, ramp, feed };
        plan(state.position, [length, width, depth], &cut).map(|moves| state.in_absolute(moves))
    }
}

/// How the pocket is cut: the tool's diameter, the depth of a level, the
/// steepest entry in degrees, the feed.
pub struct Cut {
    pub diameter: f64,
    pub stepdown: f64,
    pub ramp: f64,
    pub feed: f64,
}

/// The tool path; lengths in program units, `corner` the lower-left top corner.
pub fn plan(corner: [f64; 3], size: [f64; 3], cut: &Cut) -> Result<Vec<Statement>, String> {
    let [x0, y0, top] = corner;
    let [length, width, depth] = size;
    let Cut { diameter, stepdown, ramp, feed } = *cut;
    let r = diameter / 2.0;
    let (xa, xb, ya, yb) = (x0 + r, x0 + length - r, y0 + r, y0 + width - r);
    let levels = entry::levels(top, depth, stepdown);
    let rows = ((yb - ya) / (MAX_STEPOVER * diameter)).ceil() as u32 + 1;

    let mut out = vec![comment(format!(
        "Pocket {length} x {width} x {depth}: {} levels of {rows} rows, tool diameter {diameter}",
        levels.len()
    ))];
    out.push(g0().xy(xa, ya).into());
    // Along the first row, or up the first column of a pocket the tool's length.
    let ramp_end = if xb > xa { [xb, ya] } else { [xa, yb] };
    let mut above = top;
    for &z in &levels {
        out.extend(entry::ramp([xa, ya], ramp_end, above, z, ramp, feed)?);
        above = z;
        for row in 0..rows {
            let y = if rows == 1 { ya } else { ya + (yb - ya) * f64::from(row) / f64::from(rows - 1) };
            if row > 0 {
                out.push(g1().y(y).into());
            }
            out.push(g1().x(if row % 2 == 0 { xb } else { xa }).into());
        }
        // Finishing pass along the walls, from the start corner.
        out.push(g1().xy(xa, ya).into());
        out.push(g1().x(xb).into());
        out.push(g1().y(yb).into());
        out.push(g1().x(xa).into());
        out.push(g1().y(ya).into());
    }
    out.push(g0().z(top).into());
    out.push(g0().xy(x0, y0).into());
    Ok(out)
}

export_wizard!(Pocket);
