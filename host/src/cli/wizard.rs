//! `ger wizard new|build|list`, and `ger run --watch`.

use std::io::{self, IsTerminal, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use clap::{Args, Subcommand};
use notify::{Event, EventKind, RecursiveMode, Watcher};

use super::error::{cannot_write, plain_error, with_help};
use super::{CommonArgs, WizardOptions};
use anyhow::{anyhow, bail, Context, Result};
use ger_core::config::Config;
use ger_core::diag::clip;
use ger_core::wizard::{Wizards, SHOWN_MESSAGE};
use ger_engine::Source as ProgramSource;
use ger_output::OutputFile;
use ger_wasm::build::{self, Progress, Source};
use ger_wasm::catalog::{self, Catalog};

#[derive(Subcommand)]
pub enum WizardCommand {
    /// Make a new wizard in the wizards directory; it builds and runs as it is.
    New {
        /// The wizard's name, as programs will call it (letters only), e.g. Slot.
        name: String,
        /// The language it is written in.
        #[arg(long, value_enum, default_value_t = Lang::Rust)]
        lang: Lang,
        #[command(flatten)]
        dir: DirArg,
    },
    /// Build wizards into NAME.wasm (all of them if none is named).
    Build {
        /// A wizard's name, or the path of its folder.
        names: Vec<String>,
        #[command(flatten)]
        dir: DirArg,
    },
    /// List the wizards with their usage, building those not built yet.
    List {
        #[command(flatten)]
        dir: DirArg,
        /// Do not build; list built wizards only.
        #[arg(long)]
        no_build: bool,
    },
}

/// The languages `ger wizard new` writes a wizard in.
#[derive(Clone, Copy, clap::ValueEnum)]
pub enum Lang {
    /// A crate on the wizard SDK (`Cargo.toml`, `src/lib.rs`).
    Rust,
    /// `app.py`, built with componentize-py.
    Python,
    /// `wizard.js`, built with jco.
    Js,
}

#[derive(Args)]
pub struct DirArg {
    /// The wizards directory.
    #[arg(long = "wizards", value_name = "DIR", default_value = "wizards")]
    dir: PathBuf,
}

pub fn main(command: WizardCommand) -> Result<i32> {
    match command {
        WizardCommand::New { name, lang, dir } => new(&name, lang, &dir.dir),
        WizardCommand::Build { names, dir } => build_named(&names, &dir.dir),
        WizardCommand::List { dir, no_build } => list(&dir.dir, no_build),
    }
}

/// Says what a build is doing on a terminal; in a pipe (tests, CI logs of
/// `ger run`) stderr keeps only diagnostics.
pub fn progress() -> Progress {
    let terminal = io::stderr().is_terminal();
    Box::new(move |message| {
        if terminal {
            eprintln!("   {message}...");
        }
    })
}

/// Always says what it is doing: the user asked for a build.
fn loud() -> Progress {
    Box::new(|message| eprintln!("   {message}..."))
}

fn scan(dir: &Path) -> Result<Catalog> {
    catalog::scan(dir).map_err(|message| with_help(message, "give the wizards directory with --wizards DIR"))
}

fn build_named(names: &[String], dir: &Path) -> Result<i32> {
    let mut targets = Vec::new();
    if names.is_empty() {
        let catalog = scan(dir)?;
        for entry in catalog.entries() {
            if let Some(source) = &entry.source {
                if ger_core::lex::is_reserved_name(&entry.name) {
                    eprintln!("skipped {}: named like a macro keyword, no program can call it", entry.name);
                    continue;
                }
                targets.push((source.clone(), entry.wasm.clone(), dir.to_path_buf()));
            }
        }
        if targets.is_empty() {
            eprintln!("{}: no wizard sources to build", dir.display());
        }
    }
    for name in names {
        let path = Path::new(name);
        if let Some(source) = Source::detect(path).filter(|_| path.is_dir()) {
            if let Some(file) = path.file_name() {
                refuse_reserved(&file.to_string_lossy())?;
            }
            // A folder given by path is built into NAME.wasm beside it.
            let folder = source.dir.canonicalize().unwrap_or_else(|_| source.dir.clone());
            let parent = folder.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf);
            let file = folder.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            targets.push((source, parent.join(format!("{file}.wasm")), parent));
            continue;
        }
        refuse_reserved(name)?;
        let catalog = scan(dir)?;
        match catalog.find(name).and_then(|e| Some((e.source.clone()?, e.wasm.clone()))) {
            Some((source, wasm)) => targets.push((source, wasm, dir.to_path_buf())),
            None => {
                let help = format!("the wizard sources in {} are: {}", dir.display(), sources(&catalog).join(", "));
                return Err(with_help(format!("no wizard source named `{name}` in {}", dir.display()), &help));
            }
        }
    }
    let mut failed = 0;
    let mut progress = loud();
    for (source, wasm, wizards) in targets {
        match build::build(&source, &wasm, &wizards, true, &mut progress) {
            Ok(()) => eprintln!("   built {}", wasm.display()),
            Err(err) => {
                failed += 1;
                eprint!("{}", plain_error(&format!("{}: {}", source.dir.display(), err.message), Some(&err.details)));
            }
        }
    }
    Ok(i32::from(failed > 0))
}

