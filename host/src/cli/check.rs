//! `ger check`: the translation's diagnostics and the verifier's, then a
//! summary of what the program will do; as text for people or JSON for
//! editors and CI scripts (the shape is `host/docs/check.schema.json`).

use std::fmt::Write as _;

use clap::{Args, ValueEnum};
use serde::Serialize;

use anyhow::{Context, Result};

use super::render::{memory_limit, refused, resolution, Bar};
use super::{styled, CommonArgs};
use ger_check::{Bounds, Finding, ProfileUsed, Rule, Summary, Verdict};
use ger_core::config::Config;
use ger_core::diag::{Diagnostic, Severity};
use ger_engine::{Purpose, Report, Resolution};

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
    /// How to report.
    #[arg(long, value_enum, default_value = "text")]
    format: Output,
    /// `--deny warnings` turns warnings into errors (exit status 1).
    #[arg(long, value_enum, value_name = "WHAT")]
    deny: Option<Deny>,
    /// Do not make this check (repeatable): rapid-into-stock, spindle-off,
    /// flute-length, plunge, below-stock, travel, arc-radius, default-tool.
    #[arg(long, value_name = "CHECK", value_parser = rule)]
    allow: Vec<Rule>,
    /// The side of a simulation cell, in machine units [default: the
    /// config's scale, or 1/1000 of the stock's longer side].
    #[arg(long, value_name = "LENGTH", value_parser = resolution)]
    resolution: Option<f64>,
    /// MiB the simulation's height field may take [default: the config's, or 2048].
    #[arg(long, value_name = "MIB", value_parser = memory_limit)]
    memory_limit: Option<u64>,
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
    let mut program = args.common.program(Purpose::Cut)?;
    let source = program.source().clone();
    let mut bar = Bar::new(args.quiet || args.format == Output::Json);

    // Without a size, the stock is where the program cuts: a pass to find it
    // (its diagnostics come again from the check's own pass).
    let (stock, _) = program.stock(&mut bar);
    let asked = Resolution { cell: args.resolution, memory_limit_mib: args.memory_limit };
    let sim = match program.simulation(stock, asked) {
        Ok(sim) => sim,
        Err(err) => return refused(err, &args.common, &source),
    };
    let (mut verdict, _) = program.check(sim, &args.allow, &mut bar);
    let config = program.config();
    if args.deny == Some(Deny::Warnings) {
        for finding in &mut verdict.findings {
            finding.diagnostic.severity = Severity::Error;
        }
    }
    let errors = verdict.findings.iter().filter(|f| f.diagnostic.is_error()).count();
    match args.format {
        Output::Text => {
            let mut report = Report::default().failing_as("the check failed");
            for finding in &verdict.findings {
                report.add(finding.diagnostic.clone());
            }
            if !verdict.findings.is_empty() {
                eprint!("{}", report.render(&source.name(), source.open(), styled()));
            }
            print!("{}", summary_text(&source.name(), &verdict, config));
        }
        Output::Json => {
            let json = serde_json::to_string_pretty(&JsonReport::new(&source.name(), &verdict))
                .context("cannot write the report")?;
            println!("{json}");
        }
    }
    Ok(i32::from(errors > 0))
}

/// The summary for people: a heading line, then one line a fact.
fn summary_text(name: &str, verdict: &Verdict, config: &Config) -> String {
    let s = &verdict.summary;
    let decimals = config.units.decimals();
    let unit = s.units;
    let (errors, warnings) = verdict.findings.iter().fold((0, 0), |(e, w), f| match f.diagnostic.severity {
        Severity::Error => (e + 1, w),
        Severity::Warning => (e, w + 1),
    });
    let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    let mut out = match (errors, warnings) {
        (0, 0) => format!("{name}: no problems found\n"),
        (e, 0) => format!("{name}: {}\n", plural(e, "error")),
        (0, w) => format!("{name}: {}\n", plural(w, "warning")),
        (e, w) => format!("{name}: {}, {}\n", plural(e, "error"), plural(w, "warning")),
    };
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
    let _ =
        writeln!(out, "  run time  {} planned on {}", duration(planned.seconds), profile_text(&planned.profile, unit));
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
    let codes: Vec<String> = s.codes.iter().map(|(code, n)| format!("{code} {n}")).collect();
    let _ = writeln!(out, "  codes     {}", codes.join(", "));
    if !s.problems.is_empty() {
        let problems: Vec<String> = s.problems.iter().map(|(rule, n)| format!("{rule} {n}")).collect();
        let _ = writeln!(out, "  problems  {}", problems.join(", "));
    }
    out
}

/// Which profile the time was planned on, and where it came from.
fn profile_text(profile: &ProfileUsed, unit: &str) -> String {
    let preset = profile.preset;
    match (&profile.grbl_settings, profile.configured) {
        (_, false) => format!("{preset}, GRBL 1.1h's defaults in {unit} (no [machine.motion] in ger.toml)"),
        (Some(file), true) => format!("the GRBL settings of {file} over {preset} ([machine.motion])"),
        (None, true) => format!("[machine.motion] over {preset}"),
    }
}

/// "1 h 02 min", "3 min 05 s", "12.5 s".
fn duration(seconds: f64) -> String {
    let whole = seconds.round() as u64;
    if whole >= 3600 {
        format!("{} h {:02} min", whole / 3600, (whole % 3600 + 30) / 60)
    } else if whole >= 60 {
        format!("{} min {:02} s", whole / 60, whole % 60)
    } else {
        format!("{seconds:.1} s")
    }
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
