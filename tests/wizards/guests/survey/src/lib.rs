//! `Survey`: asks the host what `ger:wizard@0.2.0` added. It moves to
//! the stock's far corner (X max, Y max, Z min), then to X = the number
//! of tools, Y = the largest tool number, Z = 1 on a millimetre machine
//! and 2 on an inch one; it warns twice, the second time `WARNINGS` - 1
//! more times (`Survey WARNINGS`, default 2).
use ger_wizard_sdk::*;

struct Survey;

impl Wizard for Survey {
    fn describe() -> Description {
        Description::new("Survey", "reports the stock, the tools and the unit", "Survey [WARNINGS]")
            .optional("WARNINGS", "how many warnings to give")
    }

    fn expand(args: &Args, _: &State) -> Result<Vec<Statement>, String> {
        let warnings = args.optional_number(0)?.unwrap_or(2.0) as u32;
        let stock = stock().ok_or("no stock")?;
        let tools = tools();
        let unit = match machine_units() {
            Units::Mm => 1.0,
            Units::Inch => 2.0,
        };
        for n in 1..=warnings {
            warn(&format!("warning {n}"));
        }
        let largest = tools.iter().map(|t| t.number).max().unwrap_or(0);
        Ok(vec![
            g1().x(stock.max[0]).y(stock.max[1]).z(stock.min[2]).into(),
            g1().x(tools.len() as f64).y(f64::from(largest)).z(unit).into(),
        ])
    }
}

export_wizard!(Survey);