fn sources(catalog: &Catalog) -> Vec<String> {
    catalog.entries().filter(|e| e.source.is_some()).map(|e| e.name.clone()).collect()
}

fn list(dir: &Path, no_build: bool) -> Result<i32> {
    let catalog = scan(dir)?;
    let options = WizardOptions {
        dir: dir.to_path_buf(),
        no_build,
        wizard_time: 5.0,
        wizard_total_time: 5.0,
        wizard_memory: 256,
    };
    let mut runtime = options.runtime(&Config::default());
    let mut failed = 0;
    if catalog.entries().next().is_none() {
        println!("{}: no wizards", dir.display());
    }
    for entry in catalog.entries() {
        let language = entry.source.as_ref().map_or("prebuilt", |s| s.language.name());
        if ger_core::lex::is_reserved_name(&entry.name) {
            failed += 1;
            println!(
                "{:<40} ({}, {language}, named like a macro keyword: no program can call it)",
                entry.name, entry.name
            );
            continue;
        }
        if no_build && !entry.wasm.exists() {
            println!("{:<40} ({}, {language}, not built)", entry.name, entry.name);
            continue;
        }
        // Each description is a run of its own, with a call's time.
        runtime.start();
        match runtime.describe(&entry.name) {
            Ok(d) => {
                // A wizard's texts are its own, and may be any length.
                let shown = |text: &str| clip(text, SHOWN_MESSAGE).into_owned();
                println!("{:<40} ({}, {language})", shown(&d.usage), entry.name);
                println!("    {}", shown(&d.summary));
                for p in &d.params {
                    let optional = if p.optional { " (optional)" } else { "" };
                    println!("    {:<12} {}{optional}", shown(&p.name), shown(&p.description));
                }
            }
            Err(diagnostic) => {
                failed += 1;
                println!("{:<40} ({}, {language}, broken)", entry.name, entry.name);
                let message = diagnostic.message.clone();
                eprint!("{}", plain_error(&message, diagnostic.help.as_deref()));
            }
        }
    }
    Ok(i32::from(failed > 0))
}

/// A name no program could call a wizard by: one of the macro keywords or
/// expression functions the lenient dialect reads (`If`, `While`, `Sin`).
fn refuse_reserved(name: &str) -> Result<()> {
    if ger_core::lex::is_reserved_name(name) {
        let help = "a program reads it as a macro keyword or function, never as a wizard call: choose another name";
        return Err(with_help(format!("`{name}` cannot be a wizard's name"), help));
    }
    Ok(())
}

