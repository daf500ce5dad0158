//! Getting a cutter down into material without plunging it: a ramp back and
//! forth along a line, or a helix. An endmill's centre does not cut well (a
//! flat one not at all), so CAM systems enter at a shallow angle; these give
//! every wizard the same entries, and `ger check` passes them.

use crate::block::{g1, g2, g3, Statement};

/// How steep an entry goes, in degrees from the horizontal, when the caller
/// has no better figure: a usual CAM default for endmills.
pub const DEFAULT_ENTRY_ANGLE: f64 = 3.0;

pub(crate) fn slope(angle_degrees: f64) -> Result<f64, String> {
    if !(angle_degrees > 0.0 && angle_degrees < 90.0) {
        return Err(format!("an entry angle must be above 0 and below 90 degrees, not {angle_degrees}"));
    }
    Ok(angle_degrees.to_radians().tan())
}

/// The depths of equal passes from `from` down to `to`, each at most `most`
/// deep (at least one pass), the last exactly at `to`.
pub fn equal_passes(from: f64, to: f64, most: f64) -> impl Iterator<Item = f64> {
    let count = ((from - to) / most).ceil().max(1.0) as u32;
    (1..=count).map(move |n| if n == count { to } else { from - (from - to) * f64::from(n) / f64::from(count) })
}

/// The levels a cut goes down to from `top`: `stepdown` apart, the last
/// exactly at `depth` below `top` (at least one).
pub fn levels(top: f64, depth: f64, stepdown: f64) -> Vec<f64> {
    let count = (depth / stepdown).ceil().max(1.0) as u32;
    (1..=count).map(|n| if n == count { top - depth } else { top - f64::from(n) * stepdown }).collect()
}

/// A ramp from `a` at `from_z` (where the tool is) down to `to_z`, back and
/// forth along the line from `a` to `b`, no steeper than `angle_degrees`;
/// then a level pass along the line at `to_z` to cut the wedge the last
/// ramp left, ending at `a`. All moves at `feed`, absolute coordinates.
pub fn ramp(
    a: [f64; 2],
    b: [f64; 2],
    from_z: f64,
    to_z: f64,
    angle_degrees: f64,
    feed: f64,
) -> Result<Vec<Statement>, String> {
    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
    let slope = slope(angle_degrees)?;
    if !length.is_finite() || length <= 0.0 {
        return Err("a ramp needs a line of some length to run along".to_string());
    }
    if from_z < to_z {
        return Err(format!("a ramp goes down: Z{to_z} is above Z{from_z}"));
    }
    let mut out = Vec::new();
    let mut at_a = true;
    for (pass, z) in equal_passes(from_z, to_z, length * slope).enumerate() {
        let [x, y] = if at_a { b } else { a };
        let block = g1().xy(x, y).z(z);
        out.push(if pass == 0 { block.f(feed) } else { block }.into());
        at_a = !at_a;
    }
    // Level at the bottom, over the wedge the last ramp left, ending at `a`.
    if at_a {
        out.push(g1().xy(b[0], b[1]).into());
    }
    out.push(g1().xy(a[0], a[1]).into());
    Ok(out)
}

