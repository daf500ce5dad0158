//! `Pocket LENGTH WIDTH DEPTH [STEPDOWN] [RAMP] [STEPOVER] [CORNER]
//! [ALLOWANCE] ["ramp"|"helix"]`: clears a rectangular pocket.
//!
//! The pocket's lower-left corner is at the current XY and its top at the
//! current Z; its corners are rounded to CORNER (default 0: as sharp as the
//! tool leaves them). Each level (STEPDOWN apart, default the tool's
//! diameter; the last exactly at DEPTH) is cleared from the middle out in
//! rings that follow the walls, STEPOVER apart at most (default 60% of the
//! diameter), all counter-clockwise, which is climb milling with M03. The
//! tool gets down to a level by a ramp along the innermost ring, or by a
//! helix in the middle, no steeper than RAMP degrees (default 3), never
//! straight down. The rings stop ALLOWANCE (default 0) short of the walls,
//! and a finishing ring then cuts the walls exactly, at every level, joined
//! from the outermost ring by tangent arcs in the middle of the bottom wall
//! (lead-in and lead-out), so it leaves no mark where it starts and ends. The
//! tool's centre stays its radius from the walls. Afterwards the tool is
//! back at the call's position, in the call's modes.

use ger_wizard_sdk::contour::{Contour, Heights, Side};
use ger_wizard_sdk::*;

/// The default distance between rings, as a fraction of the diameter.
const DEFAULT_STEPOVER: f64 = 0.6;
/// The widest stepover that leaves nothing between rings with sharp
/// corners: a point between two corners is 0.586 stepovers from the nearer
/// ring, which must be within the tool's radius.
const MAX_STEPOVER: f64 = 0.85;
/// The innermost ring is at most this fraction of the tool's radius from
/// the middle, so the tool on it cuts the middle too.
const INNERMOST: f64 = 0.9;

pub struct Pocket;

impl Wizard for Pocket {
    fn describe() -> Description {
        Description::new(
            "Pocket",
            "clears a rectangular pocket from the current position (its lower-left corner, at its top)",
            "Pocket LENGTH WIDTH DEPTH [STEPDOWN] [RAMP] [STEPOVER] [CORNER] [ALLOWANCE] [\"ramp\"|\"helix\"]",
        )
        .param("LENGTH", "size along X")
        .param("WIDTH", "size along Y")
        .param("DEPTH", "depth below the current Z")
        .optional("STEPDOWN", "depth of cut per level (default: the tool's diameter)")
        .optional("RAMP", "steepest entry into each level, in degrees (default 3)")
        .optional("STEPOVER", "greatest distance between rings (default: 60% of the tool's diameter)")
        .optional("CORNER", "radius of the pocket's corners (default 0)")
        .optional("ALLOWANCE", "what the rings leave on the walls for the finishing ring (default 0)")
        .optional("ENTRY", "\"ramp\" along the innermost ring (the default) or \"helix\" in the middle")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let length = args.positive(0)?;
        let width = args.positive(1)?;
        let depth = args.positive(2)?;
        let tool = state.require_cutter("a pocket needs an end mill")?;
        let d = tool.diameter;
        let stepdown = args.optional_positive(3)?.unwrap_or(d);
        let ramp = args.optional_positive(4)?.unwrap_or(entry::DEFAULT_ENTRY_ANGLE);
        let stepover = args.optional_positive(5)?.unwrap_or(DEFAULT_STEPOVER * d);
        let corner = args.optional_non_negative(6)?.unwrap_or(0.0);
        let allowance = args.optional_non_negative(7)?.unwrap_or(0.0);
        let helix = args.choice(8, &["ramp", "helix"])? == 1;
        if stepover > MAX_STEPOVER * d {
            return Err(format!(
                "STEPOVER {stepover} would leave ribs between the rings: at most {} with this tool (T{}, diameter {d})",
                MAX_STEPOVER * d,
                tool.number
            ));
        }
        if allowance > stepover {
            return Err(format!(
                "ALLOWANCE {allowance} is more than the stepover ({stepover}): the finishing ring would leave a rib"
            ));
        }
        if 2.0 * corner > length.min(width) {
            return Err(format!("CORNER {corner} is more than half the pocket's narrower side"));
        }
        if d + 2.0 * allowance > length.min(width) {
            let allowing = if allowance > 0.0 { format!(" with {allowance} allowance a side") } else { String::new() };
            return Err(format!(
                "the tool (T{}, diameter {d}) is wider than the pocket ({length} x {width}){allowing}",
                tool.number
            ));
        }
        if corner > 0.0 && corner < d / 2.0 {
            warn(&format!("corners of radius {corner} are cut to the tool's radius, {} (T{})", d / 2.0, tool.number));
        }
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling Pocket")?;
        let cut = Cut { diameter: d, stepdown, ramp, stepover, corner, allowance, helix, feed };
        plan(state.position, [length, width, depth], &cut).map(|moves| state.in_absolute(moves))
    }
}

