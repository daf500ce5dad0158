//! One analysis of a document's text: what `ger check` says about it (the
//! translator's diagnostics and the verifier's), where the tool is after
//! each line, and the program's outline. Made on the worker thread; a newer
//! edit stops it between events.

use std::collections::HashSet;
use std::path::Path;
use std::sync::Arc;

use lsp_types::{DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString, Url};

use crate::outline::Outline;
use crate::text::{LineText, Lines};
use crate::Options;
use ger_engine::check::{Checker, Rule};
use ger_engine::core::diag::{Diagnostic, Origin, Severity, Span};
use ger_engine::core::passes::Event;
use ger_engine::core::state::Snapshot;
use ger_engine::core::statement::{Dialect, Distance, Plane, Statement, Units};
use ger_engine::sim::{Step, Stock, Walker};
use ger_engine::{Program, Progress, Purpose, Resolution, Source};

/// The most diagnostics published for one document: past that an editor
/// slows down and a reader learns nothing more.
const PUBLISHED: usize = 1000;

/// What an analysis found.
pub struct Analysis {
    pub dialect: Dialect,
    /// The machine's.
    pub units: Units,
    pub outline: Outline,
    /// Per program line with a move, the tool's position after its last
    /// move (in machine coordinates and units), in order of line.
    positions: Vec<(u32, [f64; 3])>,
    /// Per program line that ran, the state its last run was read in (an
    /// index in `states`), in order of line.
    line_states: Vec<(u32, u32)>,
    /// The states lines ran in, each kept once for a stretch of lines.
    states: Vec<LineState>,
    /// The planned run, when the program moves and was checked.
    pub planned: Option<Planned>,
    /// The lines of subprograms the program calls: (first, last), 1-based.
    called: Vec<(u32, u32)>,
    pub diagnostics: Vec<lsp_types::Diagnostic>,
}

/// The modal state a line is read in, as the translation keeps it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineState {
    /// The unit its lengths are written in (G20, G21).
    pub units: Units,
    pub distance: Distance,
    /// G16: the plane's second axis word is an angle.
    pub polar: bool,
    pub plane: Plane,
    /// Program zero in machine coordinates (G52, G54..., G92 in force).
    pub zero: [f64; 3],
    /// 1 for G54 to 9 for G59.3.
    pub system: u8,
}

impl LineState {
    fn of(snapshot: &Snapshot) -> LineState {
        LineState {
            units: snapshot.program_units,
            distance: snapshot.distance,
            polar: snapshot.polar,
            plane: snapshot.plane,
            zero: snapshot.prz,
            system: snapshot.system,
        }
    }
}

/// The planned run time (the checker's, as `ger check` and `ger view` give it).
pub struct Planned {
    pub seconds: f64,
    /// When the run first reaches each line of the main program (1 first).
    pub line_times: Vec<f64>,
    /// Which profile it was planned on.
    pub profile: String,
}

impl Analysis {
    /// The line of the last move at or before 1-based `line`, and where the tool
    /// is after it; `None` before the first move (the tool is at machine zero).
    pub fn position_after(&self, line: u32) -> Option<(u32, [f64; 3])> {
        let at = self.positions.partition_point(|(l, _)| *l <= line);
        at.checked_sub(1).map(|i| self.positions[i])
    }

    /// The lines with a move from 1-based `first` to `last`, and where the
    /// tool is after each.
    pub fn moves_between(&self, first: u32, last: u32) -> &[(u32, [f64; 3])] {
        let from = self.positions.partition_point(|(l, _)| *l < first);
        let to = self.positions.partition_point(|(l, _)| *l <= last);
        &self.positions[from..to.max(from)]
    }

    /// The state 1-based `line` was read in: its last run's, or for a line
    /// nothing of which reached the end of the translation (G10, G92), the
    /// last line's before it; `None` before anything ran.
    pub fn state_at(&self, line: u32) -> Option<&LineState> {
        let at = self.line_states.partition_point(|(l, _)| *l <= line);
        at.checked_sub(1).map(|i| &self.states[self.line_states[i].1 as usize])
    }

    /// When the planned run first reaches 1-based `line` of the main
    /// program; `None` for a line of a subprogram that calls run (the
    /// time is its call's), or without a plan.
    pub fn reached(&self, line: u32) -> Option<f64> {
        let planned = self.planned.as_ref()?;
        if self.called.iter().any(|&(first, last)| (first..=last).contains(&line)) {
            return None;
        }
        planned.line_times.get(line.checked_sub(1)? as usize).copied()
    }
}

