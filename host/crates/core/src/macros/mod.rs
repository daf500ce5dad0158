//! The interpreter stage of the lenient dialect: parameters, expressions
//! and LinuxCNC's O-word control flow, between the lexer and the parser.
//!
//! The lexer reads `X[#1 + 2]` as an expression word and `#1 = 5` as an
//! assignment; this stage evaluates them against the parameters set so far
//! and hands the parser plain words, so no later stage knows a program had
//! variables. As in LinuxCNC, every read on a line happens before the line's
//! assignments take effect: `#1 = 2 X#1` moves to the old `#1`. An
//! evaluation error drops the line it is on (its assignments too), so one
//! mistake gives one error. O-word lines (`control.rs`) shape the lines
//! into blocks, read whole before they run; subroutine calls, loops and
//! branches run them from memory, a line at a time.

pub mod control;
pub mod expr;

use std::collections::{HashMap, VecDeque};
use std::rc::Rc;
use std::sync::Arc;

use crate::config::RunLimits;
use crate::diag::{Diagnostic, Origin, Span};
use crate::lex::{Lexed, Lexer, Macro, Piece, SharedHistory, Token, TokenKind, MAX_NUMBER};
use crate::statement::Dialect;
use control::{Control, Keyword};
use expr::{Expr, Param, Parameters};

/// Numbered parameters from here on are LinuxCNC's system parameters
/// (work offsets, G28/G30 points, the current position): ger does not
/// compute them, so a program that reads or sets one is refused there.
const FIRST_SYSTEM_PARAMETER: u32 = 5000;

/// `#1` to `#30` belong to a call level, as in LinuxCNC.
const LOCALS: usize = 30;

/// Where `return [value]` leaves the value.
const RETURNED: &str = "_value";

/// How deep subroutine calls may nest: a recursion this deep is taken as
/// one that never ends.
const MAX_CALL_DEPTH: usize = 100;

/// The parameters of one call level: `#1`-`#30` and the names without `_`.
#[derive(Clone, Default)]
struct Locals {
    numbered: [f64; LOCALS],
    /// Which of them hold a value (Fanuc: the others are vacant).
    given: [bool; LOCALS],
    named: HashMap<String, f64>,
}

/// The parameters a program has set.
pub struct Store {
    numbered: HashMap<u32, f64>,
    named: HashMap<String, f64>,
    /// The call levels, the main program's first.
    levels: Vec<Locals>,
    /// Where the tool is now, in program coordinates, as passes 01-04 have
    /// it: #5420-#5422 and #<_x> #<_y> #<_z> read it.
    position: Option<Position>,
}

/// Where the program has got to, as the passes have it.
pub type Position = Box<dyn Fn() -> crate::state::Place>;

/// LinuxCNC's coordinate system in force: 1 for G54 to 9 for G59.3.
const COORDINATE_SYSTEM: u32 = 5220;

/// LinuxCNC's current position, X, Y and Z: #5420 to #5422.
const POSITION: u32 = 5420;

/// Fanuc's modal information (#4001-#4130), read while the program has not
/// set the parameter itself (LinuxCNC has no such parameters: there they
/// are the program's own).
const FANUC_MODAL: std::ops::RangeInclusive<u32> = 4001..=4130;

/// LinuxCNC's (and Fanuc's) first coordinate system parameter, G54's X:
/// each system has 20 from there (X Y Z A B C U V W, then R at the tenth).
const WORK_OFFSETS: u32 = 5221;

/// The parameters read from the state the passes keep.
fn reads_place(number: u32) -> bool {
    matches!(number, 4001..=4130 | 5001..=5003 | 5021..=5023 | 5041..=5043 | 5161..=5169 | 5181..=5189 | 5210..=5390 | 5420..=5422)
}

/// The value of a parameter that reads where the program has got to, if
/// `number` is one: LinuxCNC's #5220 and #5420-#5422, the coordinate
/// systems (#5221-#5390: each one's X Y Z and R, A to W reading 0 on a
/// three-axis machine), the G52/G92 offset (#5210 in force, #5211-#5213)
/// and G28's and G30's points (#5161-#5163, #5181-#5183); Fanuc's block end
/// (#5001-#5003) and current positions (#5021-#5023 machine, #5041-#5043
/// work coordinates) and the modal information ger keeps (#4002 plane,
/// #4003 distance mode, #4006 units, #4014 work offset, #4109 F, #4119 S,
/// #4120 T). Another of Fanuc's #4001-#4130 is an error: it is not kept.
fn place_parameter(place: &crate::state::Place, number: u32, at: Span) -> Result<Option<f64>, Diagnostic> {
    use crate::statement::{Distance, Plane, Units};
    let axis = |first: u32| place.position[(number - first) as usize];
    let value = match number {
        POSITION..=5422 => axis(POSITION),
        5001..=5003 => axis(5001),
        5041..=5043 => axis(5041),
        5021..=5023 => place.machine[(number - 5021) as usize],
        COORDINATE_SYSTEM => f64::from(place.system),
        5161..=5163 => place.references[0][(number - 5161) as usize],
        5181..=5183 => place.references[1][(number - 5181) as usize],
        5210 => f64::from(u8::from(place.g92_in_force)),
        5211..=5213 => place.g92[(number - 5211) as usize],
        // The rotary and secondary axes ger does not have.
        5164..=5169 | 5184..=5189 | 5214..=5219 => 0.0,
        WORK_OFFSETS..=5390 => {
            let (system, word) = ((number - WORK_OFFSETS) / 20, (number - WORK_OFFSETS) % 20);
            match word {
                0..=2 => place.work_offsets[system as usize][word as usize],
                3..=8 => 0.0,
                9 => place.rotations[system as usize],
                _ => return Ok(None),
            }
        }
        4002 => match place.plane {
            Plane::XY => 17.0,
            Plane::ZX => 18.0,
            Plane::YZ => 19.0,
        },
        4003 => {
            if place.distance == Distance::Absolute {
                90.0
            } else {
                91.0
            }
        }
        4006 => {
            if place.units == Units::Inch {
                20.0
            } else {
                21.0
            }
        }
        4014 => match place.system {
            n @ 1..=6 => 53.0 + f64::from(n),
            n @ 7..=9 => 59.0 + f64::from(n - 6) / 10.0,
            _ => 54.1,
        },
        4109 => place.feed.unwrap_or(0.0),
        4119 => place.speed.unwrap_or(0.0),
        4120 => f64::from(place.tool),
        n if FANUC_MODAL.contains(&n) => {
            let message = format!("#{n} is Fanuc's modal information, which ger does not keep for it");
            let help = "ger reads #4002 (plane), #4003 (G90/G91), #4006 (G20/G21), #4014 (work offset), #4109 (F), \
                        #4119 (S) and #4120 (T); set the parameter before reading it otherwise";
            return Err(Diagnostic::error(at, message).with_help(help));
        }
        _ => return Ok(None),
    };
    Ok(Some(value))
}

/// LinuxCNC's predefined named parameters that read where the program has
/// got to: the position (`_x` to `_w`, the axes ger's machine lacks reading
/// 0), F and S, the spindle, the units, the distance mode, the plane
/// (`_plane` 170 for G17), the coordinate system (`_coord_system` 540 for
/// G54, 591 for G59.1).
const PLACE_NAMES: [&str; 19] = [
    "_x",
    "_y",
    "_z",
    "_a",
    "_b",
    "_c",
    "_u",
    "_v",
    "_w",
    "_feed",
    "_rpm",
    "_spindle_on",
    "_spindle_cw",
    "_metric",
    "_imperial",
    "_absolute",
    "_incremental",
    "_plane",
    "_coord_system",
];

/// The value of one of [`PLACE_NAMES`], `None` for another name.
fn place_named(place: &crate::state::Place, name: &str) -> Option<f64> {
    use crate::state::Spindle;
    use crate::statement::{Distance, Plane, Units};
    let flag = |on: bool| f64::from(u8::from(on));
    let value = match name {
        "_x" => place.position[0],
        "_y" => place.position[1],
        "_z" => place.position[2],
        "_a" | "_b" | "_c" | "_u" | "_v" | "_w" => 0.0,
        "_feed" => place.feed.unwrap_or(0.0),
        "_rpm" => place.speed.unwrap_or(0.0),
        "_spindle_on" => flag(place.spindle != Spindle::Off),
        "_spindle_cw" => flag(matches!(place.spindle, Spindle::Clockwise(_))),
        "_metric" => flag(place.units == Units::Mm),
        "_imperial" => flag(place.units == Units::Inch),
        "_absolute" => flag(place.distance == Distance::Absolute),
        "_incremental" => flag(place.distance == Distance::Incremental),
        "_plane" => match place.plane {
            Plane::XY => 170.0,
            Plane::ZX => 180.0,
            Plane::YZ => 190.0,
        },
        "_coord_system" => match place.system {
            n @ 1..=6 => 530.0 + 10.0 * f64::from(n),
            n => 590.0 + f64::from(n.saturating_sub(6)),
        },
        _ => return None,
    };
    Some(value)
}

impl Default for Store {
    fn default() -> Store {
        // A subroutine's value reads 0 until one returns, as in LinuxCNC.
        let named = HashMap::from([(RETURNED.to_string(), 0.0)]);
        Store { numbered: HashMap::new(), named, levels: vec![Locals::default()], position: None }
    }
}

impl Store {
    fn level(&mut self) -> &mut Locals {
        self.levels.last_mut().expect("the main program's level is never left")
    }

    fn set(&mut self, target: Target, value: f64) {
        match target {
            Target::Vacate(target) => self.vacate(*target),
            Target::Numbered(number) if number as usize <= LOCALS => {
                let level = self.level();
                level.numbered[number as usize - 1] = value;
                level.given[number as usize - 1] = true;
            }
            Target::Numbered(number) => {
                self.numbered.insert(number, value);
            }
            Target::Named(name) if name.starts_with('_') => {
                self.named.insert(name, value);
            }
            Target::Named(name) => {
                self.level().named.insert(name, value);
            }
        }
    }
}

impl Store {
    /// Fanuc's `#n = #0`: the parameter holds no value again (it reads 0).
    fn vacate(&mut self, target: Target) {
        match target {
            Target::Numbered(number) if number as usize <= LOCALS => {
                let level = self.level();
                level.numbered[number as usize - 1] = 0.0;
                level.given[number as usize - 1] = false;
            }
            Target::Numbered(number) => {
                self.numbered.remove(&number);
            }
            Target::Named(name) if name.starts_with('_') => {
                self.named.remove(&name);
            }
            Target::Named(name) => {
                self.level().named.remove(&name);
            }
            Target::Vacate(target) => self.vacate(*target),
        }
    }
}

impl Parameters for Store {
    fn is_set(&self, number: u32) -> bool {
        match number {
            expr::VACANT => false,
            _ if number as usize <= LOCALS => self.levels.last().is_some_and(|level| level.given[number as usize - 1]),
            _ if number >= FIRST_SYSTEM_PARAMETER => true,
            _ => self.numbered.contains_key(&number),
        }
    }

    fn numbered(&self, number: u32, at: Span) -> Result<f64, Diagnostic> {
        // Fanuc's #0, always vacant, reads 0 in arithmetic.
        if number == expr::VACANT {
            return Ok(0.0);
        }
        // Locals first: most reads are theirs, in loops.
        if number as usize <= LOCALS {
            return Ok(self.levels.last().map_or(0.0, |level| level.numbered[number as usize - 1]));
        }
        if let (Some(position), true) = (&self.position, reads_place(number)) {
            if !self.numbered.contains_key(&number) {
                if let Some(value) = place_parameter(&position(), number, at)? {
                    return Ok(value);
                }
            }
        }
        system_parameter(number, at)?;
        // An unset numbered parameter reads as 0, as in LinuxCNC.
        Ok(self.numbered.get(&number).copied().unwrap_or(0.0))
    }

    fn named(&self, name: &str) -> Option<f64> {
        if let Some(value) = self.position.as_ref().and_then(|position| place_named(&position(), name)) {
            return Some(value);
        }
        if name.starts_with('_') {
            self.named.get(name).copied()
        } else {
            self.levels.last()?.named.get(name).copied()
        }
    }
}

fn system_parameter(number: u32, at: Span) -> Result<(), Diagnostic> {
    if number < FIRST_SYSTEM_PARAMETER {
        return Ok(());
    }
    Err(Diagnostic::error(at, format!("#{number} is one of LinuxCNC's system parameters, which ger does not compute"))
        .with_help(format!("ger's parameters are #1 to #{}, and named ones", FIRST_SYSTEM_PARAMETER - 1)))
}

/// Where an assignment goes, worked out when the line is read.
enum Target {
    Numbered(u32),
    Named(String),
    /// Fanuc's `#1 = #0`: the parameter is made vacant.
    Vacate(Box<Target>),
}

/// A line as the lexer gave it, kept to be run again when it is in a loop
/// or a subroutine: its tokens, the lexer's diagnostics, and its end.
#[derive(Clone, Default)]
struct Line {
    items: Vec<Piece>,
    end: Option<Token>,
}

impl Line {
    /// The program line it is.
    fn number(&self) -> u32 {
        let span = |item: &Piece| match item {
            Piece::Lexed(Lexed::Token(token)) => Some(token.span),
            Piece::Lexed(Lexed::Diagnostic(diagnostic)) => Some(diagnostic.span),
            Piece::Lexed(Lexed::Origin(_)) => None,
            Piece::Macro(_, span) => Some(*span),
        };
        self.end.as_ref().map(|end| end.span).or_else(|| self.items.iter().find_map(span)).map_or(0, |span| span.line)
    }

    /// The whole `N` number that starts the line, if it has one: where a GOTO may jump.
    fn label(&self) -> Option<u64> {
        self.items.iter().find_map(|item| match item {
            Piece::Macro(Macro::Label(number), _) if number.fract() == 0.0 => Some(*number as u64),
            _ => None,
        })
    }

    /// The words of the line, after its values are worked out.
    fn words(&self) -> impl Iterator<Item = (char, f64, Span)> + '_ {
        self.items.iter().filter_map(|item| match item {
            Piece::Lexed(Lexed::Token(Token { kind: TokenKind::Word { letter, value }, span })) => {
                Some((*letter, *value, *span))
            }
            _ => None,
        })
    }

    /// Whether the line has words for the parser (not only parameters set).
    fn has_words(&self) -> bool {
        self.items.iter().any(|item| match item {
            Piece::Lexed(Lexed::Token(token)) => !matches!(token.kind, TokenKind::Comment(_) | TokenKind::End),
            Piece::Macro(Macro::Expression { .. }, _) => true,
            _ => false,
        })
    }

    /// The line without the M99 (or M30, M2, Fadal's M17) that ends a
    /// program read as a block, and M99's P, if anything else is on it: a Fanuc runs
    /// `G90 M99` as G90, then the return.
    fn before_its_end(&self) -> Option<Line> {
        const ENDS: [f64; 4] = [99.0, 30.0, 2.0, 17.0];
        let ends = self.words().any(|(letter, value, _)| letter == 'M' && ENDS.contains(&value));
        let kept = |item: &&Piece| match item {
            Piece::Lexed(Lexed::Token(Token { kind: TokenKind::Word { letter, value }, .. })) => {
                let end = *letter == 'M' && ENDS.contains(value);
                !(end || *letter == 'P' && ends)
            }
            _ => true,
        };
        let items: Vec<Piece> = self.items.iter().filter(kept).cloned().collect();
        let something = items.iter().any(|item| match item {
            Piece::Lexed(Lexed::Token(Token { kind: TokenKind::Word { letter, .. }, .. })) => *letter != 'N',
            Piece::Macro(..) => true,
            _ => false,
        });
        something.then(|| Line { items, end: self.end.clone() })
    }

    /// Whether the line has code: anything but comments and diagnostics.
    fn is_code(&self) -> bool {
        self.items.iter().any(|item| match item {
            Piece::Lexed(Lexed::Token(token)) => !matches!(token.kind, TokenKind::Comment(_) | TokenKind::End),
            Piece::Lexed(Lexed::Diagnostic(_) | Lexed::Origin(_)) => false,
            Piece::Macro(..) => true,
        })
    }

    /// The line's O-word control, if it is a control line.
    fn control(&self) -> Option<&Control> {
        self.items.iter().find_map(|item| match item {
            Piece::Macro(Macro::Control(control), _) => Some(control),
            _ => None,
        })
    }
}

