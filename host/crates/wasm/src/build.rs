//! Building wizards from source, with no set-up by hand.
//!
//! A folder in the wizards directory is a wizard's source if it holds
//! `Cargo.toml` (Rust, on `wizard-sdk`), `app.py` (Python, componentize-py,
//! with the SDK's `ger_wizard.py` beside it) or `wizard.js` (JavaScript:
//! esbuild bundles it with the SDK's `ger_wizard.js`, as jco takes one
//! module, then jco with QuickJS). Building it writes `NAME.wasm` beside
//! the folder. The tools a build needs are fetched once into the wizards
//! directory's `target/ger/` from the pinned lists in `toolchain/` (a venv
//! for componentize-py, an npm tree for esbuild and jco), and the
//! `wasm32-wasip2` Rust target is added with rustup when it is missing.
//!
//! Builds of one directory take a file lock, so two gers starting at once
//! (or a test run's parallel cases) build a wizard once, not twice at once.

use std::fs::File;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::SystemTime;

use ger_output::{OutputFile, Replacement};

/// Tells the user what a build is doing (it can take a while).
pub type Progress = Box<dyn FnMut(&str)>;

/// The WIT contract, written out for the Python and JavaScript tools.
const WIT: &str = include_str!("../../../../wit/wizard.wit");
const WORLD: &str = "ger:wizard/wizard";
const REQUIREMENTS: &str = include_str!("toolchain/requirements.txt");
/// The Python face of the SDK, put beside every Python wizard built.
const PYTHON_SDK: &str = include_str!("../../../../wizard-sdk/python/ger_wizard.py");
/// The JavaScript face of the SDK, bundled with every JavaScript wizard built.
const JS_SDK: &str = include_str!("../../../../wizard-sdk/js/ger_wizard.js");
const PACKAGE_JSON: &str = include_str!("toolchain/package.json");
const PACKAGE_LOCK: &str = include_str!("toolchain/package-lock.json");
const RUST_TARGET: &str = "wasm32-wasip2";

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Language {
    Rust,
    Python,
    JavaScript,
}

impl Language {
    pub fn name(self) -> &'static str {
        match self {
            Language::Rust => "Rust",
            Language::Python => "Python",
            Language::JavaScript => "JavaScript",
        }
    }
}

/// A wizard's source folder.
#[derive(Clone, Debug, PartialEq)]
pub struct Source {
    pub dir: PathBuf,
    pub language: Language,
}

impl Source {
    /// The folder's language, from the files in it.
    pub fn detect(dir: &Path) -> Option<Source> {
        let language = if dir.join("Cargo.toml").is_file() {
            Language::Rust
        } else if dir.join("app.py").is_file() {
            Language::Python
        } else if dir.join("wizard.js").is_file() {
            Language::JavaScript
        } else {
            return None;
        };
        Some(Source { dir: dir.to_path_buf(), language })
    }
}

/// A build that failed: one line, and the tool's own words.
#[derive(Debug)]
pub struct BuildError {
    pub message: String,
    pub details: String,
}

impl BuildError {
    fn new(message: impl Into<String>, details: impl Into<String>) -> BuildError {
        BuildError { message: message.into(), details: details.into() }
    }
}

/// True if `wasm` is missing or older than any of the source's files
/// (for Rust, those of its path dependencies such as the SDK too).
pub fn stale(source: &Source, wasm: &Path) -> bool {
    let Ok(built) = wasm.metadata().and_then(|m| m.modified()) else {
        return true;
    };
    let mut dirs = vec![source.dir.clone()];
    if source.language == Language::Rust {
        dirs.extend(path_dependencies(&source.dir));
    }
    // Built with another ger's SDK, or none.
    let ger = wasm.with_file_name("target").join("ger");
    let sdk = match source.language {
        Language::Rust => None,
        Language::Python => Some((ger.join("python").join("ger_wizard.py"), PYTHON_SDK)),
        Language::JavaScript => Some((ger.join("js").join("sdk").join("ger_wizard.js"), JS_SDK)),
    };
    if sdk.is_some_and(|(path, text)| std::fs::read_to_string(path).ok().as_deref() != Some(text)) {
        return true;
    }
    dirs.iter().any(|dir| newest(dir).is_some_and(|t| t > built))
}

/// The newest modification time under `dir`, leaving out build output.
fn newest(dir: &Path) -> Option<SystemTime> {
    let mut latest = None;
    for entry in std::fs::read_dir(dir).ok()?.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with('.') || matches!(name.as_ref(), "target" | "node_modules" | "__pycache__") {
            continue;
        }
        let Ok(meta) = entry.metadata() else { continue };
        let time = if meta.is_dir() { newest(&entry.path()) } else { meta.modified().ok() };
        latest = latest.max(time);
    }
    latest
}

