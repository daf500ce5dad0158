//! A program on a machine, and what ger answers about it. Each answer is one
//! or more passes over the program, each streaming: statements are used as
//! they come and never collected.

use std::io;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use ger_check::{Checker, Rule, Verdict};
use ger_compare::{Design, Judged};
use ger_controller::Writer;
use ger_core::config::{quoted, Bounds, Config, MAX_MEMORY_MIB};
use ger_core::emit::Emitter;
use ger_core::passes::{translate_probed, Event, Options, LAST_STAGE};
use ger_core::state::{Probe, Snapshot};
use ger_core::statement::{Statement, Units};
use ger_core::wizard::{NoWizards, Wizards};
use ger_render::label;
use ger_render::pieces::{self, Piece};
use ger_sim::{CutBounds, Cutter, HeightField, Move, Point, Refusal, Simulation, Step, Stock, Tracker, Walker};

use crate::library::library;
use crate::progress::{Progress, Silent};
use crate::report::Report;
use crate::source::{Counting, Source};

/// A program, the machine it runs on and the wizards it may call.
pub struct Program {
    source: Source,
    config: Config,
    wizards: Box<dyn Wizards>,
}

/// Where a program goes: what it cuts, and the box of all its moves.
pub struct Extent {
    /// What the translation and the tool tracking said on the way.
    pub report: Report,
    pub cut: CutBounds,
    /// The box of every tool position; `None` when the program does not move.
    pub path_box: Option<(Point, Point)>,
}

/// How finely to simulate, as the caller asks; what it leaves out comes from
/// the config's `[render]`, else the defaults.
#[derive(Clone, Copy, Debug, Default)]
pub struct Resolution {
    /// The side of a cell, in machine units.
    pub cell: Option<f64>,
    /// MiB the height field may take.
    pub memory_limit_mib: Option<u64>,
}

/// Why no simulation could be made: the message, and whose number asked for it.
#[derive(Debug, thiserror::Error)]
#[error("{message}")]
pub struct Refused {
    pub message: String,
    pub by: Culprit,
}

/// Whose number made a simulation impossible.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Culprit {
    /// The caller's [`Resolution`].
    Caller,
    /// This key of the config's `[render]` table.
    Config(&'static str),
    /// The program, or the machine: no number anyone gave.
    Neither,
}

/// The parts of a program a pass borrows: the machine may be lent to what
/// follows the statements (a tool tracker) while the wizards are called.
struct Parts<'p> {
    source: &'p Source,
    config: &'p Config,
    wizards: &'p mut dyn Wizards,
}

impl<'p> Parts<'p> {
    /// The translation after `stage`; `count` follows the bytes of the program read.
    fn events(self, stage: u8, count: Arc<AtomicU64>) -> Box<dyn Iterator<Item = Event> + 'p> {
        self.probed_events(stage, count).0
    }

    fn probed_events(self, stage: u8, count: Arc<AtomicU64>) -> (Box<dyn Iterator<Item = Event> + 'p>, Probe) {
        let library = library(self.source, &self.config.dialect);
        let options = Options { config: self.config, stage, wizards: self.wizards };
        translate_probed(Counting { inner: self.source.open(), count }, library, options)
    }

    fn for_each_event(self, job: &'static str, progress: &mut dyn Progress, mut each: impl FnMut(Event) -> bool) {
        self.for_each_event_in_state(job, progress, |event, _| each(event))
    }

    fn for_each_event_in_state(
        self,
        job: &'static str,
        progress: &mut dyn Progress,
        mut each: impl FnMut(Event, &Snapshot) -> bool,
    ) {
        let count = Arc::new(AtomicU64::new(0));
        progress.begin(job, self.source.size());
        let (events, probe) = self.probed_events(LAST_STAGE, count.clone());
        for (n, event) in events.enumerate() {
            if !each(event, &probe.borrow()) {
                break;
            }
            if n % 4096 == 0 {
                progress.advance(count.load(Ordering::Relaxed));
                if progress.stopped() {
                    break;
                }
            }
        }
        progress.end();
    }

    fn walk(
        self,
        job: &'static str,
        progress: &mut dyn Progress,
        mut each: impl FnMut(&Statement, &mut Report) -> bool,
    ) -> Report {
        let mut report = Report::default();
        self.for_each_event(job, progress, |event| match event {
            Event::Statement(statement) => each(&statement, &mut report),
            Event::Diagnostic(diagnostic) => {
                report.add(diagnostic);
                true
            }
        });
        report
    }

    /// Hands every move of the translation to `each`, with the tool that
    /// makes it (none before the first tool change); collects the
    /// translation's diagnostics and the tracker's (a tool not in the table).
    fn moves(
        self,
        job: &'static str,
        progress: &mut dyn Progress,
        mut each: impl FnMut(&Move, Option<Cutter>),
    ) -> Report {
        let mut tracker = Tracker::new(&self.config.tools);
        self.walk(job, progress, |statement, report| {
            match tracker.step(statement) {
                Ok(Some(m)) => each(&m, tracker.cutter()),
                Ok(None) => {}
                Err(diagnostic) => report.add(diagnostic),
            }
            true
        })
    }
}

