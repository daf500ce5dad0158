//! Parser: tokens -> statements, following the manual's grouping rule.
//!
//! A new statement starts at every G or M code, `O` number and wizard name,
//! and at `;` and the end of a line; other words attach to the statement they
//! follow, so `G01 X1.0 G21 G01 Y250.0` is three statements. Parsing never
//! fails: a bad statement becomes a diagnostic and is dropped, and parsing
//! goes on with the next one.

mod block;

use std::collections::HashSet;
use std::sync::Arc;

use crate::diag::{Diagnostic, Origin, Span};
use crate::lex::{Lexed, Token, TokenKind};
use crate::statement::{
    Axes, Cycle, CycleCode, Dialect, Distance, FeedMode, Kind, Machine, Motion, MotionMode, Offset, Plane, Reference,
    Retract, Side, Spline, SplineCode, Statement, ToolTableFrom, Turns, Units, Value, WizardArg, MAX_NURBS_ORDER,
    MAX_TURNS,
};

// Statements are the hot path: boxing them would cost an allocation each.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum Event {
    Statement(Statement),
    Diagnostic(Diagnostic),
}

/// A statement's raw pieces before they are checked: its head and its words.
struct Group {
    head: Head,
    span: Span,
    words: Vec<(char, Value)>,
}

enum Head {
    /// Words with no code before them.
    Bare,
    Code {
        letter: char,
        value: Value,
    },
    Wizard {
        name: String,
        args: Vec<WizardArg>,
    },
}

pub struct Parser<L> {
    tokens: L,
    dialect: Dialect,
    group: Option<Group>,
    /// A G53 with no words: it applies to the move that follows on its line.
    pending_g53: Option<Span>,
    /// The lenient dialect's statements of the block being read.
    block: Vec<Group>,
    /// What the lenient dialect does with M codes it does not know.
    codes: CodeLists,
    /// The unknown M codes already warned about, so each is said once.
    warned: HashSet<u32>,
    /// The call of a subprogram the interpreter stage says the statements
    /// now run in (pass 00 tags those it runs itself).
    origin: Option<Arc<Origin>>,
    out: std::collections::VecDeque<Event>,
    done: bool,
}

/// `[dialect] pass_through` and `ignore` in ger.toml: M codes (numbers
/// times ten, as the parser numbers codes) the lenient dialect passes to the
/// output without a warning, or drops.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CodeLists {
    pub pass_through: Vec<u32>,
    pub ignore: Vec<u32>,
}

impl CodeLists {
    /// Reads a code as written in ger.toml (`"M62"`, `"m100"`); `None` if it
    /// is not an M code.
    pub fn code(text: &str) -> Option<u32> {
        let number = text.strip_prefix(['M', 'm'])?;
        number.parse::<f64>().ok().filter(|_| !number.starts_with(['+', '-'])).and_then(code_number)
    }
}

/// Parses the GER manual's dialect.
pub fn parse<L: Iterator<Item = Lexed>>(tokens: L) -> Parser<L> {
    parse_in(tokens, Dialect::Strict)
}

pub fn parse_in<L: Iterator<Item = Lexed>>(tokens: L, dialect: Dialect) -> Parser<L> {
    Parser {
        tokens,
        dialect,
        group: None,
        pending_g53: None,
        block: Vec::new(),
        codes: CodeLists::default(),
        warned: HashSet::new(),
        origin: None,
        out: Default::default(),
        done: false,
    }
}

impl<L> Parser<L> {
    /// What to do with M codes the lenient dialect does not know.
    pub fn with_code_lists(mut self, codes: CodeLists) -> Parser<L> {
        self.codes = codes;
        self
    }
}

impl<L: Iterator<Item = Lexed>> Iterator for Parser<L> {
    type Item = Event;

    fn next(&mut self) -> Option<Event> {
        loop {
            if let Some(event) = self.out.pop_front() {
                return Some(event);
            }
            if self.done {
                return None;
            }
            match self.tokens.next() {
                Some(Lexed::Token(token)) => self.token(token),
                Some(Lexed::Diagnostic(diagnostic)) => self.out.push_back(Event::Diagnostic(diagnostic)),
                Some(Lexed::Origin(origin)) => self.origin = origin,
                None => {
                    self.end_of_statement();
                    self.done = true;
                }
            }
        }
    }
}

impl<L> Parser<L> {
    fn token(&mut self, token: Token) {
        let span = token.span;
        match token.kind {
            TokenKind::End => self.end_of_statement(),
            TokenKind::Comment(_) => {}
            // With the block-delete switch off, as controllers start, the block runs.
            TokenKind::BlockDelete if self.dialect == Dialect::Lenient => {}
            TokenKind::BlockDelete => self.out.push_back(Event::Diagnostic(
                Diagnostic::error(span, "block delete (`/`) is not accepted")
                    .with_help("remove the `/`; with --lenient the block runs, as with the block-delete switch off"),
            )),
            TokenKind::Ident(name) => self.open(Head::Wizard { name, args: Vec::new() }, span),
            TokenKind::Number(n) => self.wizard_arg(WizardArg::Number(n), span),
            TokenKind::Str(s) => self.wizard_arg(WizardArg::Text(s), span),
            TokenKind::Word { letter, value } => {
                let value = Value { value, span };
                if matches!(letter, 'G' | 'M' | 'O') {
                    self.open(Head::Code { letter, value }, span);
                } else {
                    let group = self.group.get_or_insert(Group { head: Head::Bare, span, words: Vec::new() });
                    group.span = group.span.to(span);
                    group.words.push((letter, value));
                }
            }
        }
    }

    fn wizard_arg(&mut self, arg: WizardArg, span: Span) {
        // The lexer only makes argument tokens right after a wizard name.
        if let Some(Group { head: Head::Wizard { args, .. }, span: group_span, .. }) = &mut self.group {
            args.push(arg);
            *group_span = group_span.to(span);
        }
    }

    fn open(&mut self, head: Head, span: Span) {
        self.close();
        self.group = Some(Group { head, span, words: Vec::new() });
    }

    fn close(&mut self) {
        let Some(group) = self.group.take() else { return };
        if self.dialect == Dialect::Lenient {
            // The whole block is needed to know whose words are whose.
            self.block.push(group);
        } else {
            self.emit(group);
        }
    }

    /// The lenient dialect reads a whole block before making its statements:
    /// see [`block`].
    fn close_block(&mut self) {
        let block = std::mem::take(&mut self.block);
        if block.is_empty() {
            return;
        }
        let mut warnings = Vec::new();
        match block::arrange(block, &mut warnings) {
            Ok(groups) => groups.into_iter().for_each(|group| self.emit(group)),
            Err(diagnostic) => self.out.push_back(Event::Diagnostic(diagnostic)),
        }
        self.out.extend(warnings.into_iter().map(Event::Diagnostic));
    }

    fn emit(&mut self, mut group: Group) {
        // Most groups take all their words: nothing to split.
        if group.words.iter().all(|&(letter, _)| self.takes(&group.head, letter)) {
            if let Head::Code { value, .. } = &group.head {
                group.span = group.words.iter().fold(value.span, |span, (_, v)| span.to(v.span));
            }
            return self.emit_one(group);
        }
        for group in self.split(group) {
            self.emit_one(group);
        }
    }

    fn emit_one(&mut self, group: Group) {
        let result = classify(group, self.dialect).and_then(|statement| self.join_g53(statement));
        match result {
            Ok(Some(statement)) => {
                if let Some(mut statement) = self.unknown_m_code(statement) {
                    statement.origin.clone_from(&self.origin);
                    self.out.push_back(Event::Statement(statement));
                }
            }
            Ok(None) => {}
            Err(diagnostic) => self.out.push_back(Event::Diagnostic(diagnostic.with_origin(self.origin.clone()))),
        }
    }

    /// Whether a group's head takes a word for itself.
    fn takes(&self, head: &Head, letter: char) -> bool {
        match head {
            Head::Code { letter: code, value } => takes_word(*code, value.value, letter, self.dialect),
            Head::Bare => ARC_WORDS.contains(letter),
            Head::Wizard { .. } => true,
        }
    }

