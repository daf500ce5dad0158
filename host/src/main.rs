//! `ger`: the command line. It only wires the crates under `host/crates`
//! to argv, files and terminals (see ARCHITECTURE.md at the repository root).

mod cli;

fn main() {
    std::process::exit(cli::main());
}
