//! Material removal: the stock as a height field, cut by every move of the
//! translated program (after pass 05: absolute machine coordinates, explicit
//! modes, arcs by centre).
//!
//! Stages: a [`Tracker`] follows the statements and knows the loaded tool;
//! [`Simulation::cut`] prepares each move (the exact swept volume of its tool,
//! see [`kernel`]) and batches it; a full batch is binned by tile and the
//! tiles are cut in parallel (rayon). Removal is a minimum, so the order the
//! cuts land in does not matter. Nothing here reads files or knows argv.

pub mod field;
pub mod kernel;
pub mod obstacle;
pub mod path;
pub mod pulses;
pub mod tool;

use rayon::prelude::*;

pub use field::HeightField;
use field::{BLOCK, BLOCKS, TILE};
use ger_core::config::{Config, Tool};
use ger_core::diag::Diagnostic;
use ger_core::statement::{Plane, Statement};
use kernel::{Cut, Geometry, Key};
pub use obstacle::{Intrusion, Solid};
pub use path::{Move, Point, Segment, Step, Walker};
pub use tool::{Cutter, Part, PartKind, Shape};

/// The block of material: an axis-aligned box in machine coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stock {
    pub min: Point,
    pub max: Point,
}

impl Stock {
    /// The stock `[stock] size/origin` describes, if it does (else a margin is wanted).
    pub fn from_config(config: &Config) -> Option<Stock> {
        let [min, max] = config.stock.block()?;
        Some(Stock { min: Point::from(min), max: Point::from(max) })
    }

    pub fn size(&self) -> Point {
        self.max - self.min
    }

    /// About 1000 cells along the longer side.
    pub fn default_cell(&self) -> f64 {
        let size = self.size();
        size[0].max(size[1]) / 1000.0
    }

    /// The finest cell whose height field fits in `limit` bytes.
    pub fn finest_cell(&self, limit: u64) -> f64 {
        let size = self.size();
        // Never zero, which growing by 1% would not leave.
        let mut cell = (size[0] * size[1] * 4.0 / limit as f64).sqrt().max(f64::MIN_POSITIVE);
        while HeightField::bytes(self, cell) > limit as u128 {
            cell *= 1.01;
        }
        cell
    }
}

/// Why a simulation cannot be made.
#[derive(Clone, Debug, PartialEq)]
pub enum Refusal {
    /// The height field at this resolution would not fit in the memory limit.
    TooBig(TooBig),
    /// It would, but the system cannot give that much memory.
    OutOfMemory { needed: u128 },
}

/// A resolution whose height field would not fit in the memory limit.
#[derive(Clone, Debug, PartialEq)]
pub struct TooBig {
    pub needed: u128,
    pub limit: u64,
    /// The finest cell that fits.
    pub finest: f64,
}

/// The box everything cut below Z=0 lies in, for a stock by margin.
#[derive(Clone, Copy, Debug, Default)]
pub struct CutBounds {
    cut: Option<(Point, Point)>,
    all: Option<(Point, Point)>,
}

fn grow(bounds: &mut Option<(Point, Point)>, lo: Point, hi: Point) {
    let (l, h) = bounds.get_or_insert((lo, hi));
    for i in 0..3 {
        l[i] = l[i].min(lo[i]);
        h[i] = h[i].max(hi[i]);
    }
}

impl CutBounds {
    pub fn add(&mut self, segment: &Segment, cutter: Option<&Cutter>) {
        let r = cutter.map_or(0.0, |c| c.radius);
        let (mut lo, mut hi) = segment.bounds();
        let widen = |lo: &mut Point, hi: &mut Point| {
            for i in 0..2 {
                lo[i] -= r;
                hi[i] += r;
            }
        };
        widen(&mut lo, &mut hi);
        grow(&mut self.all, lo, hi);
        if lo[2] >= 0.0 {
            return;
        }
        // The part of a line below Z=0; an arc's whole box.
        if let Segment::Line { from, to } = *segment {
            let (below, above) = if from[2] < to[2] { (from, to) } else { (to, from) };
            let t = if above[2] > 0.0 { -below[2] / (above[2] - below[2]) } else { 1.0 };
            let end = below + t * (above - below);
            (lo, hi) = (below.min(end), below.max(end));
            widen(&mut lo, &mut hi);
        }
        grow(&mut self.cut, lo, hi);
    }