fn new(name: &str, lang: Lang, dir: &Path) -> Result<i32> {
    if name.len() < 2 || !name.chars().all(|c| c.is_ascii_alphabetic()) {
        let help = "a program calls a wizard by a word of two or more letters, e.g. `Slot 40 3`";
        return Err(with_help(format!("`{name}` cannot be a wizard's name"), help));
    }
    refuse_reserved(name)?;
    let folder = dir.join(name.to_ascii_lowercase());
    if folder.exists() {
        bail!("{} already exists", folder.display());
    }
    let write = |path: &Path, text: &str| {
        std::fs::create_dir_all(path.parent().expect("a file in a folder"))
            .and_then(|()| OutputFile::create(path))
            .and_then(|mut output| output.write_all(text.as_bytes()).and_then(|()| output.commit()))
            .with_context(|| cannot_write(path))
    };
    let edit = match lang {
        Lang::Rust => {
            let sdk = Path::new(env!("CARGO_MANIFEST_DIR")).join("../wizard-sdk");
            let sdk = sdk.canonicalize().map_err(|err| {
                let help = "`ger wizard new` uses the wizard-sdk folder of the ger source tree it was built from";
                with_help(format!("cannot find the wizard SDK at {}: {err}", sdk.display()), help)
            })?;
            std::fs::create_dir_all(&folder).with_context(|| format!("cannot create {}", folder.display()))?;
            let absolute = folder.canonicalize().unwrap_or_else(|_| folder.clone());
            let sdk_path = relative(&absolute, &sdk);
            write(&folder.join("Cargo.toml"), &manifest(&name.to_ascii_lowercase(), &sdk_path))?;
            write(&folder.join("src/lib.rs"), &template(name))?;
            "src/lib.rs"
        }
        Lang::Python => {
            write(&folder.join("app.py"), &include_str!("templates/app.py").replace("Square", name))?;
            "app.py"
        }
        Lang::Js => {
            write(&folder.join("wizard.js"), &include_str!("templates/wizard.js").replace("Square", name))?;
            "wizard.js"
        }
    };
    println!("created {}: edit {edit}, then call it as `{name} 20 1` in a program", folder.display());
    println!("ger run builds it when its sources change; `ger wizard build {name}` builds it now");
    Ok(0)
}

/// `to` as seen from `from` (both absolute): `../../wizard-sdk`.
fn relative(from: &Path, to: &Path) -> String {
    let from: Vec<Component> = from.components().collect();
    let to: Vec<Component> = to.components().collect();
    let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
    let mut path = PathBuf::new();
    for _ in common..from.len() {
        path.push("..");
    }
    for part in &to[common..] {
        path.push(part);
    }
    path.to_string_lossy().replace('\\', "/")
}

fn manifest(package: &str, sdk: &str) -> String {
    format!(
        r#"[package]
name = "{package}"
version = "0.1.0"
edition = "2021"
publish = false

[lib]
crate-type = ["cdylib"]

[dependencies]
ger-wizard-sdk = {{ path = "{sdk}" }}

# A wizard crate is its own workspace: `ger wizard build` builds it for wasm32-wasip2.
[workspace]

[profile.release]
opt-level = "s"
strip = true
"#
    )
}

fn template(name: &str) -> String {
    format!(
        r#"//! `{name} SIDE DEPTH`: mills a square outline from the current position.
//! Edit `expand` to make it yours; `ger run` rebuilds it when this changes.

use ger_wizard_sdk::*;

struct {name};

impl Wizard for {name} {{
    fn describe() -> Description {{
        Description::new("{name}", "mills a square outline from the current position", "{name} SIDE DEPTH")
            .param("SIDE", "side of the square along +X and +Y")
            .param("DEPTH", "depth below the current Z")
    }}

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {{
        let side = args.positive(0)?;
        let depth = args.positive(1)?;
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling {name}")?;
        let [x, y, z] = state.position;
        let mut out = vec![comment(format!("{name} {{side}} x {{depth}}"))];
        if state.distance == Distance::Incremental {{
            out.push(g(90).into());
        }}
        out.push(g1().z(z - depth).f(feed).into());
        out.push(g1().x(x + side).into());
        out.push(g1().y(y + side).into());
        out.push(g1().x(x).into());
        out.push(g1().y(y).into());
        out.push(g0().z(z).into());
        if state.distance == Distance::Incremental {{
            out.push(g(91).into());
        }}
        Ok(out)
    }}
}}

export_wizard!({name});
"#
    )
}

