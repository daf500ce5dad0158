//! `[machine.motion]`: how the machine moves, for the run time `ger check`
//! plans (the `ger-motion` crate). A profile is layered: a preset (GRBL
//! 1.1h's defaults unless another is named), then the GRBL `$`-settings of
//! `grbl_settings` over it, then the keys written in the table over both.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::{quoted, Bounds, Step};
use crate::diag::{Diagnostic, Span};
use crate::statement::Units;

/// `[machine.motion]` as the file writes it; every key is optional.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionConfig {
    /// The profile under everything else: default `grbl-default`.
    pub preset: Option<Preset>,
    /// A file of GRBL settings as `$$` prints them (`$110=5000.000`), read
    /// over the preset; relative to the config's folder.
    pub grbl_settings: Option<PathBuf>,
    /// Each axis's fastest speed (its rapid), machine units per minute.
    pub max_rate: Option<[f64; 3]>,
    /// Each axis's acceleration, machine units per second squared.
    pub acceleration: Option<[f64; 3]>,
    /// How far the path may stray at a corner taken without stopping
    /// (GRBL's `$11`), machine units.
    pub junction_deviation: Option<f64>,
    /// How far the lines an arc is run as may stray from it (GRBL's `$12`), machine units.
    pub arc_tolerance: Option<f64>,
    /// Steps per unit of each axis (GRBL's `$100`-`$102`): the controller
    /// moves between whole steps, and drops a move of none.
    pub steps_per_unit: Option<[f64; 3]>,
    /// The controller's planner buffer (GRBL: 16), which plans one move
    /// fewer than it has slots, as GRBL's ring keeps one empty.
    pub planner_blocks: Option<u32>,
    /// Seconds a tool change (M06) takes.
    pub tool_change_time: Option<f64>,
    /// Dwells (G04) are rounded up to a multiple of this many seconds (GRBL:
    /// 0.05); 0 runs them as programmed.
    pub dwell_multiple: Option<f64>,
    /// The slowest the controller steps, in steps per second of the axis
    /// that steps most: a move programmed slower runs at this rate. 0: no
    /// such floor.
    pub slowest_step_rate: Option<f64>,
    /// The step timer's clock, Hz: each tick of the timer takes one cycle
    /// more than the step rate asks, as a timer that counts to its compare
    /// value inclusive does (GRBL on a 16 MHz AVR: 16000000). 0: exact timing.
    pub step_clock: Option<f64>,
    /// The settings read from `grbl_settings` (the engine reads the file).
    #[serde(skip)]
    pub grbl: Option<GrblSettings>,
}

/// A named profile.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    /// GRBL 1.1h's defaults (`DEFAULTS_GENERIC`) with the rates and
    /// accelerations of the GRBL peer's default profile: X and Y at 5000
    /// mm/min and 500 mm/s², Z at 1000 mm/min and 200 mm/s², junction
    /// deviation 0.01 mm, arc tolerance 0.002 mm, a 16-block planner, dwells
    /// in steps of 50 ms, 250 steps per mm, and no step slower than a 16 MHz
    /// board's step timer goes ([`GRBL_SLOWEST_STEP_RATE`]), on its clock ([`GRBL_STEP_CLOCK`]).
    GrblDefault,
}

impl Preset {
    pub fn name(self) -> &'static str {
        match self {
            Preset::GrblDefault => "grbl-default",
        }
    }

    /// The preset's profile, in millimetres.
    fn profile(self) -> Machine {
        match self {
            Preset::GrblDefault => Machine {
                max_rate: [5000.0, 5000.0, 1000.0],
                acceleration: [500.0, 500.0, 200.0],
                steps_per_unit: [250.0; 3],
                junction_deviation: 0.01,
                arc_tolerance: 0.002,
                planner_blocks: 16,
                tool_change_time: 0.0,
                dwell_multiple: 0.05,
                slowest_step_rate: GRBL_SLOWEST_STEP_RATE,
                step_clock: GRBL_STEP_CLOCK,
            },
        }
    }
}

/// GRBL 1.1h's slowest step, steps per second: with its step smoothing
/// (AMASS) its timer ticks eight times a step, and a tick lasts at most
/// 65,535 cycles of its 16 MHz clock, plus the one every tick adds (as the
/// GRBL peer measures: a move below about 7.3 mm/min at 250 steps per mm
/// takes 8 × 65,536 cycles a step).
pub const GRBL_SLOWEST_STEP_RATE: f64 = GRBL_STEP_CLOCK / (8.0 * 65_536.0);