/// The most laps a ramp or turns a helix may take to reach a level.
const MAX_LAPS: f64 = 100.0;

fn too_tight(entry: &str, cut: &Cut) -> String {
    format!(
        "the pocket is too tight to {entry} down into at {}° in under {MAX_LAPS} turns with a tool of diameter {}: \
         use a smaller tool, a steeper entry or a drilled start",
        cut.ramp, cut.diameter
    )
}

/// How the pocket is cut; lengths in program units, the ramp in degrees.
pub struct Cut {
    pub diameter: f64,
    pub stepdown: f64,
    pub ramp: f64,
    pub stepover: f64,
    pub corner: f64,
    pub allowance: f64,
    /// A helix in the middle instead of a ramp along the innermost ring.
    pub helix: bool,
    pub feed: f64,
}

/// The tool's path round the pocket at `inset` from its walls: a rounded
/// rectangle, counter-clockwise from the left end of its bottom side.
fn ring(low: [f64; 2], high: [f64; 2], corner: f64, inset: f64) -> Contour {
    let radius = (corner - inset).max(0.0);
    let centres = |corner: [f64; 2], towards: f64| corner.map(|c| c + towards * (inset + radius));
    Contour::rounded_rectangle(centres(low, 1.0), centres(high, -1.0), radius, false)
}

