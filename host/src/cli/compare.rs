//! `ger compare`: the part the program cuts against its design (an STL), as
//! text for people or JSON (the shape is `host/docs/compare.schema.json`),
//! and a heat map; and the design's options `ger check --design` shares.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use serde::Serialize;

use super::check::Output;
use super::error::cannot_write;
use super::render::{refused, save, usage_error, Bar, GridArgs};
use super::{CommonArgs, UnitsArg};
use ger_core::config::{Bounds, Config};
use ger_core::statement::Units;
use ger_engine::compare::{heat_map, Comparison, Design, Deviation};
use ger_engine::sim::Stock;
use ger_engine::{default_tolerance, place_design, Job, Purpose, Source};
use ger_output::OutputFile;

#[derive(Args)]
pub(crate) struct CompareArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// More programs, cut after FILE on the same stock in this order (a
    /// job), then last the design: a closed mesh, binary or ASCII STL.
    #[arg(value_name = "MORE... DESIGN", required = true)]
    rest: Vec<PathBuf>,
    #[command(flatten)]
    placing: DesignArgs,
    /// How to report.
    #[arg(long, value_enum, default_value = "text")]
    format: Output,
    /// Also write a heat map (PNG): red gouged, green within the tolerance, blue material left.
    #[arg(long, value_name = "PNG")]
    heat_map: Option<PathBuf>,
    #[command(flatten)]
    grid: GridArgs,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

/// How a design is placed and judged (`ger compare`, `ger check --design`).
#[derive(Args)]
pub(crate) struct DesignArgs {
    /// How far the part may be off the design, in machine units [default: 0.05 mm or 0.002 in].
    #[arg(long, value_name = "LENGTH")]
    tolerance: Option<f64>,
    /// Where program zero is in the design's coordinates [default: the
    /// design's lowest corner on the stock's].
    #[arg(long, value_name = "X,Y,Z", value_parser = triple)]
    design_origin: Option<[f64; 3]>,
    /// The design's unit [default: the machine's].
    #[arg(long, value_enum, value_name = "UNIT")]
    design_units: Option<UnitsArg>,
}

impl DesignArgs {
    /// The design at `path`, placed over `stock`, and the tolerance; `None`
    /// (the usage error said) when the tolerance is out of bounds.
    pub(crate) fn load(&self, path: &Path, config: &Config, stock: &Stock) -> Result<Option<(Design, f64)>> {
        let Some(view) = self.for_view(path, config)? else { return Ok(None) };
        let mut design = view.mesh;
        place_design(&mut design, config, view.units.unwrap_or(config.units), view.origin, stock);
        Ok(Some((design, view.tolerance.unwrap_or(default_tolerance(config.units)))))
    }

    /// The design at `path` as read, with how to place and judge it (as
    /// `ger view` takes it: the stock changes with each snapshot); `None`
    /// (the usage error said) when the tolerance is out of bounds on `config`'s machine.
    pub(crate) fn for_view(&self, path: &Path, config: &Config) -> Result<Option<ger_view::DesignOptions>> {
        let bounds = Bounds::of(config.units);
        if self.tolerance.is_some_and(|t| !(0.0..=bounds.tool).contains(&t)) {
            usage_error(&format!("--tolerance must be from 0 to {} {}", bounds.tool, config.units.abbreviation()))?;
            return Ok(None);
        }
        let name = path.display().to_string();
        let file = std::fs::File::open(path).with_context(|| format!("cannot read {name}"))?;
        let mesh = Design::read(&mut std::io::BufReader::new(file)).with_context(|| format!("bad design {name}"))?;
        let units = self.design_units.map(|u| match u {
            UnitsArg::Inch => Units::Inch,
            UnitsArg::Mm => Units::Mm,
        });
        Ok(Some(ger_view::DesignOptions { name, mesh, units, origin: self.design_origin, tolerance: self.tolerance }))
    }
}

fn triple(text: &str) -> Result<[f64; 3]> {
    let numbers: Vec<f64> = text.split(',').map(|n| n.trim().parse::<f64>()).collect::<Result<_, _>>()?;
    match numbers[..] {
        [x, y, z] if numbers.iter().all(|n| n.is_finite()) => Ok([x, y, z]),
        _ => anyhow::bail!("expected three numbers, X,Y,Z"),
    }
}

