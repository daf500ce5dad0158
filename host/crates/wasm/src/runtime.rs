//! Runs wizard components with wasmtime, one sandboxed instance per call.
//!
//! A wizard is loaded the first time a program calls it: found by name in
//! the wizards directory (built first if its sources are newer, see
//! [`crate::build`]), compiled or taken from the disk cache, and linked once
//! into a template ([`bindings::WizardPre`]). Each call instantiates the
//! template in a new store, so no state leaks from one call to the next, and
//! runs it with:
//! - WASI with no capabilities: no preopened directories, no environment, no
//!   arguments, no network, no stdin, clocks frozen at zero; stdout and
//!   stderr go to bounded buffers that are shown if the call fails;
//! - an epoch deadline ([`Limits::time`]), ticked by one background thread;
//! - a memory limit over all of the instance's memories ([`Limits::memory`]);
//! - random numbers seeded from the call (the wizard, its arguments and the
//!   machine state), so the same call always gives the same statements.
//!
//! All the calls of one translation (nested calls too) share a budget of
//! time and statements ([`Limits::program_time`],
//! [`Limits::program_statements`]), started again by [`Wizards::start`].
//!
//! Whatever the guest does, the outcome is statements or a diagnostic at the
//! call naming the wizard: every error from wasmtime is turned into one here.

use std::cell::OnceCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use rand::{Rng, SeedableRng};
use sha2::{Digest, Sha256};
use wasmtime::component::{HasSelf, Linker, ResourceTable};
use wasmtime::{
    Config, Enabled, Engine, InstanceAllocationStrategy, PoolingAllocationConfig, ResourceLimiter, Store, Trap,
};
use wasmtime_wasi::p2::pipe::MemoryOutputPipe;
use wasmtime_wasi::{HostMonotonicClock, HostWallClock, WasiCtx, WasiCtxBuilder, WasiCtxView, WasiView};

use crate::build::{self, Progress};
use crate::cache::{self, WasmDigest};
use crate::catalog::{self, Catalog};
use crate::render::render;
use ger_core::config::{self, ToolKind};
use ger_core::diag::{clip, Diagnostic, Span};
use ger_core::state::{CallState, Spindle};
use ger_core::statement::{Distance, Plane, Units, WizardArg};
use ger_core::wizard::{shown_name, Call, Expansion, Wizards, NO_WIZARD_HELP, SHOWN_MESSAGE};

pub mod bindings {
    //! Rust types for `wit/wizard.wit`, host side.
    wasmtime::component::bindgen!({
        path: "../../../wit",
        world: "ger:wizard/wizard",
        // `log` stops a wizard that logs past its limit.
        imports: { "ger:wizard/host.log": trappable },
    });
}

mod first {
    //! The host side of `ger:wizard@0.1.0` (`wit/0.1.0`), for the wizards
    //! built against it: its `describe` and `expand` take the same types
    //! as today's, so only its `host` interface is linked apart.
    wasmtime::component::bindgen!({
        path: "../../../wit/0.1.0",
        world: "ger:wizard/wizard",
        imports: { "ger:wizard/host.log": trappable },
    });
}

use bindings::ger::wizard::{host, types as wit};
use bindings::{Wizard, WizardPre};

/// How often the epoch ticks: the granularity of the time limits.
const TICK: Duration = Duration::from_millis(10);

/// How much of a pooled slot's memory and tables is reset by copying the
/// initial image back instead of by madvise: a Rust wizard's stack and data
/// fit, so a call neither faults its pages in again nor pays the syscall.
const KEEP_RESIDENT: usize = 2 << 20;

/// `time` in ticks, rounded up.
fn ticks(time: Duration) -> u64 {
    time.as_millis().div_ceil(TICK.as_millis()) as u64
}

/// What one call, and all the calls of one program, may use.
#[derive(Clone, Debug)]
pub struct Limits {
    /// Wall time for one call, instantiation included.
    pub time: Duration,
    /// Bytes of linear memory, all of the instance's memories together.
    pub memory: usize,
    /// Bytes kept of each of stdout and stderr; writing more is an error.
    pub output: usize,
    /// Bytes one call may `log` (each line counting one more); more is an error.
    pub log: usize,
    /// Statements one call may return.
    pub statements: usize,
    /// Time for all the calls of one translation together: the time they
    /// ran, counted by the same clock as `time`.
    pub program_time: Duration,
    /// Statements all the calls of one translation may return together.
    pub program_statements: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            time: Duration::from_secs(1),
            memory: 64 << 20,
            output: 64 << 10,
            log: 64 << 10,
            statements: 1_000_000,
            program_time: Duration::from_secs(10),
            program_statements: 10_000_000,
        }
    }
}

