//! Hostile: says too much. `Rant 0` fails with a 10 MiB message, `Rant 1`
//! calls a wizard whose name is 9 MiB of letters (a line longer than the
//! lexer reads), `Rant 2` one whose name is 100,000 letters (a line it reads).
use ger_wizard_sdk::*;

struct Rant;

impl Wizard for Rant {
    fn describe() -> Description {
        Description::new("Rant", "says too much", "Rant KIND").param("KIND", "0 message, 1 and 2 call names")
    }

    fn expand(args: &Args, _: &State) -> Result<Vec<Statement>, String> {
        match args.whole(0, 0)? {
            0 => Err("no".repeat(5 << 20)),
            1 => Ok(vec![call(&"Yes".repeat(3 << 20)).into()]),
            _ => Ok(vec![call(&"Yes".repeat(100_000 / 3)).into()]),
        }
    }
}

export_wizard!(Rant);
