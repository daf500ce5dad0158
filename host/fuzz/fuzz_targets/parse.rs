//! The lexer and parser, in both dialects, on any bytes, as `ger parse` runs them.
#![no_main]

use ger_core::config::DialectConfig;
use ger_core::passes::parse;
use ger_core::statement::Dialect;
use libfuzzer_sys::fuzz_target;

/// Loops run this many times at most: the limit's own rule is a unit test,
/// and a million runs of a loop an input happens to make never end would
/// take the instrumented build past its time limit, finding nothing.
const MAX_ITERATIONS: u64 = 10_000;

fuzz_target!(|program: &[u8]| {
    for dialect in [Dialect::Strict, Dialect::Lenient] {
        let dialect = DialectConfig { max_iterations: MAX_ITERATIONS, ..DialectConfig::from(dialect) };
        parse(program, &dialect).for_each(drop);
    }
});