/// Runs the wizards of one directory.
pub struct WasmWizards {
    dir: PathBuf,
    engine: Engine,
    linker: Linker<Guest>,
    limits: Limits,
    tools: Arc<Vec<config::Tool>>,
    machine_units: Units,
    /// `None`: never build; a missing or stale `.wasm` is an error.
    progress: Option<Progress>,
    catalog: Option<Catalog>,
    /// By lower-case name, so a program that calls a broken wizard 10,000
    /// times reports it 10,000 times without looking 10,000 times.
    loaded: HashMap<String, Result<Rc<Loaded>, Diagnostic>>,
    ticker: bool,
    /// Signs the compile cache; looked up on the first load.
    cache_key: OnceCell<Option<cache::Key>>,
    /// The epoch's ticks so far: the one clock of both time limits, so a
    /// call and a program are timed alike however loaded the machine is.
    ticks: Arc<AtomicU64>,
    /// What the calls of this translation have used so far (time in ticks).
    spent: u64,
    returned: usize,
}

struct Loaded {
    pre: WizardPre<Guest>,
    digest: WasmDigest,
    description: OnceCell<wit::Description>,
}

/// A store's data: everything one call can reach.
struct Guest {
    wasi: WasiCtx,
    table: ResourceTable,
    memory: MemoryLimiter,
    log: Vec<String>,
    /// Bytes logged so far, and the most there may be.
    logged: usize,
    log_limit: usize,
    log_overflowed: bool,
    tools: Arc<Vec<config::Tool>>,
    /// Machine units -> the program's units at the call.
    to_program: f64,
    machine_units: Units,
    /// The stock at the call, in its coordinates and units.
    stock: Option<wit::Bounds>,
    /// The warnings the call gave (the first [`SHOWN_WARNINGS`]), and how many in all.
    warnings: Vec<String>,
    warned: usize,
}

/// The most warnings one call shows; the rest are counted.
const SHOWN_WARNINGS: usize = 16;

impl WasiView for Guest {
    fn ctx(&mut self) -> WasiCtxView<'_> {
        WasiCtxView { ctx: &mut self.wasi, table: &mut self.table }
    }
}

impl wit::Host for Guest {}

impl host::Host for Guest {
    fn log(&mut self, message: String) -> wasmtime::Result<()> {
        // Bounded like stdout: a wizard logging in a loop must not eat the host's memory.
        let room = self.log_limit.saturating_sub(self.logged);
        self.logged = self.logged.saturating_add(message.len() + 1);
        if self.logged <= self.log_limit {
            self.log.push(message);
            return Ok(());
        }
        // What fits is kept, to show what the wizard was saying.
        let mut end = room.min(message.len());
        while !message.is_char_boundary(end) {
            end -= 1;
        }
        self.log.push(message[..end].to_string());
        self.log_overflowed = true;
        Err(wasmtime::Error::msg("the wizard logged past its limit"))
    }

    fn find_tool(&mut self, number: u32) -> Option<wit::Tool> {
        let tool = self.tools.iter().find(|t| t.number == number)?;
        Some(tool_to_wit(tool, self.to_program))
    }

    fn tools(&mut self) -> Vec<wit::Tool> {
        let mut tools: Vec<_> = self.tools.iter().map(|tool| tool_to_wit(tool, self.to_program)).collect();
        tools.sort_by_key(|tool| tool.number);
        tools
    }

    fn stock(&mut self) -> Option<wit::Bounds> {
        self.stock
    }

    fn machine_units(&mut self) -> wit::Units {
        units_to_wit(self.machine_units)
    }

    fn warn(&mut self, message: String) {
        self.warned += 1;
        if self.warnings.len() < SHOWN_WARNINGS {
            self.warnings.push(clip(&message, SHOWN_MESSAGE).into_owned());
        }
    }
}

impl first::ger::wizard::types::Host for Guest {}

impl first::ger::wizard::host::Host for Guest {
    fn log(&mut self, message: String) -> wasmtime::Result<()> {
        host::Host::log(self, message)
    }

