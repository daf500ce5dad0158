//! The interpreter stage of the lenient dialect: parameters and
//! expressions, between the lexer and the parser.
//!
//! The lexer reads `X[#1 + 2]` as an expression word and `#1 = 5` as an
//! assignment; this stage evaluates them against the parameters set so far
//! and hands the parser plain words, so no later stage knows a program had
//! variables. As in LinuxCNC, every read on a line happens before the line's
//! assignments take effect: `#1 = 2 X#1` moves to the old `#1`. An
//! evaluation error drops the line it is on (its assignments too), so one
//! mistake gives one error.

pub mod expr;

use std::collections::HashMap;

use crate::diag::{Diagnostic, Span};
use crate::lex::{Lexed, Token, TokenKind, MAX_NUMBER};
use expr::{Expr, Param, Parameters};

/// Numbered parameters from here on are LinuxCNC's system parameters
/// (work offsets, G28/G30 points, the current position): ger does not
/// compute them, so a program that reads or sets one is refused there.
const FIRST_SYSTEM_PARAMETER: u32 = 5000;

/// The parameters a program has set.
#[derive(Default)]
pub struct Store {
    numbered: HashMap<u32, f64>,
    named: HashMap<String, f64>,
}

impl Parameters for Store {
    fn numbered(&self, number: u32, at: Span) -> Result<f64, Diagnostic> {
        system_parameter(number, at)?;
        // An unset numbered parameter reads as 0, as in LinuxCNC.
        Ok(self.numbered.get(&number).copied().unwrap_or(0.0))
    }

    fn named(&self, name: &str) -> Option<f64> {
        self.named.get(name).copied()
    }
}

fn system_parameter(number: u32, at: Span) -> Result<(), Diagnostic> {
    if number < FIRST_SYSTEM_PARAMETER {
        return Ok(());
    }
    Err(Diagnostic::error(at, format!("#{number} is one of LinuxCNC's system parameters, which ger does not compute"))
        .with_help(format!("ger's parameters are #1 to #{}, and named ones", FIRST_SYSTEM_PARAMETER - 1)))
}

/// Where an assignment goes, worked out when the line is read.
enum Target {
    Numbered(u32),
    Named(String),
}

/// Runs over the lexer's tokens a line at a time, turning expression words
/// into words and carrying out assignments at each line's end. A line is
/// held until it ends, so a line with an error gives the parser nothing of it.
pub struct Interpreter<L> {
    tokens: L,
    store: Store,
    /// The current line's assignments, made at its end.
    pending: Vec<(Target, f64)>,
    /// The current line: its tokens and the lexer's diagnostics.
    line: Vec<Lexed>,
    /// The current line's first error: the line is dropped.
    error: Option<Diagnostic>,
    out: std::collections::VecDeque<Lexed>,
}

impl<L: Iterator<Item = Lexed>> Interpreter<L> {
    pub fn new(tokens: L) -> Interpreter<L> {
        Interpreter {
            tokens,
            store: Store::default(),
            pending: Vec::new(),
            line: Vec::new(),
            error: None,
            out: Default::default(),
        }
    }

    fn evaluate(&self, expr: &Expr, span: Span) -> Result<f64, Diagnostic> {
        let value = expr.eval(&self.store)?;
        if value.abs() > MAX_NUMBER {
            let message = format!("this works out to {value:.0}: ger reads numbers up to 10^12");
            return Err(Diagnostic::error(span, message));
        }
        Ok(value)
    }

    fn assignment(&self, target: &Param, value: &Expr, span: Span) -> Result<(Target, f64), Diagnostic> {
        let target = match target {
            Param::Numbered(index) => {
                let number = expr::number(index, &self.store, span)?;
                system_parameter(number, span)?;
                Target::Numbered(number)
            }
            Param::Named(name) => Target::Named(name.clone()),
        };
        Ok((target, self.evaluate(value, span)?))
    }

    /// Hands out the line read, and makes its assignments; `end` is the
    /// line's end, which a comment never closed does not have.
    fn end_of_line(&mut self, end: Option<Token>) {
        let line = std::mem::take(&mut self.line);
        match self.error.take() {
            Some(error) => {
                self.pending.clear();
                self.out.extend(line.into_iter().filter(|lexed| matches!(lexed, Lexed::Diagnostic(_))));
                self.out.push_back(Lexed::Diagnostic(error));
            }
            None => {
                self.out.extend(line);
                for (target, value) in self.pending.drain(..) {
                    match target {
                        Target::Numbered(number) => self.store.numbered.insert(number, value),
                        Target::Named(name) => self.store.named.insert(name, value),
                    };
                }
            }
        }
        self.out.extend(end.map(Lexed::Token));
    }

    fn token(&mut self, token: Token) {
        let span = token.span;
        if self.error.is_some() && token.kind != TokenKind::End {
            return;
        }
        let result = match token.kind {
            TokenKind::End if span.len == 0 => return self.end_of_line(Some(token)),
            TokenKind::Expression { letter, value } => {
                self.evaluate(&value, span).map(|value| Some(Token { kind: TokenKind::Word { letter, value }, span }))
            }
            TokenKind::Assign { target, value } => self.assignment(&target, &value, span).map(|assignment| {
                self.pending.push(assignment);
                None
            }),
            kind => Ok(Some(Token { kind, span })),
        };
        match result {
            Ok(token) => self.line.extend(token.map(Lexed::Token)),
            Err(diagnostic) => self.error = Some(diagnostic),
        }
    }
}

