//! `ThreadMill DIAMETER PITCH DEPTH [SIDE] [PASSES]`: mills a thread on a
//! helix, in a hole already bored (`"inside"`, the default) or round a boss
//! already turned (`"outside"`), centred on the current XY, from DEPTH below
//! the current Z up to it.
//!
//! DIAMETER is the thread's major diameter inside, its major diameter
//! outside; the tool is a single-form thread mill whose diameter is the
//! tool's. The tool goes down where it cuts nothing (the hole's axis, or
//! clear of the boss), arcs in to the thread, climbs one PITCH a turn to the
//! top, and arcs out; PASSES (default 1) cut to the full thread depth in
//! equal radial steps. Inside it turns counter-clockwise going up and
//! outside clockwise, a right-hand thread climb-milled with M03. The thread
//! depth is ISO's for 60° threads: 5/8 of the fundamental triangle's height
//! (0.541 P) inside, 17/24 of it (0.613 P) outside.

use ger_wizard_sdk::*;

/// A 60° thread's fundamental triangle is this many pitches high.
const TRIANGLE: f64 = 0.866_025_403_784_438_6;
/// More turns than a thread mill makes in one hole: a mistyped pitch is an error.
const MOST_TURNS: f64 = 10_000.0;

struct ThreadMill;

impl Wizard for ThreadMill {
    fn describe() -> Description {
        Description::new(
            "ThreadMill",
            "mills a right-hand 60-degree thread on a helix round the current position",
            "ThreadMill DIAMETER PITCH DEPTH [SIDE] [PASSES]",
        )
        .param("DIAMETER", "the thread's major diameter")
        .param("PITCH", "rise of the thread per turn")
        .param("DEPTH", "length of the thread below the current Z")
        .optional("SIDE", "\"inside\" (default: a tapped hole) or \"outside\" (a bolt)")
        .optional("PASSES", "radial passes to the full thread depth (default 1)")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let diameter = args.positive(0)?;
        let pitch = args.positive(1)?;
        let depth = args.positive(2)?;
        let inside = args.choice(3, &["inside", "outside"])? == 0;
        let passes = if args.get(4).is_some() { args.whole(4, 1)? } else { 1 };
        if depth / pitch > MOST_TURNS {
            return Err(format!("{depth} / {pitch} is more than {MOST_TURNS} turns"));
        }
        let tool = state.require_cutter("threads need a thread mill")?;
        let r = tool.diameter / 2.0;
        let thread_depth = pitch * TRIANGLE * if inside { 5.0 / 8.0 } else { 17.0 / 24.0 };
        // The tool centre's radius at the full thread depth.
        let last = if inside { diameter / 2.0 - r } else { diameter / 2.0 - thread_depth + r };
        let first = if inside { last - thread_depth } else { last + thread_depth };
        // Inside, the tool must fit the bore (the minor diameter) with room to arc in.
        if inside && first <= 0.0 {
            return Err(format!(
                "the tool (T{}, diameter {}) is too big for an M{diameter} x {pitch} thread: \
                 the bore is {:.4} across, the cutter must be smaller",
                tool.number,
                tool.diameter,
                diameter - 2.0 * thread_depth
            ));
        }
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling ThreadMill")?;
        let [cx, cy, top] = state.position;
        let bottom = top - depth;
        let mut out = vec![comment(format!(
            "ThreadMill {} M{diameter} x {pitch}, {depth} long: {passes} passes, thread depth {thread_depth:.4}",
            if inside { "inside" } else { "outside" }
        ))];
        // Where the tool goes down: the axis inside, clear of the boss outside.
        let clear = if inside { 0.0 } else { first + tool.diameter };
        // Whole turns from the bottom, one pitch each, the last ending at or above the top.
        let turns = (depth / pitch).ceil() as u32;
        for pass in 1..=passes {
            let radius = first + (last - first) * f64::from(pass) / f64::from(passes);
            out.push(g0().xy(cx + clear, cy).into());
            out.push(g1().z(bottom).f(feed).into());
            // In along a half circle to the thread, tangent to the helix, and
            // out the same way: both counter-clockwise, as the helix's
            // direction where they meet it is inside (going up CCW) and outside (CW).
            let middle = (radius + clear) / 2.0;
            out.push(g3().xy(cx + radius, cy).i(middle - clear).j(0.0).into());
            for n in 1..=turns {
                let helix = if inside { g3() } else { g2() };
                out.push(helix.xy(cx + radius, cy).z(bottom + pitch * f64::from(n)).i(-radius).j(0.0).into());
            }
            out.push(g3().xy(cx + clear, cy).i(middle - radius).j(0.0).into());
        }
        out.push(g0().xy(cx, cy).into());
        out.push(g0().z(top).into());
        Ok(state.in_absolute(out))
    }
}

export_wizard!(ThreadMill);
