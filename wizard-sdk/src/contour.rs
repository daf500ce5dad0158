//! A closed path of lines and arcs in XY, followed at a height that changes
//! along it: a ramp that goes down along the contour itself (no line of its
//! own needed, so a circle or a small outline can be entered too), and
//! holding tabs that leave a bridge of material under the path.
//!
//! Distances are measured along the contour from its start; past its length
//! they go round again, so one call can follow several laps.
//!
//! Lead-in and lead-out arcs join the contour tangentially, so a finishing
//! pass starts and ends without the mark a tool leaves where it stops or
//! turns sharply against a wall.

use crate::block::{g1, g2, g3, Statement};

/// A piece of a contour, ending at `to`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Piece {
    Line { to: [f64; 2] },
    Arc { to: [f64; 2], centre: [f64; 2], clockwise: bool },
}

/// A closed path: from `start` through its pieces, the last ending at `start`.
#[derive(Clone, Debug, PartialEq)]
pub struct Contour {
    start: [f64; 2],
    pieces: Vec<Piece>,
}

/// Closer than this (in the program's unit) is the same point.
const SAME: f64 = 1e-9;

/// A side of a path, looking along it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The inside of a counter-clockwise loop, the outside of a clockwise one.
    Left,
    Right,
}

impl Contour {
    /// A contour that starts (and, once closed, ends) at `start`.
    pub fn new(start: [f64; 2]) -> Contour {
        Contour { start, pieces: Vec::new() }
    }

    /// A circle round `centre` through `start`.
    pub fn circle(centre: [f64; 2], start: [f64; 2], clockwise: bool) -> Contour {
        Contour::new(start).arc_to(start, centre, clockwise)
    }

    /// Adds a straight line to `to`.
    pub fn line_to(mut self, to: [f64; 2]) -> Contour {
        self.pieces.push(Piece::Line { to });
        self
    }

    /// Adds an arc round `centre` to `to`; ending where it starts, a whole circle.
    pub fn arc_to(mut self, to: [f64; 2], centre: [f64; 2], clockwise: bool) -> Contour {
        self.pieces.push(Piece::Arc { to, centre, clockwise });
        self
    }

    pub fn start(&self) -> [f64; 2] {
        self.start
    }

    /// A rounded rectangle from its corners' centres (`low` the lower-left,
    /// `high` the upper-right) and their radius, starting on its bottom edge
    /// (at its left end going counter-clockwise, its right end clockwise):
    /// a circle when the centres meet, a slot when they share X or Y.
    pub fn rounded_rectangle(low: [f64; 2], high: [f64; 2], radius: f64, clockwise: bool) -> Contour {
        let ([x0, y0], [x1, y1], r) = (low, high, radius);
        if low == high {
            return Contour::circle(low, [x0, y0 - r], clockwise);
        }
        // Corner centres in the loop's order from the start, each with where its arc starts and ends.
        let corners: [([f64; 2], [f64; 2], [f64; 2]); 4] = if clockwise {
            [
                ([x0, y0], [x0, y0 - r], [x0 - r, y0]),
                ([x0, y1], [x0 - r, y1], [x0, y1 + r]),
                ([x1, y1], [x1, y1 + r], [x1 + r, y1]),
                ([x1, y0], [x1 + r, y0], [x1, y0 - r]),
            ]
        } else {
            [
                ([x1, y0], [x1, y0 - r], [x1 + r, y0]),
                ([x1, y1], [x1 + r, y1], [x1, y1 + r]),
                ([x0, y1], [x0, y1 + r], [x0 - r, y1]),
                ([x0, y0], [x0 - r, y0], [x0, y0 - r]),
            ]
        };
        let start = if clockwise { [x1, y0 - r] } else { [x0, y0 - r] };
        let mut path = Contour::new(start);
        for (centre, arc_start, arc_end) in corners {
            path = path.line_to(arc_start);
            if r > 0.0 {
                path = path.arc_to(arc_end, centre, clockwise);
            }
        }
        path
    }

