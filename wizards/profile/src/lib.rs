//! `Profile LENGTH WIDTH DEPTH [SIDE] [CORNER] [STEPDOWN] [TABS] [TAB_WIDTH]
//! [TAB_HEIGHT]`: cuts along the outside or the inside of a rectangle, its
//! corners rounded to CORNER (a CORNER of half the sides makes it a circle),
//! leaving TABS holding tabs that keep the part in place.
//!
//! The rectangle's lower-left corner is at the current XY and its top at the
//! current Z. SIDE is `"outside"` (the default: the part is the rectangle)
//! or `"inside"` (the rectangle is a hole). The tool's centre runs at its
//! radius from the edge, round the outside corners, and into inside corners
//! as far as its radius allows. It goes round clockwise outside and
//! counter-clockwise inside, which is climb milling with M03. Each level
//! (STEPDOWN apart, default the tool's diameter; the last exactly at DEPTH)
//! is reached by a ramp along the path itself (3°, as many laps as it
//! takes), never straight down, then one whole lap at the level. Tabs are
//! evenly spaced round the path: bridges TAB_WIDTH wide (default twice the
//! tool's diameter) and TAB_HEIGHT high above the bottom (default a quarter
//! of DEPTH), which the tool climbs over at 45° on every level below their
//! top. Afterwards the tool is back at the call's position, in the call's
//! modes.

use ger_wizard_sdk::*;

struct Profile;

/// More tabs than this round one path would be a part held by its tabs alone.
const MAX_TABS: u32 = 100;

impl Wizard for Profile {
    fn describe() -> Description {
        Description::new(
            "Profile",
            "cuts round the outside or the inside of a rectangle from its lower-left corner",
            "Profile LENGTH WIDTH DEPTH [SIDE] [CORNER] [STEPDOWN] [TABS] [TAB_WIDTH] [TAB_HEIGHT]",
        )
        .param("LENGTH", "size along X")
        .param("WIDTH", "size along Y")
        .param("DEPTH", "depth below the current Z")
        .optional("SIDE", "\"outside\" (default) or \"inside\"")
        .optional("CORNER", "radius of the rectangle's corners (default 0; half the sides: a circle)")
        .optional("STEPDOWN", "depth of cut per level (default: the tool's diameter)")
        .optional("TABS", "how many holding tabs to leave, evenly round the path (default 0)")
        .optional("TAB_WIDTH", "width of each tab's bridge (default: twice the tool's diameter)")
        .optional("TAB_HEIGHT", "height of the tabs above the bottom (default: a quarter of DEPTH)")
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
        let tabs = match args.optional_number(6)? {
            None => 0,
            Some(_) => args.whole(6, 0)?,
        };
        if tabs > MAX_TABS {
            return Err(format!("TABS (argument 7) must be at most {MAX_TABS}, not {tabs}"));
        }
        let tab_width = args.optional_positive(7)?.unwrap_or(2.0 * tool.diameter);
        let tab_height = args.optional_positive(8)?.unwrap_or(depth / 4.0);
        if tabs > 0 && tab_height >= depth {
            return Err(format!("TAB_HEIGHT (argument 9) must be less than DEPTH ({depth}), not {tab_height}"));
        }
        let [x0, y0, top] = state.position;
        let path = contour::Contour::rounded_rectangle(
            [x0 + inset, y0 + inset],
            [x0 + length - inset, y0 + width - inset],
            radius,
            outside,
        );
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling Profile")?;
        let lap = path.length();
        let tab_top = top - depth + tab_height;
        let levels = entry::levels(top, depth, stepdown);
        let side = if outside { "outside" } else { "inside" };
        let mut out = vec![comment(format!("Profile {side} {length} x {width} x {depth}: {} levels", levels.len()))];
        let start = path.start();
        out.push(g0().xy(start[0], start[1]).into());
        let (mut above, mut at) = (top, 0.0);
        for &z in &levels {
            // Down along the path, then a whole lap at the level, which also
            // cuts away the wedge the ramp left.
            let descent = contour::Heights::descent(at, above, z, entry::DEFAULT_ENTRY_ANGLE)?;
            let end = descent.ends_at() + lap;
            let first_lap = (at / lap).floor() * lap;
            let laps = ((end - first_lap) / lap).ceil() as u32 + 1;
            // The tool's path over a tab is wider than the bridge by its diameter.
            let tabs = contour::Heights::tabs(lap, first_lap, laps, tabs, tab_width + tool.diameter, z, tab_top)?;
            let mut moves = path.follow(at, end, &descent.max(&tabs))?;
            if let Some(Statement::Block(first)) = moves.first_mut() {
                first.words.push(('F', feed));
            }
            out.extend(moves);
            (above, at) = (z, end);
        }
        out.push(g0().z(top).into());
        out.push(g0().xy(x0, y0).into());
        Ok(state.in_absolute(out))
    }
}

export_wizard!(Profile);
