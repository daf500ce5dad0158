//! `ger render` and `ger pulses`: the program translated, then simulated,
//! drawn or turned into pulses. Each pass over the program streams: the
//! statements are used as they come and never collected.

use std::io::{self, BufRead, IsTerminal, Read, Write};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::report::{plain_error, Report};
use super::{library, load_config, show, styled, CommonArgs, Input};
use crate::config::Config;
use crate::expand::Wizards;
use crate::passes::{translate, Event, Options, LAST_STAGE};
use crate::pulses::Pulser;
use crate::render::{mesh::Mesh, top, view};
use crate::sim::{CutBounds, Point, Simulation, Stock, Tracker};
use crate::statement::Statement;

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
    /// Where to write the picture or mesh.
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
    /// The side of a simulation cell, in machine units [default: the config's
    /// scale, or 1/1000 of the stock's longer side].
    #[arg(long, value_name = "LENGTH", value_parser = positive)]
    resolution: Option<f64>,
    /// A named 3D view: iso, top, bottom, front, back, right, left [default: iso].
    #[arg(long, value_parser = view_name)]
    view: Option<String>,
    /// Degrees about Z the 3D view looks from: 0 front, 90 right [default: 45].
    #[arg(long, value_name = "DEGREES", value_parser = finite, allow_negative_numbers = true)]
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
    /// MiB the height field may take [default: the config's, or 2048].
    #[arg(long, value_name = "MIB", value_parser = clap::value_parser!(u64).range(1..))]
    memory_limit: Option<u64>,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Args)]
pub(crate) struct PulsesArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Motor steps per machine unit [default: 1000 per inch, 40 per mm].
    #[arg(long, value_name = "N", value_parser = positive)]
    steps_per_unit: Option<f64>,
    /// Show only the first N ticks.
    #[arg(long, value_name = "N")]
    limit: Option<u64>,
}

pub(super) fn positive(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err("expected a number above zero".to_string()),
    }
}

fn finite(text: &str) -> Result<f64, String> {
    text.parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| "expected a number of degrees".to_string())
}

fn elevation(text: &str) -> Result<f64, String> {
    finite(text)
        .ok()
        .filter(|x| (-90.0..=90.0).contains(x))
        .ok_or_else(|| "expected degrees from -90 to 90".to_string())
}

fn zoom(text: &str) -> Result<f64, String> {
    positive(text).ok().filter(|z| *z <= 1000.0).ok_or_else(|| "expected a zoom above 0 and at most 1000".to_string())
}

fn view_name(text: &str) -> Result<String, String> {
    match view::preset(text) {
        Some(_) => Ok(text.to_string()),
        None => Err(format!("expected one of {}", view::PRESETS)),
    }
}

fn size(text: &str) -> Result<(u32, u32), String> {
    let bad = || "expected WIDTHxHEIGHT in pixels, each 16 to 16384, e.g. 1024x768".to_string();
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h) = (w.trim().parse::<u32>().map_err(|_| bad())?, h.trim().parse::<u32>().map_err(|_| bad())?);
    if !(16..=16384).contains(&w) || !(16..=16384).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

/// A reader that counts what the lexer has taken, for the progress bar.
struct Counting<R> {
    inner: R,
    count: Arc<AtomicU64>,
}

impl<R: BufRead> Read for Counting<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.count.fetch_add(n as u64, Ordering::Relaxed);
        Ok(n)
    }
}

impl<R: BufRead> BufRead for Counting<R> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        self.inner.fill_buf()
    }

    fn consume(&mut self, amount: usize) {
        self.count.fetch_add(amount as u64, Ordering::Relaxed);
        self.inner.consume(amount)
    }
}

/// A progress bar on stderr that shows itself once a pass has run a second,
/// unless quiet or stderr is not a terminal.
pub(super) struct Progress {
    bar: ProgressBar,
    started: Instant,
    shown: bool,
    enabled: bool,
}