    fn find_tool(&mut self, number: u32) -> Option<first::ger::wizard::types::Tool> {
        use first::ger::wizard::types::{Tool, ToolKind};
        let tool = host::Host::find_tool(self, number)?;
        Some(Tool {
            number: tool.number,
            kind: match tool.kind {
                wit::ToolKind::Endmill => ToolKind::Endmill,
                wit::ToolKind::Ballmill => ToolKind::Ballmill,
                wit::ToolKind::Drill => ToolKind::Drill,
                wit::ToolKind::CenterDrill => ToolKind::CenterDrill,
            },
            diameter: tool.diameter,
            flute_length: tool.flute_length,
            tip_angle: tool.tip_angle,
        })
    }
}

/// Sums the growth of all memories; remembers whether it said no.
struct MemoryLimiter {
    limit: usize,
    used: usize,
    refused: bool,
}

impl ResourceLimiter for MemoryLimiter {
    fn memory_growing(&mut self, current: usize, desired: usize, _: Option<usize>) -> wasmtime::Result<bool> {
        let used = self.used - current.min(self.used) + desired;
        if used > self.limit {
            self.refused = true;
            return Ok(false);
        }
        self.used = used;
        Ok(true)
    }

    fn table_growing(&mut self, _: usize, desired: usize, _: Option<usize>) -> wasmtime::Result<bool> {
        // Tables hold function references; a million is far past any real wizard.
        Ok(desired <= 1_000_000)
    }
}

/// Clocks frozen at zero: a wizard's output must depend only on its inputs.
struct Frozen;

impl HostWallClock for Frozen {
    fn resolution(&self) -> Duration {
        Duration::from_secs(1)
    }

    fn now(&self) -> Duration {
        Duration::ZERO
    }
}

impl HostMonotonicClock for Frozen {
    fn resolution(&self) -> u64 {
        1_000_000_000
    }

    fn now(&self) -> u64 {
        0
    }
}

/// What a failed run of a guest left behind, to show with its diagnostic.
struct Leftovers {
    stdout: MemoryOutputPipe,
    stderr: MemoryOutputPipe,
    log: Vec<String>,
    memory_refused: bool,
    log_overflowed: bool,
    /// The run's deadline was what was left of the program's time, not a call's.
    program_deadline: bool,
    warnings: Vec<String>,
    warned: usize,
}

/// The error of a call not run because the program's wizard time is spent.
#[derive(Debug)]
struct ProgramTimeSpent;

impl std::fmt::Display for ProgramTimeSpent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the program's wizard time is spent")
    }
}

impl std::error::Error for ProgramTimeSpent {}

/// What a call's random numbers are seeded from: the same call, the same numbers.
fn seed(wizard: &WasmDigest, call: &str) -> [u8; 32] {
    let mut sha = Sha256::new();
    sha.update(b"ger wizard call, version 1");
    sha.update(wizard);
    sha.update(call.as_bytes());
    sha.finalize().into()
}