type Body = Rc<[Node]>;

/// A program's structure, as far as a block that is running needs it.
enum Node {
    Line(Line),
    /// `call`, `return`, `break`, `continue`.
    Simple(Control),
    /// `if`, then any `elseif`s and an `else`, each with its body.
    If(Vec<(Control, Body)>),
    Loop(Rc<Loop>),
    Sub(Rc<Sub>),
}

struct Loop {
    head: Control,
    /// A do-while loop's condition, from its closing `while`.
    until: Option<Control>,
    body: Body,
}

struct Sub {
    head: Control,
    body: Body,
}

/// A block being read: its head, the nodes so far, and for an `if` the
/// branches before the current one.
struct Open {
    head: Control,
    nodes: Vec<Node>,
    branches: Vec<(Control, Body)>,
}

/// A body being run.
struct Frame {
    body: Body,
    next: usize,
    kind: FrameKind,
}

enum FrameKind {
    Branch,
    Loop {
        block: Rc<Loop>,
        iterations: u64,
        remaining: u64,
    },
    /// A call: with locals of its own (O-word `call`, G65: those it starts
    /// with, again for each repeat) or the caller's (M98); run `remaining` times more.
    /// A program from a file of its own (`file`) says its lines are the call's.
    Call {
        origin: Arc<Origin>,
        locals: Option<Box<Locals>>,
        remaining: u64,
        file: bool,
    },
}

/// Runs over the lexer's tokens a line at a time: turns expression words
/// into words, carries out assignments at each line's end, and runs the
/// O-word control lines. A block (`sub`, `if`, a loop) is read whole before
/// it runs and kept while it does; everything else streams. A line with an
/// error gives the parser nothing of it but its diagnostics.
pub struct Interpreter<'a, L> {
    tokens: L,
    store: Store,
    /// The line being read.
    line: Line,
    /// The blocks being read, outermost first.
    open: Vec<Open>,
    /// The bodies being run, outermost first.
    frames: Vec<Frame>,
    subs: HashMap<String, Rc<Sub>>,
    /// Lines read ahead to find a subroutine, to be run in their turn.
    ahead: VecDeque<Line>,
    /// Lines taken from the lexer to find the main program, not read yet.
    unread: VecDeque<Line>,
    limits: RunLimits,
    /// How many blocks loops and calls have run, against `limits.blocks`.
    blocks_run: u64,
    /// An error came while a loop ran: the loops stop before the next step.
    stop_loops: bool,
    out: VecDeque<Lexed>,
    /// The call the parser was last told its statements run in.
    told_origin: Option<Arc<Origin>>,
    done: bool,
    /// The text of the lines read, for a backward GOTO to read again.
    history: Option<SharedHistory>,
    /// Lines read again after a GOTO, before the program reads on.
    replay: Option<Box<dyn Iterator<Item = Piece>>>,
    /// Where each `N` label of the program's lines is: its first line and
    /// how many blocks are open there (a GOTO may not jump into one).
    labels: HashMap<u64, Label>,
    /// Labels met again, on later lines.
    more_labels: Vec<(u64, Label)>,
    /// The blocks open at the line the program has read to, for `labels`.
    structure: Vec<Control>,
    /// The first GOTO that jumped back: from there every block counts
    /// against `limits.blocks`, as a loop's do.
    jumped: Option<Span>,
    /// The backward GOTOs whose lines are running, with how often each jumped.
    goto_loops: Vec<GotoLoop>,
    /// Fanuc's programs after the main one (`O1000` to `M99`) are read as
    /// blocks, and `M98`/`G65` run them here (lenient dialect).
    fanuc_programs: bool,
    /// Finds a program kept in a file of its own: the file's name and text.
    files: Option<FindProgram<'a>>,
    /// The programs found in files, and the files' names.
    from_files: HashMap<String, String>,
    /// The program's first line of code: an `O` number there is its name.
    first_code_line: Option<u32>,
    /// The M99 that ends the file's first program, where that program is
    /// the main one and returns.
    main_return: Option<u32>,
    /// The line and call level of the last error since a GOTO jumped back:
    /// a GOTO does not jump back over it again.
    last_error: Option<(u32, usize)>,
    /// The lines of the local subprograms `M97` runs, first to last.
    local_lines: Vec<std::ops::RangeInclusive<u32>>,
    /// The main program has run its M30 or M2: what follows runs only where called.
    ended: bool,
    /// Fadal subroutines (`L0100` ... `M17`) have been defined.
    fadal_subroutines: bool,
    /// `run_line`'s buffers, kept from line to line.
    line_tokens: Vec<Token>,
    line_assignments: Vec<(Target, f64, Span)>,
    /// A line of the main program with words other than its O number has run.
    ran_code: bool,
}

#[derive(Clone, Copy)]
struct Label {
    line: u32,
    open_blocks: u32,
}

/// A backward GOTO at line `site`, to `target`, with its lines running:
/// a loop whose iterations are its jumps. It is over once a line outside
/// them runs (at the same call level).
struct GotoLoop {
    site: u32,
    target: u32,
    level: usize,
    jumps: u64,
}

