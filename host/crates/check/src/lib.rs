//! The verifier: what would break a part or a machine, found by following the
//! translated program (after pass 05) through the machine and the stock.
//!
//! A [`Checker`] takes the output statements one by one. Checks that need
//! only the move itself (travel, arc radius) are made at once; checks that
//! need the material (a rapid that cuts, cutting with the spindle stopped,
//! engagement deeper than the flutes, plunges, cuts under the stock) wait for
//! the inspecting [`Simulation`] to report what each move touched. Every
//! finding carries the move's position in the run, so the report comes out
//! in program order whichever way a finding was made. Nothing here reads
//! files or knows argv.

mod summary;
mod timing;

use std::collections::VecDeque;
use std::sync::Arc;

pub use ger_core::config::Rule;
use ger_core::config::{Config, ToolKind};
use ger_core::diag::{Diagnostic, Origin, Span};
use ger_core::statement::{Kind, Machine, Statement};
use ger_core::tools::ToolSource;
use ger_sim::{Contact, Guard, HeightField, Intrusion, Part, PartKind, Point, Segment, Simulation, Solid, Tracker};
pub use summary::{Bounds, Summary, ToolUse};
use timing::Timing;
pub use timing::{duration, outermost_line, CallTime, Planned, ProfileUsed, ToolTime};

/// One problem: a translator's diagnostic (no rule) or a check's.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    pub rule: Option<Rule>,
    pub diagnostic: Diagnostic,
    /// How many moves ran before it: findings are reported in this order.
    order: u32,
}

/// Past this many findings of one rule, the rest are only counted (in the summary).
pub const SHOWN_PER_RULE: u64 = 100;

/// What `ger check` concludes.
#[derive(Debug)]
pub struct Verdict {
    /// In program order; at most [`SHOWN_PER_RULE`] of each rule.
    pub findings: Vec<Finding>,
    pub summary: Summary,
    /// When the planned run reaches each line of the main program, in
    /// seconds (empty unless [`Checker::timing_lines`] asked).
    pub line_times: Vec<f64>,
}

/// A move cut into the stock whose contact has not been reported yet.
struct Pending {
    tag: u32,
    span: Span,
    origin: Option<Arc<Origin>>,
    rapid: bool,
    spindle: Spindle,
    /// Which stretch of the spindle standing still the move is in (the count of stops before it).
    stops: u32,
    /// A flat endmill's feed straight down: its diameter.
    plunge: Option<f64>,
    /// The tool's number and flute length, if the table gives it.
    flutes: Option<(u32, f64)>,
    /// The tool's number, and what each of the guards it was cut with is (see [`Guards`]).
    tool: u32,
    parts: Arc<[PartKind]>,
    /// The rules this move has already been reported for (a move may report twice).
    reported: u16,
}

/// What the simulation carries along each move of a tool to see that only
/// its cutting edge meets the stock: each part above the flutes, then each
/// grown by the clearance (which only warns).
struct Guards {
    tool: u32,
    guards: Vec<Guard>,
    /// What guard `n` is.
    parts: Arc<[PartKind]>,
    /// The whole tool for the fixtures: the cutting edge, then each part above it.
    assembly: Vec<Guard>,
    /// What each of `assembly` is: `None` for the cutting edge.
    assembly_parts: Vec<Option<PartKind>>,
}

