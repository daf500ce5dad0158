//! A program's shape as ger's lexer reads it: its subprograms and O-word
//! blocks (document symbols), the calls of subprograms (go to definition)
//! and of wizards, and the token under the cursor (hover).

use ger_engine::core::diag::Span;
use ger_engine::core::lex::{Lexed, Lexer, Macro, Piece, Token, TokenKind};
use ger_engine::core::macros::control::Keyword;
use ger_engine::core::statement::Dialect;

/// A subprogram or an O-word block: where it starts, where it ends, what holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// As the program writes it: `O100`, `o<probe> sub`, `o101 while`, `WHILE ... DO1`.
    pub name: String,
    /// What a call names it by, for a subprogram: `100`, `probe`.
    pub label: Option<String>,
    /// The word that opens it.
    pub start: Span,
    /// The line of the word that closes it (its start's, if it is never closed).
    pub end_line: u32,
    /// The block it is in, by index.
    pub parent: Option<usize>,
    /// Still open: closed only by its end, or by the next program (Fanuc's `O`).
    open: Opening,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Opening {
    /// Fanuc's `O100`, to the next M99 (or the next O word, or M30).
    Program,
    /// An O-word block, closed by its own keyword with the same label.
    Control {
        keyword: Keyword,
        fanuc: bool,
    },
    Closed,
}

/// A call of a subprogram: `M98 P100`, `G65 P100`, `o100 call`, `o<probe> call`.
#[derive(Clone, Debug, PartialEq)]
pub struct Call {
    /// From the code (or the `o` word) to its P word (or keyword).
    pub span: Span,
    pub label: String,
}

#[derive(Default, Debug)]
pub struct Outline {
    pub blocks: Vec<Block>,
    pub calls: Vec<Call>,
    /// Wizard calls, by the span of the wizard's name.
    pub wizard_calls: Vec<(Span, String)>,
}

impl Outline {
    /// Reads `text` with ger's lexer in `dialect`.
    pub fn of(text: &str, dialect: Dialect) -> Outline {
        let mut outline = Outline::default();
        let mut open: Vec<usize> = Vec::new();
        let mut statement: Vec<Token> = Vec::new();
        for piece in Lexer::in_dialect(text.as_bytes(), dialect).pieces() {
            match piece {
                Piece::Lexed(Lexed::Token(token)) => {
                    if token.kind == TokenKind::End {
                        outline.statement(&statement, &mut open);
                        statement.clear();
                    } else {
                        statement.push(token);
                    }
                }
                Piece::Macro(Macro::Control(control), span) => {
                    let label = control.label.clone();
                    let keyword = control.keyword;
                    if keyword == Keyword::Call {
                        outline.calls.push(Call { span, label });
                        continue;
                    }
                    let closes = |opening: Opening| match (keyword, opening) {
                        (Keyword::EndSub, Opening::Control { keyword: Keyword::Sub, .. })
                        | (Keyword::EndIf, Opening::Control { keyword: Keyword::If, .. })
                        | (Keyword::While, Opening::Control { keyword: Keyword::Do, .. })
                        | (Keyword::EndRepeat, Opening::Control { keyword: Keyword::Repeat, .. }) => true,
                        (Keyword::EndWhile, Opening::Control { keyword: Keyword::While, fanuc }) => {
                            fanuc == control.fanuc
                        }
                        _ => false,
                    };
                    let found = open.iter().rposition(|&b| {
                        let block = &outline.blocks[b];
                        closes(block.open) && block_label(block) == label
                    });
                    if let Some(at) = found {
                        for b in open.drain(at..) {
                            outline.blocks[b].end_line = span.line;
                            outline.blocks[b].open = Opening::Closed;
                        }
                    } else if matches!(
                        keyword,
                        Keyword::Sub | Keyword::If | Keyword::While | Keyword::Do | Keyword::Repeat
                    ) {
                        let label = (keyword == Keyword::Sub).then(|| label.clone());
                        let opening = Opening::Control { keyword, fanuc: control.fanuc };
                        outline.open(&mut open, control.describe(), label, span, opening);
                    }
                }
                _ => {}
            }
        }
        outline.statement(&statement, &mut open);
        outline
    }

