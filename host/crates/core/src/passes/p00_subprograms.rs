//! Pass 00: subprograms. `M98 Pw Lw` is replaced by the body of `Ow` (up to its
//! `M99`), L times, so the output is the program in the order it runs.
//!
//! Subprograms usually follow M30, after the calls to them. Bodies met in the
//! stream are kept as they go by; a call to one not seen yet asks the
//! [`Library`] to scan the whole program once for definitions. A program with
//! no forward calls is read once.
//!
//! Wizard calls are spliced in the same way: the statements a wizard returns
//! run in place of its call, so a wizard may call subprograms and wizards,
//! and a subprogram may call wizards (each time with the state of that call).
//!
//! This is also where the stream becomes an execution trace, so it is where
//! a bare move (`X1 Y2`) gets its motion mode written out: later passes see
//! every move with its G00/G01/G02/G03.

use std::collections::{HashMap, HashSet, VecDeque};
use std::io::BufRead;
use std::sync::Arc;

use crate::config::{Config, DialectConfig};
use crate::diag::{Diagnostic, Origin, Span};
use crate::parse::Event;
use crate::state::Probe;
use crate::statement::{Cycle, CycleCode, Dialect, Kind, Motion, MotionMode, SplineCode, Statement};
use crate::wizard::{shown_name, Call, Expansion, Wizards};

/// How deep subprogram calls may nest before ger calls it runaway recursion.
pub const MAX_CALL_DEPTH: usize = 32;
/// How deep wizard calls may nest (a wizard whose output calls a wizard ...).
pub const MAX_WIZARD_DEPTH: usize = 16;

pub type Body = Arc<Vec<Statement>>;

/// The subprograms a program can call.
pub struct Library<'a> {
    bodies: HashMap<u32, Body>,
    scan: Option<Box<dyn FnOnce() -> HashMap<u32, Body> + 'a>>,
    /// Reads the program again from its start, for M47.
    reopen: Option<Reopen<'a>>,
    /// Finds a program kept in a file of its own, as a Fanuc or Haas keeps
    /// programs in its memory by number: the file's name and the body.
    files: Option<FindFile<'a>>,
    /// The programs found in files, and the files' names.
    found: HashMap<u32, (String, Body)>,
    /// The text of a program in a file of its own, for the interpreter
    /// stage to run at G65 or M98 (lenient dialect).
    texts: Option<crate::macros::FindProgram<'a>>,
}

type Reopen<'a> = Box<dyn FnMut() -> Box<dyn Iterator<Item = Event> + 'a> + 'a>;
type FindFile<'a> = Box<dyn FnMut(u32) -> Option<(String, Body)> + 'a>;

/// A subprogram to run: its body, and the file it came from if it is not
/// in the program itself.
type Found = (Body, Option<String>);

impl<'a> Library<'a> {
    /// Only the subprograms defined before they are called.
    pub fn empty() -> Library<'a> {
        Library { bodies: HashMap::new(), scan: None, reopen: None, files: None, found: HashMap::new(), texts: None }
    }

    /// `scan` is run the first time a call names a program not seen yet.
    pub fn scanning(scan: impl FnOnce() -> HashMap<u32, Body> + 'a) -> Library<'a> {
        Library { scan: Some(Box::new(scan)), ..Library::empty() }
    }

    /// `files` looks for a program the program itself does not define, in
    /// files of its own (the lenient dialect).
    pub fn with_files(mut self, files: impl FnMut(u32) -> Option<(String, Body)> + 'a) -> Library<'a> {
        self.files = Some(Box::new(files));
        self
    }

    /// `texts` finds the text of a program or subroutine in a file of its
    /// own, which the interpreter stage runs at G65, M98 and `o<name> call`
    /// with the parameters of the moment.
    pub fn with_program_texts(
        mut self,
        texts: impl FnMut(crate::macros::Wanted<'_>) -> Option<(String, Vec<u8>)> + 'a,
    ) -> Library<'a> {
        self.texts = Some(Box::new(texts));
        self
    }

    pub(crate) fn take_program_texts(&mut self) -> Option<crate::macros::FindProgram<'a>> {
        self.texts.take()
    }

    /// The body of program `number` in a file of its own: the file's first
    /// O word must name it, and it runs to its M99 (or M30, or the end).
    pub fn scan_file(program: impl BufRead, number: u32, dialect: &DialectConfig) -> Option<Body> {
        let mut statements = super::parse(program, dialect).filter_map(|event| match event {
            Event::Statement(statement) => Some(statement),
            Event::Diagnostic(_) => None,
        });
        match statements.next()?.kind {
            Kind::Program(n) if n == number => {}
            _ => return None,
        }
        let body = statements.take_while(|s| !matches!(s.kind, Kind::Return | Kind::End)).collect();
        Some(Arc::new(body))
    }

    /// `reopen` parses the program again from its start: M47 (lenient
    /// dialect) repeats the program by reading it again, not by keeping it.
    pub fn with_restart(mut self, reopen: impl FnMut() -> Box<dyn Iterator<Item = Event> + 'a> + 'a) -> Library<'a> {
        self.reopen = Some(Box::new(reopen));
        self
    }

    /// Reads a whole program and keeps the body of every subprogram in it.
    pub fn scan(program: impl BufRead, dialect: &DialectConfig) -> HashMap<u32, Body> {
        let mut bodies = HashMap::new();
        let mut current: Option<(u32, Vec<Statement>)> = None;
        let mut first = true;
        for event in super::parse(program, dialect) {
            let Event::Statement(statement) = event else {
                continue;
            };
            match (&statement.kind, &mut current) {
                (Kind::Program(_), _) if first => {}
                (Kind::Program(n), None) => current = Some((*n, Vec::new())),
                (Kind::Return, Some(_)) => {
                    let (n, body) = current.take().expect("matched Some");
                    bodies.entry(n).or_insert_with(|| Arc::new(body));
                }
                (_, Some((_, body))) => body.push(statement),
                (_, None) => {}
            }
            first = false;
        }
        bodies
    }

    fn find(&mut self, program: u32) -> Option<Found> {
        if !self.bodies.contains_key(&program) {
            if let Some(scan) = self.scan.take() {
                for (n, body) in scan() {
                    self.bodies.entry(n).or_insert(body);
                }
            }
        }
        if let Some(body) = self.bodies.get(&program) {
            return Some((body.clone(), None));
        }
        if !self.found.contains_key(&program) {
            let file = self.files.as_mut().and_then(|files| files(program))?;
            self.found.insert(program, file);
        }
        self.found.get(&program).map(|(file, body)| (body.clone(), Some(file.clone())))
    }
}

