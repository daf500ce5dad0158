//! Lexer: program text -> tokens with spans.
//!
//! It reads one line at a time from any `BufRead`, so memory does not grow
//! with the program. Lexing never fails: bad text becomes a diagnostic and the
//! lexer carries on after it. Comments may span lines, so the only state kept
//! between lines is "inside a comment since line L".

use std::io::BufRead;
use std::sync::Arc;

use crate::diag::{Diagnostic, Origin, Span};
use crate::macros::control::{self, Control, Keyword};
use crate::macros::expr::{self, Expr, Param, Reader};
use crate::statement::Dialect;

#[derive(Clone, Debug, PartialEq)]
pub enum TokenKind {
    /// A letter and its number: `G01`, `X-1.25`, `x.5`. The letter is upper case.
    Word {
        letter: char,
        value: f64,
    },
    /// Two or more letters in a row: a wizard call's name (`Pocket`).
    Ident(String),
    /// A wizard call's numeric argument.
    Number(f64),
    /// A wizard call's "double-quoted" argument, without the quotes.
    Str(String),
    Comment(String),
    /// `;` or the end of a line (a line's end has no length).
    End,
    /// `/` at the start of a line: block delete.
    BlockDelete,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub kind: TokenKind,
    pub span: Span,
}

#[derive(Clone)]
pub enum Lexed {
    Token(Token),
    Diagnostic(Diagnostic),
    /// From the interpreter stage, never the lexer: the statements after it
    /// run in this call of a subprogram (the calls it is in its parents), or
    /// in none, until the next.
    Origin(Option<Arc<Origin>>),
}

/// What the lexer makes: a token or a diagnostic, or, in the lenient
/// dialect, a piece of macro programming for the interpreter stage
/// ([`crate::macros`]), which [`Lexer::pieces`] hands out. Iterating the
/// lexer itself passes over the macro pieces.
#[derive(Clone)]
pub enum Piece {
    Lexed(Lexed),
    Macro(Macro, Span),
}

#[derive(Clone, Debug, PartialEq)]
pub enum Macro {
    /// A word whose value is an expression: `X[#1 + 2]`, `F#<feed>`.
    Expression { letter: char, value: Expr },
    /// `#1 = expr`.
    Assign { target: Param, value: Expr },
    /// An O-word control line: `o100 while [#1 LT 3]`; or Fanuc's
    /// `WHILE [c] DO1` and `END1`.
    Control(Control),
    /// Fanuc's `IF [c] THEN`: the rest of the line runs only if c holds.
    Guard(Expr),
    /// Fanuc's `GOTO n`: the program goes on at the line labelled `Nn`.
    Goto(Expr),
    /// The `N` number that starts a line: where a `GOTO` may jump to.
    Label(f64),
    /// A wizard call's argument that is an expression or a parameter:
    /// `Pocket [#1 * 2] #<depth> 10`, evaluated before the call.
    Argument(Expr),
}

/// The text of every line a lexer has read, kept (lenient dialect) so that
/// a backward `GOTO` can read lines again: as much memory as the program's
/// text, never more.
#[derive(Default)]
pub struct History {
    text: Vec<u8>,
    /// Where each line starts in `text`: line n at `starts[n - 1]`.
    starts: Vec<usize>,
}

impl History {
    fn push(&mut self, line: &[u8]) {
        self.starts.push(self.text.len());
        self.text.extend_from_slice(line);
        self.text.push(b'\n');
    }

    /// How many lines have been read.
    pub fn lines(&self) -> u32 {
        self.starts.len() as u32
    }

    /// The lines read from line `from` on, to be lexed again.
    pub fn from_line(&self, from: u32) -> Vec<u8> {
        let start = self.starts.get(from.saturating_sub(1) as usize).copied().unwrap_or(self.text.len());
        self.text[start..].to_vec()
    }
}

pub type SharedHistory = std::rc::Rc<std::cell::RefCell<History>>;

/// Lexes a whole program held in memory; handy for tests and small inputs.
pub fn lex_str(text: &str) -> Lexer<&[u8]> {
    Lexer::new(text.as_bytes())
}

struct OpenComment {
    start: Span,
    body: String,
    /// Comments may not nest, but after saying so the lexer skips to the `)`
    /// that balances the first `(`, so one mistake gives one error.
    depth: u32,
    nested_reported: bool,
}

pub struct Lexer<R> {
    lines: Lines<R>,
    raw: Vec<u8>,
    line_no: u32,
    /// Tokens of the current line, handed out front to back.
    pending: std::collections::VecDeque<Piece>,
    /// Set while a comment is open across lines.
    open_comment: Option<OpenComment>,
    done: bool,
    lenient: bool,
    /// Whether a token other than a comment has been read: until then an
    /// `O<name>` line names the program (lenient dialect).
    read_code: bool,
    /// Where the lines read are kept, if they are.
    history: Option<SharedHistory>,
    /// A line not in UTF-8 has been read as Latin-1 (and said so, once).
    read_8_bit: bool,
    /// Whether the first line with anything on it was `%` (a tape, which
    /// ends at the next one); `None` before that line.
    tape: Option<bool>,
    /// Lines read past a tape's end to see what follows, to be lexed next.
    peeked: std::collections::VecDeque<Vec<u8>>,
}

/// How many blank, `%` and comment lines are looked past after a tape's end
/// for another program (and no more than [`MAX_LINE`] bytes of them).
const MAX_PEEKED: usize = 1000;

/// Whether a line (trimmed) starts a program of its own: `O8000`, or a
/// LinuxCNC subroutine `o100 sub`, maybe after an `N` number.
fn starts_a_program(line: &str) -> bool {
    let after_n = match line.strip_prefix(['N', 'n']) {
        Some(rest) => rest.trim_start_matches(|c: char| c.is_ascii_digit() || c == '.').trim_start(),
        None => line,
    };
    after_n.strip_prefix(['O', 'o']).is_some_and(|rest| rest.starts_with(|c: char| c.is_ascii_digit() || c == '<'))
}

/// The longest line read: 1 MiB, far beyond any real program's.
pub const MAX_LINE: usize = 1 << 20;

/// The largest number a word may have. Numbers this size keep every sum
/// and product the passes make finite (f64 reaches 10^308).
pub const MAX_NUMBER: f64 = 1e12;

/// A program's lines, as the lexer numbers them and diagnostics quote them:
/// a line ends at LF, CRLF or a lone CR (files saved on old Macs), as in a
/// text editor. A line longer than [`MAX_LINE`] is cut there, so one endless
/// line cannot take all memory.
pub struct Lines<R> {
    reader: R,
    /// The last line ended with CR: an LF right after it belongs to it.
    after_cr: bool,
}

impl<R: BufRead> Lines<R> {
    pub fn new(reader: R) -> Lines<R> {
        Lines { reader, after_cr: false }
    }