/// The clock of GRBL 1.1h's step timer on an Arduino Uno's AVR, Hz.
pub const GRBL_STEP_CLOCK: f64 = 16_000_000.0;

/// The numbers of a profile, without where they came from (serialised as
/// `ger check --format json` reports them).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Machine {
    /// Units per minute.
    pub max_rate: [f64; 3],
    /// Units per second squared.
    pub acceleration: [f64; 3],
    pub steps_per_unit: [f64; 3],
    pub junction_deviation: f64,
    pub arc_tolerance: f64,
    pub planner_blocks: usize,
    /// Seconds.
    pub tool_change_time: f64,
    /// Seconds; 0 for dwells as programmed.
    pub dwell_multiple: f64,
    /// Steps per second of the axis that steps most; 0 for none.
    pub slowest_step_rate: f64,
    /// Hz; 0 for exact step timing.
    pub step_clock: f64,
}

impl Machine {
    fn scaled(self, factor: f64) -> Machine {
        Machine {
            max_rate: self.max_rate.map(|v| v * factor),
            acceleration: self.acceleration.map(|v| v * factor),
            steps_per_unit: self.steps_per_unit.map(|v| v / factor),
            junction_deviation: self.junction_deviation * factor,
            arc_tolerance: self.arc_tolerance * factor,
            ..self
        }
    }
}

/// The profile the planner runs on, in the machine's unit, and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionProfile {
    pub machine: Machine,
    /// The preset under it.
    pub preset: Preset,
    /// The GRBL settings file read over the preset, as the config names it.
    pub grbl_settings: Option<PathBuf>,
    /// Whether `ger.toml` has a `[machine.motion]` table at all.
    pub configured: bool,
}

impl MotionConfig {
    /// The profile in `units`: the preset, the GRBL settings read over it,
    /// the keys over both.
    pub fn profile(&self, units: Units, configured: bool) -> MotionProfile {
        let preset = self.preset.unwrap_or(Preset::GrblDefault);
        let mut mm = preset.profile();
        if let Some(grbl) = &self.grbl {
            grbl.apply(&mut mm);
        }
        let mut machine = mm.scaled(Units::Mm.factor_to(units));
        let keys = self;
        machine.max_rate = keys.max_rate.unwrap_or(machine.max_rate);
        machine.acceleration = keys.acceleration.unwrap_or(machine.acceleration);
        machine.steps_per_unit = keys.steps_per_unit.unwrap_or(machine.steps_per_unit);
        machine.junction_deviation = keys.junction_deviation.unwrap_or(machine.junction_deviation);
        machine.arc_tolerance = keys.arc_tolerance.unwrap_or(machine.arc_tolerance);
        machine.planner_blocks = keys.planner_blocks.map_or(machine.planner_blocks, |n| n as usize);
        machine.tool_change_time = keys.tool_change_time.unwrap_or(machine.tool_change_time);
        machine.dwell_multiple = keys.dwell_multiple.unwrap_or(machine.dwell_multiple);
        machine.slowest_step_rate = keys.slowest_step_rate.unwrap_or(machine.slowest_step_rate);
        machine.step_clock = keys.step_clock.unwrap_or(machine.step_clock);
        MotionProfile { machine, preset, grbl_settings: self.grbl_settings.clone(), configured }
    }

