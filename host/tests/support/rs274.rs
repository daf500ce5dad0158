//! ger against LinuxCNC's interpreter, `rs274` (Debian's `linuxcnc-uspace`):
//! running rs274, reading its canonical output and ger's output into the same
//! [`Moves`], and comparing them with [`compare`].
//!
//! Both sides become moves in machine coordinates, in millimetres. rs274
//! prints each canonical call in the program's unit of the moment and
//! relative to the offsets in force, so its offsets, XY rotation, tool length
//! offset and unit changes are followed here as LinuxCNC's canon applies them
//! (machine = rotate(position + G92/G52) + G54..G59.3 origin + tool offset).
//! ger's output is in machine coordinates already, in the unit its preamble
//! names.
//!
//! rs274 tells which block a call came from only by the block's N word, so it
//! runs a copy of the program with every line numbered `N<line>` (an N word
//! already there is replaced): then every move of either side carries the
//! line of the program that made it. rs274 holds a move back while cutter
//! compensation is on and prints it with the next block's line.
//!
//! What rs274 prints for each construct, and how it is read:
//! - G28/G30: a rapid to the intermediate point, then one to the point in
//!   parameters 5161-5163 / 5181-5183 (written by [`Machine`]; zero by
//!   default), for the axes named (all if none).
//! - G53: a move whose end rs274 prints relative to the offsets in force;
//!   following them gives the machine coordinates back.
//! - G43/G44/G49: `USE_TOOL_LENGTH_OFFSET`, zero with [`Machine`]'s tools.
//! - G92, G52 (`SET_G92_OFFSET`), G54-G59.3 and G10 L2/L20 with R
//!   (`SET_G5X_OFFSET`, `SET_XY_ROTATION`), G20/G21 (`USE_LENGTH_UNITS`).
//! - Canned cycles: plain traverses, feeds and dwells, with zero-length ones.
//! - Splines (G5, G5.1, G5.2/G5.3): `NURBS_FEED(n, ...)`, the count of
//!   control points and nothing else, so only that a spline ran is known; a
//!   G5.2 spline is printed with the line of its G5.3.
//! - O-word subroutines, loops and conditions, `#` parameters: only the moves
//!   that run are printed, each with the line of the block that ran.
//! - Feeds: `SET_FEED_RATE` is in the unit of its moment (a later G20 does
//!   not change the feed in force, as in LinuxCNC's canon); rs274 turns
//!   inverse time (G93) into units per minute itself; feeds per revolution
//!   (G95) and spindle-synchronised moves (G33, G76, tapping) are turned
//!   into mm/min here by the spindle speed.

use std::fmt;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

use super::process::Finished;

/// How far two end points, centres or feeds may be apart, per axis, on top
/// of the rounding of the digits each side prints.
pub const TOLERANCE_MM: f64 = 0.002;

/// Seconds two dwells may differ by.
const DWELL_TOLERANCE: f64 = 0.001;

#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    Rapid,
    Feed,
    /// Centre in machine coordinates (0 along the plane's normal) and turn:
    /// +1 counter-clockwise, -1 clockwise; rs274 counts extra full turns
    /// (±2, ...).
    Arc {
        centre: [f64; 3],
        turn: i32,
    },
    /// A spline of which rs274 prints neither path nor end.
    Spline,
    /// G38 probing (rs274 only).
    Probe,
    /// G33.1 rigid tapping to the end and back (rs274 only).
    Tap,
    /// Seconds.
    Dwell(f64),
    /// +1 clockwise, -1 counter-clockwise, 0 stopped.
    Spindle(i32),
}

#[derive(Clone, Debug)]
pub struct Move {
    pub kind: Kind,
    /// Machine coordinates, mm; none for dwells, spindle changes and splines.
    pub end: Option<[f64; 3]>,
    /// mm/min, for feeds and arcs.
    pub feed: Option<f64>,
    /// Where the move starts, where known: a move that ends there (within the
    /// tolerance) goes nowhere.
    pub start: Option<[f64; 3]>,
    /// The line of the program that made the move, where known.
    pub line: Option<u32>,
    /// What the side printed for it.
    pub text: String,
}

impl fmt::Display for Move {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "line {line} `{}`", self.text),
            None => write!(f, "`{}`", self.text),
        }
    }
}