    /// Reads the next line, without its ending, into `line`: `None` at the
    /// end of the text, `Some(false)` when the line was cut at [`MAX_LINE`].
    pub fn read(&mut self, line: &mut Vec<u8>) -> std::io::Result<Option<bool>> {
        line.clear();
        let mut complete = true;
        let mut any = false;
        loop {
            let buffer = match self.reader.fill_buf() {
                Ok(buffer) => buffer,
                Err(err) if err.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(err) => return Err(err),
            };
            if buffer.is_empty() {
                break;
            }
            if std::mem::take(&mut self.after_cr) && buffer[0] == b'\n' {
                self.reader.consume(1);
                continue;
            }
            any = true;
            let end = buffer.iter().position(|b| matches!(b, b'\n' | b'\r'));
            let take = end.unwrap_or(buffer.len());
            let room = MAX_LINE.saturating_sub(line.len());
            complete &= take <= room;
            line.extend_from_slice(&buffer[..take.min(room)]);
            match end {
                Some(at) => {
                    self.after_cr = buffer[at] == b'\r';
                    self.reader.consume(at + 1);
                    break;
                }
                None => {
                    let n = buffer.len();
                    self.reader.consume(n);
                }
            }
        }
        Ok(any.then_some(complete))
    }
}

impl<R: BufRead> Lexer<R> {
    pub fn new(reader: R) -> Lexer<R> {
        Lexer::in_dialect(reader, Dialect::Strict)
    }

    /// The lenient dialect also reads `X 1.5` (a space in a word, as LinuxCNC
    /// does) and `;` starting a line or followed by prose as a comment to the
    /// end of the line (as Haas and LinuxCNC do); `G01 X1; Y2` still ends a
    /// statement at the `;`.
    pub fn in_dialect(reader: R, dialect: Dialect) -> Lexer<R> {
        Lexer {
            lines: Lines::new(reader),
            raw: Vec::new(),
            line_no: 0,
            pending: Default::default(),
            open_comment: None,
            done: false,
            lenient: dialect == Dialect::Lenient,
            read_code: false,
            history: None,
            read_8_bit: false,
            tape: None,
            peeked: Default::default(),
        }
    }

    /// Keeps the text of every line read in `history`.
    pub fn recording(mut self, history: SharedHistory) -> Lexer<R> {
        self.history = Some(history);
        self
    }

    /// Numbers the lines read from `first` on: `reader` holds a program's
    /// lines from there, read again (a backward `GOTO`).
    pub fn starting_at(mut self, first: u32) -> Lexer<R> {
        self.line_no = first.saturating_sub(1);
        self.read_code = first > 1;
        // Lines read again were read before the tape's end, if it has one.
        if first > 1 {
            self.tape = Some(false);
        }
        self
    }

    fn read_line(&mut self) -> bool {
        if let Some(line) = self.peeked.pop_front() {
            self.raw = line;
            self.line_no += 1;
            if let Some(history) = &self.history {
                history.borrow_mut().push(&self.raw);
            }
            return true;
        }
        match self.lines.read(&mut self.raw) {
            Ok(None) => false,
            Ok(Some(complete)) => {
                self.line_no += 1;
                if let Some(history) = &self.history {
                    history.borrow_mut().push(if complete { &self.raw } else { &[] });
                }
                if !complete {
                    let message = format!("this line is longer than {} MiB: it is not read", MAX_LINE >> 20);
                    self.push_diag(Diagnostic::error(Span::new(self.line_no, 1, 0), message));
                    self.raw.clear();
                }
                true
            }
            Err(err) => {
                let span = Span::new(self.line_no + 1, 1, 0);
                self.push_diag(Diagnostic::error(span, format!("cannot read the program: {err}")));
                false
            }
        }
    }

    fn push_token(&mut self, kind: TokenKind, col: usize, len: usize) {
        self.read_code |= !matches!(kind, TokenKind::Comment(_) | TokenKind::End);
        let span = Span::new(self.line_no, col as u32 + 1, len as u32);
        self.pending.push_back(Piece::Lexed(Lexed::Token(Token { kind, span })));
    }

    fn push_diag(&mut self, diagnostic: Diagnostic) {
        self.pending.push_back(Piece::Lexed(Lexed::Diagnostic(diagnostic)));
    }

    fn span(&self, col: usize, len: usize) -> Span {
        Span::new(self.line_no, col as u32 + 1, len as u32)
    }

