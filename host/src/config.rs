//! The machine, as `ger.toml` describes it. Every field has a default, so
//! no file at all is a valid configuration.

use serde::{Deserialize, Serialize};

use crate::check::Rule;
use crate::diag::{Diagnostic, Span};
use crate::statement::{Dialect, Units};
use crate::tools::ToolSource;

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
    /// what CAM programs and controllers commonly emit.
    #[serde(default, with = "dialect_name")]
    pub dialect: Dialect,
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
}

impl Default for MachineSettings {
    fn default() -> MachineSettings {
        MachineSettings { second_reference: [0.0; 3], m47_repeats: one(), travel: None, home: None, rapid_rate: None }
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
}

fn one() -> u32 {
    1
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
}

impl WorkOffsets {
    /// Entry 1..=6 (G54..G59); an entry not in the file is (0, 0, 0).
    pub fn entry(&self, entry: u8) -> [f64; 3] {
        let entries = [self.g54, self.g55, self.g56, self.g57, self.g58, self.g59];
        entries[usize::from(entry - 1)].unwrap_or([0.0; 3])
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
}

pub const MAX_TOOLS: usize = 20;

impl Default for Config {
    fn default() -> Config {
        Config {
            units: default_units(),
            offsets: WorkOffsets::default(),
            tools: vec![Tool::default_tool(default_units())],
            tool_sources: Vec::new(),
            dialect: Dialect::Strict,
            machine: MachineSettings::default(),
            stock: StockConfig::default(),
            render: RenderConfig::default(),
            check: CheckConfig::default(),
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
        Tool { number: 1, kind: ToolKind::Endmill, diameter, flute_length: None, tip_angle: None }
    }
}

mod dialect_name {
    use serde::{Deserialize, Deserializer};

