//! `BoltCircle COUNT DIAMETER DEPTH [ANGLE] [PECK] [BREAK]`: drills COUNT
//! holes evenly on a circle of DIAMETER around the current position, DEPTH
//! below the current Z.
//!
//! Unlike Pocket, which fills an area from a corner, this places points
//! around a centre: each hole is a rapid over it at the current Z, then
//! drilled as `Drill` does (plain, or PECK and BREAK as G83 and G73). The
//! first hole is at ANGLE degrees (default 0, counter-clockwise from +X).
//! The tool ends over the centre.

use ger_wizard_sdk::holes::{Hole, Pecking};
use ger_wizard_sdk::*;

struct BoltCircle;

impl Wizard for BoltCircle {
    fn describe() -> Description {
        Description::new(
            "BoltCircle",
            "drills holes evenly spaced on a circle around the current position",
            "BoltCircle COUNT DIAMETER DEPTH [ANGLE] [PECK] [BREAK]",
        )
        .param("COUNT", "number of holes")
        .param("DIAMETER", "diameter of the circle through the holes' centres")
        .param("DEPTH", "depth below the current Z")
        .optional("ANGLE", "angle of the first hole in degrees from +X (default 0)")
        .optional("PECK", "depth of each peck, with a full retract after it (default: no pecks)")
        .optional("BREAK", "with PECK: back off this far after each peck instead of retracting")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let count = args.whole(0, 1)?;
        let radius = args.positive(1)? / 2.0;
        let depth = args.positive(2)?;
        let start = args.optional_number(3)?.unwrap_or(0.0);
        let pecking = Pecking::from_args(args, 4)?;
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling BoltCircle")?;
        if count > 10_000 {
            return Err(format!("COUNT (argument 1) of {count} holes is more than a bolt circle needs (10000)"));
        }
        let [cx, cy, top] = state.position;
        let hole = Hole::new(top, top - depth, feed, pecking)?;
        let mut out = vec![comment(format!("BoltCircle: {count} holes on diameter {}", radius * 2.0))];
        for n in 0..count {
            let angle = (start + 360.0 * f64::from(n) / f64::from(count)).to_radians();
            out.extend(hole.at(cx + radius * angle.cos(), cy + radius * angle.sin()));
        }
        out.push(g0().xy(cx, cy).into());
        Ok(state.in_absolute(out))
    }
}

export_wizard!(BoltCircle);
