//! Statements: what the parser produces and every pass consumes and produces.
//!
//! One type serves the whole pipeline; each pass removes some kinds (pass 01
//! removes `Units`, pass 04 removes `Distance`, ...) so that after the last
//! pass only what `emit` calls output codes remain.

use std::sync::Arc;

use crate::diag::{Origin, Span};

#[derive(Clone, Debug, PartialEq)]
pub struct Statement {
    pub kind: Kind,
    /// The text the statement came from: its code, or its first word.
    pub span: Span,
    /// Set when the statement runs inside a subprogram (or wizard) call.
    pub origin: Option<Arc<Origin>>,
}

impl Statement {
    pub fn new(kind: Kind, span: Span) -> Statement {
        Statement { kind, span, origin: None }
    }

    /// Whether every number the statement holds is finite.
    pub fn is_finite(&self) -> bool {
        let axes = |axes: &Axes| (0..3).all(|axis| axes.get(axis).is_none_or(|v| v.value.is_finite()));
        let value = |v: &Option<Value>| v.is_none_or(|v| v.value.is_finite());
        let motion = |m: &Motion| axes(&m.target) && axes(&m.centre) && value(&m.radius) && value(&m.feed);
        match &self.kind {
            Kind::Motion(m) | Kind::MachineMove(m) => motion(m),
            Kind::Offset { axes: a, .. } | Kind::Home { via: a, .. } => axes(a),
            Kind::SetWorkOffset { axes: a, rotation, .. } => axes(a) && value(rotation),
            Kind::SetToolTable { offsets: a, radius, .. } => axes(a) && value(radius),
            Kind::SetToolTableFrom(from) => axes(&from.target) && value(&from.radius),
            Kind::Cycle(c) => axes(&c.target) && value(&c.r) && value(&c.q) && value(&c.p) && value(&c.feed),
            Kind::Machine { s, .. } => s.is_none_or(f64::is_finite),
            Kind::Dwell(v) | Kind::SpindleSpeed(v) => v.is_finite(),
            Kind::Rotary(words) => words.iter().all(value),
            Kind::PassThrough { words, .. } => words.iter().all(|(_, v)| v.is_finite()),
            _ => true,
        }
    }

    /// The same origin, a new kind: for passes that rewrite a statement.
    pub fn with_kind(&self, kind: Kind) -> Statement {
        Statement { kind, span: self.span, origin: self.origin.clone() }
    }
}

/// A number as written, with where it was written (for pointed diagnostics).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Value {
    pub value: f64,
    pub span: Span,
}

/// X, Y and Z words; `None` where the word was not written.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Axes {
    pub x: Option<Value>,
    pub y: Option<Value>,
    pub z: Option<Value>,
}

impl Axes {
    pub fn is_empty(&self) -> bool {
        self.x.is_none() && self.y.is_none() && self.z.is_none()
    }

    pub fn get(&self, axis: usize) -> Option<Value> {
        [self.x, self.y, self.z][axis]
    }

    pub fn slot(&mut self, axis: usize) -> &mut Option<Value> {
        match axis {
            0 => &mut self.x,
            1 => &mut self.y,
            _ => &mut self.z,
        }
    }

    /// Applies `f` to each written value, keeping its span.
    pub fn map(mut self, mut f: impl FnMut(usize, f64) -> f64) -> Axes {
        for axis in 0..3 {
            if let Some(v) = self.slot(axis) {
                v.value = f(axis, v.value);
            }
        }
        self
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionMode {
    Rapid,
    Linear,
    ArcCw,
    ArcCcw,
}

impl MotionMode {
    pub fn is_arc(self) -> bool {
        matches!(self, MotionMode::ArcCw | MotionMode::ArcCcw)
    }

    pub fn code(self) -> &'static str {
        match self {
            MotionMode::Rapid => "G00",
            MotionMode::Linear => "G01",
            MotionMode::ArcCw => "G02",
            MotionMode::ArcCcw => "G03",
        }
    }
}

/// A move: G00/G01/G02/G03 with its words, or bare axis words, which move in
/// the current motion mode (`mode` is `None` until pass 00 fills it in).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    pub mode: Option<MotionMode>,
    pub target: Axes,
    /// I, J, K: an arc's centre, relative to its start.
    pub centre: Axes,
    pub radius: Option<Value>,
    pub feed: Option<Value>,
    /// An arc's turns (lenient dialect): LinuxCNC's P, the times it goes
    /// round before it ends (its helix spread over them), or Haas's and
    /// Fadal's L, the times the whole block runs. None is once.
    pub turns: Option<Turns>,
}