    use crate::statement::Dialect;

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Dialect, D::Error> {
        match String::deserialize(d)?.as_str() {
            "strict" => Ok(Dialect::Strict),
            "lenient" => Ok(Dialect::Lenient),
            other => {
                Err(serde::de::Error::custom(format!("dialect must be \"strict\" or \"lenient\", not \"{other}\"")))
            }
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
        config.validate(text)
    }

    fn validate(self, text: &str) -> Result<Config, Diagnostic> {
        let at_key = |key: &str| {
            let line = text.lines().position(|l| l.trim_start().starts_with(key)).unwrap_or(0);
            Span::new(line as u32 + 1, 1, 0)
        };
        if self.tools.len() > MAX_TOOLS {
            return Err(Diagnostic::error(
                at_key("[[tools]]"),
                format!("at most {MAX_TOOLS} tools fit in the tool table"),
            ));
        }
        for (i, tool) in self.tools.iter().enumerate() {
            if !(tool.diameter > 0.0 && tool.diameter.is_finite()) {
                return Err(Diagnostic::error(
                    at_key("diameter"),
                    format!("tool {}: diameter must be greater than zero", tool.number),
                ));
            }
            if let Some(angle) = tool.tip_angle {
                if !(angle > 0.0 && angle < 180.0) {
                    return Err(Diagnostic::error(
                        at_key("tip_angle"),
                        format!("tool {}: tip_angle must be between 0 and 180 degrees", tool.number),
                    ));
                }
            }
            if tool.flute_length.is_some_and(|l| !(l > 0.0 && l.is_finite())) {
                return Err(Diagnostic::error(
                    at_key("flute_length"),
                    format!("tool {}: flute_length must be greater than zero", tool.number),
                ));
            }
            if self.tools[..i].iter().any(|t| t.number == tool.number) {
                return Err(Diagnostic::error(
                    at_key("number"),
                    format!("tool {} is in the tool table twice", tool.number),
                ));
            }
        }
        let stock = &self.stock;
        let positive = |v: &[f64; 3]| v.iter().all(|x| *x > 0.0 && x.is_finite());
        if stock.size.is_some() && stock.margin.is_some() {
            return Err(Diagnostic::error(at_key("margin"), "[stock] takes size (with origin) or margin, not both"));
        }
        if stock.size.is_some_and(|size| !positive(&size)) {
            return Err(Diagnostic::error(at_key("size"), "[stock] size must be three lengths above zero"));
        }
        if stock.origin.is_some() && stock.size.is_none() {
            return Err(Diagnostic::error(at_key("origin"), "[stock] origin needs a size"));
        }
        if stock.origin.is_some_and(|o| o.iter().any(|x| !x.is_finite())) {
            return Err(Diagnostic::error(at_key("origin"), "[stock] origin must be three numbers"));
        }
        if stock.margin.is_some_and(|m| !(m >= 0.0 && m.is_finite())) {
            return Err(Diagnostic::error(at_key("margin"), "[stock] margin must be zero or more"));
        }
        if self.render.scale.is_some_and(|s| !(s > 0.0 && s.is_finite())) {
            return Err(Diagnostic::error(at_key("scale"), "[render] scale must be above zero (cells per unit)"));
        }
        let machine = &self.machine;
        if machine.travel.is_some_and(|travel| !positive(&travel)) {
            return Err(Diagnostic::error(at_key("travel"), "[machine] travel must be three lengths above zero"));
        }
        if machine.home.is_some() && machine.travel.is_none() {
            return Err(Diagnostic::error(at_key("home"), "[machine] home needs a travel"));
        }
        if let (Some(home), Some(travel)) = (machine.home, machine.travel) {
            if (0..3).any(|i| !(home[i] >= 0.0 && home[i] <= travel[i])) {
                return Err(Diagnostic::error(at_key("home"), "[machine] home must lie within the travel"));
            }
        }
        if machine.rapid_rate.is_some_and(|r| !(r > 0.0 && r.is_finite())) {
            return Err(Diagnostic::error(at_key("rapid_rate"), "[machine] rapid_rate must be above zero"));
        }
        if self.check.min_arc_radius.is_some_and(|r| !(r >= 0.0 && r.is_finite())) {
            return Err(Diagnostic::error(at_key("min_arc_radius"), "[check] min_arc_radius must be zero or more"));
        }
        if self.check.plunge_fraction.is_some_and(|f| !(f > 0.0 && f.is_finite())) {
            return Err(Diagnostic::error(at_key("plunge_fraction"), "[check] plunge_fraction must be above zero"));
        }
        if self.render.memory_limit_mb == Some(0) {
            return Err(Diagnostic::error(at_key("memory_limit_mb"), "[render] memory_limit_mb must be above zero"));
        }
        Ok(self)
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
        assert_eq!(config.dialect, Dialect::Lenient);
        assert_eq!(config.machine.second_reference, [0.0, 0.0, 50.0]);
        assert_eq!(config.offsets.entry(1), [10.0, 20.0, -5.0]);
        assert_eq!(config.offsets.entry(2), [0.0; 3]);
        assert_eq!(config.offsets.entry(6), [1.0, 2.0, 3.0]);
        assert_eq!(config.tool(3).unwrap().kind, ToolKind::CenterDrill);
        assert!(config.tool(1).is_none());
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
    fn bad_stock_and_render_settings_are_errors() {
        for (text, line, words) in [
            ("[stock]\nsize = [1, 1, 1]\nmargin = 1\n", 3, "not both"),
            ("[stock]\nsize = [1, 0, 1]\n", 2, "above zero"),
            ("[stock]\norigin = [1, 0, 1]\n", 2, "needs a size"),
            ("[stock]\nmargin = -1\n", 2, "zero or more"),
            ("[render]\nscale = 0\n", 2, "above zero"),
            ("[[tools]]\nnumber = 1\nkind = \"drill\"\ndiameter = 1\ntip_angle = 180\n", 5, "tip_angle"),
        ] {
            let err = Config::from_toml(text).unwrap_err();
            assert_eq!(err.span.line, line, "{text}");
            assert!(err.message.contains(words), "{}", err.message);
        }
    }
}