impl Program {
    /// `source` on the machine `config` describes, calling no wizards.
    pub fn new(source: Source, config: Config) -> Program {
        Program { source, config, wizards: Box::new(NoWizards) }
    }

    /// The same program, calling `wizards` for the words it does not know.
    pub fn with_wizards(self, wizards: Box<dyn Wizards>) -> Program {
        Program { wizards, ..self }
    }

    pub fn source(&self) -> &Source {
        &self.source
    }

    pub fn config(&self) -> &Config {
        &self.config
    }

    fn parts(&mut self) -> Parts<'_> {
        Parts { source: &self.source, config: &self.config, wizards: &mut *self.wizards }
    }

    /// The translation after pass `stage` (0..=[`LAST_STAGE`]), as a stream of
    /// statements and diagnostics in program order.
    pub fn events(&mut self, stage: u8) -> impl Iterator<Item = Event> + '_ {
        self.parts().events(stage, Arc::default())
    }

    /// Hands every event of the whole translation, statement or diagnostic,
    /// to `each` in the order they come (which returns false to stop),
    /// telling `progress` how much of the program the pass `job` has read.
    pub fn for_each_event(&mut self, job: &'static str, progress: &mut dyn Progress, each: impl FnMut(Event) -> bool) {
        self.parts().for_each_event(job, progress, each)
    }

    /// As [`Program::for_each_event`], with the machine state where the
    /// translation has got to (`translate_probed`'s): the program's units,
    /// distance mode and program zero a statement was read in.
    pub fn for_each_event_in_state(
        &mut self,
        job: &'static str,
        progress: &mut dyn Progress,
        each: impl FnMut(Event, &Snapshot) -> bool,
    ) {
        self.parts().for_each_event_in_state(job, progress, each)
    }

    /// Hands every output statement to `each` (which returns false to stop,
    /// and may add to the report); collects the diagnostics.
    pub fn walk(
        &mut self,
        job: &'static str,
        progress: &mut dyn Progress,
        each: impl FnMut(&Statement, &mut Report) -> bool,
    ) -> Report {
        self.parts().walk(job, progress, each)
    }

    /// The translation after pass `stage` as G-code text, a line at a time
    /// to `write`; collects the diagnostics.
    pub fn write_translation(
        &mut self,
        stage: u8,
        line_numbers: bool,
        mut write: impl FnMut(&str) -> io::Result<()>,
    ) -> io::Result<Report> {
        // Before pass 01 the numbers are still in the program's own units, which may be finer.
        let decimals = if stage == 0 { 4 } else { self.config.units.decimals() };
        let emitter = Emitter::new(decimals, line_numbers);
        let mut report = Report::default();
        let mut line = String::new();
        for event in self.events(stage) {
            match event {
                Event::Statement(statement) => {
                    line.clear();
                    emitter.write(&mut line, &statement);
                    line.push('\n');
                    write(&line)?;
                }
                Event::Diagnostic(diagnostic) => report.add(diagnostic),
            }
        }
        Ok(report)
    }

    /// The whole translation as its target controller (`[target]`, `generic`
    /// by default) takes it: the preamble naming `source_name`, every
    /// statement in the target's lines, and its closing lines. The target's
    /// notes (what it left out) join the report as warnings.
    pub fn write_output(
        &mut self,
        source_name: &str,
        line_numbers: bool,
        mut write: impl FnMut(&str) -> io::Result<()>,
    ) -> io::Result<Report> {
        let mut writer = Writer::new(&self.config, line_numbers);
        write(&writer.preamble(source_name))?;
        let mut report = Report::default();
        let mut lines = String::new();
        let mut notes = Vec::new();
        for event in self.events(LAST_STAGE) {
            match event {
                Event::Statement(statement) => {
                    lines.clear();
                    writer.write(&statement, &mut lines, &mut notes);
                    for note in notes.drain(..) {
                        report.add(note);
                    }
                    write(&lines)?;
                }
                Event::Diagnostic(diagnostic) => report.add(diagnostic),
            }
        }
        write(&writer.postamble())?;
        Ok(report)
    }

    /// Every move of the translated program, in machine coordinates, to
    /// `each` (which returns false to stop).
    pub fn toolpath(&mut self, mut each: impl FnMut(&Move) -> bool) -> Report {
        let mut walker = Walker::new();
        self.walk("toolpath", &mut Silent, |statement, _| match walker.step(statement) {
            Some(Step::Move(m)) => each(&m),
            _ => true,
        })
    }

    /// The toolpath as straight pieces (arcs split within `tolerance`), as
    /// `ger view` draws it; each piece's `line` is the number of the statement
    /// of the translation that made it (1 for the first).
    pub fn toolpath_pieces(&mut self, tolerance: f64) -> (Vec<Piece>, Report) {
        let mut found = Vec::new();
        let mut line = 0;
        let mut walker = Walker::new();
        let report = self.walk("toolpath", &mut Silent, |statement, _| {
            line += 1;
            if let Some(Step::Move(m)) = walker.step(statement) {
                pieces::split(&m, line, tolerance, &mut found);
            }
            true
        });
        (found, report)
    }

    /// Where the program cuts, and the box of its path: a pass over it.
    pub fn extent(&mut self, progress: &mut dyn Progress) -> Extent {
        let mut cut = CutBounds::default();
        let mut path_box: Option<(Point, Point)> = None;
        let report = self.parts().moves("bounds", progress, |m, cutter| {
            cut.add(&m.segment, cutter.as_ref());
            let (lo, hi) = m.segment.bounds();
            path_box = Some(path_box.map_or((lo, hi), |(l, h)| (l.min(lo), h.max(hi))));
        });
        Extent { report, cut, path_box }
    }

    /// The stock the config describes, or else (by a pass over the program)
    /// the one around what it cuts, with that pass's report.
    pub fn stock(&mut self, progress: &mut dyn Progress) -> (Stock, Report) {
        match Stock::from_config(&self.config) {
            Some(stock) => (stock, Report::default()),
            None => {
                let extent = self.extent(progress);
                (extent.cut.stock_for(&self.config), extent.report)
            }
        }
    }

    /// The simulation of `stock` at the resolution asked for (or the config's,
    /// or the default), unless it would not fit in memory: then the refusal
    /// says what would.
    pub fn simulation(&self, stock: Stock, asked: Resolution) -> Result<Simulation, Refused> {
        simulation(stock, asked, &self.config)
    }

    /// The program cut out of `simulation`'s stock: the part, and the report
    /// of the translation and the tools.
    pub fn simulate(&mut self, mut simulation: Simulation, progress: &mut dyn Progress) -> (HeightField, Report) {
        let report = self.parts().moves("cutting", progress, |m, cutter| {
            if let Some(cutter) = cutter {
                simulation.cut(&m.segment, &cutter);
            }
        });
        (simulation.finish(), report)
    }

    /// The part the program cuts out of `simulation`'s stock against
    /// `design` (placed in machine coordinates, see [`place_design`]): the
    /// comparison at `tolerance`, with the lines of the moves that cut
    /// below the design where it is gouged deepest (a second pass, over
    /// those cells alone), each cell's verdict, the part and the report.
    pub fn compare(
        &mut self,
        simulation: Simulation,
        design: &Design,
        tolerance: f64,
        progress: &mut dyn Progress,
    ) -> (Judged, HeightField, Report) {
        let (field, report) = self.simulate(simulation, progress);
        let judged = self.judge(&field, design, tolerance, progress);
        (judged, field, report)
    }

    /// `part`, which this program cut, against `design` (see [`Program::compare`]).
    pub fn judge(
        &mut self,
        field: &HeightField,
        design: &Design,
        tolerance: f64,
        progress: &mut dyn Progress,
    ) -> Judged {
        judge(std::slice::from_mut(self), field, design, tolerance, progress)
    }

    /// The verifier's verdict, cutting `simulation`'s stock: the translation's
    /// diagnostics and the checks' (all but `allowed`), and the summary; and the part.
    pub fn check(
        &mut self,
        simulation: Simulation,
        allowed: &[Rule],
        progress: &mut dyn Progress,
    ) -> (Verdict, HeightField) {
        let parts = self.parts();
        let mut checker = Checker::new(parts.config, simulation, allowed);
        parts.for_each_event("checking", progress, |event| {
            match event {
                Event::Statement(statement) => checker.statement(&statement),
                Event::Diagnostic(diagnostic) => checker.translator(diagnostic),
            }
            true
        });
        checker.finish_with_part()
    }
}

