fn main() {
    std::process::exit(ger::cli::main());
}
