//! A call's arguments, with errors that name the parameter and show the usage.

use crate::__bindings::ger::wizard::types as wit;
use crate::Description;

/// One argument as written in the call: `75` or `"deep"`.
#[derive(Clone, Debug, PartialEq)]
pub enum Arg {
    Number(f64),
    Text(String),
}

impl From<wit::Arg> for Arg {
    fn from(arg: wit::Arg) -> Arg {
        match arg {
            wit::Arg::Number(n) => Arg::Number(n),
            wit::Arg::Text(t) => Arg::Text(t),
        }
    }
}

/// The arguments of one call. Parameter `i` (from 0) is named after the
/// wizard's [`Description`], so `args.positive(2)` on `Pocket 75 30 -1`
/// fails with "DEPTH (argument 3) must be greater than 0, not -1".
#[derive(Clone, Debug)]
pub struct Args {
    args: Vec<Arg>,
    names: Vec<String>,
    usage: String,
}

impl Args {
    /// Checks the count against the description's parameters: at least the
    /// required ones, at most all of them.
    pub(crate) fn new(args: Vec<Arg>, description: &Description) -> Args {
        Args {
            args,
            names: description.params.iter().map(|p| p.name.clone()).collect(),
            usage: description.usage.clone(),
        }
    }

    /// Arguments given directly, for testing a wizard natively.
    pub fn for_test(args: Vec<Arg>, description: &Description) -> Args {
        Args::new(args, description)
    }

    /// Fails unless the count fits the description: at least its required
    /// parameters, at most all of them.
    pub fn check_count(&self, description: &Description) -> Result<(), String> {
        let required = description.params.iter().filter(|p| !p.optional).count();
        let total = description.params.len();
        let n = self.args.len();
        if (required..=total).contains(&n) {
            return Ok(());
        }
        let expected = match (required, total) {
            (r, t) if r == t => format!("{r} argument{}", if r == 1 { "" } else { "s" }),
            (r, t) => format!("{r} to {t} arguments"),
        };
        Err(format!("{} takes {expected}, not {n} (usage: {})", description.name, self.usage))
    }

    pub fn len(&self) -> usize {
        self.args.len()
    }

    pub fn is_empty(&self) -> bool {
        self.args.is_empty()
    }

    pub fn get(&self, i: usize) -> Option<&Arg> {
        self.args.get(i)
    }

    /// "DEPTH (argument 3)", or "argument 3" for an unnamed parameter.
    fn what(&self, i: usize) -> String {
        match self.names.get(i) {
            Some(name) => format!("{name} (argument {})", i + 1),
            None => format!("argument {}", i + 1),
        }
    }

    /// A number that may be left out.
    pub fn optional_number(&self, i: usize) -> Result<Option<f64>, String> {
        match self.args.get(i) {
            None => Ok(None),
            Some(Arg::Number(n)) => Ok(Some(*n)),
            Some(Arg::Text(t)) => Err(format!("{} must be a number, not the text \"{t}\"", self.what(i))),
        }
    }

    /// A number that must be there.
    pub fn number(&self, i: usize) -> Result<f64, String> {
        self.optional_number(i)?.ok_or_else(|| format!("{} is missing (usage: {})", self.what(i), self.usage))
    }

    /// A number greater than zero, if given.
    pub fn optional_positive(&self, i: usize) -> Result<Option<f64>, String> {
        match self.optional_number(i)? {
            Some(n) if n <= 0.0 => Err(format!("{} must be greater than 0, not {n}", self.what(i))),
            other => Ok(other),
        }
    }

    /// A number of zero or more, if given: a radius or an allowance.
    pub fn optional_non_negative(&self, i: usize) -> Result<Option<f64>, String> {
        match self.optional_number(i)? {
            Some(n) if n < 0.0 => Err(format!("{} must not be negative, not {n}", self.what(i))),
            other => Ok(other),
        }
    }

    /// A number greater than zero.
    pub fn positive(&self, i: usize) -> Result<f64, String> {
        self.number(i)?;
        Ok(self.optional_positive(i)?.expect("checked present"))
    }

