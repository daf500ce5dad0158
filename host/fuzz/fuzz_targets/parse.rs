//! The lexer and parser, in both dialects, on any bytes, as `ger parse` runs them.
#![no_main]

use ger_core::config::DialectConfig;
use ger_core::passes::parse;
use ger_core::statement::Dialect;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|program: &[u8]| {
    for dialect in [Dialect::Strict, Dialect::Lenient] {
        let dialect = DialectConfig::from(dialect);
        parse(program, &dialect).for_each(drop);
    }
});
