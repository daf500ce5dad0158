//! Applies a [`Profile`] to the translated statements: each becomes the
//! lines its controller takes, through ger's emitter.

use std::collections::HashSet;
use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;

use ger_core::config::{Config, TargetConfig};
use ger_core::diag::Diagnostic;
use ger_core::emit::{Emitter, Numbers};
use ger_core::geom::arc_sweep;
use ger_core::statement::{Kind, Machine, Motion, MotionMode, Plane, Statement, Units, Value};

use crate::arcs;
use crate::profile::{self, Comments, Profile, ToolChange, ToolLength};

/// The most lines one arc becomes when the controller would refuse it.
const MOST_LINES_PER_ARC: usize = 10_000;

/// Writes statements as the target's lines.
pub struct Writer {
    profile: &'static Profile,
    options: TargetConfig,
    units: Units,
    emitter: Emitter,
    line_numbers: bool,
    plane: Plane,
    /// Where the tool is as ger computes it; `None` until an axis is first
    /// written. Where the controller reads it to be is `as_read` of it.
    exact: [Option<f64>; 3],
    /// The notes already given as warnings: each once.
    warned: HashSet<&'static str>,
    buffer: String,
}

impl Writer {
    /// For `config`'s target and unit.
    pub fn new(config: &Config, line_numbers: bool) -> Writer {
        Writer::for_profile(profile::of(config.target.name), config, line_numbers)
    }

    /// With a profile of the caller's (the tests' made-up controllers).
    pub(crate) fn for_profile(profile: &'static Profile, config: &Config, line_numbers: bool) -> Writer {
        let mut emitter = Emitter::new(config.units.decimals(), false);
        if let Some(max_digits) = profile.max_digits {
            emitter = emitter.with_numbers(Numbers::Short { max_digits });
        }
        Writer {
            profile,
            options: config.target.clone(),
            units: config.units,
            emitter,
            line_numbers,
            plane: Plane::XY,
            exact: [None; 3],
            warned: HashSet::new(),
            buffer: String::new(),
        }
    }

