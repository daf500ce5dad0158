//! ger's planned run time against GRBL's own: each program is translated
//! with `--target grbl` and timed by GRBL 1.1h's planner and stepper code
//! (`../shared/peers/grbl/gtime.py`, on the peer's default profile, which is
//! ger's `grbl-default`), and `ger check --format json` plans the same
//! program; the two must agree within 2% for every program. The figures are
//! kept in `tests/corpus/PLAN.md`; this test fails when they change
//! (`UPDATE_EXPECT=1 cargo test --test plan` rewrites the file, to review
//! with `git diff`).
//!
//! gtime simulates every step interrupt, five to ten seconds of machine
//! time per second of CPU, so the programs are those it times in reason:
//! every program of `tests/check/` that translates, the corpus's mill
//! programs (with and without macro programming) of at most `MOST_LINES`
//! lines whose planned time is at most `MOST_SECONDS`, and 2000 lines of
//! CAMotics' tiger relief, short moves over the relief (all of it takes GRBL
//! five hours, an hour of gtime: its figure is in the README). gtime runs on
//! both cores at once.
//!
//! The programs past those limits are timed by hand, with the limits
//! raised by `GER_PLAN_MOST_LINES` and `GER_PLAN_MOST_SECONDS`
//! (`host/bench/plan-long.sh`): such a run takes only the corpus programs
//! the default run leaves out, and its table is `tests/corpus/PLAN-LONG.md`.
//! The longest take hours of gtime, more than one sitting has, so a run can
//! also take only those of more than `GER_PLAN_LEAST_SECONDS`, a band whose
//! table is `tests/corpus/PLAN-LONG-<least>s.md`.
//!
//! GRBL's clock runs from the first step to the last: ger's figure here is
//! the same span (`planned.moving`), without a dwell before the first move
//! or after the last. An `M00` pause waits for the operator, which gtime
//! refuses to time: in the program GRBL runs it is `G4 P0`, a stop of no
//! time, as ger plans a pause.

mod support;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Duration;

use sha2::{Digest, Sha256};

use support::corpus::{self, Class};

/// A corpus program longer than this is not planned here (its check alone is slow in a debug build).
const MOST_LINES: usize = 5000;
/// Nor one that takes longer than this on the machine.
const MOST_SECONDS: f64 = 60.0;
/// The tiger relief's short moves over the relief: its lines after this many...
const TIGER_FROM: usize = 46_100;
/// ...this many of them...
const TIGER_LINES: usize = 2000;
/// ...after a move to where line 46,100 leaves the tool.
const TIGER_START: &str = "G17 G21 G90 G94 M3\nG0 Z5\nG0 X14.833 Y32.167\nG1 Z-20.984 F300\n";
/// Which programs a run takes: the default's, or (limits raised by hand)
/// the corpus programs past the default's limits and within the raised ones.
#[derive(Clone, Copy)]
struct Scope {
    most_lines: usize,
    most_seconds: f64,
    /// A long run's band starts past this (none: at the default's limits).
    least_seconds: Option<f64>,
    long: bool,
}

impl Scope {
    fn from_env() -> Scope {
        let read =
            |name: &str| std::env::var(name).ok().map(|v| v.parse::<f64>().unwrap_or_else(|_| panic!("{name}={v}")));
        let (lines, seconds) = (read("GER_PLAN_MOST_LINES"), read("GER_PLAN_MOST_SECONDS"));
        let least = read("GER_PLAN_LEAST_SECONDS");
        Scope {
            most_lines: lines.map_or(MOST_LINES, |l| l as usize),
            most_seconds: seconds.unwrap_or(MOST_SECONDS),
            least_seconds: least,
            long: lines.is_some() || seconds.is_some() || least.is_some(),
        }
    }

    /// Whether a corpus program of `lines` lines, planned to take `seconds`, is in.
    fn takes(&self, lines: usize, seconds: f64) -> bool {
        let past_least = self.least_seconds.is_none_or(|least| seconds > least);
        let within = lines <= self.most_lines && seconds <= self.most_seconds && past_least;
        let by_default = lines <= MOST_LINES && seconds <= MOST_SECONDS;
        within && (by_default != self.long)
    }

    fn table_file(&self) -> String {
        match (self.long, self.least_seconds) {
            (false, _) => "tests/corpus/PLAN.md".into(),
            (true, None) => "tests/corpus/PLAN-LONG.md".into(),
            (true, Some(least)) => format!("tests/corpus/PLAN-LONG-{least}s.md"),
        }
    }
}