/// What one side does, in order: every move, dwell and change of the
/// spindle. Spindle commands that change nothing (LinuxCNC stops the spindle
/// at every tool change) are left out, and so is a stop right before a start.
#[derive(Debug, Default)]
pub struct Moves {
    moves: Vec<Move>,
    /// Half the last printed digit of the coarsest number read, in mm.
    resolution: f64,
    /// Where the tool is, once known.
    at: Option<[f64; 3]>,
    spindle: i32,
    /// What the spindle did before it last stopped.
    before_stop: i32,
}

impl Moves {
    /// Both machines start at machine zero, spindle stopped.
    fn starting() -> Moves {
        Moves { at: Some([0.0; 3]), ..Moves::default() }
    }

    pub fn iter(&self) -> std::slice::Iter<'_, Move> {
        self.moves.iter()
    }

    pub fn is_empty(&self) -> bool {
        self.moves.is_empty()
    }

    /// The moves whose line `keep` accepts, after the first `skip` of them.
    pub fn select(self, keep: impl Fn(u32) -> bool, skip: usize) -> Moves {
        let moves = self.moves.into_iter().filter(|m| m.line.is_some_and(&keep)).skip(skip).collect();
        Moves { moves, ..self }
    }

    fn push(&mut self, mut m: Move) {
        match m.kind {
            Kind::Spindle(turn) => {
                // A stop with nothing between it and a start is part of the
                // start (LinuxCNC's G84 stops the spindle before reversing it).
                if turn != 0 && self.moves.last().is_some_and(|last| last.kind == Kind::Spindle(0)) {
                    self.moves.pop();
                    self.spindle = self.before_stop;
                }
                if turn == self.spindle {
                    return;
                }
                if turn == 0 {
                    self.before_stop = self.spindle;
                }
                self.spindle = turn;
            }
            // A rigid tap comes back to where it started.
            Kind::Dwell(_) | Kind::Tap => {}
            _ => {
                m.start = self.at;
                self.at = m.end;
            }
        }
        if m.kind == Kind::Rapid {
            m.feed = None;
        }
        self.moves.push(m);
    }

    /// A move; an arc going round more than once (`G02 ... P3`, which rs274
    /// prints as one ARC_FEED of turn -3) as its full turns about its centre
    /// and then the arc to its end, each taking its share of the helix, as
    /// ger writes it.
    fn push_turns(&mut self, m: Move, [a, b, normal]: [usize; 3]) {
        let (Kind::Arc { centre, turn }, Some(start), Some(end)) = (m.kind.clone(), self.at, m.end) else {
            return self.push(m);
        };
        if turn.abs() <= 1 {
            return self.push(m);
        }
        let tau = std::f64::consts::TAU;
        let angle = |p: [f64; 3]| (p[b] - centre[b]).atan2(p[a] - centre[a]);
        let closed = (start[a] - end[a]).hypot(start[b] - end[b]) < 1e-9;
        let sweep = match (closed, turn > 0) {
            (true, _) => tau,
            (false, true) => (angle(end) - angle(start)).rem_euclid(tau),
            (false, false) => (angle(start) - angle(end)).rem_euclid(tau),
        };
        let extra = turn.abs() - 1;
        let whole = sweep + tau * f64::from(extra);
        for k in 1..=extra {
            let mut through = start;
            through[normal] = start[normal] + (end[normal] - start[normal]) * tau * f64::from(k) / whole;
            let kind = Kind::Arc { centre, turn: turn.signum() };
            self.push(Move { kind, end: Some(through), ..m.clone() });
        }
        self.push(Move { kind: Kind::Arc { centre, turn: turn.signum() }, ..m });
    }

    /// Notes that a number was printed with `decimals` decimals, in a unit
    /// of `mm_per_unit` mm.
    fn printed(&mut self, decimals: usize, mm_per_unit: f64) {
        self.resolution = self.resolution.max(0.5 * 10f64.powi(-(decimals as i32)) * mm_per_unit);
    }

    /// Reads ger's output (`ger run`, with line numbers) as a controller runs
    /// it: axis words move the tool in the motion mode in force, whatever
    /// the code on the line (so `G43 Z5 H1` after a `G01` is a feed), and a
    /// tool change or the end stops the spindle, as LinuxCNC's do.
    pub fn from_ger(output: &str) -> Moves {
        let mut moves = Moves::starting();
        let mut mm_per_unit = 1.0;
        let mut position = [0.0; 3];
        let mut plane = Plane::XY;
        let mut mode = 0;
        let mut feed = None;
        for text in output.lines() {
            match text {
                "G20" => mm_per_unit = 25.4,
                "G21" => mm_per_unit = 1.0,
                _ => {}
            }
            if text.starts_with('(') {
                continue;
            }
            let mut words = Vec::new();
            for word in text.split_whitespace() {
                let (letter, number) = word.split_at(1);
                let value = number.parse::<f64>().unwrap_or_else(|_| panic!("ger wrote `{word}` in `{text}`"));
                let decimals = number.split_once('.').map_or(0, |(_, d)| d.len());
                words.push((letter.chars().next().unwrap(), value, decimals));
            }
            let word = |letter: char| words.iter().find(|w| w.0 == letter).map(|w| w.1);
            // The rest of the preamble (G90, G17) has no line.
            let Some(line) = word('N') else { continue };
            // G10 L1 writes the tool table: its X Y Z are offsets, not a move.
            if words.iter().any(|&(letter, code, _)| letter == 'G' && code == 10.0) {
                continue;
            }
            let line = Some(line as u32);
            for &(letter, _, decimals) in &words {
                if "XYZIJKF".contains(letter) {
                    moves.printed(decimals, mm_per_unit);
                }
            }
            if let Some(f) = word('F') {
                feed = Some(f * mm_per_unit);
            }
            let event = |kind: Kind| Move { kind, end: None, feed: None, start: None, line, text: text.to_string() };
            for &(letter, code, _) in &words {
                match (letter, code) {
                    ('G', g) if [0.0, 1.0, 2.0, 3.0].contains(&g) => mode = g as u32,
                    ('G', 4.0) => moves.push(event(Kind::Dwell(word('P').unwrap_or(0.0)))),
                    ('G', 17.0) => plane = Plane::XY,
                    ('G', 18.0) => plane = Plane::ZX,
                    ('G', 19.0) => plane = Plane::YZ,
                    ('M', 3.0) => moves.push(event(Kind::Spindle(1))),
                    ('M', 4.0) => moves.push(event(Kind::Spindle(-1))),
                    ('M', 5.0 | 6.0 | 30.0) => moves.push(event(Kind::Spindle(0))),
                    _ => {}
                }
            }
            if !words.iter().any(|w| "XYZ".contains(w.0)) {
                continue;
            }
            let start = position;
            for (axis, letter) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                if let Some(v) = word(letter) {
                    position[axis] = v * mm_per_unit;
                }
            }
            let kind = match mode {
                0 => Kind::Rapid,
                1 => Kind::Feed,
                turn => {
                    let [a, b, normal] = plane.axes();
                    let offsets = [word('I'), word('J'), word('K')];
                    let mut centre = start;
                    for axis in [a, b] {
                        centre[axis] += offsets[axis].unwrap_or(0.0) * mm_per_unit;
                    }
                    centre[normal] = 0.0;
                    Kind::Arc { centre, turn: if turn == 2 { -1 } else { 1 } }
                }
            };
            moves.push(Move { kind, end: Some(position), feed, start: None, line, text: text.to_string() });
        }
        moves
    }

    /// Reads what `rs274 -g` printed for a program (see the module's notes).
    pub fn from_rs274(canon: &str) -> Moves {
        let mut moves = Moves::starting();
        let mut mm_per_unit = 1.0;
        // In mm, as LinuxCNC's canon keeps them.
        let (mut g5x, mut g92, mut tool) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        let mut rotation: f64 = 0.0;
        let mut plane = Plane::XY;
        // mm/min, or mm a turn in G95: in the unit in force when it was set.
        let mut feed = None;
        let mut per_revolution = false;
        let mut synchronised = None;
        let mut speed = 0.0;
        for text in canon.lines() {
            let Some((line, call)) = canonical(text) else { continue };
            let (name, args) = call.split_once('(').unwrap_or((call, ")"));
            let args: Vec<&str> = args.trim_end_matches(')').split(',').map(str::trim).collect();
            // Arguments that are not numbers (`...`, names) read as NaN and are not used.
            let number = |i: usize| args.get(i).and_then(|a| a.parse::<f64>().ok()).unwrap_or(f64::NAN);
            let triple = |first: usize| [number(first), number(first + 1), number(first + 2)].map(|v| v * mm_per_unit);
            let to_machine = |p: [f64; 3]| -> [f64; 3] {
                let [x, y, z] = [p[0] * mm_per_unit + g92[0], p[1] * mm_per_unit + g92[1], p[2] * mm_per_unit + g92[2]];
                let (sin, cos) = rotation.to_radians().sin_cos();
                [x * cos - y * sin + g5x[0] + tool[0], x * sin + y * cos + g5x[1] + tool[1], z + g5x[2] + tool[2]]
            };
            let event = |kind: Kind, end: Option<[f64; 3]>| Move {
                kind,
                end,
                feed: None,
                start: None,
                line,
                text: call.to_string(),
            };
            match name {
                "USE_LENGTH_UNITS" => mm_per_unit = if args[0] == "CANON_UNITS_INCHES" { 25.4 } else { 1.0 },
                "SET_G5X_OFFSET" => g5x = [number(1), number(2), number(3)].map(|v| v * mm_per_unit),
                "SET_G92_OFFSET" => g92 = triple(0),
                "SET_XY_ROTATION" => rotation = number(0),
                "USE_TOOL_LENGTH_OFFSET" => {
                    let offset: Vec<f64> = args[0].split_whitespace().filter_map(|v| v.parse().ok()).collect();
                    tool = [offset[0], offset[1], offset[2]].map(|v| v * mm_per_unit);
                }
                "SELECT_PLANE" => {
                    plane = match args[0] {
                        "CANON_PLANE_XY" => Plane::XY,
                        "CANON_PLANE_XZ" => Plane::ZX,
                        _ => Plane::YZ,
                    }
                }
                // SET_FEED_MODE(spindle, 1) is G95; rs274 turns G93's inverse time into units per minute itself.
                "SET_FEED_MODE" => per_revolution = number(1) == 1.0,
                "SET_FEED_RATE" => feed = Some(number(0) * mm_per_unit),
                "SET_SPINDLE_SPEED" => speed = number(1),
                // START_SPEED_FEED_SYNC(pitch, velocity mode): G33, G76 and tapping move by the spindle's turns.
                "START_SPEED_FEED_SYNC" => synchronised = Some(number(0) * mm_per_unit),
                "STOP_SPEED_FEED_SYNCH" => synchronised = None,
                "DWELL" => moves.push(event(Kind::Dwell(number(0)), None)),
                "START_SPINDLE_CLOCKWISE" => moves.push(event(Kind::Spindle(1), None)),
                "START_SPINDLE_COUNTERCLOCKWISE" => moves.push(event(Kind::Spindle(-1), None)),
                "STOP_SPINDLE_TURNING" => moves.push(event(Kind::Spindle(0), None)),
                name if name.starts_with("NURBS") => {
                    let spline = Move { feed, ..event(Kind::Spline, None) };
                    moves.push(spline);
                }
                // What follows the end (a spindle stop, resets) is LinuxCNC's, not the program's.
                "PROGRAM_END" => break,
                "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" | "STRAIGHT_PROBE" | "RIGID_TAP" | "ARC_FEED" => {
                    for arg in &args {
                        if let Some((_, decimals)) = arg.split_once('.') {
                            moves.printed(decimals.len(), mm_per_unit);
                        }
                    }
                    let (kind, end) = match name {
                        "ARC_FEED" => {
                            let [a, b, normal] = plane.axes();
                            let (mut end, mut centre) = ([0.0; 3], [0.0; 3]);
                            (end[a], end[b], end[normal]) = (number(0), number(1), number(5));
                            (centre[a], centre[b]) = (number(2), number(3));
                            let mut centre = to_machine(centre);
                            // The plane's normal of a centre is no point: rotation and offsets moved it.
                            centre[normal] = 0.0;
                            (Kind::Arc { centre, turn: number(4) as i32 }, to_machine(end))
                        }
                        "STRAIGHT_TRAVERSE" => (Kind::Rapid, to_machine([number(0), number(1), number(2)])),
                        "STRAIGHT_FEED" => (Kind::Feed, to_machine([number(0), number(1), number(2)])),
                        "STRAIGHT_PROBE" => (Kind::Probe, to_machine([number(0), number(1), number(2)])),
                        _ => (Kind::Tap, to_machine([number(0), number(1), number(2)])),
                    };
                    let rate = match synchronised {
                        Some(pitch) => Some(pitch * speed),
                        None if per_revolution => feed.map(|f| f * speed),
                        None => feed,
                    };
                    let m = Move { kind, end: Some(end), feed: rate, start: None, line, text: call.to_string() };
                    moves.push_turns(m, plane.axes());
                }
                _ => {}
            }
        }
        moves
    }
}