impl WasmWizards {
    /// Wizards from `dir`, for a machine with `config`'s tools. With
    /// `progress`, a wizard whose `.wasm` is missing or older than its
    /// sources is built before it runs, and `progress` hears about it.
    pub fn new(dir: &Path, config: &config::Config, limits: Limits, progress: Option<Progress>) -> WasmWizards {
        let mut wasm_config = Config::new();
        wasm_config.epoch_interruption(true);
        // A few pooled slots: calls run one at a time (a wizard's nested calls
        // run after its instance is gone), and a fresh instance per call still
        // starts from the module's own memory image. Where the address space
        // cannot be reserved, instances are made on demand as before.
        let mut pooled = wasm_config.clone();
        let mut pool = PoolingAllocationConfig::default();
        pool.total_component_instances(4).total_core_instances(32).total_memories(8).total_tables(16);
        pool.linear_memory_keep_resident(KEEP_RESIDENT).table_keep_resident(KEEP_RESIDENT).pagemap_scan(Enabled::Auto);
        pooled.allocation_strategy(InstanceAllocationStrategy::Pooling(pool));
        // Engine::new can only fail on a bad configuration or a refused reservation.
        let engine =
            Engine::new(&pooled).or_else(|_| Engine::new(&wasm_config)).expect("a valid wasmtime configuration");
        let mut linker = Linker::new(&engine);
        wasmtime_wasi::p2::add_to_linker_sync(&mut linker).expect("WASI links once");
        Wizard::add_to_linker::<Guest, HasSelf<Guest>>(&mut linker, |guest| guest).expect("the host links once");
        first::Wizard::add_to_linker::<Guest, HasSelf<Guest>>(&mut linker, |guest| guest)
            .expect("the host of 0.1.0 links once");
        WasmWizards {
            dir: dir.to_path_buf(),
            engine,
            linker,
            limits,
            tools: Arc::new(config.tools.clone()),
            machine_units: config.units,
            progress,
            catalog: None,
            loaded: HashMap::new(),
            ticker: false,
            cache_key: OnceCell::new(),
            ticks: Arc::new(AtomicU64::new(0)),
            spent: 0,
            returned: 0,
        }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The wizards in the directory, built where needed (if building is on).
    pub fn catalog(&mut self) -> Result<&Catalog, catalog::ScanError> {
        if self.catalog.is_none() {
            self.catalog = Some(catalog::scan(&self.dir)?);
        }
        Ok(self.catalog.as_ref().expect("just set"))
    }

    /// The description of wizard `name`, loading (and building) it if need be.
    pub fn describe(&mut self, name: &str) -> Result<wit::Description, Diagnostic> {
        let loaded = self.load(name, Span::default())?;
        self.description_of(&loaded, name, Span::default())
    }

    fn description_of(&mut self, loaded: &Loaded, name: &str, span: Span) -> Result<wit::Description, Diagnostic> {
        if let Some(description) = loaded.description.get() {
            return Ok(description.clone());
        }
        let seed = seed(&loaded.digest, "describe");
        let (result, leftovers) = self.run(loaded, None, seed, |store, wizard| wizard.call_describe(store));
        let description = result.map_err(|err| self.failure(name, span, &err, leftovers))?;
        Ok(loaded.description.get_or_init(|| description).clone())
    }

    fn load(&mut self, name: &str, span: Span) -> Result<Rc<Loaded>, Diagnostic> {
        let key = catalog::key(name);
        if let Some(loaded) = self.loaded.get(&key) {
            return loaded.clone();
        }
        let loaded = self.load_uncached(name, span).map(Rc::new);
        self.loaded.insert(key, loaded.clone());
        loaded
    }

    fn load_uncached(&mut self, name: &str, span: Span) -> Result<Loaded, Diagnostic> {
        let dir = self.dir.display().to_string();
        let shown = shown_name(name);
        if !self.dir.is_dir() {
            // No wizards directory (the default one is often absent): as with no wizards at all.
            let message = format!("no wizard named `{shown}` to run this call");
            return Err(Diagnostic::error(span, message).with_help(NO_WIZARD_HELP));
        }
        let catalog = self.catalog().map_err(|err| Diagnostic::error(span, err.to_string()))?;
        let Some(entry) = catalog.find(name).cloned() else {
            let known = catalog.names().join(", ");
            let help = if known.is_empty() {
                format!("{dir} has no wizards; {NO_WIZARD_HELP}")
            } else {
                format!("the wizards in {dir} are: {known}; {NO_WIZARD_HELP}")
            };
            return Err(Diagnostic::error(span, format!("no wizard named `{shown}` in {dir}")).with_help(help));
        };
        if let Some(source) = &entry.source {
            match &mut self.progress {
                Some(progress) if build::stale(source, &entry.wasm) => {
                    build::build(source, &entry.wasm, &self.dir, false, progress).map_err(|err| {
                        Diagnostic::error(span, format!("wizard `{shown}` failed to build: {}", err.message))
                            .with_help(err.details)
                    })?;
                }
                None if !entry.wasm.exists() => {
                    let message = format!("wizard `{shown}` is not built: {} is missing", entry.wasm.display());
                    let help = format!("run `ger wizard build {}`, or leave out --no-build", source.dir.display());
                    return Err(Diagnostic::error(span, message).with_help(help));
                }
                _ => {}
            }
        }
        let bytes = std::fs::read(&entry.wasm).map_err(|err| {
            Diagnostic::error(span, format!("cannot read wizard `{shown}` ({}): {err}", entry.wasm.display()))
        })?;
        let cannot_load = |err: wasmtime::Error| {
            Diagnostic::error(span, format!("wizard `{shown}` ({}) cannot be loaded: {err:#}", entry.wasm.display()))
                .with_help("a wizard is a WebAssembly component of the world ger:wizard/wizard (wit/wizard.wit)")
        };
        let digest: WasmDigest = Sha256::digest(&bytes).into();
        let key = self.cache_key.get_or_init(cache::Key::user).as_ref();
        let component = cache::load(&self.engine, &bytes, &digest, &cache::dir(&self.dir), key).map_err(cannot_load)?;
        let pre = self.linker.instantiate_pre(&component).map_err(cannot_load)?;
        let pre = WizardPre::new(pre).map_err(cannot_load)?;
        Ok(Loaded { pre, digest, description: OnceCell::new() })
    }

    /// Runs `f` on a fresh instance of `loaded` in a new store, within what is
    /// left of the program's time; `to_program` converts the tool table's
    /// lengths for `find-tool`, and `seed` seeds every random source.
    fn run<R>(
        &mut self,
        loaded: &Loaded,
        state: Option<&CallState>,
        seed: [u8; 32],
        f: impl FnOnce(&mut Store<Guest>, &Wizard) -> wasmtime::Result<R>,
    ) -> (wasmtime::Result<R>, Leftovers) {
        self.start_ticker();
        let to_program = state.map_or(1.0, |state| self.machine_units.factor_to(state.units));
        let stdout = MemoryOutputPipe::new(self.limits.output);
        let stderr = MemoryOutputPipe::new(self.limits.output);
        let call = ticks(self.limits.time);
        let left = ticks(self.limits.program_time).saturating_sub(self.spent);
        let program_deadline = left < call;
        let leftovers = |guest: Option<Guest>| {
            let guest = guest.map(|g| (g.log, g.memory.refused, g.log_overflowed, g.warnings, g.warned));
            let (log, memory_refused, log_overflowed, warnings, warned) = guest.unwrap_or_default();
            Leftovers {
                stdout: stdout.clone(),
                stderr: stderr.clone(),
                log,
                memory_refused,
                log_overflowed,
                program_deadline,
                warnings,
                warned,
            }
        };
        if left == 0 {
            return (Err(wasmtime::Error::new(ProgramTimeSpent)), leftovers(None));
        }
        // Three generators from one seed: wasi:random's secure and insecure
        // ones, and the insecure seed that hash maps start from.
        let mut random = rand::rngs::StdRng::from_seed(seed);
        let insecure_seed = u128::from(random.next_u64()) << 64 | u128::from(random.next_u64());
        let insecure = rand::rngs::StdRng::from_rng(&mut random);
        let wasi = WasiCtxBuilder::new()
            .stdout(stdout.clone())
            .stderr(stderr.clone())
            .wall_clock(Frozen)
            .monotonic_clock(Frozen)
            .insecure_random_seed(insecure_seed)
            .insecure_random(insecure)
            .secure_random(random)
            .build();
        let guest = Guest {
            wasi,
            table: ResourceTable::new(),
            memory: MemoryLimiter { limit: self.limits.memory, used: 0, refused: false },
            log: Vec::new(),
            logged: 0,
            log_limit: self.limits.log,
            log_overflowed: false,
            tools: self.tools.clone(),
            to_program,
            machine_units: self.machine_units,
            stock: state.and_then(|state| state.stock).map(|[min, max]| wit::Bounds {
                min_x: min[0],
                min_y: min[1],
                min_z: min[2],
                max_x: max[0],
                max_y: max[1],
                max_z: max[2],
            }),
            warnings: Vec::new(),
            warned: 0,
        };
        let mut store = Store::new(&self.engine, guest);
        store.limiter(|guest| &mut guest.memory);
        // One more than the ticks allowed: the first may come at once.
        store.set_epoch_deadline(left.min(call) + 1);
        let result = loaded.pre.instantiate(&mut store).and_then(|wizard| f(&mut store, &wizard));
        (result, leftovers(Some(store.into_data())))
    }

    fn start_ticker(&mut self) {
        if std::mem::replace(&mut self.ticker, true) {
            return;
        }
        let engine = self.engine.weak();
        let ticks = self.ticks.clone();
        std::thread::spawn(move || loop {
            std::thread::sleep(TICK);
            match engine.upgrade() {
                Some(engine) => {
                    ticks.fetch_add(1, Ordering::Relaxed);
                    engine.increment_epoch();
                }
                None => break,
            }
        });
    }

    /// Turns an error from wasmtime into a diagnostic that says what the
    /// guest did, in the user's terms.
    fn failure(&self, name: &str, span: Span, err: &wasmtime::Error, leftovers: Leftovers) -> Diagnostic {
        let name = shown_name(name);
        let program_time = seconds(self.limits.program_time);
        if err.is::<ProgramTimeSpent>() {
            let message = format!(
                "wizard `{name}` was not run: the wizard calls of this program have used all of their {program_time}"
            );
            return Diagnostic::error(span, message).with_help(program_time_help());
        }
        let stderr = String::from_utf8_lossy(&leftovers.stderr.contents()).into_owned();
        let stdout = String::from_utf8_lossy(&leftovers.stdout.contents()).into_owned();
        let trap = err.downcast_ref::<Trap>().copied();
        let full = stdout.len() >= self.limits.output || stderr.len() >= self.limits.output;
        if trap == Some(Trap::Interrupt) && leftovers.program_deadline {
            let message = format!(
                "wizard `{name}` was stopped: the wizard calls of this program had run for {program_time}, \
                 all the time they have together"
            );
            return Diagnostic::error(span, message).with_help(program_time_help());
        }
        let what = if trap == Some(Trap::Interrupt) {
            format!("did not finish within {} and was stopped", seconds(self.limits.time))
        } else if leftovers.log_overflowed {
            format!("logged more than {} KiB and was stopped", self.limits.log >> 10)
        } else if leftovers.memory_refused {
            format!("needed more than {} MiB of memory and was stopped", self.limits.memory >> 20)
        } else if trap == Some(Trap::StackOverflow) {
            "overflowed its stack (runaway recursion?) and was stopped".to_string()
        } else if full || format!("{err:#}").contains("beyond capacity") {
            format!("wrote more than {} KiB of output and was stopped", self.limits.output >> 10)
        } else if stderr.contains("panicked") {
            "panicked".to_string()
        } else {
            match trap {
                Some(trap) => format!("crashed: {trap}"),
                None => format!("failed: {err:#}"),
            }
        };
        let mut help = String::new();
        for (title, text) in [("stderr", &stderr), ("stdout", &stdout), ("log", &leftovers.log.join("\n"))] {
            let text = text.trim_end();
            if text.is_empty() {
                continue;
            }
            let lines: Vec<&str> = text.lines().collect();
            let shown = &lines[lines.len().saturating_sub(12)..];
            if !help.is_empty() {
                help.push('\n');
            }
            help.push_str(&format!("its {title}"));
            if shown.len() < lines.len() {
                help.push_str(&format!(" (last {} of {} lines)", shown.len(), lines.len()));
            }
            help.push(':');
            for line in shown {
                let line: String = line.chars().take(200).collect();
                help.push_str(&format!("\n  {line}"));
            }
        }
        if help.is_empty() {
            help = "this is a fault in the wizard, not in the program".to_string();
        }
        Diagnostic::error(span, format!("wizard `{name}` {what}")).with_help(help)
    }
}

impl WasmWizards {
    fn expand_loaded(&mut self, loaded: &Loaded, call: &Call, state: &CallState) -> Result<Expansion, Diagnostic> {
        let args: Vec<wit::Arg> = call
            .args
            .iter()
            .map(|arg| match arg {
                WizardArg::Number(n) => wit::Arg::Number(*n),
                WizardArg::Text(t) => wit::Arg::Text(t.clone()),
            })
            .collect();
        let to_program = self.machine_units.factor_to(state.units);
        let mut machine_state = state_to_wit(state);
        // CallState has the diameter only; the table has the rest of the tool.
        machine_state.tool = state
            .tool
            .as_ref()
            .and_then(|t| self.tools.iter().find(|tool| tool.number == t.number))
            .map(|tool| tool_to_wit(tool, to_program));
        // Debug text is exact (floats read back as the same number) and the
        // same for the same call: what the call's random numbers are seeded from.
        let seed = seed(&loaded.digest, &format!("expand {args:?} {machine_state:?} {:?}", state.stock));
        let (result, leftovers) =
            self.run(loaded, Some(state), seed, |store, wizard| wizard.call_expand(store, &args, machine_state));
        let name = shown_name(call.name);
        match result {
            Ok(Ok(output)) => {
                let too_many = |count: usize| {
                    let message = format!(
                        "wizard `{name}` returned {count} statements, more than the {} one call may",
                        self.limits.statements
                    );
                    Diagnostic::error(call.span, message)
                };
                // Checked before rendering too, to spare rendering a flood.
                if output.len() > self.limits.statements {
                    return Err(too_many(output.len()));
                }
                let statements = render(&output, call.name, call.span)?;
                // A `text` statement may hold many lines: counted as rendered.
                if statements.len() > self.limits.statements {
                    return Err(too_many(statements.len()));
                }
                self.returned += statements.len();
                if self.returned > self.limits.program_statements {
                    let message = format!(
                        "wizard `{name}` returned {} statements, which takes the wizard calls of this program \
                         past the {} statements they may return together",
                        statements.len(),
                        self.limits.program_statements
                    );
                    let help = "all the wizard calls of one program, nested ones too, share this limit";
                    return Err(Diagnostic::error(call.span, message).with_help(help));
                }
                let mut warnings: Vec<Diagnostic> = leftovers
                    .warnings
                    .iter()
                    .map(|message| Diagnostic::warning(call.span, format!("wizard `{name}`: {message}")))
                    .collect();
                if leftovers.warned > warnings.len() {
                    let more = leftovers.warned - warnings.len();
                    let message = format!("wizard `{name}` gave {more} more warnings, not shown");
                    warnings.push(Diagnostic::warning(call.span, message));
                }
                Ok(Expansion { statements, warnings })
            }
            Ok(Err(message)) => {
                let message = clip(&message, SHOWN_MESSAGE);
                let mut diagnostic = Diagnostic::error(call.span, format!("wizard `{name}`: {message}"));
                if let Ok(description) = self.description_of(loaded, call.name, call.span) {
                    diagnostic = diagnostic.with_help(format!("usage: {}", clip(&description.usage, SHOWN_MESSAGE)));
                }
                Err(diagnostic)
            }
            Err(err) => Err(self.failure(call.name, call.span, &err, leftovers)),
        }
    }
}

fn seconds(time: Duration) -> String {
    format!("{} s", time.as_secs_f64())
}

fn program_time_help() -> &'static str {
    "all the wizard calls of one program, nested ones too, share one time limit \
     (--wizard-total-time SECONDS): a wizard that calls many others, or a program that calls a slow one \
     many times, can need more"
}