/// The largest difference allowed, as a fraction of GRBL's time.
const TOLERANCE: f64 = 0.02;
/// Only for a run that hangs.
const WALL_LIMIT: Duration = Duration::from_secs(1800);

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn gtime() -> PathBuf {
    repository().join("../shared/peers/grbl/gtime.py")
}

/// A program to time, and how ger reads it.
struct Job {
    /// As the table names it.
    name: String,
    file: PathBuf,
    /// `--lenient --units U`, for the corpus's programs.
    units: Option<&'static str>,
    config: PathBuf,
    lines: usize,
}

/// What ger says of a program: its planned span of moves, and the time at programmed feeds.
struct Planned {
    moving: f64,
    programmed: f64,
}

fn ger(job: &Job, args: &[&str]) -> support::process::Finished {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ger"));
    command.args(args);
    if let Some(units) = job.units {
        command.args(["--lenient", "--units", units]);
    }
    command.arg("--config").arg(&job.config).arg(&job.file).env("NO_COLOR", "1");
    support::process::run(&mut command, WALL_LIMIT)
}

/// `ger check --format json`'s planned time, if the program moves.
fn plan(job: &Job) -> Result<Option<Planned>, String> {
    let run = ger(job, &["check", "--quiet", "--format", "json"]);
    if run.timed_out {
        return Err("ger check ran too long".into());
    }
    let report: serde_json::Value = serde_json::from_str(&run.stdout)
        .map_err(|e| format!("ger check printed no report ({e}): {}", corpus::first_error(&run.stderr)))?;
    let summary = &report["summary"];
    let [start, end] = [0, 1].map(|i| summary["planned"]["moving"][i].as_f64());
    let (Some(start), Some(end)) = (start, end) else { return Ok(None) };
    Ok(Some(Planned {
        moving: end - start,
        programmed: summary["run_time_seconds"].as_f64().ok_or("ger check gave no run time")?,
    }))
}

/// The program as GRBL runs it: ger's output for it, pauses made stops;
/// or ger's first error, if it refuses the program.
fn for_grbl(job: &Job) -> Result<String, String> {
    let run = ger(job, &["run", "--target", "grbl"]);
    if run.code != Some(0) {
        return Err(corpus::first_error(&run.stderr));
    }
    let lines: Vec<&str> = run.stdout.lines().map(|line| if is_pause(line) { "G4 P0" } else { line }).collect();
    Ok(lines.join("\n") + "\n")
}

/// An `M00` line of ger's output (`N120 M00 (MSG, load tool 2)`).
fn is_pause(line: &str) -> bool {
    let code = line.trim_start_matches(|c: char| c == 'N' || c.is_ascii_digit() || c == ' ');
    code == "M00" || code.starts_with("M00 ")
}

/// GRBL's time for `program` (written in `scratch` as `name`), seconds,
/// from the cache of gtime's answers if it timed the same program before.
/// `expected` (ger's planned time, s) makes room for a long program: gtime
/// runs at least five times faster than the machine.
fn grbl_time(scratch: &Path, name: &str, program: &str, expected: f64) -> Result<f64, String> {
    let cached = cache_entry(program);
    if let Some(seconds) = std::fs::read_to_string(&cached).ok().and_then(|s| s.trim().parse().ok()) {
        return Ok(seconds);
    }
    let file = scratch.join(name.replace(['/', ' '], "_") + ".nc");
    std::fs::write(&file, program).unwrap();
    let limit = WALL_LIMIT.max(Duration::from_secs_f64(expected));
    let mut command = Command::new("python3");
    command.arg(gtime()).arg(&file).arg("--timeout").arg(limit.as_secs().to_string());
    let run = support::process::run(&mut command, limit + Duration::from_secs(60));
    let _ = std::fs::remove_file(&file);
    if run.timed_out {
        return Err("gtime ran too long".into());
    }
    let seconds: f64 = match run.code {
        Some(0) => run.stdout.trim().parse().map_err(|_| format!("gtime printed {:?}", run.stdout))?,
        _ => return Err(format!("gtime failed: {}", run.stderr.lines().take(3).collect::<Vec<_>>().join(" / "))),
    };
    // Written whole, then renamed: the other worker may read it at any time.
    let partial = cached.with_extension("partial");
    std::fs::create_dir_all(cached.parent().unwrap()).unwrap();
    std::fs::write(&partial, format!("{seconds}\n")).unwrap();
    std::fs::rename(&partial, &cached).unwrap();
    Ok(seconds)
}

