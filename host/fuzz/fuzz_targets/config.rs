//! `ger.toml` parsing on any text: a config or a diagnostic, never a panic.
#![no_main]

use ger_core::config::Config;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|text: &[u8]| {
    if let Ok(text) = std::str::from_utf8(text) {
        if let Err(diagnostic) = Config::from_toml(text) {
            drop(diagnostic.to_string());
        }
    }
});
