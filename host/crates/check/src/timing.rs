//! The planned run time (ger-motion): in all, by tool, by subprogram or
//! wizard call, and for `ger view` by program line.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use serde::Serialize;

use ger_core::config::{Config, MotionProfile};
use ger_core::diag::Origin;
use ger_core::statement::{Kind, Machine, Statement};
use ger_motion::{Clock, Run};

/// What a planned block is counted to.
#[derive(Clone, Debug)]
pub(crate) struct Tag {
    tool: u32,
    /// The line in the main program: the statement's own, or its outermost call's.
    line: u32,
    origin: Option<Arc<Origin>>,
}

/// The profile the time was planned on, as the JSON report gives it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ProfileUsed {
    /// The preset under it.
    pub preset: &'static str,
    /// The GRBL settings file read over the preset, as `ger.toml` names it.
    pub grbl_settings: Option<String>,
    /// Whether `ger.toml` has `[machine.motion]`; without it, the preset alone.
    pub configured: bool,
    /// The numbers, at the same level in the JSON.
    #[serde(flatten)]
    pub machine: ger_core::config::Machine,
}

impl ProfileUsed {
    fn new(profile: &MotionProfile) -> ProfileUsed {
        ProfileUsed {
            preset: profile.preset.name(),
            grbl_settings: profile.grbl_settings.as_deref().map(|p| Path::new(p).display().to_string()),
            configured: profile.configured,
            machine: profile.machine,
        }
    }

    /// Which profile the time was planned on, and where it came from, with
    /// `unit` the machine's.
    pub fn text(&self, unit: &str) -> String {
        let preset = self.preset;
        match (&self.grbl_settings, self.configured) {
            (_, false) => format!("{preset}, GRBL 1.1h's defaults in {unit} (no [machine.motion] in ger.toml)"),
            (Some(file), true) => format!("the GRBL settings of {file} over {preset} ([machine.motion])"),
            (None, true) => format!("[machine.motion] over {preset}"),
        }
    }
}

/// One tool's planned time: from its tool change (the change's own time
/// included) to the next; tool 1 before any.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToolTime {
    pub number: u32,
    pub seconds: f64,
}

/// One call's planned time, the calls inside it included.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CallTime {
    /// `O100`, or `wizard `Pocket``.
    pub name: String,
    /// Where the call is (in the program it is made from).
    pub line: u32,
    pub column: u32,
    /// Every time it ran, in all.
    pub seconds: f64,
}

/// The run time the motion planner gives.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Planned {
    /// From the start to the end: moves, dwells and tool changes.
    pub seconds: f64,
    /// When the first move started and the last ended, seconds from the start.
    pub moving: Option<[f64; 2]>,
    pub profile: ProfileUsed,
    /// In the order they are first used.
    pub tools: Vec<ToolTime>,
    /// Each subprogram or wizard call, by where it is, in the order first run.
    pub calls: Vec<CallTime>,
}

impl Planned {
    /// Nothing yet, on `config`'s profile.
    pub(crate) fn unplanned(config: &Config) -> Planned {
        let profile = ProfileUsed::new(&config.motion_profile());
        Planned { seconds: 0.0, moving: None, profile, tools: Vec::new(), calls: Vec::new() }
    }
}

/// Follows the statements through the planner and counts each block's time where it belongs.
pub(crate) struct Timing {
    run: Run<Tag>,
    /// The tool loaded: 1 until an M06 loads another, as the simulation has it.
    tool: u32,
    tally: Tally,
    profile: ProfileUsed,
}

struct Tally {
    tools: Vec<ToolTime>,
    calls: Vec<CallTime>,
    /// Where each call is in `calls`, by its line, column and name.
    call_index: HashMap<(u32, u32, String), usize>,
    /// The last call chain counted, and its entries in `calls`, innermost first.
    last_chain: Option<(Arc<Origin>, Vec<usize>)>,
    /// When each line of the main program is first reached (NaN: not yet), if asked.
    lines: Option<Vec<f64>>,
}

impl Timing {
    pub(crate) fn new(config: &Config) -> Timing {
        let profile = config.motion_profile();
        Timing {
            run: Run::new(&profile.machine, config.units),
            tool: 1,
            tally: Tally {
                tools: Vec::new(),
                calls: Vec::new(),
                call_index: HashMap::new(),
                last_chain: None,
                lines: None,
            },
            profile: ProfileUsed::new(&profile),
        }
    }

