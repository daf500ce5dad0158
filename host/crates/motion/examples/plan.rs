//! Plans a program's run time, as `ger check` does, without the simulation:
//! what `host/bench/plan.sh` times, and a quick way to compare with GRBL.
//!
//!     cargo run --release -p ger-motion --example plan -- [--translate-only] PROGRAM [CONFIG]
//!
//! Prints the planned seconds, then (tab-separated) when the first move
//! started and the last ended; `--translate-only` translates the same way
//! and plans nothing, for the bench to tell the planner's cost. A program of
//! subprograms kept in other files or of wizard calls needs `ger check`.

use std::io::BufReader;

use ger_core::config::Config;
use ger_core::passes::{translate, Event, Library, Options, LAST_STAGE};
use ger_core::wizard::NoWizards;
use ger_motion::Run;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let translate_only = args.first().is_some_and(|a| a == "--translate-only");
    if translate_only {
        args.remove(0);
    }
    let Some(program) = args.first() else {
        eprintln!("usage: plan [--translate-only] PROGRAM [CONFIG]");
        std::process::exit(2);
    };
    let config = match args.get(1) {
        Some(path) => {
            let text = std::fs::read_to_string(path).unwrap_or_else(|err| fail(&format!("{path}: {err}")));
            Config::from_toml(&text).unwrap_or_else(|d| fail(&format!("{path}: {d}")))
        }
        None => Config::default(),
    };
    let file = std::fs::File::open(program).unwrap_or_else(|err| fail(&format!("{program}: {err}")));
    let profile = config.motion_profile();
    let mut run = Run::new(&profile.machine, config.units);
    let mut clock = |_: &(), _: f64, _: f64| {};
    let options = Options { config: &config, stage: LAST_STAGE, wizards: &mut NoWizards };
    let mut errors = 0;
    for event in translate(BufReader::new(file), Library::empty(), options) {
        match event {
            Event::Statement(statement) if !translate_only => run.statement(&statement, (), &mut clock),
            Event::Statement(_) => {}
            Event::Diagnostic(d) if d.is_error() => errors += 1,
            Event::Diagnostic(_) => {}
        }
    }
    let totals = run.finish(&mut clock);
    let (start, end) = totals.moving.unwrap_or((0.0, 0.0));
    println!("{:.6}\t{start:.6}\t{end:.6}", totals.seconds);
    if errors > 0 {
        eprintln!("{program}: {errors} errors in the translation (their statements were dropped)");
    }
}

fn fail(message: &str) -> ! {
    eprintln!("plan: {message}");
    std::process::exit(1)
}
