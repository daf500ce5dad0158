//! What the program will do: the box it cuts, how far it moves, how long it
//! takes, which tools it uses and which codes it runs.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::timing::Planned;
use crate::Rule;
use ger_core::config::{Config, ToolKind};
use ger_core::statement::{Distance, Kind, Statement};
use ger_core::tools::ToolSource;
use ger_sim::{HeightField, Point, Segment};

/// A box, in machine coordinates (as JSON: each corner `[x, y, z]`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Bounds {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Bounds {
    fn grow(bounds: &mut Option<Bounds>, lo: Point, hi: Point) {
        let b = bounds.get_or_insert(Bounds { min: lo.to_array(), max: hi.to_array() });
        for i in 0..3 {
            b.min[i] = b.min[i].min(lo[i]);
            b.max[i] = b.max[i].max(hi[i]);
        }
    }
}

/// One tool's share of the work, and the tool as the table describes it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToolUse {
    pub number: u32,
    /// Distance moved at feed rate (G01-G03) with this tool loaded.
    pub cutting_distance: f64,
    /// Feed moves made with it.
    pub moves: u64,
    /// `None` when the tool is not in the table.
    pub kind: Option<ToolKind>,
    pub diameter: Option<f64>,
    /// Degrees, for drills and centre drills.
    pub tip_angle: Option<f64>,
    /// Where the table's entry came from (`None` when not in it, or not known).
    pub source: Option<ToolSource>,
    pub flute_length: Option<f64>,
    /// The shank above the flutes: the cutting diameter unless the table says.
    pub shank_diameter: Option<f64>,
    /// From the tip to the holder's face.
    pub stick_out: Option<f64>,
    /// The holder's pieces from its face up, each `[bottom, top, length]`
    /// (diameters equal for a cylinder).
    pub holder: Vec<[f64; 3]>,
    /// What the collision check does not see for want of the table's
    /// word, when it does not see it all.
    pub unchecked: Option<&'static str>,
}

impl ToolUse {
    fn new(number: u32) -> ToolUse {
        ToolUse {
            number,
            cutting_distance: 0.0,
            moves: 0,
            kind: None,
            diameter: None,
            tip_angle: None,
            source: None,
            flute_length: None,
            shank_diameter: None,
            stick_out: None,
            holder: Vec::new(),
            unchecked: None,
        }
    }
}

/// The field names are the JSON output's (`ger check --format json`), documented in the README.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// "in" or "mm": the unit of every length here.
    pub units: &'static str,
    /// The box of the material removed (to the simulation's cells), from the stock's top down.
    pub cut_box: Option<Bounds>,
    /// The box of the tool's path (its tip), rapids included.
    pub path_box: Option<Bounds>,
    /// Distance at feed rate (G01-G03).
    pub cutting_distance: f64,
    /// Distance at rapid (G00).
    pub rapid_distance: f64,
    /// At programmed feeds: feed moves at their F, rapids at `rapid_rate`
    /// (each axis at that speed, the slowest deciding), dwells; acceleration
    /// is not modelled (`planned` models it).
    pub run_time_seconds: f64,
    /// Units per minute.
    pub rapid_rate: f64,
    /// The run time the motion planner gives, on the machine's profile.
    pub planned: Planned,
    /// In the order they are first used.
    pub tools: Vec<ToolUse>,
    /// How many times each code runs (after translation: subprograms and
    /// wizards expanded, repeats unrolled).
    pub codes: BTreeMap<String, u64>,
    /// How many times each check found a problem, including those not shown.
    pub problems: BTreeMap<&'static str, u64>,
}

impl Summary {
    pub fn new(config: &Config) -> Summary {
        Summary {
            units: config.units.abbreviation(),
            cut_box: None,
            path_box: None,
            cutting_distance: 0.0,
            rapid_distance: 0.0,
            run_time_seconds: 0.0,
            rapid_rate: config.rapid_rate(),
            planned: Planned::unplanned(config),
            tools: Vec::new(),
            codes: BTreeMap::new(),
            problems: BTreeMap::new(),
        }
    }

