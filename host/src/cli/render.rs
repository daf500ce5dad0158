//! `ger render` and `ger pulses`: the program translated, then simulated,
//! drawn or turned into pulses. Each pass over the program streams: the
//! statements are used as they come and never collected.

use std::io::{self, BufRead, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::report::{plain_error, Report};
use super::{cannot_write, config_error, library, load_config, show, styled, CommonArgs, Input, Purpose};
use ger_core::config::{quoted, Bounds, Config, Step, MAX_MEMORY_MIB};
use ger_core::passes::{translate, Event, Options, LAST_STAGE};
use ger_core::statement::{Statement, Units};
use ger_core::wizard::Wizards;
use ger_output::OutputFile;
use ger_render::{label, mesh::Mesh, top, view};
use ger_sim::pulses::Pulser;
use ger_sim::{CutBounds, Point, Refusal, Simulation, Stock, Tracker};

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
    /// The side of a simulation cell, in machine units [default: the config's
    /// scale, or 1/1000 of the stock's longer side].
    #[arg(long, value_name = "LENGTH", value_parser = resolution)]
    resolution: Option<f64>,
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
    /// MiB the height field may take [default: the config's, or 2048].
    #[arg(long, value_name = "MIB", value_parser = memory_limit)]
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
    #[arg(long, value_name = "N", value_parser = steps_per_unit)]
    steps_per_unit: Option<f64>,
    /// Show only the first N ticks.
    #[arg(long, value_name = "N")]
    limit: Option<u64>,
}

/// A number from `low` to `high`, or what to write instead.
fn within(text: &str, low: f64, high: f64, what: &str) -> Result<f64, String> {
    text.parse::<f64>().ok().filter(|x| (low..=high).contains(x)).ok_or_else(|| format!("expected {what}"))
}

/// A cell's side: within the bounds of a machine in either unit (`simulation`
/// then holds it to the machine's own unit).
pub(super) fn resolution(text: &str) -> Result<f64, String> {
    let (inch, mm) = (Bounds::of(Units::Inch), Bounds::of(Units::Mm));
    let (low, high) = (inch.smallest, mm.length);
    within(text, low, high, &format!("a length from {} to {} (in the machine's unit)", quoted(low), quoted(high)))
}

fn steps_per_unit(text: &str) -> Result<f64, String> {
    within(text, 0.001, 1_000_000.0, "a number of steps from 0.001 to 1000000")
}

/// `--memory-limit`: MiB, as `[render] memory_limit_mb`.
pub(super) fn memory_limit(text: &str) -> Result<u64, String> {
    text.parse::<u64>()
        .ok()
        .filter(|m| (1..=MAX_MEMORY_MIB).contains(m))
        .ok_or_else(|| format!("expected a number of MiB from 1 to {MAX_MEMORY_MIB} (1 TiB)"))
}

fn azimuth(text: &str) -> Result<f64, String> {
    within(text, -360.0, 360.0, "degrees from -360 to 360")
}

fn elevation(text: &str) -> Result<f64, String> {
    within(text, -90.0, 90.0, "degrees from -90 to 90")
}