fn path_dependencies(dir: &Path) -> Vec<PathBuf> {
    let Ok(text) = std::fs::read_to_string(dir.join("Cargo.toml")) else { return Vec::new() };
    let Ok(manifest) = text.parse::<toml::Table>() else { return Vec::new() };
    let Some(deps) = manifest.get("dependencies").and_then(|d| d.as_table()) else { return Vec::new() };
    deps.values().filter_map(|d| d.get("path")?.as_str()).map(|p| dir.join(p)).collect()
}

/// Builds `source` into `wasm`. `wizards` is the wizards directory, whose
/// `target/` holds the build's intermediate files and tools.
/// Unless `force`, a wizard built by someone else meanwhile is left as it is.
pub fn build(
    source: &Source,
    wasm: &Path,
    wizards: &Path,
    force: bool,
    progress: &mut Progress,
) -> Result<(), BuildError> {
    let work = wizards.join("target");
    let ger = work.join("ger");
    std::fs::create_dir_all(&ger).map_err(|err| io_error("cannot create", &ger, &err))?;
    let lock = File::create(ger.join("build.lock")).map_err(|err| io_error("cannot create", &ger, &err))?;
    lock.lock().map_err(|err| io_error("cannot lock", &ger.join("build.lock"), &err))?;
    // Someone else may have built it while we waited for the lock.
    if !force && !stale(source, wasm) {
        return Ok(());
    }
    let name = source.dir.file_name().map_or_else(|| "wizard".into(), |n| n.to_string_lossy().into_owned());
    progress(&format!("building wizard `{name}` ({})", source.language.name()));
    // The compiler writes the file itself: the regular-file rule of `ger_output`, by path.
    let temp = Replacement::new(wasm).map_err(|err| io_error("cannot write", wasm, &err))?;
    // The tools are handed absolute paths: each resolves a relative one
    // against a folder of its own choosing (jco against the entry's).
    let absolute = |path: &Path| std::path::absolute(path).map_err(|err| io_error("cannot find", path, &err));
    let source = Source { dir: absolute(&source.dir)?, language: source.language };
    let (work, ger, out) = (absolute(&work)?, absolute(&ger)?, absolute(temp.path())?);
    match source.language {
        Language::Rust => build_rust(&source, &work, &out, progress)?,
        Language::Python => build_python(&source, &ger, &out, progress)?,
        Language::JavaScript => build_javascript(&source, &ger, &out, progress)?,
    }
    temp.commit().map_err(|err| io_error("cannot write", wasm, &err))?;
    Ok(())
}

fn io_error(what: &str, path: &Path, err: &io::Error) -> BuildError {
    BuildError::new(format!("{what} {}: {err}", path.display()), String::new())
}

/// Runs `command`; a tool that is missing or fails is a [`BuildError`]
/// that says which and shows what it printed.
fn run(command: &mut Command, what: &str, missing_help: &str) -> Result<Output, BuildError> {
    let program = command.get_program().to_string_lossy().into_owned();
    let output = command.output().map_err(|err| {
        if err.kind() == io::ErrorKind::NotFound {
            BuildError::new(format!("{program} is not installed"), missing_help)
        } else {
            BuildError::new(format!("cannot run {program}: {err}"), String::new())
        }
    })?;
    if output.status.success() {
        return Ok(output);
    }
    let mut details = String::from_utf8_lossy(&output.stderr).trim_end().to_string();
    let stdout = String::from_utf8_lossy(&output.stdout);
    if !stdout.trim().is_empty() {
        details = format!("{}\n{details}", stdout.trim_end());
    }
    Err(BuildError::new(what.to_string(), tail(&details, 60)))
}

/// The last `n` lines: where compilers put the error that stopped them.
fn tail(text: &str, n: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

fn build_rust(source: &Source, work: &Path, out: &Path, progress: &mut Progress) -> Result<(), BuildError> {
    ensure_rust_target(progress)?;
    let manifest = source.dir.join("Cargo.toml");
    // A CARGO_TARGET_DIR set by the user is shared by all wizard directories.
    let target_dir = std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| work.join("cargo"), PathBuf::from);
    let mut cargo = Command::new("cargo");
    cargo
        .args(["build", "--release", "--message-format=short", "--color=never", "--target", RUST_TARGET])
        .arg("--manifest-path")
        .arg(&manifest)
        .arg("--target-dir")
        .arg(&target_dir)
        // Set when ger itself runs under cargo; the wizard's target is fixed above.
        .env_remove("CARGO_BUILD_TARGET");
    let output = run(&mut cargo, "the Rust compiler reported errors", "install Rust with rustup")?;
    drop(output);
    let lib = library_name(&manifest)?;
    let built = target_dir.join(RUST_TARGET).join("release").join(format!("{lib}.wasm"));
    std::fs::copy(&built, out).map_err(|err| io_error("cannot copy", &built, &err))?;
    Ok(())
}

