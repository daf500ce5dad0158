//! `ger check`: the translation's diagnostics and the verifier's, then a
//! summary of what the program will do; as text for people or JSON for
//! editors and CI scripts (the shape is `host/docs/check.schema.json`).

use std::fmt::Write as _;

use clap::{Args, ValueEnum};
use serde::Serialize;

use anyhow::{Context, Result};

use super::render::{refused, Bar, GridArgs};
use super::{styled, CommonArgs};
use ger_check::{duration, Bounds, Finding, Rule, Summary, Verdict};
use ger_core::config::Config;
use ger_core::diag::{Diagnostic, Severity};
use std::path::PathBuf;

use ger_engine::compare::{Comparison, Design};
use ger_engine::{carve, stock_of, Job, Purpose, Report, Source};

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Output {
    /// Diagnostics as rustc shows them, on stderr; the summary on stdout.
    Text,
    /// One JSON document on stdout (see host/docs/check.schema.json).
    Json,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Deny {
    /// Warnings fail the check, as errors.
    Warnings,
}

#[derive(Args)]
pub(crate) struct CheckArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// More programs, cut after FILE on the same stock in this order (a job
    /// posted one file an operation): each is judged against what the ones
    /// before it left.
    #[arg(value_name = "MORE")]
    more: Vec<PathBuf>,
    /// Start from this mesh (a closed STL, in machine coordinates and units:
    /// a casting, or the part an earlier job left) instead of a block.
    #[arg(long, value_name = "STL")]
    stock_from: Option<PathBuf>,
    /// Also set the part beside its design (a closed STL), as `ger compare` does.
    #[arg(long, value_name = "STL")]
    design: Option<PathBuf>,
    #[command(flatten)]
    placing: super::compare::DesignArgs,
    /// How to report.
    #[arg(long, value_enum, default_value = "text")]
    format: Output,
    /// `--deny warnings` turns warnings into errors (exit status 1).
    #[arg(long, value_enum, value_name = "WHAT")]
    deny: Option<Deny>,
    /// Do not make this check (repeatable): rapid-into-stock, spindle-off,
    /// flute-length, plunge, below-stock, travel, arc-radius, default-tool,
    /// collision, clearance, fixture.
    #[arg(long, value_name = "CHECK", value_parser = rule)]
    allow: Vec<Rule>,
    #[command(flatten)]
    grid: GridArgs,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

fn rule(text: &str) -> Result<Rule> {
    Rule::from_name(text).with_context(|| {
        let names: Vec<&str> = Rule::ALL.iter().map(|r| r.name()).collect();
        format!("not a check; the checks are {}", names.join(", "))
    })
}

pub(crate) fn check(args: &CheckArgs) -> Result<i32> {
    if !args.more.is_empty() {
        return job(args);
    }
    let mut program = args.common.program(Purpose::Cut)?;
    let source = program.source().clone();
    let mut bar = Bar::new(args.quiet || args.format == Output::Json);

    // Without a size, the stock is where the program cuts: a pass to find it
    // (its diagnostics come again from the check's own pass).
    let mesh = start_mesh(args)?;
    let stock = match &mesh {
        Some(mesh) => stock_of(mesh),
        None => program.stock(&mut bar).0,
    };
    let asked = args.grid.asked();
    let mut sim = match program.simulation(stock, asked) {
        Ok(sim) => sim,
        Err(err) => return refused(err, &args.common, &source),
    };
    if let Some(mesh) = &mesh {
        carve(&mut sim, mesh);
    }
    let design = match &args.design {
        Some(path) => match args.placing.load(path, program.config(), &stock)? {
            Some(design) => Some(design),
            None => return Ok(2),
        },
        None => None,
    };
    let (mut verdict, part) = program.check(sim, &args.allow, &mut bar);
    let comparison = design.map(|(design, tolerance)| program.judge(&part, &design, tolerance, &mut bar).comparison);
    let config = program.config();
    if args.deny == Some(Deny::Warnings) {
        for finding in &mut verdict.findings {
            finding.diagnostic.severity = Severity::Error;
        }
    }
    let design = Problems::of_design(comparison.as_ref(), args.deny.is_some());
    let problems = Problems::of(&verdict).and(design);
    match args.format {
        Output::Text => {
            let mut report = Report::default().failing_as("the check failed");
            for finding in &verdict.findings {
                report.add(finding.diagnostic.clone());
            }
            if !verdict.findings.is_empty() {
                eprint!("{}", report.render(&source.name(), source.open(), styled()));
            }
            print!("{}", summary_text(&source.name(), &verdict, config, design));
            if let Some(c) = &comparison {
                print!("{}", super::compare::deviations(c, config.units.abbreviation(), config.units.decimals()));
            }
        }
        Output::Json => {
            let mut report = JsonReport::new(&source.name(), &verdict);
            report.design = comparison.as_ref();
            (report.errors, report.warnings) = (problems.errors, problems.warnings);
            let json = serde_json::to_string_pretty(&report).context("cannot write the report")?;
            println!("{json}");
        }
    }
    Ok(i32::from(problems.errors > 0))
}

/// What failed and what warned, counted for the summary and the exit
/// status alike, so that they never disagree.
#[derive(Clone, Copy, Default)]
struct Problems {
    errors: usize,
    warnings: usize,
    /// With `--design`: the part is below it beyond the tolerance (an error).
    gouged: bool,
    /// With `--design`: the part is above it beyond the tolerance (a
    /// warning, an error under `--deny warnings`).
    left: bool,
}

impl Problems {
    fn of(verdict: &Verdict) -> Problems {
        let errors = verdict.findings.iter().filter(|f| f.diagnostic.is_error()).count();
        Problems { errors, warnings: verdict.findings.len() - errors, ..Problems::default() }
    }

    fn of_design(comparison: Option<&Comparison>, deny_warnings: bool) -> Problems {
        let Some(c) = comparison else { return Problems::default() };
        let (gouged, left) = (c.gouge.area > 0.0, c.left.area > 0.0);
        let (left_errors, left_warnings) = if deny_warnings { (left, false) } else { (false, left) };
        Problems {
            errors: usize::from(gouged) + usize::from(left_errors),
            warnings: usize::from(left_warnings),
            gouged,
            left,
        }
    }

    fn and(self, other: Problems) -> Problems {
        Problems {
            errors: self.errors + other.errors,
            warnings: self.warnings + other.warnings,
            gouged: self.gouged || other.gouged,
            left: self.left || other.left,
        }
    }

    /// "no problems found", "2 errors, 1 warning (gouged below the design)".
    fn text(self) -> String {
        let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
        let mut text = match (self.errors, self.warnings) {
            (0, 0) => return "no problems found".to_string(),
            (e, 0) => plural(e, "error"),
            (0, w) => plural(w, "warning"),
            (e, w) => format!("{}, {}", plural(e, "error"), plural(w, "warning")),
        };
        match (self.gouged, self.left) {
            (true, true) => text.push_str(" (gouged below the design, and material left on it)"),
            (true, false) => text.push_str(" (gouged below the design)"),
            (false, true) => text.push_str(" (material left on the design)"),
            (false, false) => {}
        }
        text
    }
}

/// `ger check A B C`: the programs in turn on one stock, each reported as
/// alone (its diagnostics, its summary), then a line for the job.
fn job(args: &CheckArgs) -> Result<i32> {
    let first = args.common.program(Purpose::Cut)?;
    let mut rest = Vec::new();
    for path in &args.more {
        rest.push(args.common.program_of(Source::open_path(path)?, Purpose::Cut)?);
    }
    let mut job = Job::new(first, rest);
    let mut bar = Bar::new(args.quiet || args.format == Output::Json);
    let mesh = start_mesh(args)?;
    let stock = match &mesh {
        Some(mesh) => stock_of(mesh),
        None => job.stock(&mut bar).0,
    };
    let asked = args.grid.asked();
    let mut sim = match job.simulation(stock, asked) {
        Ok(sim) => sim,
        Err(err) => return refused(err, &args.common, job.programs()[0].source()),
    };
    if let Some(mesh) = &mesh {
        carve(&mut sim, mesh);
    }
    let design = match &args.design {
        Some(path) => match args.placing.load(path, job.programs()[0].config(), &stock)? {
            Some(design) => Some(design),
            None => return Ok(2),
        },
        None => None,
    };
    let (mut verdicts, part) = job.check(sim, &args.allow, &mut bar);
    let comparison = design.map(|(design, tolerance)| job.judge(&part, &design, tolerance, &mut bar).comparison);
    let mut problems = Problems::default();
    let mut reports = Vec::new();
    for (program, verdict) in job.programs().iter().zip(&mut verdicts) {
        if args.deny == Some(Deny::Warnings) {
            for finding in &mut verdict.findings {
                finding.diagnostic.severity = Severity::Error;
            }
        }
        problems = problems.and(Problems::of(verdict));
        let source = program.source();
        match args.format {
            Output::Text => {
                let mut report = Report::default().failing_as("the check failed");
                for finding in &verdict.findings {
                    report.add(finding.diagnostic.clone());
                }
                if !verdict.findings.is_empty() {
                    eprint!("{}", report.render(&source.name(), source.open(), styled()));
                }
                print!("{}", summary_text(&source.name(), verdict, program.config(), Problems::default()));
            }
            Output::Json => reports.push(JsonReport::new(&source.name(), verdict)),
        }
    }
    // The design is the job's part's, so it counts for the job.
    problems = problems.and(Problems::of_design(comparison.as_ref(), args.deny.is_some()));
    let names: Vec<String> = job.programs().iter().map(|p| p.source().name()).collect();
    match args.format {
        Output::Text => {
            println!("job {}: {}", names.join(", then "), problems.text());
            if let Some(c) = &comparison {
                let units = job.programs()[0].config().units;
                print!("{}", super::compare::deviations(c, units.abbreviation(), units.decimals()));
            }
        }
        Output::Json => {
            let job = JsonJob {
                version: 1,
                errors: problems.errors,
                warnings: problems.warnings,
                programs: reports,
                design: comparison.as_ref(),
            };
            println!("{}", serde_json::to_string_pretty(&job).context("cannot write the report")?);
        }
    }
    Ok(i32::from(problems.errors > 0))
}

/// `--stock-from`'s mesh, if given.
fn start_mesh(args: &CheckArgs) -> Result<Option<Design>> {
    let Some(path) = &args.stock_from else { return Ok(None) };
    let name = path.display().to_string();
    let file = std::fs::File::open(path).with_context(|| format!("cannot read {name}"))?;
    let mesh = Design::read(&mut std::io::BufReader::new(file)).with_context(|| format!("bad stock {name}"))?;
    Ok(Some(mesh))
}

/// `ger check A B C --format json`: each program's report, in order, and the job's counts.
#[derive(Serialize)]
struct JsonJob<'a> {
    version: u32,
    errors: usize,
    warnings: usize,
    programs: Vec<JsonReport<'a>>,
    /// `--design`'s comparison of the part the whole job leaves.
    #[serde(skip_serializing_if = "Option::is_none")]
    design: Option<&'a Comparison>,
}

