//! The simplification passes, 00 to 05, and the pipeline that chains them.
//!
//! Each pass is a streaming stage: an iterator over [`Event`]s that pulls
//! from the stage before it and holds only the modal state it needs, so memory
//! stays flat however long the program (subprogram bodies aside). Passes
//! 01-04 have no look-ahead: when a pass asks for the next statement, every
//! statement before it has gone through all of them. Diagnostics travel in
//! the same stream, in program order, and a statement with an error is
//! dropped so later passes see only statements that make sense.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::io::BufRead;
use std::rc::Rc;

use crate::config::{Config, DialectConfig};
use crate::diag::Diagnostic;
use crate::lex::Lexer;
use crate::macros::Interpreter;
use crate::parse::parse_in;
pub use crate::parse::Event;
use crate::state::{self, Probe};
use crate::statement::{Dialect, Statement};
use crate::wizard::Wizards;

pub mod p00_subprograms;
pub mod p01_units;
pub mod p02_offsets;
pub mod p03_polar;
pub mod p04_absolute;
pub mod p05_cutter_comp;

use p00_subprograms::WizardRuntime;
pub use p00_subprograms::{Body, Library};

/// A pass that rewrites one statement at a time.
pub trait Pass {
    fn statement(&mut self, statement: Statement, out: &mut Out);
    /// Goes on with work a statement left unfinished, a piece at a time, so a
    /// long expansion (a canned cycle repeated L times) never sits whole in
    /// `out`; false when there is none. Called whenever `out` is empty,
    /// before the next statement is read.
    fn resume(&mut self, _out: &mut Out) -> bool {
        false
    }
    /// Called once after the last statement.
    fn finish(&mut self, _out: &mut Out) {}
}

/// Where a pass puts what it makes of a statement: zero or more statements
/// and diagnostics.
#[derive(Default)]
pub struct Out {
    events: VecDeque<Event>,
}

impl Out {
    pub fn push(&mut self, statement: Statement) {
        self.events.push_back(Event::Statement(statement));
    }

    /// Reports a problem with `statement`, naming the calls it runs in.
    pub fn error(&mut self, statement: &Statement, diagnostic: Diagnostic) {
        self.report(diagnostic.with_origin(statement.origin.clone()));
    }

    /// Reports a diagnostic that already names its calls.
    pub fn report(&mut self, diagnostic: Diagnostic) {
        self.events.push_back(Event::Diagnostic(diagnostic));
    }
}

/// Runs a [`Pass`] over the events of the stage before it.
pub struct Stage<I, P> {
    upstream: I,
    pass: P,
    out: Out,
    finished: bool,
}

impl<I: Iterator<Item = Event>, P: Pass> Stage<I, P> {
    pub fn new(upstream: I, pass: P) -> Stage<I, P> {
        Stage { upstream, pass, out: Out::default(), finished: false }
    }
}

impl<I: Iterator<Item = Event>, P: Pass> Iterator for Stage<I, P> {
    type Item = Event;

    fn next(&mut self) -> Option<Event> {
        loop {
            if let Some(event) = self.out.events.pop_front() {
                return Some(event);
            }
            if self.pass.resume(&mut self.out) {
                continue;
            }
            match self.upstream.next() {
                Some(Event::Statement(statement)) => self.pass.statement(statement, &mut self.out),
                Some(diagnostic) => return Some(diagnostic),
                None if !self.finished => {
                    self.finished = true;
                    self.pass.finish(&mut self.out);
                }
                None => return None,
            }
        }
    }
}

/// The last pass: after it, only output codes remain.
pub const LAST_STAGE: u8 = 5;

/// What a translation needs besides the program.
pub struct Options<'a> {
    pub config: &'a Config,
    /// Show the program after this pass (0..=LAST_STAGE).
    pub stage: u8,
    pub wizards: &'a mut dyn Wizards,
}

/// Lexes and parses a program in the configured dialect: the statements
/// before any pass. The lenient dialect's parameters and expressions are
/// worked out between the two, by the interpreter stage.
pub fn parse<'a, R: BufRead + 'a>(program: R, dialect: &DialectConfig) -> impl Iterator<Item = Event> + 'a {
    parse_finding(program, dialect, None, None)
}

/// As [`parse`], with `files` finding the programs G65, M98 and
/// `o<name> call` call that are kept in files of their own.
fn parse_finding<'a, R: BufRead + 'a>(
    program: R,
    dialect: &DialectConfig,
    files: Option<crate::macros::FindProgram<'a>>,
    position: Option<crate::macros::Position>,
) -> impl Iterator<Item = Event> + 'a {
    let lexer = Lexer::in_dialect(program, dialect.name);
    // The strict dialect has no parameters: its tokens go straight to the parser.
    let tokens: Box<dyn Iterator<Item = crate::lex::Lexed> + 'a> = if dialect.name == Dialect::Lenient {
        // The lines' text is kept for a backward GOTO to read them again.
        let history = crate::lex::SharedHistory::default();
        Box::new(
            Interpreter::new(lexer.recording(history.clone()).pieces(), dialect.limits)
                .with_history(history)
                .running_fanuc_programs()
                .finding_programs(files)
                .reading_position(position),
        )
    } else {
        Box::new(lexer)
    };
    parse_in(tokens, dialect.name).with_code_lists(dialect.codes.clone())
}

/// Lexes, parses and simplifies a program, yielding the statements and
/// diagnostics as they are after pass `options.stage`. `library` finds
/// subprograms that are called before they are defined.
pub fn translate<'a, R: BufRead + 'a>(
    program: R,
    library: Library<'a>,
    options: Options<'a>,
) -> Box<dyn Iterator<Item = Event> + 'a> {
    translate_probed(program, library, options).0
}

