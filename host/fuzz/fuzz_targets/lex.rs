//! The lexer, in both dialects, on any bytes: it never fails, so it must
//! come to the end of the input without a panic.
#![no_main]

use ger_core::lex::Lexer;
use ger_core::statement::Dialect;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|program: &[u8]| {
    for dialect in [Dialect::Strict, Dialect::Lenient] {
        Lexer::in_dialect(program, dialect).for_each(drop);
    }
});
