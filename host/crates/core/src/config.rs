//! The machine, as `ger.toml` describes it. Every field has a default, so
//! no file at all is a valid configuration.

use serde::{Deserialize, Serialize};

use crate::diag::{Diagnostic, Span};
use crate::parse::CodeLists;
use crate::statement::{Dialect, Units};
use crate::tools::ToolSource;

mod motion;
pub use motion::{GrblSettings, Machine, MotionConfig, MotionProfile, Preset, MAX_PLANNER_BLOCKS};

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// The machine's unit; the output is entirely in it.
    #[serde(default = "default_units", with = "units_name")]
    pub units: Units,
    /// The work-offsets table: G54..G59, in machine units.
    #[serde(default)]
    pub offsets: WorkOffsets,
    /// The tool table: `[[tools]]`; without it, tool 1 is the default
    /// quarter-inch endmill until the tools the program describes replace it
    /// ([`crate::tools::settle`]).
    #[serde(default)]
    pub tools: Vec<Tool>,
    /// Where each tool of `tools` came from, by number: every tool of
    /// `[[tools]]` says so; without them this is empty until the table is
    /// settled for a program, and then every tool has its source.
    #[serde(skip)]
    pub tool_sources: Vec<(u32, ToolSource)>,
    /// "strict", the GER manual's G-code (default), or "lenient": that and
    /// what CAM programs and controllers commonly emit. Either the name
    /// alone (`dialect = "lenient"`) or a table (`[dialect]`) that also
    /// lists M codes to pass through silently or to drop.
    #[serde(default)]
    pub dialect: DialectConfig,
    #[serde(default)]
    pub machine: MachineSettings,
    /// The block the program cuts, for `ger render`.
    #[serde(default)]
    pub stock: StockConfig,
    /// How finely `ger render` simulates.
    #[serde(default)]
    pub render: RenderConfig,
    /// What `ger check` looks for.
    #[serde(default)]
    pub check: CheckConfig,
    /// What holds the stock, for `ger check` to keep the tool off.
    #[serde(default)]
    pub fixtures: Vec<Fixture>,
    /// The controller the output is written for: `target = "grbl"`, or a
    /// `[target]` table with the name and what that controller has. Only the
    /// output's shape depends on it (the `ger-controller` crate); the translation
    /// does not.
    #[serde(default)]
    pub target: TargetConfig,
}

/// The controllers `ger run --target` and `target = "..."` name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TargetName {
    /// ger's own output: what every controller below reads, with nothing left out.
    #[default]
    Generic,
    Grbl,
    Linuxcnc,
    Fanuc,
    Mach3,
}

impl TargetName {
    pub const ALL: [TargetName; 5] =
        [TargetName::Generic, TargetName::Grbl, TargetName::Linuxcnc, TargetName::Fanuc, TargetName::Mach3];

    /// As `ger.toml` and `--target` write it.
    pub fn name(self) -> &'static str {
        match self {
            TargetName::Generic => "generic",
            TargetName::Grbl => "grbl",
            TargetName::Linuxcnc => "linuxcnc",
            TargetName::Fanuc => "fanuc",
            TargetName::Mach3 => "mach3",
        }
    }

    pub fn from_name(name: &str) -> Option<TargetName> {
        TargetName::ALL.into_iter().find(|target| target.name() == name)
    }
}

/// `target = "grbl"`, or a `[target]` table: the name, and what that
/// controller has beyond its defaults.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TargetConfig {
    pub name: TargetName,
    /// GRBL: the board was built with mist coolant (M7); without it an M7 is left out.
    pub mist: bool,
    /// GRBL: the lines a tool change (M06) becomes, `{tool}` standing for its
    /// number; default a spindle stop and a pause naming the tool.
    pub tool_change: Option<String>,
    /// GRBL: tool lengths by H register, in machine units, for `G43 Hn` to
    /// become `G43.1 Z<length>`; an H not listed is left out with a note.
    pub tool_lengths: Vec<(u32, f64)>,
    /// Fanuc: the program's O number (1 to 9999).
    pub program_number: Option<u32>,
}

mod target_config {
    use std::collections::BTreeMap;

    use serde::de::{self, Deserializer, MapAccess, Visitor};
    use serde::Deserialize;

    use super::{TargetConfig, TargetName};

    fn name<E: de::Error>(text: &str) -> Result<TargetName, E> {
        TargetName::from_name(text).ok_or_else(|| {
            let names: Vec<&str> = TargetName::ALL.iter().map(|t| t.name()).collect();
            E::custom(format!("target must be one of {}, not \"{text}\"", names.join(", ")))
        })
    }

    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Table {
        name: String,
        #[serde(default)]
        mist: bool,
        tool_change: Option<String>,
        #[serde(default)]
        tool_lengths: BTreeMap<u32, f64>,
        program_number: Option<u32>,
    }

    struct TargetVisitor;

    impl<'de> Visitor<'de> for TargetVisitor {
        type Value = TargetConfig;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a target's name, or a [target] table")
        }

        fn visit_str<E: de::Error>(self, text: &str) -> Result<TargetConfig, E> {
            Ok(TargetConfig { name: name::<E>(text)?, ..TargetConfig::default() })
        }

        fn visit_map<M: MapAccess<'de>>(self, map: M) -> Result<TargetConfig, M::Error> {
            let table = Table::deserialize(de::value::MapAccessDeserializer::new(map))?;
            Ok(TargetConfig {
                name: name(&table.name)?,
                mist: table.mist,
                tool_change: table.tool_change,
                tool_lengths: table.tool_lengths.into_iter().collect(),
                program_number: table.program_number,
            })
        }
    }

    impl<'de> Deserialize<'de> for TargetConfig {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<TargetConfig, D::Error> {
            d.deserialize_any(TargetVisitor)
        }
    }
}