pub(crate) fn compare(args: &CompareArgs) -> Result<i32> {
    let Some((design_path, more)) = args.rest.split_last() else { return usage_error("give the design (an STL)") };
    let mut rest = Vec::new();
    for path in more {
        rest.push(args.common.program_of(Source::open_path(path)?, Purpose::Cut)?);
    }
    let mut job = Job::new(args.common.program(Purpose::Cut)?, rest);
    let config = job.programs()[0].config().clone();
    let name = design_path.display().to_string();
    let heat = args.heat_map.as_ref().map(|path| OutputFile::create(path).with_context(|| cannot_write(path)));
    let heat = heat.transpose()?;
    let mut bar = Bar::new(args.quiet || args.format == Output::Json);
    let (stock, reports) = job.stock(&mut bar);
    if reports.iter().any(|r| r.errors() > 0) {
        for (report, program) in reports.iter().zip(job.programs()) {
            super::show(report, program.source());
        }
        return Ok(1);
    }
    let Some((design, tolerance)) = args.placing.load(design_path, &config, &stock)? else { return Ok(2) };
    let sim = match job.simulation(stock, args.grid.asked()) {
        Ok(sim) => sim,
        Err(err) => return refused(err, &args.common, job.programs()[0].source()),
    };
    let (judged, field, reports) = job.compare(sim, &design, tolerance, &mut bar);
    for (report, program) in reports.iter().zip(job.programs()) {
        super::show(report, program.source());
    }
    if reports.iter().any(|r| r.errors() > 0) {
        return Ok(1);
    }
    let c = &judged.comparison;
    let unit = config.units.abbreviation();
    if let (Some(output), Some(path)) = (heat, &args.heat_map) {
        let image = heat_map(&field, &judged.verdicts, tolerance, 800, 600, unit);
        save(output, path, |out| image.write_png(out))?;
    }
    let files: Vec<String> = job.programs().iter().map(|p| p.source().name()).collect();
    match args.format {
        Output::Text => print!("{}", text(&files.join(", then "), &name, c, unit, config.units.decimals())),
        Output::Json => {
            let json =
                JsonReport { version: 1, file: files[0].clone(), files, design: name, units: unit, comparison: c };
            println!("{}", serde_json::to_string_pretty(&json).context("cannot write the report")?);
        }
    }
    Ok(i32::from(c.gouge.area > 0.0 || c.left.area > 0.0))
}

fn text(file: &str, design: &str, c: &Comparison, unit: &str, d: usize) -> String {
    let verdict = match (c.gouge.area > 0.0, c.left.area > 0.0) {
        (false, false) => "within the tolerance",
        (true, false) => "gouged",
        (false, true) => "material left",
        (true, true) => "gouged, and material left",
    };
    let mut out = format!("{file} against {design}: {verdict}\n");
    let _ = writeln!(
        out,
        "  judged    {:.d$} {unit}² under the design, cells of {:.d$} {unit}, tolerance {:.d$} {unit}",
        c.judged_area, c.cell, c.tolerance
    );
    out + &deviations(c, unit, d)
}

/// The comparison's lines of text: the gouges and the material left.
pub(crate) fn deviations(c: &Comparison, unit: &str, d: usize) -> String {
    let deviation = |what: &str, dev: &Deviation| match dev.at {
        None => "none".to_string(),
        Some([x, y]) => {
            let mut line = format!(
                "{:.d$} {unit} {what}, at X {x:.d$} Y {y:.d$}; {:.d$} {unit}² and {:.d$} {unit}³ beyond the tolerance",
                dev.worst, dev.area, dev.volume
            );
            let lines = |numbers: &[u32]| {
                let numbers: Vec<String> = numbers.iter().map(u32::to_string).collect();
                format!("line{} {}", if numbers.len() == 1 { "" } else { "s" }, numbers.join(", "))
            };
            if !dev.lines.is_empty() {
                let _ = write!(line, "; cut by {}", lines(&dev.lines));
            } else if !dev.cut_by.is_empty() {
                // A job's: each program's lines.
                let by: Vec<String> = dev.cut_by.iter().map(|c| format!("{} {}", c.file, lines(&c.lines))).collect();
                let _ = write!(line, "; cut by {}", by.join(" and "));
            }
            line
        }
    };
    format!("  gouged    {}\n  left      {}\n", deviation("deepest", &c.gouge), deviation("highest", &c.left))
}

/// `ger compare --format json`: field names are part of ger's interface.
#[derive(Serialize)]
struct JsonReport<'a> {
    version: u32,
    /// The first program.
    file: String,
    /// Every program, in the order they cut: one, or a job's.
    files: Vec<String>,
    design: String,
    units: &'static str,
    #[serde(flatten)]
    comparison: &'a Comparison,
}