/// How an arc goes round more than once: see [`Motion::turns`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Turns {
    /// `P n`: one arc going round n times.
    Around(u32),
    /// `L n`: the block n times, each from where the last ended.
    Repeated(u32),
}

/// The most turns an arc may take: each becomes a move of the output.
pub const MAX_TURNS: u32 = 10_000;

impl Motion {
    /// A statement with only F in it sets the feed and moves nothing.
    pub fn moves(&self) -> bool {
        !self.target.is_empty() || !self.centre.is_empty() || self.radius.is_some()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    XY,
    ZX,
    YZ,
}

impl Plane {
    /// The plane's two axes in the order angles and arcs turn (first to
    /// second is counter-clockwise seen from the positive third axis), then
    /// the axis normal to it.
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::XY => (0, 1, 2),
            Plane::ZX => (2, 0, 1),
            Plane::YZ => (1, 2, 0),
        }
    }

    pub fn code(self) -> &'static str {
        match self {
            Plane::XY => "G17",
            Plane::ZX => "G18",
            Plane::YZ => "G19",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    Inch,
    Mm,
}

impl Units {
    pub fn code(self) -> &'static str {
        match self {
            Units::Inch => "G20",
            Units::Mm => "G21",
        }
    }

    /// How many of `to` make one of `self`.
    pub fn factor_to(self, to: Units) -> f64 {
        match (self, to) {
            (Units::Inch, Units::Mm) => 25.4,
            (Units::Mm, Units::Inch) => 1.0 / 25.4,
            _ => 1.0,
        }
    }

    /// How lengths in this unit are labelled in messages.
    pub fn abbreviation(self) -> &'static str {
        match self {
            Units::Inch => "in",
            Units::Mm => "mm",
        }
    }

    /// Output precision: 4 decimals in inches, 3 in millimetres.
    pub fn decimals(self) -> usize {
        match self {
            Units::Inch => 4,
            Units::Mm => 3,
        }
    }

    /// How far an arc's end may be off its circle, as in the manual.
    pub fn arc_tolerance(self) -> f64 {
        match self {
            Units::Inch => 0.0005,
            Units::Mm => 0.01,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distance {
    Absolute,
    Incremental,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Offset {
    /// G52: program zero at the given machine coordinates.
    G52,
    /// G54..G59, G59.1..G59.3: entry 1..9 of the work-offsets table; G54.1
    /// Pn and Haas's G154 Pn: entry 9 + n.
    WorkOffset(u8),
    /// G92: the current position reads as the given coordinates.
    G92,
    /// G92.1 and G92.2 (LinuxCNC): the G92 offset is cancelled, program zero
    /// is the coordinate system's again; G92.2 keeps it for a later G92.3.
    G92Cancel { keep: bool },
    /// G92.3: the offset G92.2 kept is in force again.
    G92Restore,
}

/// The feed rate modes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedMode {
    /// G94: F is units per minute.
    PerMinute,
    /// G93: F is the inverse of the move's time in minutes.
    InverseTime,
    /// G95: F is units per spindle revolution.
    PerRevolution,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

/// The M codes that pass through translation unchanged (manual §3.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Machine {
    Pause,           // M00
    OptionalPause,   // M01
    SpindleCw,       // M03
    SpindleCcw,      // M04
    SpindleOff,      // M05
    ToolChange,      // M06
    Mist,            // M07
    Flood,           // M08
    CoolantOff,      // M09
    SpindleHigh,     // M40
    SpindleLow,      // M41
    EnableOverride,  // M48
    DisableOverride, // M49
}

impl Machine {
    pub fn from_number(n: u32) -> Option<Machine> {
        use Machine::*;
        Some(match n {
            0 => Pause,
            1 => OptionalPause,
            3 => SpindleCw,
            4 => SpindleCcw,
            5 => SpindleOff,
            6 => ToolChange,
            7 => Mist,
            8 => Flood,
            9 => CoolantOff,
            40 => SpindleHigh,
            41 => SpindleLow,
            48 => EnableOverride,
            49 => DisableOverride,
            _ => return None,
        })
    }

    pub fn code(self) -> &'static str {
        use Machine::*;
        match self {
            Pause => "M00",
            OptionalPause => "M01",
            SpindleCw => "M03",
            SpindleCcw => "M04",
            SpindleOff => "M05",
            ToolChange => "M06",
            Mist => "M07",
            Flood => "M08",
            CoolantOff => "M09",
            SpindleHigh => "M40",
            SpindleLow => "M41",
            EnableOverride => "M48",
            DisableOverride => "M49",
        }
    }
}

/// Which G-code ger reads: the GER manual's (strict), or that plus what CAM
/// programs and controllers commonly emit (lenient).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Dialect {
    #[default]
    Strict,
    Lenient,
}

