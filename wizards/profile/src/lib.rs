//! `Profile LENGTH WIDTH DEPTH [SIDE] [CORNER] [STEPDOWN] [TABS] [TAB_WIDTH]
//! [TAB_HEIGHT] [ALLOWANCE]`: cuts along the outside or the inside of a
//! rectangle, its corners rounded to CORNER (a CORNER of half the sides
//! makes it a circle), leaving TABS holding tabs that keep the part in place.
//!
//! The rectangle's lower-left corner is at the current XY and its top at the
//! current Z. SIDE is `"outside"` (the default: the part is the rectangle)
//! or `"inside"` (the rectangle is a hole). The tool's centre runs at its
//! radius from the edge, round the outside corners, and into inside corners
//! as far as its radius allows. It goes round clockwise outside and
//! counter-clockwise inside, which is climb milling with M03, starting in
//! the middle of the bottom side. Each level (STEPDOWN apart, default the
//! tool's diameter; the last exactly at DEPTH) is reached by a ramp along
//! the path itself (3°, as many laps as it takes), never straight down, then
//! one whole lap at the level. Tabs are evenly spaced round the path:
//! bridges TAB_WIDTH wide (default twice the tool's diameter) and
//! TAB_HEIGHT high above the bottom (default a quarter of DEPTH), which the
//! tool climbs over at 45° on every level below their top.
//!
//! With an ALLOWANCE (default 0, at most the tool's radius) the levels run
//! that much further from the edge, and a finishing pass then cuts the edge
//! exactly: at full depth in one lap where the tool's flutes are long enough
//! (or not known), else in as few equal levels as they allow, each joined to
//! the roughing groove by tangent arcs (lead-in and lead-out) in the middle
//! of the bottom side, so it leaves no mark where it starts and ends.
//! Afterwards the tool is back at the call's position, in the call's modes.

use ger_wizard_sdk::contour::{Contour, Heights, Side};
use ger_wizard_sdk::*;

struct Profile;

/// More tabs than this round one path would be a part held by its tabs alone.
const MAX_TABS: u32 = 100;

