//! The session `ger view` serves: one program (its file, its folder, the text
//! the page last sent) and the snapshots made of it. One worker thread makes
//! snapshots; changes that arrive while it works wait, and the next snapshot
//! takes them all at once (the latest text wins).

use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Instant;

use axum::body::Bytes;
use serde::Serialize;
use tokio::sync::watch;

use crate::{Error, Options};
use ger_engine::check::{outermost_line, Checker, Rule};
use ger_engine::compare::Comparison;
use ger_engine::core::diag::{Diagnostic, Severity, Span};
use ger_engine::core::emit::{preamble, Emitter};
use ger_engine::core::passes::Event;
use ger_engine::render::pieces::{self, Piece};
use ger_engine::sim::{HeightField, Simulation, Solid, Step, Stock, Walker};
use ger_engine::{default_tolerance, place_design, Job, Program, Purpose, Resolution, Silent, Source};
use ger_output::OutputFile;

/// Above this many pieces the toolpath sent to the page is decimated.
const MAX_PIECES: usize = 200_000;
/// Above this many lines the page shows the program without editing it.
const READ_ONLY_LINES: usize = 50_000;
/// By default the part is simulated in this many cells along the stock's longer side.
const CELLS: f64 = 500.0;

/// What a snapshot or a client waiting on one is told, by the events it becomes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Notice {
    /// Snapshot N is being made.
    Busy(u64),
    /// Snapshot N is ready.
    Ready(u64),
}

/// A program as the session holds it.
#[derive(Clone)]
struct Opened {
    /// Canonical.
    file: PathBuf,
    /// Relative to the session's folder, with `/` between parts.
    name: String,
    /// The page's text: the file's unless edited since.
    text: Arc<str>,
    /// The file's text as the session last read or wrote it.
    disk: Arc<str>,
    /// The file changed on disk while the page's text had unsaved edits.
    conflict: bool,
}

impl Opened {
    fn saved(&self) -> bool {
        self.text == self.disk
    }
}

struct State {
    /// The newest change's number: the snapshot that will show it.
    version: u64,
    /// A change is waiting for the worker.
    pending: bool,
    program: Opened,
}

/// Why a path asked for cannot be opened.
pub(crate) enum Refusal {
    /// Absolute, climbing with `..`, or a symlink out of the folder.
    Outside,
    Missing,
    TooLarge,
    NotText,
}

/// A snapshot: the program translated, checked and simulated, ready to send.
pub(crate) struct Snapshot {
    pub version: u64,
    /// The state's JSON after its opening brace, without `version` and `busy`,
    /// which are put in front of it when it is sent (`busy` changes without a new snapshot).
    rest: Bytes,
    /// `nx × ny` little-endian f32; empty without a part.
    pub heights: Bytes,
    /// 32 bytes a piece of toolpath.
    pub path: Bytes,
    /// `nx × ny` bytes, each cell's verdict against the design; empty without one.
    pub verdicts: Bytes,
}

impl Snapshot {
    /// `/api/state`'s body, in two parts to send one after the other.
    pub fn state(&self, busy: bool) -> (Bytes, Bytes) {
        (Bytes::from(format!("{{\"version\":{},\"busy\":{},", self.version, busy)), self.rest.clone())
    }
}

pub(crate) struct Session {
    options: Options,
    /// The program's folder, canonical: all that `/api/open` and `/api/files` reach.
    pub folder: PathBuf,
    state: Mutex<State>,
    wake: Condvar,
    latest: Mutex<Arc<Snapshot>>,
    notices: watch::Sender<Notice>,
}

