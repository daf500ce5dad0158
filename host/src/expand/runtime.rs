//! Runs wizard components with wasmtime, one sandboxed instance per call.
//!
//! A wizard is loaded the first time a program calls it: found by name in
//! the wizards directory (built first if its sources are newer, see
//! [`super::build`]), compiled or taken from the disk cache, and linked once
//! into a template ([`bindings::WizardPre`]). Each call instantiates the
//! template in a new store, so no state leaks from one call to the next, and
//! runs it with:
//! - WASI with no capabilities: no preopened directories, no environment, no
//!   arguments, no network, no stdin, clocks frozen at zero; stdout and
//!   stderr go to bounded buffers that are shown if the call fails;
//! - an epoch deadline ([`Limits::time`]), ticked by one background thread;
//! - a memory limit over all of the instance's memories ([`Limits::memory`]).
//!
//! Whatever the guest does, the outcome is statements or a diagnostic at the
//! call naming the wizard: every error from wasmtime is turned into one here.

use std::cell::OnceCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;
use std::time::Duration;

use wasmtime::component::{HasSelf, Linker, ResourceTable};
use wasmtime::{Config, Engine, ResourceLimiter, Store, Trap};
use wasmtime_wasi::p2::pipe::MemoryOutputPipe;
use wasmtime_wasi::{HostMonotonicClock, HostWallClock, WasiCtx, WasiCtxBuilder, WasiCtxView, WasiView};

use super::build::{self, Progress};
use super::cache;
use super::catalog::{self, Catalog};
use super::render::render;
use super::{wizard_help, Call, Wizards};
use crate::config::{self, ToolKind};
use crate::diag::{Diagnostic, Span};
use crate::state::{CallState, Spindle};
use crate::statement::{Distance, Plane, Statement, Units, WizardArg};

pub mod bindings {
    //! Rust types for `wit/wizard.wit`, host side.
    wasmtime::component::bindgen!({ path: "../wit", world: "ger:wizard/wizard" });
}

use bindings::ger::wizard::{host, types as wit};
use bindings::{Wizard, WizardPre};

/// How often the epoch ticks: the granularity of the time limit.
const TICK: Duration = Duration::from_millis(10);

/// What one call may use.
#[derive(Clone, Debug)]
pub struct Limits {
    /// Wall time for one call, instantiation included.
    pub time: Duration,
    /// Bytes of linear memory, all of the instance's memories together.
    pub memory: usize,
    /// Bytes kept of each of stdout and stderr; writing more is an error.
    pub output: usize,
    /// Statements one call may return.
    pub statements: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits { time: Duration::from_secs(1), memory: 64 << 20, output: 64 << 10, statements: 1_000_000 }
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
}

struct Loaded {
    pre: WizardPre<Guest>,
    description: OnceCell<wit::Description>,
}

/// A store's data: everything one call can reach.
struct Guest {
    wasi: WasiCtx,
    table: ResourceTable,
    memory: MemoryLimiter,
    log: Vec<String>,
    tools: Arc<Vec<config::Tool>>,
    /// Machine units -> the program's units at the call.
    to_program: f64,
}

impl WasiView for Guest {
    fn ctx(&mut self) -> WasiCtxView<'_> {
        WasiCtxView { ctx: &mut self.wasi, table: &mut self.table }
    }
}

impl wit::Host for Guest {}

impl host::Host for Guest {
    fn log(&mut self, message: String) {
        // Bounded like stdout: a wizard logging in a loop must not eat the host's memory.
        if self.log.len() < 1000 {
            self.log.push(message);
        }
    }

    fn find_tool(&mut self, number: u32) -> Option<wit::Tool> {
        let tool = self.tools.iter().find(|t| t.number == number)?;
        Some(tool_to_wit(tool, self.to_program))
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
}

impl WasmWizards {
    /// Wizards from `dir`, for a machine with `config`'s tools. With
    /// `progress`, a wizard whose `.wasm` is missing or older than its
    /// sources is built before it runs, and `progress` hears about it.
    pub fn new(dir: &Path, config: &config::Config, limits: Limits, progress: Option<Progress>) -> WasmWizards {
        let mut wasm_config = Config::new();
        wasm_config.epoch_interruption(true);
        // Component::new can only fail on a bad configuration, which this is not.
        let engine = Engine::new(&wasm_config).expect("a valid wasmtime configuration");
        let mut linker = Linker::new(&engine);
        wasmtime_wasi::p2::add_to_linker_sync(&mut linker).expect("WASI links once");
        Wizard::add_to_linker::<Guest, HasSelf<Guest>>(&mut linker, |guest| guest).expect("the host links once");
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
        }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The wizards in the directory, built where needed (if building is on).
    pub fn catalog(&mut self) -> Result<&Catalog, String> {
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
        let (result, leftovers) = self.run(loaded, 1.0, |store, wizard| wizard.call_describe(store));
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
        if !self.dir.is_dir() {
            // No wizards directory (the default one is often absent): as with no wizards at all.
            let message = format!("no wizard named `{name}` to run this call");
            return Err(Diagnostic::error(span, message).with_help(wizard_help(name)));
        }
        let catalog = self.catalog().map_err(|message| Diagnostic::error(span, message))?;
        let Some(entry) = catalog.find(name).cloned() else {
            let known = catalog.names().join(", ");
            let help = if known.is_empty() {
                format!("{dir} has no wizards; {}", wizard_help(name))
            } else {
                format!("the wizards in {dir} are: {known}; {}", wizard_help(name))
            };
            return Err(Diagnostic::error(span, format!("no wizard named `{name}` in {dir}")).with_help(help));
        };
        if let Some(source) = &entry.source {
            match &mut self.progress {
                Some(progress) if build::stale(source, &entry.wasm) => {
                    build::build(source, &entry.wasm, &self.dir, false, progress).map_err(|err| {
                        Diagnostic::error(span, format!("wizard `{name}` failed to build: {}", err.message))
                            .with_help(err.details)
                    })?;
                }
                None if !entry.wasm.exists() => {
                    let message = format!("wizard `{name}` is not built: {} is missing", entry.wasm.display());
                    let help = format!("run `ger wizard build {}`, or leave out --no-build", source.dir.display());
                    return Err(Diagnostic::error(span, message).with_help(help));
                }
                _ => {}
            }
        }
        let bytes = std::fs::read(&entry.wasm).map_err(|err| {
            Diagnostic::error(span, format!("cannot read wizard `{name}` ({}): {err}", entry.wasm.display()))
        })?;
        let cannot_load = |err: wasmtime::Error| {
            Diagnostic::error(span, format!("wizard `{name}` ({}) cannot be loaded: {err:#}", entry.wasm.display()))
                .with_help("a wizard is a WebAssembly component of the world ger:wizard/wizard (wit/wizard.wit)")
        };
        let component = cache::load(&self.engine, &bytes, &cache::dir(&self.dir)).map_err(cannot_load)?;
        let pre = self.linker.instantiate_pre(&component).map_err(cannot_load)?;
        let pre = WizardPre::new(pre).map_err(cannot_load)?;
        Ok(Loaded { pre, description: OnceCell::new() })
    }

