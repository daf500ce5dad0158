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
        Err(Diagnostic::error(call.span, message).with_help(NO_WIZARD_HELP))
    }
}

/// What a call of no wizard gets as help. (`GO1`, the letter O typed for
/// a zero, never gets here: the lexer refuses it as the code meant.)
pub const NO_WIZARD_HELP: &str =
    "a word of two or more letters calls a wizard; ger looks for it in the wizards directory";