/// The line number and call of one line of rs274's output,
/// `   12 N34    STRAIGHT_FEED(...)` (`N.....` for a block without N).
fn canonical(text: &str) -> Option<(Option<u32>, &str)> {
    let rest = text.trim_start();
    let counted = rest.split_once(' ')?;
    counted.0.parse::<u64>().ok()?;
    let rest = counted.1.trim_start().strip_prefix('N')?;
    if let Some(call) = rest.strip_prefix(".....") {
        return Some((None, call.trim()));
    }
    let digits = rest.find(|c: char| !c.is_ascii_digit()).unwrap_or(rest.len());
    Some((rest[..digits].parse().ok(), rest[digits..].trim()))
}

#[derive(Clone, Copy)]
enum Plane {
    XY,
    ZX,
    YZ,
}

impl Plane {
    /// The plane's first and second axes and its normal, as both programs order them.
    fn axes(self) -> [usize; 3] {
        match self {
            Plane::XY => [0, 1, 2],
            Plane::ZX => [2, 0, 1],
            Plane::YZ => [1, 2, 0],
        }
    }
}

/// How two sequences of moves agree.
#[derive(Debug)]
pub struct Agreement {
    /// Moves compared (a spline counts once).
    pub moves: usize,
    /// The largest difference of two coordinates, in mm.
    pub largest_difference: f64,
}