/// The machine beyond its unit and tables.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MachineSettings {
    /// G30's second reference point, in machine coordinates (default: machine zero).
    #[serde(default, rename = "g30")]
    pub second_reference: [f64; 3],
    /// How many times M47 (lenient dialect) runs the program again before it
    /// ends it: a machine would repeat it for ever.
    #[serde(default = "one")]
    pub m47_repeats: u32,
    /// How far each axis travels, in machine units (`ger check` keeps moves inside).
    pub travel: Option<[f64; 3]>,
    /// Where machine zero sits in the travel, measured from its lowest corner:
    /// default `[0, 0, z]`, X and Y at their low end and Z at the top.
    pub home: Option<[f64; 3]>,
    /// Rapid (G00) speed in machine units per minute, for run-time estimates:
    /// default 200 in/min or 5000 mm/min.
    pub rapid_rate: Option<f64>,
    /// The feed (machine units per minute) of a feed move before any F
    /// (lenient dialect): default none, so such a move is an error.
    pub default_feed: Option<f64>,
    /// How far the arcs and lines a spline (lenient G5, G5.1, G5.2) becomes
    /// may stray from it, in machine units: default 0.001 in or 0.02 mm.
    pub spline_tolerance: Option<f64>,
    /// How many times an O-word loop (lenient dialect) may run before it is
    /// stopped as one that never ends.
    #[serde(default = "default_max_iterations")]
    pub max_iterations: u64,
    /// How many blocks loops, subroutine calls and repeats may run in all,
    /// each counted every time it runs: nested loops that each end, or
    /// `M98 L` repeats nested in one another, can still be work without end.
    #[serde(default = "default_max_blocks")]
    pub max_blocks: u64,
    /// `[machine.motion]`: how the machine moves, for the planned run time.
    pub motion: Option<MotionConfig>,
}

/// The most `[machine] max_iterations` and `max_blocks` may be: a program
/// that long is a hang.
const RUN_LIMIT_BOUND: u64 = 1_000_000_000;

fn default_max_iterations() -> u64 {
    RunLimits::default().iterations
}

fn default_max_blocks() -> u64 {
    RunLimits::default().blocks
}

/// How much a program may run beyond its own text before it is stopped as
/// one that never ends: the translation is bounded whatever the input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunLimits {
    /// How many times one loop may run.
    pub iterations: u64,
    /// How many blocks may run inside loops, calls and repeats, in all.
    pub blocks: u64,
}

impl Default for RunLimits {
    /// A million passes of one loop, a hundred million repeated blocks (a
    /// few minutes' translation): far beyond what a real program runs.
    fn default() -> RunLimits {
        RunLimits { iterations: 1_000_000, blocks: 100_000_000 }
    }
}

impl Default for MachineSettings {
    fn default() -> MachineSettings {
        MachineSettings {
            second_reference: [0.0; 3],
            m47_repeats: one(),
            travel: None,
            home: None,
            rapid_rate: None,
            default_feed: None,
            spline_tolerance: None,
            max_iterations: default_max_iterations(),
            max_blocks: default_max_blocks(),
            motion: None,
        }
    }
}

/// The checks `ger check` makes beyond translation, by the names `--allow`,
/// `[check] allow` and the JSON output use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Rule {
    RapidIntoStock,
    SpindleOff,
    FluteLength,
    Plunge,
    BelowStock,
    Travel,
    ArcRadius,
    DefaultTool,
    Collision,
    Clearance,
    Fixture,
}

impl Rule {
    pub const ALL: [Rule; 11] = [
        Rule::RapidIntoStock,
        Rule::SpindleOff,
        Rule::FluteLength,
        Rule::Plunge,
        Rule::BelowStock,
        Rule::Travel,
        Rule::ArcRadius,
        Rule::DefaultTool,
        Rule::Collision,
        Rule::Clearance,
        Rule::Fixture,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Rule::RapidIntoStock => "rapid-into-stock",
            Rule::SpindleOff => "spindle-off",
            Rule::FluteLength => "flute-length",
            Rule::Plunge => "plunge",
            Rule::BelowStock => "below-stock",
            Rule::Travel => "travel",
            Rule::ArcRadius => "arc-radius",
            Rule::DefaultTool => "default-tool",
            Rule::Collision => "collision",
            Rule::Clearance => "clearance",
            Rule::Fixture => "fixture",
        }
    }

    pub fn from_name(name: &str) -> Option<Rule> {
        Rule::ALL.into_iter().find(|rule| rule.name() == name)
    }
}

/// `[check]`: the verifier's thresholds, and the checks turned off.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckConfig {
    /// Checks not to run, by name (`ger check --allow NAME` adds to them).
    #[serde(default)]
    pub allow: Vec<Rule>,
    /// The smallest arc radius the controller takes, in machine units:
    /// default 0.001 in or 0.02 mm (twice the arc tolerance, below which
    /// the translator takes an arc's radius for zero).
    pub min_arc_radius: Option<f64>,
    /// How deep a flat endmill may plunge straight down into material, as a
    /// fraction of its diameter: default 0.5.
    pub plunge_fraction: Option<f64>,
    /// How near a shank or holder may pass the stock before it is a
    /// warning (`clearance`), in machine units: default 0.5 mm or 0.02 in.
    pub clearance: Option<f64>,
}

/// `[[fixtures]]`: what holds the stock (vise jaws, clamps, bolts), which no
/// part of the tool may touch: a box (`min`, `max`) or an upright cylinder
/// (`centre` of its base, `diameter`, `height`).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fixture {
    pub name: String,
    pub min: Option<[f64; 3]>,
    pub max: Option<[f64; 3]>,
    pub centre: Option<[f64; 3]>,
    pub diameter: Option<f64>,
    pub height: Option<f64>,
    /// Whether the coordinates are from G54's program zero (`[offsets]
    /// G54`: the default) or the machine's.
    #[serde(default)]
    pub coordinates: Coordinates,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Coordinates {
    #[default]
    Program,
    Machine,
}

/// The most `[[fixtures]]` a file may list.
pub const MAX_FIXTURES: usize = 64;

fn one() -> u32 {
    1
}

impl StockConfig {
    /// The block's lowest and highest corners in machine coordinates, when
    /// its size is given: program zero at `origin` from its lower-left-bottom
    /// corner (by default on its top).
    pub fn block(&self) -> Option<[[f64; 3]; 2]> {
        let size = self.size?;
        let origin = self.origin.unwrap_or([0.0, 0.0, size[2]]);
        Some([origin.map(|o| -o), std::array::from_fn(|axis| size[axis] - origin[axis])])
    }
}

/// `[stock]`: either `size` (with `origin`) or `margin`; by default a margin.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StockConfig {
    /// The block's size, in machine units.
    pub size: Option<[f64; 3]>,
    /// Where program zero sits, measured from the block's lower-left-bottom
    /// corner: `[0, 0, height]` puts it on the top lower-left corner.
    pub origin: Option<[f64; 3]>,
    /// The bounding box of everything cut below Z=0, plus this on each side
    /// (top at Z=0). Default: 0.1 in or 2.5 mm.
    pub margin: Option<f64>,
    /// A margin of this percentage of the cut's size instead, and at least
    /// 2 mm deep: a CAMotics project's automatic workpiece (not a key of the file).
    #[serde(skip)]
    pub margin_percent: Option<f64>,
}