/// As [`translate`], with the machine state passes 01-04 keep: read between
/// two events, it is the state after the statement last handed out, or
/// ahead of it while a pass holds statements back (cutter compensation,
/// the moves a canned cycle expands into).
pub fn translate_probed<'a, R: BufRead + 'a>(
    program: R,
    library: Library<'a>,
    options: Options<'a>,
) -> (Box<dyn Iterator<Item = Event> + 'a>, Probe) {
    let Options { config, stage, wizards } = options;
    wizards.start();
    let probe = state::probe(config.units);
    // Every pass runs whatever the stage shown: wizards are told the state
    // that passes 01-04 keep, so they must see every statement.
    let tap = Tap::default();
    let tapped = |stream: Box<dyn Iterator<Item = Event> + 'a>, after: u8| -> Box<dyn Iterator<Item = Event> + 'a> {
        if after == stage && stage != LAST_STAGE {
            Box::new(tap.attach(stream))
        } else {
            stream
        }
    };
    let runtime = WizardRuntime { wizards, probe: probe.clone(), config };
    let mut library = library;
    let position: crate::macros::Position = {
        let (probe, units) = (probe.clone(), config.units);
        Box::new(move || probe.borrow().place(units))
    };
    let parsed = parse_finding(program, &config.dialect, library.take_program_texts(), Some(position));
    let stream = tapped(Box::new(p00_subprograms::Subprograms::new(parsed, library, runtime)), 0);
    let stream = tapped(Box::new(Stage::new(stream, p01_units::Units::new(config.units, probe.clone()))), 1);
    let stream = tapped(
        Box::new(Stage::new(stream, p02_offsets::Offsets::new(&config.offsets, config.dialect.name, probe.clone()))),
        2,
    );
    let stream = tapped(Box::new(Stage::new(stream, p03_polar::Polar::default())), 3);
    let stream = tapped(Box::new(Stage::new(stream, p04_absolute::Absolute::new(config, probe.clone()))), 4);
    let stream = Box::new(Stage::new(stream, p05_cutter_comp::CutterComp::new(config)));
    let shown: Box<dyn Iterator<Item = Event> + 'a> =
        if stage == LAST_STAGE { stream } else { Box::new(tap.drain(stream)) };
    (Box::new(shown.map(only_finite)), probe)
}

/// Nothing non-finite leaves the translator: the lexer bounds every number,
/// so this is the net under arithmetic that went wrong (a division by a
/// near-zero length), reported at the statement that made it.
fn only_finite(event: Event) -> Event {
    match event {
        Event::Statement(statement) if !statement.is_finite() => Event::Diagnostic(
            Diagnostic::error(statement.span, "this statement works out to a number too large to write")
                .with_help("a length or angle here is out of any machine's range: check the numbers it is made from")
                .with_origin(statement.origin.clone()),
        ),
        event => event,
    }
}

/// Shows an earlier stage while the later ones keep running: the events
/// leaving that stage are copied aside and handed out instead of the last
/// stage's. Passes 01-04 have no look-ahead, so little waits in the copy.
#[derive(Clone, Default)]
struct Tap {
    seen: Rc<RefCell<VecDeque<Event>>>,
}

impl Tap {
    fn attach<'a>(&self, stream: impl Iterator<Item = Event> + 'a) -> impl Iterator<Item = Event> + 'a {
        let seen = self.seen.clone();
        stream.inspect(move |event| seen.borrow_mut().push_back(event.clone()))
    }

    fn drain<'a>(self, mut rest: impl Iterator<Item = Event> + 'a) -> impl Iterator<Item = Event> + 'a {
        std::iter::from_fn(move || loop {
            if let Some(event) = self.seen.borrow_mut().pop_front() {
                return Some(event);
            }
            rest.next()?;
        })
    }
}

// For the tests of this crate and of those above it (their dev-dependency
// on `ger-core` turns on the `testing` feature).
#[cfg(any(test, feature = "testing"))]
pub mod testing {
    //! Runs passes over small programs and shows the result as G-code.

    use super::*;
    use crate::emit::Emitter;
    use crate::wizard::NoWizards;

    /// The program after `stage`, one line per statement or diagnostic.
    pub fn run_with(text: &str, config: &Config, stage: u8) -> Vec<String> {
        let library = library(text, &config.dialect);
        let emitter = Emitter::new(config.units.decimals(), false);
        let options = Options { config, stage, wizards: &mut NoWizards };
        translate(text.as_bytes(), library, options)
            .map(|event| match event {
                Event::Statement(s) => emitter.line(&s),
                Event::Diagnostic(d) => d.to_string(),
            })
            .collect()
    }

    /// The subprograms of `text`, and `text` again for M47.
    fn library<'a>(text: &'a str, dialect: &'a crate::config::DialectConfig) -> Library<'a> {
        Library::scanning(move || Library::scan(text.as_bytes(), dialect))
            .with_restart(move || Box::new(parse(text.as_bytes(), dialect)))
    }

    pub fn run(text: &str, stage: u8) -> Vec<String> {
        run_with(text, &Config::default(), stage)
    }

    /// The statements after the last pass (diagnostics make the test fail).
    pub fn statements_with(text: &str, config: &Config) -> Vec<Statement> {
        let library = library(text, &config.dialect);
        let options = Options { config, stage: LAST_STAGE, wizards: &mut NoWizards };
        translate(text.as_bytes(), library, options)
            .map(|event| match event {
                Event::Statement(s) => s,
                Event::Diagnostic(d) => panic!("{d}"),
            })
            .collect()
    }

    pub fn statements(text: &str) -> Vec<Statement> {
        statements_with(text, &Config::default())
    }
}