    fn lex_line(&mut self) {
        let line = std::mem::take(&mut self.raw);
        // A byte-order mark, left by some Windows editors, is not part of the program.
        let body = if self.line_no == 1 { line.strip_prefix("\u{feff}".as_bytes()).unwrap_or(&line) } else { &line };
        let decoded: String;
        let text = match std::str::from_utf8(body) {
            Ok(text) => text,
            Err(err) => {
                // Programs from older editors and controllers are often in an
                // 8-bit code page (Latin-1, Windows-1252): their G-code is
                // ASCII, and only comments hold other letters (°, Ø, µ, ą).
                // Each byte is read as its Latin-1 character.
                if !self.read_8_bit {
                    self.read_8_bit = true;
                    let message = "this line is not UTF-8 text: it is read as Latin-1 (ISO 8859-1)";
                    let help = "G-code is read the same either way; only letters in comments may show otherwise";
                    self.push_diag(Diagnostic::warning(self.span(err.valid_up_to(), 1), message).with_help(help));
                }
                decoded = body.iter().map(|&byte| char::from(byte)).collect();
                &decoded
            }
        };
        // A program whose first line is `%` is a tape, and ends at the next
        // `%` line: LinuxCNC and Fanuc read nothing after it.
        let trimmed = text.trim();
        if self.open_comment.is_none() && !trimmed.is_empty() {
            match self.tape {
                None => self.tape = Some(trimmed.starts_with('%')),
                Some(true) if trimmed.starts_with('%') => {
                    self.push_token(TokenKind::End, text.len(), 0);
                    return self.end_of_tape();
                }
                Some(_) => {}
            }
        }
        let bytes = text.as_bytes();
        let mut pos = 0;
        let mut first_on_line = true;
        // After a wizard name, the rest of the line is its arguments.
        let mut in_wizard_args = false;

        if let Some(mut comment) = self.open_comment.take() {
            comment.body.push('\n');
            match self.continue_comment(text, 0, &mut comment) {
                Some(end) => {
                    let token = Token { kind: TokenKind::Comment(comment.body), span: comment.start };
                    self.pending.push_back(Piece::Lexed(Lexed::Token(token)));
                    pos = end;
                }
                None => {
                    self.open_comment = Some(comment);
                    self.raw = line;
                    return;
                }
            }
        }

        while pos < bytes.len() {
            let c = bytes[pos];
            // Any white space separates, and leaves the line's start as it was:
            // a lone CR (old Mac files), VT, a no-break space pasted from a page.
            if let Some(space) = text[pos..].chars().next().filter(|ch| ch.is_whitespace()) {
                pos += space.len_utf8();
                continue;
            }
            match c {
                b';' if self.lenient && (first_on_line || !is_gcode(&text[pos + 1..])) => {
                    let comment = text[pos + 1..].trim().to_string();
                    self.push_token(TokenKind::Comment(comment), pos, bytes.len() - pos);
                    pos = bytes.len();
                }
                b';' => {
                    self.push_token(TokenKind::End, pos, 1);
                    in_wizard_args = false;
                    pos += 1;
                }
                b'(' => {
                    let start = self.span(pos, bytes.len() - pos);
                    let mut comment = OpenComment { start, body: String::new(), depth: 1, nested_reported: false };
                    match self.continue_comment(text, pos + 1, &mut comment) {
                        Some(end) => {
                            self.push_token(TokenKind::Comment(comment.body), pos, end - pos);
                            pos = end;
                        }
                        None => {
                            self.open_comment = Some(comment);
                            pos = bytes.len();
                        }
                    }
                }
                b')' => {
                    let message = "`)` with no `(` before it";
                    self.push_diag(Diagnostic::error(self.span(pos, 1), message));
                    pos += 1;
                }
                b'%' if first_on_line && text[pos + 1..].trim().is_empty() => pos = bytes.len(),
                // A tape marker followed by a name or comment (`%PART1`), as Fanuc reads it.
                b'%' if first_on_line && self.lenient => pos = bytes.len(),
                // LinuxCNC's spindle selection (`M3 $0 S1000`, `M5 $-1`), not GRBL's `$0=10`.
                b'$' if self.lenient && is_spindle_selection(&text[pos + 1..]) => {
                    pos = self.spindle_selection(text, pos)
                }
                // GRBL's system commands (`$H`, `$X`, `$32=1`): not G-code, and not sent to any other controller.
                b'$' if first_on_line && self.lenient => {
                    let command = text[pos..].trim_end();
                    let message = format!("`{command}` is a GRBL system command, not G-code: it is dropped");
                    let help = if command.eq_ignore_ascii_case("$H") {
                        "homing is the machine's business before the program starts; ger's machine zero is where the tool starts"
                    } else {
                        "send GRBL's settings and commands from the sender, not in the program"
                    };
                    self.push_diag(Diagnostic::warning(self.span(pos, command.len()), message).with_help(help));
                    pos = bytes.len();
                }
                b'"' if in_wizard_args => pos = self.string(text, pos),
                _ if in_wizard_args && self.lenient && is_argument_expression(&text[pos..]) => {
                    pos = self.argument_expression(text, pos)
                }
                _ if in_wizard_args => pos = self.wizard_number(text, pos),
                b'o' | b'O'
                    if self.lenient
                        && (control::head(&text[pos..]).is_some()
                            || control::computed_call(text, pos, self.line_no).is_some()) =>
                {
                    pos = self.control(text, pos)
                }
                _ if c.is_ascii_alphabetic() => {
                    let name_len = bytes[pos..].iter().take_while(|b| b.is_ascii_alphanumeric() || **b == b'_').count();
                    let letters = bytes[pos..].iter().take_while(|b| b.is_ascii_alphabetic()).count();
                    let macro_b = letters >= 2 && self.lenient && !is_function_value(&text[pos + 1..]);
                    if let Some(end) = self.program_name(text, pos) {
                        pos = end;
                    } else if letters >= 2 && self.lenient && is_function_value(&text[pos + 1..]) {
                        let letter = bytes[pos].to_ascii_uppercase() as char;
                        pos = self.expression_word(text, pos, letter);
                    } else if let Some(end) = macro_b.then(|| self.macro_b(text, pos, name_len)).flatten() {
                        // Read once: it hands its pieces out as it reads them.
                        pos = end;
                    } else if letters >= 2 && is_control_flow(&text[pos..pos + name_len]) {
                        pos = self.refuse_rest_of_line(text, pos, ControlFlow);
                    } else if let Some(meant) = letter_o_for_zero(&text[pos..pos + name_len]) {
                        let name = &text[pos..pos + name_len];
                        let message = format!("`{name}` is no code: the letter O is typed for the digit zero");
                        let help = format!("did you mean {meant}?");
                        let diagnostic = Diagnostic::error(self.span(pos, name_len), message).with_help(help);
                        pos = self.refuse_expression(text, pos, diagnostic);
                    } else if letters >= 2 {
                        let name = text[pos..pos + name_len].to_string();
                        self.push_token(TokenKind::Ident(name), pos, name_len);
                        in_wizard_args = true;
                        pos += name_len;
                    } else {
                        pos = self.word(text, pos, first_on_line);
                    }
                }
                b'#' if self.lenient => pos = self.assignment(text, pos),
                b'#' => pos = self.refuse_rest_of_line(text, pos, Parameters),
                b'[' if self.lenient => {
                    // rs274 says "Bad character '[' used": a value needs a word to take it.
                    let len = text[pos..].find(']').map_or(1, |close| close + 1);
                    let message = "an expression with no word to take its value";
                    let help = "put the letter of the word it is the value of before it: X[#1 + 2]";
                    let diagnostic = Diagnostic::error(self.span(pos, len), message).with_help(help);
                    pos = self.refuse_expression(text, pos, diagnostic);
                }
                b'[' => pos = self.refuse_rest_of_line(text, pos, Expressions),
                b'/' if first_on_line => {
                    self.push_token(TokenKind::BlockDelete, pos, 1);
                    pos += 1;
                    continue;
                }
                _ if number_len(&text[pos..]) > 0 => {
                    let len = number_len(&text[pos..]);
                    let message = format!("the number `{}` has no letter before it", &text[pos..pos + len]);
                    let diagnostic = Diagnostic::error(self.span(pos, len), message)
                        .with_help("a word is a letter and its number, e.g. X20; a wizard call's arguments follow its name on its line");
                    self.push_diag(diagnostic);
                    pos += len;
                }
                _ => {
                    let len = text[pos..].chars().next().map_or(1, char::len_utf8);
                    let shown = &text[pos..pos + len];
                    let diagnostic = Diagnostic::error(self.span(pos, len), format!("unexpected `{shown}`"))
                        .with_help("a statement is made of words such as G01 or X1.5, comments in ( ), and `;`");
                    self.push_diag(diagnostic);
                    pos += len;
                }
            }
            first_on_line = false;
        }
        // A comment left open swallows the line end: the statement goes on.
        if self.open_comment.is_none() {
            self.push_token(TokenKind::End, bytes.len(), 0);
        }
        self.raw = line;
    }

    /// Reads comment text from `from`; returns the index just past the `)`
    /// that closes the comment, or `None` if the line ends first.
    fn continue_comment(&mut self, text: &str, from: usize, comment: &mut OpenComment) -> Option<usize> {
        for (i, byte) in text.bytes().enumerate().skip(from) {
            match byte {
                b'(' => {
                    comment.depth += 1;
                    if !std::mem::replace(&mut comment.nested_reported, true) {
                        self.nested_comment(i);
                    }
                }
                b')' => {
                    comment.depth -= 1;
                    if comment.depth == 0 {
                        comment.body.push_str(&text[from..i]);
                        return Some(i + 1);
                    }
                }
                _ => {}
            }
        }
        comment.body.push_str(&text[from..]);
        None
    }

    /// Macro programming ger does not have: one error for the line, which is
    /// skipped (its other words mean nothing without the macro's values).
    fn refuse_rest_of_line(&mut self, text: &str, start: usize, what: Unsupported) -> usize {
        let end = text[start..].find('(').map_or(text.len(), |i| start + i);
        let (message, help) = match what {
            Parameters => (
                "parameters (`#1`, `#<name>`) are not supported: ger has no variables",
                "the lenient dialect (--lenient) reads parameters and expressions as LinuxCNC does",
            ),
            Expressions => (
                "expressions in `[ ]` are not supported: ger has no variables",
                "the lenient dialect (--lenient) reads parameters and expressions as LinuxCNC does",
            ),
            ControlFlow => (
                "program control flow (Fanuc macro B IF/GOTO/WHILE, LinuxCNC O-word sub/if/while) is not supported",
                "ger runs straight-line G-code with M98 subprograms; a wizard can generate what the program repeats",
            ),
        };
        let span = self.span(start, text[start..end].trim_end().len());
        self.push_diag(Diagnostic::error(span, message).with_help(help));
        end
    }