/// The summary for people: a heading line, then one line a fact.
/// `design`: what `--design` found, counted with the findings.
fn summary_text(name: &str, verdict: &Verdict, config: &Config, design: Problems) -> String {
    let s = &verdict.summary;
    let decimals = config.units.decimals();
    let unit = s.units;
    let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    let mut out = format!("{name}: {}\n", Problems::of(verdict).and(design).text());
    let boxed = |b: &Option<Bounds>| match b {
        None => "none".to_string(),
        Some(b) => format!(
            "X {:.d$} to {:.d$}, Y {:.d$} to {:.d$}, Z {:.d$} to {:.d$} {unit}",
            b.min[0],
            b.max[0],
            b.min[1],
            b.max[1],
            b.min[2],
            b.max[2],
            d = decimals
        ),
    };
    let _ = writeln!(out, "  cut       {}", boxed(&s.cut_box));
    let _ = writeln!(out, "  path      {}", boxed(&s.path_box));
    let _ = writeln!(
        out,
        "  distance  {:.d$} {unit} cutting, {:.d$} {unit} rapid",
        s.cutting_distance,
        s.rapid_distance,
        d = decimals
    );
    let planned = &s.planned;
    let _ = writeln!(out, "  run time  {} planned on {}", duration(planned.seconds), planned.profile.text(unit));
    let _ = writeln!(
        out,
        "            {} at programmed feeds (rapids at {} {unit}/min, no acceleration)",
        duration(s.run_time_seconds),
        s.rapid_rate
    );
    if planned.tools.len() > 1 {
        let tools: Vec<String> =
            planned.tools.iter().map(|t| format!("T{} {}", t.number, duration(t.seconds))).collect();
        let _ = writeln!(out, "            {}", tools.join(", "));
    }
    // One line a tool: what it cut, what it is, and where the table got it.
    let tools: Vec<String> = s
        .tools
        .iter()
        .map(|t| {
            let mut line = format!(
                "T{} {:.d$} {unit} over {}",
                t.number,
                t.cutting_distance,
                plural(t.moves as usize, "move"),
                d = decimals
            );
            match (t.kind, t.diameter) {
                (Some(kind), Some(diameter)) => {
                    let _ = write!(line, ": {} {diameter:.d$} {unit}", kind.name(), d = decimals);
                    if let Some(angle) = t.tip_angle {
                        let _ = write!(line, " with a {angle}° point");
                    }
                    if let Some(source) = &t.source {
                        let _ = write!(line, ", {source}");
                    }
                }
                _ => line.push_str(": not in the tool table"),
            }
            line
        })
        .collect();
    let tools = if tools.is_empty() { "none".to_string() } else { tools.join("\n            ") };
    let _ = writeln!(out, "  tools     {tools}");
    // What the collision check sees of each tool, so that nobody trusts a check they did not configure.
    let assemblies: Vec<String> = s
        .tools
        .iter()
        .filter(|t| t.kind.is_some())
        .map(|t| match t.unchecked {
            Some(unchecked) => format!("tool {}: {unchecked}", t.number),
            None => format!("tool {}: shank and holder checked", t.number),
        })
        .collect();
    if !assemblies.is_empty() {
        let _ = writeln!(out, "  assembly  {}", assemblies.join("\n            "));
    }
    let codes: Vec<String> = s.codes.iter().map(|(code, n)| format!("{code} {n}")).collect();
    let _ = writeln!(out, "  codes     {}", codes.join(", "));
    if !s.problems.is_empty() {
        let problems: Vec<String> = s.problems.iter().map(|(rule, n)| format!("{rule} {n}")).collect();
        let _ = writeln!(out, "  problems  {}", problems.join(", "));
    }
    out
}

