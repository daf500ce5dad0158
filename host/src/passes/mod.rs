//! The simplification passes, 00 to 05, and the pipeline that chains them.
//!
//! Each pass is a streaming stage: an iterator over [`Event`]s that pulls
//! from the stage before it and holds only the modal state it needs, so memory
//! stays flat however long the program (subprogram bodies aside). Passes
//! 01-04 have no look-ahead: when a pass asks for the next statement, every
//! statement before it has gone through all of them. Diagnostics travel in
//! the same stream, in program order, and a statement with an error is
//! dropped so later passes see only statements that make sense.

use std::collections::VecDeque;
use std::io::BufRead;

use crate::config::Config;
use crate::diag::Diagnostic;
use crate::lex::Lexer;
use crate::parse::parse;
pub use crate::parse::Event;
use crate::statement::Statement;

pub mod p00_subprograms;
pub mod p01_units;
pub mod p02_offsets;
pub mod p03_polar;
pub mod p04_absolute;
pub mod p05_cutter_comp;

pub use p00_subprograms::Library;

/// A pass that rewrites one statement at a time.
pub trait Pass {
    fn statement(&mut self, statement: Statement, out: &mut Out);
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
        let diagnostic = diagnostic.with_origin(statement.origin.clone());
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
        Stage {
            upstream,
            pass,
            out: Out::default(),
            finished: false,
        }
    }
}

impl<I: Iterator<Item = Event>, P: Pass> Iterator for Stage<I, P> {
    type Item = Event;

    fn next(&mut self) -> Option<Event> {
        loop {
            if let Some(event) = self.out.events.pop_front() {
                return Some(event);
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

/// Lexes, parses and simplifies a program up to and including pass `stage`.
/// `library` finds subprograms that are called before they are defined.
pub fn translate<'a, R: BufRead + 'a>(
    program: R,
    library: Library<'a>,
    config: &Config,
    stage: u8,
) -> Box<dyn Iterator<Item = Event> + 'a> {
    let parsed = parse(Lexer::new(program));
    let stream: Box<dyn Iterator<Item = Event>> =
        Box::new(p00_subprograms::Subprograms::new(parsed, library));
    if stage == 0 {
        return stream;
    }
    let stream = Box::new(Stage::new(stream, p01_units::Units::new(config.units)));
    if stage == 1 {
        return stream;
    }
    let stream = Box::new(Stage::new(
        stream,
        p02_offsets::Offsets::new(config.offsets.clone()),
    ));
    if stage == 2 {
        return stream;
    }
    let stream = Box::new(Stage::new(stream, p03_polar::Polar::default()));
    if stage == 3 {
        return stream;
    }
    let stream = Box::new(Stage::new(
        stream,
        p04_absolute::Absolute::new(config.units),
    ));
    if stage == 4 {
        return stream;
    }
    Box::new(Stage::new(stream, p05_cutter_comp::CutterComp))
}

#[cfg(test)]
pub(crate) mod testing {
    //! Runs passes over small programs and shows the result as G-code.

    use super::*;
    use crate::emit::Emitter;

    /// The program after `stage`, one line per statement or diagnostic.
    pub fn run_with(text: &str, config: &Config, stage: u8) -> Vec<String> {
        let library = Library::scanning(move || Library::scan(text.as_bytes()));
        let emitter = Emitter::new(config.units.decimals(), false);
        translate(text.as_bytes(), library, config, stage)
            .map(|event| match event {
                Event::Statement(s) => emitter.line(&s),
                Event::Diagnostic(d) => d.to_string(),
            })
            .collect()
    }

    pub fn run(text: &str, stage: u8) -> Vec<String> {
        run_with(text, &Config::default(), stage)
    }
}
