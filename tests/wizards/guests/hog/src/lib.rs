//! Hostile: allocates until something stops it.
use ger_wizard_sdk::*;

struct Hog;

impl Wizard for Hog {
    fn describe() -> Description {
        Description::new("Hog", "eats memory", "Hog")
    }

    fn expand(_: &Args, _: &State) -> Result<Vec<Statement>, String> {
        let mut kept = Vec::new();
        loop {
            kept.push(std::hint::black_box(vec![1u8; 1 << 20]));
        }
    }
}

export_wizard!(Hog);