    /// An M code ger does not know goes to the output with a warning the
    /// first time, unless ger.toml lists it to pass silently or to drop.
    fn unknown_m_code(&mut self, statement: Statement) -> Option<Statement> {
        let Kind::PassThrough { code, .. } = statement.kind else { return Some(statement) };
        if self.codes.ignore.contains(&code) {
            return None;
        }
        if !self.codes.pass_through.contains(&code) && self.warned.insert(code) {
            let name = code_name('M', f64::from(code) / 10.0);
            let message = format!("{name} is not a code ger knows: it goes to the output as it is");
            let help = format!(
                "ger does not simulate or check what {name} does; list it in ger.toml's [dialect] pass_through to \
                 silence this, or in ignore to drop it"
            );
            self.out.push_back(Event::Diagnostic(Diagnostic::warning(statement.span, message).with_help(help)));
        }
        Some(statement)
    }

    /// At the end of a line (or `;`), a G53 still waiting for its move has none.
    fn end_of_statement(&mut self) {
        self.close();
        self.close_block();
        if let Some(span) = self.pending_g53.take() {
            let diagnostic = Diagnostic::warning(span, "G53 with no move after it on its line does nothing")
                .with_help("write the move on the same line, e.g. G53 G00 Z0");
            self.out.push_back(Event::Diagnostic(diagnostic));
        }
    }

    /// `G91 X20` is G91, then a move: words a code cannot take, but a move
    /// can, make a move of their own. In the lenient dialect, S and T words
    /// that their statement cannot take become statements of their own too.
    fn split(&self, mut group: Group) -> Vec<Group> {
        let mut groups = Vec::new();
        let mut move_words = Vec::new();
        let mut kept = Vec::new();
        for (letter, value) in std::mem::take(&mut group.words) {
            if self.takes(&group.head, letter) {
                kept.push((letter, value));
            } else if ARC_WORDS.contains(letter) && !matches!(group.head, Head::Bare) {
                move_words.push((letter, value));
            } else if self.dialect == Dialect::Lenient && matches!(letter, 'S' | 'T') {
                groups.push(Group { head: Head::Bare, span: value.span, words: vec![(letter, value)] });
            } else {
                kept.push((letter, value));
            }
        }
        if let Head::Code { value, .. } = &group.head {
            group.span = kept.iter().fold(value.span, |span, (_, v)| span.to(v.span));
        }
        let alone = std::mem::take(&mut groups);
        if !kept.is_empty() || !matches!(group.head, Head::Bare) {
            group.words = kept;
            groups.push(group);
        }
        if !move_words.is_empty() {
            let span = move_words[0].1.span.to(move_words[move_words.len() - 1].1.span);
            groups.push(Group { head: Head::Bare, span, words: move_words });
        }
        groups.extend(alone);
        groups
    }

    /// G53 on its own applies to the move after it on the same line.
    fn join_g53(&mut self, statement: Statement) -> Result<Option<Statement>, Diagnostic> {
        let Statement { kind, span, origin } = statement;
        match (kind, self.pending_g53.take()) {
            (Kind::MachineMove(motion), None) if !motion.moves() => {
                self.pending_g53 = Some(span);
                Ok(None)
            }
            (Kind::Motion(motion), Some(g53)) if g53.line == span.line => {
                Ok(Some(Statement { kind: Kind::MachineMove(motion), span: g53.to(span), origin }))
            }
            // Other codes may stand between G53 and its move (`G53 G49 Z0`).
            (kind, Some(g53)) => {
                self.pending_g53 = Some(g53);
                Ok(Some(Statement { kind, span, origin }))
            }
            (kind, None) => Ok(Some(Statement { kind, span, origin })),
        }
    }
}

/// Which words each kind of statement takes.
const MOTION_WORDS: &str = "XYZF";
const ARC_WORDS: &str = "XYZIJKRF";
/// With LinuxCNC's turns (P) and Haas's repeats (L).
const LENIENT_ARC_WORDS: &str = "XYZIJKRFPL";

/// The words each code takes, by its number times ten (G61.1 is 611); `None`
/// for a code the dialect does not know.
fn words_of(letter: char, number: u32, dialect: Dialect) -> Option<&'static str> {
    if dialect == Dialect::Lenient && letter == 'G' && (number == 20 || number == 30) {
        return Some(LENIENT_ARC_WORDS);
    }
    let strict = match (letter, number) {
        ('G', 0 | 10) => Some("XYZF"),
        ('G', 20 | 30) => Some(ARC_WORDS),
        ('G', 410 | 420) => Some("D"),
        ('G', 430 | 440) => Some("H"),
        ('G', 520 | 920) => Some("XYZ"),
        ('G', 150 | 160 | 170 | 180 | 190 | 200 | 210 | 400 | 490 | 540 | 550 | 560 | 570 | 580 | 590 | 900 | 910) => {
            Some("")
        }
        ('M', 30 | 40) => Some("S"),
        ('M', 60) => Some("T"),
        ('M', 980) => Some("PL"),
        ('M', n) if n.is_multiple_of(10) && (n == 300 || n == 990 || Machine::from_number(n / 10).is_some()) => {
            Some("")
        }
        ('O', _) => Some(""),
        _ => None,
    };
    if strict.is_some() || dialect == Dialect::Strict {
        return strict;
    }
    match (letter, number) {
        // P in seconds (LinuxCNC), or X in seconds (Fanuc, Haas).
        ('G', 40) => Some("PX"),
        ('G', 100) => Some("LPXYZR"),
        ('G', 280 | 300) => Some("XYZ"),
        ('G', 530) => Some("XYZF"),
        // G64 R is the planner's peak scale in newer LinuxCNC (its test
        // g64-r-planner expects it); the Debian 2.9 pre-release refuses it.
        ('G', 640) => Some("PQR"),
        ('G', 730 | 740 | 810 | 820 | 830 | 840 | 850 | 860 | 890) => Some("XYZRQPLKF"),
        // The splines take every word a move might, so that a wrong one is
        // refused by name rather than made a move of its own.
        ('G', 50) => Some("XYZIJKRPQF"),
        // Q (and R) too for Fanuc's G05.1 Q1 R5, a servo mode.
        ('G', 51) => Some("XYZIJKRFQ"),
        ('G', 52) => Some("XYZIJKRPQLF"),
        ('G', 53) => Some(""),
        // M19's angle, timeout and direction go with it when it is dropped.
        ('M', 190) => Some("RQP"),
        // G54.1 Pn (Fanuc) and G154 Pn (Haas): the extended work offsets.
        ('G', 541 | 1540) => Some("P"),
        // Modes ger has no use for, and the cancels of modes it refuses.
        ('G', 80 | 1030) => Some("P"),
        ('G', 1870) => Some("PE"),
        ('G', 501) => Some("XYZ"),
        ('G', 90 | 131 | 500 | 670 | 690 | 970) => Some(""),
        ('G', 281 | 301 | 591 | 592 | 593 | 610 | 611 | 800 | 901 | 911 | 921 | 922 | 923 | 930 | 940 | 950) => {
            Some("")
        }
        ('G', 980 | 990) | ('M', 20 | 310 | 330 | 470) => Some(""),
        // Units alone; with the words of LinuxCNC's and Fanuc's lathe cycles, refused as one.
        ('G', 700 | 710) => Some("PQDIKUWRF"),
        // M97 is run by the interpreter stage (macros), on the program's own
        // text; M198 calls a program ger cannot read: refused, with why.
        ('M', 970) => Some("PL"),
        ('M', 1980) => None,
        // An M code ger does not know passes through with the words I/O and
        // user codes take (M62 P1, M66 P0 L3 Q5, M68 E0 Q50, M100 P1 Q2).
        ('M', n) if n.is_multiple_of(10) => Some("PQEL"),
        _ => None,
    }
}

/// Whether the statement of code `letter value` keeps a `word`. A code ger
/// does not know keeps them all, so its error is about the code.
fn takes_word(letter: char, value: f64, word: char, dialect: Dialect) -> bool {
    code_number(value).and_then(|n| words_of(letter, n, dialect)).is_none_or(|words| words.contains(word))
}