    /// Holds every key to what a machine could mean, in `units`; the error
    /// is at the key, through `at`.
    pub(super) fn validate(&self, units: Units, at: &dyn Fn(&[Step], String) -> Diagnostic) -> Result<(), Diagnostic> {
        let limits = Limits::of(units);
        let key = |name| [Step::Key("machine"), Step::Key("motion"), Step::Key(name)];
        let axes = |name: &'static str, values: Option<[f64; 3]>, range: (f64, f64), what: &str| match values {
            Some(v) if v.iter().any(|x| !(range.0..=range.1).contains(x)) => Err(at(
                &key(name),
                format!("[machine.motion] {name} must be three {what} from {} to {}", quoted(range.0), quoted(range.1)),
            )),
            _ => Ok(()),
        };
        let unit = units.abbreviation();
        axes("max_rate", self.max_rate, limits.rate, &format!("speeds ({unit}/min, X Y Z)"))?;
        axes("acceleration", self.acceleration, limits.acceleration, &format!("accelerations ({unit}/s², X Y Z)"))?;
        axes("steps_per_unit", self.steps_per_unit, limits.steps, &format!("counts (steps per {unit}, X Y Z)"))?;
        let number = |name: &'static str, value: Option<f64>, range: (f64, f64), unit: &str| match value {
            Some(v) if !(range.0..=range.1).contains(&v) => Err(at(
                &key(name),
                format!("[machine.motion] {name} must be from {} to {} {unit}", quoted(range.0), quoted(range.1)),
            )),
            _ => Ok(()),
        };
        number("junction_deviation", self.junction_deviation, limits.junction_deviation, unit)?;
        number("arc_tolerance", self.arc_tolerance, limits.arc_tolerance, unit)?;
        number("tool_change_time", self.tool_change_time, (0.0, MAX_TOOL_CHANGE_TIME), "seconds")?;
        number("dwell_multiple", self.dwell_multiple, (0.0, MAX_DWELL_MULTIPLE), "seconds")?;
        number("slowest_step_rate", self.slowest_step_rate, (0.0, MAX_STEP_RATE), "steps per second")?;
        // A clock slower than a few kHz could not step at all.
        if self.step_clock.is_some_and(|hz| hz != 0.0 && !(MIN_STEP_CLOCK..=MAX_STEP_CLOCK).contains(&hz)) {
            let message = format!(
                "[machine.motion] step_clock must be 0 (exact timing) or from {} to {} Hz",
                quoted(MIN_STEP_CLOCK),
                quoted(MAX_STEP_CLOCK)
            );
            return Err(at(&key("step_clock"), message));
        }
        if self.planner_blocks.is_some_and(|n| !(2..=MAX_PLANNER_BLOCKS).contains(&n)) {
            let message = format!("[machine.motion] planner_blocks must be from 2 to {MAX_PLANNER_BLOCKS}");
            return Err(at(&key("planner_blocks"), message));
        }
        Ok(())
    }
}

/// The most moves a planner may look ahead: controllers plan 16 (GRBL on
/// an AVR) to a few hundred.
pub const MAX_PLANNER_BLOCKS: u32 = 1024;
/// A tool change longer than an hour is a pause, not a change.
const MAX_TOOL_CHANGE_TIME: f64 = 3600.0;
const MAX_DWELL_MULTIPLE: f64 = 10.0;
/// Step generators run up to a few MHz.
const MAX_STEP_RATE: f64 = 10_000_000.0;
/// Step timers run on clocks from a kHz (a PC's parallel port) to a few GHz.
const MIN_STEP_CLOCK: f64 = 1000.0;
const MAX_STEP_CLOCK: f64 = 10_000_000_000.0;

/// What a profile's numbers may be, in one unit.
struct Limits {
    rate: (f64, f64),
    acceleration: (f64, f64),
    junction_deviation: (f64, f64),
    arc_tolerance: (f64, f64),
    steps: (f64, f64),
}

impl Limits {
    /// Rates as `[machine] rapid_rate`; accelerations from 0.1 mm/s² to
    /// 100,000 mm/s² (10 g); a junction deviation up to 100 mm, an arc
    /// tolerance from 0.1 µm to 100 mm; from 0.01 to a million steps per mm.
    fn of(units: Units) -> Limits {
        let f = Units::Mm.factor_to(units);
        Limits {
            rate: Bounds::of(units).rapid_rate,
            acceleration: (0.1 * f, 100_000.0 * f),
            junction_deviation: (0.0, 100.0 * f),
            arc_tolerance: (0.0001 * f, 100.0 * f),
            steps: (0.01 / f, 1_000_000.0 / f),
        }
    }
}

/// GRBL's settings as `$$` prints them, the ones a profile takes (in
/// millimetres, as GRBL keeps them whatever `$13` says).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GrblSettings {
    values: Vec<(u32, f64)>,
}

/// The settings a profile takes: `$11`, `$12`, `$100`-`$102`, `$110`-`$112`, `$120`-`$122`.
const USED: [u32; 11] = [11, 12, 100, 101, 102, 110, 111, 112, 120, 121, 122];