impl<'a, L: Iterator<Item = Piece>> Interpreter<'a, L> {
    pub fn new(tokens: L, limits: RunLimits) -> Interpreter<'a, L> {
        Interpreter {
            tokens,
            store: Store::default(),
            line: Line::default(),
            open: Vec::new(),
            frames: Vec::new(),
            subs: HashMap::new(),
            ahead: VecDeque::new(),
            unread: VecDeque::new(),
            limits,
            blocks_run: 0,
            stop_loops: false,
            out: VecDeque::new(),
            told_origin: None,
            done: false,
            history: None,
            replay: None,
            labels: HashMap::new(),
            more_labels: Vec::new(),
            structure: Vec::new(),
            jumped: None,
            goto_loops: Vec::new(),
            last_error: None,
            fanuc_programs: false,
            files: None,
            from_files: HashMap::new(),
            first_code_line: None,
            main_return: None,
            local_lines: Vec::new(),
            ended: false,
            fadal_subroutines: false,
            line_tokens: Vec::new(),
            line_assignments: Vec::new(),
            ran_code: false,
        }
    }

    /// `history` holds the text of the lines the lexer has read: a backward
    /// GOTO reads them again. Without it such a jump is an error.
    pub fn with_history(mut self, history: SharedHistory) -> Interpreter<'a, L> {
        self.history = Some(history);
        self
    }

    /// Reads Fanuc's programs after the main one (`O1000` ... `M99`) and runs
    /// them at `M98 P1000` and `G65 P1000` (lenient dialect): a program's
    /// parameters are those of the moment it is called.
    pub fn running_fanuc_programs(mut self) -> Interpreter<'a, L> {
        self.fanuc_programs = true;
        self
    }

    /// `position` tells where the tool is now (in program coordinates and
    /// units): #5420-#5422 and #<_x> #<_y> #<_z> read it. The passes that
    /// keep it have seen every statement before the line that reads it,
    /// since the pipeline pulls a statement at a time.
    pub fn reading_position(mut self, position: Option<Position>) -> Interpreter<'a, L> {
        self.store.position = position;
        self
    }

    /// `files` finds a program the program itself does not define, in a
    /// file of its own, as pass 00 finds M98's.
    pub fn finding_programs(mut self, files: Option<FindProgram<'a>>) -> Interpreter<'a, L> {
        self.files = files;
        self
    }

    /// Where what a program from another file makes is said to come from:
    /// the line that called it, as pass 00 says of such a program's lines.
    fn shown_at(&self) -> Option<Span> {
        self.frames.iter().find_map(|frame| match &frame.kind {
            FrameKind::Call { origin, file: true, .. } => Some(origin.call),
            _ => None,
        })
    }

    fn emit(&mut self, mut token: Token) {
        if let Some(span) = self.shown_at() {
            token.span = span;
        }
        // The parser tags the statements with the call they run in (for the
        // run time by call, and the diagnostics' call chains): told only
        // when it changes.
        let origin = self.origin();
        let same = match (&origin, &self.told_origin) {
            (Some(now), Some(told)) => Arc::ptr_eq(now, told),
            (now, told) => now.is_none() && told.is_none(),
        };
        if !same {
            self.told_origin.clone_from(&origin);
            self.out.push_back(Lexed::Origin(origin));
        }
        self.out.push_back(Lexed::Token(token));
    }

    /// A program in a file of its own, to its M99: a block as one after
    /// M30 is, and the file's name. Its first line of code must be its O number.
    fn program_from_file(&mut self, number: u64, label: &str) -> Option<(Rc<Sub>, String)> {
        let (name, text) = (self.files.as_mut()?)(Wanted::Program(number as u32))?;
        let mut lines = Lexer::in_dialect(std::io::Cursor::new(text), Dialect::Lenient).pieces();
        let mut partial = Line::default();
        let head = loop {
            let line = whole_line(&mut lines, &mut partial)?;
            if !line.is_code() {
                continue;
            }
            let first = line.words().next();
            match first {
                Some(('O', value, span)) if value == number as f64 => {
                    break Control {
                        label: label.to_string(),
                        keyword: Keyword::Program,
                        args: Vec::new(),
                        span,
                        fanuc: true,
                        computed: None,
                    };
                }
                _ => return None,
            }
        };
        let sub = self.program_body(head, std::iter::from_fn(|| whole_line(&mut lines, &mut partial)), &name)?;
        Some((sub, name))
    }

    /// The lines of a program that is not the running one, read into a
    /// block of their own as the program's are, up to its M99 (or M30, M2).
    fn program_body(&mut self, head: Control, lines: impl Iterator<Item = Line>, name: &str) -> Option<Rc<Sub>> {
        let around = std::mem::take(&mut self.open);
        self.open.push(Open { head: head.clone(), nodes: Vec::new(), branches: Vec::new() });
        for line in lines {
            if ends_a_program(&line) && self.open.len() == 1 {
                if let Some(before) = line.before_its_end() {
                    self.add(Node::Line(before));
                }
                break;
            }
            self.read(line);
        }
        let inner = std::mem::replace(&mut self.open, around);
        let unclosed = inner.iter().skip(1).map(|open| open.head.clone()).collect::<Vec<_>>();
        for open in unclosed {
            let message = format!("{} is never closed (in {name})", open.describe());
            self.error(Diagnostic::error(open.span, message));
        }
        let body: Body = inner.into_iter().next()?.nodes.into();
        Some(Rc::new(Sub { head, body }))
    }

    /// Haas's `M97 Pn`: the lines of this program from the one labelled
    /// `Nn` (forward from the call first, as a GOTO looks) to the next M99,
    /// a local subprogram, usually kept after M30. The lines read on to
    /// find it wait for their turn, as for a subroutine read ahead for.
    fn local_program(&mut self, number: u64, at: Span) -> Result<String, Diagnostic> {
        let label = format!("N{number}");
        let not_found = || {
            Diagnostic::error(at, format!("M97 P{number}: the program has no line N{number}"))
                .with_help("M97 Pn runs the lines from Nn to the next M99 (Haas's local subprogram)")
        };
        let Some(history) = self.history.clone() else {
            return Err(Diagnostic::error(at, "M97: the program's lines are not kept to run again"));
        };
        let forward =
            |interpreter: &Self| interpreter.label_lines(number).into_iter().find(|found| found.line > at.line);
        while forward(self).is_none() {
            let Some(line) = self.next_line() else { break };
            self.ahead.push_back(line);
        }
        let start = forward(self).or_else(|| self.label_lines(number).first().copied()).ok_or_else(not_found)?.line;
        // Its last line is the first M99 from there: read on to it too.
        let read = history.borrow().from_line(start);
        let mut pieces = Lexer::in_dialect(std::io::Cursor::new(read), Dialect::Lenient).starting_at(start).pieces();
        let mut partial = Line::default();
        let mut end = std::iter::from_fn(|| whole_line(&mut pieces, &mut partial)).find(ends_a_program);
        while end.is_none() {
            let Some(line) = self.next_line() else { break };
            end = ends_a_program(&line).then(|| line.clone());
            self.ahead.push_back(line);
        }
        let last = end.map_or(u32::MAX, |line| line.number());
        self.local_lines.push(start..=last);
        let text = history.borrow().from_line(start);
        let mut pieces = Lexer::in_dialect(std::io::Cursor::new(text), Dialect::Lenient).starting_at(start).pieces();
        let mut partial = Line::default();
        let head = Control {
            label: label.clone(),
            keyword: Keyword::Program,
            args: Vec::new(),
            span: at,
            fanuc: true,
            computed: None,
        };
        let lines = std::iter::from_fn(|| whole_line(&mut pieces, &mut partial));
        let sub = self.program_body(head, lines, &label).ok_or_else(not_found)?;
        self.subs.insert(label.clone(), sub);
        Ok(label)
    }

    /// The block a line opens or closes as a Fanuc program: `O1000` (but
    /// the program's own name, on its first line of code) or `M99`; or as
    /// a Fadal subroutine: `L0100` alone, to `M17` (inside one, `inside`).
    fn fanuc_block(&self, line: &Line, inside: Option<&Control>) -> Option<Control> {
        if !self.fanuc_programs {
            return None;
        }
        if let Some((number, 0, span)) = fadal_subroutine(line) {
            return Some(Control {
                label: format!("L{number}"),
                keyword: Keyword::Program,
                args: Vec::new(),
                span,
                fanuc: true,
                computed: None,
            });
        }
        let in_fadal = inside.is_some_and(|block| block.keyword == Keyword::Program && block.label.starts_with('L'));
        if let Some((_, _, span)) = line.words().find(|&(l, v, _)| in_fadal && l == 'M' && v == 17.0) {
            return Some(Control {
                label: String::new(),
                keyword: Keyword::EndProgram,
                args: Vec::new(),
                span,
                fanuc: true,
                computed: None,
            });
        }
        let mut words = line.words();
        let (letter, value, span) = words.next()?;
        let keyword = match letter {
            'O' if self.first_code_line != Some(line.number()) && value >= 0.0 && value.fract() == 0.0 => {
                Keyword::Program
            }
            _ if std::iter::once((letter, value, span)).chain(words).any(|(l, v, _)| l == 'M' && v == 99.0) => {
                Keyword::EndProgram
            }
            _ => return None,
        };
        let label = if keyword == Keyword::Program { format!("O{}", value as u64) } else { String::new() };
        Some(Control { label, keyword, args: Vec::new(), span, fanuc: true, computed: None })
    }

    /// A file that opens with a program ending in M99 (`O1000` ... `M99`,
    /// then perhaps `O0001` ... `M30`, as a listing of a job's programs
    /// is): LinuxCNC runs its first program as the main one, and the M99
    /// ends the run there; what follows is only looked in for the programs
    /// it calls (where a Fanuc would run the program its operator
    /// selects). Read ahead (at most `MAIN_PROGRAM_LOOKAHEAD` lines) for
    /// that program's end: an M99 before any M30 or M2.
    fn find_main_return(&mut self) {
        for _ in 0..MAIN_PROGRAM_LOOKAHEAD {
            let Some(line) = whole_line(&mut self.tokens, &mut self.line) else { break };
            let ends = line.words().find_map(|(letter, value, _)| match (letter, value) {
                ('M', 99.0) => Some(false),
                ('M', 30.0 | 2.0) => Some(true),
                _ => None,
            });
            let number = line.number();
            self.unread.push_back(line);
            match ends {
                Some(true) => return,
                Some(false) => {
                    self.main_return = Some(number);
                    return;
                }
                None => {}
            }
        }
    }

    /// The call the running line is in, for its diagnostics.
    fn origin(&self) -> Option<Arc<Origin>> {
        self.frames.iter().rev().find_map(|frame| match &frame.kind {
            FrameKind::Call { origin, .. } => Some(origin.clone()),
            _ => None,
        })
    }

    fn error(&mut self, diagnostic: Diagnostic) {
        let diagnostic = diagnostic.with_origin(self.origin());
        self.diagnostic(diagnostic);
    }

    /// Every diagnostic of the running program goes out here. An error in a
    /// loop stops it, as LinuxCNC stops the program at its first error: the
    /// same error is not said once an iteration, a million times.
    fn diagnostic(&mut self, mut diagnostic: Diagnostic) {
        if let Some(span) = self.shown_at() {
            diagnostic.span = span;
        }
        if diagnostic.is_error() && self.frames.iter().any(|frame| matches!(frame.kind, FrameKind::Loop { .. })) {
            self.stop_loops = true;
        }
        if diagnostic.is_error() {
            self.last_error = Some((diagnostic.span.line, self.store.levels.len()));
        }
        self.out.push_back(Lexed::Diagnostic(diagnostic));
    }

    /// Leaves the outermost loop running and everything it runs, saying where it stopped.
    fn stop_at_error(&mut self) {
        self.stop_loops = false;
        let Some(outermost) = self.frames.iter().position(|frame| matches!(frame.kind, FrameKind::Loop { .. })) else {
            return;
        };
        let FrameKind::Loop { block, iterations, .. } = &self.frames[outermost].kind else {
            unreachable!("found above")
        };
        let (head, iteration) = (block.head.clone(), iterations + 1);
        for frame in self.frames.drain(outermost..) {
            if matches!(frame.kind, FrameKind::Call { locals: Some(_), .. }) {
                self.store.levels.pop();
            }
        }
        let message = format!("{} stopped at the error above, in its iteration {iteration}", head.describe());
        let help = "an error ends the loop it is in, and the loops around it; the program goes on after them";
        self.error(Diagnostic::error(head.span, message).with_help(help));
    }

    fn evaluate(&self, expr: &Expr, span: Span) -> Result<f64, Diagnostic> {
        let value = expr.eval(&self.store)?;
        if value.abs() > MAX_NUMBER {
            let message = format!("this works out to {value:.0}: ger reads numbers up to 10^12");
            return Err(Diagnostic::error(span, message));
        }
        Ok(value)
    }

    fn assignment(&self, target: &Param, value: &Expr, span: Span) -> Result<(Target, f64), Diagnostic> {
        let target = match target {
            Param::Numbered(index) => {
                let number = expr::number(index, &self.store, span)?;
                if number == expr::VACANT {
                    return Err(Diagnostic::error(span, "#0 is Fanuc's vacant value: it is read, not set"));
                }
                if number >= FIRST_SYSTEM_PARAMETER && reads_place(number) {
                    let message = format!("#{number} reads the machine's state: it is read, not set");
                    let help = "set a coordinate system with G10 L2 (G10 L2 P1 X10 sets G54's X), the G92 offset \
                                with G92, G28's and G30's points with G28.1 and G30.1";
                    return Err(Diagnostic::error(span, message).with_help(help));
                }
                system_parameter(number, span)?;
                Target::Numbered(number)
            }
            Param::Named(name) if self.store.position.is_some() && PLACE_NAMES.contains(&name.as_str()) => {
                let message = format!("#<{name}> is one of LinuxCNC's predefined parameters: it is read, not set");
                return Err(Diagnostic::error(span, message));
            }
            Param::Named(name) => Target::Named(name.clone()),
        };
        if value.is_vacant() {
            return Ok((Target::Vacate(Box::new(target)), 0.0));
        }
        Ok((target, self.evaluate(value, span)?))
    }

    /// Runs a plain line: its words' values, then its assignments.
    fn run_line(&mut self, line: &Line) {
        if !self.goto_loops.is_empty() {
            let (number, level) = (line.number(), self.store.levels.len());
            self.goto_loops.retain(|jump| jump.level != level || (jump.target..=jump.site).contains(&number));
        }
        // The buffers of the line before: a loop runs lines by the million.
        let mut tokens = std::mem::take(&mut self.line_tokens);
        let mut assignments = std::mem::take(&mut self.line_assignments);
        tokens.clear();
        assignments.clear();
        let mut failed = None;
        let mut skipped = false;
        let mut jump = None;
        let in_macro = self.in_fanuc_macro();
        for item in &line.items {
            match item {
                Piece::Lexed(Lexed::Diagnostic(diagnostic)) => self.diagnostic(diagnostic.clone()),
                Piece::Lexed(Lexed::Origin(_)) => {}
                _ if failed.is_some() || skipped => {}
                Piece::Lexed(Lexed::Token(token)) => tokens.push(token.clone()),
                // Fanuc: a word whose value is vacant is not there (`G01 X#24` with no X given to
                // the G65 is `G01`), where parameters can be vacant: in a macro G65 called.
                Piece::Macro(Macro::Expression { value, .. }, _)
                    if value.is_vacant() || (in_macro && value.vacant(&self.store) == Ok(Some(true))) => {}
                Piece::Macro(Macro::Expression { letter, value }, span) => match self.evaluate(value, *span) {
                    Ok(value) => tokens.push(Token { kind: TokenKind::Word { letter: *letter, value }, span: *span }),
                    Err(diagnostic) => failed = Some(diagnostic),
                },
                Piece::Macro(Macro::Assign { target, value }, span) => match self.assignment(target, value, *span) {
                    Ok((target, value)) => assignments.push((target, value, *span)),
                    Err(diagnostic) => failed = Some(diagnostic),
                },
                Piece::Macro(Macro::Guard(condition), span) => match self.evaluate(condition, *span) {
                    // IF [c] THEN: the rest of the line is passed over.
                    Ok(0.0) => skipped = true,
                    Ok(_) => {}
                    Err(diagnostic) => failed = Some(diagnostic),
                },
                Piece::Macro(Macro::Argument(value), span) => match self.evaluate(value, *span) {
                    Ok(value) => tokens.push(Token { kind: TokenKind::Number(value), span: *span }),
                    Err(diagnostic) => failed = Some(diagnostic),
                },
                Piece::Macro(Macro::Goto(target), span) => {
                    match self.evaluate(target, *span).and_then(|n| label(n, *span)) {
                        Ok(label) => jump = Some((label, *span)),
                        Err(diagnostic) => failed = Some(diagnostic),
                    }
                }
                // A plain line has no control piece: `read` takes those.
                Piece::Macro(Macro::Control(_) | Macro::Label(_), _) => {}
            }
        }
        if let (None, Some(span)) = (&failed, alarm(&assignments)) {
            failed = Some(self.alarm(line, &assignments, span));
        }
        if failed.is_none() && self.in_fanuc_program() {
            failed = ends_program(&tokens);
        }
        if failed.is_none() && self.call_depth() == 0 {
            if self.fadal_subroutines && !self.ran_code && ends_program(&tokens).is_some() {
                // Fadal: the M30 after the subroutines that open the program
                // ends their section; the main program follows.
                tokens.retain(|token| !matches!(token.kind, TokenKind::Word { letter: 'M', value } if value == 30.0 || value == 2.0));
            }
            if ends_program(&tokens).is_some() {
                self.ended = true;
            }
            self.ran_code |=
                tokens.iter().any(|token| matches!(token.kind, TokenKind::Word { letter, .. } if letter != 'O'));
        }
        let jump = jump.filter(|_| failed.is_none());
        let mut call = None;
        if let Some(found) = fanuc_call(&tokens).filter(|_| failed.is_none() && self.fanuc_programs) {
            match self.prepare_call(found) {
                Ok(ready) => call = ready,
                Err(diagnostic) => failed = Some(diagnostic),
            }
        }
        match failed {
            Some(diagnostic) => self.error(diagnostic),
            None => {
                // A call's own words go no further: its body runs in their place.
                let kept = |token: &Token| match (&call, &token.kind) {
                    (Some(Ready { locals: Some(_), .. }), TokenKind::Word { .. }) => false,
                    (Some(_), TokenKind::Word { letter, value }) => {
                        !matches!((letter, value), ('M', 97.0 | 98.0) | ('P' | 'L', _))
                    }
                    _ => true,
                };
                for token in tokens.drain(..).filter(kept) {
                    self.emit(token);
                }
                if let Some(&(_, _, span)) =
                    assignments.iter().find(|(target, ..)| matches!(target, Target::Numbered(PAUSE)))
                {
                    // Fanuc's #3006 = n (MESSAGE): a stop with the message, which the line's comment carries.
                    self.emit(Token { kind: TokenKind::Word { letter: 'M', value: 0.0 }, span });
                }
                for (target, value, _) in assignments.drain(..) {
                    self.store.set(target, value);
                }
            }
        }
        (self.line_tokens, self.line_assignments) = (tokens, assignments);
        if let Some(end) = line.end.clone() {
            self.emit(end);
        }
        if let Some((label, span)) = jump {
            self.goto(label, span);
        }
        if let Some(ready) = call {
            self.push_call(ready);
        }
    }

    /// A subroutine or program defined: a Fanuc program's first definition is
    /// the one calls run, as in pass 00 (LinuxCNC runs the first and reads
    /// past the second); a LinuxCNC subroutine's last.
    fn define(&mut self, sub: Rc<Sub>) {
        self.fadal_subroutines |= sub.head.label.starts_with('L');
        if sub.head.keyword == Keyword::Program && self.subs.contains_key(&sub.head.label) {
            let message = format!("{} is defined again: calls run its first definition", sub.head.label);
            let help = "give each subprogram its own number, or remove the one that never runs";
            self.diagnostic(Diagnostic::warning(sub.head.span, message).with_help(help));
        } else {
            self.subs.insert(sub.head.label.clone(), sub);
        }
    }

    /// Whether program `number` (`label`) is known: in the program, read
    /// ahead for, or in a file of its own beside it.
    fn find_program(&mut self, number: u64, label: &str) -> bool {
        if !self.subs.contains_key(label) && !self.look_ahead_for(label) {
            if let Some((sub, name)) = self.program_from_file(number, label) {
                self.from_files.insert(label.to_string(), name);
                self.subs.insert(label.to_string(), sub);
            }
        }
        self.subs.contains_key(label)
    }

    /// The program a `M98` or `G65` line calls, found (read ahead for if it
    /// follows), with the locals a G65 gives it. `None` for an M98 whose
    /// program is not in the file: pass 00 looks for it beside the program.
    fn prepare_call(&mut self, call: FanucCall) -> Result<Option<Ready>, Diagnostic> {
        let code = match (call.macro_call, call.local, call.fadal) {
            (true, ..) => "G65",
            (_, true, _) => "M97",
            (.., true) => "L",
            _ => "M98",
        };
        let number = call.program.filter(|p| *p >= 0.0 && p.fract() == 0.0);
        let Some(number) = number else {
            if call.local {
                let message = "M97 needs P, the N number of the line its lines start at (a whole number)";
                let help = "M97 P100 runs the lines from N100 to the next M99, then goes on after the M97";
                return Err(Diagnostic::error(call.at, message).with_help(help));
            }
            if !call.macro_call {
                return Ok(None);
            }
            let message = "G65 needs P, the number of the program it calls (a whole number)";
            return Err(
                Diagnostic::error(call.at, message).with_help("G65 P1000 A1 B2 calls O1000 with #1 = 1, #2 = 2")
            );
        };
        let mut call = call;
        let mut label = format!("O{}", number as u64);
        if call.fadal {
            label = format!("L{number}");
            if !self.subs.contains_key(&label) {
                let (number, times) = (number as u32, call.repeat as u32);
                let message = format!("L{number:02}{times:02} calls Fadal subroutine {number}, which is not defined");
                let help = format!("define it before it is called: L{number:02}00, its lines, M17");
                return Err(Diagnostic::error(call.at, message).with_help(help));
            }
        } else if call.local {
            label = self.local_program(number as u64, call.at)?;
        } else if !self.find_program(number as u64, &label)
            && !call.macro_call
            && number >= 10_000.0
            && call.repeat == 1.0
        {
            // Fanuc packs the repeats into P when L is not given: P30010 runs O0010 three times.
            let (times, packed) = ((number / 10_000.0).floor(), number % 10_000.0);
            let packed_label = format!("O{}", packed as u64);
            if self.find_program(packed as u64, &packed_label) {
                (label, call.repeat) = (packed_label, times);
            }
        }
        if !self.subs.contains_key(&label) {
            if !call.macro_call {
                return Ok(None);
            }
            let message = format!("G65 calls {label}, which is not in the program");
            return Err(Diagnostic::error(call.at, message).with_help(format!("define it after M30: {label} ... M99")));
        }
        if call.repeat < 0.0 || call.repeat.fract() != 0.0 {
            let message = format!("{code} L{}: the number of times must be whole, 0 or more", call.repeat);
            return Err(Diagnostic::error(call.at, message));
        }
        let locals = if call.macro_call {
            let mut locals = Locals::default();
            let mut given = [false; LOCALS];
            for (letter, value, span) in call.args {
                let Some(number) = argument(letter) else {
                    let message = format!("{letter} is not one of G65's arguments");
                    let help =
                        "G65's arguments are A-F, H-K, M and Q-Z (into #1-#26); P names the program, L repeats it";
                    return Err(Diagnostic::error(span, message).with_help(help));
                };
                if std::mem::replace(&mut given[number - 1], true) {
                    let message = format!("{letter} is given twice: ger reads Fanuc's first form of arguments only");
                    let help = "each letter once: A -> #1, B -> #2, C -> #3, I -> #4, ...";
                    return Err(Diagnostic::error(span, message).with_help(help));
                }
                locals.numbered[number - 1] = value;
                locals.given[number - 1] = true;
            }
            Some(locals)
        } else {
            None
        };
        let sub = self.subs[&label].clone();
        let file = self.from_files.get(&label);
        let what = file.map_or(label.clone(), |name| format!("{label} (from {name})"));
        let origin = Arc::new(Origin { what, call: call.at, parent: self.origin() });
        Ok(Some(Ready { sub, origin, locals, repeat: call.repeat as u64, file: file.is_some() }))
    }

    fn push_call(&mut self, ready: Ready) {
        if ready.repeat == 0 {
            return;
        }
        if self.call_depth() >= MAX_CALL_DEPTH {
            let message = format!("calls nest more than {MAX_CALL_DEPTH} deep: a recursion that does not end?");
            return self.error(Diagnostic::error(ready.origin.call, message));
        }
        if let Some(locals) = &ready.locals {
            self.store.levels.push(locals.clone());
        }
        let kind = FrameKind::Call {
            origin: ready.origin,
            locals: ready.locals.map(Box::new),
            remaining: ready.repeat,
            file: ready.file,
        };
        self.frames.push(Frame { body: ready.sub.body.clone(), next: 0, kind });
    }

    /// Whether the line running is in a program M98 or G65 called.
    fn in_fanuc_program(&self) -> bool {
        self.frames
            .iter()
            .any(|frame| matches!(&frame.kind, FrameKind::Call { origin, .. } if origin.what.starts_with(['O', 'N'])))
    }

    /// Whether the locals in force are a macro's `G65` called (an M98
    /// shares its caller's): there a parameter with no value is vacant, not 0.
    fn in_fanuc_macro(&self) -> bool {
        let innermost = self.frames.iter().rev().find_map(|frame| match &frame.kind {
            FrameKind::Call { origin, locals: Some(_), .. } => Some(origin.what.starts_with('O')),
            _ => None,
        });
        innermost == Some(true)
    }

    fn call_depth(&self) -> usize {
        self.frames.iter().filter(|frame| matches!(frame.kind, FrameKind::Call { .. })).count()
    }

    /// Fanuc's `#3000 = n (MESSAGE)`: the program stops with an alarm.
    fn alarm(&self, line: &Line, assignments: &[(Target, f64, Span)], at: Span) -> Diagnostic {
        let number =
            assignments.iter().find(|(target, ..)| matches!(target, Target::Numbered(ALARM))).map_or(0.0, |a| a.1);
        let text = line.items.iter().find_map(|item| match item {
            Piece::Lexed(Lexed::Token(Token { kind: TokenKind::Comment(text), .. })) => Some(text.trim()),
            _ => None,
        });
        let message = format!("the program raises alarm {number}: {}", text.unwrap_or("(no message)"));
        Diagnostic::error(at, message)
            .with_help("a Fanuc control stops here (#3000): ger ends the translation's output of this line")
    }

    /// A line read from the program: run it, or keep it in the block being read.
    fn read(&mut self, line: Line) {
        if self.ended && self.open.is_empty() && self.local_lines.iter().any(|lines| lines.contains(&line.number())) {
            // A local subprogram after M30 (M97's), which runs only where called.
            self.out.extend(line.items.into_iter().filter_map(|item| match item {
                Piece::Lexed(said @ Lexed::Diagnostic(_)) => Some(said),
                _ => None,
            }));
            self.out.extend(line.end.map(Lexed::Token));
            return;
        }
        let program = self.fanuc_block(&line, self.open.last().map(|open| &open.head)).filter(|control| {
            control.keyword == Keyword::Program
                || self.open.last().is_some_and(|open| open.head.keyword == Keyword::Program)
        });
        let program = program.map(|control| match self.open.last() {
            Some(open) if control.keyword == Keyword::EndProgram => {
                Control { label: open.head.label.clone(), ..control }
            }
            _ => control,
        });
        let Some(control) = program.or_else(|| line.control().cloned()) else {
            return self.add(Node::Line(line));
        };
        // What goes with M99 runs before the return; the line's diagnostics
        // go with it, to be said when it runs.
        let before = (control.fanuc && control.keyword == Keyword::EndProgram).then(|| line.before_its_end()).flatten();
        let ran_before = before.is_some();
        if let Some(before) = before {
            self.add(Node::Line(before));
        }
        // The line's diagnostics and end still go out, in their place.
        if let Err(diagnostic) = self.structure(control) {
            self.error(diagnostic);
        }
        for item in line.items.into_iter().filter(|_| !ran_before) {
            if let Piece::Lexed(diagnostic @ Lexed::Diagnostic(_)) = item {
                self.out.push_back(diagnostic);
            }
        }
        self.out.extend(line.end.map(Lexed::Token));
    }

    /// Opens, continues or closes a block at a control line.
    fn structure(&mut self, control: Control) -> Result<(), Diagnostic> {
        let closes = |open: &Open, keywords: &[Keyword]| {
            open.head.label == control.label && keywords.contains(&open.head.keyword)
        };
        match control.keyword {
            Keyword::Sub | Keyword::If | Keyword::Do | Keyword::Repeat | Keyword::Program => self.open_block(control),
            Keyword::While if !self.open.last().is_some_and(|open| closes(open, &[Keyword::Do])) => {
                self.open_block(control)
            }
            Keyword::Call | Keyword::Return | Keyword::Break | Keyword::Continue => self.add(Node::Simple(control)),
            Keyword::ElseIf | Keyword::Else => {
                let open = self.open.last_mut().filter(|open| closes(open, &[Keyword::If, Keyword::ElseIf]));
                let Some(open) = open else { return Err(unmatched(&control)) };
                let body: Body = std::mem::take(&mut open.nodes).into();
                let head = std::mem::replace(&mut open.head, control);
                open.branches.push((head, body));
            }
            _ => {
                let wanted: &[Keyword] = match control.keyword {
                    Keyword::EndSub => &[Keyword::Sub],
                    Keyword::EndIf => &[Keyword::If, Keyword::ElseIf, Keyword::Else],
                    Keyword::EndWhile => &[Keyword::While],
                    Keyword::EndRepeat => &[Keyword::Repeat],
                    Keyword::EndProgram => &[Keyword::Program],
                    _ => &[Keyword::Do],
                };
                if !self.open.last().is_some_and(|open| closes(open, wanted)) {
                    return Err(unmatched(&control));
                }
                let mut open = self.open.pop().expect("checked just above");
                if control.keyword == Keyword::EndSub && !control.args.is_empty() {
                    open.nodes.push(Node::Simple(Control { keyword: Keyword::Return, ..control.clone() }));
                }
                let body: Body = open.nodes.into();
                let node = match control.keyword {
                    Keyword::EndSub | Keyword::EndProgram => Node::Sub(Rc::new(Sub { head: open.head, body })),
                    Keyword::EndIf => {
                        let mut branches = open.branches;
                        branches.push((open.head, body));
                        Node::If(branches)
                    }
                    Keyword::While => Node::Loop(Rc::new(Loop { head: open.head, until: Some(control), body })),
                    _ => Node::Loop(Rc::new(Loop { head: open.head, until: None, body })),
                };
                self.add(node);
            }
        }
        Ok(())
    }

    fn open_block(&mut self, head: Control) {
        self.open.push(Open { head, nodes: Vec::new(), branches: Vec::new() });
    }

    /// A node read: into the block being read, or run now.
    fn add(&mut self, node: Node) {
        match self.open.last_mut() {
            Some(open) => open.nodes.push(node),
            None => {
                let body: Body = Rc::new([node]);
                self.frames.push(Frame { body, next: 0, kind: FrameKind::Branch });
            }
        }
    }

    /// Runs the next node of the innermost body; false when nothing runs.
    fn step(&mut self) -> bool {
        if self.stop_loops {
            self.stop_at_error();
        }
        let Some(frame) = self.frames.last_mut() else { return false };
        if frame.next == frame.body.len() {
            self.end_of_body();
            return true;
        }
        let body = frame.body.clone();
        let node = &body[frame.next];
        frame.next += 1;
        if !self.count_block() {
            return true;
        }
        match node {
            Node::Line(line) => self.run_line(line),
            Node::Sub(sub) => self.define(sub.clone()),
            Node::If(branches) => {
                for (head, body) in branches {
                    match head.args.first().map(|condition| self.evaluate(condition, head.span)) {
                        Some(Err(diagnostic)) => return self.fail(diagnostic),
                        Some(Ok(0.0)) => continue,
                        _ => {}
                    }
                    self.frames.push(Frame { body: body.clone(), next: 0, kind: FrameKind::Branch });
                    break;
                }
            }
            Node::Loop(block) => self.enter(block.clone()),
            Node::Simple(control) => self.simple(control),
        }
        true
    }

    /// Reports an error of the running body.
    fn fail(&mut self, diagnostic: Diagnostic) -> bool {
        self.error(diagnostic);
        true
    }

    fn enter(&mut self, block: Rc<Loop>) {
        let head = &block.head;
        let remaining = match head.keyword {
            Keyword::While => match self.evaluate(&head.args[0], head.span) {
                Ok(condition) if condition != 0.0 => 1,
                Ok(_) => 0,
                Err(diagnostic) => return self.error(diagnostic),
            },
            Keyword::Repeat => match self.evaluate(&head.args[0], head.span) {
                Ok(count) => count.max(0.0).round() as u64,
                Err(diagnostic) => return self.error(diagnostic),
            },
            _ => 1,
        };
        if remaining > 0 {
            let body = block.body.clone();
            self.frames.push(Frame { body, next: 0, kind: FrameKind::Loop { block, iterations: 0, remaining } });
        }
    }

    /// The innermost body has run to its end.
    fn end_of_body(&mut self) {
        let looping = matches!(
            self.frames.last().map(|frame| &frame.kind),
            Some(FrameKind::Loop { .. } | FrameKind::Call { remaining: 2.., .. })
        );
        // A loop's end and its test are a block run again, each time.
        if looping && !self.count_block() {
            return;
        }
        let frame = self.frames.last_mut().expect("a body is running");
        match &mut frame.kind {
            FrameKind::Branch => {
                self.frames.pop();
            }
            FrameKind::Call { remaining, locals, .. } if *remaining > 1 => {
                // M98 P.. L.., G65 P.. L..: the body again, a G65's with its arguments again.
                *remaining -= 1;
                frame.next = 0;
                if let Some(locals) = locals {
                    let again = (**locals).clone();
                    *self.store.level() = again;
                }
            }
            FrameKind::Call { .. } => self.leave_call(),
            FrameKind::Loop { block, iterations, remaining } => {
                *iterations += 1;
                let block = block.clone();
                let again = match (&block.until, block.head.keyword) {
                    (_, Keyword::Repeat) => {
                        *remaining -= 1;
                        Ok(*remaining > 0)
                    }
                    (Some(until), _) => self.evaluate(&until.args[0], until.span).map(|c| c != 0.0),
                    (None, _) => self.evaluate(&block.head.args[0], block.head.span).map(|c| c != 0.0),
                };
                let frame = self.frames.last_mut().expect("a body is running");
                let FrameKind::Loop { iterations, .. } = frame.kind else { unreachable!("matched above") };
                match again {
                    Ok(true) if iterations >= self.limits.iterations => {
                        self.frames.pop();
                        let message =
                            format!("{} ran {iterations} times without ending: stopped", block.head.describe());
                        let help = "raise [machine] max_iterations in ger.toml if it is meant to run longer";
                        self.error(Diagnostic::error(block.head.span, message).with_help(help));
                    }
                    Ok(true) => frame.next = 0,
                    Ok(false) => {
                        self.frames.pop();
                    }
                    Err(diagnostic) => {
                        self.frames.pop();
                        self.error(diagnostic);
                    }
                }
            }
        }
    }

    /// Counts a block run inside a loop or a call. Past `limits.blocks` the
    /// program ends there, at the outermost loop or call, as one that never
    /// ends: false then. Loops that each end, nested, could otherwise run
    /// for longer than anyone waits.
    fn count_block(&mut self) -> bool {
        let outermost = self.frames.iter().find_map(|frame| match &frame.kind {
            FrameKind::Loop { block, .. } => Some(block.head.span),
            FrameKind::Call { origin, .. } => Some(origin.call),
            FrameKind::Branch => None,
        });
        let by_jump = outermost.is_none();
        let Some(outermost) = outermost.or(self.jumped) else { return true };
        self.blocks_run += 1;
        if self.blocks_run <= self.limits.blocks {
            return true;
        }
        let blocks = self.limits.blocks;
        let message = if by_jump {
            format!("after this GOTO jumped back, the program ran {blocks} blocks without ending: stopped")
        } else {
            format!("the loops and calls from here ran {blocks} blocks without ending: stopped")
        };
        let help = "raise [machine] max_blocks in ger.toml if the program is meant to run longer";
        self.out.push_back(Lexed::Diagnostic(Diagnostic::error(outermost, message).with_help(help)));
        self.end_program();
        false
    }

    fn leave_call(&mut self) {
        if let Some(Frame { kind: FrameKind::Call { locals: Some(_), .. }, .. }) = self.frames.pop() {
            self.store.levels.pop();
        }
    }

    fn simple(&mut self, control: &Control) {
        match control.keyword {
            Keyword::Call => self.call(control),
            Keyword::Return => {
                if let Some(value) = control.args.first() {
                    match self.evaluate(value, control.span) {
                        Ok(value) => {
                            self.store.named.insert(RETURNED.to_string(), value);
                        }
                        Err(diagnostic) => self.error(diagnostic),
                    }
                }
                if !self.frames.iter().any(|frame| matches!(frame.kind, FrameKind::Call { .. })) {
                    let message = format!("{} return is not in a subroutine", control.name());
                    return self.error(Diagnostic::error(control.span, message));
                }
                while let Some(frame) = self.frames.last() {
                    if matches!(frame.kind, FrameKind::Call { .. }) {
                        return self.leave_call();
                    }
                    self.frames.pop();
                }
            }
            _ => {
                // break and continue: the loop they name, inside this call.
                let found = self.frames.iter().rev().position(|frame| match &frame.kind {
                    FrameKind::Loop { block, .. } => block.head.label == control.label,
                    FrameKind::Call { .. } => true,
                    FrameKind::Branch => false,
                });
                let at = found.map(|from_top| self.frames.len() - 1 - from_top);
                let Some(at) = at.filter(|&at| matches!(self.frames[at].kind, FrameKind::Loop { .. })) else {
                    let message = format!("{} is not in a loop {}", control.describe(), control.name());
                    return self.error(Diagnostic::error(control.span, message));
                };
                self.frames.truncate(at + 1);
                let frame = self.frames.last_mut().expect("the loop is there");
                if control.keyword == Keyword::Break {
                    self.frames.pop();
                } else {
                    frame.next = frame.body.len();
                }
            }
        }
    }

    fn call(&mut self, control: &Control) {
        let resolved;
        let control = match &control.computed {
            None => control,
            Some(number) => match self.subroutine_number(number, control.span) {
                Ok(label) => {
                    resolved = Control { label, computed: None, ..control.clone() };
                    &resolved
                }
                Err(diagnostic) => return self.error(diagnostic),
            },
        };
        if !self.subs.contains_key(&control.label)
            && !self.look_ahead_for(&control.label)
            && !self.subroutine_from_file(&control.label)
        {
            let message = format!("{} is called but never defined", control.name());
            let file = format!("{}.ngc", control.label);
            let help = format!(
                "define the subroutine in the program (o100 sub ... o100 endsub), or in {file} beside it or in a \
                 folder of [dialect] subroutine_path"
            );
            return self.error(Diagnostic::error(control.span, message).with_help(help));
        }
        let sub = self.subs[&control.label].clone();
        if self.call_depth() >= MAX_CALL_DEPTH {
            let message = format!("calls nest more than {MAX_CALL_DEPTH} deep: a recursion that does not end?");
            return self.error(Diagnostic::error(control.span, message));
        }
        let mut locals = Locals::default();
        for (index, arg) in control.args.iter().enumerate().take(LOCALS) {
            match self.evaluate(arg, control.span) {
                Ok(value) => {
                    locals.numbered[index] = value;
                    locals.given[index] = true;
                }
                Err(diagnostic) => return self.error(diagnostic),
            }
        }
        let file = self.from_files.get(&control.label);
        let what = file.map_or(control.name(), |name| format!("{} (from {name})", control.name()));
        let origin = Arc::new(Origin { what, call: control.span, parent: self.origin() });
        let (locals_kept, file) = (Some(Box::new(locals.clone())), file.is_some());
        let kind = FrameKind::Call { origin, locals: locals_kept, remaining: 1, file };
        self.store.levels.push(locals);
        self.frames.push(Frame { body: sub.body.clone(), next: 0, kind });
    }

    /// The label of the numbered subroutine `number` works out to.
    fn subroutine_number(&self, number: &Expr, at: Span) -> Result<String, Diagnostic> {
        let value = self.evaluate(number, at)?;
        let whole = value.round();
        if (value - whole).abs() > expr::EQUAL_WITHIN || whole < 0.0 {
            let message = format!("a subroutine's number must be whole and not negative, not {value}");
            return Err(Diagnostic::error(at, message));
        }
        Ok(format!("{whole:.0}"))
    }

    /// The next line, whole: one read again after a GOTO, or the program's
    /// next; `None` at the program's end.
    fn next_line(&mut self) -> Option<Line> {
        while let Some(replay) = &mut self.replay {
            match whole_line(replay, &mut Line::default()) {
                Some(line) => return Some(line),
                None => self.replay = None,
            }
        }
        self.next_line_from_program()
    }

    /// The program's next line, read for the first time.
    fn next_line_from_program(&mut self) -> Option<Line> {
        let line = match self.unread.pop_front() {
            Some(line) => line,
            None => whole_line(&mut self.tokens, &mut self.line)?,
        };
        if self.fanuc_programs && self.first_code_line.is_none() && self.structure.is_empty() && opens_a_program(&line)
        {
            self.find_main_return();
        }
        self.note(&line);
        Some(line)
    }

    /// A line read for the first time: where its label is, and the blocks
    /// it opens or closes.
    fn note(&mut self, line: &Line) {
        // As pass 00 reads it: the first statement the parser gets, so not
        // an O-word line, a line of a block, nor one that only sets
        // parameters (LinuxCNC's `O1` title may follow its subroutines).
        if self.first_code_line.is_none() && line.has_words() && line.control().is_none() && self.structure.is_empty() {
            self.first_code_line = Some(line.number());
        }
        if let Some(number) = line.label() {
            let label = Label { line: line.number(), open_blocks: self.structure.len() as u32 };
            match self.labels.entry(number) {
                std::collections::hash_map::Entry::Vacant(entry) => {
                    entry.insert(label);
                }
                std::collections::hash_map::Entry::Occupied(_) => self.more_labels.push((number, label)),
            }
        }
        let fanuc = self.fanuc_block(line, self.structure.last());
        let Some(control) = fanuc.as_ref().or(line.control()) else { return };
        let top = self.structure.last();
        let closes = |keywords: &[Keyword]| {
            top.is_some_and(|open| open.label == control.label && keywords.contains(&open.keyword))
        };
        let close = match control.keyword {
            Keyword::Sub | Keyword::If | Keyword::Do | Keyword::Repeat => false,
            Keyword::While => closes(&[Keyword::Do]),
            Keyword::EndSub => closes(&[Keyword::Sub]),
            Keyword::EndIf => closes(&[Keyword::If]),
            Keyword::EndWhile => closes(&[Keyword::While]),
            Keyword::EndRepeat => closes(&[Keyword::Repeat]),
            Keyword::Program => false,
            Keyword::EndProgram => top.is_some_and(|open| open.keyword == Keyword::Program),
            _ => return,
        };
        if close {
            self.structure.pop();
        } else if !matches!(
            control.keyword,
            Keyword::EndSub | Keyword::EndIf | Keyword::EndWhile | Keyword::EndRepeat | Keyword::EndProgram
        ) {
            self.structure.push(control.clone());
        }
    }

    /// `GOTO n`: the program goes on at the line labelled `Nn`. As on a
    /// Fanuc, it may jump within the loop it is in or out of it (forward or
    /// back), never into one; in a subroutine, only within it. The search
    /// goes forward from the GOTO first, then from the start.
    fn goto(&mut self, label: u64, at: Span) {
        if let Some((frame, index, line)) = self.label_in_frames(label) {
            if self.jump_counted(at, line) {
                self.frames.truncate(frame + 1);
                self.frames[frame].next = index;
            }
            return;
        }
        let running = self.frames.iter().position(|frame| !matches!(frame.kind, FrameKind::Branch));
        let inner = running.map_or(&[][..], |first| &self.frames[first..]);
        if let Some(head) = inner.iter().find_map(|frame| label_inside(&frame.body, label)) {
            let message = format!("GOTO {label} jumps into {}, at line {}", head.describe(), head.span.line);
            let help = "a Fanuc refuses a jump into a loop (alarm 128): jump to its head, or out of it";
            return self.jump_failed(Diagnostic::error(at, message).with_help(help));
        }
        if let Some(origin) = self.origin() {
            let message = format!("GOTO {label}: {} has no line N{label}", origin.what);
            let help = "a GOTO jumps within the program or subroutine it is in";
            return self.jump_failed(Diagnostic::error(at, message).with_help(help));
        }
        self.jump_in_program(label, at);
    }

    /// A GOTO in the main program's lines, to a line outside every block
    /// running: those stop, and the program reads on from the label, its
    /// lines read again from the history of the text.
    fn jump_in_program(&mut self, label: u64, at: Span) {
        let Some(history) = self.history.clone() else {
            return self.jump_failed(Diagnostic::error(at, "GOTO: the program's lines are not kept to jump to"));
        };
        let forward =
            |interpreter: &Self| interpreter.label_lines(label).into_iter().find(|found| found.line > at.line);
        if forward(self).is_none() {
            // Read on to it (or to the end: a Fanuc searches on, then from
            // the start). The lines read are kept as text; if there is no
            // jump, they run after the ones waiting.
            let first = history.borrow().lines() + 1;
            while self.next_line_from_program().is_some_and(|line| line.label() != Some(label)) {}
            if history.borrow().lines() >= first {
                let text = history.borrow().from_line(first);
                let read = Lexer::in_dialect(std::io::Cursor::new(text), Dialect::Lenient).starting_at(first).pieces();
                let waiting = self.replay.take().unwrap_or_else(|| Box::new(std::iter::empty()));
                self.replay = Some(Box::new(waiting.chain(read)));
            }
        }
        let Some(target) = forward(self).or_else(|| self.label_lines(label).first().copied()) else {
            let message = format!("GOTO {label}: the program has no line N{label}");
            let help = "a Fanuc stops with alarm 128: the sequence number is not found";
            return self.jump_failed(Diagnostic::error(at, message).with_help(help));
        };
        if target.open_blocks > 0 {
            let message = format!("GOTO {label} jumps into a loop or block, at line {}", target.line);
            return self.jump_failed(Diagnostic::error(at, message).with_help(INTO_A_BLOCK));
        }
        if !self.jump_counted(at, target.line) {
            return;
        }
        self.frames.clear();
        self.ahead.clear();
        let text = history.borrow().from_line(target.line);
        let lexer = Lexer::in_dialect(std::io::Cursor::new(text), Dialect::Lenient).starting_at(target.line);
        self.replay = Some(Box::new(lexer.pieces()));
    }

    /// The lines labelled `label` read so far, in order.
    fn label_lines(&self, label: u64) -> Vec<Label> {
        let mut found: Vec<Label> = self.labels.get(&label).copied().into_iter().collect();
        found.extend(self.more_labels.iter().filter(|(n, _)| *n == label).map(|(_, found)| *found));
        found.sort_by_key(|found| found.line);
        found
    }

    /// Counts a jump back, as a loop's iteration; false if it is not taken:
    /// the jump has gone back `limits.iterations` times, or an error came
    /// while its lines ran. The program goes on after the GOTO then.
    fn jump_counted(&mut self, at: Span, target: u32) -> bool {
        if target > at.line {
            return true;
        }
        self.jumped.get_or_insert(at);
        let level = self.store.levels.len();
        let failed =
            self.last_error.take().filter(|&(line, at_level)| at_level == level && (target..=at.line).contains(&line));
        if failed.is_some() {
            self.goto_loops.clear();
            let message = "this GOTO stopped at the error above: it does not jump back again";
            let help = "an error ends the loop it is in; the program goes on after it";
            self.error(Diagnostic::error(at, message).with_help(help));
            return false;
        }
        let index = match self.goto_loops.iter().position(|jump| jump.site == at.line && jump.level == level) {
            Some(index) => index,
            None => {
                self.goto_loops.push(GotoLoop { site: at.line, target, level, jumps: 0 });
                self.goto_loops.len() - 1
            }
        };
        let jump = &mut self.goto_loops[index];
        jump.target = jump.target.min(target);
        jump.jumps += 1;
        if jump.jumps < self.limits.iterations {
            return true;
        }
        let jumps = jump.jumps;
        self.goto_loops.remove(index);
        let message = format!("this GOTO jumped back {jumps} times without ending: stopped");
        let help = "raise [machine] max_iterations in ger.toml if it is meant to run longer";
        self.error(Diagnostic::error(at, message).with_help(help));
        false
    }

    /// A GOTO that cannot jump stops the program, as a Fanuc's alarm does.
    fn jump_failed(&mut self, diagnostic: Diagnostic) {
        self.error(diagnostic);
        self.end_program();
    }

    fn end_program(&mut self) {
        self.frames.clear();
        self.open.clear();
        self.ahead.clear();
        self.replay = None;
        self.done = true;
    }

    /// Where `label` is in the bodies running (those of loops and calls),
    /// innermost first, not beyond the call the GOTO is in: the frame, the
    /// index in its body and the line. Forward from the GOTO first.
    fn label_in_frames(&self, label: u64) -> Option<(usize, usize, u32)> {
        let first = self.frames.iter().position(|frame| !matches!(frame.kind, FrameKind::Branch))?;
        for (index, frame) in self.frames.iter().enumerate().skip(first).rev() {
            let at = |node: &Node| matches!(node, Node::Line(line) if line.label() == Some(label));
            let forward = frame.body[frame.next..].iter().position(at).map(|i| i + frame.next);
            if let Some(found) = forward.or_else(|| frame.body.iter().position(at)) {
                let Node::Line(line) = &frame.body[found] else { unreachable!("found a line") };
                return Some((index, found, line.number()));
            }
            if matches!(frame.kind, FrameKind::Call { .. }) {
                break;
            }
        }
        None
    }

    /// Reads on to the definition of a subroutine called above it, as
    /// LinuxCNC does; the lines passed over wait in `ahead` for their turn
    /// (so a program whose subroutines follow its main part holds the rest
    /// of that part meanwhile). True if it was found.
    fn look_ahead_for(&mut self, label: &str) -> bool {
        while let Some(line) = self.next_line() {
            // Every definition passed on the way is taken, so that looking for
            // one program does not hide another (M98 P30010: O30010, or O10).
            let defines = line.control().is_some_and(|c| c.keyword == Keyword::Sub)
                || self.fanuc_block(&line, None).is_some_and(|c| c.keyword == Keyword::Program);
            if !defines {
                self.ahead.push_back(line);
                continue;
            }
            // The definition is read as any block; closed, it is a frame that
            // would define it when run: it is defined now instead.
            self.read(line);
            while !self.open.is_empty() {
                let Some(line) = self.next_line() else { break };
                self.read(line);
            }
            let defined = self.frames.last().and_then(|frame| match &frame.body[..] {
                [Node::Sub(sub)] if matches!(frame.kind, FrameKind::Branch) => Some(sub.clone()),
                _ => None,
            });
            if let Some(sub) = defined {
                self.frames.pop();
                self.define(sub);
            }
            if self.subs.contains_key(label) {
                return true;
            }
        }
        false
    }

    /// A LinuxCNC subroutine kept in a file of its own (`name.ngc`, found
    /// as `[dialect] subroutine_path` says): its `o<name> sub` block is
    /// read, the lines outside it are not, as LinuxCNC reads such a file.
    fn subroutine_from_file(&mut self, label: &str) -> bool {
        let Some((name, text)) = self.files.as_mut().and_then(|find| find(Wanted::Subroutine(label))) else {
            return false;
        };
        let mut lines = Lexer::in_dialect(std::io::Cursor::new(text), Dialect::Lenient).pieces();
        let mut partial = Line::default();
        let head = loop {
            let Some(line) = whole_line(&mut lines, &mut partial) else { return false };
            if line.control().is_some_and(|c| c.keyword == Keyword::Sub && c.label == label) {
                break line;
            }
        };
        // Read as the program's own definition is, in a block stack of its own.
        let around = std::mem::take(&mut self.open);
        let frames = self.frames.len();
        self.read(head);
        while !self.open.is_empty() {
            let Some(line) = whole_line(&mut lines, &mut partial) else { break };
            self.read(line);
        }
        for open in std::mem::replace(&mut self.open, around) {
            let message = format!("{} is never closed (in {name})", open.head.describe());
            self.error(Diagnostic::error(open.head.span, message));
        }
        let defined = (self.frames.len() > frames).then(|| self.frames.last()).flatten().and_then(|frame| match &frame
            .body[..]
        {
            [Node::Sub(sub)] if matches!(frame.kind, FrameKind::Branch) => Some(sub.clone()),
            _ => None,
        });
        let Some(sub) = defined else { return false };
        self.frames.pop();
        self.from_files.insert(label.to_string(), name);
        self.subs.insert(sub.head.label.clone(), sub);
        true
    }

    /// The end of the program: blocks never closed are errors at their
    /// head; but a Fanuc program after a main program that returned (one
    /// that ends with M30, say) is one of the file's programs, never run.
    fn finish(&mut self) {
        for open in std::mem::take(&mut self.open) {
            let head = &open.head;
            let listed = head.fanuc && head.keyword == Keyword::Program;
            match self.main_return {
                Some(end) if listed && head.span.line > end => {
                    let message = format!(
                        "{} is a program of its own after the main program's M99 (line {end}): LinuxCNC never runs \
                         it, and neither does ger",
                        head.describe()
                    );
                    let help = "a Fanuc runs the program its operator selects; put the main program first, and its \
                                subprograms after its M30";
                    self.diagnostic(Diagnostic::warning(head.span, message).with_help(help));
                }
                _ => {
                    let message = format!("{} is never closed", head.describe());
                    self.error(Diagnostic::error(head.span, message));
                }
            }
        }
    }
}