/// Programs cut one after another on one stock: a CAM job posted one file
/// an operation (roughing, finishing, drilling). Each is judged against
/// what the ones before it left; each keeps its own machine (its tools).
pub struct Job {
    /// Never empty.
    programs: Vec<Program>,
}

impl Job {
    /// `first`, then `rest`, in that order.
    pub fn new(first: Program, rest: Vec<Program>) -> Job {
        let mut programs = vec![first];
        programs.extend(rest);
        Job { programs }
    }

    pub fn programs(&self) -> &[Program] {
        &self.programs
    }

    pub fn programs_mut(&mut self) -> &mut [Program] {
        &mut self.programs
    }

    /// The first program's `[stock]`, or else the stock round what all of
    /// them cut (with the first's margin), with each program's report of
    /// the pass that found it.
    pub fn stock(&mut self, progress: &mut dyn Progress) -> (Stock, Vec<Report>) {
        if let Some(stock) = Stock::from_config(&self.programs[0].config) {
            return (stock, Vec::new());
        }
        let mut cut = CutBounds::default();
        let mut reports = Vec::new();
        for program in &mut self.programs {
            let extent = program.extent(progress);
            cut.merge(&extent.cut);
            reports.push(extent.report);
        }
        (cut.stock_for(&self.programs[0].config), reports)
    }