/// The canned drilling cycles of the lenient dialect, with LinuxCNC's meaning.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleCode {
    /// G73: drilling with chip breaking (short retracts between pecks).
    ChipBreak,
    /// G81: drilling.
    Drill,
    /// G82: drilling with a dwell at the bottom.
    DrillDwell,
    /// G83: peck drilling (full retracts between pecks).
    Peck,
    /// G85: boring, feed out.
    Bore,
    /// G86: boring, spindle stop, rapid out.
    BoreSpindleStop,
    /// G89: boring, dwell, feed out.
    BoreDwell,
    /// G84: right-hand tapping: feed in turning clockwise, out turning counter-clockwise.
    Tap,
    /// G74: left-hand tapping: the other way round.
    TapLeft,
}

impl CycleCode {
    pub fn code(self) -> &'static str {
        match self {
            CycleCode::ChipBreak => "G73",
            CycleCode::Drill => "G81",
            CycleCode::DrillDwell => "G82",
            CycleCode::Peck => "G83",
            CycleCode::Bore => "G85",
            CycleCode::BoreSpindleStop => "G86",
            CycleCode::BoreDwell => "G89",
            CycleCode::Tap => "G84",
            CycleCode::TapLeft => "G74",
        }
    }
}

/// A canned cycle at one position (X/Y), down to Z from the R plane.
#[derive(Clone, Debug, PartialEq)]
pub struct Cycle {
    pub code: CycleCode,
    pub target: Axes,
    pub r: Option<Value>,
    /// Peck depth (G73, G83).
    pub q: Option<Value>,
    /// Dwell in seconds (G82, G89).
    pub p: Option<Value>,
    /// L (or K): how many times; in G91 each repeat steps X/Y again.
    pub repeat: u32,
    pub feed: Option<Value>,
}

/// Where a canned cycle retracts to: G98, the Z where the cycles began; G99, the R plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Retract {
    #[default]
    Initial,
    RPlane,
}

/// G10 L10 or L11: see [`Kind::SetToolTableFrom`].
#[derive(Clone, Debug, PartialEq)]
pub struct ToolTableFrom {
    pub tool: u32,
    pub target: Axes,
    pub radius: Option<Value>,
    /// L11: in G59.3's coordinates.
    pub fixture: bool,
    pub frame: Option<Frame>,
}