/// `[render]`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderConfig {
    /// Cells per machine unit (the manual's "scale"); default: about 1000
    /// cells along the stock's longer side.
    pub scale: Option<f64>,
    /// MiB the simulation's height field may take (default 2048).
    pub memory_limit_mb: Option<u64>,
}

/// How many entries the work-offsets table has: G54..G59, G59.1..G59.3,
/// then the extended offsets of G54.1 P1.. / G154 P1...
pub const WORK_OFFSETS: usize = 9 + crate::parse::EXTENDED_OFFSETS as usize;

#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkOffsets {
    #[serde(rename = "G54")]
    pub g54: Option<[f64; 3]>,
    #[serde(rename = "G55")]
    pub g55: Option<[f64; 3]>,
    #[serde(rename = "G56")]
    pub g56: Option<[f64; 3]>,
    #[serde(rename = "G57")]
    pub g57: Option<[f64; 3]>,
    #[serde(rename = "G58")]
    pub g58: Option<[f64; 3]>,
    #[serde(rename = "G59")]
    pub g59: Option<[f64; 3]>,
    #[serde(rename = "G59.1")]
    pub g59_1: Option<[f64; 3]>,
    #[serde(rename = "G59.2")]
    pub g59_2: Option<[f64; 3]>,
    #[serde(rename = "G59.3")]
    pub g59_3: Option<[f64; 3]>,
    /// The extended offsets, P1 first: G54.1 Pn (Fanuc) and G154 Pn (Haas).
    #[serde(rename = "G54.1", default)]
    pub extended: Vec<[f64; 3]>,
}

impl WorkOffsets {
    /// Entry 1..=9 (G54..G59.3), then 9 + n (G54.1 Pn); an entry not in
    /// the file is (0, 0, 0).
    pub fn entry(&self, entry: u8) -> [f64; 3] {
        let entries = [self.g54, self.g55, self.g56, self.g57, self.g58, self.g59, self.g59_1, self.g59_2, self.g59_3];
        let entry = usize::from(entry);
        let given = match entry {
            1..=9 => entries[entry - 1],
            _ => self.extended.get(entry - 10).copied(),
        };
        given.unwrap_or([0.0; 3])
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ToolKind {
    Endmill,
    Ballmill,
    Drill,
    CenterDrill,
}

impl ToolKind {
    /// As `ger.toml` writes it.
    pub fn name(self) -> &'static str {
        match self {
            ToolKind::Endmill => "endmill",
            ToolKind::Ballmill => "ballmill",
            ToolKind::Drill => "drill",
            ToolKind::CenterDrill => "center-drill",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tool {
    pub number: u32,
    pub kind: ToolKind,
    /// In machine units.
    pub diameter: f64,
    pub flute_length: Option<f64>,
    /// For drills: the point's included angle in degrees.
    pub tip_angle: Option<f64>,
    /// The shank above the flutes: default the cutting diameter.
    pub shank_diameter: Option<f64>,
    /// From the tip to the holder's face: the shank runs from the flutes
    /// to there. Without it the shank goes up without end.
    pub stick_out: Option<f64>,
    /// The holder, from its face up: cylinders and cones, each `length`
    /// long. Without it only the shank is checked.
    #[serde(default)]
    pub holder: Vec<HolderPiece>,
}

/// One piece of a tool holder: a cylinder (`diameter`), or a cone from
/// `bottom` to `top` diameter, `length` long.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HolderPiece {
    pub diameter: Option<f64>,
    pub bottom: Option<f64>,
    pub top: Option<f64>,
    pub length: f64,
}

impl HolderPiece {
    /// Its diameters at the bottom and the top (once validated, one of the two forms is given).
    pub fn ends(&self) -> (f64, f64) {
        match (self.diameter, self.bottom, self.top) {
            (Some(d), _, _) => (d, d),
            (None, Some(bottom), Some(top)) => (bottom, top),
            _ => (0.0, 0.0),
        }
    }
}

pub const MAX_TOOLS: usize = 20;
/// The most pieces a holder is described by.
pub const MAX_HOLDER_PIECES: usize = 8;
/// The most `[render] memory_limit_mb` and `--memory-limit` may say: 1 TiB.
pub const MAX_MEMORY_MIB: u64 = 1 << 20;
/// M47 runs a program again at most this many times.
pub const MAX_M47_REPEATS: u32 = 1000;
/// A plunge deeper than this many diameters is not a threshold any tool has.
pub const MAX_PLUNGE_FRACTION: f64 = 10.0;

/// What a real machine could mean, in its unit: a number past these is a mistake in the file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// The largest length or coordinate: 100 m, more than the longest gantry travels.
    pub length: f64,
    /// The smallest length (a tool, a cell, a stock's side): 1 µm.
    pub smallest: f64,
    /// The largest tool (diameter, flute length): 1 m, more than a face mill's.
    pub tool: f64,
    /// The slowest and fastest rapid, per minute: 1 mm/min to 1 km/min.
    pub rapid_rate: (f64, f64),
}

impl Bounds {
    pub fn of(units: Units) -> Bounds {
        match units {
            Units::Mm => Bounds { length: 100_000.0, smallest: 0.001, tool: 1000.0, rapid_rate: (1.0, 1_000_000.0) },
            Units::Inch => Bounds { length: 4000.0, smallest: 0.00004, tool: 40.0, rapid_rate: (0.04, 40_000.0) },
        }
    }
}

impl Default for Config {
    fn default() -> Config {
        Config {
            units: default_units(),
            offsets: WorkOffsets::default(),
            tools: vec![Tool::default_tool(default_units())],
            tool_sources: Vec::new(),
            dialect: DialectConfig::default(),
            machine: MachineSettings::default(),
            stock: StockConfig::default(),
            render: RenderConfig::default(),
            check: CheckConfig::default(),
            fixtures: Vec::new(),
            target: TargetConfig::default(),
        }
    }
}

fn default_units() -> Units {
    Units::Inch
}

impl Tool {
    /// Tool 1 when nothing describes it: a quarter-inch endmill, in `units`.
    pub fn default_tool(units: Units) -> Tool {
        let diameter = 0.25 * Units::Inch.factor_to(units);
        Tool::new(1, ToolKind::Endmill, diameter)
    }

    /// A tool of which only the kind and diameter are known.
    pub fn new(number: u32, kind: ToolKind, diameter: f64) -> Tool {
        Tool {
            number,
            kind,
            diameter,
            flute_length: None,
            tip_angle: None,
            shank_diameter: None,
            stick_out: None,
            holder: Vec::new(),
        }
    }

    /// The shank's diameter: as given, else the cutting diameter.
    pub fn shank(&self) -> f64 {
        self.shank_diameter.unwrap_or(self.diameter)
    }
}

/// `dialect = "lenient"`, or a `[dialect]` table with the name and what to
/// do with M codes the lenient dialect does not know.
#[derive(Clone, Debug, PartialEq)]
pub struct DialectConfig {
    pub name: Dialect,
    pub codes: CodeLists,
    /// `[machine] max_iterations` and `max_blocks`, here because the
    /// interpreter stage reads the dialect alone.
    pub limits: RunLimits,
    /// `[dialect] subroutine_path`: the folders an `o<name> call` looks in
    /// for `name.ngc` after the program's own, as LinuxCNC's
    /// `[RS274NGC] SUBROUTINE_PATH` (relative ones from the config's folder).
    pub subroutine_path: Vec<std::path::PathBuf>,
}

impl Default for DialectConfig {
    fn default() -> DialectConfig {
        Dialect::default().into()
    }
}

impl From<Dialect> for DialectConfig {
    fn from(name: Dialect) -> DialectConfig {
        DialectConfig { name, codes: CodeLists::default(), limits: RunLimits::default(), subroutine_path: Vec::new() }
    }
}

mod dialect_config {
    use serde::de::{self, Deserializer, MapAccess, Visitor};
    use serde::Deserialize;

    use super::DialectConfig;
    use crate::parse::CodeLists;
    use crate::statement::Dialect;

    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Table {
        #[serde(default)]
        name: Option<String>,
        #[serde(default)]
        pass_through: Vec<String>,
        #[serde(default)]
        ignore: Vec<String>,
        #[serde(default)]
        subroutine_path: Vec<std::path::PathBuf>,
    }

    fn name<E: de::Error>(name: &str) -> Result<Dialect, E> {
        match name {
            "strict" => Ok(Dialect::Strict),
            "lenient" => Ok(Dialect::Lenient),
            other => Err(E::custom(format!("dialect must be \"strict\" or \"lenient\", not \"{other}\""))),
        }
    }

    fn codes<E: de::Error>(list: &[String]) -> Result<Vec<u32>, E> {
        list.iter()
            .map(|text| {
                CodeLists::code(text)
                    .ok_or_else(|| E::custom(format!("`{text}` is not an M code: write them as \"M62\", \"M100\"")))
            })
            .collect()
    }

    struct DialectVisitor;

    impl<'de> Visitor<'de> for DialectVisitor {
        type Value = DialectConfig;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("\"strict\", \"lenient\", or a [dialect] table")
        }

        fn visit_str<E: de::Error>(self, text: &str) -> Result<DialectConfig, E> {
            Ok(name::<E>(text)?.into())
        }

        fn visit_map<M: MapAccess<'de>>(self, map: M) -> Result<DialectConfig, M::Error> {
            let table = Table::deserialize(de::value::MapAccessDeserializer::new(map))?;
            // A table alone says what to do with codes only the lenient dialect reads.
            let name = table.name.as_deref().map_or(Ok(Dialect::Lenient), name)?;
            let codes = CodeLists { pass_through: codes(&table.pass_through)?, ignore: codes(&table.ignore)? };
            let subroutine_path = table.subroutine_path;
            Ok(DialectConfig { name, codes, limits: super::RunLimits::default(), subroutine_path })
        }
    }

