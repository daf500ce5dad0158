//! `DrillGrid COLUMNS ROWS XSTEP YSTEP DEPTH [PECK] [BREAK]`: a grid of holes,
//! the first at the current position, COLUMNS along X (XSTEP apart) and ROWS
//! along Y (YSTEP apart; either step may be negative), DEPTH below the
//! current Z, each drilled as `Drill` does. Rows are visited back and forth,
//! so no rapid crosses the whole grid. The tool ends over the first hole.

use ger_wizard_sdk::holes::{Hole, Pecking};
use ger_wizard_sdk::*;

/// More holes than any grid needs: a mistyped count is an error, not an hour of output.
const MOST_HOLES: u32 = 100_000;

struct DrillGrid;

impl Wizard for DrillGrid {
    fn describe() -> Description {
        Description::new(
            "DrillGrid",
            "drills a grid of holes from the current position",
            "DrillGrid COLUMNS ROWS XSTEP YSTEP DEPTH [PECK] [BREAK]",
        )
        .param("COLUMNS", "holes along X")
        .param("ROWS", "holes along Y")
        .param("XSTEP", "distance between columns (negative: towards -X)")
        .param("YSTEP", "distance between rows (negative: towards -Y)")
        .param("DEPTH", "depth below the current Z")
        .optional("PECK", "depth of each peck, with a full retract after it (default: no pecks)")
        .optional("BREAK", "with PECK: back off this far after each peck instead of retracting")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let columns = args.whole(0, 1)?;
        let rows = args.whole(1, 1)?;
        let (xstep, ystep) = (args.number(2)?, args.number(3)?);
        let depth = args.positive(4)?;
        let pecking = Pecking::from_args(args, 5)?;
        if u64::from(columns) * u64::from(rows) > u64::from(MOST_HOLES) {
            return Err(format!("{columns} x {rows} holes is more than a grid needs ({MOST_HOLES})"));
        }
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling DrillGrid")?;
        let [x0, y0, top] = state.position;
        let hole = Hole::new(top, top - depth, feed, pecking)?;
        let mut out = vec![comment(format!("DrillGrid: {columns} x {rows} holes, {xstep} x {ystep} apart"))];
        for row in 0..rows {
            for step in 0..columns {
                let column = if row % 2 == 0 { step } else { columns - 1 - step };
                out.extend(hole.at(x0 + xstep * f64::from(column), y0 + ystep * f64::from(row)));
            }
        }
        out.push(g0().xy(x0, y0).into());
        Ok(state.in_absolute(out))
    }
}

export_wizard!(DrillGrid);