/// Runs `once`, then again after every change to the program, its config
/// or the wizards directory, until interrupted.
pub(super) fn watch(input: &ProgramSource, common: &CommonArgs, mut once: impl FnMut() -> Result<i32>) -> Result<i32> {
    let ProgramSource::File(program) = input else {
        bail!("--watch needs a program file, not standard input");
    };
    let config = match &common.config {
        Some(path) => path.clone(),
        None => input.dir().join("ger.toml"),
    };
    let wizards = &common.wizards.dir;
    let (tx, rx) = mpsc::channel::<notify::Result<Event>>();
    let mut watcher = notify::recommended_watcher(tx).context("cannot watch for changes")?;
    // Folders, not files: editors often save by replacing the file.
    let program_dir = input.dir();
    let mut watched = vec![(program_dir.clone(), RecursiveMode::NonRecursive)];
    if let Some(parent) = config.parent().filter(|p| !p.as_os_str().is_empty() && *p != program_dir) {
        watched.push((parent.to_path_buf(), RecursiveMode::NonRecursive));
    }
    if wizards.is_dir() {
        watched.push((wizards.clone(), RecursiveMode::Recursive));
    }
    for (path, mode) in &watched {
        watcher.watch(path, *mode).with_context(|| format!("cannot watch {}", path.display()))?;
    }
    let canonical = |p: &Path| p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
    let (program, config, wizards) = (canonical(program), canonical(&config), canonical(wizards));
    let relevant = |path: &Path| {
        let path = canonical(path);
        if path == program || path == config {
            return true;
        }
        // Build output and tool caches change during a run: not a reason to run again.
        path.strip_prefix(&wizards).is_ok_and(|rest| {
            !rest.components().any(|c| {
                let c = c.as_os_str().to_string_lossy();
                c == "target" || c == "node_modules" || c == "__pycache__" || c.starts_with('.')
            })
        })
    };
    // Saves come in bursts (truncate, write, rename): a burst is let settle
    // before the run, so one save is one run even when the burst began
    // while the last run was still going.
    let settle = |mut changed: bool| {
        std::thread::sleep(Duration::from_millis(100));
        while let Ok(event) = rx.try_recv() {
            changed |= matters(event, &relevant);
        }
        changed
    };
    loop {
        if let Err(err) = once() {
            eprint!("{}", super::error::render(&err));
        }
        // A .wasm written during the run is a wizard that run built: not a
        // change to react to. Any other change during the run is.
        let mut changed = false;
        while let Ok(event) = rx.try_recv() {
            changed |= matters(event, &|p: &Path| relevant(p) && p.extension().is_none_or(|e| e != "wasm"));
        }
        if changed {
            settle(true);
            continue;
        }
        eprintln!("ger: watching {} and {} for changes (Ctrl-C stops)", program.display(), wizards.display());
        while !changed {
            let event = rx.recv().map_err(|_| anyhow!("the file watcher stopped"))?;
            changed = settle(matters(event, &relevant));
        }
    }
}

fn matters(event: notify::Result<Event>, relevant: &impl Fn(&Path) -> bool) -> bool {
    match event {
        Ok(event) => !matches!(event.kind, EventKind::Access(_)) && event.paths.iter().any(|p| relevant(p)),
        Err(_) => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_climb_to_the_common_folder() {
        assert_eq!(relative(Path::new("/a/b/wizards/x"), Path::new("/a/b/wizard-sdk")), "../../wizard-sdk");
        assert_eq!(relative(Path::new("/a/w/x"), Path::new("/a/w/x/sdk")), "sdk");
    }
}
