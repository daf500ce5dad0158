//! Hostile: returns what only a subprogram may hold. `Rewind 0` returns a
//! move, M99 and another move; `Rewind 1` defines O100 and calls it.
use ger_wizard_sdk::*;

struct Rewind;

impl Wizard for Rewind {
    fn describe() -> Description {
        Description::new("Rewind", "returns M99 or O", "Rewind KIND").param("KIND", "0 M99, 1 O100 ... M99")
    }

    fn expand(args: &Args, _: &State) -> Result<Vec<Statement>, String> {
        match args.whole(0, 0)? {
            0 => Ok(vec![text("G01 X1\nM99\nG01 X2")]),
            _ => Ok(vec![text("O100\nG01 X3\nM99\nM98 P100")]),
        }
    }
}

export_wizard!(Rewind);