/// What a call looks for in a file of its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wanted<'n> {
    /// A Fanuc program by number (`M98 P1002`, `G65 P1002`).
    Program(u32),
    /// A LinuxCNC subroutine by its label, in lower case (`o<frame_rect> call`: `frame_rect`).
    Subroutine(&'n str),
}

/// Finds what a call wants in a file of its own: the file's name and its text.
pub type FindProgram<'a> = Box<dyn FnMut(Wanted<'_>) -> Option<(String, Vec<u8>)> + 'a>;

/// Fanuc's alarm parameter: setting it stops the program with a message.
const ALARM: u32 = 3000;

/// Fanuc's pause parameter: setting it stops the program (M00) with a message.
const PAUSE: u32 = 3006;

/// A call to a Fanuc program: `M98 P.. L..`, or `G65 P.. L..` and its arguments.
struct FanucCall {
    macro_call: bool,
    /// Haas's `M97 Pn`: the lines from `Nn` of this program to its M99.
    local: bool,
    /// Fadal's `L0102`: subroutine 1, defined by `L0100` ... `M17`, twice.
    fadal: bool,
    at: Span,
    program: Option<f64>,
    repeat: f64,
    args: Vec<(char, f64, Span)>,
}

/// A call found and ready to run.
struct Ready {
    sub: Rc<Sub>,
    origin: Arc<Origin>,
    /// A G65's locals; an M98 shares its caller's.
    locals: Option<Locals>,
    repeat: u64,
    /// Whether the program is in a file of its own.
    file: bool,
}