/// Tells the engine's passes to stop when the analysis is no longer wanted.
struct Stale<'a>(&'a dyn Fn() -> bool);

impl Progress for Stale<'_> {
    fn stopped(&self) -> bool {
        (self.0)()
    }
}

/// Analyses `text`, the document at `path`, unless `stale` says a newer
/// text came first (then `None`).
pub fn analyse(
    options: &Options,
    uri: &Url,
    path: &Path,
    text: Arc<str>,
    stale: &dyn Fn() -> bool,
) -> Option<Analysis> {
    let dir = path.parent().unwrap_or(Path::new("/"));
    let name = path.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let source = Source::text(name, dir, text.clone());
    let lines = Lines::of(&text);
    let mut found = Found::default();
    let (dialect, units) = match options.settings.load(&source, Purpose::Cut) {
        Ok(config) => {
            let (dialect, units) = (config.dialect.name, config.units);
            let wizards = (options.wizards)(&options.wizards_dir(dir), &config);
            let program = Program::new(source, config).with_wizards(wizards);
            found.run(program, stale)?;
            (dialect, units)
        }
        Err(err) => {
            found.problems.push(err.to_string());
            (Dialect::Strict, Units::Inch)
        }
    };
    let outline = Outline::of(&text, dialect);
    if stale() {
        return None;
    }
    let mut diagnostics: Vec<lsp_types::Diagnostic> = found
        .problems
        .iter()
        .map(|message| lsp_types::Diagnostic {
            range: lines.range(1, 1, 0),
            severity: Some(DiagnosticSeverity::ERROR),
            source: Some("ger".to_string()),
            message: message.clone(),
            ..lsp_types::Diagnostic::default()
        })
        .collect();
    let total = found.findings.len();
    diagnostics.extend(found.findings.iter().take(PUBLISHED).map(|(rule, d)| diagnostic(*rule, d, &lines, uri)));
    if total > PUBLISHED {
        diagnostics.push(lsp_types::Diagnostic {
            range: lines.range(1, 1, 0),
            severity: Some(DiagnosticSeverity::INFORMATION),
            source: Some("ger".to_string()),
            message: format!("{} more diagnostics are not shown; `ger check` lists them", total - PUBLISHED),
            ..lsp_types::Diagnostic::default()
        });
    }
    let (line_states, states) = found.line_states();
    let positions = found.positions();
    let labels: HashSet<&str> = outline.calls.iter().map(|call| call.label.as_str()).collect();
    let called = outline
        .blocks
        .iter()
        .filter(|block| block.label.as_deref().is_some_and(|label| labels.contains(label)))
        .map(|block| (block.start.line, block.end_line))
        .collect();
    let planned = found.planned;
    Some(Analysis { dialect, units, outline, positions, line_states, states, planned, called, diagnostics })
}

#[derive(Default)]
struct Found {
    /// Problems with no place in the program (the config, the stock).
    problems: Vec<String>,
    findings: Vec<(Option<Rule>, Diagnostic)>,
    /// (line, position after it), in the order the moves ran.
    moves: Vec<(u32, [f64; 3])>,
    /// (line, index in `states`), in the order the lines ran.
    runs: Vec<(u32, u32)>,
    states: Vec<LineState>,
    planned: Option<Planned>,
}

