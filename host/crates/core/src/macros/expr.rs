//! Expressions and parameters as LinuxCNC reads them: `[1 + #2 * COS[30]]`,
//! `#<name>`, `#[#1 + 1]`. Parsing happens in the lexer (it knows where a
//! word's value ends); evaluation in the interpreter stage, against the
//! parameters set so far. Every way an evaluation can go wrong (a division
//! by zero, `SQRT` of a negative, an undefined name) is a diagnostic at the
//! part of the expression that did it, never a NaN or infinity.

use crate::diag::{Diagnostic, Span};

#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    Number(f64),
    Param(Box<Param>, Span),
    Negate(Box<Expr>),
    Call(Function, Box<Expr>, Span),
    /// `ATAN[y]/[x]`, in degrees.
    Atan(Box<Expr>, Box<Expr>, Span),
    /// `EXISTS[#<name>]`: 1 if the named parameter is set; `EXISTS[#n]`:
    /// 1 if there is a parameter n.
    Exists(Box<Param>),
    Binary(Op, Box<Expr>, Box<Expr>, Span),
}

/// A parameter as written: `#5`, `#[#1 + 1]`, `##2` (numbered, by an
/// expression) or `#<name>` (names are read without spaces, in lower case).
#[derive(Clone, Debug, PartialEq)]
pub enum Param {
    Numbered(Expr),
    Named(String),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    Abs,
    Acos,
    Asin,
    Cos,
    Exp,
    Fix,
    Fup,
    Ln,
    Round,
    Sin,
    Sqrt,
    Tan,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Power,
    Times,
    Divide,
    Modulo,
    Plus,
    Minus,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl Op {
    /// LinuxCNC's precedence: `**` binds tightest, then `* / MOD`, `+ -`,
    /// the comparisons, and `AND OR XOR` loosest; equal ones go left to right.
    fn precedence(self) -> u8 {
        match self {
            Op::Power => 4,
            Op::Times | Op::Divide | Op::Modulo => 3,
            Op::Plus | Op::Minus => 2,
            Op::Eq | Op::Ne | Op::Gt | Op::Ge | Op::Lt | Op::Le => 1,
            Op::And | Op::Or | Op::Xor => 0,
        }
    }

    pub const ALL: [(&'static str, Op); 15] = [
        ("**", Op::Power),
        ("*", Op::Times),
        ("/", Op::Divide),
        ("MOD", Op::Modulo),
        ("+", Op::Plus),
        ("-", Op::Minus),
        ("EQ", Op::Eq),
        ("NE", Op::Ne),
        ("GT", Op::Gt),
        ("GE", Op::Ge),
        ("LT", Op::Lt),
        ("LE", Op::Le),
        ("AND", Op::And),
        ("OR", Op::Or),
        ("XOR", Op::Xor),
    ];
}

const FUNCTIONS: [(&str, Function); 12] = [
    ("ABS", Function::Abs),
    ("ACOS", Function::Acos),
    ("ASIN", Function::Asin),
    ("COS", Function::Cos),
    ("EXP", Function::Exp),
    ("FIX", Function::Fix),
    ("FUP", Function::Fup),
    ("LN", Function::Ln),
    ("ROUND", Function::Round),
    ("SIN", Function::Sin),
    ("SQRT", Function::Sqrt),
    ("TAN", Function::Tan),
];

/// Whether `name` is one of the expression functions, which the lenient
/// dialect reads as keywords rather than wizard names.
pub fn is_function(name: &str) -> bool {
    let upper = name.to_ascii_uppercase();
    upper == "ATAN" || upper == "EXISTS" || FUNCTIONS.iter().any(|(known, _)| *known == upper)
}

/// Reads expressions from one line of text; positions are byte offsets in it.
pub struct Reader<'a> {
    text: &'a str,
    pub pos: usize,
    line: u32,
}

type Parsed<T> = Result<T, Diagnostic>;

impl<'a> Reader<'a> {
    pub fn new(text: &'a str, pos: usize, line: u32) -> Reader<'a> {
        Reader { text, pos, line }
    }

    fn span(&self, start: usize) -> Span {
        Span::new(self.line, start as u32 + 1, (self.pos - start).max(1) as u32)
    }

    fn skip_space(&mut self) {
        self.pos += self.text[self.pos..].len() - self.text[self.pos..].trim_start().len();
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip_space();
        self.text.as_bytes().get(self.pos).copied()
    }

    fn error(&self, start: usize, message: impl Into<String>) -> Diagnostic {
        Diagnostic::error(self.span(start), message.into())
    }

    fn expect(&mut self, byte: u8, what: &str) -> Parsed<()> {
        if self.peek() == Some(byte) {
            self.pos += 1;
            Ok(())
        } else {
            let start = self.pos;
            self.pos = (self.pos + 1).min(self.text.len());
            Err(self.error(start, format!("expected `{}` {what}", byte as char)))
        }
    }

    fn letters(&self) -> &'a str {
        let rest = &self.text[self.pos..];
        &rest[..rest.bytes().take_while(u8::is_ascii_alphabetic).count()]
    }

