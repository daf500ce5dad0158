//! LinuxCNC's O-word control lines: `o100 sub`, `o100 call [1] [2]`,
//! `o101 while [#1 LT 10]`, `o<name> if [...]` and the rest, as the lexer
//! reads them.

use super::expr::{Expr, Reader};
use crate::diag::{Diagnostic, Span};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keyword {
    Sub,
    EndSub,
    Call,
    Return,
    If,
    ElseIf,
    Else,
    EndIf,
    While,
    EndWhile,
    Do,
    Repeat,
    EndRepeat,
    Break,
    Continue,
    /// Fanuc's `O1000` starting a program after the main one (a subprogram
    /// or macro, called by M98 or G65), and the `M99` that ends it: not
    /// O-words, but read into a block as `sub` is.
    Program,
    EndProgram,
}

const KEYWORDS: [(&str, Keyword); 15] = [
    ("sub", Keyword::Sub),
    ("endsub", Keyword::EndSub),
    ("call", Keyword::Call),
    ("return", Keyword::Return),
    ("if", Keyword::If),
    ("elseif", Keyword::ElseIf),
    ("else", Keyword::Else),
    ("endif", Keyword::EndIf),
    ("while", Keyword::While),
    ("endwhile", Keyword::EndWhile),
    ("do", Keyword::Do),
    ("repeat", Keyword::Repeat),
    ("endrepeat", Keyword::EndRepeat),
    ("break", Keyword::Break),
    ("continue", Keyword::Continue),
];

impl Keyword {
    pub fn name(self) -> &'static str {
        KEYWORDS.iter().find(|(_, keyword)| *keyword == self).map_or("", |(name, _)| name)
    }
}

/// One O-word control line: its label (`100`, or a name in lower case), its
/// keyword and its bracketed arguments.
#[derive(Clone, Debug, PartialEq)]
pub struct Control {
    pub label: String,
    pub keyword: Keyword,
    pub args: Vec<Expr>,
    pub span: Span,
    /// Fanuc macro B's `WHILE [c] DOm` or `ENDm`, labelled m.
    pub fanuc: bool,
    /// A call's subroutine number, worked out when it runs: `o#<sub> call`,
    /// `o[#2 * 10] call` (the label is then empty).
    pub computed: Option<Expr>,
}

impl Control {
    /// `o100`, as the program names it (`DO1` for Fanuc's loops).
    pub fn name(&self) -> String {
        if matches!(self.keyword, Keyword::Program | Keyword::EndProgram) {
            self.label.clone()
        } else if self.fanuc {
            format!("DO{}", self.label)
        } else if self.label.chars().all(|c| c.is_ascii_digit()) {
            format!("o{}", self.label)
        } else {
            format!("o<{}>", self.label)
        }
    }
}

impl Control {
    /// The line as a message quotes it: `o100 while`, `WHILE ... DO1`, `END1`.
    pub fn describe(&self) -> String {
        match (self.fanuc, self.keyword) {
            (_, Keyword::Program) => self.label.clone(),
            (_, Keyword::EndProgram) => "M99".to_string(),
            (true, Keyword::While) => format!("WHILE ... DO{}", self.label),
            (true, _) => format!("END{}", self.label),
            (false, keyword) => format!("{} {}", self.name(), keyword.name()),
        }
    }
}

/// The label and keyword at the start of `text` (which starts at the `o`),
/// and where the keyword ends; `None` if this is not a control line.
pub fn head(text: &str) -> Option<(String, Keyword, usize)> {
    // LinuxCNC reads past spaces here too: `o <probe> sub`.
    let rest = text[1..].trim_start();
    let label_at = text.len() - rest.len();
    let (label, after) = if let Some(named) = rest.strip_prefix('<') {
        let close = named.find('>')?;
        let name: String = named[..close].chars().filter(|c| !c.is_whitespace()).collect();
        (name.to_ascii_lowercase(), label_at + 1 + close + 1)
    } else {
        let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
        let number: u64 = rest[..digits].parse().ok()?;
        (number.to_string(), label_at + digits)
    };
    let spaces = text[after..].len() - text[after..].trim_start().len();
    let start = after + spaces;
    // LinuxCNC reads past spaces: `o100 end sub` is `o100 endsub`.
    let run = text[start..].bytes().take_while(|b| b.is_ascii_alphabetic() || *b == b' ' || *b == b'\t').count();
    let run = text[start..start + run].trim_end().len();
    let word: String = text[start..start + run].chars().filter(|c| !c.is_whitespace()).collect::<String>();
    let &(_, keyword) = KEYWORDS.iter().find(|(name, _)| name.eq_ignore_ascii_case(&word))?;
    Some((label, keyword, start + run))
}

/// `o#<sub> call` or `o[#2 * 10] call` at `start` in `text`: the number's
/// expression and where `call` ends, LinuxCNC reading a numbered
/// subroutine's number as any word's value; `None` if this is not one.
pub fn computed_call(text: &str, start: usize, line: u32) -> Option<(Expr, usize)> {
    let rest = text[start + 1..].trim_start();
    if !rest.starts_with(['#', '[']) {
        return None;
    }
    let mut reader = Reader::new(text, text.len() - rest.len(), line);
    let number = reader.value().ok()?;
    let rest = &text[reader.pos..];
    let keyword = rest.trim_start();
    let call = keyword.get(..4).filter(|word| word.eq_ignore_ascii_case("call"))?;
    let after = &keyword[call.len()..];
    (!after.starts_with(|c: char| c.is_ascii_alphanumeric())).then_some((number, text.len() - after.len()))
}

/// Reads a control line's arguments, from `pos` in `text` to the end of the
/// line or a comment after the last, for the keyword that takes them.
pub fn arguments(text: &str, pos: usize, line: u32, keyword: Keyword) -> Result<(Vec<Expr>, usize), Diagnostic> {
    let mut reader = Reader::new(text, pos, line);
    let mut args = Vec::new();
    loop {
        let rest = text[reader.pos..].trim_start();
        // LinuxCNC passes over a `(comment)` between arguments:
        // `o<s> call [1] (depth) [2]` gives the sub both.
        let after_comment = rest.strip_prefix('(').and_then(|c| c.find(')').map(|close| c[close + 1..].trim_start()));
        match after_comment {
            Some(next) if next.starts_with('[') => reader.pos = text.len() - next.len(),
            _ if rest.is_empty() || rest.starts_with(['(', ';']) => break,
            _ => args.push(reader.bracketed()?),
        }
    }
    let (fewest, most) = match keyword {
        Keyword::Call => (0, 30),
        Keyword::If | Keyword::ElseIf | Keyword::While | Keyword::Repeat => (1, 1),
        Keyword::Return | Keyword::EndSub => (0, 1),
        _ => (0, 0),
    };
    if !(fewest..=most).contains(&args.len()) {
        let first = pos + text[pos..].len() - text[pos..].trim_start().len();
        let span = Span::new(line, first as u32 + 1, reader.pos.saturating_sub(first).max(1) as u32);
        let wanted = match (fewest, most) {
            (0, 0) => "nothing".to_string(),
            (1, 1) => "one [condition]".to_string(),
            (0, 1) => "at most one [value]".to_string(),
            _ => format!("at most {most} [arguments]"),
        };
        return Err(Diagnostic::error(span, format!("`{}` takes {wanted}", keyword.name())));
    }
    Ok((args, reader.pos))
}
