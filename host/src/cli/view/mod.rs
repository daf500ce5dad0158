//! `ger view`: a page on 127.0.0.1 that shows the program, its translation,
//! its diagnostics and the simulated part, made again whenever the page edits
//! the program or the file, the config or a wizard changes on disk.
//! `session` makes snapshots (one worker thread), `server` answers HTTP
//! (axum on tokio), `watch` follows the files; `docs/view-api.md` is the
//! contract with the page, whose files `assets` serves.

mod assets;
mod guard;
mod server;
mod session;
mod watch;

use std::io::Write;
use std::net::{Ipv4Addr, TcpListener};
use std::path::Path;

use clap::Args;

use super::render::{memory_limit, resolution, usage_error};
use super::report::plain_error;
use super::CommonArgs;

#[derive(Args)]
pub(crate) struct ViewArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// The port to serve on, on 127.0.0.1 only (0 lets the system pick one).
    #[arg(long, default_value_t = 8274)]
    port: u16,
    /// The side of a simulation cell, in machine units [default: 1/500 of
    /// the stock's longer side].
    #[arg(long, value_name = "LENGTH", value_parser = resolution)]
    resolution: Option<f64>,
    /// MiB the simulation's height field may take [default: the config's, or 2048].
    #[arg(long, value_name = "MIB", value_parser = memory_limit)]
    memory_limit: Option<u64>,
}

pub(crate) fn main(args: ViewArgs) -> Result<i32, String> {
    if args.common.file == Path::new("-") {
        return usage_error("ger view shows a program file, not standard input");
    }
    // Loopback only: the page can write the program's files.
    let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, args.port))
        .and_then(|listener| listener.set_nonblocking(true).map(|()| listener))
        .map_err(|err| plain_error(&format!("cannot serve on 127.0.0.1:{}: {err}", args.port), None))?;
    let port = listener.local_addr().map_err(|err| plain_error(&err.to_string(), None))?.port();
    let session = session::Session::start(args)?;
    watch::start(session.clone())?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_io()
        .enable_time()
        .build()
        .map_err(|err| plain_error(&format!("cannot start the server: {err}"), None))?;
    println!("ger view: http://127.0.0.1:{port}/");
    let _ = std::io::stdout().flush();
    runtime
        .block_on(server::serve(listener, session, port))
        .map_err(|err| plain_error(&format!("the server stopped: {err}"), None))?;
    Ok(0)
}