    pub fn profile(&self) -> &'static Profile {
        self.profile
    }

    /// The lines before the program's: framing, program number, where it
    /// came from, and the modes the rest assumes.
    pub fn preamble(&self, source: &str) -> String {
        let p = self.profile;
        let mut text = String::new();
        if p.percent_framing {
            text.push_str("%\n");
        }
        if p.program_number {
            let number = self.options.program_number.unwrap_or(1);
            let name = source.rsplit('/').next().unwrap_or(source);
            text.push_str(&format!("O{number:04} ({})\n", self.comment_text(name)));
        }
        let from = match p.name {
            ger_core::config::TargetName::Generic => format!("ger: translated from {source}"),
            _ => format!("ger: translated from {source} for {}", p.label),
        };
        text.push_str(&format!("({})\n{}\nG90\nG17\n", self.comment_text(&from), self.units.code()));
        for line in p.setup {
            text.push_str(line);
            text.push('\n');
        }
        text
    }

    /// The lines after the program's.
    pub fn postamble(&self) -> String {
        if self.profile.percent_framing {
            "%\n".to_string()
        } else {
            String::new()
        }
    }

    /// Appends `statement`'s lines to `out`, each with its newline; a rule
    /// that leaves something out says so in a comment there, and the first
    /// time in a warning pushed on `notes`.
    pub fn write(&mut self, statement: &Statement, out: &mut String, notes: &mut Vec<Diagnostic>) {
        let p = self.profile;
        match &statement.kind {
            Kind::Plane(plane) => self.plane = *plane,
            Kind::Motion(m) if m.mode.is_some_and(MotionMode::is_arc) && p.arc_check.is_some() => {
                return self.arc(statement, m, out, notes);
            }
            Kind::Machine { code: Machine::ToolChange, s, t } if p.tool_change == ToolChange::Pause => {
                return self.tool_change(statement, *s, *t, out, notes);
            }
            Kind::Machine { code: Machine::Mist, .. } if p.mist_optional && !self.options.mist => {
                let why = "M07 left out: GRBL is built without mist coolant unless [target] mist = true says otherwise";
                return self.note(statement, "mist", why, out, notes);
            }
            Kind::Machine { code, .. } if p.missing_m_codes.contains(&machine_number(*code)) => {
                let why = format!("{} left out: {} has no such code", code.code(), p.label);
                return self.note(statement, code.code(), &why, out, notes);
            }
            Kind::PassThrough { .. } if p.no_pass_through => {
                self.buffer.clear();
                self.emitter.write(&mut self.buffer, statement);
                let why = format!("{} left out: {} has no such code", self.buffer, p.label);
                return self.note(statement, "pass-through", &why, out, notes);
            }
            Kind::Rotary(_) if p.name == ger_core::config::TargetName::Grbl => {
                return self.note(statement, "rotary", "A, B, C words left out: GRBL has three axes", out, notes);
            }
            Kind::Program(_) if p.name == ger_core::config::TargetName::Grbl => return,
            Kind::ToolLength { positive, h } if p.tool_length == ToolLength::Dynamic => {
                return self.dynamic_tool_length(statement, *positive, h.unwrap_or(0), out, notes);
            }
            Kind::ToolLengthRegister(_) if p.tool_length == ToolLength::Dynamic => {
                let why = "H left out: GRBL has no tool table (write G43 Hn with [target] tool_lengths)";
                return self.note(statement, "tool-length", why, out, notes);
            }
            Kind::SetToolTable { tool, .. } if !p.tool_table_write => {
                let why = format!(
                    "G10 L1 left out: {} does not take LinuxCNC's tool table write; set tool {tool}'s length on the controller",
                    p.label
                );
                return self.note(statement, "tool-table", &why, out, notes);
            }
            Kind::Dwell(seconds) if p.dwell_word != 'P' => {
                let mut text = format!("G04 {}", p.dwell_word);
                self.emitter.number(&mut text, *seconds);
                return self.line(statement.span.line, &text, out, notes);
            }
            _ => {}
        }
        if let Kind::Motion(m) = &statement.kind {
            self.moved(m);
        }
        self.buffer.clear();
        self.emitter.write(&mut self.buffer, statement);
        let text = std::mem::take(&mut self.buffer);
        self.line(statement.span.line, &text, out, notes);
        self.buffer = text;
    }

    /// Follows the tool to a move's target.
    fn moved(&mut self, m: &Motion) {
        for axis in 0..3 {
            if let Some(v) = m.target.get(axis) {
                self.exact[axis] = Some(v.value);
            }
        }
    }

    /// A number as the controller reads it back from the output.
    fn as_read(&self, value: f64) -> f64 {
        let mut text = String::new();
        self.emitter.number(&mut text, value);
        text.parse().unwrap_or(value)
    }

    /// One line of output: its N word when there is room for it, and F on a
    /// line of its own when the line is too long with it.
    fn line(&mut self, line: u32, text: &str, out: &mut String, notes: &mut Vec<Diagnostic>) {
        let p = self.profile;
        let numbered = self.line_numbers && p.max_line_number.is_none_or(|most| line <= most);
        let Some(most) = p.max_line_length else {
            if numbered {
                let _ = write!(out, "N{line} ");
            }
            out.push_str(text);
            out.push('\n');
            return;
        };
        let with_number = if numbered { format!("N{line} {text}") } else { text.to_string() };
        let fits = |t: &str| length(t) <= most;
        if fits(&with_number) {
            out.push_str(&with_number);
        } else if fits(text) {
            out.push_str(text);
        } else if let Some((before, feed)) = text.split_once(" F").filter(|(before, _)| fits(before)) {
            // F alone on a line sets the feed of the moves after it.
            out.push('F');
            out.push_str(feed);
            out.push('\n');
            out.push_str(before);
        } else {
            let message =
                format!("this line is {} characters long, and {} reads {most} at most", length(text), p.label);
            notes.push(Diagnostic::error(ger_core::diag::Span::new(line, 1, 0), message));
            out.push_str(text);
        }
        out.push('\n');
    }

    /// A rule left something out: a comment in its place, and a warning the first time.
    fn note(
        &mut self,
        statement: &Statement,
        key: &'static str,
        why: &str,
        out: &mut String,
        notes: &mut Vec<Diagnostic>,
    ) {
        out.push_str(&format!("({})\n", self.comment_text(why)));
        if self.warned.insert(key) {
            let message = format!("target {}: {why}", self.profile.name.name());
            notes.push(Diagnostic::warning(statement.span, message).with_origin(statement.origin.clone()));
        }
    }

    fn tool_change(
        &mut self,
        statement: &Statement,
        s: Option<f64>,
        t: Option<u32>,
        out: &mut String,
        notes: &mut Vec<Diagnostic>,
    ) {
        let tool = t.map_or("the next tool".to_string(), |t| t.to_string());
        let block = match &self.options.tool_change {
            Some(block) => block.replace("{tool}", &tool),
            // LinuxCNC's M06 stops the spindle, and programs start it again after one.
            None => format!("M05\nM00 ({})", self.comment_text(&format!("MSG, load tool {tool}"))),
        };
        for text in block.lines() {
            self.line(statement.span.line, text, out, notes);
        }
        if let Some(s) = s {
            self.line(statement.span.line, &format!("S{s}"), out, notes);
        }
    }

    fn dynamic_tool_length(
        &mut self,
        statement: &Statement,
        positive: bool,
        h: u32,
        out: &mut String,
        notes: &mut Vec<Diagnostic>,
    ) {
        let length =
            if h == 0 { Some(0.0) } else { self.options.tool_lengths.iter().find(|(n, _)| *n == h).map(|(_, l)| *l) };
        let Some(length) = length else {
            let code = if positive { "G43" } else { "G44" };
            let why =
                format!("{code} H{h} left out: GRBL has no tool table; give H{h}'s length in [target] tool_lengths");
            return self.note(statement, "tool-length", &why, out, notes);
        };
        let mut text = String::from("G43.1 Z");
        self.emitter.number(&mut text, if positive { length } else { -length });
        self.line(statement.span.line, &text, out, notes);
    }

    /// An arc, as the controller's check takes it: as it is, as a line when
    /// its written end is at its start's angle (the controller would turn a
    /// full circle) though ger's is not, or as lines when the check would
    /// refuse it.
    fn arc(&mut self, statement: &Statement, m: &Motion, out: &mut String, notes: &mut Vec<Diagnostic>) {
        let (a, b, n) = self.plane.axes();
        let check = self.profile.arc_check.expect("only called with an arc check");
        let clockwise = m.mode == Some(MotionMode::ArcCw);
        let in_plane = |p: [Option<f64>; 3], target: &ger_core::statement::Axes, read: &dyn Fn(f64) -> f64| {
            let start = [p[a]?, p[b]?, p[n].unwrap_or(0.0)];
            let end = |axis: usize, from: f64| target.get(axis).map_or(from, |v| read(v.value));
            Some((start, [end(a, start[0]), end(b, start[1]), end(n, start[2])]))
        };
        let exact = in_plane(self.exact, &m.target, &|v| v);
        let written_position = self.exact.map(|p| p.map(|v| self.as_read(v)));
        let written = in_plane(written_position, &m.target, &|v| self.as_read(v));
        let centre_word = |axis: usize, read: &dyn Fn(f64) -> f64| m.centre.get(axis).map_or(0.0, |v| read(v.value));
        let (Some((start, end)), Some((written_start, written_end))) = (exact, written) else {
            return self.plain(statement, m, out, notes);
        };
        let centre = [start[0] + centre_word(a, &|v| v), start[1] + centre_word(b, &|v| v)];
        let written_centre = [
            written_start[0] + centre_word(a, &|v| self.as_read(v)),
            written_start[1] + centre_word(b, &|v| self.as_read(v)),
        ];
        // What ger means by the arc (LinuxCNC's reading), and what GRBL reads in the written words.
        let (_, meant) = arc_sweep((start[0], start[1]), (end[0], end[1]), (centre[0], centre[1]), !clockwise);
        let meant = meant.abs();
        let read = arcs::sweep(written_start, written_centre, written_end, clockwise);
        let mm_per_unit = self.units.factor_to(Units::Mm);
        if read == TAU && meant < PI {
            // ger's arc is short enough that its end rounds onto its start: a line is within rounding of it.
            let line = Motion { mode: Some(MotionMode::Linear), centre: Default::default(), radius: None, ..m.clone() };
            return self.plain(statement, &line, out, notes);
        }
        // ger's arc goes (almost) all the way round, and its written end
        // rounds to just past its start: GRBL would turn a sliver.
        let turns_short = meant > PI && read < PI;
        let refused = arcs::refused(&check, written_start, written_centre, written_end, mm_per_unit);
        if !turns_short && !refused {
            return self.plain(statement, m, out, notes);
        }
        // Lines within the arc tolerance GRBL itself cuts arcs to ($12 = 0.002 mm).
        let tolerance = 0.002 / mm_per_unit;
        let turn = if turns_short { meant } else { read };
        let points = arcs::as_lines(
            written_start,
            written_centre,
            written_end,
            (turn, clockwise),
            tolerance,
            MOST_LINES_PER_ARC,
        );
        let why = if turns_short {
            format!(
                "an arc turning {:.1} degrees whose end rounds to just past its start is written as lines: GRBL would turn {:.4} degrees",
                meant.to_degrees(),
                read.to_degrees()
            )
        } else {
            format!(
                "an arc whose end is {} off its circle is written as lines: GRBL refuses it (error:33)",
                describe_length(
                    ((written_end[0] - written_centre[0]).hypot(written_end[1] - written_centre[1])
                        - (written_start[0] - written_centre[0]).hypot(written_start[1] - written_centre[1]))
                    .abs(),
                    self.units
                )
            )
        };
        self.note(statement, "arc", &why, out, notes);
        for (i, point) in points.iter().enumerate() {
            let mut target = ger_core::statement::Axes::default();
            for (slot, value) in [(a, point[0]), (b, point[1]), (n, point[2])] {
                let given = m.target.get(slot).is_some() || slot != n;
                if given {
                    *target.slot(slot) = Some(Value { value, span: statement.span });
                }
            }
            let line = Motion {
                mode: Some(MotionMode::Linear),
                target,
                centre: Default::default(),
                radius: None,
                feed: if i == 0 { m.feed } else { None },
                turns: None,
            };
            self.plain(statement, &line, out, notes);
        }
        // The last point is the written end: ger's own end stays where it was meant to be.
        for axis in 0..3 {
            if let Some(v) = m.target.get(axis) {
                self.exact[axis] = Some(v.value);
            }
        }
    }

    fn plain(&mut self, statement: &Statement, m: &Motion, out: &mut String, notes: &mut Vec<Diagnostic>) {
        self.moved(m);
        self.buffer.clear();
        self.emitter.write(&mut self.buffer, &statement.with_kind(Kind::Motion(Box::new(m.clone()))));
        let text = std::mem::take(&mut self.buffer);
        self.line(statement.span.line, &text, out, notes);
        self.buffer = text;
    }

    /// A comment's text as the target takes it.
    fn comment_text(&self, text: &str) -> String {
        match self.profile.comments {
            Comments::Ascii => text.chars().filter(|c| (' '..='~').contains(c) && !"()".contains(*c)).collect(),
            Comments::AsciiWithoutRealtime => {
                text.chars().filter(|c| (' '..='~').contains(c) && !"()!~?".contains(*c)).collect()
            }
            Comments::FanucUpper => {
                // What it cannot hold becomes a space, so words stay apart ("PARTS BRACKET.NC").
                let kept: String = text
                    .to_ascii_uppercase()
                    .chars()
                    .map(|c| if c.is_ascii_uppercase() || c.is_ascii_digit() || ".,=_-".contains(c) { c } else { ' ' })
                    .collect();
                kept.split_whitespace().collect::<Vec<_>>().join(" ")
            }
        }
    }
}

/// A length for a note, in the output's unit.
fn describe_length(length: f64, units: Units) -> String {
    format!("{length:.d$} {}", units.abbreviation(), d = units.decimals() + 1)
}

/// A line's length as a controller's line buffer counts it: no spaces, no comments.
pub fn length(text: &str) -> usize {
    let mut depth = 0usize;
    let mut count = 0;
    for c in text.chars() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            ';' if depth == 0 => break,
            ' ' | '\t' => {}
            _ if depth == 0 => count += 1,
            _ => {}
        }
    }
    count
}

/// An M code's number as the profiles list them.
fn machine_number(code: Machine) -> u32 {
    code.code().trim_start_matches('M').parse().unwrap_or(u32::MAX)
}

#[cfg(test)]
#[path = "writer_tests.rs"]
mod tests;
