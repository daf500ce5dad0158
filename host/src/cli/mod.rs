//! The command line. The only module that knows about argv, files, standard
//! streams and terminals; everything else takes readers and returns values.

mod check;
mod render;
mod report;
mod view;
mod wizard;

use std::fs::File;
use std::io::{self, BufRead, BufReader, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};

use clap::{Args, Parser, Subcommand, ValueEnum};

use ger_core::config::{locate, Config, DialectConfig, Step, StockConfig};
use ger_core::diag::Diagnostic;
use ger_core::emit::{preamble, Emitter};
use ger_core::lex::{Lexed, Lexer, TokenKind};
use ger_core::parse::parse;
use ger_core::passes::{self, translate, Event, Library, Options, LAST_STAGE};
use ger_core::statement::{Dialect, Units};
use ger_core::tools;
use ger_core::wizard::Wizards;
use ger_output::OutputFile;
use ger_wasm::{Limits, WasmWizards};
use report::{plain_error, read_error, Report};

#[derive(Parser)]
#[command(name = "ger", version, about = "G-code emulatoR, verifiER and transpilER for 3-axis mills and routers")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Translate a program to simple G-code (absolute G00-G03 in one unit).
    #[command(visible_alias = "translate")]
    Run(RunArgs),
    /// Verify the program: translation, then what would break a part or a
    /// machine (rapids into stock, spindle off, deep cuts, travel...), and a summary.
    Check(Box<check::CheckArgs>),
    /// Show the lexer's view: one token a line.
    Tokens(InputArg),
    /// Show the parser's view: one statement a line, before any pass.
    Parse(InputArg),
    /// Simulate the cut and write a picture (2D, 3D), a mesh (STL) or the toolpath.
    Render(Box<render::RenderArgs>),
    /// Show the step/direction pulses a stepper controller would get.
    Pulses(render::PulsesArgs),
    /// Make, build and list wizards.
    #[command(subcommand)]
    Wizard(wizard::WizardCommand),
    /// Serve a page on 127.0.0.1 that shows the program, its translation, its
    /// diagnostics and the simulated part, updated live as any of them changes.
    View(Box<view::ViewArgs>),
}

#[derive(Args)]
struct InputArg {
    /// The G-code program (`-` reads standard input).
    file: PathBuf,
}

#[derive(Args)]
struct CommonArgs {
    /// The G-code program (`-` reads standard input).
    file: PathBuf,
    /// The machine description [default: ger.toml beside FILE, if there is one].
    #[arg(long, value_name = "FILE")]
    config: Option<PathBuf>,
    /// The machine's unit, overriding the config file.
    #[arg(long, value_enum)]
    units: Option<UnitsArg>,
    /// Also accept what CAM programs and controllers commonly emit (canned
    /// cycles, G28/G30/G53, G10, S and T alone, ...), translating it away.
    #[arg(long)]
    lenient: bool,
    #[command(flatten)]
    wizards: WizardOptions,
}

/// Where wizards come from and what a call of one may use.
#[derive(Args, Clone)]
pub(crate) struct WizardOptions {
    /// The wizards directory: NAME.wasm components and the folders they are built from.
    #[arg(long = "wizards", value_name = "DIR", default_value = "wizards")]
    pub dir: PathBuf,
    /// Never build a wizard: one whose .wasm is missing is an error, a stale one runs as it is.
    #[arg(long)]
    pub no_build: bool,
    /// Seconds one wizard call may run.
    #[arg(long, value_name = "SECONDS", default_value_t = 1.0, value_parser = positive_seconds)]
    pub wizard_time: f64,
    /// Seconds all the wizard calls of one program (nested ones too) may run together.
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0, value_parser = positive_seconds)]
    pub wizard_total_time: f64,
    /// MiB of memory one wizard call may use.
    #[arg(long, value_name = "MIB", default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub wizard_memory: u32,
}

fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        // Below a millisecond no call could run at all.
        Ok(s) if (0.001..=3600.0).contains(&s) => Ok(s),
        _ => Err("expected a number of seconds from 0.001 to 3600".to_string()),
    }
}

