//! A document's text as the editor edits it, and the two ways of counting
//! columns: ger's spans count bytes of a line from 1, the protocol counts
//! UTF-16 code units from 0.

use lsp_types::{Position, Range, TextDocumentContentChangeEvent};

/// Where each line starts in a text: line n (from 0) at `starts[n]`.
pub struct Lines {
    starts: Vec<usize>,
}

impl Lines {
    pub fn of(text: &str) -> Lines {
        let starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
        Lines { starts }
    }

    /// How many lines the text has (a final newline starts an empty last line).
    pub fn count(&self) -> usize {
        self.starts.len()
    }

    /// Line `line` (from 0) without its line break; empty past the end.
    pub fn line<'t>(&self, text: &'t str, line: usize) -> &'t str {
        let Some(&start) = self.starts.get(line) else { return "" };
        let end = self.starts.get(line + 1).map_or(text.len(), |&next| next - 1);
        text[start..end].strip_suffix('\r').unwrap_or(&text[start..end])
    }

    /// The byte offset in `text` of an editor's position; a position past
    /// the end of its line is the line's end, past the last line the text's end.
    pub fn offset(&self, text: &str, position: Position) -> usize {
        let line = position.line as usize;
        let Some(&start) = self.starts.get(line) else { return text.len() };
        start + byte_of_utf16(self.line(text, line), position.character)
    }

    /// The editor's position of 1-based byte column `col` on 1-based `line`,
    /// as ger's spans give them (clamped to the text).
    pub fn position(&self, text: &str, line: u32, col: u32) -> Position {
        let index = (line as usize).saturating_sub(1).min(self.count() - 1);
        let line_text = self.line(text, index);
        Position { line: index as u32, character: utf16_of_byte(line_text, col.saturating_sub(1) as usize) }
    }

    /// The editor's range of a span: `len` bytes from `col` on `line`; at
    /// least one character, so that an error at a line's end can be seen.
    pub fn range(&self, text: &str, line: u32, col: u32, len: u32) -> Range {
        let start = self.position(text, line, col);
        let mut end = self.position(text, line, col + len);
        if end == start {
            // Past the line's end, which editors read as its end.
            end.character += 1;
        }
        Range { start, end }
    }
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

/// An open document: its text, the version the editor gave it, and its lines.
pub struct Document {
    pub text: String,
    pub version: i32,
    pub lines: Lines,
}

impl Document {
    pub fn new(text: String, version: i32) -> Document {
        let lines = Lines::of(&text);
        Document { text, version, lines }
    }

    /// The 1-based line and byte column (as ger's spans count) of an
    /// editor's position, and that line's text.
    pub fn cursor(&self, position: Position) -> (u32, u32, &str) {
        let line_text = self.lines.line(&self.text, position.line as usize);
        (position.line + 1, byte_of_utf16(line_text, position.character) as u32 + 1, line_text)
    }

    /// Applies the editor's changes in order: each a range replaced, or the whole text.
    pub fn change(&mut self, changes: Vec<TextDocumentContentChangeEvent>, version: i32) {
        for change in changes {
            match change.range {
                Some(range) => {
                    let start = self.lines.offset(&self.text, range.start);
                    let end = self.lines.offset(&self.text, range.end).max(start);
                    self.text.replace_range(start..end, &change.text);
                }
                None => self.text = change.text,
            }
            self.lines = Lines::of(&self.text);
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
        assert_eq!(lines.count(), 3);
        // Byte column 8 of line 2 is the G: after "(", four bytes of 𝕏, ")" and " ".
        assert_eq!(lines.position(text, 2, 8), at(1, 5));
        assert_eq!(lines.offset(text, at(1, 5)), text.find('G').unwrap());
        assert_eq!(lines.position(text, 1, 4), at(0, 2));
        // Inside the surrogate pair: the character's start.
        assert_eq!(lines.offset(text, at(1, 2)), text.find('𝕏').unwrap());
        // Past the line's end: its end; past the last line: the text's end.
        assert_eq!(lines.offset(text, at(0, 99)), 5);
        assert_eq!(lines.offset(text, at(7, 0)), text.len());
        assert_eq!(lines.position(text, 9, 3), at(2, 0));
    }

    #[test]
    fn an_empty_span_still_covers_a_character() {
        let text = "G01 X1\n";
        let lines = Lines::of(text);
        assert_eq!(lines.range(text, 1, 5, 2), Range { start: at(0, 4), end: at(0, 6) });
        assert_eq!(lines.range(text, 1, 7, 0), Range { start: at(0, 6), end: at(0, 7) });
    }

    #[test]
    fn incremental_changes_apply_in_order() {
        let mut document = Document::new("G00 X1\nM02\n".to_string(), 1);
        let replace = |range: Option<Range>, text: &str| TextDocumentContentChangeEvent {
            range,
            range_length: None,
            text: text.to_string(),
        };
        let changes = vec![
            replace(Some(Range { start: at(1, 1), end: at(1, 3) }), "30"),
            replace(Some(Range { start: at(0, 6), end: at(0, 6) }), " Y2"),
        ];
        document.change(changes, 2);
        assert_eq!(document.text, "G00 X1 Y2\nM30\n");
        assert_eq!(document.version, 2);
        assert_eq!(document.lines.line(&document.text, 1), "M30");
        document.change(vec![replace(None, "M30\r\n")], 3);
        assert_eq!(document.lines.line(&document.text, 0), "M30");
    }
}
