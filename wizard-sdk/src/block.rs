//! A wizard's output, built from typed pieces so no wizard formats G-code.

use crate::__bindings::ger::wizard::types as wit;
use crate::Arg;

/// One statement of a wizard's output.
#[derive(Clone, Debug, PartialEq)]
pub enum Statement {
    /// A block of words, e.g. `G01 X10 F300`.
    Block(Block),
    /// A comment; it may not hold a line break.
    Comment(String),
    /// A call of a wizard.
    Call(Call),
    /// G-code text for ger to parse (several lines allowed).
    Text(String),
}

/// A block of words: `g1().x(10.0).y(5.0).f(300.0)` is `G1 X10 Y5 F300`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Block {
    pub words: Vec<(char, f64)>,
}

macro_rules! axis_words {
    ($($method:ident $letter:literal $doc:literal),* $(,)?) => {
        $(
            #[doc = $doc]
            pub fn $method(self, value: f64) -> Block {
                self.word($letter, value)
            }
        )*
    };
}

impl Block {
    /// Adds any word; the letter may be either case.
    pub fn word(mut self, letter: char, value: f64) -> Block {
        self.words.push((letter.to_ascii_uppercase(), value));
        self
    }

    axis_words! {
        x 'X' "X: target (or X distance in G91).",
        y 'Y' "Y: target.",
        z 'Z' "Z: target.",
        i 'I' "I: an arc's centre, X offset from its start.",
        j 'J' "J: an arc's centre, Y offset from its start.",
        k 'K' "K: an arc's centre, Z offset from its start.",
        r 'R' "R: an arc's radius.",
        f 'F' "F: feed rate.",
        s 'S' "S: spindle speed.",
        p 'P' "P: dwell time, or program number for M98.",
        l 'L' "L: repeat count for M98.",
    }

    /// Sets X and Y together.
    pub fn xy(self, x: f64, y: f64) -> Block {
        self.x(x).y(y)
    }
}

/// G00: rapid move.
pub fn g0() -> Block {
    g(0)
}

/// G01: straight feed move.
pub fn g1() -> Block {
    g(1)
}

/// G02: clockwise arc.
pub fn g2() -> Block {
    g(2)
}

/// G03: counter-clockwise arc.
pub fn g3() -> Block {
    g(3)
}

/// Any G code, e.g. `g(91)`.
pub fn g(code: u32) -> Block {
    Block::default().word('G', f64::from(code))
}

/// Any M code, e.g. `m(3).s(1200.0)`.
pub fn m(code: u32) -> Block {
    Block::default().word('M', f64::from(code))
}

/// A comment.
pub fn comment(text: impl Into<String>) -> Statement {
    Statement::Comment(text.into())
}

/// G-code text for ger to parse, for what is easier written than built.
pub fn text(code: impl Into<String>) -> Statement {
    Statement::Text(code.into())
}

/// A wizard call: `call("Pocket").number(10.0).number(5.0).number(2.0)`.
pub fn call(name: &str) -> Call {
    Call { name: name.to_string(), args: Vec::new() }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Call {
    pub name: String,
    pub args: Vec<Arg>,
}

impl Call {
    pub fn number(mut self, value: f64) -> Call {
        self.args.push(Arg::Number(value));
        self
    }

    pub fn text(mut self, value: &str) -> Call {
        self.args.push(Arg::Text(value.to_string()));
        self
    }
}

impl From<Block> for Statement {
    fn from(block: Block) -> Statement {
        Statement::Block(block)
    }
}

impl From<Call> for Statement {
    fn from(call: Call) -> Statement {
        Statement::Call(call)
    }
}

impl Statement {
    pub(crate) fn into_wit(self) -> wit::Statement {
        match self {
            Statement::Block(block) => wit::Statement::Words(
                block.words.into_iter().map(|(letter, value)| wit::Word { letter, value }).collect(),
            ),
            Statement::Comment(text) => wit::Statement::Comment(text),
            Statement::Call(call) => wit::Statement::Call(wit::WizardCall {
                name: call.name,
                args: call
                    .args
                    .into_iter()
                    .map(|arg| match arg {
                        Arg::Number(n) => wit::Arg::Number(n),
                        Arg::Text(t) => wit::Arg::Text(t),
                    })
                    .collect(),
            }),
            Statement::Text(text) => wit::Statement::Text(text),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builders_make_words_in_order() {
        assert_eq!(g1().x(10.0).y(5.0).f(300.0).words, [('G', 1.0), ('X', 10.0), ('Y', 5.0), ('F', 300.0)]);
        assert_eq!(m(3).s(1200.0).words, [('M', 3.0), ('S', 1200.0)]);
        assert_eq!(Block::default().word('z', -1.0).words, [('Z', -1.0)]);
        let call: Statement = call("Pocket").number(1.0).text("a").into();
        assert_eq!(
            call,
            Statement::Call(Call { name: "Pocket".into(), args: vec![Arg::Number(1.0), Arg::Text("a".into())] })
        );
    }
}