fn zoom(text: &str) -> Result<f64, String> {
    within(text, 0.01, 1000.0, "a zoom from 0.01 to 1000")
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
    let library = library(input, &config.dialect);
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

/// Why no simulation could be made: the message, and whose number asked for it.
pub(super) struct Refused {
    pub message: String,
    by: Culprit,
}

enum Culprit {
    CommandLine,
    /// A key of the config's `[render]` table.
    Config(&'static str),
    /// The program, or the machine: no number anyone gave.
    Neither,
}

impl Refused {
    /// The exit: a command line's number is a usage error (2); the config's is
    /// shown at its key, and anything else as an error (1).
    pub(super) fn exit(self, common: &CommonArgs, input: &Input) -> Result<i32, String> {
        match self.by {
            Culprit::CommandLine => usage_error(&self.message),
            Culprit::Config(key) => {
                Err(config_error(common, input, &[Step::Key("render"), Step::Key(key)], &self.message))
            }
            Culprit::Neither => Err(plain_error(&self.message, None)),
        }
    }
}

/// The simulation at the resolution asked for (or the config's, or the
/// default), unless it would not fit in memory: then the message says what would.
pub(super) fn simulation(
    stock: Stock,
    resolution: Option<f64>,
    memory_limit: Option<u64>,
    config: &Config,
) -> Result<Simulation, Refused> {
    let unit = config.units.abbreviation();
    let bounds = Bounds::of(config.units);
    let refuse = |by, message| Err(Refused { message, by });
    if resolution.is_some_and(|cell| !(bounds.smallest..=bounds.length).contains(&cell)) {
        let message =
            format!("--resolution must be from {} to {} {unit}", quoted(bounds.smallest), quoted(bounds.length));
        return refuse(Culprit::CommandLine, message);
    }
    let size = stock.size();
    // A stock by margin is where the program goes: its coordinates may be anything.
    if !size.iter().all(|s| *s <= bounds.length) {
        let message = format!(
            "the stock would be {} x {} x {} {unit}, everything the program cuts with a margin of {} {unit} all \
             round: over {} {unit}, more than any machine travels; check the program's coordinates, or give \
             [stock] size in ger.toml",
            label(size[0]),
            label(size[1]),
            label(size[2]),
            label(config.stock_margin()),
            label(bounds.length),
        );
        return refuse(Culprit::Neither, message);
    }
    let cell = resolution.or(config.render.scale.map(|s| 1.0 / s)).unwrap_or(stock.default_cell());
    // Bounded by the command line's parser and the config's validation: no overflow.
    let limit = memory_limit.or(config.render.memory_limit_mb).unwrap_or(2048) << 20;
    Simulation::new(stock, cell, limit).map_err(|refusal| match refusal {
        Refusal::TooBig(too_big) => {
            let by = if resolution.is_some() || memory_limit.is_some() {
                Culprit::CommandLine
            } else if config.render.scale.is_some() {
                Culprit::Config("scale")
            } else if config.render.memory_limit_mb.is_some() {
                Culprit::Config("memory_limit_mb")
            } else {
                Culprit::Neither
            };
            let fits = match by {
                Culprit::Config(_) => format!(
                    "the most that fits is scale = {} (or raise memory_limit_mb)",
                    // Cells per unit, rounded down so that it does fit.
                    three_digits(1.0 / too_big.finest, f64::floor)
                ),
                _ => format!(
                    "the finest that fits is --resolution {} (or raise --memory-limit)",
                    round_up(too_big.finest)
                ),
            };
            let message = format!(
                "a resolution of {} {unit} needs {} MiB for the {} x {} {unit} stock, over the limit of {} MiB; {fits}",
                label(cell),
                too_big.needed >> 20,
                label(size[0]),
                label(size[1]),
                too_big.limit >> 20,
            );
            Refused { message, by }
        }
        Refusal::OutOfMemory { needed } => Refused {
            message: format!(
                "cannot have the {} MiB the height field needs at a resolution of {} {unit}: the system refused \
                 it; give a coarser --resolution or a lower --memory-limit",
                needed >> 20,
                label(cell)
            ),
            by: Culprit::Neither,
        },
    })
}

pub(super) fn input_size(input: &Input) -> u64 {
    match input {
        Input::File(path) => std::fs::metadata(path).map_or(0, |m| m.len()),
        Input::Stdin(buffer) => buffer.len() as u64,
        Input::Text { text, .. } => text.len() as u64,
    }
}

/// Writes `out` to `output` and commits it: nothing is replaced unless all of it was written.
fn save(mut output: OutputFile, path: &Path, out: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<(), String> {
    out(&mut output).and_then(|()| output.commit()).map_err(|err| cannot_write(path, &err))
}

pub(super) fn usage_error(message: &str) -> Result<i32, String> {
    eprintln!("error: {message}");
    Ok(2)
}

pub(crate) fn render(args: &RenderArgs) -> Result<i32, String> {
    let input = Input::new(&args.common.file)?;
    let config = load_config(&args.common, &input, Purpose::Cut, styled())?;
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
    // Now, so that an output that cannot be written is said before the simulation runs.
    let output = OutputFile::create(&args.output).map_err(|err| cannot_write(&args.output, &err))?;
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
            let mut walker = ger_sim::Walker::new();
            let report = walk(&input, &config, &mut wizards, None, |statement, _| {
                if let Some(ger_sim::Step::Move(m)) = walker.step(statement) {
                    painter.add(&m.segment, m.rapid);
                }
                true
            });
            show(&report, &input);
            save(output, &args.output, |out| image.write_png(out))?;
            return Ok(0);
        }
    }
    let stock = stock.unwrap_or_else(|| bounds.stock_for(&config));

    // The simulation.
    let mut sim = match simulation(stock, args.resolution, args.memory_limit, &config) {
        Ok(sim) => sim,
        Err(refused) => return refused.exit(&args.common, &input),
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
        Format::Stl => save(output, &args.output, |out| Mesh::new(&field).write_stl(out))?,
        Format::TwoD => {
            let image = top::render(&field, camera.width, camera.height, config.units.abbreviation());
            save(output, &args.output, |out| image.write_png(out))?;
        }
        Format::ThreeD => {
            let (mut image, projection) = view::render(&field, &camera);
            if args.with_toolpath {
                let mut painter = view::PathPainter::new(&mut image, projection);
                let mut walker = ger_sim::Walker::new();
                walk(&input, &config, &mut wizards, None, |statement, _| {
                    if let Some(ger_sim::Step::Move(m)) = walker.step(statement) {
                        painter.add(&m.segment, m.rapid);
                    }
                    true
                });
            }
            save(output, &args.output, |out| image.write_png(out))?;
        }
    }
    Ok(0)
}

/// Three significant digits, rounded up (so the length quoted does fit).
fn round_up(x: f64) -> String {
    three_digits(x, f64::ceil)
}

/// Three significant digits, rounded by `round` (up or down).
fn three_digits(x: f64, round: fn(f64) -> f64) -> String {
    let magnitude = x.log10().floor();
    let p = 10f64.powf(magnitude - 2.0);
    let decimals = (2.0 - magnitude).max(0.0) as usize;
    let text = format!("{:.*}", decimals, round(x / p) * p);
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

pub(crate) fn pulses(args: &PulsesArgs) -> Result<i32, String> {
    let input = Input::new(&args.common.file)?;
    let config = load_config(&args.common, &input, Purpose::Translate, styled())?;
    let mut wizards = args.common.wizards.runtime(&config);
    let spu = args.steps_per_unit.unwrap_or(match config.units {
        ger_core::statement::Units::Inch => 1000.0,
        ger_core::statement::Units::Mm => 40.0,
    });
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    let unit = config.units.abbreviation();
    let _ = writeln!(out, "# {} steps per {unit}; a tick steps one or more axes; dir 1 is positive", spu);
    let _ = writeln!(out, "# tick\tline\tstep X Y Z\tdir X Y Z");
    let mut pulser = Pulser::new(spu);
    let mut walker = ger_sim::Walker::new();
    let mut tick = 0u64;
    let limit = args.limit.unwrap_or(u64::MAX);
    let mut broken = false;
    let bit = |b: bool| if b { '1' } else { '0' };
    let report = walk(&input, &config, &mut wizards, None, |statement, _| {
        let Some(ger_sim::Step::Move(m)) = walker.step(statement) else { return true };
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
