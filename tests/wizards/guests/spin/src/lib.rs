//! Hostile: never returns.
use ger_wizard_sdk::*;

struct Spin;

impl Wizard for Spin {
    fn describe() -> Description {
        Description::new("Spin", "loops forever", "Spin")
    }

    fn expand(_: &Args, _: &State) -> Result<Vec<Statement>, String> {
        let mut i = 0u64;
        loop {
            i = std::hint::black_box(i.wrapping_add(1));
        }
    }
}

export_wizard!(Spin);