    /// The comment runs to the `)` that balances its first `(`, so the rest
    /// of the line keeps its meaning; the lenient dialect takes that as some
    /// controllers do, with a warning.
    fn nested_comment(&mut self, col: usize) {
        let span = self.span(col, 1);
        let diagnostic = if self.lenient {
            Diagnostic::warning(span, "a comment inside a comment: read to the `)` that closes the first `(`")
                .with_help("LinuxCNC and Fanuc refuse nested comments; close the first comment before opening another")
        } else {
            Diagnostic::error(span, "comments cannot nest: `(` inside a comment")
                .with_help("close the first comment with `)` before opening another")
        };
        self.push_diag(diagnostic);
    }

    /// A letter and its number. A leading `N` line number is accepted and dropped.
    fn word(&mut self, text: &str, start: usize, first_on_line: bool) -> usize {
        let letter = text.as_bytes()[start].to_ascii_uppercase() as char;
        let number_len = number_len(&text[start + 1..]);
        let end = start + 1 + number_len;
        let Some(value) = text[start + 1..end].parse::<f64>().ok().filter(|_| number_len > 0) else {
            return self.word_without_number(text, start, letter);
        };
        let junk = text[end..].chars().take_while(|c| c.is_ascii_digit() || *c == '.').count();
        if junk > 0 {
            let message = format!("malformed number in `{}`", &text[start..end + junk]);
            self.push_diag(Diagnostic::error(self.span(start, end + junk - start), message));
        } else if letter != 'N' {
            self.push_word(letter, value, start, end - start);
        } else if first_on_line && self.lenient && value >= 0.0 {
            let span = self.span(start, end - start);
            self.pending.push_back(Piece::Macro(Macro::Label(value), span));
        } else if !first_on_line {
            let message = "an N line number may only start a line";
            let diagnostic = Diagnostic::error(self.span(start, end - start), message)
                .with_help("remove it, or move it to the start of the line");
            self.push_diag(diagnostic);
        } else if value < 0.0 || (value.fract() != 0.0 && !self.lenient) {
            // LinuxCNC reads past a fractional one (N10.5); so does the lenient dialect.
            let message = "an N line number must be a whole number";
            self.push_diag(Diagnostic::error(self.span(start, end - start), message));
        }
        end + junk
    }

    /// A letter and its number, if the number is one a machine could mean.
    fn push_word(&mut self, letter: char, value: f64, start: usize, len: usize) {
        if value.abs() > MAX_NUMBER {
            self.too_large(start, len);
        } else {
            self.push_token(TokenKind::Word { letter, value }, start, len);
        }
    }

    /// `O<name>` alone on a line, before any code: the program's name, as
    /// `O1234` is, which LinuxCNC reads past (lenient dialect). Returns where
    /// the name ends; anywhere else `O<` is O-word control flow, refused.
    fn program_name(&self, text: &str, start: usize) -> Option<usize> {
        let rest = text[start..].strip_prefix(['O', 'o'])?.strip_prefix('<')?;
        let name = rest.find('>')?;
        let after = rest[name + 1..].trim_start();
        let alone = after.is_empty() || after.starts_with(['(', ';']);
        (self.lenient && !self.read_code && alone && name > 0).then(|| start + 2 + name + 1)
    }

    fn too_large(&mut self, start: usize, len: usize) {
        let message = "this number is too large for any machine: ger reads numbers up to 10^12";
        let help = "no length, feed, speed or program number comes near it: check for a missing decimal point";
        self.push_diag(Diagnostic::error(self.span(start, len), message).with_help(help));
    }