/// The file name cargo gives the library: `[lib] name`, else the package
/// name with `-` as `_`.
fn library_name(manifest: &Path) -> Result<String, BuildError> {
    let text = std::fs::read_to_string(manifest).map_err(|err| io_error("cannot read", manifest, &err))?;
    let table: toml::Table = text
        .parse()
        .map_err(|err| BuildError::new(format!("{} is not valid TOML", manifest.display()), format!("{err}")))?;
    let lib = table.get("lib").and_then(|l| l.get("name")).and_then(|n| n.as_str());
    let package = table.get("package").and_then(|p| p.get("name")).and_then(|n| n.as_str());
    match lib.or(package) {
        Some(name) => Ok(name.replace('-', "_")),
        None => Err(BuildError::new(format!("{} names no package", manifest.display()), String::new())),
    }
}

/// Adds the wasm32-wasip2 target with rustup if the toolchain lacks it.
fn ensure_rust_target(progress: &mut Progress) -> Result<(), BuildError> {
    let sysroot = run(
        Command::new("rustc").args(["--print", "sysroot"]),
        "rustc cannot tell its sysroot",
        "install Rust with rustup (https://rustup.rs)",
    )?;
    let sysroot = PathBuf::from(String::from_utf8_lossy(&sysroot.stdout).trim());
    if sysroot.join("lib/rustlib").join(RUST_TARGET).is_dir() {
        return Ok(());
    }
    progress(&format!("adding the Rust target {RUST_TARGET} with rustup"));
    run(
        Command::new("rustup").args(["target", "add", RUST_TARGET]),
        "rustup could not add the wasm32-wasip2 target",
        "Rust wizards need the wasm32-wasip2 target; without rustup, install it the way your Rust was installed",
    )?;
    Ok(())
}

/// Writes `text` to `path` unless it is already there, so tools that watch
/// modification times are not woken for nothing.
fn write_if_changed(path: &Path, text: &str) -> Result<bool, BuildError> {
    if std::fs::read_to_string(path).is_ok_and(|old| old == text) {
        return Ok(false);
    }
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(|err| io_error("cannot create", parent, &err))?;
    }
    let mut output = OutputFile::create(path).map_err(|err| io_error("cannot write", path, &err))?;
    output
        .write_all(text.as_bytes())
        .and_then(|()| output.commit())
        .map_err(|err| io_error("cannot write", path, &err))?;
    Ok(true)
}

fn wit_dir(ger: &Path) -> Result<PathBuf, BuildError> {
    let dir = ger.join("wit");
    write_if_changed(&dir.join("wizard.wit"), WIT)?;
    Ok(dir)
}

fn build_python(source: &Source, ger: &Path, out: &Path, progress: &mut Progress) -> Result<(), BuildError> {
    let venv = ger.join("python");
    let tool = venv.join("bin").join("componentize-py");
    let pins = venv.join("ger-requirements.txt");
    if !tool.is_file() || std::fs::read_to_string(&pins).ok().as_deref() != Some(REQUIREMENTS) {
        progress("installing componentize-py (once) into the wizards directory's target/");
        run(
            Command::new("python3").arg("-m").arg("venv").arg("--clear").arg(&venv),
            "python3 could not create a virtual environment",
            "Python wizards need Python 3.10 or newer (python3) with its venv module",
        )?;
        let requirements = ger.join("requirements.txt");
        write_if_changed(&requirements, REQUIREMENTS)?;
        run(
            Command::new(venv.join("bin").join("pip"))
                .args(["install", "--quiet", "--disable-pip-version-check", "-r"])
                .arg(&requirements),
            "pip could not install componentize-py",
            "",
        )?;
        write_if_changed(&pins, REQUIREMENTS)?;
    }
    let wit = wit_dir(ger)?;
    let sdk = ger.join("python");
    write_if_changed(&sdk.join("ger_wizard.py"), PYTHON_SDK)?;
    run(
        Command::new(&tool)
            .arg("-d")
            .arg(&wit)
            .args(["-w", WORLD, "componentize", "-p"])
            .arg(&source.dir)
            .arg("-p")
            .arg(&sdk)
            .arg("app")
            .arg("-o")
            .arg(out),
        "componentize-py could not build the wizard",
        "",
    )?;
    Ok(())
}