    /// A value as a word takes it (LinuxCNC's "real value"): a number, a
    /// parameter, `[expression]` or a function, with an optional sign.
    pub fn value(&mut self) -> Parsed<Expr> {
        let next = self.peek();
        let start = self.pos;
        match next {
            Some(b'-') => {
                self.pos += 1;
                Ok(Expr::Negate(Box::new(self.value()?)))
            }
            Some(b'+') => {
                self.pos += 1;
                self.value()
            }
            Some(b'#') => {
                let param = self.param()?;
                Ok(Expr::Param(Box::new(param), self.span(start)))
            }
            Some(b'[') => self.bracketed(),
            Some(c) if c.is_ascii_digit() || c == b'.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() => self.function(),
            _ => {
                self.pos = (self.pos + 1).min(self.text.len());
                Err(self.error(start, "expected a value: a number, a parameter, `[expression]` or a function"))
            }
        }
    }

    fn number(&mut self) -> Parsed<Expr> {
        let start = self.pos;
        let bytes = self.text.as_bytes();
        let digits = |from: usize| bytes[from..].iter().take_while(|b| b.is_ascii_digit()).count();
        let mut end = start + digits(start);
        if bytes.get(end) == Some(&b'.') {
            end += 1 + digits(end + 1);
        }
        self.pos = end;
        match self.text[start..end].parse::<f64>() {
            Ok(value) => Ok(Expr::Number(value)),
            Err(_) => Err(self.error(start, format!("`{}` is not a number", &self.text[start..end]))),
        }
    }

    /// `#` and what follows it.
    pub fn param(&mut self) -> Parsed<Param> {
        self.expect(b'#', "")?;
        if self.peek() == Some(b'<') {
            let start = self.pos;
            let Some(close) = self.text[start..].find('>') else {
                self.pos = self.text.len();
                return Err(self.error(start, "a parameter name is not closed: `>` is missing"));
            };
            let name: String =
                self.text[start + 1..start + close].chars().filter(|c| !c.is_whitespace()).collect::<String>();
            self.pos = start + close + 1;
            if name.is_empty() {
                return Err(self.error(start, "a parameter name may not be empty"));
            }
            return Ok(Param::Named(name.to_ascii_lowercase()));
        }
        Ok(Param::Numbered(self.value()?))
    }

    pub fn bracketed(&mut self) -> Parsed<Expr> {
        self.expect(b'[', "")?;
        let expr = self.infix()?;
        self.expect(b']', "to close the `[`")?;
        Ok(expr)
    }

    fn function(&mut self) -> Parsed<Expr> {
        let start = self.pos;
        let name = self.letters().to_ascii_uppercase();
        self.pos += name.len();
        let span = self.span(start);
        if name == "ATAN" {
            let y = self.bracketed()?;
            self.expect(b'/', "after ATAN[y]: it is written ATAN[y]/[x]")?;
            let x = self.bracketed()?;
            return Ok(Expr::Atan(Box::new(y), Box::new(x), span));
        }
        if name == "EXISTS" {
            self.expect(b'[', "")?;
            let param = self.param()?;
            self.expect(b']', "to close the `[`")?;
            return Ok(Expr::Exists(Box::new(param)));
        }
        let Some(&(_, function)) = FUNCTIONS.iter().find(|(known, _)| *known == name) else {
            return Err(self
                .error(start, format!("`{name}` is not a function"))
                .with_help("the functions are ABS ACOS ASIN ATAN COS EXISTS EXP FIX FUP LN ROUND SIN SQRT TAN"));
        };
        Ok(Expr::Call(function, Box::new(self.bracketed()?), span))
    }

