//! `ger lsp`: a language server for G-code over the Language Server
//! Protocol, answering from what ger knows of a program: its translation's
//! and `ger check`'s diagnostics as the user types, the meaning of a code,
//! where the tool is after a line, its subprograms and their calls.
//!
//! `server` runs the protocol (lsp-server's synchronous loop on the caller's
//! thread) and one worker thread that analyses (`analysis`: the engine's
//! passes, stopped between events when a newer edit comes); requests are
//! answered from the last finished analysis and never wait for a running
//! one. `text` keeps documents as the editor edits them, `outline` reads a
//! program's shape with ger's lexer, `codes` is the README's table of codes,
//! `actions` the fixes diagnostics name. The caller (the `ger` binary) gives
//! the wizard runtime: nothing here knows argv or wasmtime.

mod actions;
mod analysis;
mod codes;
mod hover;
mod outline;
mod server;
mod text;
mod watch;

use std::path::{Path, PathBuf};

use ger_engine::core::config::Config;
use ger_engine::core::wizard::Wizards;
use ger_engine::Settings;

pub use server::{serve, serve_stdio, Error};

/// Makes the wizards an analysis calls: those of the folder given, for the machine it runs on.
pub type WizardMaker = Box<dyn Fn(&Path, &Config) -> Box<dyn Wizards> + Send + Sync>;

/// Describes the wizards of the folder given, for hover and completion.
pub type WizardCatalog = Box<dyn Fn(&Path) -> Vec<WizardInfo> + Send + Sync>;

/// What a wizard says about itself (its `describe()`).
#[derive(Clone, Debug, Default)]
pub struct WizardInfo {
    pub name: String,
    pub summary: String,
    pub usage: String,
    pub params: Vec<WizardParam>,
    /// The file a go-to-definition on a call opens: its source's main file, or its component.
    pub source: Option<PathBuf>,
}

#[derive(Clone, Debug, Default)]
pub struct WizardParam {
    pub name: String,
    pub description: String,
    pub optional: bool,
}

/// What to analyse programs with.
pub struct Options {
    /// The machine: `ger.toml` beside each program unless a config is given.
    pub settings: Settings,
    /// The wizards folder; a relative one is taken beside each program.
    pub wizards_dir: PathBuf,
    pub wizards: WizardMaker,
    pub catalog: WizardCatalog,
}

impl Options {
    /// The wizards folder of a program in `dir`.
    fn wizards_dir(&self, dir: &Path) -> PathBuf {
        dir.join(&self.wizards_dir)
    }
}