/// A helix down from `start` at `from_z` (where the tool is) to `to_z`
/// around `centre`, no steeper than `angle_degrees` along its path, in
/// whole turns (`clockwise` or not), then one level turn at `to_z`; it ends
/// back at `start`. All moves at `feed`, absolute coordinates.
pub fn helix(
    centre: [f64; 2],
    start: [f64; 2],
    from_z: f64,
    to_z: f64,
    angle_degrees: f64,
    clockwise: bool,
    feed: f64,
) -> Result<Vec<Statement>, String> {
    let slope = slope(angle_degrees)?;
    let (i, j) = (centre[0] - start[0], centre[1] - start[1]);
    let radius = i.hypot(j);
    if !radius.is_finite() || radius <= 0.0 {
        return Err("a helix needs a radius: its start is on its centre".to_string());
    }
    if from_z < to_z {
        return Err(format!("a helix goes down: Z{to_z} is above Z{from_z}"));
    }
    let turn = 2.0 * std::f64::consts::PI * radius;
    let arc = || if clockwise { g2() } else { g3() };
    let mut out = Vec::new();
    for (pass, z) in equal_passes(from_z, to_z, turn * slope).enumerate() {
        let block = arc().xy(start[0], start[1]).z(z).i(i).j(j);
        out.push(if pass == 0 { block.f(feed) } else { block }.into());
    }
    out.push(arc().xy(start[0], start[1]).i(i).j(j).into());
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::block::Block;

    fn words(statement: &Statement) -> &Block {
        match statement {
            Statement::Block(block) => block,
            other => panic!("not a block: {other:?}"),
        }
    }

    fn word(block: &Block, letter: char) -> Option<f64> {
        block.words.iter().find(|(l, _)| *l == letter).map(|(_, v)| *v)
    }

    #[test]
    fn a_ramp_is_never_steeper_than_asked_and_ends_level_at_its_start() {
        // 20 mm along X, 5 degrees: at most 20 tan 5° = 1.7498 mm a pass, so 6 mm is 4 passes of 1.5.
        let out = ramp([0.0, 0.0], [20.0, 0.0], 0.0, -6.0, 5.0, 300.0).unwrap();
        let ends: Vec<(f64, f64)> =
            out.iter().map(|s| (word(words(s), 'X').unwrap(), word(words(s), 'Z').unwrap_or(-6.0))).collect();
        assert_eq!(ends, [(20.0, -1.5), (0.0, -3.0), (20.0, -4.5), (0.0, -6.0), (20.0, -6.0), (0.0, -6.0)]);
        assert_eq!(word(words(&out[0]), 'F'), Some(300.0));
        assert!(out[1..].iter().all(|s| word(words(s), 'F').is_none()));
        let out = ramp([0.0, 0.0], [0.0, 10.0], 1.0, -1.0, 6.0, 100.0).unwrap();
        let ys: Vec<f64> = out.iter().map(|s| word(words(s), 'Y').unwrap()).collect();
        // 10 tan 6° = 1.051 a pass: 2 mm is 2 passes, ending at `a`; then to `b` and back.
        assert_eq!(ys, [10.0, 0.0, 10.0, 0.0]);
    }

    #[test]
    fn a_helix_is_whole_turns_no_steeper_than_asked_then_a_level_one() {
        // Radius 2: a turn is 4π = 12.566 mm, at 3° it drops at most 0.6586 mm: 2 mm is 4 turns of 0.5.
        let out = helix([0.0, 0.0], [2.0, 0.0], 0.0, -2.0, 3.0, false, 200.0).unwrap();
        assert_eq!(out.len(), 5);
        for (n, statement) in out.iter().enumerate() {
            let block = words(statement);
            assert_eq!(block.words[0], ('G', 3.0));
            assert_eq!((word(block, 'X'), word(block, 'Y')), (Some(2.0), Some(0.0)));
            assert_eq!((word(block, 'I'), word(block, 'J')), (Some(-2.0), Some(0.0)));
            let z = word(block, 'Z');
            assert_eq!(z, if n < 4 { Some(-0.5 * (n + 1) as f64) } else { None });
        }
    }

    #[test]
    fn entries_that_cannot_be_made_are_errors() {
        assert!(ramp([1.0, 1.0], [1.0, 1.0], 0.0, -1.0, 3.0, 100.0).unwrap_err().contains("length"));
        assert!(ramp([0.0, 0.0], [1.0, 0.0], 0.0, 1.0, 3.0, 100.0).unwrap_err().contains("goes down"));
        assert!(ramp([0.0, 0.0], [1.0, 0.0], 0.0, -1.0, 90.0, 100.0).unwrap_err().contains("angle"));
        assert!(helix([0.0, 0.0], [0.0, 0.0], 0.0, -1.0, 3.0, true, 100.0).unwrap_err().contains("radius"));
    }
}