    /// The operator at the reading position, if any, and its length.
    fn operator(&mut self) -> Option<(Op, usize)> {
        self.peek()?;
        let rest = &self.text[self.pos..];
        let letters = self.letters();
        Op::ALL.iter().find_map(|&(symbol, op)| {
            let matches = if symbol.as_bytes()[0].is_ascii_alphabetic() {
                letters.eq_ignore_ascii_case(symbol)
            } else {
                rest.starts_with(symbol)
            };
            matches.then_some((op, symbol.len()))
        })
    }

    /// Values joined by operators, by precedence climbing.
    pub fn infix(&mut self) -> Parsed<Expr> {
        self.climb(0)
    }

    fn climb(&mut self, min: u8) -> Parsed<Expr> {
        let mut left = self.value()?;
        while let Some((op, len)) = self.operator().filter(|(op, _)| op.precedence() >= min) {
            let start = self.pos;
            self.pos += len;
            let span = self.span(start);
            let right = self.climb(op.precedence() + 1)?;
            left = Expr::Binary(op, Box::new(left), Box::new(right), span);
        }
        Ok(left)
    }
}

/// Where an expression reads its parameters.
pub trait Parameters {
    fn numbered(&self, number: u32, at: Span) -> Result<f64, Diagnostic>;
    fn named(&self, name: &str) -> Option<f64>;
    /// Whether numbered parameter `number` holds a value, Fanuc's "not
    /// vacant": an unset one reads 0, but `#n EQ #0` tells them apart.
    fn is_set(&self, _number: u32) -> bool {
        true
    }
}

/// Fanuc's `#0`: always vacant, read as 0 in arithmetic.
pub const VACANT: u32 = 0;

impl Expr {
    /// Whether this is `#0` as written.
    pub fn is_vacant(&self) -> bool {
        matches!(self, Expr::Param(param, _) if matches!(param.as_ref(), Param::Numbered(Expr::Number(n)) if *n == 0.0))
    }

    /// Fanuc's test of vacancy, `#n EQ #0`: whether a bare parameter read is
    /// vacant; `None` for any other expression, which is a number.
    pub(super) fn vacant(&self, params: &dyn Parameters) -> Result<Option<bool>, Diagnostic> {
        if self.is_vacant() {
            return Ok(Some(true));
        }
        match self {
            Expr::Param(param, span) => match param.as_ref() {
                Param::Numbered(index) => Ok(Some(!params.is_set(number(index, params, *span)?))),
                Param::Named(_) => Ok(None),
            },
            _ => Ok(None),
        }
    }
}

/// LinuxCNC compares for equality within this (its `TOLERANCE_EQUAL`);
/// the other comparisons are exact, as rs274 makes them.
pub const EQUAL_WITHIN: f64 = 0.0001;

/// The largest parameter number: LinuxCNC's last.
pub const LAST_PARAMETER: u32 = 5602;

fn truth(value: bool) -> f64 {
    if value {
        1.0
    } else {
        0.0
    }
}

impl Expr {
    pub fn eval(&self, params: &dyn Parameters) -> Result<f64, Diagnostic> {
        let value = match self {
            Expr::Number(value) => *value,
            Expr::Negate(inner) => -inner.eval(params)?,
            Expr::Param(param, span) => match param.as_ref() {
                Param::Numbered(index) => params.numbered(number(index, params, *span)?, *span)?,
                Param::Named(name) => params.named(name).ok_or_else(|| undefined(name, *span))?,
            },
            Expr::Exists(param) => truth(match param.as_ref() {
                Param::Named(name) => params.named(name).is_some(),
                // As rs274: the number is read as any expression is (its errors are errors,
                // `EXISTS[###2]` with #2 = 99999 among them), and one that names no parameter is none.
                Param::Numbered(index) => whole_number(index.eval(params)?, Span::default()).is_ok(),
            }),
            Expr::Call(function, argument, span) => call(*function, argument.eval(params)?, *span)?,
            Expr::Atan(y, x, _) => y.eval(params)?.atan2(x.eval(params)?).to_degrees(),
            // Fanuc: vacant equals vacant only (not 0), so `#24 EQ #0` asks whether X was given.
            Expr::Binary(op @ (Op::Eq | Op::Ne), left, right, _) if left.is_vacant() || right.is_vacant() => {
                let (left, right) = (left.vacant(params)?, right.vacant(params)?);
                truth((left == right) == (*op == Op::Eq))
            }
            Expr::Binary(op, left, right, span) => binary(*op, left.eval(params)?, right.eval(params)?, *span)?,
        };
        Ok(value)
    }

