//! Code actions: the fixes a diagnostic's own words make mechanical. Each is
//! worked out with the diagnostic (and carried in its `data`), so a request
//! for actions needs only what the editor sends back.

use std::collections::HashMap;

use lsp_types::{CodeAction, CodeActionKind, CodeActionOrCommand, TextEdit, Url, WorkspaceEdit};

use crate::analysis::Fix;
use ger_engine::core::diag::Diagnostic;

/// The fix of diagnostic `d`, whose span covers `culprit` in the text, if
/// its help names one replacement: "did you mean G01?", "write M30 to end
/// the program", or the F a rapid may not have.
pub fn fix(d: &Diagnostic, culprit: &str) -> Option<Fix> {
    let help = d.help.as_deref().unwrap_or("");
    // The culprit is one word: the one that the replacement stands for.
    if culprit.is_empty() || culprit.contains(char::is_whitespace) {
        return None;
    }
    if let Some(rest) = help.strip_prefix("did you mean ") {
        let code = rest.split('?').next().filter(|code| is_code(code))?;
        return Some(Fix { title: format!("Replace `{culprit}` with `{code}`"), replacement: code.to_string() });
    }
    if let Some(rest) = help.strip_prefix("write ") {
        let mut words = rest.split_whitespace();
        let code = words.next().filter(|code| is_code(code))?;
        // "write M30 to end the program", not "write M03 S1000 ...": the code alone replaces the culprit.
        if words.next() == Some("to") && is_code(culprit) {
            return Some(Fix { title: format!("Replace `{culprit}` with `{code}`"), replacement: code.to_string() });
        }
    }
    if d.message.starts_with("F is not allowed on a G00") && culprit.starts_with(['F', 'f']) {
        return Some(Fix { title: format!("Remove `{culprit}` from the rapid"), replacement: String::new() });
    }
    None
}

/// A G or M code: the letter and digits (`G01`, `M30`, `G59.1`).
fn is_code(word: &str) -> bool {
    let mut chars = word.chars();
    matches!(chars.next(), Some('G' | 'M' | 'g' | 'm'))
        && chars.as_str().starts_with(|c: char| c.is_ascii_digit())
        && chars.all(|c| c.is_ascii_digit() || c == '.')
}

/// The quick fixes of the diagnostics an editor sends with its request.
pub fn code_actions(uri: &Url, diagnostics: &[lsp_types::Diagnostic]) -> Vec<CodeActionOrCommand> {
    diagnostics
        .iter()
        .filter_map(|diagnostic| {
            let fix: Fix = serde_json::from_value(diagnostic.data.clone()?).ok()?;
            let edit = TextEdit { range: diagnostic.range, new_text: fix.replacement };
            Some(CodeActionOrCommand::CodeAction(CodeAction {
                title: fix.title,
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: Some(vec![diagnostic.clone()]),
                edit: Some(WorkspaceEdit {
                    changes: Some(HashMap::from([(uri.clone(), vec![edit])])),
                    ..Default::default()
                }),
                is_preferred: Some(true),
                ..CodeAction::default()
            }))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ger_engine::core::diag::Span;

    fn error(message: &str, help: &str) -> Diagnostic {
        Diagnostic::error(Span::new(1, 1, 3), message).with_help(help)
    }

    #[test]
    fn fixes_come_from_the_help_that_names_one_replacement() {
        let m02 = error("M02 is not accepted: ...", "write M30 to end the program");
        assert_eq!(fix(&m02, "M02").unwrap().replacement, "M30");
        let typo = error(
            "no wizard named `GO1` to run this call",
            "did you mean G01? (the letter O was typed for the digit zero)",
        );
        assert_eq!(
            fix(&typo, "GO1").unwrap(),
            Fix { title: "Replace `GO1` with `G01`".into(), replacement: "G01".into() }
        );
        let rapid = error(
            "F is not allowed on a G00 (rapid) move",
            "rapids run at the machine's rapid rate; put F on the next G01/G02/G03",
        );
        assert_eq!(fix(&rapid, "F100").unwrap().replacement, "");
        // Help that shows an example is no fix.
        assert!(fix(&error("G04 needs P", "write e.g. G04 P0.5"), "G04").is_none());
        // A span over more than the word: no telling what the replacement stands for.
        assert!(fix(&typo, "GO1 X10").is_none());
        assert!(fix(
            &error("an S word (spindle speed) goes with M03 or M04", "write e.g. M03 S1000, or run with --lenient"),
            "S1000"
        )
        .is_none());
    }
}
