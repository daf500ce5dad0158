//! Hostile: calls itself without end.
use ger_wizard_sdk::*;

struct Recurse;

impl Wizard for Recurse {
    fn describe() -> Description {
        Description::new("Recurse", "calls itself forever", "Recurse")
    }

    fn expand(_: &Args, _: &State) -> Result<Vec<Statement>, String> {
        Ok(vec![g1().x(1.0).into(), call("Recurse").into()])
    }
}

export_wizard!(Recurse);
