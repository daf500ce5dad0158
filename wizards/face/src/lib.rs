//! `Face LENGTH WIDTH DEPTH [STEPDOWN] [STEPOVER]`: surfaces a rectangle.
//!
//! The rectangle's lower-left corner is at the current XY and its top at the
//! current Z. Each level (STEPDOWN apart, the last exactly at DEPTH) is cut
//! in rows along X, STEPOVER apart (default 60% of the tool's diameter), the
//! first on the rectangle's lower edge and the last on its upper one, each
//! running past both ends by the tool's radius and a clearance so the edges
//! come out clean. The tool reaches each level by a ramp along the first row,
//! so a stock larger than the rectangle is never plunged into; between levels
//! it rises to the top, clear of the scallops the rows' ends leave. Afterwards the
//! tool is back at the call's position, in the call's modes.

use ger_wizard_sdk::*;

/// The default distance between rows, as a fraction of the diameter.
const STEPOVER: f64 = 0.6;
/// How far past the rectangle the rows run, beyond the tool's radius, as a fraction of the diameter.
const CLEARANCE: f64 = 0.25;

struct Face;

impl Wizard for Face {
    fn describe() -> Description {
        Description::new(
            "Face",
            "surfaces a rectangle from the current position (its lower-left corner, at its top)",
            "Face LENGTH WIDTH DEPTH [STEPDOWN] [STEPOVER]",
        )
        .param("LENGTH", "size along X")
        .param("WIDTH", "size along Y")
        .param("DEPTH", "depth below the current Z")
        .optional("STEPDOWN", "depth of cut per level (default: DEPTH in one level)")
        .optional("STEPOVER", "distance between rows (default: 60% of the tool's diameter)")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let length = args.positive(0)?;
        let width = args.positive(1)?;
        let depth = args.positive(2)?;
        let tool = state.require_cutter("facing needs an end mill")?;
        let stepdown = args.optional_positive(3)?.unwrap_or(depth);
        let d = tool.diameter;
        let stepover = args.optional_positive(4)?.unwrap_or(STEPOVER * d);
        if stepover > d {
            return Err(format!(
                "a STEPOVER of {stepover} is wider than the tool (T{}, diameter {d}): it would leave ridges",
                tool.number
            ));
        }
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling Face")?;
        let [x0, y0, top] = state.position;
        let reach = d / 2.0 + CLEARANCE * d;
        let (xa, xb) = (x0 - reach, x0 + length + reach);
        let rows = (width / stepover).ceil() as u32 + 1;
        let levels = entry::levels(top, depth, stepdown);
        let mut out =
            vec![comment(format!("Face {length} x {width} x {depth}: {} levels of {rows} rows", levels.len()))];
        out.push(g0().xy(xa, y0).into());
        let mut above = top;
        for (level, &z) in levels.iter().enumerate() {
            // Back at the first row's start, and down through what the level
            // above cut there.
            if level > 0 {
                out.push(g0().xy(xa, y0).into());
                out.push(g1().z(above).into());
            }
            out.extend(entry::ramp([xa, y0], [xb, y0], above, z, entry::DEFAULT_ENTRY_ANGLE, feed)?);
            // The ramp cut the first row at this level; the others go back and forth from its end.
            for row in 1..rows {
                let y = y0 + width * f64::from(row) / f64::from(rows - 1);
                out.push(g1().y(y).into());
                out.push(g1().x(if row % 2 == 0 { xa } else { xb }).into());
            }
            // Up to the top before going back: at the level above, the
            // rows' rounded ends left scallops along both edges.
            out.push(g0().z(top).into());
            above = z;
        }
        out.push(g0().xy(x0, y0).into());
        Ok(state.in_absolute(out))
    }
}

export_wizard!(Face);