impl Wizard for Profile {
    fn describe() -> Description {
        Description::new(
            "Profile",
            "cuts round the outside or the inside of a rectangle from its lower-left corner",
            "Profile LENGTH WIDTH DEPTH [SIDE] [CORNER] [STEPDOWN] [TABS] [TAB_WIDTH] [TAB_HEIGHT] [ALLOWANCE]",
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
        .optional("ALLOWANCE", "what the levels leave on the edge for a finishing pass (default 0: none)")
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
        let allowance = args.optional_non_negative(9)?.unwrap_or(0.0);
        if allowance > r {
            return Err(format!(
                "ALLOWANCE (argument 10) must be at most the tool's radius ({r}), not {allowance}: \
                 the finishing pass would cut a full groove"
            ));
        }
        if !outside && tool.diameter + 2.0 * allowance >= length.min(width) {
            let allowing = if allowance > 0.0 { format!(" with {allowance} allowance a side") } else { String::new() };
            return Err(format!(
                "the tool (T{}, diameter {}){allowing} does not fit inside the rectangle ({length} x {width})",
                tool.number, tool.diameter
            ));
        }
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling Profile")?;
        let [x0, y0, top] = state.position;
        let rectangle = Rectangle { low: [x0, y0], size: [length, width], corner, outside };
        let rough = rectangle.path(r + allowance);
        let tab_top = top - depth + tab_height;
        let tab_path_width = tab_width + tool.diameter;
        let levels = entry::levels(top, depth, stepdown);
        let side = if outside { "outside" } else { "inside" };
        let finishing = if allowance > 0.0 { " and a finishing pass" } else { "" };
        let mut out =
            vec![comment(format!("Profile {side} {length} x {width} x {depth}: {} levels{finishing}", levels.len()))];
        let lap = rough.contour.length();
        let start = rectangle.bottom_middle(r + allowance);
        out.push(g0().xy(start[0], start[1]).into());
        let (mut above, mut at) = (top, rough.middle);
        // The laps' starts, from the middle of the bottom side: tabs are placed on each.
        let lap_start = |at: f64| rough.middle + ((at - rough.middle) / lap).floor() * lap;
        for &z in &levels {
            // Down along the path, then a whole lap at the level, which also
            // cuts away the wedge the ramp left.
            let descent = Heights::descent(at, above, z, entry::DEFAULT_ENTRY_ANGLE)?;
            let end = descent.ends_at() + lap;
            let first_lap = lap_start(at);
            let laps = ((end - first_lap) / lap).ceil() as u32 + 1;
            // The tool's path over a tab is wider than the bridge by its diameter.
            let tabs = Heights::tabs(lap, first_lap, laps, tabs, tab_path_width, z, tab_top)?;
            let mut moves = rough.contour.follow(at, end, &descent.max(&tabs))?;
            if let Some(Statement::Block(first)) = moves.first_mut() {
                first.words.push(('F', feed));
            }
            out.extend(moves);
            (above, at) = (z, end);
        }
        if allowance > 0.0 {
            // On along the groove at the bottom, over its tabs, to the middle of the bottom side.
            let middle = lap_start(at) + lap;
            let tabs_on = Heights::tabs(lap, lap_start(at), 2, tabs, tab_path_width, above, tab_top)?;
            out.extend(rough.contour.follow(at, middle, &tabs_on)?);
            let finish = rectangle.path(r);
            // The leads reach sqrt(2ra - a²) along the groove either side of
            // the middle, where no tab may rise, on either path.
            let reach = (2.0 * r * allowance - allowance * allowance).sqrt();
            let tab_reach = tab_path_width / 2.0 + tab_height;
            let shorter = lap.min(finish.contour.length());
            if tabs > 0 && shorter / (2.0 * f64::from(tabs)) - tab_reach < reach {
                return Err(format!("{tabs} tabs leave the finishing pass no room to lead in and out between them"));
            }
            let pass = Finishing { path: &finish, lead: r, allowance, tabs, tab_path_width, tab_top };
            let deepest_cut = tool.flute_length.unwrap_or(depth).min(depth);
            out.extend(pass.moves(entry::equal_passes(top, top - depth, deepest_cut), above)?);
        }
        out.push(g0().z(top).into());
        out.push(g0().xy(x0, y0).into());
        Ok(state.in_absolute(out))
    }
}

/// The rectangle a profile goes round, and on which side.
struct Rectangle {
    low: [f64; 2],
    size: [f64; 2],
    corner: f64,
    outside: bool,
}

/// A path round the rectangle, and how far along it the middle of its bottom side is.
struct Path {
    contour: Contour,
    middle: f64,
}

impl Rectangle {
    /// The tool's path `offset` from the edge, on the side cut away:
    /// clockwise outside, counter-clockwise inside.
    fn path(&self, offset: f64) -> Path {
        let ([x0, y0], [length, width]) = (self.low, self.size);
        // Outside, round the corners' own centres; inside, as far into the
        // corners as the tool's path can go.
        let (inset, radius) = if self.outside {
            (self.corner, self.corner + offset)
        } else {
            let radius = (self.corner - offset).max(0.0);
            (offset + radius, radius)
        };
        let (low, high) = ([x0 + inset, y0 + inset], [x0 + length - inset, y0 + width - inset]);
        let contour = Contour::rounded_rectangle(low, high, radius, self.outside);
        Path { contour, middle: (high[0] - low[0]) / 2.0 }
    }

    /// The middle of the bottom side of the path `offset` from the edge.
    fn bottom_middle(&self, offset: f64) -> [f64; 2] {
        let below = if self.outside { -offset } else { offset };
        [self.low[0] + self.size[0] / 2.0, self.low[1] + below]
    }
}

/// The pass that cuts the edge exactly after the levels left the allowance on it.
struct Finishing<'a> {
    path: &'a Path,
    lead: f64,
    allowance: f64,
    tabs: u32,
    tab_path_width: f64,
    tab_top: f64,
}

impl Finishing<'_> {
    /// The pass at each of `levels`, from the middle of the roughing
    /// groove's bottom side at `from_z`, where the tool is: at each a lead
    /// in from the groove, a lap (over the tabs) and a lead out to it, then
    /// back along the groove to where the next lead starts.
    fn moves(&self, levels: impl Iterator<Item = f64>, from_z: f64) -> Result<Vec<Statement>, String> {
        let contour = &self.path.contour;
        let (lap, at) = (contour.length(), self.path.middle);
        let (start, lead_in) = contour.lead_in(at, self.lead, self.allowance, Side::Left)?;
        let (lead_out, _) = contour.lead_out(at + lap, self.lead, self.allowance, Side::Left)?;
        let mut out = vec![g1().xy(start[0], start[1]).into()];
        let mut z_now = from_z;
        for z in levels {
            if z != z_now {
                out.push(g1().z(z).into());
            }
            let tabs = Heights::tabs(lap, at, 1, self.tabs, self.tab_path_width, z, self.tab_top)?;
            out.push(lead_in.clone());
            out.extend(contour.follow(at, at + lap, &tabs)?);
            out.push(lead_out.clone());
            out.push(g1().xy(start[0], start[1]).into());
            z_now = z;
        }
        Ok(out)
    }
}

export_wizard!(Profile);
