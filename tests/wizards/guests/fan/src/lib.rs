//! Hostile when wide and deep: `Fan WIDTH DEPTH` moves to X=DEPTH, then calls
//! `Fan WIDTH DEPTH-1` WIDTH times, down to 0: WIDTH^DEPTH calls in all.
use ger_wizard_sdk::*;

struct Fan;

impl Wizard for Fan {
    fn describe() -> Description {
        Description::new("Fan", "calls itself WIDTH times a level", "Fan WIDTH DEPTH")
            .param("WIDTH", "calls a level")
            .param("DEPTH", "levels below this one")
    }

    fn expand(args: &Args, _: &State) -> Result<Vec<Statement>, String> {
        let (width, depth) = (args.whole(0, 0)?, args.whole(1, 0)?);
        let mut out = vec![g1().x(f64::from(depth)).into()];
        if depth > 0 {
            for _ in 0..width {
                out.push(call("Fan").number(f64::from(width)).number(f64::from(depth - 1)).into());
            }
        }
        Ok(out)
    }
}

export_wizard!(Fan);