impl GrblSettings {
    /// Reads `$N=value` lines. Blank lines, `ok`, comments (`(...)` after
    /// the value, `;` to the line's end) and settings a profile does not
    /// use are passed over; anything else is an error at its line and column.
    pub fn parse(text: &str) -> Result<GrblSettings, Diagnostic> {
        let mut values = Vec::new();
        for (index, raw) in text.lines().enumerate() {
            let line = (index + 1) as u32;
            let content = raw.split(';').next().unwrap_or("");
            let content = content.split('(').next().unwrap_or("");
            let start = content.len() - content.trim_start().len();
            let content = content.trim();
            let col = |offset: usize| (start + offset + 1) as u32;
            if content.is_empty() || content == "ok" {
                continue;
            }
            let bad = |offset: usize, len: usize, message: String| {
                Diagnostic::error(Span::new(line, col(offset), len.max(1) as u32), message).with_help(
                    "a GRBL settings file has lines as `$$` prints them: `$110=5000.000` (X max rate, mm/min)",
                )
            };
            let Some(rest) = content.strip_prefix('$') else {
                return Err(bad(0, content.len(), format!("`{content}` is not a GRBL setting")));
            };
            let Some((number, value)) = rest.split_once('=') else {
                return Err(bad(0, content.len(), format!("`{content}` has no `=` and value")));
            };
            let number_text = number.trim();
            let Ok(number) = number_text.parse::<u32>() else {
                return Err(bad(1, number.len(), format!("`${number_text}` is not a setting's number")));
            };
            let value_offset = 1 + rest.len() - rest[rest.find('=').unwrap_or(0) + 1..].len();
            let value_text = value.trim();
            let value_offset = value_offset + (value.len() - value.trim_start().len());
            let Some(value) = value_text.parse::<f64>().ok().filter(|v| v.is_finite()) else {
                return Err(bad(value_offset, value_text.len(), format!("`{value_text}` is not a number")));
            };
            if !USED.contains(&number) {
                continue;
            }
            if let Some(message) = out_of_range(number, value) {
                return Err(bad(value_offset, value_text.len(), message));
            }
            values.retain(|(n, _)| *n != number);
            values.push((number, value));
        }
        Ok(GrblSettings { values })
    }

    fn apply(&self, machine: &mut Machine) {
        for &(number, value) in &self.values {
            match number {
                11 => machine.junction_deviation = value,
                12 => machine.arc_tolerance = value,
                100..=102 => machine.steps_per_unit[(number - 100) as usize] = value,
                110..=112 => machine.max_rate[(number - 110) as usize] = value,
                120..=122 => machine.acceleration[(number - 120) as usize] = value,
                _ => {}
            }
        }
    }
}