    /// The simulation of `stock` the first program's machine asks for (see [`Program::simulation`]).
    pub fn simulation(&self, stock: Stock, asked: Resolution) -> Result<Simulation, Refused> {
        self.programs[0].simulation(stock, asked)
    }

    /// The part all the programs cut in turn out of `simulation`'s stock,
    /// and each one's report.
    pub fn simulate(&mut self, simulation: Simulation, progress: &mut dyn Progress) -> (HeightField, Vec<Report>) {
        let (part, first) = self.programs[0].simulate(simulation, progress);
        let (part, mut reports) = self.simulate_after(0, part, progress);
        reports.insert(0, first);
        (part, reports)
    }

    /// The programs after the one at `index` cut on `part`, as that one
    /// left it, and their reports.
    pub fn simulate_after(
        &mut self,
        index: usize,
        mut part: HeightField,
        progress: &mut dyn Progress,
    ) -> (HeightField, Vec<Report>) {
        let mut reports = Vec::new();
        for program in &mut self.programs[index + 1..] {
            let report;
            (part, report) = program.simulate(Simulation::resume(part), progress);
            reports.push(report);
        }
        (part, reports)
    }

    /// Each program's verdict in turn, cutting `simulation`'s stock on from
    /// where the one before left it; and the part at the end.
    pub fn check(
        &mut self,
        mut simulation: Simulation,
        allowed: &[Rule],
        progress: &mut dyn Progress,
    ) -> (Vec<Verdict>, HeightField) {
        let mut verdicts = Vec::new();
        for program in &mut self.programs {
            let (verdict, part) = program.check(simulation, allowed, progress);
            verdicts.push(verdict);
            simulation = Simulation::resume(part);
        }
        (verdicts, simulation.finish())
    }