impl WizardOptions {
    /// The runtime for a translation on `config`'s machine.
    pub fn runtime(&self, config: &Config) -> WasmWizards {
        let limits = Limits {
            time: std::time::Duration::from_secs_f64(self.wizard_time),
            program_time: std::time::Duration::from_secs_f64(self.wizard_total_time),
            memory: (self.wizard_memory as usize) << 20,
            ..Limits::default()
        };
        let progress = (!self.no_build).then(wizard::progress);
        WasmWizards::new(&self.dir, config, limits, progress)
    }
}

#[derive(Args)]
struct RunArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Write the translation here instead of standard output (`-`).
    #[arg(short, long, value_name = "OUT")]
    output: Option<PathBuf>,
    /// Stop after this pass: 0 subprograms, 1 units, 2 offsets, 3 polar,
    /// 4 absolute, 5 cutter comp.
    #[arg(long, default_value_t = LAST_STAGE, value_parser = clap::value_parser!(u8).range(0..=LAST_STAGE as i64))]
    stage: u8,
    /// Leave out the N<line> on each output line.
    #[arg(long)]
    no_line_numbers: bool,
    /// Translate again whenever the program, the config or a wizard changes.
    #[arg(long)]
    watch: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum UnitsArg {
    #[value(name = "in", alias = "inch")]
    Inch,
    Mm,
}

/// Runs ger with the process's arguments; returns the exit status:
/// 0 clean (warnings allowed), 1 errors, 2 usage.
pub fn main() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => {
            let _ = err.print();
            return if err.use_stderr() { 2 } else { 0 };
        }
    };
    let result = match cli.command {
        Command::Run(args) => run(&args),
        Command::Check(args) => check::check(&args),
        Command::Tokens(args) => tokens(&args.file),
        Command::Parse(args) => parse_only(&args.file),
        Command::Render(args) => render::render(&args),
        Command::Pulses(args) => render::pulses(&args),
        Command::Wizard(command) => wizard::main(command),
        Command::View(args) => view::main(*args),
    };
    match result {
        Ok(status) => status,
        Err(message) => {
            eprint!("{message}");
            1
        }
    }
}

/// A program to read: a file, which can be read again from the start, or
/// standard input, held in memory so it can be too; or text held in memory
/// under a name, with the folder it belongs in (`ger view`'s, edited in the page).
enum Input {
    File(PathBuf),
    Stdin(Vec<u8>),
    Text { name: String, dir: PathBuf, text: std::sync::Arc<str> },
}

impl Input {
    fn new(path: &Path) -> Result<Input, String> {
        if path == Path::new("-") {
            let mut buffer = Vec::new();
            io::stdin().read_to_end(&mut buffer).map_err(|err| read_error("standard input", &err))?;
            return Ok(Input::Stdin(buffer));
        }
        // Open once now so a missing file is reported before anything runs.
        File::open(path).map_err(|err| read_error(&path.display().to_string(), &err))?;
        Ok(Input::File(path.to_path_buf()))
    }

    fn name(&self) -> String {
        match self {
            Input::File(path) => path.display().to_string(),
            Input::Stdin(_) => "<stdin>".to_string(),
            Input::Text { name, .. } => name.clone(),
        }
    }

    /// A fresh reader from the start of the program.
    fn open(&self) -> Box<dyn BufRead + '_> {
        match self {
            Input::File(path) => match File::open(path) {
                Ok(file) => Box::new(BufReader::with_capacity(1 << 16, file)),
                Err(err) => Box::new(FailingReader(Some(err))),
            },
            Input::Stdin(buffer) => Box::new(buffer.as_slice()),
            Input::Text { text, .. } => Box::new(text.as_bytes()),
        }
    }

    /// The program's file, if it has one.
    fn path(&self) -> Option<PathBuf> {
        match self {
            Input::File(path) => Some(path.clone()),
            Input::Stdin(_) => None,
            Input::Text { name, dir, .. } => Some(dir.join(name)),
        }
    }

    /// The file `name` in the program's folder, named as the program's path
    /// names that folder (`ger.toml` for `part.nc`, `jobs/ger.toml` for
    /// `jobs/part.nc`), as messages show it.
    fn beside(&self, name: impl AsRef<Path>) -> PathBuf {
        match self {
            Input::File(path) => path.with_file_name(name.as_ref()),
            Input::Stdin(_) => name.as_ref().to_path_buf(),
            Input::Text { dir, .. } => dir.join(name),
        }
    }

    fn dir(&self) -> PathBuf {
        match self {
            Input::File(path) => match path.parent() {
                Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
                _ => PathBuf::from("."),
            },
            Input::Stdin(_) => PathBuf::from("."),
            Input::Text { dir, .. } => dir.clone(),
        }
    }
}

