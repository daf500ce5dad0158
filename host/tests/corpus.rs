//! The real-world corpus (`../shared/corpus` beside the repository, described
//! by its `INDEX.tsv`): every G-code file of a 3-axis mill is run through
//! `ger run --lenient`, and must either translate or be refused with
//! diagnostics, never panic and never take more than 10 s. The results, by
//! file and by source, are kept in `tests/corpus/RESULTS.md`; this test fails
//! when they change (`UPDATE_EXPECT=1 cargo test --test corpus` rewrites the
//! table, to review with `git diff`) and when fewer than 90% of the mill files
//! without macro programming translate.

mod support;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const TIME_LIMIT: Duration = Duration::from_secs(10);

/// Files the index does not mark as other machines' but that are: with why.
const NOT_A_MILL: [(&str, &str); 4] = [
    ("gcode-rs/bondtech_estep.gcode", "3D printer (extruder calibration, M92 E)"),
    ("gcode-rs/makerblock_tinycnc.gcode", "pen plotter (M300 pen up/down)"),
    ("gcode-rs/plotter_owl.gcode", "pen plotter (M300 pen up/down)"),
    ("Hass-CNC-Programs/TEAMMACHINE-ENGRAVE.nc", "rotary engraving (A axis)"),
];

struct Entry {
    path: String,
    source: String,
    units: String,
    features: String,
}

#[derive(PartialEq)]
enum Class {
    /// A 3-axis mill program: counts towards the 90%.
    Mill,
    /// Uses `#` parameters, O-word control flow or macro B: run, not counted.
    Macro,
    /// LinuxCNC's reject suite: programs meant to be refused.
    Reject,
    /// Another machine's program: not run.
    Other(String),
}

fn class(entry: &Entry) -> Class {
    let has = |feature: &str| entry.features.contains(feature);
    if let Some((_, why)) = NOT_A_MILL.iter().find(|(path, _)| *path == entry.path) {
        return Class::Other(why.to_string());
    }
    if has("ABC-axes") {
        return Class::Other("rotary axes".into());
    }
    if has("printer-M-codes") {
        return Class::Other("3D printer".into());
    }
    if entry.source.contains("plasma") {
        return Class::Other("plasma/waterjet cutter".into());
    }
    if entry.path.contains("lathe") {
        return Class::Other("lathe".into());
    }
    if entry.source.contains("expected-error") {
        return Class::Reject;
    }
    if has("#vars") || has("IF/GOTO/WHILE") || has("O-word-subs/control") || has("G65/G66-macro-call") {
        return Class::Macro;
    }
    Class::Mill
}

enum Verdict {
    Translated,
    Refused(String),
    Broken(String),
}

/// Runs `ger run --lenient` on one file, in the file's own units.
fn translate(file: &Path, units: &str, config: &Path) -> Verdict {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["run", "--lenient", "--units", units, "--config"])
        .arg(config)
        .arg(file)
        .env("NO_COLOR", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > TIME_LIMIT {
            let _ = child.kill();
            return Verdict::Broken(format!("took more than {} s", TIME_LIMIT.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut stderr = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    match status.code() {
        Some(0) => Verdict::Translated,
        Some(1) => {
            let first = stderr.lines().find(|l| l.starts_with("error")).unwrap_or("error: (no message)");
            Verdict::Refused(first.trim_start_matches("error: ").replace('|', "\\|"))
        }
        other => Verdict::Broken(format!("exit status {other:?}: {}", stderr.lines().last().unwrap_or(""))),
    }
}

#[test]
fn the_corpus_translates_or_is_refused_cleanly() {
    let repository = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let corpus = repository.join("../shared/corpus");
    if !corpus.join("INDEX.tsv").exists() {
        let message = format!("the corpus is not at {}: the corpus test did NOT run", corpus.display());
        support::peer_missing(&message);
        return;
    }
    // A machine with a full tool table: the corpus's programs name tools 1-20.
    let scratch = tempfile::tempdir().unwrap();
    let config = scratch.path().join("ger.toml");
    let tools: String =
        (1..=20).map(|n| format!("[[tools]]\nnumber = {n}\nkind = \"endmill\"\ndiameter = 0.1\n\n")).collect();
    std::fs::write(&config, tools).unwrap();

    let index = std::fs::read_to_string(corpus.join("INDEX.tsv")).unwrap();
    let mut rows = Vec::new();
    let mut broken = Vec::new();
    let (mut mills, mut mills_translated) = (0, 0);
    let mut by_source: BTreeMap<String, [usize; 3]> = BTreeMap::new();
    for line in index.lines().skip(1) {
        let fields: Vec<&str> = line.split('\t').collect();
        if fields.len() < 8 || fields[7] != "gcode" {
            continue;
        }
        let entry = Entry {
            path: fields[0].into(),
            source: fields[3].into(),
            units: fields[4].into(),
            features: fields[6].into(),
        };
        let class = class(&entry);
        let file: PathBuf = corpus.join(&entry.path);
        let (result, note) = match &class {
            Class::Other(why) => ("skipped".to_string(), format!("not a 3-axis mill program: {why}")),
            _ => {
                let units = if entry.units == "G21" { "mm" } else { "in" };
                match translate(&file, units, &config) {
                    Verdict::Translated => ("translated".to_string(), String::new()),
                    Verdict::Refused(why) => ("refused".to_string(), why),
                    Verdict::Broken(why) => {
                        broken.push(format!("{}: {why}", entry.path));
                        ("BROKEN".to_string(), why)
                    }
                }
            }
        };
        let kind = match class {
            Class::Mill => "mill",
            Class::Macro => "mill, macro programming",
            Class::Reject => "LinuxCNC reject suite",
            Class::Other(_) => "other machine",
        };
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
         The others are refused with diagnostics, or are not mill programs.\n"
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
    assert!(percent >= 90.0, "only {percent:.1}% of the mill files translate ({mills_translated} of {mills})");
    let committed = std::fs::read_to_string(&results).unwrap_or_default();
    assert!(
        committed == table,
        "the corpus results changed: review them with `UPDATE_EXPECT=1 cargo test --test corpus` and `git diff {}`",
        results.display()
    );
}
