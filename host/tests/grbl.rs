//! GRBL takes every line of ger's `--target grbl` output: each program of
//! the shared corpus (`../shared/corpus`) that ger translates, translated
//! for GRBL, is run through GRBL 1.1h's own parser
//! (`../shared/peers/grbl/bin/gvalidate`, in check mode `$C`, which parses
//! and checks every line, arcs too, without moving or pausing at M00), and
//! no line may get an `error:` or `ALARM:` answer. Nor may the target refuse
//! a program ger translates for no target. The figures (programs
//! translated, passed, refused by ger) are printed, for the README.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use support::corpus::{self, Class};

/// Only for a run that hangs.
const WALL_LIMIT: Duration = Duration::from_secs(300);

/// GRBL's parser, beside the corpus.
fn gvalidate() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/peers/grbl/bin/gvalidate")
}

/// The program's first line GRBL refuses, with its answer, if any.
fn refused_line(scratch: &Path, output: &str) -> Option<String> {
    // In a scratch folder: gvalidate keeps GRBL's settings in EEPROM.DAT in the current folder.
    let program = scratch.join("program.nc");
    std::fs::write(&program, format!("$C\n{output}")).unwrap();
    let run = support::process::run(Command::new(gvalidate()).arg(&program).current_dir(scratch), WALL_LIMIT);
    assert!(!run.timed_out, "gvalidate ran for more than {} s", WALL_LIMIT.as_secs());
    // One answer a line: `ok` or `error:N`; `[MSG:...]` lines come beside them.
    let answers = run.stdout.lines().filter(|l| *l == "ok" || l.starts_with("error:") || l.starts_with("ALARM:"));
    // The first answer is `$C`'s.
    let lines = std::iter::once("$C").chain(output.lines());
    answers
        .zip(lines)
        .find(|(answer, _)| *answer != "ok")
        .map(|(answer, line)| format!("{answer} at `{line}`"))
        .or_else(|| {
            (run.code != Some(0))
                .then(|| format!("gvalidate exit status {:?}: {}", run.code, run.stdout.lines().last().unwrap_or("")))
        })
}

#[test]
fn grbl_takes_every_line_of_the_corpus_translated_for_it() {
    let corpus = corpus::dir();
    if !corpus.join("INDEX.tsv").exists() {
        support::peer_missing(&format!("the corpus is not at {}: the GRBL test did NOT run", corpus.display()));
        return;
    }
    if !gvalidate().is_file() {
        support::peer_missing(&format!(
            "GRBL's gvalidate is not at {}: the GRBL test did NOT run",
            gvalidate().display()
        ));
        return;
    }
    let scratch = tempfile::tempdir().unwrap();
    let config = corpus::ger_config(scratch.path());
    let (mut translated, mut passed, mut refused) = (0, 0, Vec::new());
    // ger's own output, for the figure beside it: what the target is for.
    let mut generic_refused = 0;
    // Programs ger refuses, for no target as for GRBL.
    let mut untranslated = 0;
    // Programs only the GRBL target refuses: none may be.
    let mut target_refuses = Vec::new();
    for entry in corpus::entries(&corpus) {
        if matches!(entry.class(), Class::Other(_)) {
            continue;
        }
        let file = corpus.join(&entry.path);
        let run = corpus::translate_for(&file, entry.units(), &config, "grbl", WALL_LIMIT);
        let generic = corpus::translate_for(&file, entry.units(), &config, "generic", WALL_LIMIT);
        assert!(!run.timed_out && !generic.timed_out, "{}: ger ran too long", entry.path);
        match (run.code == Some(0), generic.code == Some(0)) {
            (true, _) => {}
            (false, false) => {
                untranslated += 1;
                continue;
            }
            (false, true) => {
                target_refuses.push(format!("{}: {}", entry.path, corpus::first_error(&run.stderr)));
                continue;
            }
        }
        translated += 1;
        match refused_line(scratch.path(), &run.stdout) {
            None => passed += 1,
            Some(why) => refused.push(format!("{}: {why}", entry.path)),
        }
        if generic.code == Some(0) {
            generic_refused += usize::from(refused_line(scratch.path(), &generic.stdout).is_some());
        }
    }
    eprintln!(
        "GRBL takes every line of {passed} of the {translated} corpus programs ger translates with --target grbl \
         (and refuses a line of {generic_refused} of them translated for no target); ger refuses {untranslated} \
         more, for every target"
    );
    assert!(translated > 0, "no corpus program translated");
    assert!(
        target_refuses.is_empty(),
        "ger translates {} programs for no target but refuses them for GRBL:\n{}",
        target_refuses.len(),
        target_refuses.join("\n")
    );
    assert!(refused.is_empty(), "GRBL refuses a line of {} programs:\n{}", refused.len(), refused.join("\n"));
}

/// The test's own check: a line GRBL refuses is found, and named.
#[test]
fn a_refused_line_is_found() {
    if !gvalidate().is_file() {
        support::peer_missing("GRBL's gvalidate is missing: the GRBL test did NOT run");
        return;
    }
    let scratch = tempfile::tempdir().unwrap();
    assert_eq!(refused_line(scratch.path(), "G21\nG01 X1 F100\nM00\n"), None);
    let found = refused_line(scratch.path(), "G21\nM06 T1\nG01 X1 F100\n");
    assert_eq!(found.as_deref(), Some("error:20 at `M06 T1`"));
    // From (0,0) round (5.003,0) to (10,0): 0.006 mm off, over both limits (error:33).
    let found = refused_line(scratch.path(), "G21\nG01 X0 Y0 F100\nG02 X10 Y0 I5.003 J0\n");
    assert_eq!(found.as_deref(), Some("error:33 at `G02 X10 Y0 I5.003 J0`"));
}