    /// `X` with no number after it: the error swallows what looks like the
    /// number meant (`X -1.5`, `Y-`), so one slip gives one error.
    fn word_without_number(&mut self, text: &str, start: usize, letter: char) -> usize {
        let rest = &text[start + 1..];
        let value = rest.trim_start();
        let signed = value.strip_prefix(['-', '+']).unwrap_or(value).trim_start();
        if self.lenient && (signed.starts_with(['[', '#']) || is_function_value(signed)) {
            return self.expression_word(text, start, letter);
        }
        // `R[...]` and `X#1` are refused as expressions and parameters, once.
        if value.starts_with(['[', '#']) {
            return start + 1 + (rest.len() - rest.trim_start().len());
        }
        if self.lenient {
            let spaces = rest.len() - rest.trim_start_matches([' ', '\t']).len();
            let number = number_len(&rest[spaces..]);
            if let (true, Ok(value)) = (number > 0 && spaces > 0, rest[spaces..spaces + number].parse::<f64>()) {
                let letter = letter.to_ascii_uppercase();
                self.push_word(letter, value, start, 1 + spaces + number);
                return start + 1 + spaces + number;
            }
        }
        let junk = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit() || " \t+-.".contains(c)).len();
        let len = 1 + rest[..junk].trim_end().len();
        let message = format!("`{letter}` must be followed by a number");
        let diagnostic = Diagnostic::error(self.span(start, len), message)
            .with_help(format!("write it as one word, e.g. {letter}1.5 (no space between letter and number)"));
        self.push_diag(diagnostic);
        start + len
    }

    /// A word whose value is an expression: `X[#1 + 2]`, `F#<feed>`, `Z-#3`.
    fn expression_word(&mut self, text: &str, start: usize, letter: char) -> usize {
        let mut reader = Reader::new(text, start + 1, self.line_no);
        match reader.value() {
            Ok(value) => {
                let span = self.span(start, reader.pos - start);
                self.pending.push_back(Piece::Macro(Macro::Expression { letter, value }, span));
                reader.pos
            }
            Err(diagnostic) => self.refuse_expression(text, start, diagnostic),
        }
    }

    /// `#1 = expr`, `#<name> = expr`, `#[#1 + 1] = expr`. The value may be
    /// written without brackets (`#1 = #2 + 1`), as Fanuc allows.
    fn assignment(&mut self, text: &str, start: usize) -> usize {
        let mut reader = Reader::new(text, start, self.line_no);
        let parsed = reader.param().and_then(|target| {
            let at = reader.pos;
            match text[at..].trim_start().strip_prefix('=') {
                Some(after) => reader.pos = text.len() - after.len(),
                None => {
                    let message = "a parameter here is set: write `#1 = value`";
                    let help = "a word takes a parameter as its value: X#1";
                    return Err(Diagnostic::error(self.span(start, at - start), message).with_help(help));
                }
            }
            Ok((target, reader.infix()?))
        });
        match parsed {
            Ok((target, value)) => {
                let span = self.span(start, reader.pos - start);
                self.pending.push_back(Piece::Macro(Macro::Assign { target, value }, span));
                reader.pos
            }
            Err(diagnostic) => self.refuse_expression(text, start, diagnostic),
        }
    }

    /// An O-word control line: the rest of the line is its arguments.
    fn control(&mut self, text: &str, start: usize) -> usize {
        let (label, computed, keyword, after) = match control::head(&text[start..]) {
            Some((label, keyword, after)) => (label, None, keyword, start + after),
            None => match control::computed_call(text, start, self.line_no) {
                Some((number, after)) => (String::new(), Some(number), Keyword::Call, after),
                None => return start + 1,
            },
        };
        match control::arguments(text, after, self.line_no, keyword) {
            Ok((args, end)) => {
                let span = self.span(start, end - start);
                self.pending.push_back(Piece::Macro(
                    Macro::Control(Control { label, keyword, args, span, fanuc: false, computed }),
                    span,
                ));
                end
            }
            Err(diagnostic) => self.refuse_expression(text, start, diagnostic),
        }
    }

    /// Fanuc macro B's `WHILE [c] DOm`, `ENDm` and `IF [c] THEN ...`, read
    /// at `start` (`len` letters and digits long); `None` if the word is
    /// none of them. The result is where lexing goes on.
    fn macro_b(&mut self, text: &str, start: usize, len: usize) -> Option<usize> {
        let word = text[start..start + len].to_ascii_uppercase();
        let loop_number = |digits: &str| digits.parse::<u8>().ok().filter(|m| (1..=3).contains(m));
        // A Fanuc reads past spaces, so `END 1` and `DO 1` are END1 and DO1:
        // the length of `keyword` at `from` with the spaces and digit after it.
        let spaced = |from: usize, keyword: usize| {
            let rest = &text[from + keyword..];
            let digits = rest.trim_start();
            let number = digits.bytes().take_while(u8::is_ascii_digit).count();
            (number > 0).then(|| (keyword + rest.len() - digits.len() + number, &digits[..number]))
        };
        let end_loop = match word.strip_prefix("END").and_then(loop_number) {
            Some(number) => Some((number, len)),
            None if word == "END" => {
                spaced(start, len).and_then(|(len, digits)| loop_number(digits).map(|number| (number, len)))
            }
            None => None,
        };
        if let Some((number, len)) = end_loop {
            let span = self.span(start, len);
            let control = Control {
                label: number.to_string(),
                keyword: Keyword::EndWhile,
                args: Vec::new(),
                span,
                fanuc: true,
                computed: None,
            };
            self.pending.push_back(Piece::Macro(Macro::Control(control), span));
            return Some(start + len);
        }
        if word.starts_with("GOTO") && (word.len() == 4 || word[4..].bytes().all(|b| b.is_ascii_digit())) {
            return Some(self.goto(text, start, start + 4));
        }
        if word != "WHILE" && word != "IF" {
            return None;
        }
        let mut reader = Reader::new(text, start + len, self.line_no);
        let parsed = reader.bracketed().and_then(|condition| {
            let rest = text[reader.pos..].trim_start();
            let after = text.len() - rest.len();
            let mut letters = rest.bytes().take_while(u8::is_ascii_alphanumeric).count();
            let mut next = rest[..letters].to_ascii_uppercase();
            if next == "DO" {
                if let Some((spaced_len, digits)) = spaced(after, 2) {
                    (letters, next) = (spaced_len, format!("DO{digits}"));
                }
            }
            let span = self.span(start, after + letters - start);
            match (word.as_str(), next.strip_prefix("DO").and_then(loop_number)) {
                ("WHILE", Some(number)) => {
                    let control = Control {
                        label: number.to_string(),
                        keyword: Keyword::While,
                        args: vec![condition],
                        span,
                        fanuc: true,
                        computed: None,
                    };
                    Ok(Some((Macro::Control(control), span, after + letters)))
                }
                ("WHILE", None) => Err(Diagnostic::error(span, "WHILE [condition] is followed by DO1, DO2 or DO3")),
                _ if next == "THEN" => Ok(Some((Macro::Guard(condition), span, after + letters))),
                // IF [c] GOTO n: a jump guarded as THEN guards the rest of a line.
                _ if next.starts_with("GOTO") && next[4..].bytes().all(|b| b.is_ascii_digit()) => {
                    let span = self.span(start, after - start);
                    Ok(Some((Macro::Guard(condition), span, after)))
                }
                _ => Ok(None),
            }
        });
        match parsed {
            Ok(Some((piece, span, end))) => {
                self.pending.push_back(Piece::Macro(piece, span));
                Some(end)
            }
            Ok(None) => None,
            Err(diagnostic) => Some(self.refuse_expression(text, start, diagnostic)),
        }
    }

    /// `GOTO n`, from `start`; the target `n` (a number or any value, as
    /// Fanuc allows: `GOTO#10`, `GOTO[#1+10]`) starts at `at`.
    fn goto(&mut self, text: &str, start: usize, at: usize) -> usize {
        self.value_macro(text, start, at, Macro::Goto)
    }

    /// A piece made of the value that starts at `at`, spanning from `start`;
    /// a malformed value is refused.
    fn value_macro(&mut self, text: &str, start: usize, at: usize, make: fn(Expr) -> Macro) -> usize {
        let mut reader = Reader::new(text, at, self.line_no);
        match reader.value() {
            Ok(value) => {
                let span = self.span(start, reader.pos - start);
                self.pending.push_back(Piece::Macro(make(value), span));
                reader.pos
            }
            Err(diagnostic) => self.refuse_expression(text, start, diagnostic),
        }
    }

    /// A malformed expression: its error, and the rest of the line is
    /// skipped (up to a comment), since its words would be read wrongly.
    fn refuse_expression(&mut self, text: &str, start: usize, diagnostic: Diagnostic) -> usize {
        self.push_diag(diagnostic);
        text[start..].find('(').map_or(text.len(), |i| start + i)
    }

    /// A wizard argument that is an expression (lenient dialect): its value
    /// is worked out by the interpreter stage before the call.
    fn argument_expression(&mut self, text: &str, start: usize) -> usize {
        self.value_macro(text, start, start, Macro::Argument)
    }

    /// `$n` at `start`: the spindle the line's spindle words are for. ger's
    /// machine has one, LinuxCNC's spindle 0; `$-1` (all of them) is it too.
    fn spindle_selection(&mut self, text: &str, start: usize) -> usize {
        let len = 1 + number_len(&text[start + 1..]);
        let number = &text[start + 1..start + len];
        if !matches!(number.parse::<f64>(), Ok(n) if n == 0.0 || n == -1.0) {
            let message = format!("`${number}` selects spindle {number}: ger's machine has one spindle, LinuxCNC's $0");
            let diagnostic = Diagnostic::error(self.span(start, len), message)
                .with_help("write $0, or leave the $ word out: a spindle word is for spindle 0 by default");
            self.push_diag(diagnostic);
        }
        start + len
    }

    fn wizard_number(&mut self, text: &str, start: usize) -> usize {
        let len = text[start..]
            .find(|c: char| c.is_whitespace() || c == ';' || c == '(' || c == '"')
            .unwrap_or(text.len() - start);
        let piece = &text[start..start + len];
        match piece.parse::<f64>() {
            Ok(value) if number_len(piece) == len && value.abs() > MAX_NUMBER => self.too_large(start, len),
            Ok(value) if number_len(piece) == len => self.push_token(TokenKind::Number(value), start, len),
            _ => {
                let message = format!("wizard argument `{piece}` is neither a number nor a \"string\"");
                let diagnostic = Diagnostic::error(self.span(start, len), message)
                    .with_help("put text arguments in double quotes, e.g. Engrave \"HELLO\" 5");
                self.push_diag(diagnostic);
            }
        }
        start + len
    }

    fn string(&mut self, text: &str, start: usize) -> usize {
        match text[start + 1..].find('"') {
            Some(close) => {
                let body = text[start + 1..start + 1 + close].to_string();
                self.push_token(TokenKind::Str(body), start, close + 2);
                start + close + 2
            }
            None => {
                let message = "string is not closed: a wizard argument's closing `\"` is missing";
                self.push_diag(Diagnostic::error(self.span(start, text.len() - start), message));
                text.len()
            }
        }
    }
}