    /// What `other` adds: the bounds of both (of the programs of a job).
    pub fn merge(&mut self, other: &CutBounds) {
        for (mine, theirs) in [(&mut self.cut, other.cut), (&mut self.all, other.all)] {
            if let Some((lo, hi)) = theirs {
                grow(mine, lo, hi);
            }
        }
    }

    /// The stock: the box of the cut plus `margin` on each side, top at Z=0.
    /// A program that cuts nothing gets a block `margin` deep under its moves.
    pub fn stock(&self, margin: f64) -> Stock {
        let margin = if margin > 0.0 { margin } else { 1e-3 };
        let (lo, hi) = self.cut_box();
        Stock {
            min: Point::new(lo[0] - margin, lo[1] - margin, lo[2].min(0.0) - margin),
            max: Point::new(hi[0] + margin, hi[1] + margin, 0.0),
        }
    }

    /// The stock the config asks for around the cut: `[stock] margin`, or a
    /// CAMotics project's automatic workpiece, as CAMotics makes it: the box
    /// of the cut (at least `min_depth` deep, else that much deeper), grown by
    /// `percent` of its size on each side and below.
    pub fn stock_for(&self, config: &Config) -> Stock {
        let Some(percent) = config.stock.margin_percent else { return self.stock(config.stock_margin()) };
        let (lo, hi) = self.cut_box();
        let mut lo = Point::new(lo[0], lo[1], lo[2].min(0.0));
        let hi = Point::new(hi[0], hi[1], 0.0);
        let min_depth = 2.0 * ger_core::statement::Units::Mm.factor_to(config.units);
        if hi[2] - lo[2] < min_depth {
            lo[2] -= min_depth;
        }
        let grow = ((hi - lo) * percent / 100.0).max(Point::splat(1e-3));
        Stock { min: lo - grow, max: Point::new(hi[0] + grow[0], hi[1] + grow[1], 0.0) }
    }

    /// The box of the cut; of the moves, at Z=0, when nothing is cut.
    fn cut_box(&self) -> (Point, Point) {
        match (self.cut, self.all) {
            (Some(cut), _) => cut,
            (None, Some((lo, hi))) => (lo.with_z(0.0), hi.with_z(0.0)),
            (None, None) => (Point::ZERO, Point::ZERO),
        }
    }
}

/// Follows the statements: the moves, and the tool that makes them.
pub struct Tracker<'c> {
    walker: Walker,
    tools: &'c [Tool],
    tool: Option<&'c Tool>,
    cutter: Option<Cutter>,
    /// Reported that no tool is loaded.
    complained: bool,
}

impl<'c> Tracker<'c> {
    /// With no M06, tool 1 is loaded.
    pub fn new(tools: &'c [Tool]) -> Tracker<'c> {
        let tool = tools.iter().find(|t| t.number == 1);
        Tracker { walker: Walker::new(), tools, tool, cutter: tool.map(Cutter::new), complained: false }
    }

    /// The tool loaded now, as the table describes it.
    pub fn tool(&self) -> Option<&'c Tool> {
        self.tool
    }

    /// The tool loaded now (`None` if its number is not in the table).
    pub fn cutter(&self) -> Option<Cutter> {
        self.cutter
    }

    /// The move `statement` makes, if any. A tool change to a tool that is
    /// not in the table is an error at its M06; the moves after it are
    /// still returned, with no cutter.
    pub fn step(&mut self, statement: &Statement) -> Result<Option<Move>, Diagnostic> {
        match self.walker.step(statement) {
            Some(Step::Move(m)) => {
                if self.cutter.is_none() && !self.complained {
                    self.complained = true;
                    return Err(Diagnostic::error(m.span, "no tool is loaded, and tool 1 is not in the tool table")
                        .with_help("load a tool with M06 Tw, or add tool 1 to [[tools]] in ger.toml"));
                }
                Ok(Some(m))
            }
            Some(Step::Tool { number, span }) => {
                self.tool = self.tools.iter().find(|t| t.number == number);
                self.cutter = self.tool.map(Cutter::new);
                self.complained = true;
                if self.cutter.is_none() {
                    let known: Vec<String> = self.tools.iter().map(|t| format!("T{}", t.number)).collect();
                    return Err(Diagnostic::error(span, format!("tool {number} is not in the tool table")).with_help(
                        format!("the table has {}; add [[tools]] number = {number} to ger.toml", known.join(", ")),
                    ));
                }
                Ok(None)
            }
            None => Ok(None),
        }
    }
}