    /// Where the expression is, as well as its parts tell.
    fn span(&self) -> Option<Span> {
        match self {
            Expr::Param(_, span) | Expr::Call(_, _, span) | Expr::Atan(_, _, span) => Some(*span),
            Expr::Binary(_, left, right, span) => Some(match (left.span(), right.span()) {
                (Some(left), Some(right)) => left.to(right),
                _ => *span,
            }),
            Expr::Negate(inner) => inner.span(),
            Expr::Number(_) | Expr::Exists(_) => None,
        }
    }
}

/// A parameter's number: the value of `index`, which must be whole.
pub fn number(index: &Expr, params: &dyn Parameters, at: Span) -> Result<u32, Diagnostic> {
    // Most are written as numbers (`#3`): those need no rounding.
    if let Expr::Number(value) = index {
        let whole = *value as u32;
        if f64::from(whole) == *value && whole <= LAST_PARAMETER {
            return Ok(whole);
        }
    }
    whole_number(index.eval(params)?, index.span().unwrap_or(at))
}

/// `value` as a parameter's number, which must be whole and one of LinuxCNC's
/// (or Fanuc's #0).
fn whole_number(value: f64, at: Span) -> Result<u32, Diagnostic> {
    let whole = value.round();
    if (value - whole).abs() > EQUAL_WITHIN {
        return Err(Diagnostic::error(at, format!("a parameter's number must be whole, not {value}")));
    }
    if !(0.0..=f64::from(LAST_PARAMETER)).contains(&whole) {
        return Err(Diagnostic::error(at, format!("there is no parameter #{whole}: they are #1 to #{LAST_PARAMETER}")));
    }
    Ok(whole as u32)
}

fn undefined(name: &str, at: Span) -> Diagnostic {
    Diagnostic::error(at, format!("the parameter #<{name}> is not set"))
        .with_help("set it first (`#<name> = value`): LinuxCNC refuses to read a named parameter never set")
}

fn call(function: Function, x: f64, at: Span) -> Result<f64, Diagnostic> {
    let domain = |ok: bool, message: &str| if ok { Ok(()) } else { Err(Diagnostic::error(at, message.to_string())) };
    let value = match function {
        Function::Abs => x.abs(),
        Function::Acos => {
            domain((-1.0..=1.0).contains(&x), "ACOS takes a number from -1 to 1")?;
            x.acos().to_degrees()
        }
        Function::Asin => {
            domain((-1.0..=1.0).contains(&x), "ASIN takes a number from -1 to 1")?;
            x.asin().to_degrees()
        }
        Function::Cos => x.to_radians().cos(),
        Function::Exp => x.exp(),
        Function::Fix => x.floor(),
        Function::Fup => x.ceil(),
        Function::Ln => {
            domain(x > 0.0, "LN takes a number above zero")?;
            x.ln()
        }
        // Half away from zero, as LinuxCNC rounds.
        Function::Round => x.round(),
        Function::Sin => x.to_radians().sin(),
        Function::Sqrt => {
            domain(x >= 0.0, "SQRT of a negative number")?;
            x.sqrt()
        }
        Function::Tan => x.to_radians().tan(),
    };
    finite(value, at)
}

fn binary(op: Op, left: f64, right: f64, at: Span) -> Result<f64, Diagnostic> {
    let value = match op {
        Op::Power if left < 0.0 && right.fract() != 0.0 => {
            return Err(Diagnostic::error(at, "a negative number raised to a fractional power"))
        }
        Op::Power => left.powf(right),
        Op::Times => left * right,
        Op::Divide | Op::Modulo if right == 0.0 => return Err(Diagnostic::error(at, "division by zero")),
        Op::Divide => left / right,
        // The remainder is never negative, as in LinuxCNC.
        Op::Modulo => {
            let remainder = left % right;
            if remainder < 0.0 {
                remainder + right.abs()
            } else {
                remainder
            }
        }
        Op::Plus => left + right,
        Op::Minus => left - right,
        Op::Eq => truth((left - right).abs() < EQUAL_WITHIN),
        Op::Ne => truth((left - right).abs() >= EQUAL_WITHIN),
        Op::Gt => truth(left > right),
        Op::Ge => truth(left >= right),
        Op::Lt => truth(left < right),
        Op::Le => truth(left <= right),
        Op::And => truth(left != 0.0 && right != 0.0),
        Op::Or => truth(left != 0.0 || right != 0.0),
        Op::Xor => truth((left != 0.0) != (right != 0.0)),
    };
    finite(value, at)
}

fn finite(value: f64, at: Span) -> Result<f64, Diagnostic> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Diagnostic::error(at, "this works out to a number too large to write"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tree the test builds, prints and evaluates on its own terms.
    #[derive(Debug)]
    enum Tree {
        Leaf(f64),
        /// `#1` to `#3`, which hold 2, -3 and 0.5.
        Param(u32),
        Neg(Box<Tree>),
        Func(&'static str, Box<Tree>),
        Atan(Box<Tree>, Box<Tree>),
        Bin(&'static str, Box<Tree>, Box<Tree>),
    }

    const PARAMS: [f64; 3] = [2.0, -3.0, 0.5];

    /// The operators and how tightly each binds, as LinuxCNC's manual lists them.
    const OPERATORS: [(&str, u8); 15] = [
        ("**", 4),
        ("*", 3),
        ("/", 3),
        ("MOD", 3),
        ("+", 2),
        ("-", 2),
        ("EQ", 1),
        ("NE", 1),
        ("GT", 1),
        ("GE", 1),
        ("LT", 1),
        ("LE", 1),
        ("AND", 0),
        ("OR", 0),
        ("XOR", 0),
    ];
    const FUNCS: [&str; 12] = ["ABS", "ACOS", "ASIN", "COS", "EXP", "FIX", "FUP", "LN", "ROUND", "SIN", "SQRT", "TAN"];

    /// xorshift64: reproducible without a dependency.
    struct Random(u64);
    impl Random {
        fn below(&mut self, n: u64) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0 % n
        }
    }

    fn tree(random: &mut Random, depth: u32) -> Tree {
        match if depth == 0 { random.below(2) } else { random.below(7) } {
            0 => Tree::Leaf(random.below(40) as f64 / 4.0),
            1 => Tree::Param(1 + random.below(3) as u32),
            2 => Tree::Neg(Box::new(tree(random, depth - 1))),
            3 => Tree::Func(FUNCS[random.below(12) as usize], Box::new(tree(random, depth - 1))),
            4 => Tree::Atan(Box::new(tree(random, depth - 1)), Box::new(tree(random, depth - 1))),
            _ => {
                let (op, _) = OPERATORS[random.below(15) as usize];
                Tree::Bin(op, Box::new(tree(random, depth - 1)), Box::new(tree(random, depth - 1)))
            }
        }
    }

    fn binding(op: &str) -> u8 {
        OPERATORS.iter().find(|(known, _)| *known == op).unwrap().1
    }

    /// Prints with only the brackets precedence and left-to-right order need,
    /// so the parser's precedence is what is tested.
    fn print(tree: &Tree) -> String {
        match tree {
            Tree::Leaf(value) => format!("{value}"),
            Tree::Param(n) => format!("#{n}"),
            Tree::Neg(inner) => format!("-{}", operand(inner)),
            Tree::Func(name, inner) => format!("{name}[{}]", print(inner)),
            Tree::Atan(y, x) => format!("ATAN[{}]/[{}]", print(y), print(x)),
            Tree::Bin(op, left, right) => {
                let side = |tree: &Tree, tighter: bool| match tree {
                    Tree::Bin(inner, ..)
                        if binding(inner) < binding(op) || (tighter && binding(inner) == binding(op)) =>
                    {
                        format!("[{}]", print(tree))
                    }
                    _ => print(tree),
                };
                format!("{} {op} {}", side(left, false), side(right, true))
            }
        }
    }

    /// A sign applies to a value alone: anything bigger is bracketed.
    fn operand(tree: &Tree) -> String {
        match tree {
            Tree::Bin(..) => format!("[{}]", print(tree)),
            _ => print(tree),
        }
    }

    /// The reference: `None` where LinuxCNC reports an error.
    fn reference(tree: &Tree) -> Option<f64> {
        let degrees = std::f64::consts::PI / 180.0;
        let value = match tree {
            Tree::Leaf(value) => *value,
            Tree::Param(n) => PARAMS[*n as usize - 1],
            Tree::Neg(inner) => -reference(inner)?,
            Tree::Atan(y, x) => reference(y)?.atan2(reference(x)?) / degrees,
            Tree::Func(name, inner) => {
                let x = reference(inner)?;
                match *name {
                    "ABS" => x.abs(),
                    "ACOS" if x.abs() <= 1.0 => x.acos() / degrees,
                    "ASIN" if x.abs() <= 1.0 => x.asin() / degrees,
                    "COS" => (x * degrees).cos(),
                    "SIN" => (x * degrees).sin(),
                    "TAN" => (x * degrees).tan(),
                    "EXP" => x.exp(),
                    "FIX" => x.floor(),
                    "FUP" => x.ceil(),
                    "LN" if x > 0.0 => x.ln(),
                    "ROUND" => x.signum() * (x.abs() + 0.5).floor(),
                    "SQRT" if x >= 0.0 => x.sqrt(),
                    _ => return None,
                }
            }
            Tree::Bin(op, left, right) => {
                let (a, b) = (reference(left)?, reference(right)?);
                let yes = |condition: bool| f64::from(u8::from(condition));
                match *op {
                    "**" if a < 0.0 && b != b.trunc() => return None,
                    "**" => a.powf(b),
                    "*" => a * b,
                    "/" | "MOD" if b == 0.0 => return None,
                    "/" => a / b,
                    // C's fmod, then made positive: a zero remainder of a
                    // negative number stays -0, which ATAN tells from 0.
                    "MOD" => match a.signum() * (a.abs() % b.abs()) {
                        negative if negative < 0.0 => negative + b.abs(),
                        remainder => remainder,
                    },
                    "+" => a + b,
                    "-" => a - b,
                    "EQ" => yes((a - b).abs() < 1e-4),
                    "NE" => yes((a - b).abs() >= 1e-4),
                    "GT" => yes(a > b),
                    "GE" => yes(a >= b),
                    "LT" => yes(a < b),
                    "LE" => yes(a <= b),
                    "AND" => yes(a != 0.0 && b != 0.0),
                    "OR" => yes(a != 0.0 || b != 0.0),
                    _ => yes((a != 0.0) ^ (b != 0.0)),
                }
            }
        };
        value.is_finite().then_some(value)
    }

    struct Three;
    impl Parameters for Three {
        fn numbered(&self, number: u32, _: Span) -> Result<f64, Diagnostic> {
            Ok(PARAMS.get(number as usize - 1).copied().unwrap_or(0.0))
        }
        fn named(&self, _: &str) -> Option<f64> {
            None
        }
    }

    fn evaluate(text: &str) -> Result<f64, Diagnostic> {
        let mut reader = Reader::new(text, 0, 1);
        let expr = reader.bracketed()?;
        assert_eq!(reader.pos, text.len(), "{text} was not read whole");
        expr.eval(&Three)
    }

    #[test]
    fn random_expressions_evaluate_as_the_reference_does() {
        let mut random = Random(0x9e37_79b9_7f4a_7c15);
        let mut compared = 0;
        for _ in 0..5000 {
            let tree = tree(&mut random, 4);
            let text = format!("[{}]", print(&tree));
            match (reference(&tree), evaluate(&text)) {
                (Some(want), Ok(got)) => {
                    assert!((want - got).abs() <= 1e-9 * want.abs().max(1.0), "{text}: {got}, not {want}");
                    compared += 1;
                }
                (None, Err(_)) => {}
                (want, got) => panic!("{text}: {got:?}, not {want:?}"),
            }
        }
        // Most trees have a value: the comparison is not all errors.
        assert!(compared > 2500, "{compared}");
    }

    #[test]
    fn precedence_and_order_are_linuxcncs() {
        // Each as rs274 evaluates it (LinuxCNC 2.9).
        let cases = [
            ("[2 ** 3 ** 2]", 64.0),
            ("[1 + 2 * 3 ** 2]", 19.0),
            ("[2 - 1 - 1]", 0.0),
            ("[1 + 1 EQ 2]", 1.0),
            ("[5 OR 0 AND 0]", 0.0),
            ("[-7 MOD 3]", 2.0),
            ("[7 MOD -3]", 1.0),
            ("[ROUND[-2.5]]", -3.0),
            ("[FIX[-2.5]]", -3.0),
            ("[-2 ** 2]", 4.0),
            ("[1 EQ 1.00001]", 1.0),
            ("[1 GE 1.000001]", 0.0),
            ("[ATAN[1]/[-1]]", 135.0),
            ("[1 lt 2 and 3]", 1.0),
        ];
        for (text, want) in cases {
            assert_eq!(evaluate(text).unwrap(), want, "{text}");
        }
    }
}
