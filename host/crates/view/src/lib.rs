//! `ger view`: a page on 127.0.0.1 that shows a program, its translation,
//! its diagnostics and the simulated part, made again whenever the page edits
//! the program or the file, the config or a wizard changes on disk.
//!
//! `session` makes snapshots through [`ger_engine`] (one worker thread),
//! `server` answers HTTP (axum on tokio, each connection served by hyper with
//! a head timeout), `guard` admits requests (loopback hosts and origins
//! only), `watch` follows the files. `host/docs/view-api.md` is the contract
//! with the page, whose files `assets` serves. The caller (the `ger` binary)
//! binds the socket and gives the wizard runtime: nothing here knows argv or
//! wasmtime.

mod assets;
pub mod guard;
mod server;
mod session;
mod watch;

use std::net::TcpListener;
use std::path::PathBuf;

use ger_engine::compare::Design;
use ger_engine::core::config::Config;
use ger_engine::core::statement::Units;
use ger_engine::core::wizard::Wizards;
use ger_engine::Settings;

/// Makes the wizards a snapshot's translation calls, for the machine it runs on.
pub type WizardMaker = Box<dyn Fn(&Config) -> Box<dyn Wizards> + Send + Sync>;

/// What to serve, and on what machine.
pub struct Options {
    /// The program shown first; the page may open any other in its folder.
    pub file: PathBuf,
    pub settings: Settings,
    /// The wizards folder, watched for `NAME.wasm` files changing.
    pub wizards_dir: PathBuf,
    pub wizards: WizardMaker,
    /// The side of a simulation cell [default: 1/500 of the stock's longer side].
    pub resolution: Option<f64>,
    /// MiB the height field may take [default: the config's, or 2048].
    pub memory_limit_mib: Option<u64>,
    /// The job `file` is the first of ([`file`] alone, or more programs cut
    /// after it on the same stock, in order). Viewing one of them, the ones
    /// before it cut the stock first (it is checked against what they
    /// left) and the ones after it then: the part is the whole job's.
    pub job: Vec<PathBuf>,
    /// The design the part is set beside (`--design`), as a layer.
    pub design: Option<DesignOptions>,
}

/// A design, and how to place and judge it (see `ger_engine::place_design`).
pub struct DesignOptions {
    /// As the command line named it.
    pub name: String,
    /// As read: placed again on each snapshot's stock.
    pub mesh: Design,
    /// Its unit [default: the machine's].
    pub units: Option<Units>,
    /// Where program zero is in its coordinates [default: its lowest corner on the stock's].
    pub origin: Option<[f64; 3]>,
    /// [default: `ger_engine::default_tolerance`].
    pub tolerance: Option<f64>,
}

/// Why `ger view` could not start or stopped.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("cannot read {name}: {cause}")]
    Read { name: String, cause: std::io::Error },
    #[error("cannot {what}: {cause}")]
    Start { what: &'static str, cause: std::io::Error },
    #[error("cannot watch for changes: {0}")]
    Watch(notify::Error),
    #[error("the server stopped: {0}")]
    Stopped(std::io::Error),
}

/// Serves `options`' program on `listener` (bound to 127.0.0.1) until the
/// process ends; `ready` is called once the first snapshot is being made
/// and the server is about to answer.
pub fn serve(listener: TcpListener, options: Options, ready: impl FnOnce(u16)) -> Result<(), Error> {
    let port = listener.local_addr().map_err(|cause| Error::Start { what: "serve", cause })?.port();
    let session = session::Session::start(options)?;
    watch::start(session.clone())?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_io()
        .enable_time()
        .build()
        .map_err(|cause| Error::Start { what: "start the server", cause })?;
    ready(port);
    runtime.block_on(server::serve(listener, session, port)).map_err(Error::Stopped)
}