fn classify(group: Group, dialect: Dialect) -> Result<Statement, Diagnostic> {
    let span = group.span;
    let words = Words::new(group.words)?;
    let kind = match group.head {
        Head::Wizard { name, args } => Kind::Wizard { name, args },
        Head::Bare if dialect == Dialect::Lenient && words.list.iter().all(|(l, _)| block::ROTARY.contains(*l)) => {
            Kind::Rotary(Box::new([words.get('A'), words.get('B'), words.get('C')]))
        }
        Head::Bare => {
            // The lenient dialect's Q is a canned cycle's peck depth.
            let known = |l: char| KNOWN_LETTERS.contains(l) || (l == 'Q' && dialect == Dialect::Lenient);
            if let Some((letter, value)) = words.list.iter().find(|(l, _)| !known(*l)) {
                return Err(unknown_letter(*letter, value.span));
            }
            match words.list[0] {
                // A line of X Y P (or L) with a centre is nothing but a bad NURBS point.
                _ if dialect == Dialect::Lenient && words.has_any("PL") && words.has_any("IJK") => {
                    Kind::Spline(Box::new(spline(None, span, &words)?))
                }
                // Either the next point of a NURBS (G5.2) or, with new words,
                // the next hole of a canned cycle: whichever is in force.
                _ if dialect == Dialect::Lenient && words.has_any("PLQ") && words.has_any("XYZ") => Kind::NextPoint {
                    point: spline(None, span, &words).map(Box::new).map_err(Box::new),
                    hole: cycle(810, span, &words).map(Box::new).map_err(Box::new),
                },
                _ if words.has_any(ARC_WORDS) => {
                    words.only(ARC_WORDS, "a move")?;
                    Kind::Motion(Box::new(motion(None, &words, dialect)?))
                }
                // The lenient block reading leaves S, T, E and H alone in their statements.
                ('S', s) if dialect == Dialect::Lenient => Kind::SpindleSpeed(speed(s)?),
                ('T', _) if dialect == Dialect::Lenient => Kind::ToolSelect(words.whole('T')?.unwrap_or(0)),
                ('E', e) if dialect == Dialect::Lenient => fadal_fixture(e)?,
                ('H', _) if dialect == Dialect::Lenient => Kind::ToolLengthRegister(words.whole('H')?.unwrap_or(0)),
                _ => return Err(stray_word(&words)),
            }
        }
        Head::Code { letter, value } => code(letter, value, &words, dialect)?,
    };
    Ok(Statement::new(kind, span))
}

/// Fadal's E word: E1..E6 are the fixture offsets G54..G59, E0 machine zero.
fn fadal_fixture(e: Value) -> Result<Kind, Diagnostic> {
    let entry = match e.value {
        v if v.fract() == 0.0 && (1.0..=6.0).contains(&v) => v as u8,
        0.0 => return Ok(Kind::Offset { code: Offset::G52, axes: Box::default() }),
        _ => {
            return Err(Diagnostic::error(e.span, format!("E{} is not a fixture offset ger has", e.value))
                .with_help("Fadal's E1 to E6 are G54 to G59, and E0 is machine zero"))
        }
    };
    Ok(Kind::Offset { code: Offset::WorkOffset(entry), axes: Box::default() })
}

fn speed(s: Value) -> Result<f64, Diagnostic> {
    if s.value < 0.0 {
        return Err(Diagnostic::error(s.span, "spindle speed cannot be negative")
            .with_help("M03 turns clockwise, M04 counter-clockwise; S is the speed"));
    }
    Ok(s.value)
}

fn code(letter: char, value: Value, words: &Words, dialect: Dialect) -> Result<Kind, Diagnostic> {
    let span = value.span;
    let name = code_name(letter, value.value);
    let number = code_number(value.value)
        .ok_or_else(|| Diagnostic::error(span, format!("`{letter}{}` is not a code ger knows", value.value)))?;
    let no_words = |kind: Kind| -> Result<Kind, Diagnostic> {
        words.only("", &name)?;
        Ok(kind)
    };
    let kind = match (letter, number) {
        ('O', _) if number.is_multiple_of(10) => no_words(Kind::Program(number / 10))?,
        ('G', 0) | ('G', 10) => {
            let mode = if number == 0 { MotionMode::Rapid } else { MotionMode::Linear };
            words.only(MOTION_WORDS, &name)?;
            Kind::Motion(Box::new(motion(Some(mode), words, dialect)?))
        }
        ('G', 20) | ('G', 30) => {
            let mode = if number == 20 { MotionMode::ArcCw } else { MotionMode::ArcCcw };
            if let Some(word) = words.get('P').or(words.get('L')).filter(|_| dialect == Dialect::Strict) {
                let message = format!("{name} goes round once: P and L are not allowed with it");
                let help = "--lenient reads P (LinuxCNC's turns) and L (Haas's repeats) on an arc";
                return Err(Diagnostic::error(word.span, message).with_help(help));
            }
            words.only(if dialect == Dialect::Lenient { LENIENT_ARC_WORDS } else { ARC_WORDS }, &name)?;
            let mut arc = motion(Some(mode), words, dialect)?;
            arc.turns = turns(words, &name)?;
            Kind::Motion(Box::new(arc))
        }
        ('G', 150) => no_words(Kind::Polar(false))?,
        ('G', 160) => no_words(Kind::Polar(true))?,
        ('G', 170) => no_words(Kind::Plane(Plane::XY))?,
        ('G', 180) => no_words(Kind::Plane(Plane::ZX))?,
        ('G', 190) => no_words(Kind::Plane(Plane::YZ))?,
        ('G', 200) => no_words(Kind::Units(Units::Inch))?,
        ('G', 210) => no_words(Kind::Units(Units::Mm))?,
        ('G', 400) => no_words(Kind::CutterCompCancel)?,
        ('G', 410) | ('G', 420) => {
            words.only("D", &name)?;
            let side = if number == 410 { Side::Left } else { Side::Right };
            Kind::CutterComp { side, d: words.whole('D')?, diameter: None }
        }
        ('G', 411) | ('G', 421) if dialect == Dialect::Lenient => {
            // LinuxCNC's dynamic compensation: D is the cutter's diameter;
            // L, a lathe tool's orientation, means nothing to a mill.
            words.only("D", &name)?;
            let diameter = words.get('D').ok_or_else(|| {
                Diagnostic::error(span, format!("{name} needs D: the cutter's diameter")).with_help(format!(
                    "{name} D6 compensates for a cutter 6 across (G41/G42 D<tool> take it from the tool table)"
                ))
            })?;
            // A negative diameter puts the cutter on the other side, as LinuxCNC takes it.
            let left = (number == 411) != (diameter.value < 0.0);
            let side = if left { Side::Left } else { Side::Right };
            let diameter = Value { value: diameter.value.abs(), ..diameter };
            Kind::CutterComp { side, d: None, diameter: Some(diameter) }
        }
        ('G', 430) | ('G', 440) => {
            words.only("H", &name)?;
            // Without H, LinuxCNC uses the loaded tool's offset; so does the lenient dialect (pass 04).
            let h = words.whole('H')?;
            if h.is_none() && dialect == Dialect::Strict {
                return Err(Diagnostic::error(
                    span,
                    format!("{name} needs an H word: the tool length offset register"),
                )
                .with_help(format!("write e.g. {name} H1, or {name} Z1.0 H1 to move to Z1.0 with the offset")));
            }
            Kind::ToolLength { positive: number == 430, h }
        }
        ('G', 490) => no_words(Kind::ToolLengthCancel)?,
        ('G', 520) | ('G', 920) => {
            words.only("XYZ", &name)?;
            let code = if number == 520 { Offset::G52 } else { Offset::G92 };
            Kind::Offset { code, axes: Box::new(words.axes("XYZ")) }
        }
        ('G', 540..=590) if number.is_multiple_of(10) => {
            let entry = (number / 10 - 53) as u8;
            no_words(Kind::Offset { code: Offset::WorkOffset(entry), axes: Box::default() })?
        }
        ('G', 900) => no_words(Kind::Distance(Distance::Absolute))?,
        ('G', 910) => no_words(Kind::Distance(Distance::Incremental))?,
        ('M', 300) => no_words(Kind::End)?,
        ('M', 980) => {
            words.only("PL", &name)?;
            let program = words.whole('P')?.ok_or_else(|| {
                Diagnostic::error(span, "M98 needs a P word: the number of the program to call")
                    .with_help("write e.g. M98 P100 L2 to run O100 twice")
            })?;
            let repeat = words.whole('L')?.unwrap_or(1);
            Kind::Call { program, repeat }
        }
        ('M', 990) => no_words(Kind::Return)?,
        ('M', n) if n.is_multiple_of(10) && Machine::from_number(n / 10).is_some() => {
            let code = Machine::from_number(n / 10).expect("checked by the guard");
            match code {
                Machine::SpindleCw | Machine::SpindleCcw => {
                    words.only("S", &name)?;
                    let s = words.get('S').map(|s| s.value);
                    if let Some(s) = words.get('S').filter(|s| s.value < 0.0) {
                        return Err(Diagnostic::error(s.span, "spindle speed cannot be negative")
                            .with_help("M03 turns clockwise, M04 counter-clockwise; S is the speed"));
                    }
                    Kind::Machine { code, s, t: None }
                }
                Machine::ToolChange => {
                    words.only("T", &name)?;
                    Kind::Machine { code, s: None, t: words.whole('T')? }
                }
                _ => no_words(Kind::Machine { code, s: None, t: None })?,
            }
        }
        _ if dialect == Dialect::Lenient => lenient_code(letter, number, &name, span, words)?,
        _ => {
            let mut diagnostic = omitted_or_unknown(letter, number, &name, span);
            if words_of(letter, number, Dialect::Lenient).is_some() {
                let help = diagnostic.help.take().unwrap_or_default();
                diagnostic.help = Some(format!("{help}; or run with --lenient, which accepts {name}"));
            }
            return Err(diagnostic);
        }
    };
    Ok(kind)
}

