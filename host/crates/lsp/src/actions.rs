//! Code actions: the fixes a diagnostic's own words make mechanical. Each is
//! worked out with the diagnostic (and carried in its `data`), so a request
//! for actions needs only what the editor sends back.

use std::collections::HashMap;
use std::path::Path;

use lsp_types::{
    CodeAction, CodeActionKind, CodeActionOrCommand, CreateFile, DocumentChangeOperation, DocumentChanges, OneOf,
    OptionalVersionedTextDocumentIdentifier, Position, Range, ResourceOp, TextDocumentEdit, TextEdit, Url,
    WorkspaceEdit,
};
use serde::{Deserialize, Serialize};

use ger_engine::core::diag::Diagnostic;

/// A mechanical fix of a diagnostic, carried in its `data` for code actions.
#[derive(Serialize, Deserialize, Debug, PartialEq)]
#[serde(tag = "fix", rename_all = "lowercase")]
pub enum Fix {
    /// `replacement` in place of the diagnostic's range.
    Replace { title: String, replacement: String },
    /// `dialect = "lenient"` in the config, where the help says `--lenient` takes it.
    Lenient,
}

/// The fixes of diagnostic `d`, whose span covers `culprit` in the text:
/// the one replacement its help names ("did you mean G01?", "write M30 to
/// end the program", the F a rapid may not have), and the lenient dialect
/// where the help says it takes the code.
pub fn fixes(d: &Diagnostic, culprit: &str) -> Vec<Fix> {
    let help = d.help.as_deref().unwrap_or("");
    let mut fixes: Vec<Fix> = replacement(d, culprit).into_iter().collect();
    if help.contains("--lenient") {
        fixes.push(Fix::Lenient);
    }
    fixes
}