impl Found {
    /// Translates, checks and follows `program` as `ger check` does; `None` when stopped.
    fn run(&mut self, mut program: Program, stale: &dyn Fn() -> bool) -> Option<()> {
        // Without a size, the stock is where the program cuts: a pass to find it.
        let stock = match Stock::from_config(program.config()) {
            Some(stock) => Some(stock),
            None => {
                let extent = program.extent(&mut Stale(stale));
                extent.path_box.map(|_| extent.cut.stock_for(program.config()))
            }
        };
        if stale() {
            return None;
        }
        let config = program.config().clone();
        let mut checker = match stock.map(|stock| program.simulation(stock, Resolution::default())) {
            Some(Ok(simulation)) => Some(Checker::new(&config, simulation, &[]).timing_lines()),
            Some(Err(refused)) => {
                self.problems.push(format!("the checks that need a simulation did not run: {refused}"));
                None
            }
            None => None,
        };
        let mut walker = Walker::new();
        let mut stopped = false;
        program.for_each_event_in_state("checking", &mut Stale(stale), |event, state| {
            match event {
                Event::Statement(statement) => {
                    self.ran(&statement, LineState::of(state));
                    if let Some(Step::Move(_)) = walker.step(&statement) {
                        self.moved(&statement, walker.position().to_array());
                    }
                    if let Some(checker) = &mut checker {
                        checker.statement(&statement);
                    }
                }
                Event::Diagnostic(diagnostic) => match &mut checker {
                    Some(checker) => checker.translator(diagnostic),
                    None => self.findings.push((None, diagnostic)),
                },
            }
            stopped = stale();
            !stopped
        });
        if stopped || stale() {
            return None;
        }
        if let Some(checker) = checker {
            let verdict = checker.finish();
            let planned = &verdict.summary.planned;
            self.planned = planned.moving.is_some().then(|| Planned {
                seconds: planned.seconds,
                line_times: verdict.line_times,
                profile: planned.profile.text(config.units.abbreviation()),
            });
            self.findings = verdict.findings.into_iter().map(|f| (f.rule, f.diagnostic)).collect();
        }
        Some(())
    }

    /// A statement of this file's line reached the end of the translation,
    /// read in `state`.
    fn ran(&mut self, statement: &Statement, state: LineState) {
        if !in_this_file(statement.origin.as_deref()) {
            return;
        }
        if self.states.last() != Some(&state) {
            self.states.push(state);
        }
        let index = self.states.len() as u32 - 1;
        let line = statement.span.line;
        match self.runs.last_mut() {
            Some(last) if last.0 == line => last.1 = index,
            _ => self.runs.push((line, index)),
        }
    }

    /// By line, the state of each line's last run, and the states they index.
    fn line_states(&mut self) -> (Vec<(u32, u32)>, Vec<LineState>) {
        (last_by_line(std::mem::take(&mut self.runs)), std::mem::take(&mut self.states))
    }

    /// A statement moved the tool to `to`: the position after its line, and
    /// after the line of the call it ran in.
    fn moved(&mut self, statement: &Statement, to: [f64; 3]) {
        let own = statement.span.line;
        let outermost = outermost_call(statement.origin.as_deref()).map_or(own, |call| call.line);
        if outermost != own && in_this_file(statement.origin.as_deref()) {
            self.moves.push((own, to));
        }
        match self.moves.last_mut() {
            Some(last) if last.0 == outermost => last.1 = to,
            _ => self.moves.push((outermost, to)),
        }
    }

    /// By line, each line's last position (a line run twice, in a loop, last).
    fn positions(&mut self) -> Vec<(u32, [f64; 3])> {
        last_by_line(std::mem::take(&mut self.moves))
    }
}

/// What each line had last, in order of line, of (line, what) in the order they ran.
fn last_by_line<T>(mut runs: Vec<(u32, T)>) -> Vec<(u32, T)> {
    // Stable: among a line's runs the last stays last.
    runs.sort_by_key(|(line, _)| *line);
    let mut last: Vec<(u32, T)> = Vec::with_capacity(runs.len());
    for (line, what) in runs {
        match last.last_mut() {
            Some(previous) if previous.0 == line => previous.1 = what,
            _ => last.push((line, what)),
        }
    }
    last
}

/// The span of the outermost call in a chain.
fn outermost_call(mut origin: Option<&Origin>) -> Option<Span> {
    let mut call = None;
    while let Some(o) = origin {
        call = Some(o.call);
        origin = o.parent.as_deref();
    }
    call
}

/// Whether a statement with this chain has its own line in the program's
/// text: not if a call in the chain ran a program from another file.
fn in_this_file(mut origin: Option<&Origin>) -> bool {
    while let Some(o) = origin {
        if o.what.contains(" (from ") {
            return false;
        }
        origin = o.parent.as_deref();
    }
    true
}

/// Where a diagnostic shows in the program's text: its own span, or for
/// one in a program from another file, the outermost call of such a program.
fn shown_span(diagnostic: &Diagnostic) -> Span {
    let mut span = diagnostic.span;
    let mut origin = diagnostic.origin.as_deref();
    while let Some(o) = origin {
        if o.what.contains(" (from ") {
            span = o.call;
        }
        origin = o.parent.as_deref();
    }
    span
}

