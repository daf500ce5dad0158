//! A document's text as the editor edits it, and the two ways of counting
//! columns: ger's spans count bytes of a line from 1, the protocol counts
//! UTF-16 code units from 0.
//!
//! An open document is a rope (ropey): an edit of a 23 MB program costs a
//! few microseconds on the protocol's thread, where rebuilding a string
//! and its line index cost tens of milliseconds, and a copy for the
//! analysis is a reference, not the text. The analysis reads the text as
//! one string, indexed by [`Lines`].

use std::borrow::Cow;

use lsp_types::{Position, Range, TextDocumentContentChangeEvent};
use ropey::Rope;

/// A text read a line at a time, as a document's rope and an analysed string are.
pub trait LineText {
    /// How many lines the text has (a final newline starts an empty last line).
    fn count(&self) -> usize;

    /// Line `line` (from 0) without its line break; empty past the end.
    fn line(&self, line: usize) -> Cow<'_, str>;

    /// The editor's position of 1-based byte column `col` on 1-based `line`,
    /// as ger's spans give them (clamped to the text).
    fn position(&self, line: u32, col: u32) -> Position {
        let index = (line as usize).saturating_sub(1).min(self.count() - 1);
        let line_text = self.line(index);
        Position { line: index as u32, character: utf16_of_byte(&line_text, col.saturating_sub(1) as usize) }
    }

    /// The editor's range of a span: `len` bytes from `col` on `line`; at
    /// least one character, so that an error at a line's end can be seen.
    fn range(&self, line: u32, col: u32, len: u32) -> Range {
        let start = self.position(line, col);
        let mut end = self.position(line, col + len);
        if end == start {
            // Past the line's end, which editors read as its end.
            end.character += 1;
        }
        Range { start, end }
    }
}

/// A string and where each of its lines starts: line n (from 0) at `starts[n]`.
pub struct Lines<'t> {
    text: &'t str,
    starts: Vec<usize>,
}

impl<'t> Lines<'t> {
    pub fn of(text: &'t str) -> Lines<'t> {
        let starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
        Lines { text, starts }
    }
}

impl LineText for Lines<'_> {
    fn count(&self) -> usize {
        self.starts.len()
    }

    fn line(&self, line: usize) -> Cow<'_, str> {
        let Some(&start) = self.starts.get(line) else { return Cow::Borrowed("") };
        let end = self.starts.get(line + 1).map_or(self.text.len(), |&next| next - 1);
        Cow::Borrowed(without_break(&self.text[start..end]))
    }
}

fn without_break(line: &str) -> &str {
    let line = line.strip_suffix('\n').unwrap_or(line);
    line.strip_suffix('\r').unwrap_or(line)
}

/// The byte offset in `line` of UTF-16 column `character` (the line's end past it;
/// inside a surrogate pair, the character's start).
pub fn byte_of_utf16(line: &str, character: u32) -> usize {
    let mut units = 0;
    for (byte, c) in line.char_indices() {
        units += c.len_utf16() as u32;
        if units > character {
            return byte;
        }
    }
    line.len()
}

/// The UTF-16 column of byte offset `byte` in `line` (rounded down to a
/// character's start, clamped to the line).
pub fn utf16_of_byte(line: &str, byte: usize) -> u32 {
    let mut byte = byte.min(line.len());
    while !line.is_char_boundary(byte) {
        byte -= 1;
    }
    if line.is_ascii() {
        return byte as u32;
    }
    line[..byte].encode_utf16().count() as u32
}

/// An open document: its text and the version the editor gave it.
pub struct Document {
    text: Rope,
    pub version: i32,
}

impl LineText for Document {
    fn count(&self) -> usize {
        self.text.len_lines()
    }

    fn line(&self, line: usize) -> Cow<'_, str> {
        if line >= self.text.len_lines() {
            return Cow::Borrowed("");
        }
        match Cow::from(self.text.line(line)) {
            Cow::Borrowed(line) => Cow::Borrowed(without_break(line)),
            Cow::Owned(line) => Cow::Owned(without_break(&line).to_string()),
        }
    }
}

impl Document {
    pub fn new(text: &str, version: i32) -> Document {
        Document { text: Rope::from_str(text), version }
    }