fn replacement(d: &Diagnostic, culprit: &str) -> Option<Fix> {
    let help = d.help.as_deref().unwrap_or("");
    // The culprit is one word: the one that the replacement stands for.
    if culprit.is_empty() || culprit.contains(char::is_whitespace) {
        return None;
    }
    let replace = |code: &str| Fix::Replace {
        title: format!("Replace `{culprit}` with `{code}`"),
        replacement: code.to_string(),
    };
    if let Some(rest) = help.strip_prefix("did you mean ") {
        let code = rest.split('?').next().filter(|code| is_code(code))?;
        return Some(replace(code));
    }
    if let Some(rest) = help.strip_prefix("write ") {
        let mut words = rest.split_whitespace();
        let code = words.next().filter(|code| is_code(code))?;
        // "write M30 to end the program", not "write M03 S1000 ...": the code alone replaces the culprit.
        if words.next() == Some("to") && is_code(culprit) {
            return Some(replace(code));
        }
    }
    if d.message.starts_with("F is not allowed on a G00") && culprit.starts_with(['F', 'f']) {
        return Some(Fix::Replace { title: format!("Remove `{culprit}` from the rapid"), replacement: String::new() });
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

/// The quick fixes of the diagnostics an editor sends with its request, for
/// the program `uri` whose machine is described by `config` (which may not exist yet).
pub fn code_actions(uri: &Url, config: &Path, diagnostics: &[lsp_types::Diagnostic]) -> Vec<CodeActionOrCommand> {
    let mut actions = Vec::new();
    let mut lenient = None;
    for diagnostic in diagnostics {
        let Some(fixes) = diagnostic.data.clone().and_then(|data| serde_json::from_value::<Vec<Fix>>(data).ok()) else {
            continue;
        };
        for fix in fixes {
            let (title, edit) = match fix {
                Fix::Replace { title, replacement } => {
                    let edit = TextEdit { range: diagnostic.range, new_text: replacement };
                    let changes = HashMap::from([(uri.clone(), vec![edit])]);
                    (title, WorkspaceEdit { changes: Some(changes), ..WorkspaceEdit::default() })
                }
                // One action, whichever diagnostics suggest it.
                Fix::Lenient if lenient.is_none() => {
                    let Some(edit) = lenient_config(config) else { continue };
                    lenient = Some(actions.len());
                    (format!("Read this folder's programs in the lenient dialect ({})", config.display()), edit)
                }
                Fix::Lenient => continue,
            };
            let preferred = !title.starts_with("Read ");
            actions.push(CodeActionOrCommand::CodeAction(CodeAction {
                title,
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: Some(vec![diagnostic.clone()]),
                edit: Some(edit),
                is_preferred: Some(preferred),
                ..CodeAction::default()
            }));
        }
    }
    actions
}

/// The edit that makes `config` say `dialect = "lenient"`: its `dialect`
/// line replaced, or a line put first; the file made if there is none.
fn lenient_config(config: &Path) -> Option<WorkspaceEdit> {
    const LINE: &str = "dialect = \"lenient\"";
    let uri = Url::from_file_path(config).ok()?;
    let Ok(text) = std::fs::read_to_string(config) else {
        if config.exists() {
            return None;
        }
        let create = DocumentChangeOperation::Op(ResourceOp::Create(CreateFile {
            uri: uri.clone(),
            options: None,
            annotation_id: None,
        }));
        let insert = TextEdit { range: Range::default(), new_text: format!("{LINE}\n") };
        let edit = DocumentChangeOperation::Edit(TextDocumentEdit {
            text_document: OptionalVersionedTextDocumentIdentifier { uri, version: None },
            edits: vec![OneOf::Left(insert)],
        });
        return Some(WorkspaceEdit {
            document_changes: Some(DocumentChanges::Operations(vec![create, edit])),
            ..WorkspaceEdit::default()
        });
    };
    // A top-level key comes before the first table.
    let top = text.lines().take_while(|line| !line.trim_start().starts_with('['));
    let edit = match top.enumerate().find(|(_, line)| line.trim_start().starts_with("dialect") && line.contains('=')) {
        Some((n, line)) => {
            let end = Position { line: n as u32, character: line.encode_utf16().count() as u32 };
            TextEdit {
                range: Range { start: Position { line: n as u32, character: 0 }, end },
                new_text: LINE.to_string(),
            }
        }
        None => TextEdit { range: Range::default(), new_text: format!("{LINE}\n") },
    };
    Some(WorkspaceEdit { changes: Some(HashMap::from([(uri, vec![edit])])), ..WorkspaceEdit::default() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use ger_engine::core::diag::Span;

    fn error(message: &str, help: &str) -> Diagnostic {
        Diagnostic::error(Span::new(1, 1, 3), message).with_help(help)
    }

    fn replaced(fixes: &[Fix]) -> Option<&str> {
        fixes.iter().find_map(|fix| match fix {
            Fix::Replace { replacement, .. } => Some(replacement.as_str()),
            Fix::Lenient => None,
        })
    }

    #[test]
    fn fixes_come_from_the_help_that_names_one_replacement() {
        let m02 =
            error("M02 is not accepted: ...", "write M30 to end the program; or run with --lenient, which accepts M02");
        assert_eq!(
            fixes(&m02, "M02"),
            [Fix::Replace { title: "Replace `M02` with `M30`".into(), replacement: "M30".into() }, Fix::Lenient]
        );
        let typo = error(
            "no wizard named `GO1` to run this call",
            "did you mean G01? (the letter O was typed for the digit zero)",
        );
        assert_eq!(replaced(&fixes(&typo, "GO1")), Some("G01"));
        let rapid = error(
            "F is not allowed on a G00 (rapid) move",
            "rapids run at the machine's rapid rate; put F on the next G01/G02/G03",
        );
        assert_eq!(replaced(&fixes(&rapid, "F100")), Some(""));
        // Help that shows an example is no fix.
        assert!(fixes(&error("G04 needs P", "write e.g. G04 P0.5"), "G04").is_empty());
        // A span over more than the word: no telling what the replacement stands for.
        assert!(fixes(&typo, "GO1 X10").is_empty());
        let stray =
            error("an S word (spindle speed) goes with M03 or M04", "write e.g. M03 S1000, or run with --lenient");
        assert_eq!(fixes(&stray, "S1000"), [Fix::Lenient]);
    }

    #[test]
    fn the_lenient_dialect_goes_first_in_the_config_or_replaces_its_dialect() {
        let dir = tempfile::tempdir().unwrap();
        let config = dir.path().join("ger.toml");
        let edit_of = |edit: WorkspaceEdit| edit.changes.unwrap().into_values().next().unwrap().remove(0);
        std::fs::write(&config, "units = \"mm\"\n[check]\ndialect = 1\n").unwrap();
        let edit = edit_of(lenient_config(&config).unwrap());
        assert_eq!((edit.range, edit.new_text.as_str()), (Range::default(), "dialect = \"lenient\"\n"));
        std::fs::write(&config, "units = \"mm\"\n  dialect = \"strict\" # the GER manual's\n").unwrap();
        let edit = edit_of(lenient_config(&config).unwrap());
        let line = Range { start: Position { line: 1, character: 0 }, end: Position { line: 1, character: 39 } };
        assert_eq!((edit.range, edit.new_text.as_str()), (line, "dialect = \"lenient\""));
        // No file: it is made.
        std::fs::remove_file(&config).unwrap();
        let Some(DocumentChanges::Operations(operations)) = lenient_config(&config).unwrap().document_changes else {
            panic!("no operations")
        };
        assert!(matches!(&operations[0], DocumentChangeOperation::Op(ResourceOp::Create(_))));
    }
}