/// Cuts per batch: enough to keep every core busy, few enough to stay small.
const BATCH: usize = 1 << 15;
/// Tile entries per batch (a cut has one for each tile it reaches): however
/// wide the cuts, a batch's bins stay this small.
const BIN_ENTRIES: usize = 1 << 20;
/// Cuts remembered to recognise a repeat (direct-mapped by the cut's key).
const RECENT: usize = 1 << 10;

/// Material removal in progress.
pub struct Simulation {
    field: HeightField,
    frame: Frame,
    batch: Vec<Cut>,
    /// What each cut of the batch is for.
    roles: Vec<Role>,
    /// The batch's (tile, cut) pairs, in the order the cuts came.
    entries: Vec<(u32, u32)>,
    /// How finely arcs that are not cut exactly are split into lines.
    tolerance: f64,
    moves: u64,
    /// Cuts made lately, by a hash of their key, with the height each was made at:
    /// a cut with the same key made no lower removes nothing.
    recent: Vec<Option<(Key, f64)>>,
    /// When inspecting (for the verifier): the tag of the move each cut of the batch belongs to.
    tags: Option<Vec<u32>>,
    /// What the cuts flushed so far touched, not yet taken by the caller.
    contacts: Vec<Contact>,
    /// Every move tagged below this has been cut and has reported.
    settled_below: u32,
}

/// What one move did to the stock, as an inspecting simulation reports it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The tag the move was cut with.
    pub tag: u32,
    /// The most material the move removed over one cell: how deep the tool was engaged.
    pub depth: f32,
    /// How far under the stock's bottom the tool went, over the stock (0 if it did not).
    pub below: f32,
    /// The deepest a guard (see [`Simulation::inspect`]) went into the
    /// material the move's cut left, and which guard (by its index).
    pub clash: Option<(f32, u8)>,
    /// The same for the guards that only warn ([`Guard::near`]).
    pub near: Option<(f32, u8)>,
}

/// A part of the tool that may not touch the stock, for [`Simulation::inspect`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guard {
    /// Its underside, `base` above the tip.
    pub cutter: Cutter,
    pub base: f64,
    /// Reported in [`Contact::near`] rather than [`Contact::clash`].
    pub near: bool,
}

/// What a cut of a batch is for.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    /// It removes material.
    Cut,
    /// It only looks: guard `n` of its move, whose material it must not
    /// meet, and whether that guard only warns.
    Guard(u8, bool),
}

/// What a tile needs to know of the field.
#[derive(Clone, Copy)]
struct Frame {
    x0: f64,
    y0: f64,
    cx: f64,
    cy: f64,
    nx: usize,
    ny: usize,
    /// The stock's bottom.
    floor: f32,
    /// Where cutting stops: the floor for pictures, nowhere when inspecting,
    /// so that a fixture once cut into is not reported again.
    clamp: f32,
}

impl Frame {
    /// The lowest a cell can end after `cut`: the tool's lowest point, or the
    /// stock's bottom where cells stop there. A cell at or below it keeps its height.
    fn reach(&self, cut: &Cut) -> f32 {
        (cut.floor() as f32).max(self.clamp)
    }

    /// The cells along X whose centres lie in [lo, hi].
    fn columns(&self, lo: f64, hi: f64) -> Option<(usize, usize)> {
        cells_between(lo, hi, self.x0, self.cx, self.nx)
    }

    /// The cells along Y whose centres lie in [lo, hi].
    fn rows(&self, lo: f64, hi: f64) -> Option<(usize, usize)> {
        cells_between(lo, hi, self.y0, self.cy, self.ny)
    }
}

fn cells_between(lo: f64, hi: f64, origin: f64, cell: f64, n: usize) -> Option<(usize, usize)> {
    let a = ((lo - origin) / cell - 0.5).ceil().max(0.0);
    let b = ((hi - origin) / cell - 0.5).floor().min(n as f64 - 1.0);
    (a <= b).then_some((a as usize, b as usize))
}