    pub(super) fn count(&mut self, statement: &Statement) {
        let code = match &statement.kind {
            Kind::Motion(m) => m.mode.map(|mode| mode.code()),
            Kind::Plane(plane) => Some(plane.code()),
            Kind::Units(units) => Some(units.code()),
            Kind::Distance(Distance::Absolute) => Some("G90"),
            Kind::Distance(Distance::Incremental) => Some("G91"),
            Kind::Machine { code, .. } => Some(code.code()),
            Kind::End => Some("M30"),
            Kind::Dwell(_) => Some("G04"),
            _ => None,
        };
        if let Some(code) = code {
            // Allocates only the first time a code is seen.
            match self.codes.get_mut(code) {
                Some(n) => *n += 1,
                None => {
                    self.codes.insert(code.to_string(), 1);
                }
            }
        }
    }

    pub(super) fn dwell(&mut self, seconds: f64) {
        self.run_time_seconds += seconds.max(0.0);
    }

    pub(super) fn add_move(&mut self, segment: &Segment, rapid: bool, feed: Option<f64>, tool: Option<u32>) {
        let (lo, hi) = segment.bounds();
        Bounds::grow(&mut self.path_box, lo, hi);
        let length = segment.length();
        if rapid {
            self.rapid_distance += length;
            let (from, to) = (segment.from(), segment.to());
            let longest = (0..3).map(|i| (to[i] - from[i]).abs()).fold(0.0, f64::max);
            self.run_time_seconds += longest / self.rapid_rate * 60.0;
            return;
        }
        self.cutting_distance += length;
        if let Some(feed) = feed.filter(|f| *f > 0.0) {
            self.run_time_seconds += length / feed * 60.0;
        }
        if let Some(number) = tool {
            let index = match self.tools.iter().position(|t| t.number == number) {
                Some(index) => index,
                None => {
                    self.tools.push(ToolUse::new(number));
                    self.tools.len() - 1
                }
            };
            self.tools[index].cutting_distance += length;
            self.tools[index].moves += 1;
        }
    }

    /// The box of the cells cut below the stock's top (deeper than `tolerance`).
    pub(super) fn measure_cut(&mut self, field: &HeightField, tolerance: f64) {
        let top = field.stock.max[2];
        let (half_x, half_y) = (field.cell / 2.0, field.cell_y() / 2.0);
        for j in 0..field.ny {
            for i in 0..field.nx {
                let z = field.get(i, j);
                if z < top - tolerance {
                    let [x, y] = field.centre(i, j);
                    let (lo, hi) = (Point::new(x - half_x, y - half_y, z), Point::new(x + half_x, y + half_y, top));
                    Bounds::grow(&mut self.cut_box, lo, hi);
                }
            }
        }
    }

    /// Says what each tool used is, and where the table got it from.
    pub(super) fn describe_tools(&mut self, config: &Config) {
        for used in &mut self.tools {
            if let Some(tool) = config.tool(used.number) {
                used.kind = Some(tool.kind);
                used.diameter = Some(tool.diameter);
                let pointed = matches!(tool.kind, ToolKind::Drill | ToolKind::CenterDrill);
                used.tip_angle = tool.tip_angle.or(pointed.then_some(ger_sim::tool::DEFAULT_TIP_ANGLE));
                used.source = config.tool_source(used.number).cloned();
                used.flute_length = tool.flute_length;
                used.shank_diameter = Some(tool.shank());
                used.stick_out = tool.stick_out;
                used.holder = tool.holder.iter().map(|p| [p.ends().0, p.ends().1, p.length]).collect();
                used.unchecked = match (tool.flute_length.is_some(), !tool.holder.is_empty()) {
                    (false, false) => Some("flute length and holder not configured: only the cutting edge is checked"),
                    (false, true) => Some("flute length not configured: the shank is not checked"),
                    (true, false) => Some("holder not configured: only the shank is checked"),
                    (true, true) => None,
                };
            }
        }
    }

    /// Counts one more problem found by `rule`; returns how many so far.
    pub(super) fn problem(&mut self, rule: Rule) -> u64 {
        let n = self.problems.entry(rule.name()).or_default();
        *n += 1;
        *n
    }
}
