//! Uses random numbers: moves to X from a hash map's random keys and to Y
//! from wasi:random's secure generator.
use std::hash::BuildHasher;

use ger_wizard_sdk::*;

#[link(wasm_import_module = "wasi:random/random@0.2.6")]
unsafe extern "C" {
    #[link_name = "get-random-u64"]
    fn get_random_u64() -> u64;
}

struct Random;

impl Wizard for Random {
    fn describe() -> Description {
        Description::new("Random", "moves somewhere random", "Random")
    }

    fn expand(_: &Args, _: &State) -> Result<Vec<Statement>, String> {
        let hashed = std::collections::hash_map::RandomState::new().hash_one("ger");
        // SAFETY: a WASI import that takes nothing and returns a number.
        let secure = unsafe { get_random_u64() };
        let at = |n: u64| (n % 1_000_000) as f64 / 1000.0;
        Ok(vec![g1().x(at(hashed)).y(at(secure)).into()])
    }
}

export_wizard!(Random);
