//! `ger render` and `ger pulses`: the program translated, then simulated,
//! drawn or turned into pulses. Each pass over the program streams: the
//! statements are used as they come and never collected.

use std::io::{self, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::error::cannot_write;
use super::{show, CommonArgs};
use ger_core::config::{quoted, Bounds, Step, MAX_MEMORY_MIB};
use ger_core::statement::Units;
use ger_engine::{Culprit, Job, Purpose, Refused, Resolution, Source};
use ger_output::OutputFile;
use ger_render::{mesh::Mesh, top, view};
use ger_sim::pulses::Pulser;
use ger_sim::{Point, Solid};

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Format {
    /// PNG: the stock from above, shaded by depth of cut.
    #[value(name = "2d")]
    TwoD,
    /// PNG: the cut stock lit in 3D.
    #[value(name = "3d")]
    ThreeD,
    /// Binary STL mesh of the cut stock.
    Stl,
}

#[derive(Args)]
pub(crate) struct RenderArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// More programs, cut after FILE on the same stock in this order (a job).
    #[arg(value_name = "MORE")]
    more: Vec<PathBuf>,
    /// Where to write the picture or mesh (`-`: standard output, with --format).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
    /// What to write [default: by OUT's extension: .stl a mesh, .png a 2D
    /// picture, or 3D when a view is given].
    #[arg(long, value_enum)]
    format: Option<Format>,
    /// Draw the toolpath alone (every tool position): rapids red, feeds blue.
    #[arg(long, conflicts_with_all = ["format", "with_toolpath"])]
    toolpath: bool,
    /// Draw the toolpath over the 3D picture.
    #[arg(long)]
    with_toolpath: bool,
    #[command(flatten)]
    grid: GridArgs,
    /// A named 3D view: iso, top, bottom, front, back, right, left [default: iso].
    #[arg(long, value_parser = view_name)]
    view: Option<String>,
    /// Degrees about Z the 3D view looks from: 0 front, 90 right [default: 45].
    #[arg(long, value_name = "DEGREES", value_parser = azimuth, allow_negative_numbers = true)]
    azimuth: Option<f64>,
    /// Degrees above the XY plane the 3D view looks from, -90 to 90 [default: 35.3].
    #[arg(long, value_name = "DEGREES", value_parser = elevation, allow_negative_numbers = true)]
    elevation: Option<f64>,
    /// Magnification of the 3D view (1 fits the part).
    #[arg(long, default_value_t = 1.0, value_parser = zoom)]
    zoom: f64,
    /// The picture's size in pixels.
    #[arg(long, value_name = "WxH", default_value = "1024x768", value_parser = size)]
    size: (u32, u32),
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Args)]
pub(crate) struct PulsesArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Motor steps per machine unit [default: 1000 per inch, 40 per mm].
    #[arg(long, value_name = "N", value_parser = steps_per_unit)]
    steps_per_unit: Option<f64>,
    /// Show only the first N ticks.
    #[arg(long, value_name = "N")]
    limit: Option<u64>,
}

/// A number from `low` to `high`, or what to write instead.
fn within(text: &str, low: f64, high: f64, what: &str) -> Result<f64> {
    match text.parse::<f64>() {
        Ok(x) if (low..=high).contains(&x) => Ok(x),
        _ => bail!("expected {what}"),
    }
}

/// A cell's side: within the bounds of a machine in either unit (`simulation`
/// then holds it to the machine's own unit).
/// How finely `render`, `check` and `compare` simulate.
#[derive(clap::Args)]
pub(super) struct GridArgs {
    /// The side of a simulation cell, in machine units [default: the
    /// config's scale, or 1/1000 of the stock's longer side].
    #[arg(long, value_name = "LENGTH", value_parser = resolution)]
    resolution: Option<f64>,
    /// MiB the simulation's height field may take [default: the config's, or 2048].
    #[arg(long, value_name = "MIB", value_parser = memory_limit)]
    memory_limit: Option<u64>,
}

impl GridArgs {
    pub(super) fn asked(&self) -> Resolution {
        Resolution { cell: self.resolution, memory_limit_mib: self.memory_limit }
    }
}

pub(super) fn resolution(text: &str) -> Result<f64> {
    let (inch, mm) = (Bounds::of(Units::Inch), Bounds::of(Units::Mm));
    let (low, high) = (inch.smallest, mm.length);
    within(text, low, high, &format!("a length from {} to {} (in the machine's unit)", quoted(low), quoted(high)))
}

fn steps_per_unit(text: &str) -> Result<f64> {
    within(text, 0.001, 1_000_000.0, "a number of steps from 0.001 to 1000000")
}