impl Wizards for WasmWizards {
    fn expand(&mut self, call: &Call, state: &CallState) -> Result<Expansion, Diagnostic> {
        let loaded = self.load(call.name, call.span).map_err(|d| Diagnostic { span: call.span, ..d })?;
        // What the call costs, its output read and checked too (but not
        // loading, which happens once), counts towards the program's time.
        let started = self.ticks.load(Ordering::Relaxed);
        let result = self.expand_loaded(&loaded, call, state);
        self.spent += self.ticks.load(Ordering::Relaxed) - started;
        result
    }

    fn start(&mut self) {
        self.spent = 0;
        self.returned = 0;
    }
}

fn tool_to_wit(tool: &config::Tool, to_program: f64) -> wit::Tool {
    wit::Tool {
        number: tool.number,
        kind: match tool.kind {
            ToolKind::Endmill => wit::ToolKind::Endmill,
            ToolKind::Ballmill => wit::ToolKind::Ballmill,
            ToolKind::Drill => wit::ToolKind::Drill,
            ToolKind::CenterDrill => wit::ToolKind::CenterDrill,
        },
        diameter: tool.diameter * to_program,
        flute_length: tool.flute_length.map(|l| l * to_program),
        tip_angle: tool.tip_angle,
    }
}

fn units_to_wit(units: Units) -> wit::Units {
    match units {
        Units::Mm => wit::Units::Mm,
        Units::Inch => wit::Units::Inch,
    }
}

fn state_to_wit(state: &CallState) -> wit::MachineState {
    let [x, y, z] = state.position;
    wit::MachineState {
        units: units_to_wit(state.units),
        x,
        y,
        z,
        distance: match state.distance {
            Distance::Absolute => wit::Distance::Absolute,
            Distance::Incremental => wit::Distance::Incremental,
        },
        plane: match state.plane {
            Plane::XY => wit::Plane::Xy,
            Plane::ZX => wit::Plane::Zx,
            Plane::YZ => wit::Plane::Yz,
        },
        feed: state.feed,
        spindle: match state.spindle {
            Spindle::Off => wit::Spindle::Off,
            Spindle::Clockwise(s) => wit::Spindle::Clockwise(s),
            Spindle::CounterClockwise(s) => wit::Spindle::CounterClockwise(s),
        },
        tool: None,
        tool_number: state.tool_number,
        line: state.line,
    }
}