    /// A whole number of at least `min`, e.g. a count of holes.
    pub fn whole(&self, i: usize, min: u32) -> Result<u32, String> {
        let n = self.number(i)?;
        if n.fract() != 0.0 || n < f64::from(min) || n > f64::from(u32::MAX) {
            return Err(format!("{} must be a whole number of at least {min}, not {n}", self.what(i)));
        }
        Ok(n as u32)
    }

    /// Which of `choices` argument `i` names, as its index; the first when
    /// it is left out. Anything else is an error that lists them.
    pub fn choice(&self, i: usize, choices: &[&str]) -> Result<usize, String> {
        if self.args.get(i).is_none() {
            return Ok(0);
        }
        let given = self.text(i)?;
        choices.iter().position(|c| *c == given).ok_or_else(|| {
            let quoted: Vec<String> = choices.iter().map(|c| format!("\"{c}\"")).collect();
            let list = match quoted.split_last() {
                Some((last, [])) => last.clone(),
                Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
                None => String::new(),
            };
            format!("{} is {list}, not \"{given}\"", self.what(i))
        })
    }

    /// A text argument (written in double quotes).
    pub fn text(&self, i: usize) -> Result<&str, String> {
        match self.args.get(i) {
            Some(Arg::Text(t)) => Ok(t),
            Some(Arg::Number(n)) => {
                Err(format!("{} must be a text in double quotes, not the number {n}", self.what(i)))
            }
            None => Err(format!("{} is missing (usage: {})", self.what(i), self.usage)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pocket(args: Vec<Arg>) -> (Args, Description) {
        let d = Description::new("Pocket", "clears a pocket", "Pocket LENGTH WIDTH DEPTH [STEPDOWN]")
            .param("LENGTH", "")
            .param("WIDTH", "")
            .param("DEPTH", "")
            .optional("STEPDOWN", "");
        (Args::for_test(args, &d), d)
    }

    #[test]
    fn errors_name_the_parameter() {
        let (a, _) = pocket(vec![Arg::Number(75.0), Arg::Text("wide".into()), Arg::Number(-1.0)]);
        assert_eq!(a.positive(0), Ok(75.0));
        assert_eq!(a.number(1), Err("WIDTH (argument 2) must be a number, not the text \"wide\"".into()));
        assert_eq!(a.positive(2), Err("DEPTH (argument 3) must be greater than 0, not -1".into()));
        assert_eq!(a.optional_positive(3), Ok(None));
        assert_eq!(
            a.number(3),
            Err("STEPDOWN (argument 4) is missing (usage: Pocket LENGTH WIDTH DEPTH [STEPDOWN])".into())
        );
        assert_eq!(a.text(0), Err("LENGTH (argument 1) must be a text in double quotes, not the number 75".into()));
        assert_eq!(a.whole(0, 1), Ok(75));
        assert!(a.whole(2, 1).unwrap_err().contains("whole number of at least 1"));
    }

    #[test]
    fn a_choice_is_one_of_its_words_or_the_first_when_left_out() {
        let d = Description::new("Profile", "", "Profile DEPTH [SIDE]").param("DEPTH", "").optional("SIDE", "");
        let sides = ["outside", "inside", "on"];
        assert_eq!(Args::for_test(vec![Arg::Number(1.0)], &d).choice(1, &sides), Ok(0));
        let inside = Args::for_test(vec![Arg::Number(1.0), Arg::Text("inside".into())], &d);
        assert_eq!(inside.choice(1, &sides), Ok(1));
        let round = Args::for_test(vec![Arg::Number(1.0), Arg::Text("round".into())], &d);
        assert_eq!(
            round.choice(1, &sides),
            Err("SIDE (argument 2) is \"outside\", \"inside\" or \"on\", not \"round\"".into())
        );
        let number = Args::for_test(vec![Arg::Number(1.0), Arg::Number(2.0)], &d);
        assert!(number.choice(1, &sides).unwrap_err().contains("must be a text in double quotes"));
    }

    #[test]
    fn counts_are_checked_against_the_description() {
        let (a, d) = pocket(vec![Arg::Number(1.0); 5]);
        assert_eq!(
            a.check_count(&d),
            Err("Pocket takes 3 to 4 arguments, not 5 (usage: Pocket LENGTH WIDTH DEPTH [STEPDOWN])".into())
        );
        let (a, d) = pocket(vec![Arg::Number(1.0); 3]);
        assert_eq!(a.check_count(&d), Ok(()));
    }
}