impl Session {
    /// Reads the program and starts the worker on its first snapshot.
    pub fn start(mut options: Options) -> Result<Arc<Session>, Error> {
        // The job's programs by canonical path: the one opened is found among them by it.
        for path in &mut options.job {
            let cause = |cause| Error::Read { name: path.display().to_string(), cause };
            *path = path.canonicalize().map_err(cause)?;
        }
        let given = &options.file;
        let cannot = |cause: io::Error| Error::Read { name: given.display().to_string(), cause };
        let file = given.canonicalize().map_err(cannot)?;
        let text: Arc<str> = std::fs::read_to_string(&file).map_err(cannot)?.into();
        let folder = file.parent().map_or_else(|| PathBuf::from("/"), Path::to_path_buf);
        let name = file.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let program = Opened { file, name, text: text.clone(), disk: text, conflict: false };
        let empty = Arc::new(snapshot(0, &program, Made::default(), 0));
        let session = Arc::new(Session {
            options,
            folder,
            state: Mutex::new(State { version: 1, pending: true, program }),
            wake: Condvar::new(),
            latest: Mutex::new(empty),
            notices: watch::Sender::new(Notice::Busy(1)),
        });
        let worker = session.clone();
        std::thread::Builder::new()
            .name("ger view snapshots".to_string())
            .spawn(move || worker.work())
            .map_err(|cause| Error::Start { what: "start the snapshot worker", cause })?;
        Ok(session)
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic while holding the lock leaves the state consistent: every change is one assignment.
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Asks for a snapshot of the state as changed now; returns its number.
    fn changed(&self, state: &mut State) -> u64 {
        state.version += 1;
        state.pending = true;
        self.wake.notify_one();
        state.version
    }

    /// The latest snapshot, and whether a newer one is on its way.
    pub fn latest(&self) -> (Arc<Snapshot>, bool) {
        let snapshot = self.latest.lock().unwrap_or_else(|p| p.into_inner()).clone();
        let busy = self.lock().version > snapshot.version;
        (snapshot, busy)
    }

    pub fn notices(&self) -> watch::Receiver<Notice> {
        self.notices.subscribe()
    }

    /// The page's text, not saved.
    pub fn edit(&self, text: String) -> u64 {
        let mut state = self.lock();
        state.program.text = text.into();
        if state.program.saved() {
            state.program.conflict = false;
        }
        self.changed(&mut state)
    }

    /// The page's text, written to the file. The lock is held while writing,
    /// so the watcher, seeing the file change, finds the text it already knows.
    pub fn save(&self, text: String) -> Result<u64, FileError> {
        let mut state = self.lock();
        write_whole(&state.program.file, text.as_bytes())?;
        let text: Arc<str> = text.into();
        state.program.text = text.clone();
        state.program.disk = text;
        state.program.conflict = false;
        Ok(self.changed(&mut state))
    }

    /// Drops unsaved edits: the file's text again.
    pub fn reload(&self) -> Result<u64, FileError> {
        let mut state = self.lock();
        let text: Arc<str> = read(&state.program.file)?.into();
        state.program.text = text.clone();
        state.program.disk = text;
        state.program.conflict = false;
        Ok(self.changed(&mut state))
    }

    /// Views another program of the folder, `relative` to it.
    pub fn open(&self, relative: &str) -> Result<u64, Refusal> {
        let file = self.resolve(relative)?;
        let size = std::fs::metadata(&file).map_err(|_| Refusal::Missing)?.len();
        if size > crate::server::BODY_LIMIT as u64 {
            return Err(Refusal::TooLarge);
        }
        let text: Arc<str> = std::fs::read_to_string(&file).map_err(|_| Refusal::NotText)?.into();
        let name = file.strip_prefix(&self.folder).map_or_else(|_| relative.to_string(), slashed);
        let mut state = self.lock();
        state.program = Opened { file, name, text: text.clone(), disk: text, conflict: false };
        Ok(self.changed(&mut state))
    }

    /// The canonical path of the file `relative` names, if it is in the folder.
    fn resolve(&self, relative: &str) -> Result<PathBuf, Refusal> {
        let path = Path::new(relative);
        let climbs = path.components().any(|c| !matches!(c, std::path::Component::Normal(_)));
        // `Path::is_absolute` misses `/x` on Windows and `C:x` anywhere: refuse any root or prefix.
        if relative.is_empty() || climbs || relative.starts_with(['/', '\\']) {
            return Err(Refusal::Outside);
        }
        let joined = self.folder.join(path);
        let file = joined.canonicalize().map_err(|_| match joined.symlink_metadata() {
            // A dangling symlink: wherever it points, it does not lead to a file here.
            Ok(_) => Refusal::Outside,
            Err(_) => Refusal::Missing,
        })?;
        if !file.starts_with(&self.folder) {
            return Err(Refusal::Outside);
        }
        if !file.is_file() {
            return Err(Refusal::Missing);
        }
        Ok(file)
    }

    /// The file the watcher reports changed: the page follows it unless it has
    /// unsaved edits (then it is a conflict). A save of our own changes nothing.
    pub fn file_changed(&self) {
        let file = self.lock().program.file.clone();
        // Missing while an editor replaces it: the next event brings the new file.
        let Ok(text) = read(&file) else { return };
        let mut state = self.lock();
        if state.program.file != file || *state.program.disk == *text {
            return;
        }
        if state.program.saved() {
            state.program.text = text.as_str().into();
        } else {
            state.program.conflict = true;
        }
        state.program.disk = text.into();
        self.changed(&mut state);
    }

    /// The config or a wizard changed: the same text again.
    pub fn machine_changed(&self) {
        let mut state = self.lock();
        self.changed(&mut state);
    }

    /// The files the watcher looks at now: the program, and its config.
    pub fn watched(&self) -> (PathBuf, PathBuf) {
        let file = self.lock().program.file.clone();
        let config = match &self.options.settings.config {
            Some(path) => path.clone(),
            None => file.with_file_name("ger.toml"),
        };
        (file, config)
    }

    pub fn wizards(&self) -> &Path {
        &self.options.wizards_dir
    }

    /// The G-code files in the folder and below it, relative and sorted.
    /// Hidden folders and symlinks are passed by; at most `LIMIT` are listed.
    pub fn files(&self) -> Vec<String> {
        const LIMIT: usize = 10_000;
        const EXTENSIONS: [&str; 5] = ["ngc", "nc", "tap", "gcode", "cnc"];
        let mut files = Vec::new();
        let mut folders = vec![self.folder.clone()];
        while let Some(folder) = folders.pop() {
            let Ok(entries) = std::fs::read_dir(&folder) else { continue };
            for entry in entries.flatten() {
                let (path, Ok(kind)) = (entry.path(), entry.file_type()) else { continue };
                if kind.is_dir() && !entry.file_name().to_string_lossy().starts_with('.') {
                    folders.push(path);
                } else if kind.is_file()
                    && path.extension().is_some_and(|e| EXTENSIONS.iter().any(|x| e.eq_ignore_ascii_case(x)))
                {
                    files.push(slashed(path.strip_prefix(&self.folder).unwrap_or(&path)));
                    if files.len() == LIMIT {
                        folders.clear();
                        break;
                    }
                }
            }
        }
        files.sort();
        files
    }

    /// The worker: makes a snapshot whenever one is asked for, forever.
    fn work(&self) {
        loop {
            let (version, program) = {
                let mut state = self.lock();
                while !state.pending {
                    state = self.wake.wait(state).unwrap_or_else(|p| p.into_inner());
                }
                state.pending = false;
                (state.version, state.program.clone())
            };
            self.notices.send_replace(Notice::Busy(version));
            let started = Instant::now();
            let made = make(&self.options, &program);
            let snapshot = snapshot(version, &program, made, started.elapsed().as_millis() as u64);
            *self.latest.lock().unwrap_or_else(|p| p.into_inner()) = Arc::new(snapshot);
            self.notices.send_replace(Notice::Ready(version));
        }
    }
}

fn slashed(path: &Path) -> String {
    path.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/")
}

/// A program file the page asked to read or write that could not be.
#[derive(Debug, thiserror::Error)]
#[error("cannot {action} {}: {cause}", file.display())]
pub(crate) struct FileError {
    action: &'static str,
    file: PathBuf,
    cause: io::Error,
}

fn read(file: &Path) -> Result<String, FileError> {
    std::fs::read_to_string(file).map_err(|cause| FileError { action: "read", file: file.to_path_buf(), cause })
}

/// Writes the file whole (see `ger_output`): never half-written, keeping its mode.
fn write_whole(file: &Path, text: &[u8]) -> Result<(), FileError> {
    let written = OutputFile::create(file).and_then(|mut output| output.write_all(text).and_then(|()| output.commit()));
    written.map_err(|cause| FileError { action: "write", file: file.to_path_buf(), cause })
}

/// What a translation, check and simulation of a program made.
#[derive(Default)]
struct Made {
    output: String,
    source_lines: Vec<u32>,
    /// The translator's diagnostics and the checks', in program order.
    findings: Vec<(Option<Rule>, Diagnostic)>,
    /// Problems with no place in the program (the config, the stock).
    problems: Vec<String>,
    field: Option<HeightField>,
    units: &'static str,
    pieces: Vec<Piece>,
    /// The cell pieces were made within.
    cell: f64,
    /// The planned run time, when the program moves.
    run_time: Option<RunTime>,
    fixtures: Vec<JsonFixture>,
    /// The names of the job's programs, when the program is one of them.
    job: Vec<String>,
    /// The part against `--design`, and each cell's verdict (`Verdict as u8`).
    design: Option<JsonDesign>,
    verdicts: Vec<u8>,
}

/// The part against its design, as `ger compare --format json` gives it.
#[derive(Serialize)]
struct JsonDesign {
    file: String,
    #[serde(flatten)]
    comparison: Comparison,
}

/// The planned run time, as the snapshot gives it.
#[derive(Default, Serialize)]
struct RunTime {
    seconds: f64,
    /// The profile's preset, and whether ger.toml's [machine.motion] set it.
    preset: &'static str,
    configured: bool,
    /// When the run reaches each line of the program (1 first), seconds.
    lines: Vec<f64>,
}

/// To the hundredth of a second: the page shows no finer, and the snapshot stays short.
fn centiseconds(seconds: f64) -> f64 {
    (seconds * 100.0).round() / 100.0
}

/// Translates, checks and simulates `opened` on the machine `options` describe,
/// with the programs of its job before and after it (see [`Options::job`]).
fn make(options: &Options, opened: &Opened) -> Made {
    let dir = opened.file.parent().map_or_else(|| PathBuf::from("/"), Path::to_path_buf);
    let source = Source::text(opened.name.clone(), dir, opened.text.clone());
    let mut made = Made::default();
    let load = |source: Source| -> Result<Program, String> {
        let config =
            options.settings.load(&source, Purpose::Cut).map_err(|err| err.render(false).trim_end().to_string())?;
        let wizards = (options.wizards)(&config);
        Ok(Program::new(source, config).with_wizards(wizards))
    };
    let program = match load(source) {
        Ok(program) => program,
        Err(problem) => {
            made.problems.push(problem);
            return made;
        }
    };
    let config = program.config().clone();
    made.units = config.units.abbreviation();
    made.fixtures = config.fixtures.iter().map(|f| JsonFixture::of(&Solid::of(f, &config), &f.name)).collect();
    // The job around it: none when the program opened is not one of the job's.
    let at = options.job.iter().position(|path| *path == opened.file);
    let (before, after) = at.map_or((&[][..], &[][..]), |k| (&options.job[..k], &options.job[k + 1..]));
    let mut programs = Vec::new();
    for path in before.iter().chain(after) {
        match Source::open_path(path).map_err(|err| err.to_string()).and_then(load) {
            Ok(program) => programs.push(program),
            Err(problem) => made.problems.push(problem),
        }
    }
    if !made.problems.is_empty() {
        return made;
    }
    made.job = at.map_or_else(Vec::new, |_| options.job.iter().map(|p| name_of(p)).collect());
    let after = programs.split_off(before.len());
    let first = before.len();
    programs.push(program);
    programs.extend(after);
    let mut job = Job::new(programs.remove(0), programs);
    // Without a size, the stock is where the job cuts: one pass to find it
    // (as `ger check`), unless the program alone does not move.
    let stock = match job.programs().len() {
        1 => Stock::from_config(&config).or_else(|| {
            let extent = job.programs_mut()[0].extent(&mut Silent);
            extent.path_box.map(|_| extent.cut.stock_for(&config))
        }),
        _ => Some(job.stock(&mut Silent).0),
    };
    made.cell = stock.map_or(1.0, |stock| options.resolution.unwrap_or(view_cell(&stock)));
    let asked = Resolution { cell: Some(made.cell), memory_limit_mib: options.memory_limit_mib };
    let mut simulation = match stock.map(|stock| job.simulation(stock, asked)) {
        Some(Ok(sim)) => Some(sim),
        Some(Err(refused)) => {
            made.problems.push(refused.message);
            None
        }
        None => None,
    };
    // The programs before it cut the stock it is checked on.
    for program in &mut job.programs_mut()[..first] {
        let Some(sim) = simulation.take() else { break };
        let (part, report) = program.simulate(sim, &mut Silent);
        if report.errors() > 0 {
            made.problems.push(format!(
                "{}: {} errors: the part shown is cut without it",
                program.source().name(),
                report.errors()
            ));
        }
        simulation = Some(Simulation::resume(part));
    }
    let mut checker = simulation.map(|sim| Checker::new(&config, sim, &[]).timing_lines());
    let output = &mut made.output;
    output.push_str(&preamble(&opened.name, config.units));
    made.source_lines = vec![0; output.lines().count()];
    let emitter = Emitter::new(config.units.decimals(), true);
    let mut walker = Walker::new();
    // One pass makes the translation's text, the toolpath and the check.
    job.programs_mut()[first].for_each_event("checking", &mut Silent, |event| {
        match event {
            Event::Statement(statement) => {
                emitter.write(output, &statement);
                output.push('\n');
                let line = made.source_lines.len() as u32;
                made.source_lines.push(outermost_line(&statement));
                if let Some(Step::Move(m)) = walker.step(&statement) {
                    pieces::split(&m, line, made.cell, &mut made.pieces);
                }
                if let Some(checker) = &mut checker {
                    checker.statement(&statement);
                }
            }
            Event::Diagnostic(diagnostic) => match &mut checker {
                Some(checker) => checker.translator(diagnostic),
                None => made.findings.push((None, diagnostic)),
            },
        }
        true
    });
    if let Some(checker) = checker {
        let (verdict, field) = checker.finish_with_part();
        made.findings = verdict.findings.into_iter().map(|f| (f.rule, f.diagnostic)).collect();
        let planned = &verdict.summary.planned;
        made.run_time = planned.moving.is_some().then(|| RunTime {
            seconds: centiseconds(planned.seconds),
            preset: planned.profile.preset,
            configured: planned.profile.configured,
            lines: verdict.line_times.iter().map(|t| centiseconds(*t)).collect(),
        });
        let failed_before_moving = made.pieces.is_empty() && made.findings.iter().any(|(_, d)| d.is_error());
        if !failed_before_moving {
            // The programs after it cut on; the part is the job's.
            let (field, _) = job.simulate_after(first, field, &mut Silent);
            if let (Some(design), Some(stock)) = (&options.design, stock) {
                let first_config = job.programs()[0].config();
                let mut mesh = design.mesh.clone();
                place_design(
                    &mut mesh,
                    first_config,
                    design.units.unwrap_or(first_config.units),
                    design.origin,
                    &stock,
                );
                let tolerance = design.tolerance.unwrap_or(default_tolerance(first_config.units));
                let judged = ger_engine::compare::compare(&field, &mesh.top_surface(&field), tolerance);
                made.verdicts = judged.verdicts.iter().map(|v| *v as u8).collect();
                made.design = Some(JsonDesign { file: design.name.clone(), comparison: judged.comparison });
            }
            made.field = Some(field);
        }
    }
    made
}

/// A program's file name, as the page names the job's programs.
fn name_of(path: &Path) -> String {
    path.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

/// The default cell: the stock's longer side in `CELLS`.
fn view_cell(stock: &Stock) -> f64 {
    let size = stock.size();
    size[0].max(size[1]) / CELLS
}

#[derive(Serialize)]
struct Body<'a> {
    file: &'a str,
    source: &'a str,
    saved: bool,
    conflict: bool,
    read_only: bool,
    output: Output<'a>,
    diagnostics: Vec<JsonDiagnostic>,
    part: Option<Part>,
    fixtures: &'a [JsonFixture],
    job: &'a [String],
    design: Option<&'a JsonDesign>,
    path: PathSummary,
    run_time: Option<RunTime>,
    elapsed_ms: u64,
}

/// A `[[fixtures]]` solid, in machine coordinates, for the page to draw.
#[derive(Serialize)]
struct JsonFixture {
    name: String,
    /// "box" or "cylinder" (upright).
    shape: &'static str,
    /// Its box: a cylinder's centre is the middle of it in X and Y, its radius half its X extent.
    min: [f64; 3],
    max: [f64; 3],
}

impl JsonFixture {
    fn of(solid: &Solid, name: &str) -> JsonFixture {
        let (min, max) = solid.bounds();
        let shape = match solid {
            Solid::Box { .. } => "box",
            Solid::Cylinder { .. } => "cylinder",
        };
        JsonFixture { name: name.to_string(), shape, min: min.into(), max: max.into() }
    }
}

#[derive(Serialize)]
struct Output<'a> {
    text: &'a str,
    source_lines: &'a [u32],
}