impl Simulation {
    /// Uncut stock at `cell` resolution, unless its height field would take more than `limit` bytes.
    pub fn new(stock: Stock, cell: f64, limit: u64) -> Result<Simulation, Refusal> {
        let needed = HeightField::bytes(&stock, cell);
        if needed > limit as u128 {
            return Err(Refusal::TooBig(TooBig { needed, limit, finest: stock.finest_cell(limit) }));
        }
        let field = HeightField::new(stock, cell).map_err(|_| Refusal::OutOfMemory { needed })?;
        Ok(Simulation::resume(field))
    }

    /// Cutting `field` on, as an earlier simulation left it (the next program of a job).
    pub fn resume(field: HeightField) -> Simulation {
        let frame = Frame {
            x0: field.stock.min[0],
            y0: field.stock.min[1],
            cx: field.cell,
            cy: field.cell_y(),
            nx: field.nx,
            ny: field.ny,
            floor: field.stock.min[2] as f32,
            clamp: field.stock.min[2] as f32,
        };
        Simulation {
            tolerance: field.cell / 20.0,
            field,
            frame,
            batch: Vec::with_capacity(BATCH),
            roles: Vec::with_capacity(BATCH),
            entries: Vec::new(),
            moves: 0,
            recent: vec![None; RECENT],
            tags: None,
            contacts: Vec::new(),
            settled_below: 0,
        }
    }

    /// Reports, for every move cut with [`Simulation::cut_tagged`], how deep it
    /// engaged the material it met and whether it went under the stock. Cuts
    /// are still batched and cut in parallel: a cell is only ever touched by
    /// its own tile, in program order, so what a move meets is exactly what
    /// the moves before it left.
    pub fn inspecting(mut self) -> Simulation {
        self.tags = Some(Vec::with_capacity(BATCH));
        self.frame.clamp = f32::NEG_INFINITY;
        self
    }

    pub fn field(&self) -> &HeightField {
        &self.field
    }

    /// Starts from material shaped as `heights` (see [`HeightField::carve`]).
    pub fn carve(&mut self, heights: &[Option<f64>]) {
        self.field.carve(heights);
    }

    /// Moves simulated so far.
    pub fn moves(&self) -> u64 {
        self.moves
    }

    /// Removes what `cutter` cuts moving along `segment`.
    pub fn cut(&mut self, segment: &Segment, cutter: &Cutter) {
        self.cut_tagged(segment, cutter, 0);
    }

    /// Every move tagged below this has reported all it touched.
    pub fn settled_below(&self) -> u32 {
        self.settled_below
    }

    /// [`Simulation::cut`], and when inspecting, reports what the move
    /// touched under `tag` (tags must not decrease), once its batch is cut.
    /// False when the move cannot remove anything (it will report nothing):
    /// it is above or beside the stock, over material already cut lower, or
    /// a repeat of a cut made lately (or of one made lower).
    pub fn cut_tagged(&mut self, segment: &Segment, cutter: &Cutter, tag: u32) -> bool {
        self.inspect(segment, cutter, &[], tag)
    }

    /// [`Simulation::cut_tagged`], and when inspecting, each of `guards` (at
    /// most 256) carried along the move, reported in [`Contact::clash`] where
    /// the material the move's cut leaves is above it. A guard never cuts: it
    /// is judged in program order like a cut, after its move's. False when
    /// neither the cut nor a guard can meet material.
    pub fn inspect(&mut self, segment: &Segment, cutter: &Cutter, guards: &[Guard], tag: u32) -> bool {
        self.moves += 1;
        let mut any = self.push_segment(segment, cutter, 0.0, Role::Cut, tag);
        if self.tags.is_some() {
            for (n, guard) in guards.iter().enumerate().take(256) {
                any |= self.push_segment(segment, &guard.cutter, guard.base, Role::Guard(n as u8, guard.near), tag);
            }
        }
        if let Some(tags) = &self.tags {
            // The move is all in: what is not waiting in the batch has reported.
            self.settled_below = tags.first().copied().unwrap_or(tag + 1);
        }
        any
    }