/// The codes only the lenient dialect accepts.
fn lenient_code(letter: char, number: u32, name: &str, span: Span, words: &Words) -> Result<Kind, Diagnostic> {
    if let Some(allowed) = words_of(letter, number, Dialect::Lenient) {
        words.only(allowed, name)?;
    }
    let kind = match (letter, number) {
        ('M', 20) => Kind::End,
        ('M', 470) => Kind::Repeat,
        ('G', 40) => {
            let seconds = match (words.get('P'), words.get('X')) {
                (Some(p), None) | (None, Some(p)) => p,
                (Some(_), Some(x)) => {
                    return Err(Diagnostic::error(x.span, "G04 takes P or X (the dwell in seconds), not both"))
                }
                (None, None) => {
                    return Err(Diagnostic::error(span, "G04 needs a P word: the dwell in seconds")
                        .with_help("write e.g. G04 P0.5"))
                }
            };
            if seconds.value < 0.0 {
                return Err(Diagnostic::error(seconds.span, "a dwell cannot be negative"));
            }
            Kind::Dwell(seconds.value)
        }
        // Inch and millimetres as Siemens, Fagor, Heidenhain's ISO programs
        // and older controls write them. LinuxCNC's and Fanuc's G70/G71 are
        // lathe cycles, which always have words (P Q for the profile).
        ('G', 700 | 710) if words.list.is_empty() => Kind::Units(if number == 700 { Units::Inch } else { Units::Mm }),
        ('G', 700 | 710) => {
            let message =
                format!("{name} with words is a lathe's finishing or roughing cycle, which a mill does not run");
            return Err(Diagnostic::error(span, message).with_help(format!(
                "alone on a mill, {name} selects {}",
                if number == 700 { "inches (G20)" } else { "millimetres (G21)" }
            )));
        }
        ('G', 610) => Kind::NoEffect("G61"),
        ('G', 611) => Kind::NoEffect("G61.1"),
        ('G', 640) => Kind::NoEffect("G64"),
        // Exact stop for one block; spindle speed in rpm (what S always is here).
        ('G', 90) => Kind::NoEffect("G09"),
        ('G', 970) => Kind::NoEffect("G97"),
        // Fanuc's and Haas's look-ahead and smoothing settings.
        ('G', 80) => Kind::NoEffect("G08"),
        ('G', 1030) => Kind::NoEffect("G103"),
        ('G', 1870) => Kind::NoEffect("G187"),
        // The cancels of modes ger refuses to turn on: polar interpolation,
        // scaling, mirroring, modal macros, rotation.
        ('G', 131) => Kind::NoEffect("G13.1"),
        ('G', 500) => Kind::NoEffect("G50"),
        ('G', 501) => Kind::NoEffect("G50.1"),
        ('G', 670) => Kind::NoEffect("G67"),
        ('G', 690) => Kind::NoEffect("G69"),
        ('G', 901) => Kind::ArcCentres(Distance::Absolute),
        ('G', 911) => Kind::ArcCentres(Distance::Incremental),
        ('G', 930) => Kind::FeedMode(FeedMode::InverseTime),
        ('G', 940) => Kind::FeedMode(FeedMode::PerMinute),
        ('G', 950) => Kind::FeedMode(FeedMode::PerRevolution),
        ('G', 281) => Kind::SetReference(Reference::Home),
        ('G', 301) => Kind::SetReference(Reference::Second),
        ('G', 921) => Kind::Offset { code: Offset::G92Cancel { keep: false }, axes: Box::default() },
        ('G', 922) => Kind::Offset { code: Offset::G92Cancel { keep: true }, axes: Box::default() },
        ('G', 923) => Kind::Offset { code: Offset::G92Restore, axes: Box::default() },
        ('G', 591..=593) => Kind::Offset { code: Offset::WorkOffset((number - 591 + 7) as u8), axes: Box::default() },
        ('G', 541 | 1540) => {
            let entry = match words.whole('P')? {
                Some(p @ 1..=EXTENDED_OFFSETS) => p,
                _ => {
                    return Err(Diagnostic::error(
                        span,
                        format!("{name} needs P1 to P{EXTENDED_OFFSETS}: which extended work offset"),
                    )
                    .with_help(format!("write e.g. {name} P1")))
                }
            };
            Kind::Offset { code: Offset::WorkOffset(9 + entry as u8), axes: Box::default() }
        }
        ('M', 190) => Kind::NoEffect("M19"),
        ('M', 310) => Kind::NoEffect("M31"),
        ('M', 330) => Kind::NoEffect("M33"),
        ('G', 800) => Kind::CycleCancel,
        ('G', 980) => Kind::CycleRetract(Retract::Initial),
        ('G', 990) => Kind::CycleRetract(Retract::RPlane),
        ('G', 280) => Kind::Home { reference: Reference::Home, via: Box::new(words.axes("XYZ")) },
        ('G', 300) => Kind::Home { reference: Reference::Second, via: Box::new(words.axes("XYZ")) },
        ('G', 530) => Kind::MachineMove(Box::new(motion(None, words, Dialect::Lenient)?)),
        ('G', 100) => {
            let relative = match words.whole('L')? {
                Some(2) => false,
                Some(20) => true,
                Some(1) => return tool_table_entry(words, span),
                // LinuxCNC's L10 and L11 set an entry from where the tool is: they have axes.
                Some(l @ (10 | 11)) if words.has_any("XYZ") => {
                    let Kind::SetToolTable { tool, offsets, radius } = tool_table_entry(words, span)? else {
                        unreachable!("a tool table entry")
                    };
                    let from = ToolTableFrom { tool, target: *offsets, radius, fixture: l == 11, frame: None };
                    return Ok(Kind::SetToolTableFrom(Box::new(from)));
                }
                // Fanuc's L10-L13 (and LinuxCNC's with no axis) write an H or D register's value.
                Some(l @ 10..=13) => {
                    let tool = words.whole('P')?.map_or("a tool".to_string(), |p| format!("tool {p}"));
                    let message = format!(
                            "G10 L{l} writes {tool}'s offsets into the controller's tool table, which ger's output leaves to the controller (G43 H passes through), so ger cannot say where its later moves go"
                        );
                    return Err(Diagnostic::error(span, message)
                        .with_help("set the tool's length and radius on the controller, not in the program"));
                }
                _ => {
                    return Err(Diagnostic::error(span, "G10 sets work offsets with L2 or L20 only").with_help(
                        "G10 L2 P1 X.. Y.. Z.. sets G54's origin; G10 L20 P1 X.. makes the current position read X..",
                    ))
                }
            };
            let entry = match words.whole('P')? {
                Some(p) if p <= 9 => p as u8,
                _ => {
                    return Err(Diagnostic::error(span, "G10 needs P0 (the offset in force) to P9 (G59.3)")
                        .with_help("P1 is G54, P2 G55, ... P6 G59, P7 to P9 G59.1 to G59.3"))
                }
            };
            // R turns the coordinate system about its origin; LinuxCNC takes it with L2 only.
            let rotation = words.get('R');
            if let (Some(r), true) = (rotation, relative) {
                return Err(Diagnostic::error(r.span, "R is not allowed with G10 L20")
                    .with_help("turn the coordinate system with G10 L2 Pn R.., then set its origin with L20"));
            }
            Kind::SetWorkOffset { entry, axes: Box::new(words.axes("XYZ")), relative, rotation }
        }
        ('G', 730 | 740 | 810 | 820 | 830 | 840 | 850 | 860 | 890) => {
            Kind::Cycle(Box::new(cycle(number, span, words)?))
        }
        // Fanuc's high-speed machining (G05 P10000, G05 P0) and AI contour
        // control or smoothing (G05.1 Q1 R5, G05.1 Q0) share their numbers
        // with LinuxCNC's splines; with none of a curve's words they set how
        // the servos follow the path, not the path.
        ('G', 50) if !words.has_any("XYZIJKRQF") => Kind::NoEffect("G05"),
        ('G', 51) if words.get('Q').is_some() && !words.has_any("XYZIJKF") => Kind::NoEffect("G05.1"),
        ('G', 50) => Kind::Spline(Box::new(spline(Some(SplineCode::Cubic), span, words)?)),
        ('G', 51) => Kind::Spline(Box::new(spline(Some(SplineCode::Quadratic), span, words)?)),
        ('G', 52) => Kind::Spline(Box::new(spline(Some(SplineCode::Nurbs), span, words)?)),
        ('G', 53) => Kind::NurbsEnd,
        ('M', 970 | 1980) => return Err(lenient_refusal(letter, number, name, span)),
        ('M', n) if n.is_multiple_of(10) => {
            Kind::PassThrough { code: n, words: words.list.iter().map(|(l, v)| (*l, v.value)).collect() }
        }
        _ => return Err(lenient_refusal(letter, number, name, span)),
    };
    Ok(kind)
}