/// The first place where ger and rs274 part.
#[derive(Debug)]
pub struct Disagreement {
    /// What differs.
    pub what: String,
    /// Index (from 1) and move of each side there; none where a side has no more moves.
    pub ger: (usize, Option<Move>),
    pub peer: (usize, Option<Move>),
}

impl fmt::Display for Disagreement {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let side = |(index, m): &(usize, Option<Move>)| match m {
            Some(m) => format!("move {index}, {m}"),
            None => format!("no move {index}"),
        };
        write!(f, "{}: ger {}; rs274 {}", self.what, side(&self.ger), side(&self.peer))
    }
}

/// Compares ger's moves with rs274's one by one: the same kind (a rapid is
/// not a feed), end points, arc centres within `tolerance` (on top of the
/// rounding of the digits each side printed), the same turn, the same feed,
/// the same dwells and spindle changes. A straight move that goes nowhere
/// (within the same tolerance), or a dwell of no time, on one side is passed
/// over where the other side has no such move. A spline of rs274's stands for the feeds and arcs
/// ger made for it: those after the previous move up to the spline's line.
/// How far `at` is from the XY spiral LinuxCNC runs from `start` to `end`
/// about `centre` (`turn` +1 counter-clockwise, -1 clockwise): its radius
/// and height change evenly with the angle turned.
fn off_spiral(start: [f64; 3], end: [f64; 3], centre: &[f64; 3], turn: i32, at: [f64; 3]) -> f64 {
    use std::f64::consts::TAU;
    let angle = |p: [f64; 3]| (p[1] - centre[1]).atan2(p[0] - centre[0]);
    let radius = |p: [f64; 3]| (p[0] - centre[0]).hypot(p[1] - centre[1]);
    let turned = |p: [f64; 3]| (f64::from(turn) * (angle(p) - angle(start))).rem_euclid(TAU);
    let whole = match turned(end) {
        t if t < 1e-9 => TAU,
        t => t,
    };
    let fraction = (turned(at) / whole).min(1.0);
    let expected = radius(start) + (radius(end) - radius(start)) * fraction;
    let height = start[2] + (end[2] - start[2]) * fraction;
    (radius(at) - expected).abs().hypot(at[2] - height)
}