/// A coordinate system's place on the machine: its origin (machine
/// coordinates) and its turn about it (degrees counter-clockwise in XY).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub origin: [f64; 3],
    pub rotation: f64,
}

/// The lenient dialect's splines (LinuxCNC's), in the XY plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SplineCode {
    /// G5: a cubic Bézier curve.
    Cubic,
    /// G5.1: a quadratic Bézier curve.
    Quadratic,
    /// G5.2: a NURBS control point (the curve is drawn at G5.3).
    Nurbs,
}

impl SplineCode {
    pub fn code(self) -> &'static str {
        match self {
            SplineCode::Cubic => "G05",
            SplineCode::Quadratic => "G5.1",
            SplineCode::Nurbs => "G5.2",
        }
    }
}

/// The most control points one NURBS may have: they are kept until its G5.3.
pub const MAX_NURBS_POINTS: usize = 10_000;
/// The highest order a NURBS may have (LinuxCNC sets no limit).
pub const MAX_NURBS_ORDER: u32 = 16;

/// A spline statement (lenient dialect), with LinuxCNC's words.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    /// `None`: a line of X Y P with no code, which pass 00 makes the next
    /// control point of the NURBS in force.
    pub code: Option<SplineCode>,
    /// X, Y: the end (G5, G5.1), or a control point (G5.2). Never Z.
    pub target: Axes,
    /// I, J (as x, y): the first control point, relative to the start (G5, G5.1).
    pub first: Axes,
    /// P, Q (as x, y): G5's second control point, relative to the end.
    pub second: Axes,
    /// P: a NURBS control point's weight (G5.2).
    pub weight: Option<Value>,
    /// L: the NURBS's order (G5.2).
    pub order: Option<u32>,
    pub feed: Option<Value>,
}

/// G28 goes to machine zero, G30 to the configured second reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    Home,
    Second,
}

#[derive(Clone, Debug, PartialEq)]
pub enum WizardArg {
    Number(f64),
    Text(String),
}