/// G10 L1 P<tool> [X Y Z] [R<radius>]: LinuxCNC's direct write of a tool's entry.
fn tool_table_entry(words: &Words, span: Span) -> Result<Kind, Diagnostic> {
    let tool = match words.whole('P')? {
        Some(tool) if tool >= 1 => tool,
        _ => {
            let span = words.get('P').map_or(span, |p| p.span);
            let l = words.whole('L')?.unwrap_or(1);
            return Err(Diagnostic::error(span, format!("G10 L{l} needs P, the tool whose entry it sets (1 or more)"))
                .with_help("G10 L1 P1 Z0 R3 sets tool 1's length offset to 0 and its radius to 3"));
        }
    };
    let radius = words.get('R');
    if let Some(r) = radius.filter(|r| r.value < 0.0) {
        return Err(Diagnostic::error(r.span, "a tool's radius cannot be negative"));
    }
    Ok(Kind::SetToolTable { tool, offsets: Box::new(words.axes("XYZ")), radius })
}

fn cycle(number: u32, span: Span, words: &Words) -> Result<Cycle, Diagnostic> {
    let code = match number {
        730 => CycleCode::ChipBreak,
        740 => CycleCode::TapLeft,
        840 => CycleCode::Tap,
        810 => CycleCode::Drill,
        820 => CycleCode::DrillDwell,
        830 => CycleCode::Peck,
        850 => CycleCode::Bore,
        860 => CycleCode::BoreSpindleStop,
        _ => CycleCode::BoreDwell,
    };
    // Z, R, Q and P carry over from the cycle before, but a cycle code needs
    // a position to drill at: as in LinuxCNC, none at all is an error, not a
    // second hole where the tool is.
    let target = words.axes("XYZ");
    if target.is_empty() {
        let name = code.code();
        return Err(Diagnostic::error(span, format!("{name} with no X, Y or Z: it has no hole to drill"))
            .with_help(format!("give the hole's position on the line, e.g. {name} X1 Y1 Z-0.5 R0.1")));
    }
    let repeat = match (words.whole('L')?, words.whole('K')?) {
        (Some(_), Some(_)) => {
            return Err(Diagnostic::error(span, "a cycle takes L or K (repeats), not both"));
        }
        (l, k) => l.or(k).unwrap_or(1),
    };
    let q = words.get('Q');
    if let Some(q) = q.filter(|q| q.value <= 0.0) {
        return Err(Diagnostic::error(q.span, "the peck depth Q must be greater than zero"));
    }
    if let Some(f) = words.get('F').filter(|f| f.value <= 0.0) {
        return Err(Diagnostic::error(f.span, "the feed rate must be greater than zero"));
    }
    Ok(Cycle { code, target, r: words.get('R'), q, p: words.get('P'), repeat, feed: words.get('F') })
}

/// G5, G5.1 and G5.2 with LinuxCNC's rules for their words; `None`: a line
/// of X Y P, the next control point if a NURBS (G5.2) is in force.
fn spline(code: Option<SplineCode>, span: Span, words: &Words) -> Result<Spline, Diagnostic> {
    let name = code.map_or("a NURBS control point", SplineCode::code);
    if let Some(z) = words.get('Z') {
        return Err(Diagnostic::error(z.span, "splines may not move in Z").with_help(
            "G05, G5.1 and G5.2 draw in the XY plane at the tool's Z: move Z with G01 before or after the curve",
        ));
    }
    let allowed = match code {
        Some(SplineCode::Cubic) => "XYIJPQF",
        Some(SplineCode::Quadratic) => "XYIJF",
        _ => "XYPLF",
    };
    // Q is a word of the lenient dialect's, not one that ger does not know.
    if let Some(q) = words.get('Q').filter(|_| !allowed.contains('Q')) {
        return Err(Diagnostic::error(q.span, format!("Q is not allowed with {name}"))
            .with_help("Q goes with G05: the Y of its second control point, from the end"));
    }
    words.only(allowed, name)?;
    if let Some(f) = words.get('F').filter(|f| f.value <= 0.0) {
        return Err(Diagnostic::error(f.span, "the feed rate must be greater than zero"));
    }
    let pair = |a: char, b: char| Axes { x: words.get(a), y: words.get(b), z: None };
    let mut spline = Spline {
        code,
        target: words.axes("XYZ"),
        first: Axes::default(),
        second: Axes::default(),
        weight: None,
        order: None,
        feed: words.get('F'),
    };
    // Of two words that go together, the one given when the other is not.
    let lone = |a: char, b: char| match (words.get(a), words.get(b)) {
        (Some(v), None) | (None, Some(v)) => Some(v),
        _ => None,
    };
    match code {
        Some(SplineCode::Cubic) => {
            if words.get('P').is_none() || words.get('Q').is_none() {
                return Err(Diagnostic::error(
                    span,
                    "G05 needs both P and Q: the second control point, relative to the end",
                )
                .with_help("write e.g. G05 I1 J0 P-1 Q0 X2 Y1; I and J may be left out after another G05"));
            }
            if let Some(v) = lone('I', 'J') {
                return Err(Diagnostic::error(v.span, "G05 takes both I and J, or neither").with_help(
                    "I and J place the first control point from the start; without them it mirrors the G05 before",
                ));
            }
            spline.first = pair('I', 'J');
            spline.second = pair('P', 'Q');
        }
        Some(SplineCode::Quadratic) => {
            if words.get('I').is_none() || words.get('J').is_none() {
                return Err(Diagnostic::error(
                    span,
                    "G5.1 needs both I and J: the control point, relative to the start",
                )
                .with_help("write e.g. G5.1 I1 J1 X2 Y0"));
            }
            spline.first = pair('I', 'J');
        }
        _ => {
            if let Some(v) = lone('X', 'Y') {
                return Err(Diagnostic::error(v.span, "a NURBS control point needs both X and Y")
                    .with_help("write e.g. X1 Y2 P1"));
            }
            let weight = words.get('P');
            if let Some(p) = weight.filter(|p| p.value <= 0.0) {
                return Err(Diagnostic::error(p.span, "a NURBS control point's weight (P) must be greater than zero"));
            }
            if weight.is_none() && !spline.target.is_empty() {
                return Err(Diagnostic::error(span, "a NURBS control point needs a weight P greater than zero")
                    .with_help("write e.g. X1 Y2 P1: P1 is a plain point, more pulls the curve towards it"));
            }
            if let (Some(order), Some(l)) = (words.whole('L')?, words.get('L')) {
                if !(3..=MAX_NURBS_ORDER).contains(&order) {
                    return Err(Diagnostic::error(
                        l.span,
                        format!("a NURBS's order (L) must be from 3 to {MAX_NURBS_ORDER}, not {order}"),
                    )
                    .with_help("L3, the default, is a quadratic curve, L4 a cubic; LinuxCNC reads an L below 3 as 3"));
                }
                spline.order = Some(order);
            }
            spline.weight = weight;
        }
    }
    Ok(spline)
}

