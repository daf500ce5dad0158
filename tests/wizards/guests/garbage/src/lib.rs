//! Hostile: returns statements that are not G-code.
use ger_wizard_sdk::*;

struct Garbage;

impl Wizard for Garbage {
    fn describe() -> Description {
        Description::new("Garbage", "returns a bad word", "Garbage")
    }

    fn expand(_: &Args, _: &State) -> Result<Vec<Statement>, String> {
        Ok(vec![g1().x(1.0).into(), Block::default().word('%', 1.0).into()])
    }
}

export_wizard!(Garbage);
