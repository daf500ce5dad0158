//! Hostile: panics.
use ger_wizard_sdk::*;

struct Crash;

impl Wizard for Crash {
    fn describe() -> Description {
        Description::new("Crash", "panics", "Crash")
    }

    fn expand(_: &Args, _: &State) -> Result<Vec<Statement>, String> {
        println!("about to give up");
        panic!("boom: the wizard gave up");
    }
}

export_wizard!(Crash);