/// The call a line makes, if it has `G65` or `M98`.
fn fanuc_call(tokens: &[Token]) -> Option<FanucCall> {
    let words = || {
        tokens.iter().filter_map(|token| match token.kind {
            TokenKind::Word { letter, value } => Some((letter, value, token.span)),
            _ => None,
        })
    };
    if let Some((number, times, at)) = fadal_call(tokens) {
        let program = Some(number as f64);
        return Some(FanucCall {
            macro_call: false,
            local: false,
            fadal: true,
            at,
            program,
            repeat: times as f64,
            args: Vec::new(),
        });
    }
    let (macro_call, local, at) = words().find_map(|(letter, value, span)| match (letter, value) {
        ('G', 65.0) => Some((true, false, span)),
        ('M', 98.0) => Some((false, false, span)),
        ('M', 97.0) => Some((false, true, span)),
        _ => None,
    })?;
    let value = |wanted: char| words().find(|(letter, ..)| *letter == wanted).map(|(_, value, _)| value);
    let args = if macro_call {
        words().filter(|(letter, value, _)| !matches!((letter, value), ('G', 65.0) | ('P' | 'L', _))).collect()
    } else {
        Vec::new()
    };
    Some(FanucCall {
        macro_call,
        local,
        fadal: false,
        at,
        program: value('P'),
        repeat: value('L').unwrap_or(1.0),
        args,
    })
}

/// Fadal's subroutines: a line of one `L` word of four digits (`L0100`,
/// leading zeros optional), its first two the subroutine (1 to 99), its last
/// two the times to run it (00: the subroutine's definition starts here).
fn fadal_subroutine(line: &Line) -> Option<(u32, u32, Span)> {
    let mut words = line.words();
    match (words.next()?, words.next()) {
        (('L', value, span), None) if value.fract() == 0.0 && (100.0..10_000.0).contains(&value) => {
            let value = value as u32;
            Some((value / 100, value % 100, span))
        }
        _ => None,
    }
}

/// [`fadal_subroutine`] as the tokens of a line about to run: a call.
fn fadal_call(tokens: &[Token]) -> Option<(u32, u32, Span)> {
    let mut words = tokens.iter().filter(|token| matches!(token.kind, TokenKind::Word { .. }));
    match (words.next(), words.next()) {
        (Some(Token { kind: TokenKind::Word { letter: 'L', value }, span }), None)
            if value.fract() == 0.0 && (100.0..10_000.0).contains(value) && !(*value as u32).is_multiple_of(100) =>
        {
            Some((*value as u32 / 100, *value as u32 % 100, *span))
        }
        _ => None,
    }
}

/// How many lines a file's first program is read through for its end, to
/// find whether it returns with M99 (`Interpreter::find_main_return`).
const MAIN_PROGRAM_LOOKAHEAD: usize = 10_000;

/// Whether a line opens a Fanuc program: it starts with a whole `O` number.
fn opens_a_program(line: &Line) -> bool {
    line.words().next().is_some_and(|(letter, value, _)| letter == 'O' && value >= 0.0 && value.fract() == 0.0)
}