/// What the lenient dialect still refuses, with why.
fn lenient_refusal(letter: char, number: u32, name: &str, span: Span) -> Diagnostic {
    let why = match (letter, number) {
        ('G', 760 | 870 | 880) => "this boring cycle differs too much between controllers",
        ('G', 930) => "inverse-time feed (G93) is not supported: feeds are per minute",
        ('G', 901) => "absolute arc centres (G90.1) are not supported: ger's I/J/K are relative to the start",
        ('G', 380..=389) | ('G', 310) => "probing needs a real machine",
        ('G', 650 | 660) => "Fanuc macro calls are not supported",
        ('G', 330 | 331) => "spindle-synchronised motion (threading, rigid tapping) needs the spindle's encoder",
        ('G', 680) => "coordinate rotation (G68) is not supported: rotate the program in the CAM system",
        ('G', 510) => "scaling (G51) is not supported",
        ('G', 511) => "mirror imaging (G51.1) is not supported",
        ('G', 960) => "constant surface speed (G96) is a lathe's mode: give the spindle speed in rpm",
        ('G', 120 | 130) => "circular pocket cycles differ between controllers: write the moves, or use a wizard",
        ('G', 431 | 432) => "dynamic tool length offsets are not supported: use G43 H with the tool table",
        ('M', 970) => "M97 runs lines of the program's own text by their N number, which a wizard's output has none of",
        ('M', 1980) => "M198 calls a program from the controller's memory card, which ger cannot read",
        _ => return omitted_or_unknown(letter, number, name, span),
    };
    Diagnostic::error(span, format!("{name} is not accepted: {why}"))
}

/// An arc's P (LinuxCNC's turns) or L (Haas's and Fadal's repeats).
fn turns(words: &Words, name: &str) -> Result<Option<Turns>, Diagnostic> {
    let (p, l) = (words.get('P'), words.get('L'));
    if let (Some(_), Some(l)) = (p, l) {
        return Err(Diagnostic::error(
            l.span,
            format!("{name} takes P (turns, LinuxCNC) or L (repeats, Haas), not both"),
        ));
    }
    let Some(word) = p.or(l) else { return Ok(None) };
    let letter = if p.is_some() { 'P' } else { 'L' };
    let times = words.whole(letter)?.filter(|n| (1..=MAX_TURNS).contains(n)).ok_or_else(|| {
        Diagnostic::error(word.span, format!("{letter} on {name} is the times it goes round: 1 to {MAX_TURNS}"))
    })?;
    Ok(Some(if p.is_some() { Turns::Around(times) } else { Turns::Repeated(times) }))
}

fn motion(mode: Option<MotionMode>, words: &Words, dialect: Dialect) -> Result<Motion, Diagnostic> {
    let motion = Motion {
        mode,
        target: words.axes("XYZ"),
        centre: words.axes("IJK"),
        radius: words.get('R'),
        feed: words.get('F'),
        turns: None,
    };
    if let (Some(r), false) = (motion.radius, motion.centre.is_empty()) {
        return Err(Diagnostic::error(r.span, "an arc takes either R or I/J/K, not both")
            .with_help("keep I/J/K (the centre, relative to the start) or R (the radius)"));
    }
    // LinuxCNC takes F0 as a feed, and refuses a feed move made at it.
    let least = if dialect == Dialect::Lenient { 0.0 } else { f64::MIN_POSITIVE };
    if let Some(f) = motion.feed.filter(|f| f.value < least) {
        return Err(Diagnostic::error(f.span, "the feed rate must be greater than zero"));
    }
    // LinuxCNC reads F on a rapid as the feed for later moves; so does the lenient dialect.
    if mode == Some(MotionMode::Rapid) && dialect == Dialect::Strict {
        if let Some(f) = motion.feed {
            return Err(Diagnostic::error(f.span, "F is not allowed on a G00 (rapid) move")
                .with_help("rapids run at the machine's rapid rate; put F on the next G01/G02/G03"));
        }
    }
    Ok(motion)
}

fn omitted_or_unknown(letter: char, number: u32, name: &str, span: Span) -> Diagnostic {
    let omitted = |why: &str, help: &str| {
        Diagnostic::error(span, format!("{name} is not accepted: {why}")).with_help(help.to_string())
    };
    match (letter, number) {
        ('M', 20) => omitted(
            "on old machines it stopped without rewinding the tape; ger's programs end with M30",
            "write M30 to end the program",
        ),
        ('M', 470) => omitted(
            "its meaning varies between controllers (repeat program, or engraving)",
            "to repeat, put the code in a subprogram and call it with M98 P<program> L<times>",
        ),
        ('G', 280) => omitted(
            "ger's machine zero is where the tool starts, (0, 0, 0), so no homing move is needed",
            "move there with an ordinary move, e.g. G00 Z0 then G00 X0 Y0 (after G52 X0 Y0 Z0 if offsets are set)",
        ),
        ('G', 730 | 800..=890) if number.is_multiple_of(10) => omitted(
            "ger has no canned cycles; controllers disagree too much on them",
            "write the cycle out with G00/G01 moves, or call a wizard that generates them",
        ),
        _ => {
            let text = format!("{name} is not a code ger knows");
            let help = match letter {
                'G' | 'M' => "the codes ger accepts are listed in the README's table of codes",
                _ => "an O word names a program and must be a whole number, e.g. O100",
            };
            Diagnostic::error(span, text).with_help(help)
        }
    }
}

fn stray_word(words: &Words) -> Diagnostic {
    let (letter, value) = words.list[0];
    let (message, help) = match letter {
        'S' => ("an S word (spindle speed) goes with M03 or M04", "write e.g. M03 S1000, or run with --lenient"),
        'T' => ("a T word (tool number) goes with M06", "write e.g. M06 T2, or run with --lenient"),
        'L' if words.list.len() == 1 => (
            "an L word alone goes with no code",
            "write e.g. M98 P100 L2; --lenient reads Fadal's L0100 ... M17 subroutines and their L0102 calls",
        ),
        'P' | 'L' => ("P and L words go with M98", "write e.g. M98 P100 L2"),
        'H' => ("an H word goes with G43 or G44", "write e.g. G43 H1, or run with --lenient"),
        'E' => ("an E word is Fadal's fixture offset", "write G54 to G59 instead, or run with --lenient"),
        'D' => ("a D word goes with G41 or G42", "write e.g. G41 D1"),
        _ => return unknown_letter(letter, value.span),
    };
    Diagnostic::error(value.span, message).with_help(help)
}

