//! Shows diagnostics the way rustc does: the message, ` --> FILE:LINE:COL`, the
//! source line with a caret under the culprit, and a `help:` line.
//!
//! Diagnostics carry only positions; the lines they point at are read back
//! from the input once the run is over, so a long program is never held in
//! memory just in case it has an error.

use std::collections::{BTreeSet, HashMap};
use std::io::BufRead;

use annotate_snippets::{AnnotationKind, Group, Level, Renderer, Snippet};

use ger_core::diag::{Diagnostic, Severity};

/// How many diagnostics are shown in full; past that they are only counted.
const SHOWN: usize = 200;
/// How many calls of a chain are listed.
const CHAIN_SHOWN: usize = 6;

/// The diagnostics of a job: counted, the first ones kept, rendered on demand.
#[derive(Default)]
pub struct Report {
    shown: Vec<Diagnostic>,
    errors: usize,
    warnings: usize,
    /// What failed, for the closing line (default: the translation).
    failure: Option<&'static str>,
}

impl Report {
    /// Closes with "error: `failure`: N errors" rather than "could not translate the program".
    pub fn failing_as(mut self, failure: &'static str) -> Report {
        self.failure = Some(failure);
        self
    }

    pub fn add(&mut self, diagnostic: Diagnostic) {
        match diagnostic.severity {
            Severity::Error => self.errors += 1,
            Severity::Warning => self.warnings += 1,
        }
        if self.shown.len() < SHOWN {
            self.shown.push(diagnostic);
        }
    }

    /// The diagnostics kept to show (the first 200; past that they are only counted).
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.shown
    }

    pub fn errors(&self) -> usize {
        self.errors
    }

    pub fn warnings(&self) -> usize {
        self.warnings
    }

    /// Renders every diagnostic against `source`, read again from the start,
    /// and a closing count.
    pub fn render(&self, path: &str, source: impl BufRead, styled: bool) -> String {
        let wanted: BTreeSet<u32> = self.shown.iter().map(|d| d.span.line).collect();
        let lines = read_lines(source, &wanted);
        let renderer = if styled { Renderer::styled() } else { Renderer::plain() };
        let mut text = String::new();
        for diagnostic in &self.shown {
            text.push_str(&render_one(&renderer, diagnostic, path, lines.get(&diagnostic.span.line)));
            text.push_str("\n\n");
        }
        let hidden = self.errors + self.warnings - self.shown.len();
        if hidden > 0 {
            text.push_str(&format!("... and {hidden} more not shown\n"));
        }
        if let Some(summary) = self.summary() {
            text.push_str(&summary);
            text.push('\n');
        }
        text
    }

    fn summary(&self) -> Option<String> {
        let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
        let failure = self.failure.unwrap_or("could not translate the program");
        match (self.errors, self.warnings) {
            (0, 0) => None,
            (0, w) => Some(format!("warning: {} emitted", plural(w, "warning"))),
            (e, 0) => Some(format!("error: {failure}: {}", plural(e, "error"))),
            (e, w) => Some(format!("error: {failure}: {}, {}", plural(e, "error"), plural(w, "warning"))),
        }
    }
}

/// The text of the `wanted` lines (numbered from 1, as the lexer numbers them).
fn read_lines(source: impl BufRead, wanted: &BTreeSet<u32>) -> HashMap<u32, String> {
    let mut found = HashMap::new();
    let Some(&last) = wanted.last() else {
        return found;
    };
    let mut lines = ger_core::lex::Lines::new(source);
    let mut raw = Vec::new();
    for line_no in 1..=last {
        match lines.read(&mut raw) {
            Ok(Some(_)) => {}
            Ok(None) | Err(_) => break,
        }
        if wanted.contains(&line_no) {
            found.insert(line_no, String::from_utf8_lossy(&raw).into_owned());
        }
    }
    found
}

fn render_one(renderer: &Renderer, diagnostic: &Diagnostic, path: &str, line: Option<&String>) -> String {
    let level = match diagnostic.severity {
        Severity::Error => Level::ERROR,
        Severity::Warning => Level::WARNING,
    };
    let span = diagnostic.span;
    let mut group = Group::with_title(level.primary_title(&diagnostic.message));
    let location;
    match line {
        Some(text) => {
            let start = (span.col as usize).saturating_sub(1).min(text.len());
            let end = (start + span.len.max(1) as usize).min(text.len());
            let (start, end) = (floor_char(text, start), floor_char(text, end.max(start)));
            let annotation = AnnotationKind::Primary.span(start..end);
            group = group.element(
                Snippet::source(text.as_str()).line_start(span.line as usize).path(path).annotation(annotation),
            );
        }
        None => {
            // The line is gone (the input changed, or it is past the end): say where, without a snippet.
            location = format!("at {path}:{}:{}", span.line, span.col);
            group = group.element(Level::NOTE.message(&location));
        }
    }
    let chain = diagnostic.call_chain();
    let mut notes: Vec<String> = chain.iter().take(CHAIN_SHOWN).cloned().collect();
    if chain.len() > CHAIN_SHOWN {
        notes.push(format!("... and {} calls more", chain.len() - CHAIN_SHOWN));
    }
    for note in &notes {
        group = group.element(Level::NOTE.message(note));
    }
    if let Some(help) = &diagnostic.help {
        group = group.element(Level::HELP.message(help));
    }
    renderer.render(&[group])
}

fn floor_char(text: &str, mut index: usize) -> usize {
    while !text.is_char_boundary(index) {
        index -= 1;
    }
    index
}

#[cfg(test)]
mod tests {
    use super::*;
    use ger_core::diag::Span;

    #[test]
    fn renders_like_rustc() {
        let mut report = Report::default();
        report.add(Diagnostic::error(Span::new(2, 5, 3), "F is not allowed").with_help("drop it"));
        let text = report.render("prog.ngc", "G00 X1\nG00 F10\n".as_bytes(), false);
        let expected = "\
error: F is not allowed
 --> prog.ngc:2:5
  |
2 | G00 F10
  |     ^^^
  |
  = help: drop it

error: could not translate the program: 1 error
";
        assert_eq!(text, expected);
    }
}
