//! `ger view`'s command line: the socket it serves on, and the wizard
//! runtime; the server is the `ger-view` crate.

use std::io::Write;
use std::net::{Ipv4Addr, TcpListener};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;

use super::render::{memory_limit, resolution, usage_error};
use super::CommonArgs;
use ger_core::wizard::Wizards;
use ger_engine::Purpose;

#[derive(Args)]
pub(crate) struct ViewArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// More programs, cut after FILE on the same stock in this order (a
    /// job): the part shown is the whole job's, and each program is checked
    /// against what the ones before it left.
    #[arg(value_name = "MORE")]
    more: Vec<PathBuf>,
    /// Also set the part beside its design (a closed STL), as `ger compare`
    /// does: a layer of the 3D view.
    #[arg(long, value_name = "STL")]
    design: Option<PathBuf>,
    #[command(flatten)]
    placing: super::compare::DesignArgs,
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

pub(crate) fn main(args: ViewArgs) -> Result<i32> {
    if args.common.file == Path::new("-") {
        return usage_error("ger view shows a program file, not standard input");
    }
    // Loopback only: the page can write the program's files.
    let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, args.port))
        .and_then(|listener| listener.set_nonblocking(true).map(|()| listener))
        .with_context(|| format!("cannot serve on 127.0.0.1:{}", args.port))?;
    let design = match &args.design {
        Some(path) => {
            let config = args.common.program(Purpose::Cut)?.config().clone();
            match args.placing.for_view(path, &config)? {
                Some(design) => Some(design),
                None => return Ok(2),
            }
        }
        None => None,
    };
    let mut job = vec![args.common.file.clone()];
    job.extend(args.more.iter().cloned());
    let wizards = args.common.wizards.clone();
    let options = ger_view::Options {
        file: args.common.file.clone(),
        settings: args.common.settings(),
        wizards_dir: wizards.dir.clone(),
        wizards: Box::new(move |config| Box::new(wizards.runtime(config)) as Box<dyn Wizards>),
        resolution: args.resolution,
        memory_limit_mib: args.memory_limit,
        job,
        design,
    };
    ger_view::serve(listener, options, |port| {
        println!("ger view: http://127.0.0.1:{port}/");
        let _ = std::io::stdout().flush();
    })?;
    Ok(0)
}