pub fn compare(ger: &Moves, peer: &Moves, tolerance: f64) -> Result<Agreement, Box<Disagreement>> {
    let slack = tolerance + ger.resolution + peer.resolution;
    let mut largest: f64 = 0.0;
    let (mut i, mut j) = (0, 0);
    let mut previous_line = None;
    let part = |i: usize, j: usize, what: String| {
        Box::new(Disagreement {
            what,
            ger: (i + 1, ger.moves.get(i).cloned()),
            peer: (j + 1, peer.moves.get(j).cloned()),
        })
    };
    let mut compared = 0;
    loop {
        let (g, p) = match (ger.moves.get(i), peer.moves.get(j)) {
            (None, None) => return Ok(Agreement { moves: compared, largest_difference: largest }),
            (Some(g), None) if goes_nowhere(g, slack) => {
                i += 1;
                continue;
            }
            (None, Some(p)) if goes_nowhere(p, slack) => {
                j += 1;
                continue;
            }
            (Some(_), None) => return Err(part(i, j, "ger makes more moves".into())),
            (None, Some(_)) => return Err(part(i, j, "rs274 makes more moves".into())),
            (Some(g), Some(p)) => (g, p),
        };
        if p.kind == Kind::Spline {
            let first = i;
            let spline_line = p.line.unwrap_or(0);
            let within = |line: u32| match previous_line {
                Some(previous) if previous < spline_line => (previous + 1..=spline_line).contains(&line),
                _ => line == spline_line,
            };
            while let Some(g) = ger
                .moves
                .get(i)
                .filter(|g| matches!(g.kind, Kind::Feed | Kind::Arc { .. }) && g.line.is_some_and(within))
            {
                if !close_enough(g.feed, p.feed, slack) {
                    return Err(part(i, j, format!("feeds differ along a spline: {}", feeds(g.feed, p.feed))));
                }
                i += 1;
            }
            if i == first {
                return Err(part(i, j, "rs274 runs a spline where ger does not".into()));
            }
            previous_line = p.line;
            compared += 1;
            j += 1;
            continue;
        }
        if let (Kind::Feed, Kind::Arc { centre, turn }) = (&g.kind, &p.kind) {
            // LinuxCNC's spiral (an arc whose radii differ), which ger writes
            // as straight feeds along it: each of the line's feeds must end
            // on it, the last where it ends.
            if let (Some(start), Some(end), 1) = (p.start, p.end, turn.abs()) {
                let first = i;
                while let Some(g) = ger.moves.get(i).filter(|g| g.kind == Kind::Feed && g.line == p.line) {
                    let at = g.end.expect("a feed has an end");
                    let off = off_spiral(start, end, centre, *turn, at);
                    if off > slack {
                        return Err(part(i, j, format!("a feed ends {off:.4} mm off rs274's spiral")));
                    }
                    if !close_enough(g.feed, p.feed, slack) {
                        return Err(part(i, j, format!("feeds differ along a spiral: {}", feeds(g.feed, p.feed))));
                    }
                    largest = largest.max(off);
                    i += 1;
                }
                let last = ger.moves[i - 1].end.expect("a feed has an end");
                if distance(&last, &end) > slack {
                    return Err(part(i - 1, j, "the feeds along a spiral end elsewhere".into()));
                }
                debug_assert!(i > first);
                previous_line = p.line;
                compared += 1;
                j += 1;
                continue;
            }
        }
        let kinds_match = match (&g.kind, &p.kind) {
            (Kind::Arc { centre: a, turn: s }, Kind::Arc { centre: b, turn: t }) => {
                if s != t {
                    return Err(part(i, j, format!("arcs turn differently ({s} and {t})")));
                }
                let difference = distance(a, b);
                if difference > slack {
                    return Err(part(i, j, format!("arc centres differ by {difference:.4} mm")));
                }
                largest = largest.max(difference);
                true
            }
            (Kind::Dwell(a), Kind::Dwell(b)) => (a - b).abs() <= DWELL_TOLERANCE,
            (a, b) => a == b,
        };
        let ends = match (g.end, p.end) {
            (Some(a), Some(b)) => distance(&a, &b),
            _ => 0.0,
        };
        if !kinds_match || ends > slack {
            // A move that goes nowhere on one side may be missing on the other:
            // LinuxCNC writes some (a canned cycle's retract to where the tool is),
            // and each side rounds the end of a tiny move its own way.
            if goes_nowhere(g, slack) {
                i += 1;
                continue;
            }
            if goes_nowhere(p, slack) {
                j += 1;
                continue;
            }
        }
        if !kinds_match {
            return Err(part(i, j, format!("{} where rs274 has {}", name(&g.kind), name(&p.kind))));
        }
        if ends > slack {
            return Err(part(i, j, format!("end points differ by {ends:.4} mm")));
        }
        largest = largest.max(ends);
        if matches!(g.kind, Kind::Feed | Kind::Arc { .. }) && !close_enough(g.feed, p.feed, slack) {
            return Err(part(i, j, format!("feeds differ: {}", feeds(g.feed, p.feed))));
        }
        previous_line = p.line;
        compared += 1;
        i += 1;
        j += 1;
    }
}