/// `--memory-limit`: MiB, as `[render] memory_limit_mb`.
pub(super) fn memory_limit(text: &str) -> Result<u64> {
    match text.parse::<u64>() {
        Ok(m) if (1..=MAX_MEMORY_MIB).contains(&m) => Ok(m),
        _ => bail!("expected a number of MiB from 1 to {MAX_MEMORY_MIB} (1 TiB)"),
    }
}

fn azimuth(text: &str) -> Result<f64> {
    within(text, -360.0, 360.0, "degrees from -360 to 360")
}

fn elevation(text: &str) -> Result<f64> {
    within(text, -90.0, 90.0, "degrees from -90 to 90")
}

fn zoom(text: &str) -> Result<f64> {
    within(text, 0.01, 1000.0, "a zoom from 0.01 to 1000")
}

fn view_name(text: &str) -> Result<String> {
    match view::preset(text) {
        Some(_) => Ok(text.to_string()),
        None => bail!("expected one of {}", view::PRESETS),
    }
}

fn size(text: &str) -> Result<(u32, u32)> {
    let pixels = |side: &str| side.trim().parse::<u32>().ok().filter(|n| (16..=16384).contains(n));
    match text.split_once(['x', 'X']).map(|(w, h)| (pixels(w), pixels(h))) {
        Some((Some(w), Some(h))) => Ok((w, h)),
        _ => bail!("expected WIDTHxHEIGHT in pixels, each 16 to 16384, e.g. 1024x768"),
    }
}

/// A progress bar on stderr for each pass over the program, shown once the
/// pass has run a second, unless quiet or stderr is not a terminal.
pub(super) struct Bar {
    bar: Option<ProgressBar>,
    started: Instant,
    shown: bool,
    enabled: bool,
}

impl Bar {
    pub(super) fn new(quiet: bool) -> Bar {
        Bar { bar: None, started: Instant::now(), shown: false, enabled: !quiet && io::stderr().is_terminal() }
    }
}