    fn open(&mut self, open: &mut Vec<usize>, name: String, label: Option<String>, start: Span, opening: Opening) {
        self.blocks.push(Block {
            name,
            label,
            start,
            end_line: start.line,
            parent: open.last().copied(),
            open: opening,
        });
        open.push(self.blocks.len() - 1);
    }

    /// Closes the Fanuc program open, and the blocks in it, at `line`.
    fn end_program(&mut self, open: &mut Vec<usize>, line: u32) {
        if let Some(at) = open.iter().rposition(|&b| self.blocks[b].open == Opening::Program) {
            for b in open.drain(at..) {
                self.blocks[b].end_line = line;
                self.blocks[b].open = Opening::Closed;
            }
        }
    }

    /// One statement's tokens: an `O` that starts it defines a program; M98
    /// and G65 with P call one; M99 and M30 end one; a name calls a wizard.
    fn statement(&mut self, tokens: &[Token], open: &mut Vec<usize>) {
        let words: Vec<(char, f64, Span)> = tokens
            .iter()
            .filter_map(|t| match t.kind {
                TokenKind::Word { letter, value } => Some((letter, value, t.span)),
                _ => None,
            })
            .filter(|(letter, _, _)| *letter != 'N')
            .collect();
        let code = |letter: char, number: f64| words.iter().find(|w| w.0 == letter && w.1 == number);
        if let Some(&('O', number, span)) = words.first() {
            self.end_program(open, span.line.saturating_sub(1).max(1));
            let name = format!("O{}", number as u64);
            self.open(open, name, Some(label(number)), span, Opening::Program);
        }
        if let Some(&(_, _, span)) = code('M', 99.0).or_else(|| code('M', 30.0)).or_else(|| code('M', 2.0)) {
            self.end_program(open, span.line);
        }
        if let Some(&(_, _, start)) = code('M', 98.0).or_else(|| code('G', 65.0)) {
            if let Some(&(_, number, p)) = words.iter().find(|w| w.0 == 'P') {
                self.calls.push(Call { span: start.to(p), label: label(number) });
            }
        }
        for token in tokens {
            if let TokenKind::Ident(name) = &token.kind {
                self.wizard_calls.push((token.span, name.clone()));
            }
        }
    }

    /// The subprogram a call names: its first definition, as ger runs the first.
    pub fn definition(&self, label: &str) -> Option<&Block> {
        self.blocks.iter().find(|b| b.label.as_deref() == Some(label))
    }

    /// The call at 1-based byte column `col` of `line`, or the only one on the line.
    pub fn call_at(&self, line: u32, col: u32) -> Option<&Call> {
        let on_line: Vec<&Call> = self.calls.iter().filter(|c| c.span.line == line).collect();
        let hit = on_line.iter().find(|c| (c.span.col..=c.span.col + c.span.len).contains(&col));
        hit.or(if on_line.len() == 1 { on_line.first() } else { None }).copied()
    }

    /// The wizard named at 1-based byte column `col` of `line`.
    pub fn wizard_at(&self, line: u32, col: u32) -> Option<&str> {
        let at = self.wizard_calls.partition_point(|(span, _)| span.line < line);
        self.wizard_calls[at..]
            .iter()
            .take_while(|(span, _)| span.line == line)
            .find(|(span, _)| (span.col..=span.col + span.len).contains(&col))
            .map(|(_, name)| name.as_str())
    }
}

/// What a call by number names: `100` for P100 or O100.
fn label(number: f64) -> String {
    (number.max(0.0) as u64).to_string()
}