    /// Batches `cutter` along `segment` raised by `lift`; false if it can reach no material.
    fn push_segment(&mut self, segment: &Segment, cutter: &Cutter, lift: f64, role: Role, tag: u32) -> bool {
        let (lo, hi) = segment.bounds();
        let stock = &self.field.stock;
        let r = cutter.radius;
        // Above the stock, or beside it: nothing to cut.
        if lo[2] + lift >= stock.max[2]
            || lo[0] - r > stock.max[0]
            || hi[0] + r < stock.min[0]
            || lo[1] - r > stock.max[1]
            || hi[1] + r < stock.min[1]
        {
            return false;
        }
        let mut any = false;
        each_cut(segment, cutter, lift, self.tolerance, |cut| any |= self.push(cut, role, tag));
        any
    }

    /// Bins `cut` into the tiles it may lower; false if there are none.
    fn push(&mut self, cut: Cut, role: Role, tag: u32) -> bool {
        // A guard removes nothing, so it is no cut's repeat, nor a cut its.
        if role == Role::Cut {
            let (key, z) = cut.key();
            let slot = &mut self.recent[recent_slot(&key)];
            match slot {
                Some((seen, lowest)) if *seen == key && *lowest <= z => return false,
                _ => *slot = Some((key, z)),
            }
        }
        let frame = &self.frame;
        let (Some((i0, i1)), Some((j0, j1))) = (frame.columns(cut.lo[0], cut.hi[0]), frame.rows(cut.lo[1], cut.hi[1]))
        else {
            return false;
        };
        // A tile whose every cell is already at or below the tool's lowest point keeps them all.
        let floor = frame.reach(&cut);
        let k = self.batch.len() as u32;
        let before = self.entries.len();
        for ty in j0 / TILE..=j1 / TILE {
            for tx in i0 / TILE..=i1 / TILE {
                let t = ty * self.field.tiles_x + tx;
                if self.field.tile_tops[t] > floor {
                    self.entries.push((t as u32, k));
                }
            }
        }
        if self.entries.len() == before {
            return false;
        }
        self.batch.push(cut);
        self.roles.push(role);
        if let Some(tags) = &mut self.tags {
            tags.push(tag);
        }
        if self.batch.len() == BATCH || self.entries.len() >= BIN_ENTRIES {
            self.flush();
        }
        true
    }

    /// Cuts the batch: each tile, in parallel, takes the cuts that reach it, in program order.
    fn flush(&mut self) {
        if self.batch.is_empty() {
            return;
        }
        let frame = self.frame;
        let field = &mut self.field;
        let tiles_x = field.tiles_x;
        // The entries sorted by tile (a counting sort, so each tile keeps its cuts' order).
        let mut starts = vec![0u32; field.tile_tops.len() + 1];
        for &(t, _) in &self.entries {
            starts[t as usize + 1] += 1;
        }
        for t in 1..starts.len() {
            starts[t] += starts[t - 1];
        }
        let mut order = vec![0u32; self.entries.len()];
        let mut next = starts.clone();
        for &(t, k) in &self.entries {
            order[next[t as usize] as usize] = k;
            next[t as usize] += 1;
        }
        self.entries.clear();
        let batch = &self.batch;
        let roles = &self.roles;
        let order = &order;
        let tiles = field
            .data
            .par_chunks_mut(TILE * TILE)
            .zip(field.block_tops.par_chunks_mut(BLOCKS))
            .zip(field.tile_tops.par_iter_mut())
            .zip(starts.par_windows(2))
            .enumerate()
            .map(move |(t, (((cells, blocks), top), range))| {
                let tile = Tile { cells, blocks, top, i_base: (t % tiles_x) * TILE, j_base: (t / tiles_x) * TILE };
                (tile, &order[range[0] as usize..range[1] as usize])
            });
        match &mut self.tags {
            None => tiles.for_each(|(mut tile, cuts)| {
                for &k in cuts {
                    tile.cut(&batch[k as usize], &frame);
                }
            }),
            Some(tags) => {
                // Each tile lists what each of its cuts touched; a cut's contact is the worst over its tiles.
                let touched: Vec<Vec<(u32, Touch)>> = tiles
                    .map(|(mut tile, cuts)| {
                        let mut touched = Vec::new();
                        for &k in cuts {
                            let cut = &batch[k as usize];
                            let touch = match roles[k as usize] {
                                Role::Cut => tile.cut(cut, &frame),
                                Role::Guard(n, near) => {
                                    let clash = tile.clash(cut, &frame).map(|c| (c, n));
                                    if near {
                                        Touch { near: clash, ..Touch::default() }
                                    } else {
                                        Touch { clash, ..Touch::default() }
                                    }
                                }
                            };
                            if touch.depth > 0.0 || touch.below > 0.0 || touch.clash.is_some() || touch.near.is_some() {
                                touched.push((k, touch));
                            }
                        }
                        touched
                    })
                    .collect();
                let mut per_cut = vec![Touch::default(); batch.len()];
                for (k, touch) in touched.into_iter().flatten() {
                    per_cut[k as usize].merge(touch);
                }
                for (touch, &tag) in per_cut.iter().zip(tags.iter()) {
                    if touch.depth <= 0.0 && touch.below <= 0.0 && touch.clash.is_none() && touch.near.is_none() {
                        continue;
                    }
                    match self.contacts.last_mut() {
                        Some(last) if last.tag == tag => {
                            last.depth = last.depth.max(touch.depth);
                            last.below = last.below.max(touch.below);
                            last.clash = deeper(last.clash, touch.clash);
                            last.near = deeper(last.near, touch.near);
                        }
                        _ => self.contacts.push(Contact {
                            tag,
                            depth: touch.depth,
                            below: touch.below,
                            clash: touch.clash,
                            near: touch.near,
                        }),
                    }
                }
                tags.clear();
            }
        }
        self.batch.clear();
        self.roles.clear();
    }