impl<L: Iterator<Item = Lexed>> Iterator for Interpreter<L> {
    type Item = Lexed;

    fn next(&mut self) -> Option<Lexed> {
        loop {
            if let Some(lexed) = self.out.pop_front() {
                return Some(lexed);
            }
            match self.tokens.next() {
                Some(Lexed::Token(token)) => self.token(token),
                Some(diagnostic) => self.line.push(diagnostic),
                None if self.line.is_empty() && self.error.is_none() => return None,
                None => self.end_of_line(None),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::config::Config;
    use crate::passes::testing::run_with;
    use crate::statement::{Dialect, Units};

    /// The program after pass 04, in millimetres, in the lenient dialect.
    fn flat(text: &str) -> Vec<String> {
        let config = Config { dialect: Dialect::Lenient.into(), units: Units::Mm, ..Config::default() };
        run_with(&format!("G21\n{text}"), &config, 4).into_iter().filter(|line| !line.contains("G21")).collect()
    }

    #[test]
    fn words_take_expressions_and_parameters() {
        // Values worked out by hand: 10*cos(60°) = 5, atan2(1, -1) = 135°.
        assert_eq!(
            flat("#1 = 2\n#<depth> = -1.5\nG01 X[#1 + 10*COS[60]] Y[ATAN[1]/[-1]] Z#<depth> F[#1*100]"),
            ["G01 X7.000 Y135.000 Z-1.500 F200.000"]
        );
        // A sign before a parameter, a function as a word's value, indirection.
        assert_eq!(
            flat("#3 = 4\n#4 = 7\n#5 = 3\nG01 X-#3 YSQRT[16] Z#[#5 + 1] F10"),
            ["G01 X-4.000 Y4.000 Z7.000 F10.000"]
        );
        // Fanuc's unbracketed value; a name read without spaces, in lower case.
        assert_eq!(flat("#<Feed Rate> = 100 + 20\nG01 X1 F#<feedrate>"), ["G01 X1.000 F120.000"]);
    }

    #[test]
    fn reads_on_a_line_come_before_its_assignments() {
        // rs274 moves this to X0: `#1 = 2` takes effect at the end of the line.
        assert_eq!(flat("#1 = 2 #2 = #1 G01 X#1 F10\nG01 Y#1 Z#2"), ["G01 X0.000 F10.000", "G01 Y2.000 Z0.000"]);
    }

    #[test]
    fn an_unset_numbered_parameter_is_zero_and_an_unset_name_an_error() {
        assert_eq!(flat("G01 X#7 Y1 F10"), ["G01 X0.000 Y1.000 F10.000"]);
        assert_eq!(
            flat("G01 X#<nothing> F10\nG01 Y2 F10"),
            ["2:6: error: the parameter #<nothing> is not set", "G01 Y2.000 F10.000"]
        );
        assert_eq!(flat("#<_done> = 1\nG01 X[EXISTS[#<_done>] + EXISTS[#<other>]] F10"), ["G01 X1.000 F10.000"]);
    }

    #[test]
    fn evaluation_errors_are_at_their_column_and_drop_the_line() {
        let cases = [
            ("G01 X[1/0] F10", "2:8: error: division by zero"),
            ("G01 X[SQRT[-1]] F10", "2:7: error: SQRT of a negative number"),
            ("G01 X[ACOS[2]] F10", "2:7: error: ACOS takes a number from -1 to 1"),
            ("G01 X[LN[0]] F10", "2:7: error: LN takes a number above zero"),
            ("G01 X[[-2] ** 0.5] F10", "2:12: error: a negative number raised to a fractional power"),
            ("G01 X[1 MOD 0] F10", "2:9: error: division by zero"),
            (
                "G01 X[10 ** 20] F10",
                "2:5: error: this works out to 100000000000000000000: ger reads numbers up to 10^12",
            ),
            ("#5221 = 1", "2:1: error: #5221 is one of LinuxCNC's system parameters, which ger does not compute"),
            ("G01 X#0", "2:6: error: there is no parameter #0: they are #1 to #5602"),
            ("G01 X#1.5", "2:6: error: a parameter's number must be whole, not 1.5"),
            ("G01 X[1 + ] F10", "2:11: error: expected a value: a number, a parameter, `[expression]` or a function"),
            ("G01 X[1 + 2 F10", "2:13: error: expected `]` to close the `[`"),
            ("G01 X[FOO[1]] F10", "2:7: error: `FOO` is not a function"),
            ("#1 X2", "2:1: error: a parameter here is set: write `#1 = value`"),
        ];
        for (line, error) in cases {
            let got = flat(&format!("{line}\nG01 Y2 F10"));
            assert_eq!(got[0], error, "{line}");
            assert_eq!(got[1..], ["G01 Y2.000 F10.000"], "{line}");
        }
    }

    #[test]
    fn the_strict_dialect_refuses_parameters_with_a_hint() {
        let got = run_with("#1 = 2", &Config::default(), 4);
        assert_eq!(got, ["1:1: error: parameters (`#1`, `#<name>`) are not supported: ger has no variables"]);
        let Some(crate::lex::Lexed::Diagnostic(diagnostic)) = crate::lex::lex_str("#1 = 2").next() else {
            panic!("the strict lexer read a parameter")
        };
        assert!(diagnostic.help.unwrap().contains("--lenient"));
    }
}
