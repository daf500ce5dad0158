//! `ger`: the command line. It only wires the crates under `host/crates`
//! to argv, files and terminals (see ARCHITECTURE.md at the repository root).

mod cli;

fn main() {
    let code = cli::main();
    ger_output::end_as_signalled();
    std::process::exit(code);
}