    /// A lead-in: an arc of `radius` from the `side` of the contour that
    /// meets it at `distance` along it, tangent to it there. The arc starts
    /// `offset` (above 0, at most `radius`) from the line the contour runs
    /// along at that point: `offset` equal to `radius` is a quarter circle, a
    /// smaller one a shorter arc that starts on a path `offset` from a
    /// straight side (a roughing pass that left `offset` for this one).
    /// Returns where the arc starts and the arc (at the current Z), which
    /// ends on the contour. Where the contour turns sharply at `distance`,
    /// the arc follows the piece that starts there.
    pub fn lead_in(
        &self,
        distance: f64,
        radius: f64,
        offset: f64,
        side: Side,
    ) -> Result<([f64; 2], Statement), String> {
        let (on, along) = self.point_and_direction(distance, false)?;
        let lead = Lead::new(on, along, radius, offset, side)?;
        let start = lead.point(-1.0);
        Ok((start, lead.arc(start, on)))
    }

    /// A lead-out: the mirror image of [`Contour::lead_in`], from the
    /// contour at `distance`, tangent to it as it arrives there, away to
    /// `side`. Returns the arc and where it ends, `offset` from the line the
    /// contour ran along.
    pub fn lead_out(
        &self,
        distance: f64,
        radius: f64,
        offset: f64,
        side: Side,
    ) -> Result<(Statement, [f64; 2]), String> {
        let (on, along) = self.point_and_direction(distance, true)?;
        let lead = Lead::new(on, along, radius, offset, side)?;
        let end = lead.point(1.0);
        Ok((lead.arc(on, end), end))
    }

    /// The point at `distance` along the contour and the direction of
    /// travel there: at a corner, that of the piece `arriving` there, or of
    /// the one leaving.
    fn point_and_direction(&self, distance: f64, arriving: bool) -> Result<([f64; 2], [f64; 2]), String> {
        let lap = self.length();
        if !(lap.is_finite() && lap > SAME && distance.is_finite()) {
            return Err("a lead needs a contour with a length and a place on it".to_string());
        }
        let mut at = distance.rem_euclid(lap);
        if arriving && at <= SAME {
            at = lap;
        }
        let mut piece_start = 0.0;
        let spans: Vec<_> = self.spans().collect();
        for (n, &(start, piece)) in spans.iter().enumerate() {
            let piece_end = piece_start + piece.length(start);
            let last = n + 1 == spans.len();
            let inside = if arriving { at <= piece_end + SAME } else { at < piece_end - SAME };
            if inside || last {
                let along = (at - piece_start).clamp(0.0, piece_end - piece_start);
                let point = piece.point_at(start, along);
                return Ok((point, piece.direction(start, point)));
            }
            piece_start = piece_end;
        }
        Err("a lead needs a contour with pieces".to_string())
    }

    /// Each piece with where it starts.
    fn spans(&self) -> impl Iterator<Item = ([f64; 2], Piece)> + '_ {
        let starts = std::iter::once(self.start).chain(self.pieces.iter().map(|piece| piece.end()));
        starts.zip(self.pieces.iter().copied())
    }

    /// The length of one lap.
    pub fn length(&self) -> f64 {
        self.spans().map(|(from, piece)| piece.length(from)).sum()
    }

    /// Moves (G1, or G2/G3 for arcs, absolute XY and Z) along the contour
    /// from distance `from` to distance `to` (laps past the first allowed),
    /// at the heights `heights` gives; a move ends at every change of slope
    /// of `heights`, so the tool follows it exactly. The tool is at distance
    /// `from`, at `heights.at(from)`, when they start.
    pub fn follow(&self, from: f64, to: f64, heights: &Heights) -> Result<Vec<Statement>, String> {
        let lap = self.length();
        if !(lap.is_finite() && lap > SAME) {
            return Err("a contour needs a length to follow".to_string());
        }
        if !(from.is_finite() && to.is_finite() && from <= to) {
            return Err(format!("a contour is followed forwards, not from {from} to {to}"));
        }
        let mut out = Vec::new();
        let mut z_now = heights.at(from);
        let mut lap_start = (from / lap).floor() * lap;
        while lap_start < to - SAME {
            let mut piece_start = lap_start;
            for (start, piece) in self.spans() {
                let piece_end = piece_start + piece.length(start);
                let (a, b) = (piece_start.max(from), piece_end.min(to));
                if b - a > SAME {
                    let mut stops: Vec<f64> = heights.breaks_within(a, b).collect();
                    stops.push(b);
                    let mut along = a - piece_start;
                    for s in stops {
                        let z = heights.at(s);
                        let changes = (z - z_now).abs() > SAME;
                        out.push(piece.move_between(start, along, s - piece_start, changes.then_some(z)));
                        (along, z_now) = (s - piece_start, z);
                    }
                }
                piece_start = piece_end;
            }
            lap_start += lap;
        }
        Ok(out)
    }
}