fn unknown_letter(letter: char, span: Span) -> Diagnostic {
    let why = match letter {
        'A' | 'B' | 'C' => "rotary axes are not part of a 3-axis machine",
        'U' | 'V' | 'W' => "secondary linear axes are not part of a 3-axis machine",
        'Q' => "Q belongs to canned cycles, which only the lenient dialect has",
        _ => "it is not a word ger knows",
    };
    Diagnostic::error(span, format!("`{letter}` word is not accepted: {why}"))
}

/// `G01` for G1, `G61.1` for G61.1: how a code is named in messages.
fn code_name(letter: char, value: f64) -> String {
    if value.fract() == 0.0 && (0.0..100.0).contains(&value) {
        format!("{letter}{:02}", value as u32)
    } else {
        format!("{letter}{value}")
    }
}

/// A code's number times ten (G61.1 -> 611), if it has at most one decimal.
fn code_number(value: f64) -> Option<u32> {
    let tenths = value * 10.0;
    (value >= 0.0 && (tenths - tenths.round()).abs() < 1e-6 && tenths < 1e7).then(|| tenths.round() as u32)
}

const KNOWN_LETTERS: &str = "XYZIJKRFSTPLHDE";

/// How many extended work offsets G54.1 Pn and G154 Pn reach.
pub const EXTENDED_OFFSETS: u32 = 99;

/// The words of one statement, checked for repeats.
struct Words {
    list: Vec<(char, Value)>,
}

impl Words {
    fn new(list: Vec<(char, Value)>) -> Result<Words, Diagnostic> {
        for (i, (letter, value)) in list.iter().enumerate() {
            if list[..i].iter().any(|(other, _)| other == letter) {
                return Err(Diagnostic::error(value.span, format!("{letter} appears twice in one statement"))
                    .with_help("a statement takes each word once; start a new line for a second move"));
            }
        }
        Ok(Words { list })
    }

    fn get(&self, letter: char) -> Option<Value> {
        self.list.iter().find(|(l, _)| *l == letter).map(|(_, v)| *v)
    }

    fn has_any(&self, letters: &str) -> bool {
        self.list.iter().any(|(l, _)| letters.contains(*l))
    }

    /// Fails on the first word that `what` does not take.
    fn only(&self, letters: &str, what: &str) -> Result<(), Diagnostic> {
        match self.list.iter().find(|(l, _)| !letters.contains(*l)) {
            None => Ok(()),
            Some((letter, value)) if !KNOWN_LETTERS.contains(*letter) => Err(unknown_letter(*letter, value.span)),
            Some((letter, value)) => {
                let takes = if letters.is_empty() {
                    "no words".to_string()
                } else {
                    letters.chars().map(String::from).collect::<Vec<_>>().join(", ")
                };
                Err(Diagnostic::error(value.span, format!("{letter} is not allowed with {what}"))
                    .with_help(format!("{what} takes {takes}")))
            }
        }
    }

    fn axes(&self, letters: &str) -> Axes {
        let mut letters = letters.chars();
        let mut next = || self.get(letters.next().expect("three letters"));
        Axes { x: next(), y: next(), z: next() }
    }