    impl<'de> Deserialize<'de> for DialectConfig {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<DialectConfig, D::Error> {
            d.deserialize_any(DialectVisitor)
        }
    }
}

mod units_name {
    use serde::{Deserialize, Deserializer};

    use crate::statement::Units;

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Units, D::Error> {
        match String::deserialize(d)?.as_str() {
            "inch" | "in" => Ok(Units::Inch),
            "mm" => Ok(Units::Mm),
            other => Err(serde::de::Error::custom(format!("units must be \"inch\" or \"mm\", not \"{other}\""))),
        }
    }
}

impl Config {
    /// Parses a `ger.toml`. The diagnostic's span points into `text`.
    pub fn from_toml(text: &str) -> Result<Config, Diagnostic> {
        let mut config: Config = toml::from_str(text).map_err(|err| {
            let span = err.span().map_or(Span::new(1, 1, 0), |range| span_of(text, range));
            Diagnostic::error(span, err.message().to_string())
        })?;
        if config.tools.is_empty() {
            config.tools = vec![Tool::default_tool(config.units)];
        } else {
            // The file's name is filled in when the table is settled for a program.
            let source = ToolSource::Config { file: String::new() };
            config.tool_sources = config.tools.iter().map(|t| (t.number, source.clone())).collect();
        }
        config.dialect.limits =
            RunLimits { iterations: config.machine.max_iterations, blocks: config.machine.max_blocks };
        config.validate(text)
    }