struct Frame {
    body: Body,
    next: usize,
    repeats_left: u32,
    origin: Arc<Origin>,
    wizard: bool,
}

/// What pass 00 needs to run wizard calls.
pub struct WizardRuntime<'a> {
    pub wizards: &'a mut dyn Wizards,
    pub probe: Probe,
    pub config: &'a Config,
}

pub struct Subprograms<'a, I> {
    upstream: I,
    /// The program read again after an M47, in place of `upstream`.
    restarted: Option<Box<dyn Iterator<Item = Event> + 'a>>,
    /// How many more times M47 may repeat the program.
    repeats_left: u32,
    library: Library<'a>,
    runtime: WizardRuntime<'a>,
    stack: Vec<Frame>,
    /// How many statements and repeats the stack has run, against
    /// `[machine] max_blocks`: repeats nested in repeats multiply.
    blocks_run: u64,
    /// The runs went past `max_blocks`: the program ends.
    stopped: bool,
    /// The subprogram being defined in the main stream, and its body so far.
    defining: Option<(u32, Span, Vec<Statement>)>,
    /// Programs defined in the main stream so far, to catch a second definition.
    defined: HashSet<u32>,
    seen_first_statement: bool,
    ended: bool,
    warned_after_end: bool,
    /// Events to hand out before reading on.
    pending: VecDeque<Event>,
    motion: MotionMode,
    /// The canned cycle a bare position repeats, until G80 or a motion code.
    cycle: Option<CycleCode>,
    /// After a spline code (lenient), what a line without a motion code is.
    after_spline: Option<AfterSpline>,
}

/// As in LinuxCNC, G5.2 makes each line of X Y P a control point of its
/// NURBS, while G5, G5.1 and G5.3 leave no motion mode in force.
#[derive(Clone, Copy)]
enum AfterSpline {
    Nurbs,
    NoMode(&'static str),
}

impl<'a, I: Iterator<Item = Event>> Subprograms<'a, I> {
    pub fn new(upstream: I, library: Library<'a>, runtime: WizardRuntime<'a>) -> Subprograms<'a, I> {
        Subprograms {
            upstream,
            restarted: None,
            repeats_left: runtime.config.machine.m47_repeats,
            library,
            runtime,
            stack: Vec::new(),
            blocks_run: 0,
            stopped: false,
            defining: None,
            defined: HashSet::new(),
            seen_first_statement: false,
            ended: false,
            warned_after_end: false,
            pending: VecDeque::new(),
            motion: MotionMode::Rapid,
            cycle: None,
            after_spline: None,
        }
    }

    /// The next statement of the innermost running subprogram, if any.
    fn next_from_stack(&mut self) -> Option<Statement> {
        while !self.stack.is_empty() {
            if !self.count_block() {
                return None;
            }
            let frame = self.stack.last_mut().expect("not empty");
            if let Some(statement) = frame.body.get(frame.next) {
                frame.next += 1;
                let mut statement = statement.clone();
                statement.origin = Some(frame.origin.clone());
                return Some(statement);
            }
            if frame.repeats_left > 1 {
                frame.repeats_left -= 1;
                frame.next = 0;
            } else {
                self.stack.pop();
            }
        }
        None
    }

    /// Counts a statement or a repeat the stack runs. Past `max_blocks` the
    /// program ends with an error at the outermost call: false then.
    fn count_block(&mut self) -> bool {
        self.blocks_run += 1;
        let limit = self.runtime.config.dialect.limits.blocks;
        if self.blocks_run <= limit {
            return true;
        }
        let outermost = self.stack[0].origin.call;
        let message = format!("the calls from here ran {limit} blocks without ending: stopped");
        let help = "raise [machine] max_blocks in ger.toml if the program is meant to run longer";
        self.pending.push_back(Event::Diagnostic(Diagnostic::error(outermost, message).with_help(help)));
        self.stack.clear();
        self.stopped = true;
        false
    }