/// Why a used setting's value is not one a machine could have, in millimetres.
fn out_of_range(number: u32, value: f64) -> Option<String> {
    let limits = Limits::of(Units::Mm);
    let (range, what) = match number {
        11 => (limits.junction_deviation, "$11 (junction deviation, mm)"),
        12 => (limits.arc_tolerance, "$12 (arc tolerance, mm)"),
        100..=102 => (limits.steps, "steps per mm ($100-$102)"),
        110..=112 => (limits.rate, "a max rate ($110-$112, mm/min)"),
        _ => (limits.acceleration, "an acceleration ($120-$122, mm/s²)"),
    };
    (!(range.0..=range.1).contains(&value))
        .then(|| format!("{what} must be from {} to {}", quoted(range.0), quoted(range.1)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;

    fn mm(text: &str) -> Config {
        Config::from_toml(&format!("units = \"mm\"\n{text}")).unwrap()
    }

    #[test]
    fn no_table_is_grbl_default_in_the_machine_unit() {
        let profile = mm("").motion_profile();
        assert_eq!(profile.preset, Preset::GrblDefault);
        assert!(!profile.configured);
        assert_eq!(profile.machine.max_rate, [5000.0, 5000.0, 1000.0]);
        assert_eq!(profile.machine.acceleration, [500.0, 500.0, 200.0]);
        assert_eq!(profile.machine.planner_blocks, 16);
        assert_eq!(profile.machine.dwell_multiple, 0.05);
        // An inch machine has the same machine, in inches.
        let inch = Config::from_toml("").unwrap().motion_profile().machine;
        assert!((inch.max_rate[0] - 5000.0 / 25.4).abs() < 1e-9);
        assert!((inch.acceleration[2] - 200.0 / 25.4).abs() < 1e-9);
        assert!((inch.junction_deviation - 0.01 / 25.4).abs() < 1e-12);
    }

    #[test]
    fn keys_override_the_preset_and_settings_the_preset() {
        let mut config = mm("[machine.motion]\npreset = \"grbl-default\"\nacceleration = [100, 200, 50]\n\
                             planner_blocks = 32\ntool_change_time = 20\ndwell_multiple = 0\n");
        let settings = GrblSettings::parse("$110=8000.000\n$120=250\n$11=0.020\n").unwrap();
        config.machine.motion.as_mut().unwrap().grbl = Some(settings);
        let profile = config.motion_profile();
        assert!(profile.configured);
        let m = profile.machine;
        assert_eq!(m.max_rate, [8000.0, 5000.0, 1000.0]);
        // The keys win over the settings file.
        assert_eq!(m.acceleration, [100.0, 200.0, 50.0]);
        assert_eq!(m.junction_deviation, 0.02);
        assert_eq!((m.planner_blocks, m.tool_change_time, m.dwell_multiple), (32, 20.0, 0.0));
    }

    #[test]
    fn grbl_settings_read_as_dollar_dollar_prints_them() {
        let text = "$0=10\n$1=25\n$11=0.010\n$12=0.002\n$13=0\n$100=250.000\n$110=5000.000\n$111=4000.000\n\
                    $112=500.000\n$120=10.000\n$121=20.000 (y accel, mm/sec^2)\n$122=30 ; z\n\nok\n";
        let settings = GrblSettings::parse(text).unwrap();
        let mut machine = Preset::GrblDefault.profile();
        settings.apply(&mut machine);
        assert_eq!(machine.max_rate, [5000.0, 4000.0, 500.0]);
        assert_eq!(machine.acceleration, [10.0, 20.0, 30.0]);
        assert_eq!((machine.junction_deviation, machine.arc_tolerance), (0.01, 0.002));
    }

    #[test]
    fn a_malformed_grbl_setting_is_an_error_at_its_line_and_column() {
        for (text, line, col, words) in [
            ("$110=5000\nG1 X10\n", 2, 1, "not a GRBL setting"),
            ("$110=5000\n  $111 5000\n", 2, 3, "no `=`"),
            ("$x10=5000\n", 1, 2, "not a setting's number"),
            ("$110=5000\n$111=fast\n", 2, 6, "`fast` is not a number"),
            ("$111= 1e999\n", 1, 7, "not a number"),
            ("$120=0\n", 1, 6, "acceleration ($120-$122, mm/s²) must be from 0.1 to 100000"),
            ("$110=-5\n", 1, 6, "max rate"),
            ("$12=0\n", 1, 5, "$12 (arc tolerance, mm)"),
        ] {
            let err = GrblSettings::parse(text).unwrap_err();
            assert_eq!((err.span.line, err.span.col), (line, col), "{text:?}: {}", err.message);
            assert!(err.message.contains(words), "{text:?}: {}", err.message);
        }
        // A setting a profile does not use is passed over whatever its value.
        assert!(GrblSettings::parse("$130=-1\n$32=1\n").is_ok());
    }

    #[test]
    fn bad_motion_keys_are_errors_at_the_key() {
        for (text, line, words) in [
            ("[machine.motion]\npreset = \"grbl\"\n", 2, "grbl-default"),
            (
                "[machine.motion]\nmax_rate = [5000, 0, 1000]\n",
                2,
                "max_rate must be three speeds (mm/min, X Y Z) from 1 to 1000000",
            ),
            ("[machine.motion]\nacceleration = [500, 500, 1e9]\n", 2, "from 0.1 to 100000"),
            ("[machine.motion]\njunction_deviation = -0.01\n", 2, "from 0 to 100 mm"),
            ("[machine.motion]\narc_tolerance = 0\n", 2, "from 0.0001 to 100 mm"),
            ("[machine.motion]\nplanner_blocks = 1\n", 2, "from 2 to 1024"),
            ("[machine.motion]\ntool_change_time = -1\n", 2, "from 0 to 3600 seconds"),
            ("[machine.motion]\ndwell_multiple = 11\n", 2, "from 0 to 10 seconds"),
            ("[machine.motion]\nspeed = 1\n", 2, "unknown field"),
            ("[machine]\nmotion.max_rate = [1, 1, 1e12]\n", 2, "max_rate"),
        ] {
            let err = Config::from_toml(&format!("units = \"mm\"\n{text}")).unwrap_err();
            assert_eq!(err.span.line, line + 1, "{text}: {}", err.message);
            assert!(err.message.contains(words), "{text}: {}", err.message);
        }
        // In inches the bounds are in inches.
        let err = Config::from_toml("[machine.motion]\nmax_rate = [200, 200, 50000]\n").unwrap_err();
        assert!(err.message.contains("from 0.04 to 40000"), "{}", err.message);
    }
}
