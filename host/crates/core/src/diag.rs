//! Spans and diagnostics: the one error type every stage speaks.
//!
//! A [`Span`] is a line, a byte column and a length; it never holds the text
//! itself, so a stage can report on a line long after the lexer has dropped it.
//! Rendering (which needs the text again) is the job of `cli`.

use std::borrow::Cow;
use std::fmt;
use std::sync::Arc;

/// Where something came from in the program text. Lines and columns count from 1;
/// `col` and `len` are in bytes of the line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Span {
    pub line: u32,
    pub col: u32,
    pub len: u32,
}

impl Span {
    pub fn new(line: u32, col: u32, len: u32) -> Span {
        Span { line, col, len }
    }

    /// The smallest span on `self`'s line covering both spans (a span that
    /// starts on a later line is ignored: spans never cross lines).
    pub fn to(self, other: Span) -> Span {
        if other.line != self.line || other.col + other.len <= self.col {
            return self;
        }
        Span { len: other.col + other.len - self.col, ..self }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    Warning,
    Error,
}

/// How a statement came to be executed: through which subprogram calls (and,
/// later, wizard calls). Diagnostics print it so an error inside a subprogram
/// that runs three times says which call it was.
#[derive(Clone, Debug, PartialEq)]
pub struct Origin {
    pub what: String,
    pub call: Span,
    pub parent: Option<Arc<Origin>>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    pub message: String,
    pub span: Span,
    pub help: Option<String>,
    pub origin: Option<Arc<Origin>>,
}

impl Diagnostic {
    pub fn error(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic { severity: Severity::Error, message: message.into(), span, help: None, origin: None }
    }

    pub fn warning(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic { severity: Severity::Warning, ..Diagnostic::error(span, message) }
    }

    pub fn with_help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    pub fn with_origin(mut self, origin: Option<Arc<Origin>>) -> Diagnostic {
        self.origin = origin;
        self
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// The call chain, innermost first: "in O100 called at line 12", ...
    pub fn call_chain(&self) -> Vec<String> {
        let mut chain = Vec::new();
        let mut next = self.origin.as_deref();
        while let Some(origin) = next {
            chain.push(format!("in {} called at line {}", origin.what, origin.call.line));
            next = origin.parent.as_deref();
        }
        chain
    }
}

impl fmt::Display for Diagnostic {
    /// One line, for tests and logs: `3:5: error: message`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let level = match self.severity {
            Severity::Warning => "warning",
            Severity::Error => "error",
        };
        write!(f, "{}:{}: {}: {}", self.span.line, self.span.col, level, self.message)
    }
}

/// `text` as a diagnostic shows it: at most `max` characters, then a note of
/// how much was left out. Names and messages from wizards can be any length,
/// and a diagnostic must stay readable (and small).
pub fn clip(text: &str, max: usize) -> Cow<'_, str> {
    match text.char_indices().nth(max) {
        None => Cow::Borrowed(text),
        Some((end, _)) => Cow::Owned(format!("{}... ({} more bytes cut)", &text[..end], text.len() - end)),
    }
}

#[cfg(test)]
mod tests {
    use super::clip;

    #[test]
    fn clip_keeps_short_text_and_says_how_much_it_cut() {
        assert_eq!(clip("Pocket", 6), "Pocket");
        assert_eq!(clip("Pocket", 3), "Poc... (3 more bytes cut)");
        // Characters, not bytes: a cut never splits one.
        assert_eq!(clip("ééé", 1), "é... (4 more bytes cut)");
    }
}