fn build_javascript(source: &Source, ger: &Path, out: &Path, progress: &mut Progress) -> Result<(), BuildError> {
    let js = ger.join("js");
    let bin = js.join("node_modules").join(".bin");
    let (jco, esbuild) = (bin.join("jco"), bin.join("esbuild"));
    let changed = write_if_changed(&js.join("package.json"), PACKAGE_JSON)?
        | write_if_changed(&js.join("package-lock.json"), PACKAGE_LOCK)?;
    if changed || !jco.is_file() || !esbuild.is_file() {
        progress("installing esbuild and jco (once) into the wizards directory's target/");
        // `npm install` follows the lock file; `npm ci` would refuse it, as
        // npm leaves other platforms' optional packages out of the lock.
        run(
            Command::new("npm")
                .args(["install", "--no-save", "--no-audit", "--no-fund", "--loglevel=error"])
                .current_dir(&js),
            "npm could not install esbuild and jco",
            "JavaScript wizards need Node.js 18 or newer with npm",
        )?;
    }
    // `import ... from "ger_wizard"` finds the SDK as a package would be found.
    let sdk = js.join("sdk");
    write_if_changed(&sdk.join("ger_wizard.js"), JS_SDK)?;
    let name = source.dir.file_name().map_or_else(|| "wizard".into(), |n| n.to_string_lossy().into_owned());
    let bundle = js.join("bundles").join(format!("{name}.js"));
    run(
        Command::new(&esbuild)
            .arg(source.dir.join("wizard.js"))
            .args(["--bundle", "--format=esm", "--platform=neutral", "--external:ger:*", "--log-level=warning"])
            .arg(format!("--outfile={}", bundle.display()))
            .env("NODE_PATH", &sdk),
        "esbuild could not bundle the wizard",
        "",
    )?;
    let wit = wit_dir(ger)?;
    run(
        Command::new(&jco)
            .arg("componentize")
            .arg(&bundle)
            .arg("--wit")
            .arg(&wit)
            .args(["-n", "wizard", "--backend", "quickjs", "--backend-qjs-disable-async", "-o"])
            .arg(out),
        "jco could not build the wizard",
        "",
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `wit/wizard.wit` names: the host's functions and the statement's cases.
    fn contract() -> (Vec<String>, Vec<String>) {
        let mut resolve = wit_parser::Resolve::new();
        resolve.push_file(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../wit/wizard.wit")).unwrap();
        let interface = |name: &str| {
            let found = resolve.interfaces.iter().find(|(_, i)| i.name.as_deref() == Some(name));
            found.unwrap_or_else(|| panic!("no interface {name}")).1
        };
        let functions = interface("host").functions.keys().cloned().collect();
        let statement = interface("types").types["statement"];
        let wit_parser::TypeDefKind::Variant(variant) = &resolve.types[statement].kind else {
            panic!("statement is a variant")
        };
        (functions, variant.cases.iter().map(|case| case.name.clone()).collect())
    }

    #[test]
    fn the_javascript_sdk_offers_all_the_contract_does() {
        let (functions, cases) = contract();
        assert!(JS_SDK.contains("from \"ger:wizard/host@0.2.0\""), "ger_wizard.js imports another host");
        for function in functions {
            // jco names `find-tool` findTool.
            let mut parts = function.split('-');
            let first = parts.next().unwrap().to_string();
            let js = parts.fold(first, |name, part| name + &part[..1].to_uppercase() + &part[1..]);
            assert!(
                JS_SDK.contains(&format!("export const {js} = (")) && JS_SDK.contains(&format!("host.{js}(")),
                "ger_wizard.js has no wrapper of the host's `{function}`"
            );
        }
        for case in cases {
            assert!(JS_SDK.contains(&format!("tag: \"{case}\"")), "ger_wizard.js never makes a `{case}` statement");
        }
        for export in ["describe() {", "expand(args, state) {"] {
            assert!(JS_SDK.contains(export), "ger_wizard.js's exportWizard lacks `{export}`");
        }
    }

    #[test]
    fn the_python_sdk_offers_all_the_contract_does() {
        let (functions, cases) = contract();
        assert_eq!(functions.len(), 6, "{functions:?}");
        for function in functions {
            let python = function.replace('-', "_");
            assert!(
                PYTHON_SDK.contains(&format!("def {python}(")) && PYTHON_SDK.contains(&format!("_host.{python}(")),
                "ger_wizard.py has no wrapper of the host's `{function}`"
            );
        }
        for case in cases {
            let class = format!("Statement_{}{}", case[..1].to_uppercase(), &case[1..]);
            assert!(PYTHON_SDK.contains(&class), "ger_wizard.py never makes a {class}");
        }
        for export in ["def describe(self)", "def expand(self, args, state)"] {
            assert!(PYTHON_SDK.contains(export), "ger_wizard.py's export lacks `{export}`");
        }
    }
}