#[derive(Serialize)]
struct JsonDiagnostic {
    severity: &'static str,
    message: String,
    help: Option<String>,
    line: u32,
    column: u32,
    end_line: u32,
    end_column: u32,
    call_chain: Vec<String>,
    check: Option<&'static str>,
}

#[derive(Serialize)]
struct Part {
    nx: usize,
    ny: usize,
    x0: f64,
    y0: f64,
    cell_x: f64,
    cell_y: f64,
    top: f64,
    bottom: f64,
    units: &'static str,
}

#[derive(Serialize)]
struct PathSummary {
    pieces: usize,
    total: usize,
    decimated: bool,
    min: [f32; 3],
    max: [f32; 3],
}

/// The snapshot of what `make` made: JSON and binary, as sent.
fn snapshot(version: u64, program: &Opened, made: Made, elapsed_ms: u64) -> Snapshot {
    let text = &*program.text;
    let columns = Columns::new(text);
    let mut diagnostics: Vec<JsonDiagnostic> = made
        .problems
        .into_iter()
        .map(|message| JsonDiagnostic {
            severity: "error",
            message,
            help: None,
            line: 0,
            column: 0,
            end_line: 0,
            end_column: 0,
            call_chain: Vec::new(),
            check: None,
        })
        .collect();
    diagnostics.extend(made.findings.iter().map(|(rule, d)| diagnostic(*rule, d, &columns)));
    let total = made.pieces.len();
    let (mut min, mut max) = ([f32::MAX; 3], [f32::MIN; 3]);
    for piece in &made.pieces {
        for i in 0..3 {
            min[i] = min[i].min(piece.from[i]).min(piece.to[i]);
            max[i] = max[i].max(piece.from[i]).max(piece.to[i]);
        }
    }
    if total == 0 {
        (min, max) = ([0.0; 3], [0.0; 3]);
    }
    let sent = if total > MAX_PIECES { pieces::decimate(&made.pieces, made.cell) } else { made.pieces };
    let mut path = Vec::with_capacity(sent.len() * 32);
    for piece in &sent {
        for v in piece.from.iter().chain(&piece.to) {
            path.extend_from_slice(&v.to_le_bytes());
        }
        path.extend_from_slice(&piece.line.to_le_bytes());
        path.extend_from_slice(&(piece.kind as u32).to_le_bytes());
    }
    let mut heights = Vec::new();
    let part = made.field.as_ref().map(|field| {
        heights.reserve(field.nx * field.ny * 4);
        for j in 0..field.ny {
            for i in 0..field.nx {
                heights.extend_from_slice(&(field.get(i, j) as f32).to_le_bytes());
            }
        }
        Part {
            nx: field.nx,
            ny: field.ny,
            x0: field.stock.min[0],
            y0: field.stock.min[1],
            cell_x: field.cell,
            cell_y: field.cell_y(),
            top: field.top(),
            bottom: field.bottom(),
            units: made.units,
        }
    });
    let body = Body {
        file: &program.name,
        source: text,
        saved: program.saved(),
        conflict: program.conflict,
        read_only: text.lines().count() > READ_ONLY_LINES,
        output: Output { text: &made.output, source_lines: &made.source_lines },
        diagnostics,
        part,
        fixtures: &made.fixtures,
        job: &made.job,
        design: made.design.as_ref(),
        path: PathSummary { pieces: sent.len(), total, decimated: sent.len() < total, min, max },
        run_time: made.run_time,
        elapsed_ms,
    };
    let json = serde_json::to_string(&body).expect("the snapshot serialises: no maps, no non-string keys");
    Snapshot {
        version,
        rest: Bytes::from(json).slice(1..),
        heights: Bytes::from(heights),
        path: Bytes::from(path),
        verdicts: Bytes::from(made.verdicts),
    }
}