    fn validate(self, text: &str) -> Result<Config, Diagnostic> {
        let at = |steps: &[Step], message: String| Diagnostic::error(locate(text, steps), message);
        let bounds = Bounds::of(self.units);
        let unit = self.units.abbreviation();
        let (length, smallest, tool_size) = (bounds.length, bounds.smallest, bounds.tool);
        let coordinates = |v: &[f64; 3]| v.iter().all(|x| x.abs() <= length);
        let sizes = |v: &[f64; 3]| v.iter().all(|x| (smallest..=length).contains(x));
        let lengths = format!("from {} to {length} {unit}", quoted(smallest));
        if self.tools.len() > MAX_TOOLS {
            let message = format!("at most {MAX_TOOLS} tools fit in the tool table");
            return Err(at(&[Step::Key("tools"), Step::Index(MAX_TOOLS)], message));
        }
        for (i, tool) in self.tools.iter().enumerate() {
            let key = |name| [Step::Key("tools"), Step::Index(i), Step::Key(name)];
            let n = tool.number;
            if !(smallest..=tool_size).contains(&tool.diameter) {
                let message = format!("tool {n}: diameter must be from {} to {tool_size} {unit}", quoted(smallest));
                return Err(at(&key("diameter"), message));
            }
            if tool.tip_angle.is_some_and(|angle| !(angle > 0.0 && angle < 180.0)) {
                return Err(at(&key("tip_angle"), format!("tool {n}: tip_angle must be between 0 and 180 degrees")));
            }
            if tool.flute_length.is_some_and(|l| !(smallest..=tool_size).contains(&l)) {
                let message = format!("tool {n}: flute_length must be from {} to {tool_size} {unit}", quoted(smallest));
                return Err(at(&key("flute_length"), message));
            }
            if tool.shank_diameter.is_some_and(|d| !(smallest..=tool_size).contains(&d)) {
                let message =
                    format!("tool {n}: shank_diameter must be from {} to {tool_size} {unit}", quoted(smallest));
                return Err(at(&key("shank_diameter"), message));
            }
            if let Some(stick_out) = tool.stick_out {
                let flutes = tool.flute_length.unwrap_or(0.0);
                if !(stick_out > flutes && stick_out <= tool_size) {
                    let message = format!(
                        "tool {n}: stick_out must be longer than the flutes ({} {unit}) and at most {tool_size} {unit}",
                        quoted(flutes)
                    );
                    return Err(at(&key("stick_out"), message));
                }
            }
            if !tool.holder.is_empty() && tool.stick_out.is_none() {
                let message = format!("tool {n}: a holder needs the tool's stick_out (from its tip to the holder)");
                return Err(at(&key("holder"), message));
            }
            if tool.holder.len() > MAX_HOLDER_PIECES {
                let message = format!("tool {n}: a holder has at most {MAX_HOLDER_PIECES} pieces");
                return Err(at(
                    &[Step::Key("tools"), Step::Index(i), Step::Key("holder"), Step::Index(MAX_HOLDER_PIECES)],
                    message,
                ));
            }
            for (p, piece) in tool.holder.iter().enumerate() {
                let steps = [Step::Key("tools"), Step::Index(i), Step::Key("holder"), Step::Index(p)];
                let size = |x: f64| (smallest..=tool_size).contains(&x);
                let form = match (piece.diameter, piece.bottom, piece.top) {
                    (Some(d), None, None) => size(d),
                    (None, Some(bottom), Some(top)) => size(bottom) && size(top),
                    _ => false,
                };
                if !form || !size(piece.length) {
                    let message = format!(
                        "tool {n}: holder piece {} must be {{ diameter, length }} or {{ bottom, top, length }}, \
                         each from {} to {tool_size} {unit}",
                        p + 1,
                        quoted(smallest)
                    );
                    return Err(at(&steps, message));
                }
            }
            if self.tools[..i].iter().any(|t| t.number == n) {
                return Err(at(&key("number"), format!("tool {n} is in the tool table twice")));
            }
        }
        let offsets = &self.offsets;
        let names = ["G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"];
        for (name, entry) in names.into_iter().zip(1..) {
            if !coordinates(&offsets.entry(entry)) {
                let message = format!("[offsets] {name} must be three coordinates within ±{length} {unit}");
                return Err(at(&[Step::Key("offsets"), Step::Key(name)], message));
            }
        }
        if let Some(i) = offsets.extended.iter().position(|entry| !coordinates(entry)) {
            let message = format!("[offsets] G54.1 P{} must be three coordinates within ±{length} {unit}", i + 1);
            return Err(at(&[Step::Key("offsets"), Step::Key("G54.1"), Step::Index(i)], message));
        }
        let stock = &self.stock;
        let key = |table, name| [Step::Key(table), Step::Key(name)];
        if stock.size.is_some() && stock.margin.is_some() {
            let message = "[stock] takes size (with origin) or margin, not both".to_string();
            return Err(at(&key("stock", "margin"), message));
        }
        if stock.size.is_some_and(|size| !sizes(&size)) {
            return Err(at(&key("stock", "size"), format!("[stock] size must be three lengths {lengths}")));
        }
        if stock.origin.is_some() && stock.size.is_none() {
            return Err(at(&key("stock", "origin"), "[stock] origin needs a size".to_string()));
        }
        if stock.origin.is_some_and(|o| !coordinates(&o)) {
            let message = format!("[stock] origin must be three coordinates within ±{length} {unit}");
            return Err(at(&key("stock", "origin"), message));
        }
        // A margin is what is left round a cut, not a block of its own: at most a tool's size.
        if stock.margin.is_some_and(|m| !(0.0..=tool_size).contains(&m)) {
            return Err(at(&key("stock", "margin"), format!("[stock] margin must be from 0 to {tool_size} {unit}")));
        }
        let (fewest, most) = (1.0 / length, 1.0 / smallest);
        if self.render.scale.is_some_and(|s| !(fewest..=most).contains(&s)) {
            let message = format!(
                "[render] scale must be from {} to {} cells per {unit} (cells from {length} down to {} {unit})",
                quoted(fewest),
                quoted(most),
                quoted(smallest)
            );
            return Err(at(&key("render", "scale"), message));
        }
        if self.render.memory_limit_mb.is_some_and(|m| !(1..=MAX_MEMORY_MIB).contains(&m)) {
            let message = format!("[render] memory_limit_mb must be from 1 to {MAX_MEMORY_MIB} (1 TiB)");
            return Err(at(&key("render", "memory_limit_mb"), message));
        }
        let machine = &self.machine;
        if !coordinates(&machine.second_reference) {
            let message = format!("[machine] g30 must be three coordinates within ±{length} {unit}");
            return Err(at(&key("machine", "g30"), message));
        }
        if machine.m47_repeats > MAX_M47_REPEATS {
            let message = format!("[machine] m47_repeats must be from 0 to {MAX_M47_REPEATS}");
            return Err(at(&key("machine", "m47_repeats"), message));
        }
        for (name, limit) in [("max_iterations", machine.max_iterations), ("max_blocks", machine.max_blocks)] {
            if !(1..=RUN_LIMIT_BOUND).contains(&limit) {
                let message = format!("[machine] {name} must be from 1 to {RUN_LIMIT_BOUND}");
                return Err(at(&key("machine", name), message));
            }
        }
        if machine.travel.is_some_and(|travel| !sizes(&travel)) {
            return Err(at(&key("machine", "travel"), format!("[machine] travel must be three lengths {lengths}")));
        }
        if machine.home.is_some() && machine.travel.is_none() {
            return Err(at(&key("machine", "home"), "[machine] home needs a travel".to_string()));
        }
        if let (Some(home), Some(travel)) = (machine.home, machine.travel) {
            if (0..3).any(|i| !(home[i] >= 0.0 && home[i] <= travel[i])) {
                return Err(at(&key("machine", "home"), "[machine] home must lie within the travel".to_string()));
            }
        }
        let (slowest, fastest) = bounds.rapid_rate;
        if machine.rapid_rate.is_some_and(|r| !(slowest..=fastest).contains(&r)) {
            let message = format!("[machine] rapid_rate must be from {} to {fastest} {unit}/min", quoted(slowest));
            return Err(at(&key("machine", "rapid_rate"), message));
        }
        if machine.default_feed.is_some_and(|f| !(slowest..=fastest).contains(&f)) {
            let message = format!("[machine] default_feed must be from {} to {fastest} {unit}/min", quoted(slowest));
            return Err(at(&key("machine", "default_feed"), message));
        }
        let least = self.least_spline_tolerance();
        if machine.spline_tolerance.is_some_and(|t| !(least..=tool_size).contains(&t)) {
            let d = self.units.decimals();
            let message = format!(
                "[machine] spline_tolerance must be at least {least:.d$} {unit}, twice the output's resolution, \
                 and at most {tool_size} {unit}"
            );
            return Err(at(&key("machine", "spline_tolerance"), message));
        }
        if let Some(motion) = &machine.motion {
            motion.validate(self.units, &at)?;
        }
        let target = &self.target;
        if target.program_number.is_some_and(|n| !(1..=9999).contains(&n)) {
            let message = "[target] program_number must be from 1 to 9999, as a Fanuc's O number".to_string();
            return Err(at(&key("target", "program_number"), message));
        }
        if let Some((h, _)) = target.tool_lengths.iter().find(|(_, l)| !l.is_finite() || l.abs() > tool_size) {
            let message = format!("[target] tool_lengths: H{h} must be within ±{tool_size} {unit}");
            return Err(at(&key("target", "tool_lengths"), message));
        }
        // A tool change block goes to the controller as it is: one that could not be a line of G-code is a mistake.
        if target
            .tool_change
            .as_ref()
            .is_some_and(|block| !block.chars().all(|c| c == '\n' || (' '..='~').contains(&c)))
        {
            let message = "[target] tool_change must be printable ASCII lines".to_string();
            return Err(at(&key("target", "tool_change"), message));
        }
        if self.check.min_arc_radius.is_some_and(|r| !(0.0..=tool_size).contains(&r)) {
            let message = format!("[check] min_arc_radius must be from 0 to {tool_size} {unit}");
            return Err(at(&key("check", "min_arc_radius"), message));
        }
        if self.check.plunge_fraction.is_some_and(|f| !(f > 0.0 && f <= MAX_PLUNGE_FRACTION)) {
            let message =
                format!("[check] plunge_fraction must be above 0 and at most {MAX_PLUNGE_FRACTION} (diameters)");
            return Err(at(&key("check", "plunge_fraction"), message));
        }
        if self.check.clearance.is_some_and(|c| !(0.0..=tool_size).contains(&c)) {
            let message = format!("[check] clearance must be from 0 to {tool_size} {unit}");
            return Err(at(&key("check", "clearance"), message));
        }
        if self.fixtures.len() > MAX_FIXTURES {
            let message = format!("at most {MAX_FIXTURES} fixtures may be listed");
            return Err(at(&[Step::Key("fixtures"), Step::Index(MAX_FIXTURES)], message));
        }
        for (i, fixture) in self.fixtures.iter().enumerate() {
            let sized = |x: Option<f64>| x.is_some_and(|x| (smallest..=length).contains(&x));
            let fits = match (fixture.min, fixture.max, fixture.centre) {
                (Some(min), Some(max), None) => {
                    fixture.diameter.is_none()
                        && fixture.height.is_none()
                        && coordinates(&min)
                        && coordinates(&max)
                        && (0..3).all(|a| sized(Some(max[a] - min[a])))
                }
                (None, None, Some(centre)) => coordinates(&centre) && sized(fixture.diameter) && sized(fixture.height),
                _ => false,
            };
            if !fits {
                let message = format!(
                    "fixture \"{}\" must be a box (min and max, max above min on every axis) or an upright \
                     cylinder (centre, diameter, height), within ±{length} {unit}",
                    fixture.name
                );
                return Err(at(&[Step::Key("fixtures"), Step::Index(i)], message));
            }
        }
        Ok(self)
    }