/// Whether a line ends a program read as a block: M99, or M30 or M2.
fn ends_a_program(line: &Line) -> bool {
    line.words().any(|(letter, value, _)| letter == 'M' && [99.0, 30.0, 2.0].contains(&value))
}

/// M30, M2 or M47 in a called program, as pass 00 says of them in a subprogram.
fn ends_program(tokens: &[Token]) -> Option<Diagnostic> {
    tokens.iter().find_map(|token| match token.kind {
        TokenKind::Word { letter: 'M', value: 47.0 } => Some(
            Diagnostic::error(token.span, "M47 inside a subprogram")
                .with_help("M47 repeats the main program; a subprogram repeats with M98 P.. L.."),
        ),
        TokenKind::Word { letter: 'M', value } if value == 30.0 || value == 2.0 => Some(
            Diagnostic::error(token.span, format!("M{value} inside a subprogram"))
                .with_help("a subprogram returns with M99; M30 ends the main program"),
        ),
        _ => None,
    })
}

/// The local a G65 argument letter sets, as Fanuc's first form of arguments maps them.
fn argument(letter: char) -> Option<usize> {
    const LETTERS: [(char, usize); 21] = [
        ('A', 1),
        ('B', 2),
        ('C', 3),
        ('I', 4),
        ('J', 5),
        ('K', 6),
        ('D', 7),
        ('E', 8),
        ('F', 9),
        ('H', 11),
        ('M', 13),
        ('Q', 17),
        ('R', 18),
        ('S', 19),
        ('T', 20),
        ('U', 21),
        ('V', 22),
        ('W', 23),
        ('X', 24),
        ('Y', 25),
        ('Z', 26),
    ];
    LETTERS.iter().find(|(known, _)| *known == letter).map(|(_, number)| *number)
}

const INTO_A_BLOCK: &str = "a Fanuc refuses a jump into a loop (alarm 128): jump to its head, or out of it";

/// A GOTO's target as a Fanuc reads it: a sequence number from 1 to 99999
/// (a parameter's value rounded).
fn label(value: f64, at: Span) -> Result<u64, Diagnostic> {
    let number = value.round();
    if (1.0..=99999.0).contains(&number) {
        return Ok(number as u64);
    }
    Err(Diagnostic::error(at, format!("GOTO {value}: a line's sequence number is 1 to 99999"))
        .with_help("a Fanuc stops with alarm 128 here"))
}

/// The next line from `source`, whole, gathered in `line`.
fn whole_line(source: &mut impl Iterator<Item = Piece>, line: &mut Line) -> Option<Line> {
    loop {
        match source.next() {
            Some(Piece::Lexed(Lexed::Token(token))) if token.kind == TokenKind::End && token.span.len == 0 => {
                let mut line = std::mem::take(line);
                line.end = Some(token);
                return Some(line);
            }
            Some(item) => line.items.push(item),
            None => {
                let line = std::mem::take(line);
                return (!line.items.is_empty()).then_some(line);
            }
        }
    }
}

/// The head of the block inside `body` whose lines have `label`, if any.
fn label_inside(body: &[Node], label: u64) -> Option<Control> {
    let has = |body: &[Node]| {
        body.iter().any(|node| matches!(node, Node::Line(line) if line.label() == Some(label)))
            || label_inside(body, label).is_some()
    };
    body.iter().find_map(|node| match node {
        Node::Loop(block) if has(&block.body) => Some(block.head.clone()),
        Node::If(branches) => branches.iter().find(|(_, body)| has(body)).map(|(head, _)| head.clone()),
        _ => None,
    })
}

/// Where a line sets the alarm, if it does.
fn alarm(assignments: &[(Target, f64, Span)]) -> Option<Span> {
    assignments.iter().find(|(target, ..)| matches!(target, Target::Numbered(ALARM))).map(|(_, _, span)| *span)
}

fn unmatched(control: &Control) -> Diagnostic {
    let message = format!("{} has no block {} to belong to", control.describe(), control.name());
    Diagnostic::error(control.span, message).with_help("an O-word block opens and closes with the same number")
}