    /// The part the programs cut in turn out of `simulation`'s stock against
    /// `design`, as [`Program::compare`] judges one program's: the lines
    /// that gouged are each program's, named in [`Deviation::cut_by`](ger_compare::Deviation).
    pub fn compare(
        &mut self,
        simulation: Simulation,
        design: &Design,
        tolerance: f64,
        progress: &mut dyn Progress,
    ) -> (Judged, HeightField, Vec<Report>) {
        let (field, reports) = self.simulate(simulation, progress);
        let judged = self.judge(&field, design, tolerance, progress);
        (judged, field, reports)
    }

    /// `part`, which the programs cut in turn, against `design` (see [`Job::compare`]).
    pub fn judge(
        &mut self,
        field: &HeightField,
        design: &Design,
        tolerance: f64,
        progress: &mut dyn Progress,
    ) -> Judged {
        judge(&mut self.programs, field, design, tolerance, progress)
    }
}

/// `field`, which `programs` cut in turn, against `design`: the comparison,
/// with the lines of the moves that cut below the design where it is
/// gouged deepest. Those cells are cut again in the programs' order, by the
/// kernel alone: a move that lowered one below the design gouged it.
fn judge(
    programs: &mut [Program],
    field: &HeightField,
    design: &Design,
    tolerance: f64,
    progress: &mut dyn Progress,
) -> Judged {
    let top = design.top_surface(field);
    let mut judged = ger_compare::compare(field, &top, tolerance);
    if judged.gouged.is_empty() {
        return judged;
    }
    let cell = field.cell;
    let mut cells: Vec<([f64; 2], f64, f64)> =
        judged.gouged.iter().map(|&(at, below)| (at, below, field.top())).collect();
    let mut cut_by = Vec::new();
    for program in programs.iter_mut() {
        let mut lines = std::collections::BTreeSet::new();
        program.parts().moves("attributing", progress, |m, cutter| {
            let Some(cutter) = cutter else { return };
            for (at, below, height) in &mut cells {
                let low = ger_sim::lowest_over(&m.segment, &cutter, at[0], at[1], cell);
                if low < *height {
                    *height = low;
                    if low < *below {
                        lines.insert(m.span.line);
                    }
                }
            }
        });
        if !lines.is_empty() {
            cut_by.push(ger_compare::ProgramLines { file: program.source.name(), lines: lines.into_iter().collect() });
        }
    }
    let gouge = &mut judged.comparison.gouge;
    if programs.len() == 1 {
        gouge.lines = cut_by.first().map(|c| c.lines.clone()).unwrap_or_default();
    }
    gouge.cut_by = cut_by;
    judged
}

/// A stock that starts as `mesh` (a casting, an earlier job's part), in
/// machine coordinates as it is: its box.
pub fn stock_of(mesh: &Design) -> Stock {
    let (min, max) = mesh.bounds();
    Stock { min, max }
}

/// Shapes `simulation`'s stock as `mesh`'s top surface (see [`stock_of`]).
pub fn carve(simulation: &mut Simulation, mesh: &Design) {
    let top = mesh.top_surface(simulation.field());
    simulation.carve(&top);
}

/// How far a part may be off its design unless the caller says: 0.05 mm, 0.002 in.
pub fn default_tolerance(units: Units) -> f64 {
    match units {
        Units::Mm => 0.05,
        Units::Inch => 0.002,
    }
}