    /// Cuts the batch now, so that every move cut so far has reported its contact.
    pub fn settle(&mut self) {
        if let Some(&last) = self.tags.as_ref().and_then(|tags| tags.last()) {
            self.settled_below = last + 1;
        }
        self.flush();
    }

    /// The contacts reported since the last call, in the order of their tags.
    /// A move whose cuts straddle two batches may report twice.
    pub fn take_contacts(&mut self) -> Vec<Contact> {
        std::mem::take(&mut self.contacts)
    }

    /// Cuts what is left and hands over the height field.
    pub fn finish(mut self) -> HeightField {
        self.flush();
        self.field
    }
}

/// The lowest `cutter` goes over (x, y) moving along `segment` (infinity if
/// it never passes over it), exactly as a simulation with cells of `cell` cuts it.
pub fn lowest_over(segment: &Segment, cutter: &Cutter, x: f64, y: f64, cell: f64) -> f64 {
    let (lo, hi) = segment.bounds();
    let r = cutter.radius;
    if x < lo[0] - r || x > hi[0] + r || y < lo[1] - r || y > hi[1] + r {
        return f64::INFINITY;
    }
    let mut lowest = f64::INFINITY;
    each_cut(segment, cutter, 0.0, cell / 20.0, |cut| lowest = lowest.min(cut.low(x, y)));
    lowest
}

/// The cuts `cutter` makes along `segment` raised by `lift`: one, or for
/// helices cut by ball and cone tools and arcs in XZ and YZ, short lines
/// within `tolerance` of the arc, each cut exactly.
fn each_cut(segment: &Segment, cutter: &Cutter, lift: f64, tolerance: f64, mut each: impl FnMut(Cut)) {
    let up = Point::new(0.0, 0.0, lift);
    let r = cutter.radius;
    match *segment {
        Segment::Line { from, to } => each(Cut::line(from + up, to + up, *cutter)),
        Segment::Arc { from, to, centre, plane: Plane::XY, radius, start, sweep }
            if from[2] == to[2] || cutter.shape == Shape::Flat =>
        {
            let (lo, hi) = segment.bounds();
            each(Cut {
                geometry: Geometry::Arc {
                    c: [centre[0], centre[1]],
                    r: radius,
                    start,
                    sweep,
                    z0: from[2] + lift,
                    dz: to[2] - from[2],
                },
                cutter: *cutter,
                lo: [lo[0] - r, lo[1] - r],
                hi: [hi[0] + r, hi[1] + r],
            })
        }
        Segment::Arc { .. } => {
            let n = segment.pieces(tolerance);
            let mut a = segment.from();
            for k in 1..=n {
                let b = if k == n { segment.to() } else { segment.at(k as f64 / n as f64) };
                each(Cut::line(a + up, b + up, *cutter));
                a = b;
            }
        }
    }
}