#[derive(Clone, Copy)]
enum Unsupported {
    Parameters,
    Expressions,
    ControlFlow,
}
use Unsupported::*;

/// Whether a program could not call a wizard of this name: it is a
/// keyword of Fanuc's macro B or LinuxCNC's O-words (`If`, `Do`, `End`), or
/// the name of a function of their expressions (`Sin`, `Round`).
pub fn is_reserved_name(name: &str) -> bool {
    is_control_flow(name) || expr::is_function(name)
}

/// Fanuc macro B's and LinuxCNC's O-word control-flow keywords, maybe with a
/// number glued on (`GOTO10`, `END1`).
fn is_control_flow(name: &str) -> bool {
    const KEYWORDS: [&str; 18] = [
        "IF",
        "GOTO",
        "WHILE",
        "DO",
        "END",
        "THEN",
        "SUB",
        "ENDSUB",
        "CALL",
        "ELSE",
        "ELSEIF",
        "ENDIF",
        "ENDWHILE",
        "REPEAT",
        "ENDREPEAT",
        "BREAK",
        "CONTINUE",
        "RETURN",
    ];
    let word = name.trim_end_matches(|c: char| c.is_ascii_digit()).to_ascii_uppercase();
    KEYWORDS.contains(&word.as_str())
}

/// Whether a wizard argument is an expression: `[...]`, a parameter, or
/// a function (with a sign before it, maybe), not a number or a string.
fn is_argument_expression(rest: &str) -> bool {
    let rest = rest.strip_prefix(['-', '+']).unwrap_or(rest);
    rest.starts_with(['[', '#']) || is_function_value(rest)
}

/// Whether `rest` starts with a function's name and `[`: `SIN[30]`.
/// Whether `rest` (after a `$`) is a spindle number, not a GRBL setting (`$0=10`).
fn is_spindle_selection(rest: &str) -> bool {
    let len = number_len(rest);
    len > 0 && !rest[len..].trim_start().starts_with('=')
}

/// A G or M code typed with the letter O for a zero (`GOO`, `G0O`, `MO3`),
/// as it was meant; not a lone `GO`, which may be a wizard's name.
fn letter_o_for_zero(name: &str) -> Option<String> {
    let (first, rest) = name.split_at(1);
    let code = first.eq_ignore_ascii_case("G") || first.eq_ignore_ascii_case("M");
    let digits_or_o = rest.chars().all(|c| c.is_ascii_digit() || c.eq_ignore_ascii_case(&'O'));
    let os = rest.chars().filter(|c| c.eq_ignore_ascii_case(&'O')).count();
    (code && digits_or_o && os >= 1 && rest.len() >= 2)
        .then(|| format!("{}{}", first.to_ascii_uppercase(), rest.replace(['O', 'o'], "0")))
}

fn is_function_value(rest: &str) -> bool {
    let letters = rest.bytes().take_while(u8::is_ascii_alphabetic).count();
    letters >= 2 && expr::is_function(&rest[..letters]) && rest[letters..].trim_start().starts_with('[')
}

/// Whether `rest` reads as G-code: words (`X1.5`, `G01`), comments, or nothing.
fn is_gcode(rest: &str) -> bool {
    let mut rest = rest.trim_start();
    while let Some(c) = rest.chars().next() {
        if c == '(' {
            let Some(end) = rest.find(')') else { return false };
            rest = rest[end + 1..].trim_start();
        } else if c.is_ascii_alphabetic() && number_len(&rest[1..]) > 0 {
            rest = rest[1 + number_len(&rest[1..])..].trim_start();
        } else {
            return c == ';';
        }
    }
    true
}

/// Length of the G-code number at the start of `s`: `[+-]digits[.digits]` or `[+-].digits`.
fn number_len(s: &str) -> usize {
    let bytes = s.as_bytes();
    let mut i = usize::from(matches!(bytes.first(), Some(b'+' | b'-')));
    let int_digits = bytes[i..].iter().take_while(|b| b.is_ascii_digit()).count();
    i += int_digits;
    let mut frac_digits = 0;
    if bytes.get(i) == Some(&b'.') {
        frac_digits = bytes[i + 1..].iter().take_while(|b| b.is_ascii_digit()).count();
        i += 1 + frac_digits;
    }
    if int_digits + frac_digits == 0 {
        0
    } else {
        i
    }
}

impl<R: BufRead> Lexer<R> {
    /// The lexer's pieces, macro programming included, for the interpreter stage.
    pub fn pieces(self) -> Pieces<R> {
        Pieces(self)
    }

    /// The tape's closing `%`: nothing after it is read as the program, and
    /// if anything is there, it is said once. But where what follows is
    /// another program (`O8000`, after more `%` and comments), the file is
    /// a Fanuc's store of programs, main and subprograms each between `%`
    /// lines: it is read on, so that the main program's calls find them.
    fn end_of_tape(&mut self) {
        let at = self.line_no;
        let has_text = |line: &[u8]| line.iter().any(|b| !b.is_ascii_whitespace());
        let mut peeked: Vec<Vec<u8>> = Vec::new();
        let mut bytes = 0;
        let mut next = None;
        while peeked.len() < MAX_PEEKED && bytes < MAX_LINE {
            let Ok(Some(_)) = self.lines.read(&mut self.raw) else { break };
            let line = std::mem::take(&mut self.raw);
            bytes += line.len();
            let text = String::from_utf8_lossy(&line);
            let text = text.trim();
            if text.is_empty() || text.starts_with('%') || (text.starts_with('(') && text.ends_with(')')) {
                peeked.push(line);
            } else {
                next = Some(line);
                break;
            }
        }
        if let Some(line) = next.take_if(|line| starts_a_program(String::from_utf8_lossy(line).trim())) {
            self.peeked.extend(peeked);
            self.peeked.push_back(line);
            self.tape = Some(false);
            return;
        }
        let mut left = peeked.iter().chain(&next).filter(|line| has_text(line)).count();
        while let Ok(Some(_)) = self.lines.read(&mut self.raw) {
            left += usize::from(has_text(&self.raw));
        }
        self.done = true;
        self.raw.clear();
        if left > 0 {
            let message = format!(
                "the program ends at this `%`, as LinuxCNC and Fanuc read a tape: {left} line{} after it {} not read",
                if left == 1 { "" } else { "s" },
                if left == 1 { "is" } else { "are" }
            );
            let help = "a file whose first line is `%` ends at the next `%`; remove it to run what follows";
            self.push_diag(Diagnostic::warning(Span::new(at, 1, 1), message).with_help(help));
        }
    }

    fn next_piece(&mut self) -> Option<Piece> {
        loop {
            if let Some(piece) = self.pending.pop_front() {
                return Some(piece);
            }
            if self.done {
                return None;
            }
            if self.read_line() {
                self.lex_line();
            } else {
                self.done = true;
                if let Some(comment) = self.open_comment.take() {
                    let diagnostic = Diagnostic::error(comment.start, "comment is never closed")
                        .with_help("add `)` where the comment should end");
                    self.push_diag(diagnostic);
                }
            }
        }
    }
}

