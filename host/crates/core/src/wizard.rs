//! Wizard calls -> statements.
//!
//! A wizard call (`Pocket 75 30 10`) is handed to a [`Wizards`] implementation
//! with the machine state at the call; the statements it returns run in place
//! of the call (pass 00 splices them in, as it does subprogram bodies, so they
//! may call subprograms and other wizards). [`NoWizards`] is the runtime for
//! a translation with no wizards directory; the `ger-wasm` crate's
//! `WasmWizards` runs WebAssembly components from one (see `wit/wizard.wit`
//! for the contract).

use crate::diag::{clip, Diagnostic, Span};
use crate::state::CallState;
use crate::statement::{Statement, WizardArg};

/// One wizard call, as written.
pub struct Call<'a> {
    pub name: &'a str,
    pub args: &'a [WizardArg],
    pub span: Span,
}

/// The most characters of a wizard's name a diagnostic shows.
pub const SHOWN_NAME: usize = 64;
/// The most characters of a wizard's own message (or of its usage) a
/// diagnostic shows.
pub const SHOWN_MESSAGE: usize = 1000;

/// The key a wizard is found by: its name, ignoring case, `-` and `_`
/// (`BoltCircle` runs `boltcircle.wasm` or `bolt-circle.wasm`).
pub fn key(name: &str) -> String {
    name.chars().filter(|c| !matches!(c, '-' | '_')).flat_map(char::to_lowercase).collect()
}

/// A wizard's name as diagnostics show it: cut to [`SHOWN_NAME`] characters.
pub fn shown_name(name: &str) -> std::borrow::Cow<'_, str> {
    clip(name, SHOWN_NAME)
}

/// What a call becomes.
#[derive(Debug, Default)]
pub struct Expansion {
    /// The statements that replace the call.
    pub statements: Vec<Statement>,
    /// Warnings the wizard gave, at the call's span: the statements still run.
    pub warnings: Vec<Diagnostic>,
}

/// Runs wizards.
pub trait Wizards {
    /// What replaces `call`, each statement with the call's span, or a
    /// diagnostic (at the call's span) saying why nothing does.
    fn expand(&mut self, call: &Call, state: &CallState) -> Result<Expansion, Diagnostic>;

    /// A translation starts: what all the wizard calls of one program may use
    /// together (time, statements) is counted afresh from here.
    fn start(&mut self) {}
}

/// No wizards at all: every call is an error.
pub struct NoWizards;

impl Wizards for NoWizards {
    fn expand(&mut self, call: &Call, _: &CallState) -> Result<Expansion, Diagnostic> {
        let message = format!("no wizard named `{}` to run this call", shown_name(call.name));
        Err(Diagnostic::error(call.span, message).with_help(wizard_help(call.name)))
    }
}

/// `GO1` is an easy typo for `G01`; say so rather than only "no wizard".
pub fn wizard_help(name: &str) -> String {
    let upper = name.to_ascii_uppercase();
    let bytes = upper.as_bytes();
    // G and M codes have a few digits: a longer name is no typo of one.
    if (2..=6).contains(&bytes.len())
        && matches!(bytes[0], b'G' | b'M')
        && bytes[1] == b'O'
        && bytes[2..].iter().all(u8::is_ascii_digit)
    {
        return format!("did you mean {}0{}? (the letter O was typed for the digit zero)", &upper[..1], &upper[2..]);
    }
    "a word of two or more letters calls a wizard; ger looks for it in the wizards directory".to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn letter_o_for_zero_is_pointed_out() {
        assert!(wizard_help("GO1").contains("did you mean G01?"));
        assert!(wizard_help("mo3").contains("did you mean M03?"));
        assert!(wizard_help("Pocket").contains("wizards directory"));
    }
}