impl Piece {
    fn end(&self) -> [f64; 2] {
        match *self {
            Piece::Line { to } | Piece::Arc { to, .. } => to,
        }
    }

    /// The angle the arc turns through, positive, from `from`.
    fn sweep(from: [f64; 2], to: [f64; 2], centre: [f64; 2], clockwise: bool) -> f64 {
        let angle = |p: [f64; 2]| (p[1] - centre[1]).atan2(p[0] - centre[0]);
        let turn = std::f64::consts::TAU;
        let mut sweep = if clockwise { angle(from) - angle(to) } else { angle(to) - angle(from) };
        sweep = sweep.rem_euclid(turn);
        if sweep < SAME {
            sweep = turn;
        }
        sweep
    }

    fn length(&self, from: [f64; 2]) -> f64 {
        match *self {
            Piece::Line { to } => (to[0] - from[0]).hypot(to[1] - from[1]),
            Piece::Arc { to, centre, clockwise } => {
                let radius = (from[0] - centre[0]).hypot(from[1] - centre[1]);
                radius * Piece::sweep(from, to, centre, clockwise)
            }
        }
    }

    /// The direction of travel (a unit vector) at `point` on the piece that starts at `from`.
    fn direction(&self, from: [f64; 2], point: [f64; 2]) -> [f64; 2] {
        let [dx, dy] = match *self {
            Piece::Line { to } => [to[0] - from[0], to[1] - from[1]],
            Piece::Arc { centre, clockwise: false, .. } => [centre[1] - point[1], point[0] - centre[0]],
            Piece::Arc { centre, clockwise: true, .. } => [point[1] - centre[1], centre[0] - point[0]],
        };
        let length = dx.hypot(dy);
        [dx / length, dy / length]
    }

    /// The point `along` from the piece's start `from`.
    fn point_at(&self, from: [f64; 2], along: f64) -> [f64; 2] {
        let total = self.length(from);
        if total - along <= SAME {
            return self.end();
        }
        match *self {
            Piece::Line { to } => {
                let t = along / total;
                [from[0] + (to[0] - from[0]) * t, from[1] + (to[1] - from[1]) * t]
            }
            Piece::Arc { centre, clockwise, .. } => {
                let radius = (from[0] - centre[0]).hypot(from[1] - centre[1]);
                let start_angle = (from[1] - centre[1]).atan2(from[0] - centre[0]);
                let turned = along / radius;
                let angle = if clockwise { start_angle - turned } else { start_angle + turned };
                [centre[0] + radius * angle.cos(), centre[1] + radius * angle.sin()]
            }
        }
    }

    /// The move along this piece (which starts at `from`) from `along_from`
    /// to `along_to`, ending at height `z` (written only if `z_changes`).
    fn move_between(&self, from: [f64; 2], along_from: f64, along_to: f64, z: Option<f64>) -> Statement {
        let [x, y] = self.point_at(from, along_to);
        let block = match *self {
            Piece::Line { .. } => g1().xy(x, y),
            Piece::Arc { centre, clockwise, .. } => {
                let here = self.point_at(from, along_from);
                let arc = if clockwise { g2() } else { g3() };
                arc.xy(x, y).i(centre[0] - here[0]).j(centre[1] - here[1])
            }
        };
        match z {
            Some(z) => block.z(z).into(),
            None => block.into(),
        }
    }
}