/// Where a key lives in [`Simulation::recent`]: a multiplicative hash of its words.
fn recent_slot(key: &Key) -> usize {
    let mut h = 0u64;
    for &word in key {
        h = (h.rotate_left(5) ^ word).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
    (h >> 32) as usize % RECENT
}

/// What a cut did to the cells of one tile.
#[derive(Clone, Copy, Debug, Default)]
struct Touch {
    /// The most material removed over one cell.
    depth: f32,
    /// How far under the stock's bottom the tool reached.
    below: f32,
    /// A guard's: how far into the material it went, and which guard.
    clash: Option<(f32, u8)>,
    near: Option<(f32, u8)>,
}

impl Touch {
    fn merge(&mut self, other: Touch) {
        self.depth = self.depth.max(other.depth);
        self.below = self.below.max(other.below);
        self.clash = deeper(self.clash, other.clash);
        self.near = deeper(self.near, other.near);
    }
}

/// The deeper of two clashes.
fn deeper(a: Option<(f32, u8)>, b: Option<(f32, u8)>) -> Option<(f32, u8)> {
    match (a, b) {
        (Some(x), Some(y)) => Some(if y.0 > x.0 { y } else { x }),
        (x, y) => x.or(y),
    }
}

/// One tile of the field, as a thread cutting it holds it.
struct Tile<'f> {
    cells: &'f mut [f32],
    /// The highest cell of each block.
    blocks: &'f mut [f32],
    /// The highest cell of the tile.
    top: &'f mut f32,
    i_base: usize,
    j_base: usize,
}

/// The rows of a tile a cut may reach (`j0..=j1`), and where the stock ends in it.
struct Span {
    j0: usize,
    j1: usize,
    i_end: usize,
    j_end: usize,
    j_base: usize,
}

impl Span {
    /// The block rows (in the tile) the rows lie in.
    fn block_rows(&self) -> std::ops::RangeInclusive<usize> {
        (self.j0 - self.j_base) / BLOCK..=(self.j1 - self.j_base) / BLOCK
    }
}

/// The cells of a block row that one row of cells takes from a cut: up to two runs of columns.
type Runs = [Option<(usize, usize)>; 2];