/// A lexer's pieces: see [`Piece`].
pub struct Pieces<R>(Lexer<R>);

impl<R: BufRead> Iterator for Pieces<R> {
    type Item = Piece;

    fn next(&mut self) -> Option<Piece> {
        self.0.next_piece()
    }
}

impl<R: BufRead> Iterator for Lexer<R> {
    type Item = Lexed;

    fn next(&mut self) -> Option<Lexed> {
        loop {
            if let Piece::Lexed(lexed) = self.next_piece()? {
                return Some(lexed);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tokens(text: &str) -> Vec<String> {
        shown(lex_str(text))
    }

    fn lenient_tokens(text: &str) -> Vec<String> {
        shown(Lexer::in_dialect(text.as_bytes(), Dialect::Lenient))
    }

    fn shown(lexed: impl Iterator<Item = Lexed>) -> Vec<String> {
        lexed
            .map(|item| match item {
                Lexed::Token(t) => {
                    let s = t.span;
                    let kind = match t.kind {
                        TokenKind::Word { letter, value } => format!("{letter}{value}"),
                        TokenKind::Ident(name) => format!("ident {name}"),
                        TokenKind::Number(v) => format!("num {v}"),
                        TokenKind::Str(v) => format!("str {v:?}"),
                        TokenKind::Comment(v) => format!("comment {v:?}"),
                        TokenKind::End => "end".to_string(),
                        TokenKind::BlockDelete => "/".to_string(),
                    };
                    format!("{}:{}+{} {kind}", s.line, s.col, s.len)
                }
                Lexed::Diagnostic(d) => format!("{d}"),
                Lexed::Origin(_) => "origin".to_string(),
            })
            .collect()
    }

    #[test]
    fn words_have_spans_and_upper_case_letters() {
        assert_eq!(
            tokens("G01 x-1.25 Y.5 z+2."),
            ["1:1+3 G1", "1:5+6 X-1.25", "1:12+3 Y0.5", "1:16+4 Z2", "1:20+0 end"]
        );
    }

    #[test]
    fn semicolon_and_newline_end_statements() {
        assert_eq!(tokens("X1;Y2\nZ3"), ["1:1+2 X1", "1:3+1 end", "1:4+2 Y2", "1:6+0 end", "2:1+2 Z3", "2:3+0 end"]);
    }

    #[test]
    fn comments_may_span_lines_but_not_nest() {
        assert_eq!(tokens("G00 (one\ntwo) X1"), ["1:1+3 G0", "1:5+4 comment \"one\\ntwo\"", "2:6+2 X1", "2:8+0 end"]);
        // One error, and the comment runs to the `)` that balances the first `(`.
        assert_eq!(
            tokens("(a (b) c) X1"),
            [
                "1:4: error: comments cannot nest: `(` inside a comment",
                "1:1+9 comment \"a (b) c\"",
                "1:11+2 X1",
                "1:13+0 end"
            ]
        );
        assert_eq!(tokens("G00 (open")[1], "1:5: error: comment is never closed");
    }

    #[test]
    fn a_line_in_an_8_bit_code_page_is_read_as_latin_1_with_one_warning() {
        // `(Ø6 FRÄSER)` and `(45°)` saved as Latin-1: 0xD8, 0xC4 and 0xB0 are not UTF-8.
        let program = b"G01 X1 (\xd86 FR\xc4SER)\nG00 Z5 (45\xb0)\n";
        let got: Vec<String> = Lexer::new(&program[..])
            .map(|item| match item {
                Lexed::Token(t) => format!("{:?}", t.kind),
                Lexed::Diagnostic(d) => format!("{d}"),
                Lexed::Origin(_) => "origin".to_string(),
            })
            .collect();
        assert_eq!(
            got,
            [
                "1:9: warning: this line is not UTF-8 text: it is read as Latin-1 (ISO 8859-1)",
                "Word { letter: 'G', value: 1.0 }",
                "Word { letter: 'X', value: 1.0 }",
                "Comment(\"Ø6 FRÄSER\")",
                "End",
                "Word { letter: 'G', value: 0.0 }",
                "Word { letter: 'Z', value: 5.0 }",
                "Comment(\"45°\")",
                "End",
            ]
        );
    }

    #[test]
    fn a_tape_ends_at_its_second_percent_line() {
        // As LinuxCNC and Fanuc read a file whose first line is `%`: the
        // second program is not read, and that is said once.
        assert_eq!(
            tokens("\n%\nX1\n% END\nX2\n\n%\nX3\n"),
            [
                "1:1+0 end",
                "2:2+0 end",
                "3:1+2 X1",
                "3:3+0 end",
                "4:6+0 end",
                "4:1: warning: the program ends at this `%`, as LinuxCNC and Fanuc read a tape: 3 lines after it are not read"
            ]
        );
        // What follows is another program (a Fanuc's store of programs): read on.
        let got = tokens("%\nM98 P8000\nM30\n%\n\n( THE PROFILE )\n%\nO8000\nX2\nM99\n%");
        assert_eq!(got.iter().filter(|t| t.contains("warning")).count(), 0, "{got:?}");
        assert!(got.contains(&"8:1+5 O8000".to_string()) && got.contains(&"9:1+2 X2".to_string()), "{got:?}");
        // Not a tape: a `%` later on is only dropped.
        assert_eq!(tokens("X1\n%\nX2"), ["1:1+2 X1", "1:3+0 end", "2:2+0 end", "3:1+2 X2", "3:3+0 end"]);
    }

    #[test]
    fn line_numbers_and_tape_markers_are_dropped() {
        assert_eq!(tokens("%\nN10 G01 X1\n%"), ["1:2+0 end", "2:5+3 G1", "2:9+2 X1", "2:11+0 end", "3:2+0 end"]);
        assert_eq!(tokens("G01 N10")[1], "1:5: error: an N line number may only start a line");
    }

    #[test]
    fn wizard_calls_take_numbers_and_strings_to_the_end_of_the_line() {
        assert_eq!(
            tokens("Engrave \"HI there\" -5 .25 (c)\nX1"),
            [
                "1:1+7 ident Engrave",
                "1:9+10 str \"HI there\"",
                "1:20+2 num -5",
                "1:23+3 num 0.25",
                "1:27+3 comment \"c\"",
                "1:30+0 end",
                "2:1+2 X1",
                "2:3+0 end"
            ]
        );
        assert_eq!(tokens("Pocket 7 X1")[2], "1:10: error: wizard argument `X1` is neither a number nor a \"string\"");
    }

    #[test]
    fn linuxcnc_spindle_zero_is_the_spindle_and_no_other_is() {
        assert_eq!(lenient_tokens("M3 $0 S1000"), ["1:1+2 M3", "1:7+5 S1000", "1:12+0 end"]);
        assert_eq!(lenient_tokens("M5 $-1"), ["1:1+2 M5", "1:7+0 end"]);
        assert_eq!(
            lenient_tokens("M3 $1 S100")[1],
            "1:4: error: `$1` selects spindle 1: ger's machine has one spindle, LinuxCNC's $0"
        );
        // GRBL's settings stay GRBL's.
        assert!(lenient_tokens("$0=10")[0].contains("GRBL system command"), "{:?}", lenient_tokens("$0=10"));
    }

    #[test]
    fn a_lenient_expression_needs_a_word_to_take_it() {
        let got = lenient_tokens("G1 X1 [2] (why)");
        assert_eq!(got[..2], ["1:1+2 G1", "1:4+2 X1"]);
        assert_eq!(got[2], "1:7: error: an expression with no word to take its value");
        assert_eq!(got[3..], ["1:11+5 comment \"why\"", "1:16+0 end"]);
    }

    #[test]
    fn a_code_typed_with_the_letter_o_for_a_zero_is_refused_with_the_code_meant() {
        let refused = lex_str("GOO Z.500 (clear)\nmO3 S1000\nG0O X1\n").filter_map(|item| match item {
            Lexed::Diagnostic(d) => Some((d.span.line, d.message, d.help)),
            _ => None,
        });
        let refused: Vec<_> = refused.collect();
        assert_eq!(refused.len(), 3, "{refused:?}");
        assert_eq!(refused[0].1, "`GOO` is no code: the letter O is typed for the digit zero");
        assert_eq!(refused[0].2.as_deref(), Some("did you mean G00?"));
        assert_eq!((refused[1].0, refused[1].2.as_deref()), (2, Some("did you mean M03?")));
        assert_eq!((refused[2].0, refused[2].2.as_deref()), (3, Some("did you mean G00?")));
        // A wizard may be called Go; GOTO is control flow.
        assert_eq!(tokens("Go 5")[0], "1:1+2 ident Go");
    }

    #[test]
    fn macro_programming_is_refused_once_a_line() {
        assert_eq!(
            tokens("#1=5 G01 X#1 (c)\nIF [#1 EQ 0] GOTO10\nN20 WHILE [#2 LT 3] DO1\nX1"),
            [
                "1:1: error: parameters (`#1`, `#<name>`) are not supported: ger has no variables",
                "1:14+3 comment \"c\"",
                "1:17+0 end",
                "2:1: error: program control flow (Fanuc macro B IF/GOTO/WHILE, LinuxCNC O-word sub/if/while) is not supported",
                "2:20+0 end",
                "3:5: error: program control flow (Fanuc macro B IF/GOTO/WHILE, LinuxCNC O-word sub/if/while) is not supported",
                "3:24+0 end",
                "4:1+2 X1",
                "4:3+0 end"
            ]
        );
        assert_eq!(tokens("o100 sub")[1], "1:6: error: program control flow (Fanuc macro B IF/GOTO/WHILE, LinuxCNC O-word sub/if/while) is not supported");
        assert_eq!(tokens("/G01 X1")[0], "1:1+1 /");
    }

    #[test]
    fn a_named_program_before_any_code_is_its_name() {
        // LinuxCNC's test m98m99/13-named-program: rs274 runs it as if the line were not there.
        let lenient = |text: &str| -> Vec<String> {
            Lexer::in_dialect(text.as_bytes(), Dialect::Lenient)
                .map(|item| match item {
                    Lexed::Token(t) => format!("{}:{} {:?}", t.span.line, t.span.col, t.kind),
                    Lexed::Diagnostic(d) => d.to_string(),
                    Lexed::Origin(_) => "origin".to_string(),
                })
                .collect()
        };
        assert_eq!(
            lenient("(named)\nO<MyProgram> (body)\nM30"),
            [
                "1:1 Comment(\"named\")",
                "1:8 End",
                "2:14 Comment(\"body\")",
                "2:20 End",
                "3:1 Word { letter: 'M', value: 30.0 }",
                "3:4 End"
            ]
        );
        // After code it is not a name.
        assert!(lenient("G0 X1\nO<MyProgram>")[3].starts_with("2:1: error: `O` must be followed by a number"));
        // With more on its line it is an O-word, for the interpreter stage: not a name.
        let first = Lexer::in_dialect("O<sub1> sub".as_bytes(), Dialect::Lenient).pieces().next();
        assert!(matches!(first, Some(Piece::Macro(..))));
        assert!(tokens("O<MyProgram>")[0].starts_with("1:1: error: `O` must be followed by a number"));
    }

    #[test]
    fn the_lenient_dialect_reads_spaced_words_and_semicolon_comments() {
        let lenient = |text: &str| -> Vec<String> {
            Lexer::in_dialect(text.as_bytes(), Dialect::Lenient)
                .map(|item| match item {
                    Lexed::Token(t) => format!("{}:{} {:?}", t.span.line, t.span.col, t.kind),
                    Lexed::Diagnostic(d) => d.to_string(),
                    Lexed::Origin(_) => "origin".to_string(),
                })
                .collect()
        };
        assert_eq!(
            lenient("X -0.25 y 2; IESI Project 2: drilling"),
            [
                "1:1 Word { letter: 'X', value: -0.25 }",
                "1:9 Word { letter: 'Y', value: 2.0 }",
                "1:12 Comment(\"IESI Project 2: drilling\")",
                "1:38 End"
            ]
        );
        // G-code after the `;` is still a statement of its own.
        assert_eq!(lenient("X1; Y2")[1], "1:3 End");
        // The strict dialect keeps the manual's rules.
        assert_eq!(tokens("X -0.25")[0], "1:1: error: `X` must be followed by a number");
        assert_eq!(tokens("\u{feff}%\nX1")[1], "2:1+2 X1");
    }

    #[test]
    fn every_line_ending_and_white_space_is_read() {
        // A lone CR ends a line (old Mac files), CRLF is one ending, and any
        // Unicode white space separates words: these once made the lexer loop.
        assert_eq!(
            tokens("X1\rY2\r\nZ3\n"),
            ["1:1+2 X1", "1:3+0 end", "2:1+2 Y2", "2:3+0 end", "3:1+2 Z3", "3:3+0 end"]
        );
        assert_eq!(
            tokens("Pocket 1\u{a0}2\u{b}3 \u{2003}4"),
            ["1:1+6 ident Pocket", "1:8+1 num 1", "1:11+1 num 2", "1:13+1 num 3", "1:18+1 num 4", "1:19+0 end"]
        );
        assert_eq!(tokens("  N10 X1")[0], "1:7+2 X1");
        assert_eq!(tokens("20 3")[0], "1:1: error: the number `20` has no letter before it");
    }

    #[test]
    fn an_endless_line_is_cut() {
        let text = format!("X1 {}\nY2", "(c)".repeat(MAX_LINE / 3 + 10));
        let got = tokens(&text);
        assert!(got.iter().any(|t| t.starts_with("1:1: error: this line is longer than 1 MiB")), "{:?}", &got[..3]);
        assert!(got.iter().any(|t| t == "2:1+2 Y2"));
    }

    #[test]
    fn malformed_numbers_are_diagnosed() {
        assert_eq!(tokens("X1.2.3")[0], "1:1: error: malformed number in `X1.2.3`");
        assert_eq!(tokens("X - 1"), ["1:1: error: `X` must be followed by a number", "1:6+0 end"]);
        assert_eq!(
            tokens("G00 Y- X1")[1..],
            ["1:5: error: `Y` must be followed by a number", "1:8+2 X1", "1:10+0 end"]
        );
        // A parameter in place of the number is one error, about the parameter.
        assert_eq!(
            tokens("G01 X#1")[1..],
            ["1:6: error: parameters (`#1`, `#<name>`) are not supported: ger has no variables", "1:8+0 end"]
        );
        assert_eq!(tokens("G01 @")[1], "1:5: error: unexpected `@`");
    }
}
