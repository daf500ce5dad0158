//! `Echo`: fails with the state it was given, so tests can read it, and
//! with what the host's `find-tool` says of tool 2.
use ger_wizard_sdk::*;

struct Echo;

impl Wizard for Echo {
    fn describe() -> Description {
        Description::new("Echo", "reports the state it sees, as an error", "Echo")
    }

    fn expand(_: &Args, state: &State) -> Result<Vec<Statement>, String> {
        log("echoing");
        Err(format!("{state:?}; find_tool(2) = {:?}; find_tool(9) = {:?}", tool(2), tool(9)))
    }
}

export_wizard!(Echo);
