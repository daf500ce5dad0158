//! The lexer and parser, in both dialects, on any bytes, as `ger parse` runs them.
#![no_main]

use ger_core::config::{DialectConfig, RunLimits};
use ger_core::passes::parse;
use ger_core::statement::Dialect;
use libfuzzer_sys::fuzz_target;

/// Loops and calls run this much at most: the limits' own rules are unit
/// tests, and under the default limits (a hundred million blocks) an input
/// whose loops run long (nested, or over a 64 KiB line) takes the
/// instrumented build past its time limit, finding nothing. A thousand
/// runs of the longest line are a few seconds.
const LIMITS: RunLimits = RunLimits { iterations: 1_000, blocks: 1_000 };

fuzz_target!(|program: &[u8]| {
    for dialect in [Dialect::Strict, Dialect::Lenient] {
        let dialect = DialectConfig { limits: LIMITS, ..DialectConfig::from(dialect) };
        parse(program, &dialect).for_each(drop);
    }
});
