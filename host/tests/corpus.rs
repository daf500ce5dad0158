//! The real-world corpus (`../shared/corpus` beside the repository, described
//! by its `INDEX.tsv`): every G-code file of a 3-axis mill is run through
//! `ger run --lenient`, and must either translate or be refused with
//! diagnostics, never panic and never take more than a minute of CPU time
//! (a guard against hangs, not a speed target: the tests' debug build is
//! about ten times slower than release, where the largest file takes 1 s;
//! a wall-clock limit would measure the machine's load). The results, by
//! file and by source, are kept in `tests/corpus/RESULTS.md`; this test fails
//! when they change (`UPDATE_EXPECT=1 cargo test --test corpus` rewrites the
//! table, to review with `git diff`) and when fewer than 95% of the mill files
//! without macro programming translate.

mod support;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use support::corpus::{self, Class};

/// `la_peinture.gc` (180,585 lines) takes 1.0 s of CPU in release, 8-12 s
/// in the debug build on a loaded 2-core machine.
const CPU_LIMIT: Duration = Duration::from_secs(60);
/// Only for a run that hangs without using the CPU.
const WALL_LIMIT: Duration = Duration::from_secs(120);

enum Verdict {
    Translated,
    Refused(String),
    Broken(String),
}

/// Runs `ger run --lenient` on one file, in the file's own units.
fn translate(file: &Path, units: &str, config: &Path) -> Verdict {
    let run = corpus::translate(file, units, config, WALL_LIMIT);
    if run.timed_out {
        return Verdict::Broken(format!("ran for more than {} s", WALL_LIMIT.as_secs()));
    }
    if run.cpu > CPU_LIMIT {
        return Verdict::Broken(format!("took {:.1} s of CPU time", run.cpu.as_secs_f64()));
    }
    match run.code {
        Some(0) => Verdict::Translated,
        Some(1) => Verdict::Refused(corpus::first_error(&run.stderr)),
        other => Verdict::Broken(format!("exit status {other:?}: {}", run.stderr.lines().last().unwrap_or(""))),
    }
}

#[test]
fn the_corpus_translates_or_is_refused_cleanly() {
    let repository = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let corpus = corpus::dir();
    if !corpus.join("INDEX.tsv").exists() {
        let message = format!("the corpus is not at {}: the corpus test did NOT run", corpus.display());
        support::peer_missing(&message);
        return;
    }
    let scratch = tempfile::tempdir().unwrap();
    let config = corpus::ger_config(scratch.path());

    let mut rows = Vec::new();
    let mut broken = Vec::new();
    let (mut mills, mut mills_translated) = (0, 0);
    let mut by_source: BTreeMap<String, [usize; 3]> = BTreeMap::new();
    for entry in corpus::entries(&corpus) {
        let class = entry.class();
        let file: PathBuf = corpus.join(&entry.path);
        let (result, note) = match &class {
            Class::Other(why) => ("skipped".to_string(), format!("not a 3-axis mill program: {why}")),
            _ => match translate(&file, entry.units(), &config) {
                Verdict::Translated => ("translated".to_string(), String::new()),
                Verdict::Refused(why) => ("refused".to_string(), why),
                Verdict::Broken(why) => {
                    broken.push(format!("{}: {why}", entry.path));
                    ("BROKEN".to_string(), why)
                }
            },
        };
        let kind = class.label();
        if class == Class::Mill {
            mills += 1;
            mills_translated += usize::from(result == "translated");
        }
        let counts = by_source.entry(entry.source.clone()).or_default();
        counts[0] += 1;
        counts[1] += usize::from(result == "translated");
        counts[2] += usize::from(result == "refused");
        rows.push(format!("| `{}` | {} | {kind} | {result} | {note} |", entry.path, entry.source));
    }

    let percent = 100.0 * mills_translated as f64 / mills.max(1) as f64;
    let mut table = String::new();
    let _ = writeln!(table, "# ger on the real-world corpus\n");
    let _ = writeln!(
        table,
        "Written by `host/tests/corpus.rs` (`UPDATE_EXPECT=1 cargo test --test corpus`): every G-code file of \
         `../shared/corpus/INDEX.tsv`, run through `ger run --lenient` in its own units, with a tool table of \
         20 tools.\n"
    );
    let _ = writeln!(
        table,
        "**3-axis mill programs without macro programming: {mills_translated} of {mills} translate ({percent:.1}%).** \
         The others are refused with diagnostics, or are not mill programs. A program that uses `#` parameters, \
         `[ ]` expressions or O-word control flow outside its comments counts as macro programming, whatever the \
         index says. The figure counts programs LinuxCNC refuses too: `RS274.md` says which.\n"
    );
    let _ = writeln!(table, "## By source\n\n| source | files | translated | refused |\n| --- | --- | --- | --- |");
    for (source, [files, translated, refused]) in &by_source {
        let _ = writeln!(table, "| {source} | {files} | {translated} | {refused} |");
    }
    let _ = writeln!(
        table,
        "\n## By file\n\n| file | source | kind | result | first diagnostic |\n| --- | --- | --- | --- | --- |"
    );
    for row in &rows {
        let _ = writeln!(table, "{row}");
    }

    let results = repository.join("tests/corpus/RESULTS.md");
    if std::env::var_os("UPDATE_EXPECT").is_some() {
        std::fs::create_dir_all(results.parent().unwrap()).unwrap();
        std::fs::write(&results, &table).unwrap();
    }
    assert!(broken.is_empty(), "ger broke on corpus files:\n{}", broken.join("\n"));
    assert!(percent >= 95.0, "only {percent:.1}% of the mill files translate ({mills_translated} of {mills})");
    let committed = std::fs::read_to_string(&results).unwrap_or_default();
    assert!(
        committed == table,
        "the corpus results changed: review them with `UPDATE_EXPECT=1 cargo test --test corpus` and `git diff {}`",
        results.display()
    );
}