    /// The text as it is now: a copy that shares the document's, made at once.
    pub fn snapshot(&self) -> Rope {
        self.text.clone()
    }

    /// The 1-based line and byte column (as ger's spans count) of an
    /// editor's position, and that line's text.
    pub fn cursor(&self, position: Position) -> (u32, u32, Cow<'_, str>) {
        let line_text = self.line(position.line as usize);
        let col = byte_of_utf16(&line_text, position.character) as u32 + 1;
        (position.line.saturating_add(1), col, line_text)
    }

    /// The character index of an editor's position: a position past the
    /// end of its line is the line's end, past the last line the text's end.
    fn char_at(&self, position: Position) -> usize {
        let line = position.line as usize;
        if line >= self.text.len_lines() {
            return self.text.len_chars();
        }
        let line_text = self.line(line);
        let chars = line_text[..byte_of_utf16(&line_text, position.character)].chars().count();
        self.text.line_to_char(line) + chars
    }

    /// Applies the editor's changes in order: each a range replaced, or the whole text.
    pub fn change(&mut self, changes: Vec<TextDocumentContentChangeEvent>, version: i32) {
        for change in changes {
            match change.range {
                Some(range) => {
                    let start = self.char_at(range.start);
                    let end = self.char_at(range.end).max(start);
                    self.text.remove(start..end);
                    self.text.insert(start, &change.text);
                }
                None => self.text = Rope::from_str(&change.text),
            }
        }
        self.version = version;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(line: u32, character: u32) -> Position {
        Position { line, character }
    }

    #[test]
    fn columns_convert_between_bytes_and_utf16_units() {
        // "Ø" is two bytes and one UTF-16 unit; "𝕏" four bytes and two units.
        let text = "(Ø6)\n(𝕏) G07\n";
        let lines = Lines::of(text);
        let document = Document::new(text, 1);
        for read in [&lines as &dyn LineText, &document] {
            assert_eq!(read.count(), 3);
            // Byte column 8 of line 2 is the G: after "(", four bytes of 𝕏, ")" and " ".
            assert_eq!(read.position(2, 8), at(1, 5));
            assert_eq!(read.position(1, 4), at(0, 2));
            assert_eq!(read.position(9, 3), at(2, 0));
            assert_eq!(read.line(1), "(𝕏) G07");
        }
        let char_of = |byte: usize| text[..byte].chars().count();
        assert_eq!(document.char_at(at(1, 5)), char_of(text.find('G').unwrap()));
        // Inside the surrogate pair: the character's start.
        assert_eq!(document.char_at(at(1, 2)), char_of(text.find('𝕏').unwrap()));
        // Past the line's end: its end; past the last line: the text's end.
        assert_eq!(document.char_at(at(0, 99)), 4);
        assert_eq!(document.char_at(at(7, 0)), text.chars().count());
        assert_eq!(document.cursor(at(1, 5)), (2, 8, Cow::Borrowed("(𝕏) G07")));
    }

    #[test]
    fn an_empty_span_still_covers_a_character() {
        let lines = Lines::of("G01 X1\n");
        assert_eq!(lines.range(1, 5, 2), Range { start: at(0, 4), end: at(0, 6) });
        assert_eq!(lines.range(1, 7, 0), Range { start: at(0, 6), end: at(0, 7) });
    }

    #[test]
    fn incremental_changes_apply_in_order() {
        let mut document = Document::new("G00 X1\r\nM02\n", 1);
        let replace = |range: Option<Range>, text: &str| TextDocumentContentChangeEvent {
            range,
            range_length: None,
            text: text.to_string(),
        };
        let changes = vec![
            replace(Some(Range { start: at(1, 1), end: at(1, 3) }), "30"),
            // Past the end of line 0: before its CR LF.
            replace(Some(Range { start: at(0, 6), end: at(0, 9) }), " Y2"),
        ];
        document.change(changes, 2);
        assert_eq!(document.snapshot().to_string(), "G00 X1 Y2\r\nM30\n");
        assert_eq!(document.version, 2);
        assert_eq!(document.line(0), "G00 X1 Y2");
        assert_eq!(document.line(1), "M30");
        document.change(vec![replace(None, "M30\r\n")], 3);
        assert_eq!(document.line(0), "M30");
        assert_eq!(document.line(5), "");
    }
}