/// A tangent arc at a point of a contour: its circle's centre, and what
/// the arc turns through from the contour to where it starts or ends.
struct Lead {
    centre: [f64; 2],
    radius: f64,
    /// Unit vectors: along the contour, and from it towards the lead's side.
    along: [f64; 2],
    across: [f64; 2],
    /// The angle between the contour's point and the lead's far end.
    turn: f64,
    side: Side,
}

impl Lead {
    fn new(on: [f64; 2], along: [f64; 2], radius: f64, offset: f64, side: Side) -> Result<Lead, String> {
        if !(radius.is_finite() && radius > SAME) {
            return Err(format!("a lead arc needs a radius above 0, not {radius}"));
        }
        if !(offset > SAME && offset <= radius + SAME) {
            return Err(format!(
                "a lead arc of radius {radius} starts above 0 and at most its radius away, not {offset}"
            ));
        }
        let left = [-along[1], along[0]];
        let across = if side == Side::Left { left } else { left.map(|v| -v) };
        let centre = [on[0] + radius * across[0], on[1] + radius * across[1]];
        let turn = (1.0 - offset.min(radius) / radius).acos();
        Ok(Lead { centre, radius, along, across, turn, side })
    }

    /// The lead's far end: behind the contour's point (`forward` -1, a lead-in) or ahead of it (1, a lead-out).
    fn point(&self, forward: f64) -> [f64; 2] {
        let (sin, cos) = self.turn.sin_cos();
        let ([c, a, n], r) = ([self.centre, self.along, self.across], self.radius);
        [c[0] - r * n[0] * cos + forward * r * a[0] * sin, c[1] - r * n[1] * cos + forward * r * a[1] * sin]
    }

    /// The arc from `from` to `to` round the lead's centre: it turns towards
    /// the lead's side, counter-clockwise on the left.
    fn arc(&self, from: [f64; 2], to: [f64; 2]) -> Statement {
        let arc = if self.side == Side::Left { g3() } else { g2() };
        arc.xy(to[0], to[1]).i(self.centre[0] - from[0]).j(self.centre[1] - from[1]).into()
    }
}

/// Heights along a contour: straight between the points given, level before
/// the first and after the last.
#[derive(Clone, Debug, PartialEq)]
pub struct Heights {
    /// (distance, z), by distance.
    points: Vec<(f64, f64)>,
}

impl Heights {
    /// One height all along.
    pub fn level(z: f64) -> Heights {
        Heights { points: vec![(0.0, z)] }
    }

    /// From `from_z` at distance `at` straight down to `to_z`, no steeper
    /// than `angle_degrees`, then level.
    pub fn descent(at: f64, from_z: f64, to_z: f64, angle_degrees: f64) -> Result<Heights, String> {
        let slope = crate::entry::slope(angle_degrees)?;
        if from_z < to_z {
            return Err(format!("a descent goes down: Z{to_z} is above Z{from_z}"));
        }
        Ok(Heights { points: vec![(at, from_z), (at + (from_z - to_z) / slope, to_z)] })
    }

    /// `count` holding tabs, evenly spaced round each lap of `lap` from
    /// `first` on, for `laps` laps: over `width` of the path the tool rises
    /// to `tab_top` (by 45° ramps either side), elsewhere it is at `level`.
    /// `width` is the tool path's: the bridge left is narrower by the tool's
    /// diameter. Nothing rises where `level` is at or above `tab_top`.
    pub fn tabs(
        lap: f64,
        first: f64,
        laps: u32,
        count: u32,
        width: f64,
        level: f64,
        tab_top: f64,
    ) -> Result<Heights, String> {
        let rise = tab_top - level;
        if rise <= 0.0 || count == 0 {
            return Ok(Heights::level(level));
        }
        let footprint = width + 2.0 * rise;
        if f64::from(count) * footprint >= lap {
            return Err(format!(
                "{count} tabs {width:.3} wide (with their ramps {footprint:.3}) do not fit on a path {lap:.3} long"
            ));
        }
        let mut points = Vec::new();
        for n in 0..laps * count {
            let centre = first + (f64::from(n) + 0.5) * lap / f64::from(count);
            let half = width / 2.0;
            points.extend([
                (centre - half - rise, level),
                (centre - half, tab_top),
                (centre + half, tab_top),
                (centre + half + rise, level),
            ]);
        }
        Ok(Heights { points })
    }