impl Guards {
    fn new(tool: &ger_core::config::Tool, clearance: f64, allowed: &[Rule]) -> Guards {
        let parts = if allowed.contains(&Rule::Collision) { Vec::new() } else { Part::of(tool) };
        let mut guards: Vec<Guard> =
            parts.iter().map(|p| Guard { cutter: p.cutter, base: p.base, near: false }).collect();
        let mut kinds: Vec<PartKind> = parts.iter().map(|p| p.kind).collect();
        if clearance > 0.0 && !allowed.contains(&Rule::Clearance) {
            for part in Part::of(tool) {
                let grown = part.grown(clearance);
                guards.push(Guard { cutter: grown.cutter, base: grown.base, near: true });
                kinds.push(part.kind);
            }
        }
        let cutter = ger_sim::Cutter::new(tool);
        let mut assembly = vec![Guard { cutter, base: 0.0, near: false }];
        let mut assembly_parts = vec![None];
        for part in Part::of(tool) {
            assembly.push(Guard { cutter: part.cutter, base: part.base, near: false });
            assembly_parts.push(Some(part.kind));
        }
        Guards { tool: tool.number, guards, parts: kinds.into(), assembly, assembly_parts }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Spindle {
    /// Not started yet.
    Never,
    On,
    /// Stopped by M05 (or M30) at this span.
    Stopped(Span),
}

pub struct Checker<'c> {
    config: &'c Config,
    tracker: Tracker<'c>,
    sim: Simulation,
    allowed: Vec<Rule>,
    /// Material thinner than this is not a contact (the height field is f32).
    tolerance: f64,
    travel: Option<(Point, Point)>,
    spindle: Spindle,
    /// How many times the spindle has been stopped, and the last stop reported cutting.
    stops: u32,
    reported_stop: Option<u32>,
    feed: Option<f64>,
    /// Said that a tool nothing describes is simulated as the default.
    defaulted: bool,
    /// Moves seen so far: the tag of the next one.
    moves: u32,
    /// The loaded tool's guards.
    guards: Option<Guards>,
    /// `[[fixtures]]`, in machine coordinates, with their names.
    fixtures: Vec<(Solid, &'c str)>,
    pending: VecDeque<Pending>,
    findings: Vec<Finding>,
    summary: Summary,
    timing: Timing,
}

impl<'c> Checker<'c> {
    /// Checks on `config`'s machine, cutting `sim`'s stock (made inspecting here).
    /// `allowed` rules are not checked.
    pub fn new(config: &'c Config, sim: Simulation, allowed: &[Rule]) -> Checker<'c> {
        let mut allowed = allowed.to_vec();
        allowed.extend_from_slice(&config.check.allow);
        Checker {
            config,
            tracker: Tracker::new(&config.tools),
            sim: sim.inspecting(),
            allowed,
            tolerance: config.units.arc_tolerance() / 10.0,
            travel: config.travel_box().map(|(lo, hi)| (lo.into(), hi.into())),
            spindle: Spindle::Never,
            stops: 0,
            reported_stop: None,
            feed: None,
            defaulted: false,
            moves: 0,
            guards: None,
            fixtures: config.fixtures.iter().map(|f| (Solid::of(f, config), f.name.as_str())).collect(),
            pending: VecDeque::new(),
            findings: Vec::new(),
            summary: Summary::new(config),
            timing: Timing::new(config),
        }
    }

    /// Also works out when the planned run reaches each line of the main program.
    pub fn timing_lines(mut self) -> Checker<'c> {
        self.timing.by_line();
        self
    }

    /// A diagnostic of the translation, in its place in the run.
    pub fn translator(&mut self, diagnostic: Diagnostic) {
        self.findings.push(Finding { rule: None, diagnostic, order: self.moves });
    }

    /// Follows one output statement.
    pub fn statement(&mut self, statement: &Statement) {
        self.summary.count(statement);
        self.timing.statement(statement);
        match &statement.kind {
            Kind::Machine { code: Machine::SpindleCw | Machine::SpindleCcw, .. } => self.spindle = Spindle::On,
            Kind::Machine { code: Machine::SpindleOff, .. } | Kind::End => {
                if self.spindle != Spindle::Never {
                    self.stops += 1;
                }
                self.spindle = Spindle::Stopped(statement.span);
            }
            Kind::Dwell(seconds) => self.summary.dwell(*seconds),
            Kind::Motion(motion) => {
                if let Some(feed) = motion.feed {
                    self.feed = Some(feed.value);
                }
            }
            _ => {}
        }
        let step = match self.tracker.step(statement) {
            Ok(step) => step,
            Err(diagnostic) => {
                self.translator(diagnostic.with_origin(statement.origin.clone()));
                None
            }
        };
        let Some(m) = step else { return };
        let tag = self.moves;
        self.moves += 1;
        let tool = self.tracker.tool();
        self.summary.add_move(&m.segment, m.rapid, self.feed, tool.map(|t| t.number));
        if let Some(tool) = tool.filter(|t| self.config.tool_source(t.number) == Some(&ToolSource::Default)) {
            if !std::mem::replace(&mut self.defaulted, true) {
                let message = format!(
                    "nothing describes tool {}: it is simulated as a quarter-inch endmill ({})",
                    tool.number,
                    self.length(tool.diameter)
                );
                let help =
                    "give the machine's tools in ger.toml ([[tools]]), or keep the tool comments the CAM post writes";
                let diagnostic = Diagnostic::warning(statement.span, message).with_help(help);
                self.report(Rule::DefaultTool, tag, diagnostic.with_origin(statement.origin.clone()));
            }
        }
        self.check_travel(&m.segment, statement);
        if let Segment::Arc { radius, .. } = m.segment {
            let min = self.config.min_arc_radius();
            if radius < min {
                self.report(
                    Rule::ArcRadius,
                    tag,
                    Diagnostic::error(
                        statement.span,
                        format!(
                            "arc radius {} is below the smallest the machine takes, {}",
                            self.length(radius),
                            self.length(min)
                        ),
                    )
                    .with_help(
                        "make it a straight move, or set [check] min_arc_radius in ger.toml if the controller takes it",
                    )
                    .with_origin(statement.origin.clone()),
                );
            }
        }
        let (Some(cutter), Some(tool)) = (self.tracker.cutter(), tool) else { return };
        if self.guards.as_ref().is_none_or(|g| g.tool != tool.number) {
            self.guards = Some(Guards::new(tool, self.config.clearance(), &self.allowed));
        }
        let Some(guards) = &self.guards else { return };
        let parts = guards.parts.clone();
        if !self.allowed.contains(&Rule::Fixture) {
            let clearance = if self.allowed.contains(&Rule::Clearance) { 0.0 } else { self.config.clearance() };
            let (mut hits, mut near) = (Vec::new(), Vec::new());
            for (solid, name) in &self.fixtures {
                let part =
                    |hit: Intrusion| guards.assembly_parts[hit.part].map_or("cutting edge".to_string(), self::name);
                if let Some(hit) = self.sim.intrusion(solid, &m.segment, &guards.assembly) {
                    hits.push(format!("its {} goes {} into fixture \"{name}\"", part(hit), self.length(hit.depth)));
                } else if clearance > 0.0 {
                    if let Some(hit) = self.sim.intrusion(&solid.grown(clearance), &m.segment, &guards.assembly) {
                        near.push(format!(
                            "its {} passes within {} of fixture \"{name}\"",
                            part(hit),
                            self.length(clearance)
                        ));
                    }
                }
            }
            let at = if m.rapid { " in a rapid move (G00)" } else { "" };
            if !hits.is_empty() {
                let diagnostic =
                    Diagnostic::error(statement.span, format!("tool {}{at}: {}", tool.number, hits.join("; ")))
                        .with_help("the fixtures are [[fixtures]] in ger.toml: move the tool round them, or above");
                self.report(Rule::Fixture, tag, diagnostic.with_origin(statement.origin.clone()));
            }
            if !near.is_empty() {
                let diagnostic =
                    Diagnostic::warning(statement.span, format!("tool {}{at}: {}", tool.number, near.join("; ")))
                        .with_help("keep [check] clearance from the [[fixtures]] in ger.toml: a fixture is never quite where it is drawn");
                self.report(Rule::Clearance, tag, diagnostic.with_origin(statement.origin.clone()));
            }
        }
        let Some(guards) = &self.guards else { return };
        if !self.sim.inspect(&m.segment, &cutter, &guards.guards, tag) {
            return;
        }
        let (from, to) = (m.segment.from(), m.segment.to());
        let straight_down = matches!(m.segment, Segment::Line { .. })
            && (from[0] - to[0]).hypot(from[1] - to[1]) <= 1e-9
            && to[2] < from[2];
        self.pending.push_back(Pending {
            tag,
            span: statement.span,
            origin: statement.origin.clone(),
            rapid: m.rapid,
            spindle: self.spindle,
            stops: self.stops,
            plunge: (straight_down && !m.rapid && tool.kind == ToolKind::Endmill).then_some(tool.diameter),
            flutes: tool.flute_length.map(|length| (tool.number, length)),
            tool: tool.number,
            parts,
            reported: 0,
        });
        self.collect();
    }

    /// Cuts what is left and reports.
    pub fn finish(self) -> Verdict {
        self.finish_with_part().0
    }

    /// Cuts what is left and reports, with the part as cut (what `ger view` shows).
    pub fn finish_with_part(mut self) -> (Verdict, HeightField) {
        self.sim.settle();
        let contacts = self.sim.take_contacts();
        self.judge(contacts);
        self.pending.clear();
        // Stable: a translator's diagnostic stays before the checks of the move it precedes.
        self.findings.sort_by_key(|f| f.order);
        self.summary.measure_cut(self.sim.field(), self.tolerance);
        self.summary.describe_tools(self.config);
        let (planned, line_times) = self.timing.finish();
        self.summary.planned = planned;
        (Verdict { findings: self.findings, summary: self.summary, line_times }, self.sim.finish())
    }

    /// Takes what the simulation has reported and forgets the moves it is done with.
    fn collect(&mut self) {
        let contacts = self.sim.take_contacts();
        if !contacts.is_empty() {
            self.judge(contacts);
        }
        let settled = self.sim.settled_below();
        while self.pending.front().is_some_and(|p| p.tag < settled) {
            self.pending.pop_front();
        }
    }

    fn judge(&mut self, contacts: Vec<Contact>) {
        let mut pending = std::mem::take(&mut self.pending);
        let mut next = 0;
        for contact in contacts {
            while pending.get(next).is_some_and(|p| p.tag < contact.tag) {
                next += 1;
            }
            let Some(p) = pending.get_mut(next).filter(|p| p.tag == contact.tag) else { continue };
            self.judge_one(p, contact);
        }
        self.pending = pending;
    }

    fn judge_one(&mut self, p: &mut Pending, contact: Contact) {
        let depth = f64::from(contact.depth);
        let below = f64::from(contact.below);
        let mut found = Vec::new();
        if depth > self.tolerance {
            if p.rapid {
                found.push((
                    Rule::RapidIntoStock,
                    Diagnostic::error(p.span, format!("rapid move (G00) cuts {} into the stock", self.length(depth)))
                        .with_help(
                            "a rapid into material breaks the tool: feed in with G01, or retract above the stock first",
                        ),
                ));
            } else if p.spindle != Spindle::On && self.reported_stop != Some(p.stops) {
                // Once for each time the spindle stands still: the moves after it are the same mistake.
                self.reported_stop = Some(p.stops);
                let help = match p.spindle {
                    Spindle::Stopped(at) => {
                        format!("the spindle was stopped at line {}: start it with M03 or M04", at.line)
                    }
                    _ => "start the spindle with M03 (or M04) before the first cut".to_string(),
                };
                found.push((
                    Rule::SpindleOff,
                    Diagnostic::error(p.span, "cuts the stock while the spindle is not turning").with_help(help),
                ));
            }
            if let Some((number, flutes)) = p.flutes {
                if !p.rapid && depth > flutes + self.tolerance {
                    found.push((
                        Rule::FluteLength,
                        Diagnostic::warning(
                            p.span,
                            format!(
                                "cuts {} deep in one pass, more than tool {number}'s flute length of {}",
                                self.length(depth),
                                self.length(flutes)
                            ),
                        )
                        .with_help("the shank rubs on the material: cut in passes no deeper than the flutes"),
                    ));
                }
            }
            if let Some(diameter) = p.plunge {
                let limit = self.config.plunge_fraction() * diameter;
                if depth > limit + self.tolerance {
                    found.push((
                        Rule::Plunge,
                        Diagnostic::warning(
                            p.span,
                            format!(
                                "plunges a flat endmill {} straight down into material, more than {} of its diameter ({})",
                                self.length(depth),
                                self.config.plunge_fraction(),
                                self.length(limit)
                            ),
                        )
                        .with_help("ramp or helix down instead, or drill first ([check] plunge_fraction sets the limit)"),
                    ));
                }
            }
        }
        if below > self.tolerance {
            found.push((
                Rule::BelowStock,
                Diagnostic::warning(
                    p.span,
                    format!("cuts {} below the bottom of the stock, into what holds it", self.length(below)),
                )
                .with_help("check the depth, and [stock] size and origin in ger.toml"),
            ));
        }
        if let Some((into, n)) = contact.clash.filter(|(into, _)| f64::from(*into) > self.tolerance) {
            let part = name(p.parts[usize::from(n)]);
            let at = if p.rapid { " in a rapid move (G00)" } else { "" };
            found.push((
                Rule::Collision,
                Diagnostic::error(
                    p.span,
                    format!("tool {}'s {part} goes {} into the stock{at}", p.tool, self.length(f64::from(into))),
                )
                .with_help(collision_help(p.parts[usize::from(n)])),
            ));
        } else if let Some((_, n)) = contact.near.filter(|(into, _)| f64::from(*into) > self.tolerance) {
            let part = name(p.parts[usize::from(n)]);
            found.push((
                Rule::Clearance,
                Diagnostic::warning(
                    p.span,
                    format!(
                        "tool {}'s {part} passes within {} of the stock",
                        p.tool,
                        self.length(self.config.clearance())
                    ),
                )
                .with_help(format!(
                    "{} ([check] clearance says how near is too near)",
                    collision_help(p.parts[usize::from(n)])
                )),
            ));
        }
        for (rule, diagnostic) in found {
            let bit = 1 << rule as u16;
            if p.reported & bit == 0 {
                p.reported |= bit;
                self.report(rule, p.tag, diagnostic.with_origin(p.origin.clone()));
            }
        }
    }

    fn check_travel(&mut self, segment: &Segment, statement: &Statement) {
        let Some((min, max)) = self.travel else { return };
        // A line's start was the last move's end, checked then.
        let (lo, hi) = match segment {
            Segment::Line { to, .. } => (*to, *to),
            Segment::Arc { .. } => segment.bounds(),
        };
        let beyond: Vec<String> = (0..3)
            .filter_map(|axis| {
                let name = ["X", "Y", "Z"][axis];
                if lo[axis] < min[axis] - self.tolerance {
                    Some(format!(
                        "{name} {} is past its lower limit, {}",
                        self.length(lo[axis]),
                        self.length(min[axis])
                    ))
                } else if hi[axis] > max[axis] + self.tolerance {
                    Some(format!(
                        "{name} {} is past its upper limit, {}",
                        self.length(hi[axis]),
                        self.length(max[axis])
                    ))
                } else {
                    None
                }
            })
            .collect();
        if !beyond.is_empty() {
            let beyond = beyond.join("; ");
            let tag = self.moves - 1;
            self.report(
                Rule::Travel,
                tag,
                Diagnostic::error(statement.span, format!("the move leaves the machine's travel: {beyond}"))
                    .with_help("in machine coordinates, as [machine] travel and home in ger.toml describe them")
                    .with_origin(statement.origin.clone()),
            );
        }
    }

    fn report(&mut self, rule: Rule, order: u32, diagnostic: Diagnostic) {
        if self.allowed.contains(&rule) {
            return;
        }
        if self.summary.problem(rule) <= SHOWN_PER_RULE {
            self.findings.push(Finding { rule: Some(rule), diagnostic, order });
        }
    }

    /// A length as the translator's messages show it: the output's decimals, and the unit.
    fn length(&self, value: f64) -> String {
        let mut text = String::new();
        ger_core::emit::push_number(&mut text, value, self.config.units.decimals());
        text + " " + self.config.units.abbreviation()
    }
}

/// A part as the messages name it.
fn name(part: PartKind) -> String {
    match part {
        PartKind::Shank => "shank".to_string(),
        PartKind::Holder(0) => "holder".to_string(),
        PartKind::Holder(n) => format!("holder (piece {})", n + 1),
    }
}

fn collision_help(part: PartKind) -> &'static str {
    match part {
        PartKind::Shank => {
            "the material above the flutes meets the shank: a tool with longer flutes, or leave the shank room \
             (the shank is [[tools]] flute_length and shank_diameter in ger.toml)"
        }
        PartKind::Holder(_) => {
            "the holder reaches the material: a longer stick-out, or keep the holder clear of it \
             (the holder is [[tools]] stick_out and holder in ger.toml)"
        }
    }
}

#[cfg(test)]
mod tests;