/// A reader whose first read fails: the lexer turns that into a diagnostic.
struct FailingReader(Option<io::Error>);

impl Read for FailingReader {
    fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
        self.0.take().map_or(Ok(0), Err)
    }
}

impl BufRead for FailingReader {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        self.0.take().map_or(Ok(&[]), Err)
    }

    fn consume(&mut self, _: usize) {}
}

/// The config file: `args.config`, or `ger.toml` beside the program if there is one.
fn config_path(args: &CommonArgs, input: &Input) -> Option<PathBuf> {
    match &args.config {
        Some(path) => Some(path.clone()),
        None => Some(input.beside("ger.toml")).filter(|p| p.is_file()),
    }
}

/// A config's error, rendered as rustc would (with colour when `styled`).
fn config_diagnostic(name: &str, text: &str, diagnostic: Diagnostic, styled: bool) -> String {
    let mut report = Report::default();
    report.add(diagnostic);
    report.render(name, text.as_bytes(), styled).replace("could not translate the program", "bad configuration")
}

/// A value of the config file that cannot be used, shown at the key `steps` lead to.
fn config_error(args: &CommonArgs, input: &Input, steps: &[Step], message: &str) -> String {
    let Some(path) = config_path(args, input) else { return plain_error(message, None) };
    // Read again, as a program's lines are to quote them: the config keeps no text.
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    config_diagnostic(&path.display().to_string(), &text, Diagnostic::error(locate(&text, steps), message), styled())
}

/// The machine: `args.config`, or `ger.toml` beside the program. A bad one is
/// an error rendered as rustc would (with colour when `styled`). The tools
/// and stock the file leaves out come from the program (see [`ger_core::tools`]).
/// What a command does with the program. Only one that cuts a stock has a
/// use for the stock a program describes, so only it reads the program for one.
#[derive(Clone, Copy, PartialEq)]
enum Purpose {
    /// Translates it, or follows its path (`ger run`, `ger pulses`).
    Translate,
    /// Simulates it cutting a stock (`ger render`, `ger check`, `ger view`).
    Cut,
}

fn load_config(args: &CommonArgs, input: &Input, purpose: Purpose, styled: bool) -> Result<Config, String> {
    let path = config_path(args, input);
    let name = path.as_ref().map(|path| path.display().to_string());
    let mut config = match (&path, &name) {
        (Some(path), Some(name)) => {
            let text = std::fs::read_to_string(path).map_err(|err| read_error(name, &err))?;
            Config::from_toml(&text).map_err(|diagnostic| config_diagnostic(name, &text, diagnostic, styled))?
        }
        _ => Config::default(),
    };
    if args.lenient {
        config.dialect.name = Dialect::Lenient;
    }
    if let Some(units) = args.units {
        config.units = match units {
            UnitsArg::Inch => Units::Inch,
            UnitsArg::Mm => Units::Mm,
        };
    }
    let stock_wanted = purpose == Purpose::Cut && config.stock == StockConfig::default();
    let wanted = !config.has_tool_table() || stock_wanted;
    let (project, described) = if wanted {
        (project(input)?, tools::scan(input.open(), config.dialect.name))
    } else {
        (None, tools::ProgramTools::default())
    };
    let project = project.as_ref().map(|(name, project)| (name.as_str(), project));
    tools::settle(&mut config, name.as_deref(), project, &described);
    Ok(config)
}

