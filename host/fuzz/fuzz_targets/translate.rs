//! The whole translation, strict (on an inch machine) and lenient (on a
//! millimetre one), with every statement written as `ger run` writes it and
//! as each `--target` controller's writer does: no panic, and every line
//! plain G-code (no `inf`, `NaN` or exponent) outside its comments.
#![no_main]

#[path = "../../tests/support/plain.rs"]
mod plain;

use ger_controller::Writer;
use ger_core::config::{Config, DialectConfig, RunLimits, TargetConfig, TargetName};
use ger_core::emit::Emitter;
use ger_core::passes::{parse, translate, Event, Library, Options, LAST_STAGE};
use ger_core::statement::{Dialect, Units};
use ger_core::wizard::NoWizards;
use libfuzzer_sys::fuzz_target;

/// Events looked at per translation. A short program can mean an endless
/// output (`M98 P1 L99999999`), which ger streams in flat memory; past this
/// many lines the rest is more of the same.
const EVENTS: usize = 100_000;
/// Loops, calls and repeats run this much at most: the limits' own rules
/// are unit tests, and nested loops or repeats that make no output would
/// otherwise run a hundred million blocks (see the parse target).
const LIMITS: RunLimits = RunLimits { iterations: 1_000, blocks: 1_000 };

fuzz_target!(|program: &[u8]| {
    for (dialect, units) in [(Dialect::Strict, Units::Inch), (Dialect::Lenient, Units::Mm)] {
        let limited = DialectConfig { limits: LIMITS, ..DialectConfig::from(dialect) };
        let config = Config { dialect: limited, units, ..Config::default() };
        let library = Library::scanning(|| Library::scan(program, &config.dialect))
            .with_restart(|| Box::new(parse(program, &config.dialect)));
        let emitter = Emitter::new(config.units.decimals(), true);
        let mut writers: Vec<_> = TargetName::ALL
            .into_iter()
            .map(|name| {
                let config = Config { target: TargetConfig { name, ..TargetConfig::default() }, ..config.clone() };
                (name, Writer::new(&config, true))
            })
            .collect();
        let (mut lines, mut notes) = (String::new(), Vec::new());
        let options = Options { config: &config, stage: LAST_STAGE, wizards: &mut NoWizards };
        for event in translate(program, library, options).take(EVENTS) {
            match event {
                Event::Statement(statement) => {
                    let line = emitter.line(&statement);
                    if let Some(word) = plain::odd_word(&line) {
                        panic!("{dialect:?}: the output line {line:?} has the word {word:?}");
                    }
                    for (name, writer) in &mut writers {
                        lines.clear();
                        writer.write(&statement, &mut lines, &mut notes);
                        notes.clear();
                        for line in lines.lines() {
                            let code = line.split('(').next().unwrap_or("").trim_end();
                            if let Some(word) = plain::odd_word(code).filter(|_| !code.is_empty()) {
                                panic!("{dialect:?} for {name:?}: the line {line:?} has the word {word:?}");
                            }
                        }
                    }
                }
                Event::Diagnostic(diagnostic) => drop(diagnostic.to_string()),
            }
        }
    }
});