    /// Where the last change of slope is: past it, the height stays.
    pub fn ends_at(&self) -> f64 {
        self.points.last().map_or(0.0, |&(d, _)| d)
    }

    /// The height at distance `s`.
    pub fn at(&self, s: f64) -> f64 {
        let points = &self.points;
        let after = points.partition_point(|&(d, _)| d <= s);
        match (after.checked_sub(1).map(|i| points[i]), points.get(after)) {
            (Some((d0, z0)), Some(&(d1, z1))) if d1 - d0 > SAME => z0 + (z1 - z0) * (s - d0) / (d1 - d0),
            (Some((_, z)), _) => z,
            (None, Some(&(_, z))) => z,
            (None, None) => 0.0,
        }
    }

    /// The distances strictly between `a` and `b` where the slope changes.
    fn breaks_within(&self, a: f64, b: f64) -> impl Iterator<Item = f64> + '_ {
        let mut last = a;
        self.points.iter().map(|&(d, _)| d).filter(move |&d| {
            let keep = d > last + SAME && d < b - SAME;
            if keep {
                last = d;
            }
            keep
        })
    }

    /// The higher of the two at every distance: a descent that must also
    /// pass over tabs.
    pub fn max(&self, other: &Heights) -> Heights {
        let mut breaks: Vec<f64> = self.points.iter().chain(&other.points).map(|&(d, _)| d).collect();
        breaks.sort_by(f64::total_cmp);
        breaks.dedup_by(|a, b| (*a - *b).abs() <= SAME);
        let higher = |s: f64| self.at(s).max(other.at(s));
        let mut points = Vec::new();
        for pair in breaks.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            points.push((a, higher(a)));
            // Where one crosses the other between two breaks, a new one.
            let (da, db) = (self.at(a) - other.at(a), self.at(b) - other.at(b));
            if da * db < 0.0 {
                let s = a + (b - a) * da / (da - db);
                points.push((s, higher(s)));
            }
        }
        if let Some(&last) = breaks.last() {
            points.push((last, higher(last)));
        }
        Heights { points }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::block::Block;

    fn block(statement: &Statement) -> &Block {
        match statement {
            Statement::Block(block) => block,
            other => panic!("not a block: {other:?}"),
        }
    }

    /// The statement's words, rounded to 1e-9 so hand values compare exactly.
    fn words(statement: &Statement) -> Vec<(char, f64)> {
        block(statement).words.iter().map(|&(l, v)| (l, (v * 1e9).round() / 1e9 + 0.0)).collect()
    }

    #[test]
    fn a_square_is_four_lines_and_laps_go_round_again() {
        let square = Contour::new([0.0, 0.0])
            .line_to([10.0, 0.0])
            .line_to([10.0, 10.0])
            .line_to([0.0, 10.0])
            .line_to([0.0, 0.0]);
        assert_eq!(square.length(), 40.0);
        // From 5 along the first side, one and a quarter laps: to 55, the middle of the second side.
        let out = square.follow(5.0, 55.0, &Heights::level(-1.0)).unwrap();
        let ends: Vec<Vec<(char, f64)>> = out.iter().map(words).collect();
        let line = |x, y| vec![('G', 1.0), ('X', x), ('Y', y)];
        assert_eq!(
            ends,
            [line(10.0, 0.0), line(10.0, 10.0), line(0.0, 10.0), line(0.0, 0.0), line(10.0, 0.0), line(10.0, 5.0)]
        );
    }

    #[test]
    fn a_descent_round_a_circle_is_a_helix_that_ends_exactly_at_its_depth() {
        // Radius 5: a lap is 10π. At 45° from Z0 to Z-5π the descent ends half way round, at (-5, 0).
        let circle = Contour::circle([0.0, 0.0], [5.0, 0.0], false);
        let lap = circle.length();
        assert!((lap - 10.0 * std::f64::consts::PI).abs() < 1e-12);
        let descent = Heights::descent(0.0, 0.0, -lap / 2.0, 45.0).unwrap();
        let out = circle.follow(0.0, lap, &descent).unwrap();
        assert_eq!(out.len(), 2);
        let z = (-lap / 2.0 * 1e9).round() / 1e9;
        assert_eq!(words(&out[0]), [('G', 3.0), ('X', -5.0), ('Y', 0.0), ('I', -5.0), ('J', 0.0), ('Z', z)]);
        // The second half from (-5, 0): its centre is +5 in X, and Z no longer changes.
        assert_eq!(words(&out[1]), [('G', 3.0), ('X', 5.0), ('Y', 0.0), ('I', 5.0), ('J', 0.0)]);
        // Clockwise, a quarter lap goes to (0, -5).
        let cw = Contour::circle([0.0, 0.0], [5.0, 0.0], true);
        let out = cw.follow(0.0, lap / 4.0, &Heights::level(0.0)).unwrap();
        assert_eq!(words(&out[0]), [('G', 2.0), ('X', 0.0), ('Y', -5.0), ('I', -5.0), ('J', 0.0)]);
    }

    #[test]
    fn tabs_rise_at_45_degrees_over_their_width_and_a_descent_passes_over_them() {
        // A 100 long lap, 2 tabs 4 wide from 0: centres at 25 and 75; level -3, tab top -1: ramps 2 long.
        let tabs = Heights::tabs(100.0, 0.0, 1, 2, 4.0, -3.0, -1.0).unwrap();
        for (s, z) in [
            (0.0, -3.0),
            (21.0, -3.0),
            (22.0, -2.0),
            (23.0, -1.0),
            (25.0, -1.0),
            (27.0, -1.0),
            (28.0, -2.0),
            (29.0, -3.0),
            (75.0, -1.0),
        ] {
            assert!((tabs.at(s) - z).abs() < 1e-12, "at {s}: {} not {z}", tabs.at(s));
        }
        // A 45° descent from Z0 at 20 reaches the tab's ramp at 22 (both at -2), so
        // the tool goes down to it and climbs the ramp to the tab's top.
        let both = Heights::descent(20.0, 0.0, -3.0, 45.0).unwrap().max(&tabs);
        for (s, z) in [
            (20.0, 0.0),
            (21.0, -1.0),
            (22.0, -2.0),
            (23.0, -1.0),
            (27.0, -1.0),
            (28.0, -2.0),
            (29.0, -3.0),
            (50.0, -3.0),
        ] {
            assert!((both.at(s) - z).abs() < 1e-12, "at {s}: {} not {z}", both.at(s));
        }
        // ...and a square followed at those heights stops at every change of slope.
        let square = Contour::new([0.0, 0.0])
            .line_to([50.0, 0.0])
            .line_to([50.0, 50.0])
            .line_to([0.0, 50.0])
            .line_to([0.0, 0.0]);
        let out = square.follow(0.0, 30.0, &both.max(&Heights::level(-3.0))).unwrap();
        let xz: Vec<(f64, Option<f64>)> =
            out.iter().map(words).map(|w| (w[1].1, w.iter().find(|w| w.0 == 'Z').map(|w| w.1))).collect();
        let stops = [
            (20.0, None),
            (21.0, Some(-1.0)),
            (22.0, Some(-2.0)),
            (23.0, Some(-1.0)),
            (27.0, None),
            (29.0, Some(-3.0)),
            (30.0, None),
        ];
        assert_eq!(xz, stops);
    }

    fn assert_near(point: [f64; 2], expected: [f64; 2]) {
        assert!((point[0] - expected[0]).abs() < 1e-12 && (point[1] - expected[1]).abs() < 1e-12, "{point:?}");
    }

    #[test]
    fn leads_are_tangent_arcs_from_the_side_asked_that_start_offset_from_the_contour() {
        // A 10 x 10 square counter-clockwise from the origin: at 5 along, the middle of its bottom, going +X.
        let square = Contour::new([0.0, 0.0])
            .line_to([10.0, 0.0])
            .line_to([10.0, 10.0])
            .line_to([0.0, 10.0])
            .line_to([0.0, 0.0]);
        // A quarter circle of radius 2 from the inside (left): its centre is 2 above (5, 0), it starts 2 before it.
        let (start, arc) = square.lead_in(5.0, 2.0, 2.0, Side::Left).unwrap();
        assert_near(start, [3.0, 2.0]);
        assert_eq!(words(&arc), [('G', 3.0), ('X', 5.0), ('Y', 0.0), ('I', 2.0), ('J', 0.0)]);
        // Offset 1 of radius 2: 60° of arc, starting at (5 - 2 sin 60°, 1); from the outside it is clockwise.
        let (start, arc) = square.lead_in(45.0, 2.0, 1.0, Side::Right).unwrap();
        let s = 3f64.sqrt();
        assert_near(start, [5.0 - s, -1.0]);
        let centre_from_start = [5.0 - start[0], -2.0 - start[1]];
        let w = words(&arc);
        assert_eq!(w[..3], [('G', 2.0), ('X', 5.0), ('Y', 0.0)]);
        assert!((w[3].1 - centre_from_start[0]).abs() < 1e-9 && (w[4].1 - centre_from_start[1]).abs() < 1e-9);
        // Out at the same place: from (5, 0) ahead and up to (7, 2).
        let (arc, end) = square.lead_out(5.0, 2.0, 2.0, Side::Left).unwrap();
        assert_near(end, [7.0, 2.0]);
        assert_eq!(words(&arc), [('G', 3.0), ('X', 7.0), ('Y', 2.0), ('I', 0.0), ('J', 2.0)]);
        // At the start's corner a lead-in follows the bottom, a lead-out the left side coming down.
        let (start, _) = square.lead_in(0.0, 1.0, 1.0, Side::Left).unwrap();
        assert_near(start, [-1.0, 1.0]);
        let (_, end) = square.lead_out(40.0, 1.0, 1.0, Side::Left).unwrap();
        assert_near(end, [1.0, -1.0]);
        // On a circle the lead meets the arc's tangent: round (0, 0) from (0, -5), going +X.
        let circle = Contour::circle([0.0, 0.0], [0.0, -5.0], false);
        let (start, arc) = circle.lead_in(0.0, 2.0, 2.0, Side::Left).unwrap();
        assert_near(start, [-2.0, -3.0]);
        assert_eq!(words(&arc), [('G', 3.0), ('X', 0.0), ('Y', -5.0), ('I', 2.0), ('J', 0.0)]);
        // A quarter lap on, at (5, 0), a clockwise circle goes -Y: its left is +X.
        let cw = Contour::circle([0.0, 0.0], [5.0, 0.0], true);
        let (_, end) = cw.lead_out(0.0, 1.0, 1.0, Side::Left).unwrap();
        assert_near(end, [6.0, -1.0]);
        assert!(square.lead_in(5.0, 1.0, 2.0, Side::Left).unwrap_err().contains("at most its radius"));
        assert!(square.lead_in(5.0, 0.0, 0.0, Side::Left).unwrap_err().contains("radius above 0"));
    }

    #[test]
    fn what_cannot_be_followed_is_an_error() {
        assert!(Heights::tabs(10.0, 0.0, 1, 3, 2.0, -2.0, -1.0).unwrap_err().contains("do not fit"));
        assert_eq!(Heights::tabs(10.0, 0.0, 1, 3, 2.0, -1.0, -1.0).unwrap(), Heights::level(-1.0));
        assert!(Heights::descent(0.0, -1.0, 0.0, 3.0).unwrap_err().contains("goes down"));
        let dot = Contour::new([1.0, 1.0]).line_to([1.0, 1.0]);
        assert!(dot.follow(0.0, 1.0, &Heights::level(0.0)).unwrap_err().contains("length"));
        let square = Contour::new([0.0, 0.0]).line_to([1.0, 0.0]).line_to([0.0, 0.0]);
        assert!(square.follow(1.0, 0.0, &Heights::level(0.0)).unwrap_err().contains("forwards"));
    }
}