/// The tool path; `corner` the pocket's lower-left top corner.
pub fn plan(corner: [f64; 3], size: [f64; 3], cut: &Cut) -> Result<Vec<Statement>, String> {
    let [x0, y0, top] = corner;
    let [length, width, depth] = size;
    let (low, high) = ([x0, y0], [x0 + length, y0 + width]);
    let r = cut.diameter / 2.0;
    // Insets from the walls: the finishing ring's, the outermost and the
    // innermost rough ones (the middle is `half` from the nearer walls).
    let half = length.min(width) / 2.0;
    let (finish, outermost) = (r, r + cut.allowance);
    let innermost = (half - INNERMOST * r).max(outermost).min(half - 1e-6);
    let spacing = innermost - outermost;
    let steps = (spacing / cut.stepover).ceil() as u32;
    let insets: Vec<f64> = (0..=steps)
        .map(|k| if steps == 0 { innermost } else { innermost - spacing * f64::from(k) / f64::from(steps) })
        .collect();
    let rings: Vec<Contour> = insets.iter().map(|&inset| ring(low, high, cut.corner, inset)).collect();
    let finishing = (cut.allowance > 0.0).then(|| Finishing::new(ring(low, high, cut.corner, finish), length, cut));
    let middle = [x0 + length / 2.0, y0 + width / 2.0];
    let helix_radius = half - innermost;
    let helix_start = [middle[0] + helix_radius.min(r), middle[1]];

    let levels = entry::levels(top, depth, cut.stepdown);
    let mut out = vec![comment(format!(
        "Pocket {length} x {width} x {depth}: {} levels of {} rings, tool diameter {}",
        levels.len(),
        rings.len() + usize::from(finishing.is_some()),
        cut.diameter
    ))];
    let first = rings[0].start();
    let entry_point = if cut.helix { helix_start } else { first };
    out.push(g0().xy(entry_point[0], entry_point[1]).into());
    out.push(g1().f(cut.feed).into());
    let mut above = top;
    for (level, &z) in levels.iter().enumerate() {
        // After a level, from the last ring's start across what it cleared.
        if level > 0 {
            out.push(g1().xy(entry_point[0], entry_point[1]).into());
        }
        if cut.helix {
            let turn = std::f64::consts::TAU * (helix_start[0] - middle[0]);
            if above - z > MAX_LAPS * turn * cut.ramp.to_radians().tan() {
                return Err(too_tight("helix", cut));
            }
            out.extend(entry::helix(middle, helix_start, above, z, cut.ramp, false, cut.feed)?);
            out.push(g1().xy(first[0], first[1]).into());
        } else {
            let lap = rings[0].length();
            let descent = Heights::descent(0.0, above, z, cut.ramp)?;
            if descent.ends_at() > MAX_LAPS * lap {
                return Err(too_tight("ramp", cut));
            }
            let down = (descent.ends_at() / lap).ceil().max(1.0) * lap;
            out.extend(rings[0].follow(0.0, down, &descent)?);
        }
        // Every ring a whole lap at the level, each reached straight from the
        // last one's start, through what that one cleared.
        for (k, ring) in rings.iter().enumerate() {
            // The entry leaves the tool on the innermost ring's start.
            if k > 0 {
                let [x, y] = ring.start();
                out.push(g1().xy(x, y).into());
            }
            out.extend(ring.follow(0.0, ring.length(), &Heights::level(z))?);
        }
        if let Some(finishing) = &finishing {
            out.extend(finishing.at_level(z)?);
        }
        above = z;
    }
    out.push(g0().z(top).into());
    out.push(g0().xy(x0, y0).into());
    Ok(out)
}

/// The ring that cuts the walls exactly, after the rough ones left the
/// allowance on them.
struct Finishing {
    ring: Contour,
    /// Where the leads join it: the middle of its bottom side.
    joined_at: f64,
    /// The leads' radius; `None` where the bottom side has no room for
    /// them, and the ring is reached straight from the outermost rough one.
    lead: Option<f64>,
    allowance: f64,
}

impl Finishing {
    fn new(ring: Contour, length: f64, cut: &Cut) -> Finishing {
        let (r, a) = (cut.diameter / 2.0, cut.allowance);
        // The leads start and end on the outermost rough ring's bottom side, `a`
        // in from the finishing one: an arc of radius R that starts `a` from
        // its tangent runs sqrt(2Ra - a²) along it, which must stay on that
        // straight side (from the middle, `room` either way).
        let room = length / 2.0 - cut.corner.max(r + a);
        let lead = (room >= a).then(|| r.max(a).min((room * room + a * a) / (2.0 * a)));
        let joined_at = length / 2.0 - cut.corner.max(r);
        Finishing { ring, joined_at, lead, allowance: a }
    }

    /// The finishing ring at `z`, from the outermost rough ring's start
    /// (where its lap ended) and back onto its line.
    fn at_level(&self, z: f64) -> Result<Vec<Statement>, String> {
        let lap = self.ring.length();
        let level = Heights::level(z);
        let Some(radius) = self.lead else {
            let [x, y] = self.ring.start();
            let mut out = vec![g1().xy(x, y).into()];
            out.extend(self.ring.follow(0.0, lap, &level)?);
            return Ok(out);
        };
        let at = self.joined_at;
        let (start, lead_in) = self.ring.lead_in(at, radius, self.allowance, Side::Left)?;
        let (lead_out, _) = self.ring.lead_out(at + lap, radius, self.allowance, Side::Left)?;
        let mut out = vec![g1().xy(start[0], start[1]).into(), lead_in];
        out.extend(self.ring.follow(at, at + lap, &level)?);
        out.push(lead_out);
        Ok(out)
    }
}

export_wizard!(Pocket);
