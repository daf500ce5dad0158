//! `Drill DEPTH [PECK] [BREAK]`: a hole at the current position, DEPTH below
//! the current Z: the GER way to write G81 (no PECK), G83 (PECK: pecks with
//! a full retract) or G73 (PECK and BREAK: pecks that back off BREAK to
//! break the chip). The tool ends where it was.

use ger_wizard_sdk::holes::{Hole, Pecking};
use ger_wizard_sdk::*;

struct Drill;

impl Wizard for Drill {
    fn describe() -> Description {
        Description::new(
            "Drill",
            "drills a hole at the current position, plain or pecking",
            "Drill DEPTH [PECK] [BREAK]",
        )
        .param("DEPTH", "depth below the current Z")
        .optional("PECK", "depth of each peck, with a full retract after it (default: no pecks)")
        .optional("BREAK", "with PECK: back off this far after each peck instead of retracting")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let depth = args.positive(0)?;
        let pecking = Pecking::from_args(args, 1)?;
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling Drill")?;
        let [x, y, top] = state.position;
        let hole = Hole::new(top, top - depth, feed, pecking)?;
        let mut out = Vec::new();
        out.extend(hole.at(x, y));
        Ok(state.in_absolute(out))
    }
}

export_wizard!(Drill);