    /// Runs `f` on a fresh instance of `loaded` in a new store; `to_program`
    /// converts the tool table's lengths for `find-tool`.
    fn run<R>(
        &mut self,
        loaded: &Loaded,
        to_program: f64,
        f: impl FnOnce(&mut Store<Guest>, &Wizard) -> wasmtime::Result<R>,
    ) -> (wasmtime::Result<R>, Leftovers) {
        self.start_ticker();
        let stdout = MemoryOutputPipe::new(self.limits.output);
        let stderr = MemoryOutputPipe::new(self.limits.output);
        let wasi = WasiCtxBuilder::new()
            .stdout(stdout.clone())
            .stderr(stderr.clone())
            .wall_clock(Frozen)
            .monotonic_clock(Frozen)
            .build();
        let guest = Guest {
            wasi,
            table: ResourceTable::new(),
            memory: MemoryLimiter { limit: self.limits.memory, used: 0, refused: false },
            log: Vec::new(),
            tools: self.tools.clone(),
            to_program,
        };
        let mut store = Store::new(&self.engine, guest);
        store.limiter(|guest| &mut guest.memory);
        store.set_epoch_deadline(self.limits.time.as_millis().div_ceil(TICK.as_millis()) as u64 + 1);
        let result = loaded.pre.instantiate(&mut store).and_then(|wizard| f(&mut store, &wizard));
        let guest = store.into_data();
        (result, Leftovers { stdout, stderr, log: guest.log, memory_refused: guest.memory.refused })
    }

    fn start_ticker(&mut self) {
        if std::mem::replace(&mut self.ticker, true) {
            return;
        }
        let engine = self.engine.weak();
        std::thread::spawn(move || loop {
            std::thread::sleep(TICK);
            match engine.upgrade() {
                Some(engine) => engine.increment_epoch(),
                None => break,
            }
        });
    }

    /// Turns an error from wasmtime into a diagnostic that says what the
    /// guest did, in the user's terms.
    fn failure(&self, name: &str, span: Span, err: &wasmtime::Error, leftovers: Leftovers) -> Diagnostic {
        let stderr = String::from_utf8_lossy(&leftovers.stderr.contents()).into_owned();
        let stdout = String::from_utf8_lossy(&leftovers.stdout.contents()).into_owned();
        let trap = err.downcast_ref::<Trap>().copied();
        let full = stdout.len() >= self.limits.output || stderr.len() >= self.limits.output;
        let what = if trap == Some(Trap::Interrupt) {
            format!("did not finish within {} and was stopped", seconds(self.limits.time))
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

fn seconds(time: Duration) -> String {
    format!("{} s", time.as_secs_f64())
}

impl Wizards for WasmWizards {
    fn expand(&mut self, call: &Call, state: &CallState) -> Result<Vec<Statement>, Diagnostic> {
        let loaded = self.load(call.name, call.span).map_err(|d| Diagnostic { span: call.span, ..d })?;
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
        let (result, leftovers) =
            self.run(&loaded, to_program, |store, wizard| wizard.call_expand(store, &args, machine_state));
        match result {
            Ok(Ok(output)) => {
                if output.len() > self.limits.statements {
                    let message = format!(
                        "wizard `{}` returned {} statements, more than the {} one call may",
                        call.name,
                        output.len(),
                        self.limits.statements
                    );
                    return Err(Diagnostic::error(call.span, message));
                }
                render(&output, call.name, call.span)
            }
            Ok(Err(message)) => {
                let mut diagnostic = Diagnostic::error(call.span, format!("wizard `{}`: {message}", call.name));
                if let Ok(description) = self.description_of(&loaded, call.name, call.span) {
                    diagnostic = diagnostic.with_help(format!("usage: {}", description.usage));
                }
                Err(diagnostic)
            }
            Err(err) => Err(self.failure(call.name, call.span, &err, leftovers)),
        }
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

fn state_to_wit(state: &CallState) -> wit::MachineState {
    let [x, y, z] = state.position;
    wit::MachineState {
        units: match state.units {
            Units::Mm => wit::Units::Mm,
            Units::Inch => wit::Units::Inch,
        },
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
