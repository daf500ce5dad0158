//! `Nest N`: moves to X=N, then calls `Nest N-1`, down to 0: N+1 levels.
use ger_wizard_sdk::*;

struct Nest;

impl Wizard for Nest {
    fn describe() -> Description {
        Description::new("Nest", "calls itself N times", "Nest N").param("N", "levels below this one")
    }

    fn expand(args: &Args, _: &State) -> Result<Vec<Statement>, String> {
        let n = args.whole(0, 0)?;
        let mut out = vec![g1().x(f64::from(n)).into()];
        if n > 0 {
            out.push(call("Nest").number(f64::from(n - 1)).into());
        }
        Ok(out)
    }
}

export_wizard!(Nest);
