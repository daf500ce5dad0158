//! `Legacy N`: a wizard built against `ger:wizard@0.1.0` (`wit/0.1.0`). It
//! looks tool N up and moves to X = its diameter, Y = its flute length (0
//! if none), logging as it goes: what any 0.1.0 wizard may still do.
wit_bindgen::generate!({
    path: "../../../../wit/0.1.0",
    world: "ger:wizard/wizard",
});

use ger::wizard::host;
use ger::wizard::types::{Param, Word};

struct Legacy;

impl Guest for Legacy {
    fn describe() -> Description {
        let param = Param { name: "N".into(), description: "a tool number".into(), optional: false };
        Description {
            name: "Legacy".into(),
            summary: "a wizard of ger:wizard@0.1.0".into(),
            usage: "Legacy N".into(),
            params: vec![param],
        }
    }

    fn expand(args: Vec<Arg>, _: MachineState) -> Result<Vec<Statement>, String> {
        let Some(Arg::Number(n)) = args.first() else { return Err("N must be a number".into()) };
        host::log("looking the tool up");
        let tool = host::find_tool(*n as u32).ok_or("no such tool")?;
        let word = |letter, value| Word { letter, value };
        let flutes = tool.flute_length.unwrap_or(0.0);
        Ok(vec![Statement::Words(vec![word('G', 1.0), word('X', tool.diameter), word('Y', flutes)])])
    }
}

export!(Legacy);
