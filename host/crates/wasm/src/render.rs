//! A wizard's typed statements -> ger's statements.
//!
//! Each typed statement is written as one line of G-code (a `text` statement
//! as its own lines) and the lines go through ger's own lexer and parser, so
//! a wizard's output means exactly what the same text would mean in a
//! program. Anything that does not make a clean line (a non-letter word, a
//! NaN, a comment with a line break, text that does not parse) is an error at
//! the call naming the wizard and the statement: wizards are untrusted, and
//! their mistakes must read as theirs.

use std::fmt::Write;

use crate::runtime::bindings::ger::wizard::types as wit;
use ger_core::diag::{clip, Diagnostic, Severity, Span};
use ger_core::lex::lex_str;
use ger_core::parse::{parse, Event};
use ger_core::statement::Statement;
use ger_core::wizard::{shown_name, SHOWN_MESSAGE};

/// The statements `output` stands for, or an error at `span` naming `wizard`.
pub fn render(output: &[wit::Statement], wizard: &str, span: Span) -> Result<Vec<Statement>, Diagnostic> {
    let wizard = shown_name(wizard);
    let mut text = String::new();
    // The statement (1-based) each line of `text` came from.
    let mut line_owner = Vec::new();
    for (index, statement) in output.iter().enumerate() {
        let bad = |why: String| {
            Diagnostic::error(span, format!("wizard `{wizard}` returned a bad statement (#{}): {why}", index + 1))
                .with_help("this is a fault in the wizard, not in the program")
        };
        let start = text.len();
        write_statement(&mut text, statement).map_err(bad)?;
        text.push('\n');
        line_owner.extend(std::iter::repeat_n(index, text[start..].lines().count()));
    }
    let mut statements = Vec::with_capacity(output.len());
    for event in parse(lex_str(&text)) {
        match event {
            Event::Statement(statement) => statements.push(statement),
            // Even a warning fails the call: there is no way to return both,
            // and a wizard's output should be clean.
            Event::Diagnostic(diagnostic) => {
                let line = diagnostic.span.line as usize;
                let index = line_owner.get(line.saturating_sub(1)).copied().unwrap_or(0);
                let source = clip(text.lines().nth(line.saturating_sub(1)).unwrap_or(""), SHOWN_MESSAGE);
                let kind = if diagnostic.severity == Severity::Error { "a bad" } else { "a doubtful" };
                let message = format!(
                    "wizard `{wizard}` returned {kind} statement (#{}, `{source}`): {}",
                    index + 1,
                    clip(&diagnostic.message, SHOWN_MESSAGE)
                );
                let help = diagnostic.help.unwrap_or_else(|| "this is a fault in the wizard".to_string());
                return Err(Diagnostic::error(span, message).with_help(help));
            }
        }
    }
    Ok(statements)
}

fn write_statement(out: &mut String, statement: &wit::Statement) -> Result<(), String> {
    match statement {
        wit::Statement::Words(words) => {
            if words.is_empty() {
                return Err("a block with no words".to_string());
            }
            for (i, word) in words.iter().enumerate() {
                if !word.letter.is_ascii_alphabetic() {
                    return Err(format!("`{}` is not a G-code letter (A-Z)", word.letter.escape_default()));
                }
                if !word.value.is_finite() {
                    return Err(format!("{} has no finite value ({})", word.letter, word.value));
                }
                if i > 0 {
                    out.push(' ');
                }
                // `{}` of an f64 is the shortest text that reads back as the
                // same number, and never uses an exponent.
                let _ = write!(out, "{}{}", word.letter.to_ascii_uppercase(), word.value);
            }
        }
        wit::Statement::Comment(comment) => {
            if comment.contains(['\n', '\r']) {
                return Err("a comment with a line break".to_string());
            }
            // G-code comments do not nest, and `;` ends a statement.
            if comment.contains(['(', ')']) {
                return Err("a comment holding `(` or `)`".to_string());
            }
            let _ = write!(out, "({comment})");
        }
        wit::Statement::Call(call) => {
            if call.name.len() < 2 || !call.name.chars().all(|c| c.is_ascii_alphabetic()) {
                return Err(format!(
                    "a call of `{}`: a wizard's name is two or more letters",
                    shown_name(&call.name).escape_default()
                ));
            }
            let name = shown_name(&call.name);
            out.push_str(&call.name);
            for arg in &call.args {
                match arg {
                    wit::Arg::Number(n) if n.is_finite() => {
                        let _ = write!(out, " {n}");
                    }
                    wit::Arg::Number(n) => return Err(format!("a call of `{name}` with the argument {n}")),
                    wit::Arg::Text(t) if !t.contains(['"', '\n', '\r']) => {
                        let _ = write!(out, " \"{t}\"");
                    }
                    wit::Arg::Text(_) => {
                        return Err(format!("a call of `{name}` with a text holding `\"` or a line break"))
                    }
                }
            }
        }
        wit::Statement::Text(code) => out.push_str(code),
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use ger_core::emit::Emitter;

    fn words(pairs: &[(char, f64)]) -> wit::Statement {
        wit::Statement::Words(pairs.iter().map(|&(letter, value)| wit::Word { letter, value }).collect())
    }

    fn shown(output: &[wit::Statement]) -> Result<Vec<String>, String> {
        let emitter = Emitter::new(4, false);
        render(output, "Test", Span::new(7, 1, 4))
            .map(|s| s.iter().map(|s| emitter.line(s)).collect())
            .map_err(|d| d.to_string())
    }

    #[test]
    fn typed_statements_read_as_the_same_text_would() {
        let output = [
            words(&[('G', 1.0), ('x', 10.5), ('Y', -0.25), ('F', 300.0)]),
            wit::Statement::Comment("rough pass; then".into()),
            wit::Statement::Comment("finish".into()),
            wit::Statement::Call(wit::WizardCall {
                name: "Pocket".into(),
                args: vec![wit::Arg::Number(1.5), wit::Arg::Text("deep".into())],
            }),
            wit::Statement::Text("G91\nX1".into()),
        ];
        let got = shown(&output).unwrap();
        // Comments are checked, then dropped by the parser as in any program.
        assert_eq!(got, ["G01 X10.5000 Y-0.2500 F300.0000", "Pocket 1.5 \"deep\"", "G91", "X1.0000"]);
    }

    #[test]
    fn malformed_statements_are_errors_at_the_call_naming_the_wizard() {
        let cases: [(wit::Statement, &str); 7] = [
            (wit::Statement::Comment("(nested)".into()), "a comment holding `(` or `)`"),
            (words(&[('%', 1.0)]), "bad statement (#1): `%` is not a G-code letter"),
            (words(&[('X', f64::NAN)]), "X has no finite value (NaN)"),
            (words(&[]), "a block with no words"),
            (wit::Statement::Comment("a\nb".into()), "a comment with a line break"),
            (wit::Statement::Text("G1 X".into()), "bad statement (#1, `G1 X`): `X` must be followed by a number"),
            (
                wit::Statement::Call(wit::WizardCall { name: "P1".into(), args: vec![] }),
                "a wizard's name is two or more letters",
            ),
        ];
        for (statement, expected) in cases {
            let got = shown(&[statement]).unwrap_err();
            assert!(got.starts_with("7:1: error: wizard `Test` returned"), "{got}");
            assert!(got.contains(expected), "{got} should contain {expected}");
        }
    }
}
