//! Hostile: prints without end.
use ger_wizard_sdk::*;

struct Chatter;

impl Wizard for Chatter {
    fn describe() -> Description {
        Description::new("Chatter", "prints forever", "Chatter")
    }

    fn expand(_: &Args, _: &State) -> Result<Vec<Statement>, String> {
        loop {
            println!("chatter chatter chatter chatter chatter chatter chatter");
        }
    }
}

export_wizard!(Chatter);
