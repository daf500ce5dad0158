//! Hostile: logs a hundred lines of 1 MiB each, then returns a move.
use ger_wizard_sdk::*;

struct Babble;

impl Wizard for Babble {
    fn describe() -> Description {
        Description::new("Babble", "logs 100 MiB", "Babble")
    }

    fn expand(_: &Args, _: &State) -> Result<Vec<Statement>, String> {
        let line = "babble ".repeat((1 << 20) / 7);
        for _ in 0..100 {
            log(&line);
        }
        Ok(vec![g1().x(1.0).into()])
    }
}

export_wizard!(Babble);