    /// Handles a statement from the main program text. Returns what to emit.
    fn main_statement(&mut self, statement: Statement) -> Option<Event> {
        let first = !std::mem::replace(&mut self.seen_first_statement, true);
        if let Some((number, start, body)) = &mut self.defining {
            match statement.kind {
                Kind::Return => {
                    let (number, _, body) = self.defining.take().expect("matched Some");
                    self.library.bodies.entry(number).or_insert_with(|| Arc::new(body));
                }
                Kind::Program(inner) => {
                    let message = format!("O{inner} starts inside O{number}, which has no M99 yet");
                    let help = format!(
                        "end O{number} (begun at line {}) with M99 before starting another program",
                        start.line
                    );
                    return Some(error(&statement, Diagnostic::error(statement.span, message).with_help(help)));
                }
                _ => body.push(statement),
            }
            return None;
        }
        match statement.kind {
            Kind::Program(_) if first => None,
            Kind::Program(number) => {
                self.defining = Some((number, statement.span, Vec::new()));
                if !self.defined.insert(number) {
                    // LinuxCNC runs the first and reads past the second.
                    if self.runtime.config.dialect.name == Dialect::Lenient {
                        let message = format!("O{number} is defined again: calls run its first definition");
                        let diagnostic = Diagnostic::warning(statement.span, message)
                            .with_help("give each subprogram its own number, or remove the one that never runs");
                        return Some(error(&statement, diagnostic));
                    }
                    let diagnostic = Diagnostic::error(statement.span, format!("O{number} is defined twice"))
                        .with_help("give each subprogram its own number; calls run the first definition");
                    return Some(error(&statement, diagnostic));
                }
                None
            }
            _ if self.ended => {
                if std::mem::replace(&mut self.warned_after_end, true) {
                    return None;
                }
                let diagnostic = Diagnostic::warning(statement.span, "this statement follows M30 and never runs")
                    .with_help("after M30, only subprograms (O... to M99) belong in the file");
                Some(Event::Diagnostic(diagnostic))
            }
            // A subprogram's file run on its own: LinuxCNC ends the program at
            // its M99, as the lenient dialect does; Fanuc and Haas would rewind.
            Kind::Return if self.runtime.config.dialect.name == Dialect::Lenient => {
                let message = "M99 in the main program ends it here";
                let help = "a Fanuc or Haas would run the program again: write M30 to end it, or M47 to repeat it";
                self.pending.push_back(Event::Diagnostic(Diagnostic::warning(statement.span, message).with_help(help)));
                self.main_statement(statement.with_kind(Kind::End))
            }
            Kind::Return => {
                let diagnostic = Diagnostic::error(statement.span, "M99 outside a subprogram")
                    .with_help("M99 ends a subprogram that starts with O<number>; the main program ends with M30");
                Some(Event::Diagnostic(diagnostic))
            }
            Kind::End => {
                self.ended = true;
                Some(Event::Statement(statement))
            }
            Kind::Repeat => {
                if let Some(reopen) = self.library.reopen.as_mut().filter(|_| self.repeats_left > 0) {
                    self.repeats_left -= 1;
                    self.restarted = Some(reopen());
                    self.seen_first_statement = false;
                    self.defined.clear();
                    return None;
                }
                // A machine would repeat it for ever; the translation stops here.
                self.ended = true;
                Some(Event::Statement(statement.with_kind(Kind::End)))
            }
            _ => self.run(statement),
        }
    }