/// Where gtime's answer for `program` is kept, in the build's own scratch
/// folder: its name is a digest of all that the answer depends on (the
/// program, gtime, its simulator and its profile). The lockstep simulator
/// repeats to the clock tick, so the answer is as good as a new run's, and a
/// long run that stops half-way (the longest programs take hours) resumes
/// where it stopped.
fn cache_entry(program: &str) -> PathBuf {
    let peer = gtime().parent().unwrap().to_path_buf();
    let mut digest = Sha256::new();
    for part in [gtime(), peer.join("bin/grbl-sim"), peer.join("profiles/default.txt")] {
        let bytes = std::fs::read(&part).unwrap_or_else(|e| panic!("{}: {e}", part.display()));
        digest.update((bytes.len() as u64).to_le_bytes());
        digest.update(bytes);
    }
    digest.update(program.as_bytes());
    let name: String = digest.finalize().iter().map(|b| format!("{b:02x}")).collect();
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("gtime").join(name)
}

struct Row {
    name: String,
    lines: usize,
    grbl: f64,
    ger: f64,
    programmed: f64,
}

impl Row {
    fn error(&self) -> f64 {
        relative(self.ger, self.grbl)
    }
}

fn relative(ours: f64, theirs: f64) -> f64 {
    if theirs == 0.0 {
        if ours == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        (ours - theirs) / theirs
    }
}

/// Runs `work` on each of `items`, on both cores, in their order.
fn on_two_cores<'a, T: Sync>(items: &'a [T], work: impl Fn(&'a T) + Sync) {
    let next = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                while let Some(item) = items.get(next.fetch_add(1, Ordering::Relaxed)) {
                    work(item);
                }
            });
        }
    });
}

/// A file's lines, as an editor counts them (a last line without its newline too).
fn line_count(file: &Path) -> usize {
    let text = std::fs::read(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    text.split(|c| *c == b'\n').count() - usize::from(text.last().is_none_or(|c| *c == b'\n'))
}

/// The programs: `tests/check/`, the corpus's short ones, part of the tiger.
fn jobs(scratch: &Path, scope: Scope) -> Vec<Job> {
    let mut jobs = Vec::new();
    let corpus = corpus::dir();
    let config = corpus::ger_config(scratch);
    for entry in corpus::entries(&corpus) {
        if !matches!(entry.class(), Class::Mill | Class::Macro) {
            continue;
        }
        let file = corpus.join(&entry.path);
        let lines = line_count(&file);
        jobs.push(Job { name: entry.path.clone(), file, units: Some(entry.units()), config: config.clone(), lines });
    }
    if scope.long {
        return jobs;
    }
    let cases = repository().join("tests/check");
    let mut names: Vec<PathBuf> = std::fs::read_dir(&cases)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "ngc"))
        .collect();
    names.sort();
    for file in names {
        let config = file.with_extension("toml");
        let name = format!("tests/check/{}", file.file_name().unwrap().to_string_lossy());
        let lines = line_count(&file);
        jobs.push(Job { name, file, units: None, config, lines });
    }
    let tiger = std::fs::read_to_string(corpus.join("camotics-examples/tiger/tiger.nc")).unwrap();
    let passes: String = tiger.lines().skip(TIGER_FROM).take(TIGER_LINES).map(|l| format!("{l}\n")).collect();
    let file = scratch.join("tiger-passes.nc");
    std::fs::write(&file, format!("{TIGER_START}{passes}")).unwrap();
    let name = format!("camotics-examples/tiger/tiger.nc, lines {} to {}", TIGER_FROM + 1, TIGER_FROM + TIGER_LINES);
    let lines = line_count(&file);
    jobs.push(Job { name, file, units: Some("mm"), config, lines });
    jobs
}