/// A straight move that ends where it starts, within `slack`, or a dwell of
/// no time.
fn goes_nowhere(m: &Move, slack: f64) -> bool {
    match m.kind {
        Kind::Rapid | Kind::Feed => m.start.zip(m.end).is_some_and(|(start, end)| distance(&start, &end) <= slack),
        Kind::Dwell(seconds) => seconds.abs() <= DWELL_TOLERANCE,
        _ => false,
    }
}

fn feeds(ger: Option<f64>, peer: Option<f64>) -> String {
    let show = |f: Option<f64>| f.map_or("none".to_string(), |f| format!("{f:.3}"));
    format!("{} and {} mm/min", show(ger), show(peer))
}

fn close_enough(a: Option<f64>, b: Option<f64>, slack: f64) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => (a - b).abs() <= slack,
        (a, b) => a.is_none() && b.is_none(),
    }
}

/// The largest difference of one coordinate.
fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a.iter().zip(b).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
}

fn name(kind: &Kind) -> String {
    match kind {
        Kind::Rapid => "a rapid".into(),
        Kind::Feed => "a feed".into(),
        Kind::Arc { .. } => "an arc".into(),
        Kind::Spline => "a spline".into(),
        Kind::Probe => "a probe".into(),
        Kind::Tap => "a rigid tap".into(),
        Kind::Dwell(seconds) => format!("a dwell of {seconds} s"),
        Kind::Spindle(0) => "a spindle stop".into(),
        Kind::Spindle(_) => "a spindle start".into(),
    }
}