    /// Runs a statement in execution order: calls push a frame, moves get
    /// their motion mode.
    fn run(&mut self, mut statement: Statement) -> Option<Event> {
        if let Kind::NextPoint { .. } = statement.kind {
            return self.next_point(statement);
        }
        match &mut statement.kind {
            Kind::Call { program, repeat } => {
                let (program, repeat) = (*program, *repeat);
                if self.stack.len() >= MAX_CALL_DEPTH {
                    let message = format!(
                        "subprogram calls nest deeper than {MAX_CALL_DEPTH}: M98 P{program} recurses without end"
                    );
                    let diagnostic = Diagnostic::error(statement.span, message)
                        .with_help("a subprogram that calls itself, directly or through others, never returns");
                    // Unwind: the rest of this recursion would only repeat the error.
                    self.stack.clear();
                    return Some(error(&statement, diagnostic));
                }
                // Fanuc packs the repeats into P when L is not given: P30010 runs O0010 three
                // times (if there is no O30010).
                let lenient = self.runtime.config.dialect.name == Dialect::Lenient;
                let (program, repeat, found) = match self.library.find(program) {
                    None if lenient && program >= 10_000 && repeat == 1 => {
                        let (times, packed) = (program / 10_000, program % 10_000);
                        match self.library.find(packed) {
                            Some(found) => (packed, times, Some(found)),
                            None => (program, repeat, None),
                        }
                    }
                    found => (program, repeat, found),
                };
                let Some((mut body, file)) = found else {
                    let mut help = format!("define it after M30: O{program} ... M99");
                    if self.runtime.config.dialect.name == Dialect::Lenient {
                        help.push_str(&format!(", or keep it in a file of its own beside the program (O{program}.nc)"));
                    }
                    let diagnostic =
                        Diagnostic::error(statement.span, format!("M98 calls O{program}, which is not in the program"))
                            .with_help(help);
                    return Some(error(&statement, diagnostic));
                };
                if file.is_some() {
                    // Its lines are another file's: they say where the call is, as a wizard's do.
                    let mut statements = body.to_vec();
                    statements.iter_mut().for_each(|s| s.span = statement.span);
                    body = Arc::new(statements);
                }
                if repeat > 0 {
                    let what = match &file {
                        Some(file) => format!("O{program} (from {file})"),
                        None => format!("O{program}"),
                    };
                    let origin = Arc::new(Origin { what, call: statement.span, parent: statement.origin.clone() });
                    self.stack.push(Frame { body, next: 0, repeats_left: repeat, origin, wizard: false });
                }
                None
            }
            Kind::Repeat => {
                let diagnostic = Diagnostic::error(statement.span, "M47 inside a subprogram")
                    .with_help("M47 repeats the main program; a subprogram repeats with M98 P.. L..");
                Some(error(&statement, diagnostic))
            }
            Kind::End => {
                let diagnostic = Diagnostic::error(statement.span, "M30 inside a subprogram")
                    .with_help("a subprogram returns with M99; M30 ends the main program");
                Some(error(&statement, diagnostic))
            }
            // Only a wizard's output brings these here (a subprogram's body
            // ends before its M99): run in place of the call, M99 would end
            // the main program, and O would define a subprogram inside one.
            Kind::Return | Kind::Program(_) if self.stack.last().is_some_and(|frame| frame.wizard) => {
                let frame = self.stack.pop().expect("matched Some");
                let (message, help) = match statement.kind {
                    Kind::Program(number) => (
                        format!(
                            "O{number} in the output of {}: a wizard cannot define a subprogram",
                            frame.origin.what
                        ),
                        "subprograms are defined in the program (O... to M99, after M30); \
                         a wizard's output may call them with M98 P...",
                    ),
                    _ => (
                        format!("M99 in the output of {}", frame.origin.what),
                        "a wizard's statements run in place of its call, not as a subprogram: \
                         there M99 would end the main program (on Fanuc or Haas, rewind and repeat it)",
                    ),
                };
                let help = format!("{help}; the rest of this call's statements are dropped");
                Some(error(&statement, Diagnostic::error(statement.span, message).with_help(help)))
            }
            Kind::Wizard { name, args } => {
                let depth = self.stack.iter().filter(|frame| frame.wizard).count();
                if depth >= MAX_WIZARD_DEPTH {
                    let name = shown_name(name);
                    let message =
                        format!("wizard calls nest deeper than {MAX_WIZARD_DEPTH}: `{name}` recurses without end");
                    let diagnostic = Diagnostic::error(statement.span, message)
                        .with_help("a wizard whose output calls itself, directly or through others, never finishes");
                    self.stack.clear();
                    return Some(error(&statement, diagnostic));
                }
                let state = self.runtime.probe.borrow().call_state(self.runtime.config, statement.span.line);
                let call = Call { name, args, span: statement.span };
                match self.runtime.wizards.expand(&call, &state) {
                    Ok(Expansion { statements: mut body, warnings }) => {
                        let warnings = warnings.into_iter().map(|w| w.with_origin(statement.origin.clone()));
                        self.pending.extend(warnings.map(Event::Diagnostic));
                        for generated in &mut body {
                            generated.span = statement.span;
                        }
                        let origin = Arc::new(Origin {
                            what: format!("wizard `{}`", shown_name(name)),
                            call: statement.span,
                            parent: statement.origin.clone(),
                        });
                        self.stack.push(Frame { body: Arc::new(body), next: 0, repeats_left: 1, origin, wizard: true });
                        None
                    }
                    Err(diagnostic) => Some(error(&statement, diagnostic)),
                }
            }
            Kind::Motion(motion) => {
                if let Err(diagnostic) = self.check_bare_words(motion, statement.span) {
                    return Some(error(&statement, diagnostic));
                }
                match (motion.mode, self.cycle) {
                    (Some(mode), _) => {
                        self.motion = mode;
                        self.cycle = None;
                        self.after_spline = None;
                    }
                    // In a series of canned cycles, a bare position is one more hole.
                    (None, Some(code)) if motion.moves() => {
                        let cycle = Cycle {
                            code,
                            target: motion.target,
                            r: motion.radius,
                            q: None,
                            p: None,
                            repeat: 1,
                            feed: motion.feed,
                        };
                        return Some(Event::Statement(statement.with_kind(Kind::Cycle(Box::new(cycle)))));
                    }
                    (None, _) => motion.mode = Some(self.motion),
                }
                Some(Event::Statement(statement))
            }
            Kind::MachineMove(motion) => {
                motion.mode = motion.mode.or(Some(self.motion));
                Some(Event::Statement(statement))
            }
            Kind::Cycle(cycle) => {
                self.cycle = Some(cycle.code);
                self.after_spline = None;
                Some(Event::Statement(statement))
            }
            Kind::Spline(spline) => {
                match (spline.code, self.after_spline) {
                    (Some(code), _) => {
                        self.after_spline = Some(match code {
                            SplineCode::Nurbs => AfterSpline::Nurbs,
                            _ => AfterSpline::NoMode(code.code()),
                        });
                        self.cycle = None;
                    }
                    (None, Some(AfterSpline::Nurbs)) => spline.code = Some(SplineCode::Nurbs),
                    (None, _) => {
                        let (letter, word) = spline.weight.map_or(('L', statement.span), |p| ('P', p.span));
                        let message = format!("{letter} is not used by {}, the motion mode in force", self.mode_name());
                        let diagnostic = Diagnostic::error(word, message)
                            .with_help("lines of X Y P are the control points of a NURBS: they follow G5.2");
                        return Some(error(&statement, diagnostic));
                    }
                }
                Some(Event::Statement(statement))
            }
            Kind::NurbsEnd => {
                self.after_spline = Some(AfterSpline::NoMode("G5.3"));
                self.cycle = None;
                Some(Event::Statement(statement))
            }
            // G80 ends the series, here and in pass 04, which drops it.
            Kind::CycleCancel => {
                self.cycle = None;
                Some(Event::Statement(statement))
            }
            Kind::NoEffect(_) => None,
            _ => Some(Event::Statement(statement)),
        }
    }
}