impl<L: Iterator<Item = Piece>> Iterator for Interpreter<'_, L> {
    type Item = Lexed;

    fn next(&mut self) -> Option<Lexed> {
        loop {
            if let Some(lexed) = self.out.pop_front() {
                return Some(lexed);
            }
            if self.step() {
                continue;
            }
            if let Some(line) = self.ahead.pop_front() {
                self.read(line);
                continue;
            }
            if self.done {
                return None;
            }
            match self.next_line() {
                Some(line) => self.read(line),
                None => {
                    self.done = true;
                    self.finish();
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::config::{Config, DialectConfig, RunLimits};
    use crate::passes::testing::run_with;
    use crate::statement::{Dialect, Units};

    /// The program after pass 04, in millimetres, in the lenient dialect.
    fn flat(text: &str) -> Vec<String> {
        let config = Config { dialect: Dialect::Lenient.into(), units: Units::Mm, ..Config::default() };
        run_with(&format!("G21\n{text}"), &config, 4).into_iter().filter(|line| !line.contains("G21")).collect()
    }

    #[test]
    fn words_take_expressions_and_parameters() {
        // Values worked out by hand: 10*cos(60°) = 5, atan2(1, -1) = 135°.
        assert_eq!(
            flat("#1 = 2\n#<depth> = -1.5\nG01 X[#1 + 10*COS[60]] Y[ATAN[1]/[-1]] Z#<depth> F[#1*100]"),
            ["G01 X7.000 Y135.000 Z-1.500 F200.000"]
        );
        // A sign before a parameter, a function as a word's value, indirection.
        assert_eq!(
            flat("#3 = 4\n#4 = 7\n#5 = 3\nG01 X-#3 YSQRT[16] Z#[#5 + 1] F10"),
            ["G01 X-4.000 Y4.000 Z7.000 F10.000"]
        );
        // Fanuc's unbracketed value; a name read without spaces, in lower case.
        assert_eq!(flat("#<Feed Rate> = 100 + 20\nG01 X1 F#<feedrate>"), ["G01 X1.000 F120.000"]);
    }

    #[test]
    fn reads_on_a_line_come_before_its_assignments() {
        // rs274 moves this to X0: `#1 = 2` takes effect at the end of the line.
        assert_eq!(flat("#1 = 2 #2 = #1 G01 X#1 F10\nG01 Y#1 Z#2"), ["G01 X0.000 F10.000", "G01 Y2.000 Z0.000"]);
    }

    #[test]
    fn an_unset_numbered_parameter_is_zero_and_an_unset_name_an_error() {
        assert_eq!(flat("G01 X#7 Y1 F10"), ["G01 X0.000 Y1.000 F10.000"]);
        // rs274 reads #<_value> as 0 before any subroutine returns.
        assert_eq!(flat("G01 X#<_value> Y1 F10"), ["G01 X0.000 Y1.000 F10.000"]);
        assert_eq!(
            flat("G01 X#<nothing> F10\nG01 Y2 F10"),
            ["2:6: error: the parameter #<nothing> is not set", "G01 Y2.000 F10.000"]
        );
        assert_eq!(flat("#<_done> = 1\nG01 X[EXISTS[#<_done>] + EXISTS[#<other>]] F10"), ["G01 X1.000 F10.000"]);
        // As rs274 reads LinuxCNC's exists test: a numbered one exists if its number is one.
        assert_eq!(
            flat("#1 = 2\n#2 = 99999\nG01 X[EXISTS[##1]] Y[EXISTS[##2]] Z[EXISTS[###1]] F10"),
            ["G01 X1.000 Y0.000 Z0.000 F10.000"]
        );
        // ...but reading #99999 to find the number is an error, as rs274 says of LinuxCNC's exists-3.ngc.
        let out = flat("#2 = 99999\nG0 X EXISTS[###2]\nM2");
        assert!(out[0].starts_with("3:") && out[0].contains("there is no parameter #99999"), "{out:?}");
    }

    #[test]
    fn evaluation_errors_are_at_their_column_and_drop_the_line() {
        let cases = [
            ("G01 X[1/0] F10", "2:8: error: division by zero"),
            ("G01 X[SQRT[-1]] F10", "2:7: error: SQRT of a negative number"),
            ("G01 X[ACOS[2]] F10", "2:7: error: ACOS takes a number from -1 to 1"),
            ("G01 X[LN[0]] F10", "2:7: error: LN takes a number above zero"),
            ("G01 X[[-2] ** 0.5] F10", "2:12: error: a negative number raised to a fractional power"),
            ("G01 X[1 MOD 0] F10", "2:9: error: division by zero"),
            (
                "G01 X[10 ** 20] F10",
                "2:5: error: this works out to 100000000000000000000: ger reads numbers up to 10^12",
            ),
            ("#5400 = 1", "2:1: error: #5400 is one of LinuxCNC's system parameters, which ger does not compute"),
            ("G01 X#-1", "2:6: error: there is no parameter #-1: they are #1 to #5602"),
            ("G01 X#1.5", "2:6: error: a parameter's number must be whole, not 1.5"),
            ("G01 X[1 + ] F10", "2:11: error: expected a value: a number, a parameter, `[expression]` or a function"),
            ("G01 X[1 + 2 F10", "2:13: error: expected `]` to close the `[`"),
            ("G01 X[FOO[1]] F10", "2:7: error: `FOO` is not a function"),
            ("#1 X2", "2:1: error: a parameter here is set: write `#1 = value`"),
        ];
        for (line, error) in cases {
            let got = flat(&format!("{line}\nG01 Y2 F10"));
            assert_eq!(got[0], error, "{line}");
            assert_eq!(got[1..], ["G01 Y2.000 F10.000"], "{line}");
        }
    }

    #[test]
    fn the_strict_dialect_refuses_parameters_with_a_hint() {
        let got = run_with("#1 = 2", &Config::default(), 4);
        assert_eq!(got, ["1:1: error: parameters (`#1`, `#<name>`) are not supported: ger has no variables"]);
        let Some(crate::lex::Lexed::Diagnostic(diagnostic)) = crate::lex::lex_str("#1 = 2").next() else {
            panic!("the strict lexer read a parameter")
        };
        assert!(diagnostic.help.unwrap().contains("--lenient"));
    }

    #[test]
    fn subroutines_take_arguments_in_their_own_locals() {
        // As rs274 runs it: the call's #1..#3 are its arguments (unset ones 0),
        // the caller's #1 comes back after it, #40 is global, and
        // `return [value]` leaves the value in #<_value>.
        let program =
            "#1 = 7\no100 sub\nG01 X#1 Y#2 Z#3 F10\n#1 = 9 #40 = 1\no100 return [#1 * 2]\nG01 X99\no100 endsub\n\
                       o100 call [3] [4]\nG01 X#1 Y#<_value> Z#40";
        assert_eq!(flat(program), ["G01 X3.000 Y4.000 Z0.000 F10.000", "G01 X7.000 Y18.000 Z1.000"]);
        // A numbered subroutine's number may be worked out when it is called, as any value is.
        let program = "#<sub> = 2\no1 sub\nG01 X1 F10\no1 endsub\no2 sub\nG01 X#1 F10\no2 endsub\n\
                       o#<sub> call [5]\nO[#<sub> * 10 - 19] call\no[2.5] call\nG01 Y1";
        assert_eq!(
            flat(program),
            [
                "G01 X5.000 F10.000",
                "G01 X1.000",
                "11:1: error: a subroutine's number must be whole and not negative, not 2.5",
                "G01 Y1.000"
            ]
        );
        // LinuxCNC reads past spaces after the O, as everywhere outside comments.
        assert_eq!(flat("o <probe> sub\nG01 X#1 F10\no <probe> endsub\nO 7 sub\nG01 Y#1\nO 7 endsub\no <probe> call [2]\no 7 call [3]"), ["G01 X2.000 F10.000", "G01 Y3.000"]);
        // rs274 passes over a comment between arguments; one after them ends the line.
        let program = "o1 sub\nG01 X#1 Y#2 Z#3 F10\no1 endsub\no1 call [1] (depth) [2] [3]\no1 call [4] [5] (not [6])";
        assert_eq!(flat(program), ["G01 X1.000 Y2.000 Z3.000 F10.000", "G01 X4.000 Y5.000 Z0.000"]);
        // A named local of the caller is not seen in the call.
        let got = flat("#<here> = 1\no<show> sub\nG01 X#<here> F10\no<show> endsub\no<show> call");
        assert_eq!(got, ["4:6: error: the parameter #<here> is not set"]);
        assert_eq!(
            flat("o100 call\nG01 X1 F10"),
            ["2:1: error: o100 is called but never defined", "G01 X1.000 F10.000"]
        );
        // A subroutine defined below its call is read ahead for, as LinuxCNC
        // does; what it passed over runs after the call, in order.
        assert_eq!(
            flat("G01 F10\no100 call [3]\nG01 Y1\no100 call [4]\nM30\no100 sub\nG01 X#1\no100 endsub"),
            ["G01 X3.000 F10.000", "G01 Y1.000", "G01 X4.000", "M30"]
        );
    }

    #[test]
    fn loops_run_their_bodies_and_stream() {
        // `o101 end while`: LinuxCNC reads past the space.
        let whiles = "#1 = 0\no101 while [#1 LT 3]\nG01 X#1 F10\n#1 = [#1 + 1]\no101 end while";
        assert_eq!(flat(whiles), ["G01 X0.000 F10.000", "G01 X1.000", "G01 X2.000"]);
        // do-while runs once before its test; repeat its count.
        let dos = "#1 = 5\no102 do\nG01 X#1 F10\n#1 = [#1 + 1]\no102 while [#1 LT 3]\no103 repeat [2]\nG01 Y1\nG01 Y0\no103 endrepeat";
        assert_eq!(flat(dos), ["G01 X5.000 F10.000", "G01 Y1.000", "G01 Y0.000", "G01 Y1.000", "G01 Y0.000"]);
        // break and continue name the loop they leave or go on with.
        let flow = "#1 = 0\no1 while [1]\n#1 = [#1 + 1]\no2 if [#1 EQ 2]\no1 continue\no2 elseif [#1 GT 3]\no1 break\no2 else\nG01 X#1 F10\no2 endif\no1 endwhile";
        assert_eq!(flat(flow), ["G01 X1.000 F10.000", "G01 X3.000"]);
    }

    #[test]
    fn an_error_in_a_loop_stops_it_once_and_the_program_goes_on() {
        // Without the rule, this would say the division by zero 1,000,000 times (the loop never ends).
        let program = "#1 = 0\no1 while [1]\no2 repeat [3]\nG01 X[1/#1] F10\no2 endrepeat\no1 endwhile\nG01 Y1 F10";
        let got = flat(program);
        assert_eq!(got.len(), 3, "{got:?}");
        assert!(got[0].starts_with("5:") && got[0].contains("division by zero"), "{got:?}");
        assert!(got[1].starts_with("3:1: error: o1 while stopped at the error above, in its iteration 1"), "{got:?}");
        assert_eq!(got[2], "G01 Y1.000 F10.000");
        // A lexer's error in a loop's line (the line is mangled), and one inside a call the loop makes.
        let got = flat("#1 = 0\no1 while [#1 LT 5]\n#< Y1\n#1 = [#1 + 1]\no1 endwhile\nG01 X#1 F10");
        assert_eq!(got.iter().filter(|l| l.contains("error")).count(), 2, "{got:?}");
        // Stopped at the mangled line, before the increment after it.
        assert_eq!(got.last().unwrap(), "G01 X0.000 F10.000", "{got:?}");
        let got = flat("o9 sub\nG01 X[1/0] F10\no9 endsub\no1 repeat [100]\no9 call\no1 endrepeat\nG01 Y2 F10");
        assert_eq!(got.iter().filter(|l| l.contains("error")).count(), 2, "{got:?}");
        assert_eq!(got.last().unwrap(), "G01 Y2.000 F10.000", "{got:?}");
    }

    #[test]
    fn loops_that_each_end_are_stopped_when_together_they_run_too_long() {
        let limits = RunLimits { iterations: 1000, blocks: 100 };
        let config = Config {
            dialect: DialectConfig { limits, ..Dialect::Lenient.into() },
            units: Units::Mm,
            ..Config::default()
        };
        // Each loop ends after ten passes. A pass of o1 runs 33 blocks: `#2=0`, o2's
        // head, ten times o2's two lines and its end, and o1's end; three make 99, and
        // the fourth stops at o2's head, the 101st, having moved in three passes.
        let program = "G21 G01 F10\n#1=0\no1 repeat [10]\n#2=0\no2 repeat [10]\nG01 X#2\n#2=[#2+1]\no2 endrepeat\no1 endrepeat\nG01 Y1";
        let got = run_with(program, &config, 4);
        assert_eq!(got.iter().filter(|line| line.starts_with("G01 X")).count(), 30, "{got:?}");
        assert_eq!(
            got.last().unwrap(),
            "3:1: error: the loops and calls from here ran 100 blocks without ending: stopped"
        );
        assert!(!got.iter().any(|line| line.contains("Y1")), "the program ends at the stop: {got:?}");
        // Calls count as well: a subroutine that calls another ten times, ten times.
        let program = "o1 sub\nG01 X1 F10\no1 endsub\no2 sub\no3 repeat [10]\no1 call\no3 endrepeat\no2 endsub\no4 repeat [10]\no2 call\no4 endrepeat";
        let got = run_with(&format!("G21\n{program}"), &config, 4);
        assert_eq!(
            got.last().unwrap(),
            "10:1: error: the loops and calls from here ran 100 blocks without ending: stopped"
        );
    }

    #[test]
    fn a_loop_that_does_not_end_is_stopped_at_its_head() {
        let config = Config {
            dialect: DialectConfig {
                limits: RunLimits { iterations: 5, ..RunLimits::default() },
                ..Dialect::Lenient.into()
            },
            units: Units::Mm,
            ..Config::default()
        };
        let got = run_with("G21 G01 F10\no7 while [1]\nG01 X1\nG01 X0\no7 endwhile\nG01 Y1", &config, 4);
        assert_eq!(got.iter().filter(|line| line.contains("X1.000")).count(), 5);
        assert_eq!(got[got.len() - 2], "2:1: error: o7 while ran 5 times without ending: stopped");
        assert_eq!(got[got.len() - 1], "G01 Y1.000");
        // A recursion is stopped too, and an error inside a call says where it ran.
        let got = flat("o8 sub\no8 call\no8 endsub\no8 call\nG01 X1 F10");
        assert_eq!(got[0], "3:1: error: calls nest more than 100 deep: a recursion that does not end?");
        let program = "o9 sub\nG01 X[1/#1] F10\no9 endsub\no9 call [0]";
        let config = Config { dialect: Dialect::Lenient.into(), units: Units::Mm, ..Config::default() };
        let library = crate::passes::Library::scanning(Default::default);
        let options = crate::passes::Options { config: &config, stage: 4, wizards: &mut crate::wizard::NoWizards };
        let diagnostic = crate::passes::translate(program.as_bytes(), library, options)
            .find_map(|event| match event {
                crate::passes::Event::Diagnostic(diagnostic) => Some(diagnostic),
                _ => None,
            })
            .unwrap();
        assert_eq!(diagnostic.to_string(), "2:8: error: division by zero");
        assert_eq!(diagnostic.call_chain(), ["in o9 called at line 4"]);
    }

    #[test]
    fn blocks_must_close_with_their_own_number() {
        assert_eq!(
            flat("o1 if [1]\nG01 X1 F10\no2 endif"),
            ["4:1: error: o2 endif has no block o2 to belong to", "2:1: error: o1 if is never closed"]
        );
        assert_eq!(flat("o1 while [1] [2]"), ["2:10: error: `while` takes one [condition]"]);
    }

    /// A Fanuc macro B program and its twin flattened by hand translate to
    /// the same moves (N numbers aside: they name different lines).
    fn same_as_twin(macro_b: &str, twin: &str) {
        let strip = |lines: Vec<String>| -> Vec<String> {
            lines
                .into_iter()
                .map(|line| line.split_once(' ').map_or(line.clone(), |(_, rest)| rest.to_string()))
                .collect()
        };
        let config = Config { dialect: Dialect::Lenient.into(), units: Units::Mm, ..Config::default() };
        let got = crate::passes::testing::run_with(macro_b, &config, 5);
        assert!(got.iter().all(|line| !line.contains("error")), "{got:?}");
        assert_eq!(
            strip(got),
            strip(crate::passes::testing::run_with(twin, &Config { units: Units::Mm, ..Config::default() }, 5))
        );
    }

    #[test]
    fn fanuc_while_loops_and_if_then_flatten_as_written_out() {
        // Three passes down in 1 mm steps, then a move made only if a flag is set.
        same_as_twin(
            "G21 G90\n#100 = 0\n#101 = 3\nWHILE [#100 LT #101] DO1\n#100 = #100 + 1\nG01 X10 Z-#100 F100\nG00 X0\nEND1\n\
             #102 = 1\nIF [#102 EQ 1] THEN #103 = 25\nIF [#102 EQ 0] THEN #103 = 50\nG00 Y#103\nM30",
            "G21 G90\nG01 X10 Z-1 F100\nG00 X0\nG01 X10 Z-2\nG00 X0\nG01 X10 Z-3\nG00 X0\nG00 Y25\nM30",
        );
        // Nested loops, DO1 around DO2.
        same_as_twin(
            "G21 G90 F50\n#1 = 0\nWHILE [#1 LT 2] DO1\n#2 = 0\nWHILE [#2 LT 2] DO2\nG01 X#2 Y#1\n#2 = #2 + 1\nEND2\n#1 = #1 + 1\nEND1\nM30",
            "G21 G90 F50\nG01 X0 Y0\nG01 X1 Y0\nG01 X0 Y1\nG01 X1 Y1\nM30",
        );
    }

    #[test]
    fn a_fanuc_alarm_is_an_error_at_its_line() {
        assert_eq!(
            flat("#3000 = 12 (TOOL TOO SHORT)\nG01 X1 F10"),
            ["2:1: error: the program raises alarm 12: TOOL TOO SHORT", "G01 X1.000 F10.000"]
        );
        assert_eq!(
            flat("WHILE [1] DO1\nEND2"),
            ["3:1: error: END2 has no block DO2 to belong to", "2:1: error: WHILE ... DO1 is never closed"]
        );
    }

    fn limited(iterations: u64, blocks: u64) -> Config {
        let limits = RunLimits { iterations, blocks };
        Config { dialect: DialectConfig { limits, ..Dialect::Lenient.into() }, units: Units::Mm, ..Config::default() }
    }

    #[test]
    fn fanuc_goto_jumps_forward_and_back() {
        // Forward: the lines between are passed over; `GOTO20` and `IF[...]GOTO` glued, as Fanuc reads them.
        same_as_twin(
            "G21 G90\n#1 = 1\nIF [#1 EQ 1] GOTO 20\nG01 X5 F10\nN20 G01 X1 F10\nGOTO30\nG01 Y9\nN30 IF[#1 EQ 2]GOTO20\nG00 Z5\nM30",
            "G21 G90\nG01 X1 F10\nG00 Z5\nM30",
        );
        // Back: a loop made of a label and a conditional jump, three passes.
        same_as_twin(
            "G21 G90\n#1 = 0\nN10 G01 X#1 F100\n#1 = #1 + 1\nIF [#1 LT 3] GOTO 10\nG00 Z5\nM30",
            "G21 G90\nG01 X0 F100\nG01 X1\nG01 X2\nG00 Z5\nM30",
        );
        // The target may be a parameter or an expression (rounded, as a Fanuc reads an address).
        same_as_twin(
            "G21 G90\n#5 = 40.2\nGOTO #5\nN30 G01 X3 F10\nGOTO [#5 + 9.8]\nN40 G01 X4 F10\nGOTO 30\nN50 M30",
            "G21 G90\nG01 X4 F10\nG01 X3\nM30",
        );
        // Nested GOTO loops: two rows of three, each pass of the inner loop counted afresh.
        same_as_twin(
            "G21 G90 F50\n#2 = 0\nN1 #1 = 0\nN2 G01 X#1 Y#2\n#1 = #1 + 1\nIF [#1 LT 3] GOTO 2\n#2 = #2 + 1\nIF [#2 LT 2] GOTO 1\nM30",
            "G21 G90 F50\nG01 X0 Y0\nG01 X1 Y0\nG01 X2 Y0\nG01 X0 Y1\nG01 X1 Y1\nG01 X2 Y1\nM30",
        );
    }

    #[test]
    fn fanuc_goto_leaves_loops_and_jumps_within_them() {
        // Out of a WHILE, forward: the loop stops at its third pass.
        same_as_twin(
            "G21 G90 F50\n#1 = 0\nWHILE [1] DO1\n#1 = #1 + 1\nIF [#1 GE 3] GOTO 99\nG01 X#1\nEND1\nG01 Y9\nN99 G00 Z5\nM30",
            "G21 G90 F50\nG01 X1\nG01 X2\nG00 Z5\nM30",
        );
        // Within the loop's body (forward), and out of it back to a line before it: the loop starts again.
        same_as_twin(
            "G21 G90 F50\n#2 = 0\nN5 #1 = 0\n#2 = #2 + 1\nWHILE [#1 LT 2] DO1\n#1 = #1 + 1\nIF [#1 EQ 1] GOTO 8\nG01 Y#2\nN8 G01 X#1\nIF [#2 LT 2] GOTO 5\nEND1\nM30",
            "G21 G90 F50\nG01 X1\nG01 X1\nG01 Y2\nG01 X2\nM30",
        );
        // Back within the body: the label is the loop's own line.
        same_as_twin(
            "G21 G90 F50\n#1 = 0\nWHILE [#1 LT 1] DO1\nN7 #1 = #1 + 1\nG01 X#1\nIF [#1 LT 3] GOTO 7\nEND1\nM30",
            "G21 G90 F50\nG01 X1\nG01 X2\nG01 X3\nM30",
        );
    }

    #[test]
    fn fanuc_goto_refuses_a_jump_into_a_loop_or_to_no_line() {
        // Into a loop, from before it (read on to it) and from after it (kept): an error, and the program ends.
        let got = flat("GOTO 5\nWHILE [1] DO1\nN5 G01 X1 F10\nEND1\nG01 Y1 F10");
        assert_eq!(got, ["2:1: error: GOTO 5 jumps into a loop or block, at line 4"]);
        let got = flat("#1 = 0\nWHILE [#1 LT 1] DO1\nN5 G01 X1 F10\n#1 = 1\nEND1\nGOTO 5\nG01 Y1 F10");
        assert_eq!(got, ["G01 X1.000 F10.000", "7:1: error: GOTO 5 jumps into a loop or block, at line 4"]);
        // From a loop into another one nested in it.
        let got = flat("WHILE [1] DO1\nGOTO 6\nWHILE [1] DO2\nN6 G01 X1 F10\nEND2\nEND1");
        assert_eq!(got, ["3:1: error: GOTO 6 jumps into WHILE ... DO2, at line 4"]);
        assert_eq!(
            flat("G01 X1 F10\nGOTO 7\nG01 Y1"),
            ["G01 X1.000 F10.000", "3:1: error: GOTO 7: the program has no line N7"]
        );
        assert_eq!(
            flat("GOTO 0\nG01 Y1 F10"),
            ["2:1: error: GOTO 0: a line's sequence number is 1 to 99999", "G01 Y1.000 F10.000"]
        );
        // A subroutine's GOTO stays in it.
        let got = flat("N1 G01 X1 F10\no9 sub\nGOTO 1\no9 endsub\no9 call\nG01 Y1");
        assert_eq!(got[1], "4:1: error: GOTO 1: o9 has no line N1");
    }

    #[test]
    fn a_goto_loop_that_does_not_end_is_stopped() {
        // Each jump back is an iteration: five passes run, the fifth jump is not taken.
        let got = run_with("G21 G01 F10\n#1 = 0\nN1 #1 = #1 + 1\nG01 X#1\nGOTO 1\nG01 Y1", &limited(5, 1000), 4);
        assert_eq!(got.iter().filter(|line| line.starts_with("G01 X")).count(), 5, "{got:?}");
        assert_eq!(got[got.len() - 2], "5:1: error: this GOTO jumped back 5 times without ending: stopped", "{got:?}");
        assert_eq!(got[got.len() - 1], "G01 Y1.000");
        // A jump to its own line, and loops that each end but together run too long: the blocks' budget.
        let got = run_with("G21 G01 F10\nN1 GOTO 1", &limited(1_000_000, 100), 4);
        assert_eq!(
            got,
            ["2:4: error: after this GOTO jumped back, the program ran 100 blocks without ending: stopped"]
        );
        let program = "G21 G01 F10\n#2 = 0\nN1 #1 = 0\nN2 #1 = #1 + 1\nIF [#1 LT 30] GOTO 2\n#2 = #2 + 1\nIF [#2 LT 30] GOTO 1\nG01 X1";
        let got = run_with(program, &limited(40, 100), 4);
        assert_eq!(
            got,
            ["5:15: error: after this GOTO jumped back, the program ran 100 blocks without ending: stopped"]
        );
        // An error while its lines run stops it once, and the program goes on after it.
        let got = flat("#1 = 0\nN1 #1 = #1 + 1\nG01 X[1/0] F10\nIF [#1 LT 1000] GOTO 1\nG01 Y1 F10");
        assert_eq!(got.len(), 3, "{got:?}");
        assert!(got[0].starts_with("4:") && got[0].contains("division by zero"), "{got:?}");
        assert_eq!(got[1], "5:17: error: this GOTO stopped at the error above: it does not jump back again");
        assert_eq!(got[2], "G01 Y1.000 F10.000");
    }

    #[test]
    fn g65_calls_a_program_with_its_arguments_in_locals() {
        // A macro after M30, called above it: X -> #24, Y -> #25, Z -> #26, R -> #18.
        same_as_twin(
            "G21 G90 F100\nG65 P9000 X10 Y20 Z-1 R2\nG65 P9000 X30 Y5 Z-2 R2\nM30\nO9000 (DRILL)\nG00 X#24 Y#25 Z#18\nG01 Z#26\nG00 Z#18\nM99",
            "G21 G90 F100\nG00 X10 Y20 Z2\nG01 Z-1\nG00 Z2\nG00 X30 Y5 Z2\nG01 Z-2\nG00 Z2\nM30",
        );
        // Every letter of Fanuc's first form lands in its local; unset ones read 0.
        same_as_twin(
            "G21 G90 F100\nG65 P1 A1 B2 C3 I4 J5 K6 D7 E8 F9 H11 M13 Q17 R18 S19 T20 U21 V22 W23 X24 Y25 Z26\nM30\n\
             O1\n#30 = #1 + #2 * 10 + #3 * 100\nG01 X#30 Y[#4 + #5 + #6 + #7 + #8 + #9 + #11 + #13] Z[#17 + #18 + #19 + #20 + #21 + #22 + #23 + #10]\n\
             G01 X#24 Y#25 Z#26\nM99",
            "G21 G90 F100\nG01 X321 Y63 Z140\nG01 X24 Y25 Z26\nM30",
        );
        // The caller's locals come back after the call; common parameters are shared; L repeats
        // it with its arguments each time.
        same_as_twin(
            "G21 G90 F100\n#1 = 7\n#100 = 0\nG65 P2 A3 L2\nG01 X#1 Y#100\nM30\nO2\n#100 = #100 + #1\n#1 = 50\nG01 X#100\nM99",
            "G21 G90 F100\nG01 X3\nG01 X6\nG01 X7 Y6\nM30",
        );
        // A macro with a loop and a jump of its own: a bolt circle of #11 holes on radius #18.
        same_as_twin(
            "G21 G90 F100\nG65 P8000 H4 R10 Z-1\nG00 Z5\nM30\nO8000\n#1 = 0\nWHILE [#1 LT #11] DO1\n\
             G00 X[#18 * COS[360 * #1 / #11]] Y[#18 * SIN[360 * #1 / #11]]\nIF [#1 EQ 2] GOTO 10\nG01 Z#26\nG00 Z1\nN10 #1 = #1 + 1\nEND1\nM99",
            "G21 G90 F100\nG00 X10 Y0\nG01 Z-1\nG00 Z1\nG00 X0 Y10\nG01 Z-1\nG00 Z1\nG00 X-10 Y0\n\
             G00 X0 Y-10\nG01 Z-1\nG00 Z1\nG00 Z5\nM30",
        );
    }

    #[test]
    fn m98_runs_its_program_with_the_parameters_of_the_moment() {
        // #100 is read when each call runs, not where the program is written; M98 shares
        // the caller's locals (#1), as on a Fanuc.
        same_as_twin(
            "G21 G90 F100\n#100 = 5\n#1 = 1\nM98 P1000\n#100 = 10\nM98 P1000 L2\nG01 Y#1\nM30\nO1000\nG01 X#100\n#100 = #100 + 1\n#1 = #1 + 1\nM99",
            "G21 G90 F100\nG01 X5\nG01 X10\nG01 X11\nG01 Y4\nM30",
        );
        // Other words of an M98 line run before the call; a program defined above its call.
        same_as_twin(
            "G21 G90 F100\nM98 P3 L0\nO3\nG01 Z#500\nM99\n#500 = -2\nG01 X1 M98 P3\nM30",
            "G21 G90 F100\nG01 X1\nG01 Z-2\nM30",
        );
    }

    #[test]
    fn fanuc_calls_refuse_what_they_cannot_run() {
        assert_eq!(
            flat("G65 A1\nG01 X1 F10"),
            ["2:1: error: G65 needs P, the number of the program it calls (a whole number)", "G01 X1.000 F10.000"]
        );
        assert_eq!(
            flat("G65 P77 A1\nG01 X1 F10"),
            ["2:1: error: G65 calls O77, which is not in the program", "G01 X1.000 F10.000"]
        );
        let got = flat("G65 P5 A1 A2\nM30\nO5\nG01 X#1 F10\nM99");
        assert_eq!(got[0], "2:11: error: A is given twice: ger reads Fanuc's first form of arguments only");
        let got = flat("G65 P5 G01\nM30\nO5\nG01 X#1 F10\nM99");
        assert_eq!(got[0], "2:8: error: G is not one of G65's arguments");
        // A program that calls itself without end is stopped.
        let got = flat("M98 P6\nM30\nO6\nM98 P6\nM99");
        assert_eq!(got[0], "5:1: error: calls nest more than 100 deep: a recursion that does not end?");
    }

    #[test]
    fn fanuc_pause_is_a_stop_with_its_message() {
        same_as_twin(
            "G21 G90\n#3006 = 1 (TURN THE PART)\nG01 X1 F10\nM30",
            "G21 G90\nM00 (TURN THE PART)\nG01 X1 F10\nM30",
        );
    }

    #[test]
    fn the_coordinate_systems_are_read_in_the_machines_unit() {
        // A mm machine: G55 set to X-3 (mm) reads -3 in a G20 program too, so X#5241 moves to -3 in
        // (-76.2 mm) from G55's origin at -3 mm: -79.2 mm. G30's point after G30.1 at G55's X12 is
        // in machine coordinates, 12 - 3 = 9. G92's X: the tool at X5 (G54 zero) reading 1 gives an offset of 4 mm,
        // in force (#5210 = 1) until G92.1 clears both.
        assert_eq!(
            flat("G10 L2 P2 X-3\nG55\nG20\nG00 X#5241\nG21\nG00 X12\nG30.1\nG00 Y#5181\nG54\nG00 X5\nG92 X1\nG00 Y[#5211 + #5210]\nG92.1\nG00 Y[#5211 + #5210]"),
            [
                "G00 X-79.200",
                "G00 X9.000",
                "G00 Y9.000",
                "G00 X5.000",
                "G00 Y5.000",
                "G00 Y0.000",
            ]
        );
        // A system's R (#5230 for G54), and the axes ger does not have (A: #5224) reading 0: the move
        // to (30, 0) in G54 turned by 30 degrees ends at (30 cos 30, 30 sin 30).
        assert_eq!(flat("G10 L2 P1 R30\nG00 X#5230 Y#5224"), ["G00 X25.981 Y15.000"]);
        assert_eq!(flat("#5241 = 2"), ["2:1: error: #5241 reads the machine's state: it is read, not set"]);
        // Between two systems' parameters, #5231-#5240 are nobody's.
        assert!(flat("G00 X#5231")[0].contains("error: #5231 is one of LinuxCNC's system parameters"));
    }

    #[test]
    fn the_current_position_is_read_from_the_passes() {
        // By hand: after the rapid the tool is at (5, 7, 2) in G54 (zero here); after G92 X0 Y0 at (6, 14)
        // it reads (0, 0); in G20 the 8 mm of X read 0.315 in, twice that is 16 mm (the output is in mm).
        assert_eq!(
            flat("G90 G00 X5 Y7 Z2\nG01 X[#5420 + 1] Y[#<_y> * 2] Z[#5422 - 3] F100\nG92 X0 Y0\nG01 X[#<_x> + 2] Y#5421\nG92.1\nG20\nG01 X[#5420 * 2]"),
            [
                "G00 X5.000 Y7.000 Z2.000",
                "G01 X6.000 Y14.000 Z-1.000 F100.000",
                "G01 X8.000 Y14.000",
                "G01 X16.000",
            ]
        );
        assert_eq!(
            flat("#<_x> = 1"),
            ["2:1: error: #<_x> is one of LinuxCNC's predefined parameters: it is read, not set"]
        );
        // #5220: the coordinate system in force, G54 being 1 and G59.3 9.
        assert_eq!(
            flat("G01 X#5220 F10\nG56\nG01 X#5220\nG59.3\nG01 X#5220"),
            ["G01 X1.000 F10.000", "G01 X3.000", "G01 X9.000"]
        );
    }

    #[test]
    fn linuxcnc_predefined_parameters_read_the_modes_the_passes_keep() {
        // As rs274 reads them (LinuxCNC 2.9): F, S (kept when the spindle
        // stops), the spindle, units, distance mode, plane, coordinate system.
        let program = "G90 G55 G18 F123 M3 S4000\nG01 X#<_feed> Y#<_rpm> Z#<_spindle_on>\n\
                       G01 X#<_spindle_cw> Y#<_metric> Z#<_imperial>\nG01 X#<_absolute> Y#<_incremental> Z#<_plane>\n\
                       G01 X#<_coord_system> Y[#<_a> + #<_w>]\nM4\nG01 X#<_spindle_cw>\nM5\nG01 X#<_spindle_on> Y#<_rpm>";
        let moves: Vec<String> = flat(program).into_iter().filter(|line| line.starts_with("G01")).collect();
        assert_eq!(
            moves,
            [
                "G01 X123.000 Y4000.000 Z1.000 F123.000",
                "G01 X1.000 Y1.000 Z0.000",
                "G01 X1.000 Y0.000 Z180.000",
                "G01 X550.000 Y0.000",
                "G01 X0.000",
                "G01 X0.000 Y4000.000"
            ]
        );
    }

    #[test]
    fn fanuc_m98_packs_its_repeats_into_p_without_l() {
        // P30010: O0010 three times, when there is no O30010; with O30010 in the program it is that.
        same_as_twin(
            "G21 G90 F100\nM98 P30010\nM30\nO10\nG91 G01 X1\nG90\nM99",
            "G21 G90 F100\nG91 G01 X1\nG90\nG91 X1\nG90\nG91 X1\nG90\nM30",
        );
        same_as_twin(
            "G21 G90 F100\nM98 P30010\nM30\nO10\nG01 X1\nM99\nO30010\nG01 Y2\nM99",
            "G21 G90 F100\nG01 Y2\nM30",
        );
    }

    #[test]
    fn fanuc_loop_numbers_may_follow_a_space() {
        // A Fanuc reads past spaces: `DO 1` and `END 1` are DO1 and END1.
        same_as_twin(
            "G21 G90 F50\n#1 = 0\nWHILE [#1 LT 2] DO 1\n#1 = #1 + 1\nG01 X#1\nEND 1\nM30",
            "G21 G90 F50\nG01 X1\nX2\nM30",
        );
    }

    #[test]
    fn a_file_whose_first_program_returns_ends_at_its_m99_as_linuxcnc_runs_it() {
        // As rs274 runs it: the first program is the main one, and its M99
        // ends the run; the programs after it (the main one a Fanuc operator
        // would select among them) are not run.
        let program = "%\nO1000 (SQUARE)\nG21 G91 G01 X10 F100\nY10\nG90\nM99\n%\n%\nO2000\nG00 Z5\nM99\n%\n\
                       %\nO0001 (MAIN)\nG21 G90\nG00 X0 Y0\nM98 P1000 L2\nM98 P2000\nG00 X50\nM30\n%";
        let config = Config { dialect: Dialect::Lenient.into(), units: Units::Mm, ..Config::default() };
        let got = run_with(program, &config, 4);
        let warning = "14:1: warning: O1 is a program of its own after the main program's M99 (line 6): LinuxCNC \
                       never runs it, and neither does ger";
        let moves =
            ["G01 X10.000 F100.000", "G01 Y10.000", "M30", "6:1: warning: M99 in the main program ends it here"];
        assert_eq!(got[..4], moves, "{got:?}");
        assert!(got.contains(&warning.to_string()), "{got:?}");
        assert!(!got.iter().any(|line| line.contains("error")), "{got:?}");
        // Its calls still find the programs after it, as LinuxCNC's do
        // (LinuxCNC's test m98m99/12-M99-endless-main-program).
        let got = run_with("O1\nG21 G01 X1 F40\nM98 P100\nG01 X5\nM99\nO100\nG01 Y-4\nM99", &config, 4);
        assert_eq!(got[..4], ["G01 X1.000 F40.000", "G01 Y-4.000", "G01 X5.000", "M30"], "{got:?}");
        // A first program that ends the run is the main one: what follows is defined, run where called.
        same_as_twin("O0001\nG21 G90 F100\nM98 P1000\nM30\nO1000\nG01 X5\nM99", "G21 G90 F100\nG01 X5\nM30");
    }

    #[test]
    fn fadal_subroutines_open_the_program_and_run_at_their_l_words() {
        // As a Fadal reads them: L0100 ... M17 defines subroutine 1, the M30
        // after the definitions ends their section, and L0102 runs it twice.
        same_as_twin(
            "O2 (PLATE)\nL100\nG91 X1.\nG90 M17\nL200\nY5.\nM17\nM30\nG21 G90 F100\nG01 X1 Y1\nL102\nL201\nM30",
            "O2 (PLATE)\nG21 G90 F100\nG01 X1 Y1\nG91 X1\nG90\nG91 X1\nG90\nY5\nM30",
        );
        let got = flat("G01 X1 F10\nL0301\nG01 Y1");
        assert_eq!(got[1], "3:1: error: L0301 calls Fadal subroutine 3, which is not defined", "{got:?}");
    }

    #[test]
    fn what_goes_with_m99_runs_before_the_return() {
        // `G90 M99`: the G90 is in force after the call, as a Fanuc runs it.
        same_as_twin(
            "G21 G90 F100\nM98 P100 L2\nX5\nM30\nO100\nG91 G01 X1\nG90 M99",
            "G21 G90 F100\nG91 G01 X1\nG90\nG91 X1\nG90\nX5\nM30",
        );
    }

    #[test]
    fn haas_m97_runs_the_lines_from_its_label_to_m99() {
        // The local subprograms after M30, each ending at its own M99, L times;
        // their lines do not run again after M30 (and are not warned of).
        same_as_twin(
            "G21 G90 F100\nG01 X1 Y1\nM97 P100 L2\nX2\nM97 P200\nG00 Z1\nM30\n\
             N100 G91 G01 X0.5\nY0.5\nG90 M99\nN200 G01 Y3\nM99",
            "G21 G90 F100\nG01 X1 Y1\nG91 G01 X0.5\nY0.5\nG90\nG91 X0.5\nY0.5\nG90\nX2\nY3\nG00 Z1\nM30",
        );
        // Called again, from a loop: read once, run each time.
        same_as_twin(
            "G21 G90 F100\n#1 = 0\nWHILE [#1 LT 2] DO1\nM97 P5\n#1 = #1 + 1\nEND1\nM30\nN5 G91 G01 X1\nG90 M99",
            "G21 G90 F100\nG91 G01 X1\nG90\nG91 X1\nG90\nM30",
        );
        let got = flat("G01 X1 F10\nM97 P7\nG01 Y1");
        assert_eq!(got[1], "3:1: error: M97 P7: the program has no line N7", "{got:?}");
    }

    #[test]
    fn fanuc_system_variables_read_the_modes_and_positions_the_passes_keep() {
        // Worked by hand: G90 saved in #1 and restored with G#1; #5001-#5003 are where the tool is
        // (6, 7, 2) after the incremental X1; #4120 the tool, #4119 the speed, #4006 the units
        // (21), #4002 the plane (18 after G18).
        same_as_twin(
            "G21 G90 F100\nG00 X5 Y7 Z2\n#1 = #4003\n#2 = #4006\nG91 G01 X1\nG#1 X[#5001 + 1] Y#5002 Z[#5003 * 2]\n\
             M06 T3\nM03 S1200\nG01 X[#4120] Y[#4119 / 100] Z#2 F[#4109 / 2]\nG18\nG01 X[#4002]\nM30",
            "G21 G90 F100\nG00 X5 Y7 Z2\nG91 G01 X1\nG90 X7 Y7 Z4\nM06 T3\nM03 S1200\nG01 X3 Y12 Z21 F50\nG18\nG01 X18\nM30",
        );
        // One ger does not keep is an error; one the program set is its own (a LinuxCNC parameter).
        assert_eq!(
            flat("#1 = #4001"),
            ["2:6: error: #4001 is Fanuc's modal information, which ger does not keep for it"]
        );
        assert_eq!(flat("#4001 = 7\nG01 X#4001 F1"), ["G01 X7.000 F1.000"]);
    }

    #[test]
    fn an_o_number_after_o_word_subroutines_is_the_programs_title() {
        // LinuxCNC's m98m99/11 and 12: `O1` after an O-word subroutine and a line setting a parameter
        // names the main program.
        same_as_twin(
            "o2 sub\nG00 Z3\no2 endsub\n#1 = 2\nO1 (MAIN)\nG21 G00 X1 Y#1\no2 call\nM30",
            "G21 G00 X1 Y2\nG00 Z3\nM30",
        );
    }

    #[test]
    fn fanuc_vacant_is_told_from_zero() {
        // Fanuc's #0: a G65 argument not given is vacant, one given as 0 is not; vacant reads 0
        // in arithmetic, `#1 = #0` empties #1, and a word whose value is #0 is not there.
        same_as_twin(
            "G21 G90 F100\nG65 P7 X0\nG65 P7 X5 Y1\nM30\nO7\nIF [#25 EQ #0] GOTO 1\nG01 Y#25\nN1 IF [#24 NE #0] GOTO 2\nG01 Z9\nN2 G01 X[#24 + #0] Z#0\n\
             #24 = #0\nIF [#24 EQ #0] THEN #100 = 3\nG01 Z#100\nM99",
            "G21 G90 F100\nG01 X0\nG01 Z3\nG01 Y1\nG01 X5\nG01 Z3\nM30",
        );
        assert_eq!(flat("#0 = 1"), ["2:1: error: #0 is Fanuc's vacant value: it is read, not set"]);
    }

    #[test]
    fn in_a_macro_a_word_whose_parameter_is_vacant_is_not_there() {
        // Fanuc: in O9 called with X and Z only, `G01 X#24 Y#25 Z#26 F#9` is `G01 X.. Z..` (Y, #25, and
        // F, #9, vacant); an expression reads vacant as 0, and an M98 program shares the macro's locals.
        // Outside a macro an unset parameter reads 0, as in LinuxCNC.
        same_as_twin(
            "G21 G90 F100\nG65 P9 X4 Z-1\nG01 X#24 Y#25\nM30\nO9\nG01 X#24 Y#25 Z#26 F#9\nG01 Y[#25 + 2]\nM98 P8\nM99\n\
             O8\nG01 X#4 Z#26\nM99",
            "G21 G90 F100\nG01 X4 Z-1\nG01 Y2\nG01 Z-1\nG01 X0 Y0\nM30",
        );
    }
}