fn block_label(block: &Block) -> String {
    // The label a block's closing keyword repeats: its `o` label, or Fanuc's loop number.
    let name = block.name.trim_start_matches(['o', 'O']);
    let name = name.split_whitespace().next().unwrap_or("");
    let name = name.trim_start_matches('<').trim_end_matches('>');
    match block.name.strip_prefix("WHILE ... DO") {
        Some(number) => number.to_string(),
        None => name.to_string(),
    }
}

/// The tokens of line `line` (text `line_text`, 1-based number `line`), as
/// ger's lexer reads the line alone, each with the text it is written as.
pub fn line_tokens(line_text: &str, line: u32, dialect: Dialect) -> Vec<(Token, String)> {
    Lexer::in_dialect(line_text.as_bytes(), dialect)
        .starting_at(line)
        .filter_map(|lexed| match lexed {
            Lexed::Token(token) if token.kind != TokenKind::End => {
                let from = token.span.col.saturating_sub(1) as usize;
                let written = line_text.get(from..from + token.span.len as usize).unwrap_or("").to_string();
                Some((token, written))
            }
            _ => None,
        })
        .collect()
}

/// Whether a token covers 1-based byte column `col` (an empty one, its own column).
pub fn covers(token: &Token, col: u32) -> bool {
    (token.span.col..token.span.col + token.span.len.max(1)).contains(&col)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fanuc_programs_and_their_calls() {
        let text = "O0001\nG00 X0\nM98 P100 L2\nM30\nO100\nG01 X1 F10\nM99\n";
        let outline = Outline::of(text, Dialect::Strict);
        let names: Vec<(&str, u32, u32)> =
            outline.blocks.iter().map(|b| (b.name.as_str(), b.start.line, b.end_line)).collect();
        assert_eq!(names, [("O1", 1, 4), ("O100", 5, 7)]);
        assert_eq!(outline.calls, [Call { span: Span::new(3, 1, 8), label: "100".into() }]);
        assert_eq!(outline.definition("100").unwrap().start, Span::new(5, 1, 4));
        assert_eq!(outline.call_at(3, 12).unwrap().label, "100");
    }

    #[test]
    fn o_word_blocks_nest() {
        let text = "o<probe> sub\no101 while [#1 LT 3]\n#1 = [#1 + 1]\no101 endwhile\no<probe> endsub\n\
                    o<probe> call\nG65 P9 A1\nPocket 10 5 1\nM30\n";
        let outline = Outline::of(text, Dialect::Lenient);
        let names: Vec<(&str, Option<&str>)> =
            outline.blocks.iter().map(|b| (b.name.as_str(), b.label.as_deref())).collect();
        assert_eq!(names, [("o<probe> sub", Some("probe")), ("o101 while", None)]);
        let places: Vec<(u32, u32, Option<usize>)> =
            outline.blocks.iter().map(|b| (b.start.line, b.end_line, b.parent)).collect();
        assert_eq!(places, [(1, 5, None), (2, 4, Some(0))]);
        let calls: Vec<(u32, &str)> = outline.calls.iter().map(|c| (c.span.line, c.label.as_str())).collect();
        assert_eq!(calls, [(6, "probe"), (7, "9")]);
        assert_eq!(outline.wizard_at(8, 3), Some("Pocket"));
        assert_eq!(outline.wizard_at(8, 9), None);
    }

    #[test]
    fn the_token_under_the_cursor() {
        let tokens = line_tokens("G01 X1.5 (cut)", 4, Dialect::Strict);
        let (token, written) = tokens.iter().find(|(t, _)| covers(t, 6)).unwrap();
        assert_eq!(token.kind, TokenKind::Word { letter: 'X', value: 1.5 });
        assert_eq!(token.span, Span::new(4, 5, 4));
        assert_eq!(written, "X1.5");
        assert!(!tokens.iter().any(|(t, _)| covers(t, 4)));
    }
}