impl<I: Iterator<Item = Event>> Subprograms<'_, I> {
    /// A line of axis words with P, L or Q: a NURBS's next point, or the
    /// next hole of the canned cycle in force, whichever is in force.
    fn next_point(&mut self, statement: Statement) -> Option<Event> {
        let Statement { kind: Kind::NextPoint { point, hole }, span, origin } = statement else {
            unreachable!("run hands only NextPoint here")
        };
        let kind = match (self.after_spline, self.cycle, point, hole) {
            (Some(AfterSpline::Nurbs), _, point, _) => point.map(Kind::Spline),
            (None, Some(code), _, hole) => hole.map(|mut hole| {
                hole.code = code;
                Kind::Cycle(hole)
            }),
            // Neither: the spline's reading says what the mode in force does not take.
            (_, _, Ok(point), _) => Ok(Kind::Spline(point)),
            _ => {
                let message = format!("P, L and Q are not used by {}, the motion mode in force", self.mode_name());
                let help = "with no code, they go with a canned cycle (G81 ...) or a NURBS (G5.2) in force";
                Err(Box::new(Diagnostic::error(span, message).with_help(help)))
            }
        };
        match kind {
            Ok(kind) => self.run(Statement { kind, span, origin }),
            Err(diagnostic) => Some(Event::Diagnostic(diagnostic.with_origin(origin))),
        }
    }
}

impl<I> Subprograms<'_, I> {
    /// The code a line without one moves by, for messages.
    fn mode_name(&self) -> &'static str {
        match (self.after_spline, self.cycle) {
            (Some(AfterSpline::NoMode(code)), _) => code,
            (Some(AfterSpline::Nurbs), _) => "G5.2",
            (None, Some(cycle)) => cycle.code(),
            (None, None) => self.motion.code(),
        }
    }

    /// A line with no G code moves in the mode in force, which may have no use
    /// for some of its words: I, J, K and R belong to arcs, a canned cycle has
    /// no centre, and it repeats only at a new position. Dropping such a word
    /// would hide a mistake, and writing it out would put R on a G00, so it is
    /// an error, as in LinuxCNC ("R word with no g code that uses it").
    fn check_bare_words(&self, motion: &Motion, span: Span) -> Result<(), Diagnostic> {
        if motion.mode.is_some() {
            return Ok(());
        }
        match self.after_spline {
            Some(AfterSpline::Nurbs) if motion.moves() => {
                return Err(Diagnostic::error(span, "a NURBS control point needs a weight P greater than zero")
                    .with_help("G5.2 is in force: write e.g. X1 Y2 P1, or a motion code for a move of another kind"));
            }
            Some(AfterSpline::NoMode(code)) if motion.moves() => {
                return Err(Diagnostic::error(
                    span,
                    format!("a move with no motion code after {code}, which leaves none in force"),
                )
                .with_help("write the motion code on this line, e.g. G01; only G5.2 goes on in lines of X Y P"));
            }
            _ => {}
        }
        let centre = (0..3).find_map(|axis| motion.centre.get(axis).map(|v| (["I", "J", "K"][axis], v)));
        let radius = motion.radius.map(|v| ("R", v));
        match self.cycle {
            Some(code) => {
                let code = code.code();
                if let Some((letter, v)) = centre {
                    return Err(Diagnostic::error(
                        v.span,
                        format!("{letter} is not used by {code}, the canned cycle in force"),
                    )
                    .with_help("a line without a G code repeats the cycle at its X, Y and Z; it takes R and F too"));
                }
                if let (Some((_, v)), true) = (radius, motion.target.is_empty()) {
                    return Err(Diagnostic::error(
                        v.span,
                        format!("R with no X, Y or Z does not repeat {code}, the canned cycle in force"),
                    )
                    .with_help("give the next hole's position on this line with it, e.g. X1 Y1 R0.2"));
                }
            }
            None if !self.motion.is_arc() => {
                if let Some((letter, v)) = centre.or(radius) {
                    let code = self.motion.code();
                    return Err(Diagnostic::error(
                        v.span,
                        format!("{letter} is not used by {code}, the motion mode in force"),
                    )
                    .with_help(
                        "I, J, K and R belong to arcs: write G02 or G03 on this line for an arc, or remove the word",
                    ));
                }
            }
            None => {}
        }
        Ok(())
    }
}

