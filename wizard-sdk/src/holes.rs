//! Drilling a hole the way a machinist would write G81, G83 or G73, in
//! moves every controller runs: a plain feed to the bottom, pecks with a
//! full retract to clear the chips, or pecks that only back off to break them.

use crate::block::{g0, g1, Statement};
use crate::entry::equal_passes;
use crate::Args;

/// How a hole is drilled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pecking {
    /// One feed to the bottom (G81).
    None,
    /// Pecks of at most `peck`, each followed by a rapid out of the hole (G83).
    FullRetract { peck: f64 },
    /// Pecks of at most `peck`, each followed by a rapid back of `back` (G73).
    ChipBreak { peck: f64, back: f64 },
}

impl Pecking {
    /// From a wizard's optional PECK and BREAK arguments, at `index` and
    /// `index + 1`: neither is a plain hole, PECK alone pecks with a full
    /// retract, both break chips by backing off BREAK.
    pub fn from_args(args: &Args, index: usize) -> Result<Pecking, String> {
        Ok(match (args.optional_positive(index)?, args.optional_positive(index + 1)?) {
            (None, None) => Pecking::None,
            (Some(peck), None) => Pecking::FullRetract { peck },
            (Some(peck), Some(back)) => Pecking::ChipBreak { peck, back },
            (None, Some(_)) => return Err("BREAK needs a PECK: the depth of each peck it follows".to_string()),
        })
    }
}

/// A hole's depths and feed, in program units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hole {
    /// Where the tool is over the hole, and comes back to: above the material.
    pub clearance: f64,
    /// The bottom of the hole.
    pub bottom: f64,
    pub feed: f64,
    pub pecking: Pecking,
}

/// How far above the last peck's bottom the tool comes back down by rapid
/// after a full retract, so it never rapids into material: LinuxCNC's G83
/// stops 0.010 in short; this is the same in a fraction of the peck.
const REENTRY: f64 = 0.1;

impl Hole {
    /// Checks what the numbers must be: the bottom below the clearance, pecks and backing off above zero.
    pub fn new(clearance: f64, bottom: f64, feed: f64, pecking: Pecking) -> Result<Hole, String> {
        if bottom >= clearance {
            return Err(format!("a hole goes down: its bottom Z{bottom} is not below Z{clearance}"));
        }
        if feed <= 0.0 {
            return Err(format!("a hole needs a feed above zero, not {feed}"));
        }
        match pecking {
            Pecking::FullRetract { peck } | Pecking::ChipBreak { peck, .. } if peck <= 0.0 => {
                return Err(format!("a peck must be above zero, not {peck}"));
            }
            Pecking::ChipBreak { peck, back } if back <= 0.0 || back >= peck => {
                return Err(format!(
                    "backing off to break a chip must be above zero and less than the peck ({peck}), not {back}"
                ));
            }
            _ => {}
        }
        Ok(Hole { clearance, bottom, feed, pecking })
    }

    /// The moves of the hole at `x`, `y` from the clearance, where the tool
    /// must be (as each hole leaves it): a rapid over it, the drilling, a
    /// rapid back to the clearance.
    pub fn at(&self, x: f64, y: f64) -> Vec<Statement> {
        let mut out = vec![g0().xy(x, y).into()];
        let depths = |peck: f64| equal_passes(self.clearance, self.bottom, peck);
        match self.pecking {
            Pecking::None => out.push(g1().z(self.bottom).f(self.feed).into()),
            Pecking::FullRetract { peck } => {
                let mut reached = self.clearance;
                for depth in depths(peck) {
                    if reached < self.clearance {
                        out.push(g0().z(reached + REENTRY * peck).into());
                    }
                    out.push(g1().z(depth).f(self.feed).into());
                    out.push(g0().z(self.clearance).into());
                    reached = depth;
                }
                // The last retract is the hole's own.
                out.pop();
            }
            Pecking::ChipBreak { peck, back } => {
                let mut reached = None;
                for depth in depths(peck) {
                    if let Some(bottom) = reached {
                        out.push(g0().z(bottom + back).into());
                    }
                    out.push(g1().z(depth).f(self.feed).into());
                    reached = Some(depth);
                }
            }
        }
        out.push(g0().z(self.clearance).into());
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (G code, Z) of each move.
    fn zs(out: &[Statement]) -> Vec<(u8, Option<f64>)> {
        out.iter()
            .map(|s| match s {
                Statement::Block(b) => {
                    (b.words[0].1 as u8, b.words.iter().find(|(l, _)| *l == 'Z').map(|(_, v)| (v * 1e6).round() / 1e6))
                }
                other => panic!("{other:?}"),
            })
            .collect()
    }

    #[test]
    fn a_plain_hole_is_one_feed_down() {
        let hole = Hole::new(1.0, -5.0, 100.0, Pecking::None).unwrap();
        assert_eq!(zs(&hole.at(3.0, 4.0)), [(0, None), (1, Some(-5.0)), (0, Some(1.0))]);
    }

    #[test]
    fn full_retract_pecks_clear_the_hole_and_come_back_short_of_the_last_bottom() {
        // 6 deep in pecks of at most 2.5: three of 2; back down by rapid to 0.25 above each bottom.
        let hole = Hole::new(1.0, -5.0, 100.0, Pecking::FullRetract { peck: 2.5 }).unwrap();
        assert_eq!(
            zs(&hole.at(0.0, 0.0)),
            [
                (0, None),
                (1, Some(-1.0)),
                (0, Some(1.0)),
                (0, Some(-0.75)),
                (1, Some(-3.0)),
                (0, Some(1.0)),
                (0, Some(-2.75)),
                (1, Some(-5.0)),
                (0, Some(1.0)),
            ]
        );
    }

    #[test]
    fn chip_breaking_pecks_only_back_off() {
        let hole = Hole::new(0.0, -3.0, 50.0, Pecking::ChipBreak { peck: 1.0, back: 0.2 }).unwrap();
        assert_eq!(
            zs(&hole.at(0.0, 0.0)),
            [
                (0, None),
                (1, Some(-1.0)),
                (0, Some(-0.8)),
                (1, Some(-2.0)),
                (0, Some(-1.8)),
                (1, Some(-3.0)),
                (0, Some(0.0)),
            ]
        );
    }

    #[test]
    fn impossible_holes_are_errors() {
        assert!(Hole::new(0.0, 0.0, 1.0, Pecking::None).unwrap_err().contains("goes down"));
        assert!(Hole::new(0.0, -1.0, 0.0, Pecking::None).unwrap_err().contains("feed"));
        assert!(Hole::new(0.0, -1.0, 1.0, Pecking::FullRetract { peck: 0.0 }).unwrap_err().contains("peck"));
        let err = Hole::new(0.0, -1.0, 1.0, Pecking::ChipBreak { peck: 0.5, back: 0.5 }).unwrap_err();
        assert!(err.contains("less than the peck"), "{err}");
    }
}