    /// How near a shank or holder may pass the stock, in machine units.
    pub fn clearance(&self) -> f64 {
        self.check.clearance.unwrap_or(match self.units {
            Units::Inch => 0.02,
            Units::Mm => 0.5,
        })
    }

    /// The stock's margin in machine units: as configured, or 0.1 in / 2.5 mm.
    pub fn stock_margin(&self) -> f64 {
        self.stock.margin.unwrap_or(match self.units {
            Units::Inch => 0.1,
            Units::Mm => 2.5,
        })
    }

    /// The box the machine's axes can reach, in machine coordinates, if `[machine] travel` says.
    pub fn travel_box(&self) -> Option<([f64; 3], [f64; 3])> {
        let travel = self.machine.travel?;
        let home = self.machine.home.unwrap_or([0.0, 0.0, travel[2]]);
        Some((std::array::from_fn(|i| -home[i]), std::array::from_fn(|i| travel[i] - home[i])))
    }

    /// G00's speed in machine units per minute.
    pub fn rapid_rate(&self) -> f64 {
        self.machine.rapid_rate.unwrap_or(match self.units {
            Units::Inch => 200.0,
            Units::Mm => 5000.0,
        })
    }

    /// How the machine moves: `[machine.motion]`, or without it the
    /// `grbl-default` preset in the machine's unit.
    pub fn motion_profile(&self) -> MotionProfile {
        match &self.machine.motion {
            Some(motion) => motion.profile(self.units, true),
            None => MotionConfig::default().profile(self.units, false),
        }
    }

    /// How far a spline's arcs and lines may stray from it, in machine units.
    pub fn spline_tolerance(&self) -> f64 {
        self.machine.spline_tolerance.unwrap_or(match self.units {
            Units::Inch => 0.001,
            Units::Mm => 0.02,
        })
    }

