//! The command line. The only module that knows about argv, files, standard
//! streams and terminals; everything else takes readers and returns values.

mod check;
mod compare;
mod error;
mod lsp;
mod render;
mod view;
mod wizard;

use std::io::{self, IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand, ValueEnum};

use error::{cannot_write, Shown};
use ger_core::config::{Config, Step, TargetName};
use ger_core::emit::{preamble, Emitter};
use ger_core::lex::{Lexed, Lexer, TokenKind};
use ger_core::parse::parse;
use ger_core::passes::{Event, LAST_STAGE};
use ger_core::statement::Units;
use ger_engine::{Program, Purpose, Report, Settings, Source};
use ger_output::OutputFile;
use ger_wasm::{Limits, WasmWizards};

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
    /// Simulate the cut and set the part beside its design (an STL): gouges
    /// and material left beyond a tolerance, and the lines that gouged.
    Compare(Box<compare::CompareArgs>),
    /// Show the step/direction pulses a stepper controller would get.
    Pulses(render::PulsesArgs),
    /// Make, build and list wizards.
    #[command(subcommand)]
    Wizard(wizard::WizardCommand),
    /// Serve a page on 127.0.0.1 that shows the program, its translation, its
    /// diagnostics and the simulated part, updated live as any of them changes.
    View(Box<view::ViewArgs>),
    /// Serve the Language Server Protocol on standard input and output, for
    /// editors: diagnostics as you type, hover, definitions, symbols, fixes.
    Lsp(Box<lsp::LspArgs>),
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

fn positive_seconds(text: &str) -> Result<f64> {
    match text.parse::<f64>() {
        // Below a millisecond no call could run at all.
        Ok(s) if (0.001..=3600.0).contains(&s) => Ok(s),
        _ => anyhow::bail!("expected a number of seconds from 0.001 to 3600"),
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
    /// The controller the output is for: what its lines may hold (overrides
    /// `target` in the config file). Only the whole translation has one: with
    /// `--stage` below 5 the output is ger's own.
    #[arg(long, value_enum, value_name = "NAME", conflicts_with = "stage")]
    target: Option<TargetArg>,
    /// Translate again whenever the program, the config or a wizard changes.
    #[arg(long)]
    watch: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum TargetArg {
    Generic,
    Grbl,
    Linuxcnc,
    Fanuc,
    Mach3,
}

impl From<TargetArg> for TargetName {
    fn from(target: TargetArg) -> TargetName {
        match target {
            TargetArg::Generic => TargetName::Generic,
            TargetArg::Grbl => TargetName::Grbl,
            TargetArg::Linuxcnc => TargetName::Linuxcnc,
            TargetArg::Fanuc => TargetName::Fanuc,
            TargetArg::Mach3 => TargetName::Mach3,
        }
    }
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
        Command::Compare(args) => compare::compare(&args),
        Command::Pulses(args) => render::pulses(&args),
        Command::Wizard(command) => wizard::main(command),
        Command::View(args) => view::main(*args),
        Command::Lsp(args) => lsp::main(*args),
    };
    match result {
        Ok(status) => status,
        Err(err) => {
            eprint!("{}", error::render(&err));
            1
        }
    }
}

impl From<UnitsArg> for Units {
    fn from(units: UnitsArg) -> Units {
        match units {
            UnitsArg::Inch => Units::Inch,
            UnitsArg::Mm => Units::Mm,
        }
    }
}

impl CommonArgs {
    /// What the command line says about the machine.
    fn settings(&self) -> Settings {
        Settings {
            config: self.config.clone(),
            lenient: self.lenient,
            units: self.units.map(Units::from),
            target: None,
        }
    }

    /// The program FILE names, on the machine the config and the options
    /// describe (a bad config is shown as rustc would, coloured when
    /// `styled`), calling the wizards of the wizards directory.
    fn program(&self, purpose: Purpose) -> Result<Program> {
        let source = Source::open_path(&self.file)?;
        self.program_of(source, purpose)
    }

    fn program_of(&self, source: Source, purpose: Purpose) -> Result<Program> {
        self.program_with(self.settings(), source, purpose)
    }

    /// The program on the machine `settings` describe.
    fn program_with(&self, settings: Settings, source: Source, purpose: Purpose) -> Result<Program> {
        let config = settings.load(&source, purpose).map_err(|err| Shown(err.render(styled())))?;
        let wizards = self.wizards.runtime(&config);
        Ok(Program::new(source, config).with_wizards(Box::new(wizards)))
    }

    /// A value of the config file that cannot be used, shown at the key `steps` lead to.
    fn config_error(&self, source: &Source, steps: &[Step], message: &str) -> anyhow::Error {
        match self.settings().invalid(source, steps, message) {
            Some(err) => Shown(err.render(styled())).into(),
            None => anyhow::anyhow!("{message}"),
        }
    }
}

pub(crate) fn styled() -> bool {
    io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none()
}

/// Shows the report's diagnostics, if it has any, against the program's lines.
fn show(report: &Report, source: &Source) {
    if report.errors() + report.warnings() > 0 {
        eprint!("{}", report.render(&source.name(), source.open(), styled()));
    }
}

fn run(args: &RunArgs) -> Result<i32> {
    let source = Source::open_path(&args.common.file)?;
    if args.watch {
        return wizard::watch(&source, &args.common, || run_once(args, &source));
    }
    run_once(args, &source)
}

fn run_once(args: &RunArgs, source: &Source) -> Result<i32> {
    let settings = Settings { target: args.target.map(TargetName::from), ..args.common.settings() };
    let mut program = args.common.program_with(settings, source.clone(), Purpose::Translate)?;
    // Withheld: a failed run leaves no half-written output, and writes nothing to a terminal or pipe.
    let path = args.output.as_deref().unwrap_or(Path::new("-"));
    let mut output = OutputFile::withheld(path).with_context(|| cannot_write(path))?;
    let line_numbers = !args.no_line_numbers;
    let report = if args.stage == LAST_STAGE {
        program.write_output(&source.name(), line_numbers, |line| output.write_all(line.as_bytes()))
    } else {
        // A pass's own output: ger's dialect, whatever the target.
        let preamble = preamble(&source.name(), program.config().units);
        output.write_all(preamble.as_bytes()).and_then(|()| {
            program.write_translation(args.stage, line_numbers, |line| output.write_all(line.as_bytes()))
        })
    }
    .with_context(|| cannot_write(path))?;
    show(&report, source);
    if report.errors() > 0 {
        return Ok(1);
    }
    output.commit().with_context(|| cannot_write(path))?;
    Ok(0)
}

/// `ger run x | head` is not an error.
fn ignore_broken_pipe(err: io::Error) -> io::Result<()> {
    if err.kind() == io::ErrorKind::BrokenPipe {
        Ok(())
    } else {
        Err(err)
    }
}

fn tokens(path: &Path) -> Result<i32> {
    let input = Source::open_path(path)?;
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
            // Only the interpreter stage says which call statements run in.
            Lexed::Origin(_) => continue,
        };
        if out.write_all(line.as_bytes()).or_else(ignore_broken_pipe).is_err() {
            break;
        }
    }
    let _ = out.flush();
    show(&report, &input);
    Ok(i32::from(report.errors() > 0))
}

fn parse_only(path: &Path) -> Result<i32> {
    let input = Source::open_path(path)?;
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