impl ger_engine::Progress for Bar {
    fn begin(&mut self, job: &'static str, total: u64) {
        let bar = ProgressBar::with_draw_target(Some(total.max(1)), ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template("{msg:>9} [{bar:40}] {percent:>3}% {elapsed} (eta {eta})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        bar.set_message(job);
        (self.bar, self.started, self.shown) = (Some(bar), Instant::now(), false);
    }

    fn advance(&mut self, done: u64) {
        let Some(bar) = &self.bar else { return };
        if self.enabled && !self.shown && self.started.elapsed() > Duration::from_secs(1) {
            self.shown = true;
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.set_position(done);
    }

    fn end(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

/// The exit for a simulation that cannot be made: a command line's number
/// is a usage error (2); the config's is shown at its key, anything else as
/// an error (1).
pub(super) fn refused(refused: Refused, common: &CommonArgs, source: &Source) -> Result<i32> {
    match refused.by {
        Culprit::Caller => usage_error(&refused.message),
        Culprit::Config(key) => {
            Err(common.config_error(source, &[Step::Key("render"), Step::Key(key)], &refused.message))
        }
        Culprit::Neither => Err(refused.into()),
    }
}

/// Writes `out` to `output` and commits it: nothing is replaced unless all of it was written.
pub(super) fn save(
    mut output: OutputFile,
    path: &Path,
    out: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<()> {
    out(&mut output).and_then(|()| output.commit()).with_context(|| cannot_write(path))
}

pub(super) fn usage_error(message: &str) -> Result<i32> {
    eprintln!("error: {message}");
    Ok(2)
}

pub(crate) fn render(args: &RenderArgs) -> Result<i32> {
    let mut program = args.common.program(Purpose::Cut)?;
    let extension = args.output.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let wants_view = args.view.is_some() || args.azimuth.is_some() || args.elevation.is_some();
    let format = match (args.format, extension.as_deref()) {
        (Some(format), _) => format,
        (None, Some("stl")) => Format::Stl,
        (None, Some("png")) if wants_view || args.with_toolpath => Format::ThreeD,
        (None, Some("png")) => Format::TwoD,
        (None, _) if args.toolpath => Format::TwoD,
        (None, _) => return usage_error("cannot tell the format from OUT's extension: give --format 2d, 3d or stl"),
    };
    if wants_view && format != Format::ThreeD && !args.toolpath {
        return usage_error("--view, --azimuth and --elevation are for 3D pictures (--format 3d) and --toolpath");
    }
    let (az, el) = args.view.as_deref().and_then(view::preset).unwrap_or(view::preset("iso").unwrap());
    let camera = view::Camera {
        azimuth: args.azimuth.unwrap_or(az),
        elevation: args.elevation.unwrap_or(el),
        zoom: args.zoom,
        width: args.size.0,
        height: args.size.1,
    };
    // Now, so that an output that cannot be written is said before the simulation runs.
    let output = OutputFile::create(&args.output).with_context(|| cannot_write(&args.output))?;
    let source = program.source().clone();
    let mut bar = Bar::new(args.quiet);

    if args.toolpath {
        let extent = program.extent(&mut bar);
        if extent.report.errors() > 0 {
            show(&extent.report, &source);
            return Ok(1);
        }
        let (lo, hi) = extent.path_box.unwrap_or((Point::ZERO, Point::ONE));
        let (mut image, projection) = view::blank(&camera, lo, hi);
        let mut painter = view::PathPainter::new(&mut image, projection);
        let report = program.toolpath(|m| {
            painter.add(&m.segment, m.rapid);
            true
        });
        show(&report, &source);
        save(output, &args.output, |out| image.write_png(out))?;
        return Ok(0);
    }
    // A job: the programs after FILE cut on where it left off.
    let mut rest = Vec::new();
    for path in &args.more {
        rest.push(args.common.program_of(Source::open_path(path)?, Purpose::Cut)?);
    }
    let mut job = Job::new(program, rest);
    // Without a size, the stock is where the programs cut: a pass to find it.
    let (stock, reports) = job.stock(&mut bar);
    if reports.iter().any(|r| r.errors() > 0) {
        for (report, program) in reports.iter().zip(job.programs()) {
            show(report, program.source());
        }
        return Ok(1);
    }
    let asked = args.grid.asked();
    let sim = match job.simulation(stock, asked) {
        Ok(sim) => sim,
        Err(err) => return refused(err, &args.common, &source),
    };
    let (field, reports) = job.simulate(sim, &mut bar);
    for (report, program) in reports.iter().zip(job.programs()) {
        show(report, program.source());
    }
    if reports.iter().any(|r| r.errors() > 0) {
        return Ok(1);
    }
    let config = job.programs()[0].config().clone();

    match format {
        Format::Stl => save(output, &args.output, |out| Mesh::new(&field).write_stl(out))?,
        Format::TwoD => {
            let fixtures = Solid::fixtures(&config);
            let image = top::render(&field, &fixtures, camera.width, camera.height, config.units.abbreviation());
            save(output, &args.output, |out| image.write_png(out))?;
        }
        Format::ThreeD => {
            let fixtures = Solid::fixtures(&config);
            let (mut image, projection) = view::render(&field, &fixtures, &camera);
            if args.with_toolpath {
                let mut painter = view::PathPainter::new(&mut image, projection);
                for program in job.programs_mut() {
                    program.toolpath(|m| {
                        painter.add(&m.segment, m.rapid);
                        true
                    });
                }
            }
            save(output, &args.output, |out| image.write_png(out))?;
        }
    }
    Ok(0)
}

pub(crate) fn pulses(args: &PulsesArgs) -> Result<i32> {
    let mut program = args.common.program(Purpose::Translate)?;
    let units = program.config().units;
    let spu = args.steps_per_unit.unwrap_or(match units {
        Units::Inch => 1000.0,
        Units::Mm => 40.0,
    });
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    let unit = units.abbreviation();
    let _ = writeln!(out, "# {} steps per {unit}; a tick steps one or more axes; dir 1 is positive", spu);
    let _ = writeln!(out, "# tick\tline\tstep X Y Z\tdir X Y Z");
    let mut pulser = Pulser::new(spu);
    let mut tick = 0u64;
    let limit = args.limit.unwrap_or(u64::MAX);
    let mut broken = false;
    let bit = |b: bool| if b { '1' } else { '0' };
    let report = program.toolpath(|m| {
        pulser.segment(&m.segment, |p| {
            if tick >= limit {
                return false;
            }
            tick += 1;
            let line = format!(
                "{tick}\t{}\t{} {} {}\t{} {} {}\n",
                m.span.line,
                bit(p.step[0]),
                bit(p.step[1]),
                bit(p.step[2]),
                bit(p.dir[0]),
                bit(p.dir[1]),
                bit(p.dir[2])
            );
            if out.write_all(line.as_bytes()).is_err() {
                broken = true;
                return false;
            }
            true
        }) && !broken
    });
    if !broken {
        let [x, y, z] = pulser.steps;
        let [px, py, pz] = pulser.position;
        let _ = writeln!(out, "# {tick} ticks; steps X {x} Y {y} Z {z}; at X {px} Y {py} Z {pz} (steps)");
    }
    let _ = out.flush();
    show(&report, program.source());
    Ok(i32::from(report.errors() > 0))
}