/// `ger check --format json`: field names are part of ger's interface.
#[derive(Serialize)]
struct JsonReport<'a> {
    /// Of this shape: bumped when a field changes meaning or goes away.
    version: u32,
    file: String,
    errors: usize,
    warnings: usize,
    diagnostics: Vec<JsonDiagnostic>,
    summary: &'a Summary,
    /// `--design`'s comparison (`ger compare`'s figures).
    #[serde(skip_serializing_if = "Option::is_none")]
    design: Option<&'a Comparison>,
}

#[derive(Serialize)]
struct JsonDiagnostic {
    severity: &'static str,
    /// The check's name; null for a problem the translation found.
    rule: Option<&'static str>,
    message: String,
    help: Option<String>,
    line: u32,
    column: u32,
    /// Bytes of the line the problem covers (at least 1 in editors).
    length: u32,
    /// The subprogram and wizard calls the problem happened in, innermost first.
    calls: Vec<JsonCall>,
}

#[derive(Serialize)]
struct JsonCall {
    /// `O100`, or the wizard's name.
    name: String,
    line: u32,
    column: u32,
}

impl<'a> JsonReport<'a> {
    fn new(file: &str, verdict: &'a Verdict) -> JsonReport<'a> {
        let diagnostics: Vec<JsonDiagnostic> = verdict.findings.iter().map(JsonDiagnostic::new).collect();
        let errors = diagnostics.iter().filter(|d| d.severity == "error").count();
        JsonReport {
            version: 1,
            file: file.to_string(),
            errors,
            warnings: diagnostics.len() - errors,
            diagnostics,
            summary: &verdict.summary,
            design: None,
        }
    }
}

impl JsonDiagnostic {
    fn new(finding: &Finding) -> JsonDiagnostic {
        let d: &Diagnostic = &finding.diagnostic;
        let mut calls = Vec::new();
        let mut next = d.origin.as_deref();
        while let Some(origin) = next {
            calls.push(JsonCall { name: origin.what.clone(), line: origin.call.line, column: origin.call.col });
            next = origin.parent.as_deref();
        }
        JsonDiagnostic {
            severity: if d.is_error() { "error" } else { "warning" },
            rule: finding.rule.map(Rule::name),
            message: d.message.clone(),
            help: d.help.clone(),
            line: d.span.line,
            column: d.span.col,
            length: d.span.len,
            calls,
        }
    }
}
