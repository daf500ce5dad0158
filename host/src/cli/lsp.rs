//! `ger lsp`'s command line: the machine and the wizard runtime; the server
//! is the `ger-lsp` crate, speaking on standard input and output.

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;

use super::{UnitsArg, WizardOptions};
use ger_core::config::Config;
use ger_core::diag::clip;
use ger_core::wizard::{key, Wizards, SHOWN_MESSAGE};
use ger_engine::Settings;
use ger_lsp::{WizardInfo, WizardParam};
use ger_wasm::build::Language;
use ger_wasm::catalog;

#[derive(Args)]
pub(crate) struct LspArgs {
    /// The machine description for every program [default: ger.toml beside each program, if there is one].
    #[arg(long, value_name = "FILE")]
    config: Option<PathBuf>,
    /// The machine's unit, overriding the config file.
    #[arg(long, value_enum)]
    units: Option<UnitsArg>,
    /// Read every program in the lenient dialect.
    #[arg(long)]
    lenient: bool,
    /// Serve on standard input and output (the only way; editors pass it).
    #[arg(long)]
    stdio: bool,
    /// The wizards directory; a relative one is beside each program.
    #[command(flatten)]
    wizards: WizardOptions,
}

pub(crate) fn main(args: LspArgs) -> Result<i32> {
    let settings =
        Settings { config: args.config, lenient: args.lenient, units: args.units.map(Into::into), target: None };
    let runtime = args.wizards.clone();
    let described = args.wizards;
    let options = ger_lsp::Options {
        settings,
        wizards_dir: runtime.dir.clone(),
        wizards: Box::new(move |dir: &Path, config: &Config| {
            let options = WizardOptions { dir: dir.to_path_buf(), ..runtime.clone() };
            Box::new(options.runtime(config)) as Box<dyn Wizards>
        }),
        catalog: Box::new(move |dir: &Path| describe(&WizardOptions { dir: dir.to_path_buf(), ..described.clone() })),
    };
    ger_lsp::serve_stdio(options)?;
    Ok(0)
}

/// What each wizard of the folder says about itself (`ger wizard list`'s
/// descriptions), for those built: describing builds nothing (a call does,
/// unless `--no-build`). One that cannot describe itself is left out.
fn describe(options: &WizardOptions) -> Vec<WizardInfo> {
    let Ok(found) = catalog::scan(&options.dir) else { return Vec::new() };
    let mut runtime = WizardOptions { no_build: true, ..options.clone() }.runtime(&Config::default());
    let shown = |text: &str| clip(text, SHOWN_MESSAGE).into_owned();
    found
        .entries()
        .filter(|entry| entry.wasm.exists())
        .filter_map(|entry| {
            runtime.start();
            let d = runtime.describe(&entry.name).ok()?;
            let source = match &entry.source {
                Some(source) => main_file(&source.dir, source.language),
                None => entry.wasm.clone(),
            };
            // Programs call it by its file's name; as it writes that name, if it does.
            let name = if key(&d.name) == key(&entry.name) { &d.name } else { &entry.name };
            Some(WizardInfo {
                name: shown(name),
                summary: shown(&d.summary),
                usage: shown(&d.usage),
                params: d
                    .params
                    .iter()
                    .map(|p| WizardParam {
                        name: shown(&p.name),
                        description: shown(&p.description),
                        optional: p.optional,
                    })
                    .collect(),
                source: Some(source),
            })
        })
        .collect()
}

/// The file a wizard's source starts in, as `ger wizard new` writes it.
fn main_file(dir: &Path, language: Language) -> PathBuf {
    let file = match language {
        Language::Rust => "src/lib.rs",
        Language::Python => "app.py",
        Language::JavaScript => "wizard.js",
    };
    Some(dir.join(file)).filter(|path| path.is_file()).unwrap_or_else(|| dir.to_path_buf())
}