    /// Also keeps when each line of the main program is reached.
    pub(crate) fn by_line(&mut self) {
        self.tally.lines = Some(Vec::new());
    }

    pub(crate) fn statement(&mut self, statement: &Statement) {
        if let Kind::Machine { code: Machine::ToolChange, t: Some(tool), .. } = statement.kind {
            self.tool = tool;
        }
        let line = outermost_line(statement);
        if let Some(lines) = &mut self.tally.lines {
            // A line that runs nothing is reached all the same.
            if lines.len() < line as usize {
                lines.resize(line as usize, f64::NAN);
            }
        }
        let tag = Tag { tool: self.tool, line, origin: statement.origin.clone() };
        self.run.statement(statement, tag, &mut self.tally);
    }

    /// The planned time, and when each line is reached (empty unless asked):
    /// a line nothing runs at is reached when the next one is.
    pub(crate) fn finish(mut self) -> (Planned, Vec<f64>) {
        let totals = self.run.finish(&mut self.tally);
        let mut lines = self.tally.lines.unwrap_or_default();
        let mut next = totals.seconds;
        for time in lines.iter_mut().rev() {
            if time.is_nan() {
                *time = next;
            }
            next = *time;
        }
        let planned = Planned {
            seconds: totals.seconds,
            moving: totals.moving.map(|(start, end)| [start, end]),
            profile: self.profile,
            tools: self.tally.tools,
            calls: self.tally.calls,
        };
        (planned, lines)
    }
}

impl Clock<Tag> for Tally {
    fn tick(&mut self, tag: &Tag, start: f64, seconds: f64) {
        match self.tools.iter_mut().find(|t| t.number == tag.tool) {
            Some(tool) => tool.seconds += seconds,
            None => self.tools.push(ToolTime { number: tag.tool, seconds }),
        }
        if let Some(origin) = &tag.origin {
            self.count_calls(origin, seconds);
        }
        if let Some(lines) = &mut self.lines {
            let index = tag.line.max(1) as usize - 1;
            if lines.len() <= index {
                lines.resize(index + 1, f64::NAN);
            }
            if lines[index].is_nan() {
                lines[index] = start;
            }
        }
    }
}

impl Tally {
    fn count_calls(&mut self, origin: &Arc<Origin>, seconds: f64) {
        // Consecutive blocks mostly share their chain: found once. The chain
        // kept here holds its origin, so its address is not another's.
        let same = self.last_chain.as_ref().is_some_and(|(last, _)| Arc::ptr_eq(last, origin));
        if !same {
            let mut entries = Vec::new();
            let mut next = Some(origin);
            while let Some(call) = next {
                let key = (call.call.line, call.call.col, call.what.clone());
                let calls = &mut self.calls;
                let entry = *self.call_index.entry(key).or_insert_with(|| {
                    calls.push(CallTime {
                        name: call.what.clone(),
                        line: call.call.line,
                        column: call.call.col,
                        seconds: 0.0,
                    });
                    calls.len() - 1
                });
                entries.push(entry);
                next = call.parent.as_ref();
            }
            self.last_chain = Some((origin.clone(), entries));
        }
        if let Some((_, entries)) = &self.last_chain {
            for &entry in entries {
                self.calls[entry].seconds += seconds;
            }
        }
    }
}

/// The line of the main program a statement runs at: its own, or its outermost call's.
pub fn outermost_line(statement: &Statement) -> u32 {
    let mut line = statement.span.line;
    let mut next = statement.origin.as_deref();
    while let Some(origin) = next {
        line = origin.call.line;
        next = origin.parent.as_deref();
    }
    line
}

/// "1 h 02 min", "3 min 05 s", "12.5 s".
pub fn duration(seconds: f64) -> String {
    let whole = seconds.round() as u64;
    if whole >= 3600 {
        format!("{} h {:02} min", whole / 3600, (whole % 3600 + 30) / 60)
    } else if whole >= 60 {
        format!("{} min {:02} s", whole / 60, whole % 60)
    } else {
        format!("{seconds:.1} s")
    }
}