fn error(statement: &Statement, diagnostic: Diagnostic) -> Event {
    Event::Diagnostic(diagnostic.with_origin(statement.origin.clone()))
}

impl<I: Iterator<Item = Event>> Iterator for Subprograms<'_, I> {
    type Item = Event;

    fn next(&mut self) -> Option<Event> {
        loop {
            if let Some(event) = self.pending.pop_front() {
                return Some(event);
            }
            let event = match self.next_from_stack() {
                Some(statement) => self.run(statement),
                None if self.stopped => return self.pending.pop_front(),
                None => match self.restarted.as_mut().map_or_else(|| self.upstream.next(), |stream| stream.next()) {
                    Some(Event::Statement(statement)) => self.main_statement(statement),
                    Some(diagnostic) => Some(diagnostic),
                    None => {
                        let (number, span, _) = self.defining.take()?;
                        let diagnostic = Diagnostic::error(span, format!("O{number} has no M99 to end it"))
                            .with_help("a subprogram runs from O<number> to M99");
                        Some(Event::Diagnostic(diagnostic))
                    }
                },
            };
            if event.is_some() {
                return event;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::config::Config;
    use crate::passes::testing::{run, run_with};
    use crate::statement::Dialect;

    #[test]
    fn repeats_nested_in_repeats_are_stopped_past_max_blocks() {
        let mut config = Config::default();
        config.dialect.limits.blocks = 50;
        // A pass of O200 runs its move and its end: 2 blocks, 20 for L10. A pass
        // of O100 runs its M98, those 20 and its end: 22. Two passes make 44; the
        // third stops at the 51st block, after three moves of its O200.
        let program = "O1\nM98 P100 L10\nM30\nO100\nM98 P200 L10\nM99\nO200\nG01 X1 F10\nM99\n";
        let got = run_with(program, &config, 0);
        assert_eq!(got.iter().filter(|line| line.starts_with("G01")).count(), 23, "{got:?}");
        assert_eq!(got.last().unwrap(), "2:1: error: the calls from here ran 50 blocks without ending: stopped");
        assert!(!got.iter().any(|line| line == "M30"), "the program ends at the stop: {got:?}");
    }

    #[test]
    fn calls_are_replaced_by_the_body_l_times() {
        let program = "O1\nG01 X1 F10\nM98 P100 L2\nM30\nO100\nG91\nX1\nM99\n";
        assert_eq!(run(program, 0), ["G01 X1.0000 F10.0000", "G91", "G01 X1.0000", "G91", "G01 X1.0000", "M30"]);
    }

    #[test]
    fn nested_calls_and_definitions_before_use() {
        // The first O names the main program; later ones start subprograms.
        let program = "O1\nO5\nY2\nM98 P6\nM99\nO6\nZ3\nM99\nM98 P5 L1\nM30\n";
        assert_eq!(run(program, 0), ["G00 Y2.0000", "G00 Z3.0000", "M30"]);
    }

    #[test]
    fn bare_moves_take_the_mode_in_force_where_they_run() {
        let program = "G01 X1 F5\nM98 P2\nG00 X0\nM98 P2\nM30\nO2\nY1\nM99\n";
        assert_eq!(run(program, 0), ["G01 X1.0000 F5.0000", "G01 Y1.0000", "G00 X0.0000", "G00 Y1.0000", "M30"]);
    }

    #[test]
    fn arc_words_on_a_bare_line_need_an_arc_to_use_them() {
        // In G00/G01 nothing uses I, J, K or R: before, `R0.5` came out as `G00 R0.5000`.
        assert_eq!(run("R0.5\nM30", 0), ["1:1: error: R is not used by G00, the motion mode in force", "M30"]);
        assert_eq!(
            run("G01 X1 F5\nX2 J1\nM30", 0),
            ["G01 X1.0000 F5.0000", "2:4: error: J is not used by G01, the motion mode in force", "M30"]
        );
        // The mode is the one where the line runs, as for any bare move.
        let got = run("G02 X2 I1 F5\nM98 P2\nG00 X0\nM98 P2\nM30\nO2\nI1\nM99", 0);
        // First in G02: a full circle, the bare I1 being its centre.
        assert_eq!(got[1], "G02 I1.0000", "{got:?}");
        assert_eq!(got[3], "7:1: error: I is not used by G00, the motion mode in force", "{got:?}");
        // An arc's own words are its business (pass 04 checks them).
        assert_eq!(run("G02 X2 I1 F5\nX0 I-1\nM30", 0)[1], "G02 X0.0000 I-1.0000");
    }

    #[test]
    fn a_line_with_no_code_gives_a_canned_cycle_new_words() {
        // As rs274 runs `X2 P1` after a G82 (a new dwell), `X1 L2` (two
        // repeats) and `X6 Q2` after a G83 (a new peck).
        let config = Config { dialect: Dialect::Lenient.into(), ..Config::default() };
        let program = "G82 X1 Y1 Z-2 R2 P0.5 F100\nX2 P1\nX1 L2\nG83 X5 Z-4 R2 Q1\nX6 Q2";
        let got = run_with(program, &config, 0);
        assert_eq!(
            got[1..],
            ["G82 X2.0000 P1.0000", "G82 X1.0000 L2", "G83 X5.0000 Z-4.0000 R2.0000 Q1.0000", "G83 X6.0000 Q2.0000"]
        );
        // With no cycle or NURBS in force they are an error.
        let got = run_with("G01 X1 F10\nX2 P1\nX2 Y1 P1", &config, 0);
        assert_eq!(got[1], "2:1: error: P, L and Q are not used by G01, the motion mode in force");
        assert_eq!(got[2], "3:7: error: P is not used by G01, the motion mode in force");
        // After G5.2 the same words are the next control point.
        let got = run_with("G01 F100\nG5.2 X0 Y1 P1 L3\nX2 Y1 P1\nX3 Y0 P1\nG5.3", &config, 0);
        assert_eq!(got[2..4], ["G5.2 X2.0000 Y1.0000 P1.0000", "G5.2 X3.0000 Y0.0000 P1.0000"]);
    }

    #[test]
    fn a_canned_cycle_repeats_only_at_a_position_and_has_no_centre() {
        let config = crate::config::Config { dialect: crate::statement::Dialect::Lenient.into(), ..Default::default() };
        let cycle = "G81 X0 Z-1 R0.1 F5\n";
        // R changes with a new hole, not alone: alone LinuxCNC rejects it, and ger drilled the same hole again.
        let got = run_with(&format!("{cycle}R0.2\nX1 R0.3\nM30"), &config, 0);
        assert_eq!(got[1], "2:1: error: R with no X, Y or Z does not repeat G81, the canned cycle in force");
        assert!(got[2].starts_with("G81 X1.0000") && got[2].contains("R0.3000"), "{got:?}");
        let got = run_with(&format!("{cycle}X1 I2\nM30"), &config, 0);
        assert_eq!(got[1], "2:4: error: I is not used by G81, the canned cycle in force");
    }

    #[test]
    fn unknown_programs_and_recursion_are_errors_not_hangs() {
        assert_eq!(run("M98 P9\nM30", 0), ["1:1: error: M98 calls O9, which is not in the program", "M30"]);
        let got = run("M98 P1\nM30\nO1\nX1\nM98 P1\nM99", 0);
        assert_eq!(got.iter().filter(|l| l.contains("nest deeper than 32")).count(), 1, "{got:?}");
        assert_eq!(got.iter().filter(|l| l.as_str() == "G00 X1.0000").count(), 32);
    }

    #[test]
    fn a_second_definition_is_an_error() {
        let got = run("M98 P1\nM30\nO1\nX1\nM99\nO1\nX2\nM99", 0);
        assert_eq!(got, ["G00 X1.0000", "M30", "6:1: error: O1 is defined twice"]);
    }

    #[test]
    fn a_second_definition_is_read_past_in_the_lenient_dialect() {
        // rs274 runs the first of two O2s (LinuxCNC's test m98m99/10-M98-P001), O0002 being O2.
        let config = Config { dialect: Dialect::Lenient.into(), ..Config::default() };
        let got = run_with("M98 P2\nM30\nO0002\nX1\nM99\nO2\nX2\nM99", &config, 0);
        assert_eq!(got, ["G00 X1.0000", "M30", "6:1: warning: O2 is defined again: calls run its first definition"]);
    }

    #[test]
    fn misplaced_m99_m30_and_trailing_code() {
        assert_eq!(run("X1\nM99", 0), ["G00 X1.0000", "2:1: error: M99 outside a subprogram"]);
        assert_eq!(run("M30\nX1\nY1", 0), ["M30", "2:1: warning: this statement follows M30 and never runs"]);
        assert_eq!(run("M98 P1\nM30\nO1\nM30\nM99", 0)[0], "4:1: error: M30 inside a subprogram");
        assert_eq!(run("M30\nO1\nX1", 0)[1], "2:1: error: O1 has no M99 to end it");
    }

    #[test]
    fn m47_repeats_the_program_a_bounded_number_of_times() {
        let mut config =
            crate::config::Config { dialect: crate::statement::Dialect::Lenient.into(), ..Default::default() };
        config.machine.m47_repeats = 2;
        let got = run_with("O9\nG91\nG00 X1\nM98 P5\nM47\nO5\nY1\nM99", &config, 0);
        let once = ["G91", "G00 X1.0000", "G00 Y1.0000"];
        assert_eq!(got, [&once[..], &once[..], &once[..], &["M30"]].concat());
        // Inside a subprogram it is an error.
        assert_eq!(run_with("M98 P5\nM30\nO5\nM47\nM99", &config, 0)[0], "4:1: error: M47 inside a subprogram");
    }

    #[test]
    fn wizard_calls_without_a_wizard_are_errors() {
        assert_eq!(run("Pocket 1 2 3", 0), ["1:1: error: no wizard named `Pocket` to run this call"]);
    }

    mod wizards {
        use crate::config::Config;
        use crate::diag::Diagnostic;
        use crate::emit::Emitter;
        use crate::lex::lex_str;
        use crate::parse::{parse, Event};
        use crate::passes::{translate, Library, Options};
        use crate::state::{CallState, Spindle};
        use crate::statement::{Distance, Units, WizardArg};
        use crate::wizard::{Call, Expansion, Wizards};

        /// Records what it is told and answers with the G-code text it is given.
        struct Fake {
            seen: Vec<CallState>,
            args: Vec<Vec<WizardArg>>,
            answer: &'static str,
        }

        impl Wizards for Fake {
            fn expand(&mut self, call: &Call, state: &CallState) -> Result<Expansion, Diagnostic> {
                self.seen.push(state.clone());
                self.args.push(call.args.to_vec());
                let statements = parse(lex_str(self.answer))
                    .map(|e| match e {
                        Event::Statement(s) => s,
                        Event::Diagnostic(d) => panic!("{d}"),
                    })
                    .collect();
                Ok(Expansion { statements, warnings: Vec::new() })
            }
        }

        fn run(program: &str, fake: &mut Fake) -> Vec<String> {
            let config = Config::default();
            let emitter = Emitter::new(4, true);
            let options = Options { config: &config, stage: 5, wizards: fake };
            translate(program.as_bytes(), Library::empty(), options)
                .map(|e| match e {
                    Event::Statement(s) => emitter.line(&s),
                    Event::Diagnostic(d) => format!("{d} {:?}", d.call_chain()),
                })
                .collect()
        }

        #[test]
        fn a_wizards_arguments_may_be_expressions_worked_out_before_the_call() {
            // Lenient: `[#1 * 2]` with #1 = 5 is 10, `#<depth>` -1.5, `-SQRT[16]` -4, a string stays one.
            let mut fake = Fake { seen: Vec::new(), args: Vec::new(), answer: "G01 X1 F100" };
            let config = Config { dialect: crate::statement::Dialect::Lenient.into(), ..Config::default() };
            let options = Options { config: &config, stage: 5, wizards: &mut fake };
            let program = "#1 = 5\n#<depth> = -1.5\nPocket [#1 * 2] #<depth> -SQRT[16] \"A\" 3\nM30";
            let errors: Vec<String> = translate(program.as_bytes(), Library::empty(), options)
                .filter_map(|e| match e {
                    Event::Diagnostic(d) => Some(d.to_string()),
                    Event::Statement(_) => None,
                })
                .collect();
            assert!(errors.is_empty(), "{errors:?}");
            let expected = [
                WizardArg::Number(10.0),
                WizardArg::Number(-1.5),
                WizardArg::Number(-4.0),
                WizardArg::Text("A".into()),
                WizardArg::Number(3.0),
            ];
            assert_eq!(fake.args, [expected.to_vec()]);
        }

        #[test]
        fn a_wizard_sees_the_state_at_its_call_in_program_terms() {
            let mut fake = Fake { seen: Vec::new(), args: Vec::new(), answer: "G01 X1 F100" };
            let program = "G21\nG52 X25.4\nG00 X10 Y5 Z2\nM03 S1200\nG91\nProbe 1\nM30";
            let got = run(program, &mut fake);
            let state = &fake.seen[0];
            assert_eq!(state.units, Units::Mm);
            let expected = [10.0, 5.0, 2.0];
            assert!(state.position.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-9), "{:?}", state.position);
            assert_eq!(state.distance, Distance::Incremental);
            assert_eq!(state.spindle, Spindle::Clockwise(Some(1200.0)));
            assert!((state.tool.as_ref().unwrap().diameter - 6.35).abs() < 1e-9);
            assert_eq!(state.line, 6);
            // The wizard's move is incremental, in mm, from X35.4 mm: to 36.4 mm = 1.4331 in.
            assert_eq!(got[2], "N6 G01 X1.4331 F3.9370");
        }

        #[test]
        fn m99_or_o_in_a_wizards_output_is_an_error_at_the_call() {
            let chain = r#"["in wizard `Rewind` called at line 1"]"#;
            let mut fake = Fake { seen: Vec::new(), args: Vec::new(), answer: "G01 X1 F10\nM99\nG01 X2" };
            let got = run("Rewind\nM30", &mut fake);
            let error = format!("1:1: error: M99 in the output of wizard `Rewind` {chain}");
            assert_eq!(got, ["N1 G01 X1.0000 F10.0000", &error, "N2 M30"]);
            let mut fake = Fake { seen: Vec::new(), args: Vec::new(), answer: "O100\nX3\nM99" };
            let got = run("Rewind\nM30", &mut fake);
            let error = format!(
                "1:1: error: O100 in the output of wizard `Rewind`: a wizard cannot define a subprogram {chain}"
            );
            assert_eq!(got, [&error, "N2 M30"]);
        }

        #[test]
        fn runaway_wizard_recursion_is_an_error() {
            let mut fake = Fake { seen: Vec::new(), args: Vec::new(), answer: "Again" };
            let got = run("Again\nM30", &mut fake);
            assert_eq!(fake.seen.len(), 16);
            assert!(got[0].starts_with("1:1: error: wizard calls nest deeper than 16"), "{got:?}");
            assert_eq!(got[1], "N2 M30");
        }
    }
}
