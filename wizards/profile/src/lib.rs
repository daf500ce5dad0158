//! `Profile LENGTH WIDTH DEPTH [SIDE] [CORNER] [STEPDOWN]`: cuts along the
//! outside or the inside of a rectangle, its corners rounded to CORNER (a
//! CORNER of half the sides makes it a circle).
//!
//! The rectangle's lower-left corner is at the current XY and its top at the
//! current Z. SIDE is `"outside"` (the default: the part is the rectangle)
//! or `"inside"` (the rectangle is a hole). The tool's centre runs at its
//! radius from the edge, round the outside corners, and into inside corners
//! as far as its radius allows. It goes round clockwise outside and
//! counter-clockwise inside, which is climb milling with M03. Each level
//! (STEPDOWN apart, default the tool's diameter; the last exactly at DEPTH)
//! is reached by a ramp along the bottom edge (a helix for a circle), never
//! straight down. Afterwards the tool is back at the call's position, in the
//! call's modes.

use ger_wizard_sdk::*;

struct Profile;

/// The tool centre's path: a rounded rectangle, corner centres and radius.
struct Path {
    /// Lower-left and upper-right corner centres.
    low: [f64; 2],
    high: [f64; 2],
    radius: f64,
    clockwise: bool,
}

impl Path {
    /// Where the loop starts: the bottom edge's first end, in the loop's direction.
    fn start(&self) -> [f64; 2] {
        let x = if self.clockwise { self.high[0] } else { self.low[0] };
        [x, self.low[1] - self.radius]
    }

    /// The bottom edge's other end.
    fn bottom_end(&self) -> [f64; 2] {
        let x = if self.clockwise { self.low[0] } else { self.high[0] };
        [x, self.low[1] - self.radius]
    }

    fn is_circle(&self) -> bool {
        self.low == self.high
    }

    /// One loop at the current level, from `start()` back to it.
    fn round(&self) -> Vec<Statement> {
        let ([x0, y0], [x1, y1], r) = (self.low, self.high, self.radius);
        // Corner centres in the loop's order after the start, with the point each corner's arc ends at.
        let corners: [([f64; 2], [f64; 2]); 4] = if self.clockwise {
            [([x0, y0], [x0 - r, y0]), ([x0, y1], [x0, y1 + r]), ([x1, y1], [x1 + r, y1]), ([x1, y0], [x1, y0 - r])]
        } else {
            [([x1, y0], [x1 + r, y0]), ([x1, y1], [x1, y1 + r]), ([x0, y1], [x0 - r, y1]), ([x0, y0], [x0, y0 - r])]
        };
        // Before each corner, the straight edge to where its arc starts.
        let starts: [[f64; 2]; 4] = if self.clockwise {
            [[x0, y0 - r], [x0 - r, y1], [x1, y1 + r], [x1 + r, y0]]
        } else {
            [[x1, y0 - r], [x1 + r, y1], [x0, y1 + r], [x0 - r, y0]]
        };
        let mut out = Vec::new();
        for ((centre, end), arc_start) in corners.iter().zip(starts) {
            out.push(g1().xy(arc_start[0], arc_start[1]).into());
            if r > 0.0 {
                let arc = if self.clockwise { g2() } else { g3() };
                out.push(arc.xy(end[0], end[1]).i(centre[0] - arc_start[0]).j(centre[1] - arc_start[1]).into());
            }
        }
        out
    }
}

impl Wizard for Profile {
    fn describe() -> Description {
        Description::new(
            "Profile",
            "cuts round the outside or the inside of a rectangle from its lower-left corner",
            "Profile LENGTH WIDTH DEPTH [SIDE] [CORNER] [STEPDOWN]",
        )
        .param("LENGTH", "size along X")
        .param("WIDTH", "size along Y")
        .param("DEPTH", "depth below the current Z")
        .optional("SIDE", "\"outside\" (default) or \"inside\"")
        .optional("CORNER", "radius of the rectangle's corners (default 0; half the sides: a circle)")
        .optional("STEPDOWN", "depth of cut per level (default: the tool's diameter)")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let length = args.positive(0)?;
        let width = args.positive(1)?;
        let depth = args.positive(2)?;
        let outside = args.choice(3, &["outside", "inside"])? == 0;
        let corner = args.optional_number(4)?.unwrap_or(0.0);
        if corner < 0.0 || corner > length.min(width) / 2.0 {
            return Err(format!(
                "CORNER (argument 5) must be from 0 to half the shorter side ({}), not {corner}",
                length.min(width) / 2.0
            ));
        }
        let tool = state.require_cutter("a profile needs an end mill")?;
        let stepdown = args.optional_positive(5)?.unwrap_or(tool.diameter);
        let r = tool.diameter / 2.0;
        // Inside, a corner is as round as the tool at least.
        let inset = if outside { corner } else { corner.max(r) };
        let radius = if outside { corner + r } else { inset - r };
        if !outside && tool.diameter >= length.min(width) {
            return Err(format!(
                "the tool (T{}, diameter {}) does not fit inside the rectangle ({length} x {width})",
                tool.number, tool.diameter
            ));
        }
        let [x0, y0, top] = state.position;
        let path = Path {
            low: [x0 + inset, y0 + inset],
            high: [x0 + length - inset, y0 + width - inset],
            radius,
            clockwise: outside,
        };
        if !path.is_circle() && path.low[0] == path.high[0] {
            return Err("the bottom edge is all corner, with no straight part to ramp down along: make CORNER smaller"
                .to_string());
        }
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling Profile")?;
        let levels = entry::levels(top, depth, stepdown);
        let side = if outside { "outside" } else { "inside" };
        let mut out = vec![comment(format!("Profile {side} {length} x {width} x {depth}: {} levels", levels.len()))];
        let start = path.start();
        out.push(g0().xy(start[0], start[1]).into());
        let mut above = top;
        for &z in &levels {
            if path.is_circle() {
                // Its whole turn at the level is the loop.
                out.extend(entry::helix(path.low, start, above, z, entry::DEFAULT_ENTRY_ANGLE, outside, feed)?);
            } else {
                out.extend(entry::ramp(start, path.bottom_end(), above, z, entry::DEFAULT_ENTRY_ANGLE, feed)?);
                out.extend(path.round());
            }
            above = z;
        }
        out.push(g0().z(top).into());
        out.push(g0().xy(x0, y0).into());
        Ok(state.in_absolute(out))
    }
}

export_wizard!(Profile);