/// The machine rs274 runs on, in mm: its tools have no length.
pub struct Machine {
    /// The origins of G54, G55, ... G59.3, in machine coordinates.
    pub work_offsets: Vec<[f64; 3]>,
    /// The points of G28 and G30.
    pub g28: [f64; 3],
    pub g30: [f64; 3],
    /// Tool numbers and diameters.
    pub tools: Vec<(u32, f64)>,
    /// Whether a program reads in inches until it says G21 (else in mm).
    /// rs274 has no setting for it (LinuxCNC takes it from the machine's
    /// configuration), so the program it runs starts with G20 or G21.
    pub inches: bool,
}

impl Default for Machine {
    /// In mm, every origin at machine zero; tools 1 to 999, all of diameter 0.
    fn default() -> Machine {
        let tools = (1..=999).map(|n| (n, 0.0)).collect();
        Machine { work_offsets: Vec::new(), g28: [0.0; 3], g30: [0.0; 3], tools, inches: false }
    }
}

/// Is rs274 installed?
pub fn available() -> bool {
    Command::new("rs274").arg("-h").output().is_ok()
}

/// Why rs274 gave no moves.
#[derive(Debug, PartialEq)]
pub enum Refusal {
    /// What rs274 said, all on one line.
    Error(String),
    TimedOut,
}

/// The moves rs274 makes of `program` on `machine` (see the module's notes),
/// or why it makes none: it exited with an error, or ran for `limit`.
pub fn moves(program: &Path, machine: &Machine, limit: Duration) -> Result<Moves, Refusal> {
    let text = std::fs::read(program).unwrap_or_else(|e| panic!("{}: {e}", program.display()));
    let scratch = tempfile::tempdir().unwrap();
    // The copy keeps the program's name, which rs274's messages quote.
    let copy = scratch.path().join(program.file_name().unwrap());
    std::fs::write(&copy, numbered(&text, if machine.inches { "G20" } else { "G21" })).unwrap();
    let output = run(&copy, machine, scratch.path(), limit);
    if output.timed_out {
        return Err(Refusal::TimedOut);
    }
    let complaint: Vec<&str> =
        output.stderr.lines().map(str::trim).filter(|l| !l.is_empty() && *l != "executing").collect();
    if !complaint.is_empty() {
        // Messages that name the copy name it without the scratch folder, which changes each run.
        let folder = format!("{}/", scratch.path().display());
        return Err(Refusal::Error(complaint.join(" / ").replace(&folder, "")));
    }
    if output.code != Some(0) {
        return Err(Refusal::Error(format!("exit status {:?}", output.code)));
    }
    Ok(Moves::from_rs274(&output.stdout))
}