/// Puts `design` where the part is: its coordinates are in `units`
/// (scaled to the machine's); `origin`, where program zero is in them
/// (as `[stock] origin` says where it is in the block), or else the
/// design's lowest corner on the stock's.
pub fn place_design(design: &mut Design, config: &Config, units: Units, origin: Option<[f64; 3]>, stock: &Stock) {
    let scale = units.factor_to(config.units);
    let shift = match origin {
        Some(origin) => -Point::from(origin) * scale,
        None => stock.min - design.bounds().0 * scale,
    };
    design.place(scale, shift);
}

/// See [`Program::simulation`].
fn simulation(stock: Stock, asked: Resolution, config: &Config) -> Result<Simulation, Refused> {
    let unit = config.units.abbreviation();
    let bounds = Bounds::of(config.units);
    let refuse = |by, message| Err(Refused { message, by });
    if asked.cell.is_some_and(|cell| !(bounds.smallest..=bounds.length).contains(&cell)) {
        let message =
            format!("--resolution must be from {} to {} {unit}", quoted(bounds.smallest), quoted(bounds.length));
        return refuse(Culprit::Caller, message);
    }
    if asked.memory_limit_mib.is_some_and(|m| !(1..=MAX_MEMORY_MIB).contains(&m)) {
        return refuse(Culprit::Caller, format!("--memory-limit must be from 1 to {MAX_MEMORY_MIB} MiB"));
    }
    let size = stock.size();
    // A stock by margin is where the program goes: its coordinates may be anything.
    if !size.cmple(Point::splat(bounds.length)).all() {
        let message = format!(
            "the stock would be {} x {} x {} {unit}, everything the program cuts with a margin of {} {unit} all \
             round: over {} {unit}, more than any machine travels; check the program's coordinates, or give \
             [stock] size in ger.toml",
            label(size[0]),
            label(size[1]),
            label(size[2]),
            label(config.stock_margin()),
            label(bounds.length),
        );
        return refuse(Culprit::Neither, message);
    }
    let cell = asked.cell.or(config.render.scale.map(|s| 1.0 / s)).unwrap_or(stock.default_cell());
    // Bounded above and by the config's validation: no overflow.
    let limit = asked.memory_limit_mib.or(config.render.memory_limit_mb).unwrap_or(2048) << 20;
    Simulation::new(stock, cell, limit).map_err(|refusal| match refusal {
        Refusal::TooBig(too_big) => {
            let by = if asked.cell.is_some() || asked.memory_limit_mib.is_some() {
                Culprit::Caller
            } else if config.render.scale.is_some() {
                Culprit::Config("scale")
            } else if config.render.memory_limit_mb.is_some() {
                Culprit::Config("memory_limit_mb")
            } else {
                Culprit::Neither
            };
            let fits = match by {
                Culprit::Config(_) => format!(
                    "the most that fits is scale = {} (or raise memory_limit_mb)",
                    // Cells per unit, rounded down so that it does fit.
                    three_digits(1.0 / too_big.finest, f64::floor)
                ),
                _ => format!(
                    "the finest that fits is --resolution {} (or raise --memory-limit)",
                    three_digits(too_big.finest, f64::ceil)
                ),
            };
            let message = format!(
                "a resolution of {} {unit} needs {} MiB for the {} x {} {unit} stock, over the limit of {} MiB; {fits}",
                label(cell),
                too_big.needed >> 20,
                label(size[0]),
                label(size[1]),
                too_big.limit >> 20,
            );
            Refused { message, by }
        }
        Refusal::OutOfMemory { needed } => Refused {
            message: format!(
                "cannot have the {} MiB the height field needs at a resolution of {} {unit}: the system refused \
                 it; give a coarser --resolution or a lower --memory-limit",
                needed >> 20,
                label(cell)
            ),
            by: Culprit::Neither,
        },
    })
}

/// Three significant digits, rounded by `round` (up, so that the length
/// quoted does fit; or down).
fn three_digits(x: f64, round: fn(f64) -> f64) -> String {
    let magnitude = x.log10().floor();
    let p = 10f64.powf(magnitude - 2.0);
    let decimals = (2.0 - magnitude).max(0.0) as usize;
    let text = format!("{:.*}", decimals, round(x / p) * p);
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}