impl Tile<'_> {
    /// Lowers the cells `cut` reaches, passing over each block whose highest
    /// cell is no higher than the tool's tip ever goes: the kernel never
    /// answers below [`Cut::floor`] (every term it adds to the tip's height
    /// is at least zero), so such a block keeps every cell.
    fn cut(&mut self, cut: &Cut, frame: &Frame) -> Touch {
        let mut touch = Touch::default();
        let floor = frame.reach(cut);
        if *self.top <= floor {
            return touch;
        }
        let Some(span) = self.span(cut, frame) else { return touch };
        let (i_end, j_end) = (span.i_end, span.j_end);
        let side = TILE / BLOCK;
        let mut lowered = false;
        for bj in span.block_rows() {
            let Some((runs, c0, c1)) = self.runs(cut, frame, &span, bj) else { continue };
            // The highest cell of each block of this block row: if none is above
            // the floor, the row is passed over; each block whose highest cell
            // is lowered finds its new one after.
            let tops: [f32; TILE / BLOCK] = std::array::from_fn(|bi| self.blocks[bj * side + bi]);
            if tops[c0 / BLOCK..=c1 / BLOCK].iter().all(|&top| top <= floor) {
                continue;
            }
            let mut topped = [false; TILE / BLOCK];
            for (r, row_runs) in runs.iter().enumerate() {
                let y = frame.y0 + ((self.j_base + bj * BLOCK + r) as f64 + 0.5) * frame.cy;
                let row = &mut self.cells[(bj * BLOCK + r) * TILE..][..TILE];
                for &(i0, i1) in row_runs.iter().flatten() {
                    for (i, cell) in row.iter_mut().enumerate().take(i1 + 1).skip(i0) {
                        let old = *cell;
                        if old <= floor {
                            continue;
                        }
                        let x = frame.x0 + ((self.i_base + i) as f64 + 0.5) * frame.cx;
                        let z = cut.low(x, y) as f32;
                        if z < old {
                            topped[i / BLOCK] |= old >= tops[i / BLOCK];
                            touch.depth = touch.depth.max(old - z.max(frame.floor));
                            touch.below = touch.below.max(old.min(frame.floor) - z);
                            *cell = z.max(frame.clamp);
                        }
                    }
                }
            }
            for (bi, _) in topped.iter().enumerate().filter(|(_, topped)| **topped) {
                self.blocks[bj * side + bi] = self.highest_in_block(bi, bj, i_end, j_end);
                lowered = true;
            }
        }
        if lowered {
            *self.top = self.blocks.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        }
        touch
    }

    /// How far into the material a guard (that removes nothing) goes: the
    /// most any cell is above its underside; `None` where no cell is.
    fn clash(&self, cut: &Cut, frame: &Frame) -> Option<f32> {
        let floor = cut.floor() as f32;
        if *self.top <= floor {
            return None;
        }
        let span = self.span(cut, frame)?;
        let side = TILE / BLOCK;
        let mut worst: Option<f32> = None;
        for bj in span.block_rows() {
            let Some((runs, c0, c1)) = self.runs(cut, frame, &span, bj) else { continue };
            if self.blocks[bj * side..][c0 / BLOCK..=c1 / BLOCK].iter().all(|&top| top <= floor) {
                continue;
            }
            for (r, row_runs) in runs.iter().enumerate() {
                let y = frame.y0 + ((self.j_base + bj * BLOCK + r) as f64 + 0.5) * frame.cy;
                let row = &self.cells[(bj * BLOCK + r) * TILE..][..TILE];
                for &(i0, i1) in row_runs.iter().flatten() {
                    for (i, &cell) in row.iter().enumerate().take(i1 + 1).skip(i0) {
                        if cell <= floor {
                            continue;
                        }
                        let x = frame.x0 + ((self.i_base + i) as f64 + 0.5) * frame.cx;
                        let above = cell - cut.low(x, y) as f32;
                        if above > 0.0 && worst.is_none_or(|w| above > w) {
                            worst = Some(above);
                        }
                    }
                }
            }
        }
        worst
    }

    /// The rows of the tile `cut` may reach, if any.
    fn span(&self, cut: &Cut, frame: &Frame) -> Option<Span> {
        let j_end = (self.j_base + TILE).min(frame.ny);
        let i_end = (self.i_base + TILE).min(frame.nx);
        let (j0, j1) = frame.rows(cut.lo[1], cut.hi[1])?;
        let (j0, j1) = (j0.max(self.j_base), j1.min(j_end - 1));
        (j0 <= j1).then_some(Span { j0, j1, i_end, j_end, j_base: self.j_base })
    }

    /// Each row's runs of cells `cut` reaches in block row `bj`, in tile
    /// columns, and the columns of them all; `None` when there are none.
    fn runs(&self, cut: &Cut, frame: &Frame, span: &Span, bj: usize) -> Option<([Runs; BLOCK], usize, usize)> {
        let mut runs: [Runs; BLOCK] = [[None; 2]; BLOCK];
        let (mut c0, mut c1) = (usize::MAX, 0);
        for (r, row_runs) in runs.iter_mut().enumerate() {
            let j = self.j_base + bj * BLOCK + r;
            if j < span.j0 || j > span.j1 {
                continue;
            }
            let y = frame.y0 + (j as f64 + 0.5) * frame.cy;
            for (run, interval) in row_runs.iter_mut().zip(cut.row(y)) {
                let Some((i0, i1)) = interval.and_then(|(lo, hi)| frame.columns(lo, hi)) else { continue };
                let (i0, i1) = (i0.max(self.i_base), i1.min(span.i_end - 1));
                if i0 <= i1 {
                    *run = Some((i0 - self.i_base, i1 - self.i_base));
                    c0 = c0.min(i0 - self.i_base);
                    c1 = c1.max(i1 - self.i_base);
                }
            }
        }
        (c0 <= c1).then_some((runs, c0, c1))
    }

    /// The highest cell of block (bi, bj) that lies in the stock.
    fn highest_in_block(&self, bi: usize, bj: usize, i_end: usize, j_end: usize) -> f32 {
        let mut highest = f32::NEG_INFINITY;
        for r in bj * BLOCK..(bj * BLOCK + BLOCK).min(j_end - self.j_base) {
            let row = &self.cells[r * TILE..][..TILE];
            for &z in &row[bi * BLOCK..(bi * BLOCK + BLOCK).min(i_end - self.i_base)] {
                highest = highest.max(z);
            }
        }
        highest
    }
}

#[cfg(test)]
mod tests;