impl Progress {
    pub(super) fn new(total: u64, message: &'static str, quiet: bool) -> Progress {
        let bar = ProgressBar::with_draw_target(Some(total.max(1)), ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template("{msg:>9} [{bar:40}] {percent:>3}% {elapsed} (eta {eta})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        bar.set_message(message);
        Progress { bar, started: Instant::now(), shown: false, enabled: !quiet && io::stderr().is_terminal() }
    }

    fn update(&mut self, done: u64) {
        if self.enabled && !self.shown && self.started.elapsed() > Duration::from_secs(1) {
            self.shown = true;
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        self.bar.set_position(done);
    }

    pub(super) fn finish(self) {
        self.bar.finish_and_clear();
    }
}

/// Translates `input` and hands every output statement to `each` (which
/// returns false to stop); collects the diagnostics.
pub(super) fn walk(
    input: &Input,
    config: &Config,
    wizards: &mut dyn Wizards,
    progress: Option<&mut Progress>,
    mut each: impl FnMut(&Statement, &mut Report) -> bool,
) -> Report {
    let mut report = Report::default();
    walk_events(input, config, wizards, progress, |event| match event {
        Event::Statement(statement) => each(&statement, &mut report),
        Event::Diagnostic(diagnostic) => {
            report.add(diagnostic);
            true
        }
    });
    report
}

/// Translates `input` and hands every event, statement or diagnostic, to
/// `each` in the order they come (which returns false to stop).
pub(super) fn walk_events(
    input: &Input,
    config: &Config,
    wizards: &mut dyn Wizards,
    progress: Option<&mut Progress>,
    mut each: impl FnMut(Event) -> bool,
) {
    let library = library(input, config.dialect);
    let options = Options { config, stage: LAST_STAGE, wizards };
    let count = Arc::new(AtomicU64::new(0));
    let reader = Counting { inner: input.open(), count: count.clone() };
    let mut progress = progress;
    for (n, event) in translate(reader, library, options).enumerate() {
        if !each(event) {
            break;
        }
        if n % 4096 == 0 {
            if let Some(p) = progress.as_deref_mut() {
                p.update(count.load(Ordering::Relaxed));
            }
        }
    }
}

/// Where the program cuts, and the box of its path (pass 1, when the stock has no size).
pub(super) fn bounds(
    input: &Input,
    config: &Config,
    wizards: &mut dyn Wizards,
    quiet: bool,
) -> (Report, CutBounds, Option<(Point, Point)>) {
    let mut bounds = CutBounds::default();
    let mut path_box: Option<(Point, Point)> = None;
    let mut progress = Progress::new(input_size(input), "bounds", quiet);
    let mut tracker = Tracker::new(&config.tools);
    let report = walk(input, config, wizards, Some(&mut progress), |statement, report| {
        match tracker.step(statement) {
            Ok(Some(m)) => {
                bounds.add(&m.segment, tracker.cutter().as_ref());
                let (lo, hi) = m.segment.bounds();
                let (l, h) = path_box.get_or_insert((lo, hi));
                for i in 0..3 {
                    l[i] = l[i].min(lo[i]);
                    h[i] = h[i].max(hi[i]);
                }
            }
            Ok(None) => {}
            Err(diagnostic) => report.add(diagnostic),
        }
        true
    });
    progress.finish();
    (report, bounds, path_box)
}

/// The simulation at the resolution asked for (or the config's, or the
/// default), unless it would not fit in memory: then the message says what would.
pub(super) fn simulation(
    stock: Stock,
    resolution: Option<f64>,
    memory_limit: Option<u64>,
    config: &Config,
) -> Result<Simulation, String> {
    let cell = resolution.or(config.render.scale.map(|s| 1.0 / s)).unwrap_or(stock.default_cell());
    let limit = memory_limit.or(config.render.memory_limit_mb).unwrap_or(2048) << 20;
    Simulation::new(stock, cell, limit).map_err(|too_big| {
        let unit = config.units.abbreviation();
        format!(
            "a resolution of {} {unit} needs {} MiB for the {} x {} {unit} stock, over the limit of {} MiB; \
             the finest that fits is --resolution {} (or raise --memory-limit)",
            crate::render::label(cell),
            too_big.needed >> 20,
            crate::render::label(stock.size()[0]),
            crate::render::label(stock.size()[1]),
            too_big.limit >> 20,
            round_up(too_big.finest),
        )
    })
}

pub(super) fn input_size(input: &Input) -> u64 {
    match input {
        Input::File(path) => std::fs::metadata(path).map_or(0, |m| m.len()),
        Input::Stdin(buffer) => buffer.len() as u64,
        Input::Text { text, .. } => text.len() as u64,
    }
}

/// Writes `out` through a temporary file beside `path`, so a failure leaves nothing half-written.
fn write_atomically(path: &PathBuf, out: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<(), String> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).map_or_else(|| PathBuf::from("."), PathBuf::from);
    let failed = |err: io::Error| plain_error(&format!("cannot write {}: {err}", path.display()), None);
    let mut temp = tempfile::NamedTempFile::new_in(&dir).map_err(failed)?;
    {
        let mut writer = io::BufWriter::with_capacity(1 << 16, temp.as_file_mut());
        out(&mut writer).map_err(failed)?;
        writer.flush().map_err(failed)?;
    }
    // A temporary file is private (0600); a picture is not.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        temp.as_file().set_permissions(std::fs::Permissions::from_mode(0o644)).map_err(failed)?;
    }
    temp.persist(path).map_err(|err| failed(err.error))?;
    Ok(())
}

pub(super) fn usage_error(message: &str) -> Result<i32, String> {
    eprintln!("error: {message}");
    Ok(2)
}

pub(crate) fn render(args: &RenderArgs) -> Result<i32, String> {
    let input = Input::new(&args.common.file)?;
    let config = load_config(&args.common, &input, styled())?;
    let mut wizards = args.common.wizards.runtime(&config);
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
    let total = input_size(&input);
    let failed = |report: &Report| {
        show(report, &input);
        Ok(1)
    };

    // Pass 1 (unless the stock has a size): where the program cuts, and the path's box.
    let mut bounds = CutBounds::default();
    let stock = Stock::from_config(&config);
    if stock.is_none() || args.toolpath {
        let (report, cut, path_box) = self::bounds(&input, &config, &mut wizards, args.quiet);
        bounds = cut;
        if report.errors() > 0 {
            return failed(&report);
        }
        if args.toolpath {
            let (lo, hi) = path_box.unwrap_or(([0.0; 3], [1.0; 3]));
            let (mut image, projection) = view::blank(&camera, lo, hi);
            let mut painter = view::PathPainter::new(&mut image, projection);
            let mut walker = crate::sim::Walker::new();
            let report = walk(&input, &config, &mut wizards, None, |statement, _| {
                if let Some(crate::sim::Step::Move(m)) = walker.step(statement) {
                    painter.add(&m.segment, m.rapid);
                }
                true
            });
            show(&report, &input);
            write_atomically(&args.output, |out| image.write_png(out))?;
            return Ok(0);
        }
    }
    let stock = stock.unwrap_or_else(|| bounds.stock_for(&config));

    // The simulation.
    let mut sim = match simulation(stock, args.resolution, args.memory_limit, &config) {
        Ok(sim) => sim,
        Err(message) => return usage_error(&message),
    };
    let mut progress = Progress::new(total, "cutting", args.quiet);
    let mut tracker = Tracker::new(&config.tools);
    let report = walk(&input, &config, &mut wizards, Some(&mut progress), |statement, report| {
        match tracker.step(statement) {
            Ok(Some(m)) => {
                if let Some(cutter) = tracker.cutter() {
                    sim.cut(&m.segment, &cutter);
                }
            }
            Ok(None) => {}
            Err(diagnostic) => report.add(diagnostic),
        }
        true
    });
    progress.finish();
    show(&report, &input);
    if report.errors() > 0 {
        return Ok(1);
    }
    let field = sim.finish();

    match format {
        Format::Stl => write_atomically(&args.output, |out| Mesh::new(&field).write_stl(out))?,
        Format::TwoD => {
            let image = top::render(&field, camera.width, camera.height, config.units.abbreviation());
            write_atomically(&args.output, |out| image.write_png(out))?;
        }
        Format::ThreeD => {
            let (mut image, projection) = view::render(&field, &camera);
            if args.with_toolpath {
                let mut painter = view::PathPainter::new(&mut image, projection);
                let mut walker = crate::sim::Walker::new();
                walk(&input, &config, &mut wizards, None, |statement, _| {
                    if let Some(crate::sim::Step::Move(m)) = walker.step(statement) {
                        painter.add(&m.segment, m.rapid);
                    }
                    true
                });
            }
            write_atomically(&args.output, |out| image.write_png(out))?;
        }
    }
    Ok(0)
}

/// Three significant digits, rounded up (so the length quoted does fit).
fn round_up(x: f64) -> String {
    let magnitude = x.log10().floor();
    let p = 10f64.powf(magnitude - 2.0);
    let decimals = (2.0 - magnitude).max(0.0) as usize;
    let text = format!("{:.*}", decimals, (x / p).ceil() * p);
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

pub(crate) fn pulses(args: &PulsesArgs) -> Result<i32, String> {
    let input = Input::new(&args.common.file)?;
    let config = load_config(&args.common, &input, styled())?;
    let mut wizards = args.common.wizards.runtime(&config);
    let spu = args.steps_per_unit.unwrap_or(match config.units {
        crate::statement::Units::Inch => 1000.0,
        crate::statement::Units::Mm => 40.0,
    });
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    let unit = config.units.abbreviation();
    let _ = writeln!(out, "# {} steps per {unit}; a tick steps one or more axes; dir 1 is positive", spu);
    let _ = writeln!(out, "# tick\tline\tstep X Y Z\tdir X Y Z");
    let mut pulser = Pulser::new(spu);
    let mut walker = crate::sim::Walker::new();
    let mut tick = 0u64;
    let limit = args.limit.unwrap_or(u64::MAX);
    let mut broken = false;
    let bit = |b: bool| if b { '1' } else { '0' };
    let report = walk(&input, &config, &mut wizards, None, |statement, _| {
        let Some(crate::sim::Step::Move(m)) = walker.step(statement) else { return true };
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
    show(&report, &input);
    Ok(i32::from(report.errors() > 0))
}
