//! Wizard runtime costs, timed with the clock (`cargo bench --bench wizards`):
//! cold load (compile) and warm load (disk cache) of Pocket, per-call
//! overhead of a trivial wizard and of Pocket (CPU time, best of three), and
//! a 10,000-call program.
//! Pocket and Nest are built from source first if need be.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use ger_core::config::Config;
use ger_core::passes::{translate, Event, Library, Options, LAST_STAGE};
use ger_core::statement::WizardArg;
use ger_core::wizard::{Call, Wizards};
use ger_wasm::{Limits, WasmWizards};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
}

fn runtime(dir: &Path, config: &Config) -> WasmWizards {
    WasmWizards::new(dir, config, Limits::default(), Some(Box::new(|m: &str| eprintln!("   {m}"))))
}

/// One call of `name` with `args`, at the state of an empty program.
fn call(wizards: &mut WasmWizards, config: &Config, name: &str, args: &[f64]) {
    let args: Vec<WizardArg> = args.iter().map(|&a| WizardArg::Number(a)).collect();
    let probe = ger_core::state::probe(config.units);
    let mut state = probe.borrow().call_state(config, 1);
    state.feed = Some(100.0);
    let call = Call { name, args: &args, span: Default::default() };
    wizards.expand(&call, &state).expect("the wizard runs");
}

/// The CPU time this thread has used: other work on a busy machine does not count.
fn thread_cpu_time() -> Duration {
    let mut time = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes the timespec it is given, nothing else.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut time) };
    assert_eq!(status, 0, "CLOCK_THREAD_CPUTIME_ID is there on Linux");
    Duration::new(time.tv_sec as u64, time.tv_nsec as u32)
}

/// The CPU time of one call, the best of three rounds of `n` calls.
fn per_call(wizards: &mut WasmWizards, config: &Config, name: &str, args: &[f64], n: u32) -> Duration {
    call(wizards, config, name, args);
    let mut best = Duration::MAX;
    for _ in 0..3 {
        let start = thread_cpu_time();
        for _ in 0..n {
            call(wizards, config, name, args);
        }
        best = best.min((thread_cpu_time() - start) / n);
    }
    best
}

fn main() {
    // The machine of tests/wizards/pocket: Pocket 10 8 2 is then 18 statements.
    let config = Config::from_toml("units = \"mm\"\n[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 4.0\n")
        .expect("a valid config");
    // Build (if stale) and copy Pocket into a fresh directory: its cache starts empty.
    runtime(&repo("wizards"), &config).describe("Pocket").expect("Pocket builds");
    runtime(&repo("tests/wizards/guests"), &config).describe("Nest").expect("Nest builds");
    let temp = tempfile::tempdir().unwrap();
    for (from, to) in [("wizards/pocket.wasm", "pocket.wasm"), ("tests/wizards/guests/nest.wasm", "nest.wasm")] {
        std::fs::copy(repo(from), temp.path().join(to)).unwrap();
    }
    let args = [10.0, 8.0, 2.0];

    let start = Instant::now();
    call(&mut runtime(temp.path(), &config), &config, "Pocket", &args);
    println!("cold load + first call of Pocket (compile, cache store): {:>10.2?}", start.elapsed());

    let mut warm = Duration::MAX;
    for _ in 0..10 {
        let start = Instant::now();
        call(&mut runtime(temp.path(), &config), &config, "Pocket", &args);
        warm = warm.min(start.elapsed());
    }
    println!("warm load + first call of Pocket (disk cache), best of 10: {:>10.2?}", warm);

    let mut wizards = runtime(temp.path(), &config);
    let nest = per_call(&mut wizards, &config, "Nest", &[0.0], 2_000);
    println!("per call, trivial wizard (Nest 0: one statement):          {nest:>10.2?}");
    let pocket = per_call(&mut wizards, &config, "Pocket", &args, 2_000);
    println!("per call, Pocket 10 8 2 (18 statements):                  {pocket:>10.2?}");

    let program: String = (0..10_000).map(|_| "Pocket 10 8 2\n").collect();
    let program = format!("G21\nF100\n{program}M30\n");
    let start = Instant::now();
    let mut wizards = runtime(temp.path(), &config);
    let options = Options { config: &config, stage: LAST_STAGE, wizards: &mut wizards };
    let mut statements = 0;
    for event in translate(program.as_bytes(), Library::empty(), options) {
        match event {
            Event::Statement(_) => statements += 1,
            Event::Diagnostic(d) => panic!("{d}"),
        }
    }
    println!("program of 10,000 Pocket calls ({statements} statements out):  {:>10.2?}", start.elapsed());
}
