//! The machine a program runs on: its `ger.toml`, what the caller overrides,
//! and the tools and stock the program itself describes.

use std::path::{Path, PathBuf};

use ger_core::config::{locate, Config, GrblSettings, Step, StockConfig, TargetName};
use ger_core::diag::Diagnostic;
use ger_core::statement::{Dialect, Units};
use ger_core::tools;

use crate::report::Report;
use crate::source::{ReadError, Source};

/// What the caller says about the machine, over its config file.
#[derive(Clone, Debug, Default)]
pub struct Settings {
    /// The config file [default: `ger.toml` beside the program, if there is one].
    pub config: Option<PathBuf>,
    /// Accept the lenient dialect whatever the file says.
    pub lenient: bool,
    /// The machine's unit, whatever the file says.
    pub units: Option<Units>,
    /// The controller the output is for, whatever the file says.
    pub target: Option<TargetName>,
}

/// What a job does with the program. Only one that cuts a stock has a use
/// for the stock a program describes, so only it reads the program for one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Purpose {
    /// Translates it, or follows its path (`ger run`, `ger pulses`).
    Translate,
    /// Simulates it cutting a stock (`ger render`, `ger check`, `ger view`).
    Cut,
}

/// A machine that cannot be described.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    #[error(transparent)]
    Read(#[from] ReadError),
    /// A value of a config file that cannot be used, at its place in `text`.
    #[error("bad configuration {name}:{}:{}: {}", diagnostic.span.line, diagnostic.span.col, diagnostic.message)]
    Invalid { name: String, text: String, diagnostic: Diagnostic },
    #[error("bad CAMotics project {name}: {cause}")]
    Project { name: String, cause: tools::camotics::ProjectError },
}

impl ConfigError {
    /// The error as rustc would show it: a config's with the file's line under
    /// it (coloured when `styled`), anything else as one line, both ending in a newline.
    pub fn render(&self, styled: bool) -> String {
        match self {
            ConfigError::Invalid { name, text, diagnostic } => {
                let mut report = Report::default().failing_as("bad configuration");
                report.add(diagnostic.clone());
                report.render(name, text.as_bytes(), styled)
            }
            other => format!("error: {other}\n"),
        }
    }
}

impl Settings {
    /// The config file: the one given, or `ger.toml` beside the program if there is one.
    pub fn config_path(&self, source: &Source) -> Option<PathBuf> {
        match &self.config {
            Some(path) => Some(path.clone()),
            None => Some(source.beside("ger.toml")).filter(|p| p.is_file()),
        }
    }

    /// The machine for `source`: its config file, then these settings over
    /// it; the tools and stock the file leaves out come from the program's
    /// CAMotics project or its comments (see [`ger_core::tools`]).
    pub fn load(&self, source: &Source, purpose: Purpose) -> Result<Config, ConfigError> {
        let path = self.config_path(source);
        let name = path.as_ref().map(|path| path.display().to_string());
        let mut config = match (&path, &name) {
            (Some(path), Some(name)) => {
                let text = read(path, name)?;
                let mut config = Config::from_toml(&text).map_err(|diagnostic| ConfigError::Invalid {
                    name: name.clone(),
                    text,
                    diagnostic,
                })?;
                // Its folders are from the config's own, wherever ger runs.
                let folder = path.parent().unwrap_or(Path::new(""));
                for dir in &mut config.dialect.subroutine_path {
                    *dir = folder.join(&*dir);
                }
                if let Some(motion) = &mut config.machine.motion {
                    if let Some(file) = &motion.grbl_settings {
                        motion.grbl = Some(grbl_settings(&folder.join(file))?);
                    }
                }
                config
            }
            _ => Config::default(),
        };
        if self.lenient {
            config.dialect.name = Dialect::Lenient;
        }
        if let Some(units) = self.units {
            config.units = units;
        }
        if let Some(target) = self.target {
            config.target.name = target;
        }
        let stock_wanted = purpose == Purpose::Cut && config.stock == StockConfig::default();
        let wanted = !config.has_tool_table() || stock_wanted;
        let (project, described) = if wanted {
            (project(source)?, tools::scan(source.open(), config.dialect.name))
        } else {
            (None, tools::ProgramTools::default())
        };
        let project = project.as_ref().map(|(name, project)| (name.as_str(), project));
        tools::settle(&mut config, name.as_deref(), project, &described);
        Ok(config)
    }

    /// A value of the config file that cannot be used, at the key `steps`
    /// lead to; `None` when there is no config file to show it in.
    pub fn invalid(&self, source: &Source, steps: &[Step], message: &str) -> Option<ConfigError> {
        let path = self.config_path(source)?;
        // Read again, as a program's lines are to quote them: the config keeps no text.
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let diagnostic = Diagnostic::error(locate(&text, steps), message);
        Some(ConfigError::Invalid { name: path.display().to_string(), text, diagnostic })
    }
}

/// A file of GRBL settings (`[machine.motion] grbl_settings`), as `$$` prints them.
fn grbl_settings(path: &Path) -> Result<GrblSettings, ConfigError> {
    let name = path.display().to_string();
    let text = read(path, &name)?;
    GrblSettings::parse(&text).map_err(|diagnostic| ConfigError::Invalid { name, text, diagnostic })
}

fn read(path: &Path, name: &str) -> Result<String, ReadError> {
    std::fs::read_to_string(path).map_err(|cause| ReadError { name: name.to_string(), cause })
}

/// The CAMotics project of the program: `NAME.camotics` beside `NAME.nc`,
/// else a project in its folder that lists it. Its name is as the program's
/// folder is given; a bad one is an error, unless found by its list.
fn project(source: &Source) -> Result<Option<(String, tools::camotics::Project)>, ConfigError> {
    let Some(program) = source.path() else { return Ok(None) };
    let own = program.with_extension("camotics");
    if own.is_file() {
        let name = own.display().to_string();
        let text = read(&own, &name)?;
        let project =
            tools::camotics::parse(&text).map_err(|cause| ConfigError::Project { name: name.clone(), cause })?;
        return Ok(Some((name, project)));
    }
    let Some(file_name) = program.file_name().and_then(|n| n.to_str()) else { return Ok(None) };
    let Ok(entries) = std::fs::read_dir(source.dir()) else { return Ok(None) };
    let mut projects: Vec<PathBuf> = entries
        .flatten()
        .map(|entry| source.beside(entry.file_name()))
        .filter(|path| path.extension().is_some_and(|e| e == "camotics") && path.is_file())
        .collect();
    projects.sort();
    Ok(projects.into_iter().find_map(|path| {
        let project = tools::camotics::parse(&std::fs::read_to_string(&path).ok()?).ok()?;
        let listed = project.files.iter().any(|f| Path::new(f).file_name().is_some_and(|f| f == file_name));
        listed.then(|| (path.display().to_string(), project))
    }))
}