    /// The output rounds coordinates to its last decimal: a tolerance must leave room for that.
    fn least_spline_tolerance(&self) -> f64 {
        2.0 * 10f64.powi(-(self.units.decimals() as i32))
    }

    pub fn min_arc_radius(&self) -> f64 {
        self.check.min_arc_radius.unwrap_or(2.0 * self.units.arc_tolerance())
    }

    pub fn plunge_fraction(&self) -> f64 {
        self.check.plunge_fraction.unwrap_or(0.5)
    }

    pub fn tool(&self, number: u32) -> Option<&Tool> {
        self.tools.iter().find(|t| t.number == number)
    }

    /// Whether the tool table is the file's `[[tools]]`, which nothing the program says replaces.
    pub fn has_tool_table(&self) -> bool {
        self.tool_sources.iter().any(|(_, source)| matches!(source, ToolSource::Config { .. }))
    }

    /// Where tool `number` came from, once the table is settled.
    pub fn tool_source(&self, number: u32) -> Option<&ToolSource> {
        self.tool_sources.iter().find(|(n, _)| *n == number).map(|(_, source)| source)
    }
}

/// One step to a key in a TOML document: a table's key, or an array's element.
#[derive(Clone, Copy, Debug)]
pub enum Step {
    Key(&'static str),
    Index(usize),
}

/// Where `steps` lead in `text`: from the last key to the end of its value
/// (an array element's own span when the last step is an index). The
/// start of the file if they lead nowhere (a default, not written in it).
pub fn locate(text: &str, steps: &[Step]) -> Span {
    use toml::de::{DeTable, DeValue};
    let nowhere = Span::new(1, 1, 0);
    let Ok(root) = DeTable::parse(text) else { return nowhere };
    let mut table = Some(root.get_ref());
    let mut array = None;
    let mut start = 0;
    let mut end = 0;
    for step in steps {
        let value = match *step {
            Step::Key(name) => {
                let Some((key, value)) = table.and_then(|t| t.iter().find(|(key, _)| key.get_ref() == name)) else {
                    return nowhere;
                };
                start = key.span().start;
                value
            }
            Step::Index(i) => {
                let Some(value) = array.and_then(|a: &toml::de::DeArray| a.get(i)) else { return nowhere };
                start = value.span().start;
                value
            }
        };
        end = value.span().end;
        (table, array) = match value.get_ref() {
            DeValue::Table(t) => (Some(t), None),
            DeValue::Array(a) => (None, Some(a)),
            _ => (None, None),
        };
    }
    span_of(text, start..end.max(start))
}

/// A bound as the messages quote it: no exponent, no trailing zeros.
pub fn quoted(x: f64) -> String {
    let text = format!("{x:.6}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn span_of(text: &str, range: std::ops::Range<usize>) -> Span {
    let start = range.start.min(text.len());
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let line = text[..start].matches('\n').count() + 1;
    let line_end = text[start..].find('\n').map_or(text.len(), |i| start + i);
    let len = range.end.min(line_end).saturating_sub(start);
    Span::new(line as u32, (start - line_start) as u32 + 1, len as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_file_means_inch_and_a_quarter_inch_endmill() {
        let config = Config::from_toml("").unwrap();
        assert_eq!(config, Config::default());
        assert_eq!(config.units, Units::Inch);
        assert_eq!(config.tool(1).unwrap().diameter, 0.25);
    }

    #[test]
    fn the_default_tool_is_a_quarter_inch_in_a_mm_machine_too() {
        let config = Config::from_toml("units = \"mm\"\n").unwrap();
        assert_eq!(config.tool(1).unwrap().diameter, 6.35);
        assert!(!config.has_tool_table());
        let config = Config::from_toml("[[tools]]\nnumber = 2\nkind = \"drill\"\ndiameter = 0.25\n").unwrap();
        assert!(config.has_tool_table() && config.tool(1).is_none());
    }

    #[test]
    fn a_full_file_parses() {
        let text = r#"
units = "mm"
dialect = "lenient"
[machine]
g30 = [0, 0, 50]
[offsets]
G54 = [10.0, 20.0, -5.0]
G59 = [1, 2, 3]

[[tools]]
number = 3
kind = "center-drill"
diameter = 6.0
tip_angle = 90
"#;
        let config = Config::from_toml(text).unwrap();
        assert_eq!(config.units, Units::Mm);
        assert_eq!(config.dialect.name, Dialect::Lenient);
        assert_eq!(config.machine.second_reference, [0.0, 0.0, 50.0]);
        assert_eq!(config.offsets.entry(1), [10.0, 20.0, -5.0]);
        assert_eq!(config.offsets.entry(2), [0.0; 3]);
        assert_eq!(config.offsets.entry(6), [1.0, 2.0, 3.0]);
        assert_eq!(config.tool(3).unwrap().kind, ToolKind::CenterDrill);
        assert!(config.tool(1).is_none());
    }

    #[test]
    fn a_tool_assembly_and_fixtures_parse() {
        let text = r#"
units = "mm"
[check]
clearance = 1
[[tools]]
number = 2
kind = "endmill"
diameter = 3
flute_length = 8
shank_diameter = 6
stick_out = 30
holder = [{ bottom = 20, top = 30, length = 10 }, { diameter = 40, length = 20 }]
[[fixtures]]
name = "left jaw"
min = [-20, 0, -20]
max = [0, 50, 5]
coordinates = "machine"
[[fixtures]]
name = "bolt"
centre = [50, 60, 0]
diameter = 10
height = 6
"#;
        let config = Config::from_toml(text).unwrap();
        let tool = config.tool(2).unwrap();
        assert_eq!((tool.shank(), tool.stick_out), (6.0, Some(30.0)));
        assert_eq!(tool.holder.iter().map(HolderPiece::ends).collect::<Vec<_>>(), [(20.0, 30.0), (40.0, 40.0)]);
        assert_eq!(config.clearance(), 1.0);
        assert_eq!(config.fixtures[0].coordinates, Coordinates::Machine);
        assert_eq!(config.fixtures[1].coordinates, Coordinates::Program);
        // The defaults: the shank is the cutting diameter; clearance 0.5 mm or 0.02 in.
        let config = Config::from_toml("units = \"mm\"\n").unwrap();
        assert_eq!(config.tool(1).unwrap().shank(), 6.35);
        assert_eq!(config.clearance(), 0.5);
        assert_eq!(Config::default().clearance(), 0.02);
    }

    #[test]
    fn errors_name_the_key_and_line() {
        let err = Config::from_toml("units = \"mm\"\n[offsets]\nG60 = [1, 2, 3]\n").unwrap_err();
        assert_eq!(err.span.line, 3);
        assert!(err.message.contains("G60"), "{}", err.message);

        let err = Config::from_toml("units = \"furlong\"\n").unwrap_err();
        assert_eq!(err.span.line, 1);
        assert!(err.message.contains("\"inch\" or \"mm\""), "{}", err.message);

        let err = Config::from_toml("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = -1\n").unwrap_err();
        assert_eq!(err.span.line, 4);
    }

    #[test]
    fn stock_and_render_default_to_a_margin_and_no_scale() {
        let config = Config::from_toml("").unwrap();
        assert_eq!(config.stock, StockConfig::default());
        assert_eq!(config.stock_margin(), 0.1);
        assert_eq!(Config::from_toml("units = \"mm\"").unwrap().stock_margin(), 2.5);
        assert_eq!(config.render, RenderConfig::default());
    }

    #[test]
    fn stock_by_size_and_origin_or_by_margin() {
        let config = Config::from_toml("[stock]\nsize = [100, 80, 20]\norigin = [0, 0, 20]\n").unwrap();
        assert_eq!(config.stock.size, Some([100.0, 80.0, 20.0]));
        assert_eq!(config.stock.origin, Some([0.0, 0.0, 20.0]));
        let config = Config::from_toml("[stock]\nmargin = 0.5\n[render]\nscale = 200\nmemory_limit_mb = 64\n").unwrap();
        assert_eq!(config.stock_margin(), 0.5);
        assert_eq!(config.render.scale, Some(200.0));
        assert_eq!(config.render.memory_limit_mb, Some(64));
    }

    #[test]
    fn errors_point_at_the_key_in_its_own_table() {
        let at = |text: &str| {
            let Span { line, col, len } = Config::from_toml(text).unwrap_err().span;
            (line, col, len)
        };
        // The second tool's diameter, not the first line that starts with `diameter`.
        let two = "[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 1\n\n[[tools]]\nnumber = 2\nkind = \"drill\"\n  diameter = 0\n";
        assert_eq!(at(two), (9, 3, 12));
        // A dotted key, an inline table: the key itself.
        assert_eq!(at("render.scale = 1e12\n"), (1, 8, 12));
        assert_eq!(at("stock = { size = [0, 1, 1] }\n"), (1, 11, 16));
        // The 21st [[tools]] header for a table over 20.
        let many: String =
            (1..=21).map(|n| format!("[[tools]]\nnumber = {n}\nkind = \"endmill\"\ndiameter = 1\n")).collect();
        assert_eq!(at(&many).0, 81);
    }

    #[test]
    fn bad_stock_and_render_settings_are_errors() {
        for (text, line, words) in [
            ("[stock]\nsize = [1, 1, 1]\nmargin = 1\n", 3, "not both"),
            ("[stock]\nsize = [1, 0, 1]\n", 2, "from 0.00004 to 4000 in"),
            ("[stock]\norigin = [1, 0, 1]\n", 2, "needs a size"),
            ("[stock]\nmargin = -1\n", 2, "from 0 to 40 in"),
            ("[render]\nscale = 0\n", 2, "cells per in"),
            ("[render]\nmemory_limit_mb = 0\n", 2, "from 1 to 1048576"),
            ("units = \"mm\"\n[machine]\nm47_repeats = 1000000\n", 3, "from 0 to 1000"),
            ("[machine]\nmax_iterations = 0\n", 2, "from 1 to 1000000000"),
            ("[machine]\nmax_blocks = 1000000001\n", 2, "max_blocks must be from 1 to 1000000000"),
            ("units = \"mm\"\n[machine]\nrapid_rate = 1e-300\n", 3, "from 1 to 1000000 mm/min"),
            ("[machine]\ng30 = [0, 0, 1e300]\n", 2, "within ±4000 in"),
            ("[machine]\ndefault_feed = 0\n", 2, "default_feed must be from 0.04 to 40000 in/min"),
            ("[offsets]\n\"G59.3\" = [0, 0, 1e300]\n", 2, "G59.3 must be"),
            ("[offsets]\n\"G54.1\" = [\n  [1, 2, 3],\n  [0, 1e300, 0],\n]\n", 4, "G54.1 P2 must be"),
            ("[check]\nplunge_fraction = 1e9\n", 2, "at most 10"),
            ("[check]\nmin_arc_radius = 1e300\n", 2, "from 0 to 40 in"),
            ("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 1\nflute_length = 1e300\n", 5, "flute_length"),
            ("[machine]\nspline_tolerance = 0.0001\n", 2, "at least 0.0002 in"),
            ("units = \"mm\"\n[machine]\nspline_tolerance = -1\n", 3, "at least 0.002 mm"),
            ("[machine]\nspline_tolerance = 1e300\n", 2, "at most 40 in"),
            ("[[tools]]\nnumber = 1\nkind = \"drill\"\ndiameter = 1\ntip_angle = 180\n", 5, "tip_angle"),
            ("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 1\nshank_diameter = 0\n", 5, "shank_diameter"),
            (
                "[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 1\nflute_length = 1\nstick_out = 0.5\n",
                6,
                "longer than the flutes (1 in)",
            ),
            (
                "[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 1\nholder = [{ diameter = 2, length = 1 }]\n",
                5,
                "needs the tool's stick_out",
            ),
            (
                "[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 1\nstick_out = 2\n\
                 holder = [\n  { diameter = 2, length = 1 },\n  { diameter = 2, bottom = 1, length = 1 },\n]\n",
                8,
                "holder piece 2 must be",
            ),
            ("[check]\nclearance = -0.1\n", 2, "clearance must be from 0 to 40 in"),
            ("[[fixtures]]\nname = \"jaw\"\nmin = [0, 0, 0]\nmax = [1, 0, 1]\n", 1, "fixture \"jaw\" must be"),
            ("[[fixtures]]\nname = \"bolt\"\ncentre = [0, 0, 0]\ndiameter = 1\n", 1, "upright"),
        ] {
            let err = Config::from_toml(text).unwrap_err();
            assert_eq!(err.span.line, line, "{text}");
            assert!(err.message.contains(words), "{}", err.message);
        }
    }
}