/// A ger diagnostic as the protocol's: its range in UTF-16 columns, the
/// check's name as its code, the help after the message, the calls it ran
/// in as related locations, and a mechanical fix if it has one.
fn diagnostic(rule: Option<Rule>, d: &Diagnostic, lines: &Lines, uri: &Url) -> lsp_types::Diagnostic {
    let span = shown_span(d);
    let range = lines.range(span.line, span.col, span.len);
    let mut message = d.message.clone();
    if let Some(help) = &d.help {
        message.push_str("\nhelp: ");
        message.push_str(help);
    }
    let mut related = Vec::new();
    let mut origin = d.origin.as_deref();
    while let Some(o) = origin {
        let call = o.call;
        related.push(DiagnosticRelatedInformation {
            location: Location { uri: uri.clone(), range: lines.range(call.line, call.col, call.len) },
            message: format!("in {} called here", o.what),
        });
        origin = o.parent.as_deref();
    }
    let line_text = lines.line(span.line.saturating_sub(1) as usize);
    let culprit = line_text.get(span.col.saturating_sub(1) as usize..(span.col + span.len).saturating_sub(1) as usize);
    let fixes = crate::actions::fixes(d, culprit.unwrap_or(""));
    lsp_types::Diagnostic {
        range,
        severity: Some(match d.severity {
            Severity::Error => DiagnosticSeverity::ERROR,
            Severity::Warning => DiagnosticSeverity::WARNING,
        }),
        code: rule.map(|rule| NumberOrString::String(rule.name().to_string())),
        source: Some("ger".to_string()),
        message,
        related_information: (!related.is_empty()).then_some(related),
        data: (!fixes.is_empty()).then(|| serde_json::to_value(fixes).expect("a fix serialises")),
        ..lsp_types::Diagnostic::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn origin(what: &str, line: u32, parent: Option<Arc<Origin>>) -> Option<Arc<Origin>> {
        Some(Arc::new(Origin { what: what.to_string(), call: Span::new(line, 1, 7), parent }))
    }

    #[test]
    fn a_diagnostic_from_another_file_shows_at_the_call_in_this_one() {
        // O1002 from its own file, called at line 4 of O100, called at line 2.
        let chain = origin("O1002 (from O1002.nc)", 4, origin("O100", 2, None));
        let inner = Diagnostic::error(Span::new(7, 3, 2), "bad").with_origin(chain);
        assert_eq!(shown_span(&inner), Span::new(4, 1, 7));
        assert!(!in_this_file(inner.origin.as_deref()));
        let local = Diagnostic::error(Span::new(9, 3, 2), "bad").with_origin(origin("O100", 2, None));
        assert_eq!(shown_span(&local), Span::new(9, 3, 2));
        assert_eq!(outermost_call(local.origin.as_deref()), Some(Span::new(2, 1, 7)));
    }

    #[test]
    fn positions_are_the_last_each_line_reached() {
        let mut found = Found::default();
        let statement = |line: u32| Statement::new(ger_engine::core::statement::Kind::End, Span::new(line, 1, 1));
        found.moved(&statement(3), [1.0, 0.0, 0.0]);
        found.moved(&statement(3), [2.0, 0.0, 0.0]);
        found.moved(&statement(5), [3.0, 0.0, 0.0]);
        // Line 3 again (a loop): its last run counts.
        found.moved(&statement(3), [4.0, 0.0, 0.0]);
        let mut inner = statement(9);
        inner.origin = origin("O100", 6, None);
        found.moved(&inner, [5.0, 0.0, 0.0]);
        let analysis = Analysis {
            dialect: Dialect::Strict,
            units: Units::Mm,
            outline: Outline::default(),
            positions: found.positions(),
            line_states: Vec::new(),
            states: Vec::new(),
            planned: None,
            called: Vec::new(),
            diagnostics: Vec::new(),
        };
        assert_eq!(analysis.position_after(2), None);
        assert_eq!(analysis.position_after(3), Some((3, [4.0, 0.0, 0.0])));
        assert_eq!(analysis.position_after(4), Some((3, [4.0, 0.0, 0.0])));
        assert_eq!(analysis.position_after(6), Some((6, [5.0, 0.0, 0.0])));
        assert_eq!(analysis.position_after(9), Some((9, [5.0, 0.0, 0.0])));
    }
}