/// The CAMotics project of the program: `NAME.camotics` beside `NAME.nc`,
/// else a project in its folder that lists it. Its name is as the program's
/// folder is given; a bad one is an error, unless found by its list.
fn project(input: &Input) -> Result<Option<(String, tools::camotics::Project)>, String> {
    let Some(program) = input.path() else { return Ok(None) };
    let own = program.with_extension("camotics");
    if own.is_file() {
        let name = own.display().to_string();
        let text = std::fs::read_to_string(&own).map_err(|err| read_error(&name, &err))?;
        let project = tools::camotics::parse(&text)
            .map_err(|err| plain_error(&format!("bad CAMotics project {name}: {err}"), None))?;
        return Ok(Some((name, project)));
    }
    let Some(file_name) = program.file_name().and_then(|n| n.to_str()) else { return Ok(None) };
    let Ok(entries) = std::fs::read_dir(input.dir()) else { return Ok(None) };
    let mut projects: Vec<PathBuf> = entries
        .flatten()
        .map(|entry| input.beside(entry.file_name()))
        .filter(|path| path.extension().is_some_and(|e| e == "camotics") && path.is_file())
        .collect();
    projects.sort();
    Ok(projects.into_iter().find_map(|path| {
        let project = tools::camotics::parse(&std::fs::read_to_string(&path).ok()?).ok()?;
        let listed = project.files.iter().any(|f| Path::new(f).file_name().is_some_and(|f| f == file_name));
        listed.then(|| (path.display().to_string(), project))
    }))
}

/// The subprograms of `input`, found by reading it again when a call names
/// one not seen yet; and the program itself again, for M47.
fn library<'a>(input: &'a Input, dialect: &'a DialectConfig) -> Library<'a> {
    let library = Library::scanning(move || Library::scan(input.open(), dialect))
        .with_restart(move || Box::new(passes::parse(input.open(), dialect)));
    match dialect.name {
        Dialect::Lenient => library.with_files(move |number| program_file(&input.dir(), number, dialect)),
        Dialect::Strict => library,
    }
}

/// A program kept in a file of its own beside the calling one, as a Fanuc or
/// Haas keeps programs by number: a G-code file whose name holds the number
/// (`O1002.nc`, `o01002.tap`, `bracket_o1002.cnc`) and whose first O word is it.
fn program_file(dir: &Path, number: u32, dialect: &DialectConfig) -> Option<(String, passes::Body)> {
    const EXTENSIONS: [&str; 7] = ["nc", "ngc", "tap", "cnc", "gcode", "txt", ""];
    let mut candidates: Vec<PathBuf> = std::fs::read_dir(dir)
        .ok()?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| {
            let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
            let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
            path.is_file() && EXTENSIONS.contains(&extension.as_str()) && names_program(stem, number)
        })
        .collect();
    candidates.sort();
    candidates.into_iter().find_map(|path| {
        let file = File::open(&path).ok()?;
        let body = Library::scan_file(BufReader::new(file), number, dialect)?;
        Some((path.file_name()?.to_string_lossy().into_owned(), body))
    })
}

/// Whether a file's name ends with program `number`: `O1002`, `1002`,
/// `O01002`, `part-o1002`.
fn names_program(stem: &str, number: u32) -> bool {
    let stem = stem.to_ascii_lowercase();
    let digits = stem.len() - stem.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let (head, tail) = stem.split_at(stem.len() - digits);
    let head = head.strip_suffix('o').unwrap_or(head);
    digits > 0
        && tail.parse::<u32>() == Ok(number)
        && (head.is_empty() || !head.ends_with(|c: char| c.is_ascii_alphanumeric()))
}

pub(crate) fn styled() -> bool {
    io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none()
}

/// Translates `input`, handing each output line to `write`; collects the diagnostics.
fn translate_into(
    input: &Input,
    config: &Config,
    stage: u8,
    line_numbers: bool,
    wizards: &mut dyn Wizards,
    mut write: impl FnMut(&str) -> io::Result<()>,
) -> io::Result<Report> {
    let library = library(input, &config.dialect);
    let options = Options { config, stage, wizards };
    // Before pass 01 the numbers are still in the program's own units, which may be finer.
    let decimals = if stage == 0 { 4 } else { config.units.decimals() };
    let emitter = Emitter::new(decimals, line_numbers);
    let mut report = Report::default();
    let mut line = String::new();
    for event in translate(input.open(), library, options) {
        match event {
            Event::Statement(statement) => {
                line.clear();
                emitter.write(&mut line, &statement);
                line.push('\n');
                write(&line)?;
            }
            Event::Diagnostic(diagnostic) => report.add(diagnostic),
        }
    }
    Ok(report)
}