#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    /// Boxed, as every payload larger than a few words is: each statement is
    /// moved through every stage, and a `Statement` of 80 bytes moves in
    /// registers where one of 168 went through `memmove` (a fifth of the
    /// translation's time).
    Motion(Box<Motion>),
    Plane(Plane),
    Units(Units),
    Distance(Distance),
    /// G16 (true) / G15 (false).
    Polar(bool),
    Offset {
        code: Offset,
        axes: Box<Axes>,
    },
    /// G43 (positive) / G44 with the H register (none: the loaded tool's,
    /// lenient dialect only, settled in pass 04). A Z written with it is a
    /// move of its own, in the motion mode in force, as on every controller.
    ToolLength {
        positive: bool,
        h: Option<u32>,
    },
    /// G49.
    ToolLengthCancel,
    /// G10 L1 (LinuxCNC, lenient dialect): tool `tool`'s entry in the
    /// controller's tool table gets the offsets given (Z its length) and the
    /// radius R. The controller keeps the table (so G43 H reads it there and
    /// the line goes to the output); cutter compensation takes the radius.
    SetToolTable {
        tool: u32,
        offsets: Box<Axes>,
        radius: Option<Value>,
    },
    /// G10 L10 and L11 (LinuxCNC, lenient dialect): tool `tool`'s entry is
    /// set so that, once G43 applies it, the tool's position reads `target`
    /// in the coordinate system in force (L10) or in G59.3's (L11, a
    /// touch-off fixture's). Pass 02 tells which system that is (`frame`),
    /// and pass 04 makes it the `SetToolTable` it comes to, from where the
    /// machine is and the tool offsets.
    SetToolTableFrom(Box<ToolTableFrom>),
    /// An H word with no G43/G44 (lenient dialect): a new register for the
    /// offset in force (Fanuc), or the offset applied as G43 (Fadal).
    ToolLengthRegister(u32),
    /// G41/G42 with an optional D (tool table entry), or LinuxCNC's G41.1/
    /// G42.1 (lenient dialect) with the cutter's `diameter` given (their D).
    CutterComp {
        side: Side,
        d: Option<u32>,
        diameter: Option<Value>,
    },
    /// G40.
    CutterCompCancel,
    /// M00..M49 pass-through codes; M03/M04 may carry S, M06 may carry T.
    Machine {
        code: Machine,
        s: Option<f64>,
        t: Option<u32>,
    },
    /// `Ow`: names the main program, or starts a subprogram.
    Program(u32),
    /// M98 Pw Lw.
    Call {
        program: u32,
        repeat: u32,
    },
    /// M99.
    Return,
    /// M30.
    End,
    /// M47 (lenient dialect): run the program again from its start.
    Repeat,
    Wizard {
        name: String,
        args: Vec<WizardArg>,
    },

    // The lenient dialect's codes; the strict parser never makes these.
    /// G04 Pn: dwell n seconds. An output code.
    Dwell(f64),
    /// S alone: the speed for the next M03/M04, or a new speed now if the spindle turns.
    SpindleSpeed(f64),
    /// T alone: the tool the next M06 loads.
    ToolSelect(u32),
    /// Codes with no effect on the toolpath (G61, G61.1, G64, G94, G91.1; M19
    /// spindle orient, M31/M33 chip conveyor); pass 00 drops them.
    NoEffect(&'static str),
    /// G80: the end of a series of canned cycles.
    CycleCancel,
    /// G98/G99.
    CycleRetract(Retract),
    Cycle(Box<Cycle>),
    /// G28/G30: a rapid through `via` (if given) to the reference point, for
    /// the axes given (all of them if none).
    Home {
        reference: Reference,
        via: Box<Axes>,
    },
    /// G53: a move in machine coordinates, whatever the offsets and G90/G91.
    MachineMove(Box<Motion>),
    /// A, B, C words (lenient dialect): the rotary axes of a post written for
    /// a machine that has them. Pass 04 drops them while they stay where they
    /// are, and refuses the first that would turn.
    Rotary(Box<[Option<Value>; 3]>),
    /// An M code ger does not know (lenient dialect), passed to the output as
    /// it came (`M62 P1`): I/O, clamps, user and vendor codes. `code` is its
    /// number times ten, as the parser numbers codes.
    PassThrough {
        code: u32,
        words: Vec<(char, f64)>,
    },
    /// G93 (inverse time), G94 (per minute), G95 (per revolution): pass 04
    /// turns every feed into units per minute, the output's only mode.
    FeedMode(FeedMode),
    /// G90.1 (absolute) / G91.1 (relative, the output's mode): how I, J and K
    /// give an arc's centre.
    ArcCentres(Distance),
    /// G28.1 / G30.1: the reference point becomes where the tool is.
    SetReference(Reference),
    /// G5, G5.1, G5.2 and its control points.
    Spline(Box<Spline>),
    /// G5.3: the end of a NURBS, which is drawn here.
    NurbsEnd,
    /// A line of axis words with P, L or Q and no code (lenient dialect),
    /// read both ways: the next control point of the NURBS in force (G5.2),
    /// or the next hole of the canned cycle in force (its code to be filled
    /// in) with a new dwell, repeat count or peck. Pass 00 keeps the reading
    /// that fits the mode in force, or its error.
    NextPoint {
        point: Result<Box<Spline>, Box<crate::diag::Diagnostic>>,
        hole: Result<Box<Cycle>, Box<crate::diag::Diagnostic>>,
    },
    /// G10 L2 (`relative` false): entry `entry` of the work-offsets table (0:
    /// the one in force) is set to the given machine coordinates, and with R
    /// its coordinate system turned by `rotation` degrees about its origin
    /// (counter-clockwise in XY, as LinuxCNC); G10 L20 (`relative`): set so
    /// that the current position reads as given.
    SetWorkOffset {
        entry: u8,
        axes: Box<Axes>,
        relative: bool,
        rotation: Option<Value>,
    },
}