/// Runs `rs274 -g` on `program` as it is, on `machine`, in a scratch folder
/// of its own, for at most `limit`.
pub fn run_as_is(program: &Path, machine: &Machine, limit: Duration) -> Finished {
    let scratch = tempfile::tempdir().unwrap();
    run(program, machine, scratch.path(), limit)
}

fn run(program: &Path, machine: &Machine, scratch: &Path, limit: Duration) -> Finished {
    // Without an INI file rs274 reads lengths in its tool table and var file in inches.
    let mut tools = String::new();
    for (number, diameter) in &machine.tools {
        tools.push_str(&format!("T{number} P{number} D{:.9} Z0\n", diameter / 25.4));
    }
    std::fs::write(scratch.join("tools.tbl"), tools).unwrap();
    // Parameters in ascending order, as rs274 wants them.
    let mut parameters = String::new();
    for (first, point) in [(5161, machine.g28), (5181, machine.g30)] {
        for (axis, value) in point.iter().enumerate() {
            parameters.push_str(&format!("{}\t{:.9}\n", first + axis, value / 25.4));
        }
    }
    for (i, origin) in machine.work_offsets.iter().enumerate() {
        for (axis, value) in origin.iter().enumerate() {
            parameters.push_str(&format!("{}\t{:.9}\n", 5221 + 20 * i + axis, value / 25.4));
        }
    }
    // rs274 writes the parameters back when it ends: this copy is its own.
    std::fs::write(scratch.join("ger.var"), parameters).unwrap();
    let mut command = Command::new("rs274");
    // rs274 maps the tool table to $HOME/.tool.mmap and truncates it as it
    // starts: runs sharing a HOME crash each other (SIGBUS). One each.
    command.current_dir(scratch).env("HOME", scratch).args(["-t", "tools.tbl", "-v", "ger.var", "-g"]).arg(program);
    super::process::run(&mut command, limit)
}

/// The program with every line numbered `N<line>` for rs274 to print:
/// after any spaces and block-delete slashes, replacing an N word there
/// already. Lines that are blank or a `%` tape marker stay as they are.
/// `first` is a line of no number put before the program's first line, or
/// after it when that is the `%` that opens the program.
pub fn numbered(text: &[u8], first: &str) -> Vec<u8> {
    let mut out = Vec::with_capacity(text.len() + text.len() / 4);
    let opening = text.iter().position(|b| !b.is_ascii_whitespace()).is_some_and(|i| text[i] == b'%');
    if !opening {
        out.extend_from_slice(first.as_bytes());
        out.push(b'\n');
    }
    let mut before_first = opening;
    for (index, line) in text.split_inclusive(|&b| b == b'\n').enumerate() {
        let start = line.iter().position(|b| !b" \t/".contains(b)).unwrap_or(line.len());
        let rest = &line[start..];
        if rest.iter().all(|b| b.is_ascii_whitespace()) || rest[0] == b'%' {
            out.extend_from_slice(line);
            if before_first && rest.first() == Some(&b'%') {
                if !line.ends_with(b"\n") {
                    out.push(b'\n');
                }
                out.extend_from_slice(first.as_bytes());
                out.push(b'\n');
                before_first = false;
            }
            continue;
        }
        let mut after = 0;
        if rest[0].eq_ignore_ascii_case(&b'n') {
            after = 1 + rest[1..].iter().take_while(|b| b" \t".contains(b)).count();
            after += rest[after..].iter().take_while(|b| b.is_ascii_digit() || **b == b'.').count();
            after += rest[after..].iter().take_while(|b| b" \t".contains(b)).count();
        }
        out.extend_from_slice(&line[..start]);
        out.extend_from_slice(format!("N{} ", index + 1).as_bytes());
        out.extend_from_slice(&rest[after..]);
    }
    out
}