fn show(report: &Report, input: &Input) {
    if report.errors() + report.warnings() > 0 {
        eprint!("{}", report.render(&input.name(), input.open(), styled()));
    }
}

fn run(args: &RunArgs) -> Result<i32, String> {
    let input = Input::new(&args.common.file)?;
    if args.watch {
        return wizard::watch(&input, &args.common, || run_once(args, &input));
    }
    run_once(args, &input)
}

fn run_once(args: &RunArgs, input: &Input) -> Result<i32, String> {
    let config = load_config(&args.common, input, Purpose::Translate, styled())?;
    let mut wizards = args.common.wizards.runtime(&config);
    // Withheld: a failed run leaves no half-written output, and writes nothing to a terminal or pipe.
    let path = args.output.as_deref().unwrap_or(Path::new("-"));
    let mut output = OutputFile::withheld(path).map_err(|err| cannot_write(path, &err))?;
    let write_failed = |err: io::Error| cannot_write(path, &err);
    output.write_all(preamble(&input.name(), config.units).as_bytes()).map_err(write_failed)?;
    let report = translate_into(input, &config, args.stage, !args.no_line_numbers, &mut wizards, |line| {
        output.write_all(line.as_bytes())
    })
    .map_err(write_failed)?;
    show(&report, input);
    if report.errors() > 0 {
        return Ok(1);
    }
    output.commit().map_err(write_failed)?;
    Ok(0)
}

/// The error for an output that cannot be written: `-` is standard output.
pub(crate) fn cannot_write(path: &Path, err: &io::Error) -> String {
    let name = if path == Path::new("-") { "standard output".to_string() } else { path.display().to_string() };
    plain_error(&format!("cannot write {name}: {err}"), None)
}

/// `ger run x | head` is not an error.
fn ignore_broken_pipe(err: io::Error) -> io::Result<()> {
    if err.kind() == io::ErrorKind::BrokenPipe {
        Ok(())
    } else {
        Err(err)
    }
}

fn tokens(path: &Path) -> Result<i32, String> {
    let input = Input::new(path)?;
    let mut report = Report::default();
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    for item in Lexer::new(input.open()) {
        let line = match item {
            Lexed::Token(token) => {
                let s = token.span;
                let kind = match token.kind {
                    TokenKind::Word { letter, value } => format!("word     {letter}{value}"),
                    TokenKind::Ident(name) => format!("wizard   {name}"),
                    TokenKind::Number(value) => format!("number   {value}"),
                    TokenKind::Str(text) => format!("string   {text:?}"),
                    TokenKind::Comment(text) => format!("comment  {text:?}"),
                    TokenKind::End => "end".to_string(),
                    TokenKind::BlockDelete => "block-delete".to_string(),
                };
                format!("{}:{}\t{kind}\n", s.line, s.col)
            }
            Lexed::Diagnostic(diagnostic) => {
                report.add(diagnostic);
                continue;
            }
        };
        if out.write_all(line.as_bytes()).or_else(ignore_broken_pipe).is_err() {
            break;
        }
    }
    let _ = out.flush();
    show(&report, &input);
    Ok(i32::from(report.errors() > 0))
}

fn parse_only(path: &Path) -> Result<i32, String> {
    let input = Input::new(path)?;
    let emitter = Emitter::new(4, true);
    let mut report = Report::default();
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    for event in parse(Lexer::new(input.open())) {
        match event {
            Event::Statement(statement) => {
                let line = emitter.line(&statement) + "\n";
                if out.write_all(line.as_bytes()).or_else(ignore_broken_pipe).is_err() {
                    break;
                }
            }
            Event::Diagnostic(diagnostic) => report.add(diagnostic),
        }
    }
    let _ = out.flush();
    show(&report, &input);
    Ok(i32::from(report.errors() > 0))
}