    /// A word that must be a whole number (H, D, T, P, L).
    fn whole(&self, letter: char) -> Result<Option<u32>, Diagnostic> {
        match self.get(letter) {
            None => Ok(None),
            Some(v) if v.value.fract() == 0.0 && (0.0..1e9).contains(&v.value) => Ok(Some(v.value as u32)),
            Some(v) => Err(Diagnostic::error(v.span, format!("{letter} must be a whole number, not {}", v.value))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lex::lex_str;

    fn parsed(text: &str) -> Vec<String> {
        parse(lex_str(text))
            .map(|event| match event {
                Event::Statement(s) => format!("{}:{} {:?}", s.span.line, s.span.col, s.kind),
                Event::Diagnostic(d) => d.to_string(),
            })
            .collect()
    }

    #[test]
    fn a_new_statement_starts_at_every_code() {
        let got = parsed("G01 X1.0 G21 G01 Y250.0");
        assert_eq!(got.len(), 3);
        assert!(got[0].starts_with("1:1 Motion(Motion { mode: Some(Linear), target: Axes { x: Some(Value { value: 1.0"));
        assert_eq!(got[1], "1:10 Units(Mm)");
        assert!(got[2].starts_with(
            "1:14 Motion(Motion { mode: Some(Linear), target: Axes { x: None, y: Some(Value { value: 250.0"
        ));
    }

    #[test]
    fn semicolons_split_a_line_into_moves() {
        let got = parsed("G01 X1.0; Y2.0");
        assert_eq!(got.len(), 2);
        assert!(got[1].starts_with("1:11 Motion(Motion { mode: None"));
    }

    #[test]
    fn move_words_after_a_code_that_takes_none_are_a_move() {
        let got = parsed("G91 X20 F5\nG54 X0 Y0\nM08 Z1");
        assert_eq!(got.len(), 6);
        assert_eq!(got[0], "1:1 Distance(Incremental)");
        assert!(got[1].starts_with("1:5 Motion(Motion { mode: None, target: Axes { x: Some(Value { value: 20.0"));
        assert!(got[1].contains("feed: Some(Value { value: 5.0, span: Span { line: 1, col: 9, len: 2 } })"));
        assert_eq!(got[2], "2:1 Offset { code: WorkOffset(1), axes: Axes { x: None, y: None, z: None } }");
        assert!(got[3].starts_with("2:5 Motion"));
        assert!(got[5].starts_with("3:5 Motion"));
        // Codes that take axis words keep them; other words are still errors.
        assert!(parsed("G52 X1")[0].starts_with("1:1 Offset { code: G52"));
        assert_eq!(parsed("G17 P1"), ["1:5: error: P is not allowed with G17"]);
    }

    #[test]
    fn codes_take_their_words() {
        assert_eq!(parsed("M98 P100 L3"), ["1:1 Call { program: 100, repeat: 3 }"]);
        assert_eq!(parsed("M98 P7"), ["1:1 Call { program: 7, repeat: 1 }"]);
        assert_eq!(parsed("M06 T2"), ["1:1 Machine { code: ToolChange, s: None, t: Some(2) }"]);
        assert_eq!(parsed("G55"), ["1:1 Offset { code: WorkOffset(2), axes: Axes { x: None, y: None, z: None } }"]);
        assert_eq!(parsed("O0100"), ["1:1 Program(100)"]);
        assert_eq!(parsed("Pocket 1 \"a\""), ["1:1 Wizard { name: \"Pocket\", args: [Number(1.0), Text(\"a\")] }"]);
    }

    #[test]
    fn bad_statements_are_diagnosed_and_dropped() {
        assert_eq!(parsed("G00 X1 F10"), ["1:8: error: F is not allowed on a G00 (rapid) move"]);
        assert_eq!(parsed("G01 X1 X2"), ["1:8: error: X appears twice in one statement"]);
        assert_eq!(parsed("G02 X1 R1 I1"), ["1:8: error: an arc takes either R or I/J/K, not both"]);
        assert_eq!(
            parsed("G01 A3"),
            ["1:5: error: `A` word is not accepted: rotary axes are not part of a 3-axis machine"]
        );
        assert_eq!(parsed("S1000"), ["1:1: error: an S word (spindle speed) goes with M03 or M04"]);
        assert_eq!(parsed("G07"), ["1:1: error: G07 is not a code ger knows"]);
        // The code is judged before its words: a canned cycle is named as such.
        assert_eq!(
            parsed("G83 X1 Q0.1")[0],
            "1:1: error: G83 is not accepted: ger has no canned cycles; controllers disagree too much on them"
        );
        assert_eq!(
            parsed("X1 B2"),
            ["1:4: error: `B` word is not accepted: rotary axes are not part of a 3-axis machine"]
        );
        assert_eq!(parsed("M98 L2"), ["1:1: error: M98 needs a P word: the number of the program to call"]);
        assert_eq!(parsed("M06 T1.5"), ["1:5: error: T must be a whole number, not 1.5"]);
    }

    fn parsed_lenient(text: &str) -> Vec<String> {
        let lexer = crate::lex::Lexer::in_dialect(text.as_bytes(), Dialect::Lenient);
        parse_in(lexer, Dialect::Lenient)
            .map(|event| match event {
                Event::Statement(s) => format!("{}:{} {:?}", s.span.line, s.span.col, s.kind),
                Event::Diagnostic(d) => d.to_string(),
            })
            .collect()
    }

    #[test]
    fn a_negative_dynamic_diameter_compensates_on_the_other_side() {
        // LinuxCNC's rule (rs274: G41.1 D-2 moves as G42.1 D2); `tests/differential/lenient/dynamic_comp.ngc`.
        for (text, side) in [("G41.1 D-3", "Right"), ("G42.1 D-3", "Left"), ("G41.1 D3", "Left"), ("G42.1 D3", "Right")]
        {
            let expected = format!("1:1 CutterComp {{ side: {side}, d: None, diameter: Some(Value {{ value: 3.0,");
            let parsed = parsed_lenient(text);
            assert!(parsed.len() == 1 && parsed[0].starts_with(&expected), "{text}: {parsed:?}");
        }
    }

    #[test]
    fn lenient_m19_takes_its_orientation_words() {
        // LinuxCNC's M19 R<angle> Q<timeout> P<direction>: they go with M19,
        // not to a move of their own (which came out as `G00 R90`). The
        // block runs in LinuxCNC's order: speed, spindle, path control.
        assert_eq!(
            parsed_lenient("G64 M19 R90 Q2 P1 S0"),
            ["1:19 SpindleSpeed(0.0)", "1:5 NoEffect(\"M19\")", "1:1 NoEffect(\"G64\")"]
        );
        // G64 takes R too: LinuxCNC's test g64-r-planner expects `G64 P1 R0.5` to move nothing.
        assert_eq!(parsed_lenient("G64 P0.01 R1"), ["1:1 NoEffect(\"G64\")"]);
        // G61 takes no R: LinuxCNC's reject g64-r-on-g61.
        assert!(parsed_lenient("G61 R0.5")[1].starts_with("1:5 Motion(Motion { mode: None"));
    }

    #[test]
    fn g00_beside_g28_leaves_it_the_axes_and_is_the_mode_after_it() {
        // `G00 G91 G28 Z0`: G28 Z0 through no intermediate point in G91, then G00 in force.
        let got = parsed_lenient("G00 G91 G28 Z0");
        assert_eq!(got.len(), 3, "{got:?}");
        assert_eq!(got[0], "1:5 Distance(Incremental)");
        assert!(
            got[1].starts_with("1:9 Home { reference: Home, via: Axes { x: None, y: None, z: Some(Value { value: 0.0")
        );
        assert!(got[2].starts_with("1:1 Motion(Motion { mode: Some(Rapid), target: Axes { x: None, y: None, z: None }"));
        // An arc cannot give its axes away.
        assert!(parsed_lenient("G02 G28 Z0")[0].ends_with("G28 and G02 both use the axis words of their line"));
    }

    #[test]
    fn a_code_written_twice_in_a_block_is_read_once() {
        // A Fadal post's `G0 G90 G0 X0 Y0`: one rapid; two codes of one group still clash.
        let got = parsed_lenient("G0 G90 G0 X1 Y2");
        assert_eq!(got.len(), 2, "{got:?}");
        assert_eq!(got[0], "1:4 Distance(Absolute)");
        assert!(got[1].starts_with("1:1 Motion(Motion { mode: Some(Rapid), target: Axes { x: Some(Value { value: 1.0"));
        assert!(parsed_lenient("G0 G1 X1")[0].ends_with("G00 and G01 on one line: they are codes of the same group"));
    }

    #[test]
    fn a_word_alone_in_its_statement_is_still_once_a_block() {
        // rs274: "Multiple t words on one line". S, T, E and H each go to a
        // statement of their own, but a block still says each once.
        assert_eq!(parsed_lenient("T11 T12")[0], "1:5: error: T appears twice in one block");
        assert_eq!(parsed_lenient("G0 X1 S100 S200")[0], "1:12: error: S appears twice in one block");
        assert_eq!(parsed_lenient("T11 S100"), ["1:5 SpindleSpeed(100.0)", "1:1 ToolSelect(11)"]);
    }

    #[test]
    fn fanucs_g05_and_g05_1_servo_modes_are_not_splines() {
        // G05 P10000 / G05 P0 (high-speed machining) and G05.1 Q1 R5 / Q0
        // (AI contour control) with no word of a curve: modes of the servos.
        for program in ["G05 P10000", "G05 P0", "G05", "G05.1 Q1", "G05.1 Q1 R5", "G5.1 Q0"] {
            let got = parsed_lenient(program);
            assert_eq!(got.len(), 1, "{program}: {got:?}");
            assert!(got[0].starts_with("1:1 NoEffect(\"G05"), "{program}: {got:?}");
        }
        // With a curve's words they are still LinuxCNC's splines, and their errors.
        assert!(parsed_lenient("G5.1 X1 Y1 I1 J0")[0].starts_with("1:1 Spline("));
        assert!(parsed_lenient("G5.1 X1 Y1 Q1")[0].ends_with("Q is not allowed with G5.1"));
        assert!(parsed_lenient("G05 P1 X1 Y1")[0].contains("error"));
    }

    #[test]
    fn g10_l1_writes_a_tool_table_entry_and_the_others_are_refused_with_their_reason() {
        assert_eq!(
            parsed_lenient("G10 L1 P3 Z-1.5 R2"),
            ["1:1 SetToolTable { tool: 3, offsets: Axes { x: None, y: None, z: Some(Value { value: -1.5, span: Span { line: 1, col: 11, len: 5 } }) }, radius: Some(Value { value: 2.0, span: Span { line: 1, col: 17, len: 2 } }) }"]
        );
        assert_eq!(
            parsed_lenient("G10 L1 Z0 R1"),
            ["1:1: error: G10 L1 needs P, the tool whose entry it sets (1 or more)"]
        );
        assert_eq!(
            parsed_lenient("G10 L1 P0 R1"),
            ["1:8: error: G10 L1 needs P, the tool whose entry it sets (1 or more)"]
        );
        assert_eq!(parsed_lenient("G10 L1 P1 R-1"), ["1:11: error: a tool's radius cannot be negative"]);
        assert!(parsed_lenient("G10 L10 P2 Z0")[0].starts_with(
            "1:1 SetToolTableFrom(ToolTableFrom { tool: 2, target: Axes { x: None, y: None, z: Some(Value { value: 0.0"
        ));
        assert!(parsed_lenient("G10 L11 P2 X1")[0].contains("fixture: true"));
        assert_eq!(
            parsed_lenient("G10 L11 Z0"),
            ["1:1: error: G10 L11 needs P, the tool whose entry it sets (1 or more)"]
        );
        for (program, tool) in [("G10 L10 P2 R1", "tool 2"), ("G10 L12 P1 R1", "tool 1")] {
            let got = &parsed_lenient(program)[0];
            assert!(got.contains(&format!("writes {tool}'s offsets into the controller's tool table")), "{got}");
        }
        assert!(parsed_lenient("G10 L3 P1")[0].ends_with("G10 sets work offsets with L2 or L20 only"));
    }

    #[test]
    fn a_canned_cycle_needs_a_position() {
        // As in LinuxCNC ("All axes missing with motion code"); before, ger
        // drilled again where the tool was, with Z carried over.
        assert_eq!(parsed_lenient("G81 R0.2 F10"), ["1:1: error: G81 with no X, Y or Z: it has no hole to drill"]);
        assert!(parsed_lenient("G81 Z-1 R0.2 F10")[0].starts_with("1:1 Cycle"));
    }

    #[test]
    fn omitted_codes_say_what_to_write_instead() {
        for (code, help) in [("M02", "M30"), ("M47", "M98"), ("G28", "G00"), ("G81", "wizard"), ("G83", "wizard")] {
            let diagnostic = match parse(lex_str(code)).next() {
                Some(Event::Diagnostic(d)) => d,
                _ => panic!("{code} was accepted"),
            };
            assert!(diagnostic.message.starts_with(&format!("{code} is not accepted")), "{code}");
            assert!(diagnostic.help.unwrap().contains(help), "{code}");
        }
    }
}