#[test]
fn the_planned_time_is_grbls_within_two_percent() {
    let corpus = corpus::dir();
    if !corpus.join("INDEX.tsv").exists() {
        support::peer_missing(&format!("the corpus is not at {}: the plan test did NOT run", corpus.display()));
        return;
    }
    if !gtime().is_file() {
        support::peer_missing(&format!("GRBL's gtime.py is not at {}: the plan test did NOT run", gtime().display()));
        return;
    }
    if !Command::new("python3").arg("--version").output().is_ok_and(|o| o.status.success()) {
        support::peer_missing("python3, which runs GRBL's gtime.py, is missing: the plan test did NOT run");
        return;
    }
    let scratch = tempfile::tempdir().unwrap();
    let range = Scope::from_env();
    let jobs = jobs(scratch.path(), range);

    let untimed = Mutex::new(Vec::new());
    // Corpus programs past the default run's limits, which PLAN-LONG.md times.
    let past = Mutex::new(0);
    let failures = Mutex::new(Vec::new());
    let fail = |job: &Job, why: String| failures.lock().unwrap().push(format!("{}: {why}", job.name));

    // First ger plans them all, then gtime times the shortest first: a long
    // run stopped half-way has timed the programs up to some length, which a
    // run with that limit finds kept.
    let planned = Mutex::new(Vec::new());
    on_two_cores(&jobs, |job| {
        let not_timed = |why: String| untimed.lock().unwrap().push(NotTimed { name: job.name.clone(), why });
        // The corpus's files, not the tiger's excerpt (in the default run).
        let in_corpus = job.units.is_some() && job.file.starts_with(corpus::dir());
        if in_corpus && job.lines > range.most_lines {
            if range.long {
                not_timed(format!("past this run's limits: {} lines", job.lines));
            } else {
                *past.lock().unwrap() += 1;
            }
            return;
        }
        // A corpus program is in one of the two tables, whose line limits it is within.
        let in_table = !in_corpus || range.takes(job.lines, 0.0);
        let program = match for_grbl(job) {
            Ok(program) => program,
            Err(error) => {
                if in_table {
                    not_timed(format!("ger refuses it: {error}"));
                }
                return;
            }
        };
        match plan(job) {
            Ok(Some(plan)) if in_corpus && !range.takes(job.lines, plan.moving) => {
                if !range.long {
                    *past.lock().unwrap() += 1;
                } else if plan.moving > range.most_seconds {
                    not_timed(format!("past this run's limits: planned {:.0} s", plan.moving));
                }
            }
            Ok(Some(plan)) => planned.lock().unwrap().push((job, program, plan)),
            Ok(None) if in_table => not_timed("it never moves".into()),
            Ok(None) => {}
            Err(why) => fail(job, why),
        }
    });
    let mut planned = planned.into_inner().unwrap();
    planned.sort_by(|(_, _, a), (_, _, b)| a.moving.total_cmp(&b.moving));

    let rows = Mutex::new(Vec::new());
    let gtime_wall = Mutex::new(Duration::ZERO);
    on_two_cores(&planned, |(job, program, plan)| {
        let started = std::time::Instant::now();
        match grbl_time(scratch.path(), &job.name, program, plan.moving) {
            Ok(grbl) => {
                if range.long {
                    eprintln!("{}: GRBL {grbl:.3} s, ger {:.3} s", job.name, plan.moving);
                }
                rows.lock().unwrap().push(Row {
                    name: job.name.clone(),
                    lines: job.lines,
                    grbl,
                    ger: plan.moving,
                    programmed: plan.programmed,
                })
            }
            Err(why) => fail(job, why),
        }
        *gtime_wall.lock().unwrap() += started.elapsed();
    });
    let mut rows = rows.into_inner().unwrap();
    rows.sort_by(|a, b| a.name.cmp(&b.name));
    let mut untimed = untimed.into_inner().unwrap();
    untimed.sort_by(|a, b| a.name.cmp(&b.name));
    let failures = failures.into_inner().unwrap();
    eprintln!(
        "gtime timed {} programs in {:.0} s of its wall time (its earlier answers kept in {}); {} not timed",
        rows.len(),
        gtime_wall.into_inner().unwrap().as_secs_f64(),
        cache_entry("").parent().unwrap().display(),
        untimed.len()
    );

    let table = table(&rows, &untimed, past.into_inner().unwrap(), range);
    let path = repository().join(range.table_file());
    if std::env::var_os("UPDATE_EXPECT").is_some() {
        std::fs::write(&path, &table).unwrap();
    }
    assert!(failures.is_empty(), "{} programs could not be timed:\n{}", failures.len(), failures.join("\n"));
    assert!(range.long || rows.len() > 90, "only {} programs timed", rows.len());
    let off: Vec<String> = rows
        .iter()
        .filter(|r| r.error().abs() > TOLERANCE)
        .map(|r| format!("{}: ger {:.3} s, GRBL {:.3} s ({:+.2}%)", r.name, r.ger, r.grbl, 100.0 * r.error()))
        .collect();
    assert!(off.is_empty(), "ger's planned time is more than 2% off GRBL's for:\n{}", off.join("\n"));
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == table,
        "the planned times changed: review them with `UPDATE_EXPECT=1 cargo test --test plan` and `git diff {}`",
        path.display()
    );
}