fn diagnostic(rule: Option<Rule>, d: &Diagnostic, columns: &Columns) -> JsonDiagnostic {
    let Span { line, col, len } = d.span;
    let mut call_chain = Vec::new();
    let mut next = d.origin.as_deref();
    while let Some(origin) = next {
        call_chain.push(format!("{} at line {}", origin.what, origin.call.line));
        next = origin.parent.as_deref();
    }
    JsonDiagnostic {
        severity: match d.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        },
        message: d.message.clone(),
        help: d.help.clone(),
        line,
        column: columns.utf16(line, col),
        end_line: line,
        end_column: columns.utf16(line, col + len.max(1)),
        call_chain,
        check: rule.map(Rule::name),
    }
}

/// Byte columns to the page's: JavaScript counts UTF-16 units. Only a text
/// with non-ASCII characters needs its lines found.
struct Columns<'a> {
    text: &'a str,
    starts: Option<Vec<usize>>,
}

impl<'a> Columns<'a> {
    fn new(text: &'a str) -> Columns<'a> {
        let starts = (!text.is_ascii())
            .then(|| std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect());
        Columns { text, starts }
    }

    /// The 1-based UTF-16 column of 1-based byte column `col` on 1-based `line`.
    fn utf16(&self, line: u32, col: u32) -> u32 {
        let Some(starts) = &self.starts else { return col };
        let Some(&start) = starts.get((line as usize).wrapping_sub(1)) else { return col };
        let end = self.text[start..].find('\n').map_or(self.text.len(), |n| start + n);
        let line_text = &self.text[start..end];
        let mut byte = (col as usize).saturating_sub(1).min(line_text.len());
        while !line_text.is_char_boundary(byte) {
            byte -= 1;
        }
        line_text[..byte].encode_utf16().count() as u32 + 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_count_utf16_units_on_non_ascii_lines() {
        let ascii = Columns::new("G00 X1\nG01 Y2\n");
        assert_eq!(ascii.utf16(2, 5), 5);
        // "Ø" is two bytes and one UTF-16 unit; "𝕏" four bytes and two units.
        let text = "(Ø6)\n(𝕏) G07\n";
        let columns = Columns::new(text);
        assert_eq!(columns.utf16(1, 1), 1);
        assert_eq!(columns.utf16(1, 4), 3);
        assert_eq!(columns.utf16(2, 8), 6);
        assert_eq!(columns.utf16(9, 3), 3);
    }
}