/// A program the run would take but could not time, and why.
struct NotTimed {
    name: String,
    why: String,
}

/// `tests/corpus/PLAN.md`, or `PLAN-LONG.md`.
fn table(rows: &[Row], untimed: &[NotTimed], past: usize, scope: Scope) -> String {
    let mean =
        |f: &dyn Fn(&Row) -> f64| 100.0 * rows.iter().map(|r| f(r).abs()).sum::<f64>() / rows.len().max(1) as f64;
    let worst = |f: &dyn Fn(&Row) -> f64| 100.0 * rows.iter().map(|r| f(r).abs()).fold(0.0, f64::max);
    let planned = |r: &Row| r.error();
    let programmed = |r: &Row| relative(r.programmed, r.grbl);
    let mut out = String::new();
    let _ = writeln!(out, "# ger's planned run time against GRBL's\n");
    let (command, programs) = if scope.long {
        let Scope { most_lines, most_seconds, least_seconds, .. } = scope;
        let (least_variable, least_words) = match least_seconds {
            Some(least) => (format!("GER_PLAN_LEAST_SECONDS={least} "), format!("more than {least} s and ")),
            None => Default::default(),
        };
        (
            format!(
                "{least_variable}GER_PLAN_MOST_LINES={most_lines} GER_PLAN_MOST_SECONDS={most_seconds} \
                 host/bench/plan-long.sh"
            ),
            format!(
                "the corpus's mill programs that the test leaves out (over {MOST_LINES} lines or {MOST_SECONDS} s), \
                 of at most {most_lines} lines that take {least_words}at most {most_seconds} s"
            ),
        )
    } else {
        (
            "UPDATE_EXPECT=1 cargo test --test plan".to_string(),
            format!(
                "every one of `tests/check/`, the corpus's mill programs of at most {MOST_LINES} \
                 lines that take at most {MOST_SECONDS} s, and {TIGER_LINES} lines of the tiger relief's passes over \
                 the relief, after a move to where they start"
            ),
        )
    };
    let _ = writeln!(
        out,
        "Written by `host/tests/plan.rs` (`{command}`): each program translated with `ger run --target grbl` and \
         timed by GRBL 1.1h's own planner and stepper (`../shared/peers/grbl/gtime.py`, its default profile), beside \
         `ger check`'s planned time on the same profile (`grbl-default`, from the first move to the last, as GRBL's \
         clock runs) and its time at programmed feeds (no acceleration). The programs: {programs}.\n"
    );
    let _ = writeln!(
        out,
        "**{} programs: ger's planned time is GRBL's within {:.3}% on average (mean absolute difference), {:.3}% at \
         worst. At programmed feeds: {:.2}% on average, {:.1}% at worst.**\n",
        rows.len(),
        mean(&planned),
        worst(&planned),
        mean(&programmed),
        worst(&programmed)
    );
    let _ = writeln!(
        out,
        "| program | lines | GRBL (s) | ger planned (s) | difference | at programmed feeds (s) | difference |"
    );
    let _ = writeln!(out, "| --- | ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in rows {
        let _ = writeln!(
            out,
            "| `{}` | {} | {:.3} | {:.3} | {:+.3}% | {:.3} | {:+.2}% |",
            r.name.replace('|', "\\|"),
            r.lines,
            r.grbl,
            r.ger,
            100.0 * r.error(),
            r.programmed,
            100.0 * relative(r.programmed, r.grbl)
        );
    }
    let _ = writeln!(out, "\n## Not timed\n");
    if let Some(least) = scope.least_seconds {
        let _ = writeln!(
            out,
            "The programs of at most {least} s are in `PLAN-LONG.md`, those it refuses or that never move among them.\n"
        );
    }
    if !scope.long {
        let _ = writeln!(
            out,
            "{past} more of the corpus's mill programs are past these limits: `PLAN-LONG.md` times them, up to its \
             own.\n"
        );
    }
    if untimed.is_empty() {
        let _ = writeln!(out, "Every other program the run takes is timed.");
    } else {
        let _ = writeln!(out, "{} programs the run takes are not timed:\n", untimed.len());
        let _ = writeln!(out, "| program | why |\n| --- | --- |");
        for NotTimed { name, why } in untimed {
            let _ = writeln!(out, "| `{}` | {} |", name.replace('|', "\\|"), why.replace('|', "\\|"));
        }
    }
    out
}
