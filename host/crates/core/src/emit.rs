//! Emit: statements -> G-code text. Any stage's statements can be written,
//! so `--stage N` shows each pass's work; after the last pass only output
//! codes remain. Numbers are fixed decimals, never exponents or `-0`.

use std::fmt::Write;

use crate::statement::{
    Axes, Cycle, Distance, FeedMode, Kind, Offset, Reference, Retract, Side, Statement, Units, Value, WizardArg,
};

pub struct Emitter {
    decimals: usize,
    line_numbers: bool,
    numbers: Numbers,
}

/// How a number is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Numbers {
    /// Always the unit's decimals (`X1.000`): ger's own form.
    Fixed,
    /// No trailing zeros (`X1`, `X1.25`), and at most this many digits, the
    /// leading `0` of `0.5` counted: for a controller that drops the digits
    /// past its limit (GRBL reads 8). Decimals go first; a number whose whole
    /// part alone is longer is written whole.
    Short { max_digits: usize },
}

/// The lines that open every translation: where it came from, and the modes
/// the rest of the output assumes.
pub fn preamble(source: &str, units: Units) -> String {
    let source = source.replace(['(', ')'], "");
    format!("(ger: translated from {source})\n{}\nG90\nG17\n", units.code())
}

/// An M code as the parser numbers it (times ten): `M62`, `M100`, `M1.5`.
fn pass_through_code(code: u32) -> String {
    if code.is_multiple_of(10) {
        format!("M{:02}", code / 10)
    } else {
        format!("M{}.{}", code / 10, code % 10)
    }
}

impl Emitter {
    pub fn new(decimals: usize, line_numbers: bool) -> Emitter {
        Emitter { decimals, line_numbers, numbers: Numbers::Fixed }
    }

    /// The same emitter, writing numbers in `numbers`' form.
    pub fn with_numbers(mut self, numbers: Numbers) -> Emitter {
        self.numbers = numbers;
        self
    }

    /// One statement as a line of G-code, without the newline.
    pub fn line(&self, statement: &Statement) -> String {
        let mut line = String::new();
        self.write(&mut line, statement);
        line
    }

    /// Appends one statement as a line of G-code, without the newline.
    pub fn write(&self, out: &mut String, statement: &Statement) {
        if self.line_numbers {
            let _ = write!(out, "N{} ", statement.span.line);
        }
        let start = out.len();
        self.write_statement(out, statement);
        // Words are written with a space before them; a bare move (no code) starts with a word.
        if out[start..].starts_with(' ') {
            out.remove(start);
        }
    }

    fn write_statement(&self, out: &mut String, statement: &Statement) {
        match &statement.kind {
            Kind::Motion(m) => {
                if let Some(mode) = m.mode {
                    out.push_str(mode.code());
                }
                self.axes(out, "XYZ", &m.target);
                self.axes(out, "IJK", &m.centre);
                self.value(out, 'R', m.radius);
                self.value(out, 'F', m.feed);
            }
            Kind::Plane(plane) => out.push_str(plane.code()),
            Kind::Units(units) => out.push_str(units.code()),
            Kind::Distance(d) => out.push_str(if *d == Distance::Absolute { "G90" } else { "G91" }),
            Kind::Polar(on) => out.push_str(if *on { "G16" } else { "G15" }),
            Kind::Offset { code, axes } => {
                match code {
                    Offset::G52 => out.push_str("G52"),
                    Offset::G92 => out.push_str("G92"),
                    Offset::WorkOffset(entry @ 1..=6) => {
                        let _ = write!(out, "G{}", 53 + entry);
                    }
                    Offset::WorkOffset(entry @ 7..=9) => {
                        let _ = write!(out, "G59.{}", entry - 6);
                    }
                    Offset::WorkOffset(entry) => {
                        let _ = write!(out, "G54.1 P{}", entry - 9);
                    }
                    Offset::G92Cancel { keep: false } => out.push_str("G92.1"),
                    Offset::G92Cancel { keep: true } => out.push_str("G92.2"),
                    Offset::G92Restore => out.push_str("G92.3"),
                }
                self.axes(out, "XYZ", axes);
            }
            Kind::ToolLength { positive, h } => {
                out.push_str(if *positive { "G43" } else { "G44" });
                if let Some(h) = h {
                    let _ = write!(out, " H{h}");
                }
            }
            Kind::ToolLengthCancel => out.push_str("G49"),
            Kind::SetToolTable { tool, offsets, radius } => {
                let _ = write!(out, "G10 L1 P{tool}");
                self.axes(out, "XYZ", offsets);
                self.value(out, 'R', *radius);
            }
            Kind::SetToolTableFrom(from) => {
                let _ = write!(out, "G10 L{} P{}", if from.fixture { 11 } else { 10 }, from.tool);
                self.axes(out, "XYZ", &from.target);
                self.value(out, 'R', from.radius);
            }
            Kind::ToolLengthRegister(h) => {
                let _ = write!(out, "H{h}");
            }
            Kind::CutterComp { side, d, diameter } => {
                out.push_str(if *side == Side::Left { "G41" } else { "G42" });
                if diameter.is_some() {
                    out.push_str(".1");
                    self.value(out, 'D', *diameter);
                } else if let Some(d) = d {
                    let _ = write!(out, " D{d}");
                }
            }
            Kind::CutterCompCancel => out.push_str("G40"),
            Kind::Machine { code, s, t } => {
                out.push_str(code.code());
                if let Some(s) = s {
                    let _ = write!(out, " S{s}");
                }
                if let Some(t) = t {
                    let _ = write!(out, " T{t}");
                }
            }
            Kind::Program(n) => {
                let _ = write!(out, "O{n}");
            }
            Kind::Call { program, repeat } => {
                let _ = write!(out, "M98 P{program} L{repeat}");
            }
            Kind::Return => out.push_str("M99"),
            Kind::End => out.push_str("M30"),
            Kind::Repeat => out.push_str("M47"),
            Kind::Dwell(seconds) => {
                out.push_str("G04");
                self.value(out, 'P', Some(Value { value: *seconds, span: statement.span }));
            }
            Kind::SpindleSpeed(s) => {
                let _ = write!(out, "S{s}");
            }
            Kind::ToolSelect(t) => {
                let _ = write!(out, "T{t}");
            }
            Kind::NoEffect(code) => out.push_str(code),
            Kind::Rotary(words) => {
                for (letter, word) in ['A', 'B', 'C'].into_iter().zip(words.iter()) {
                    self.value(out, letter, *word);
                }
            }
            Kind::PassThrough { code, words } => {
                out.push_str(&pass_through_code(*code));
                for (letter, value) in words {
                    let _ = write!(out, " {letter}{value}");
                }
            }
            Kind::FeedMode(mode) => out.push_str(match mode {
                FeedMode::InverseTime => "G93",
                FeedMode::PerMinute => "G94",
                FeedMode::PerRevolution => "G95",
            }),
            Kind::ArcCentres(distance) => out.push_str(if *distance == Distance::Absolute { "G90.1" } else { "G91.1" }),
            Kind::SetReference(reference) => {
                out.push_str(if *reference == Reference::Home { "G28.1" } else { "G30.1" })
            }
            Kind::CycleCancel => out.push_str("G80"),
            Kind::CycleRetract(retract) => out.push_str(if *retract == Retract::Initial { "G98" } else { "G99" }),
            Kind::Cycle(cycle) => {
                out.push_str(cycle.code.code());
                self.cycle_words(out, cycle);
            }
            // Pass 00 reads it one way or the other, so no stage shows it; a
            // line written without a code, its words are a hole's.
            Kind::NextPoint { hole: Ok(hole), .. } => self.cycle_words(out, hole),
            // Read neither way, it has been reported and has no words to write.
            Kind::NextPoint { hole: Err(_), .. } => {}
            Kind::Home { reference, via } => {
                out.push_str(if *reference == Reference::Home { "G28" } else { "G30" });
                self.axes(out, "XYZ", via);
            }
            Kind::MachineMove(m) => {
                out.push_str("G53");
                if let Some(mode) = m.mode {
                    out.push(' ');
                    out.push_str(mode.code());
                }
                self.axes(out, "XYZ", &m.target);
                self.value(out, 'F', m.feed);
            }
            Kind::Spline(spline) => {
                if let Some(code) = spline.code {
                    out.push_str(code.code());
                }
                self.axes(out, "XYZ", &spline.target);
                self.axes(out, "IJ", &spline.first);
                self.axes(out, "PQ", &spline.second);
                self.value(out, 'P', spline.weight);
                if let Some(order) = spline.order {
                    let _ = write!(out, " L{order}");
                }
                self.value(out, 'F', spline.feed);
            }
            Kind::NurbsEnd => out.push_str("G5.3"),
            Kind::SetWorkOffset { entry, axes, relative, rotation } => {
                let _ = write!(out, "G10 L{} P{entry}", if *relative { 20 } else { 2 });
                self.axes(out, "XYZ", axes);
                self.value(out, 'R', *rotation);
            }
            Kind::Wizard { name, args } => {
                out.push_str(name);
                for arg in args {
                    match arg {
                        WizardArg::Number(n) => {
                            let _ = write!(out, " {n}");
                        }
                        WizardArg::Text(t) => {
                            let _ = write!(out, " \"{t}\"");
                        }
                    }
                }
            }
        }
    }

    fn axes(&self, out: &mut String, letters: &str, axes: &Axes) {
        for (axis, letter) in letters.chars().enumerate() {
            self.value(out, letter, axes.get(axis));
        }
    }

    fn cycle_words(&self, out: &mut String, cycle: &Cycle) {
        self.axes(out, "XYZ", &cycle.target);
        self.value(out, 'R', cycle.r);
        self.value(out, 'Q', cycle.q);
        self.value(out, 'P', cycle.p);
        if cycle.repeat != 1 {
            let _ = write!(out, " L{}", cycle.repeat);
        }
        self.value(out, 'F', cycle.feed);
    }

    fn value(&self, out: &mut String, letter: char, value: Option<Value>) {
        if let Some(v) = value {
            out.push(' ');
            out.push(letter);
            self.number(out, v.value);
        }
    }

    /// Appends a number as this emitter writes a word's value.
    pub fn number(&self, out: &mut String, value: f64) {
        match self.numbers {
            Numbers::Fixed => push_number(out, value, self.decimals),
            Numbers::Short { max_digits } => push_short_number(out, value, self.decimals, max_digits),
        }
    }
}

/// [`Numbers::Short`]: at most `decimals`, rounded once from the value (never
/// from a rounded text), fewer when the digits would pass `max_digits`.
pub fn push_short_number(out: &mut String, value: f64, decimals: usize, max_digits: usize) {
    let start = out.len();
    let mut places = decimals;
    loop {
        out.truncate(start);
        push_number(out, value, places);
        let digits = out[start..].bytes().filter(u8::is_ascii_digit).count();
        if digits <= max_digits || places == 0 {
            break;
        }
        places = places.saturating_sub(digits - max_digits);
    }
    if out[start..].contains('.') {
        let kept = out.trim_end_matches('0').trim_end_matches('.').len();
        out.truncate(kept);
    }
    if &out[start..] == "-0" {
        out.replace_range(start.., "0");
    }
}

/// Fixed decimals; a value that rounds to zero is written `0.000`, not `-0.000`.
///
/// Written by hand because the standard library's exact formatting falls back
/// to big-number arithmetic for many values, and it dominated translation
/// time: here the value is scaled, rounded to an integer and the point put in.
pub fn push_number(out: &mut String, value: f64, decimals: usize) {
    const SCALES: [f64; 7] = [1.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6];
    let scaled = (value * SCALES[decimals.min(6)]).round();
    // Past 2^53 an f64 holds no fraction anyway; let the standard library write it.
    if decimals > 6 || !scaled.is_finite() || scaled.abs() >= 9.0e15 {
        let start = out.len();
        let _ = write!(out, "{value:.decimals$}");
        if out[start..].starts_with('-') && out[start + 1..].bytes().all(|b| b == b'0' || b == b'.') {
            out.remove(start);
        }
        return;
    }
    let units = scaled as i64;
    if units < 0 {
        out.push('-');
    }
    let mut integer = itoa::Buffer::new();
    let digits = integer.format(units.unsigned_abs());
    if digits.len() <= decimals {
        out.push_str("0.");
        out.extend(std::iter::repeat_n('0', decimals - digits.len()));
        out.push_str(digits);
    } else {
        let (whole, fraction) = digits.split_at(digits.len() - decimals);
        out.push_str(whole);
        if decimals > 0 {
            out.push('.');
            out.push_str(fraction);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn number(value: f64, decimals: usize) -> String {
        let mut s = String::new();
        push_number(&mut s, value, decimals);
        s
    }

    #[test]
    fn numbers_are_fixed_decimals_without_negative_zero_or_exponents() {
        assert_eq!(number(1.0, 4), "1.0000");
        assert_eq!(number(-0.00004, 4), "0.0000");
        assert_eq!(number(-0.00005001, 4), "-0.0001");
        assert_eq!(number(1e-20, 3), "0.000");
        assert_eq!(number(1e12, 3), "1000000000000.000");
        assert_eq!(number(1e300, 3).len(), 305);
        assert_eq!(number(0.5, 0), "1");
        assert_eq!(number(-0.0005001, 3), "-0.001");
        assert_eq!(number(123.4567, 3), "123.457");
        assert_eq!(number(-2.5, 3), "-2.500");
    }

    #[test]
    fn agrees_with_the_standard_library_away_from_ties() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        for i in 0..200_000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let magnitude = 10f64.powi(i % 9 - 3);
            let value = (seed as f64 / u64::MAX as f64 - 0.5) * magnitude;
            for decimals in [3, 4] {
                let scaled = value * 10f64.powi(decimals as i32);
                if (scaled.fract().abs() - 0.5).abs() < 1e-6 {
                    continue; // exact ties may round either way
                }
                let mut std = format!("{value:.decimals$}");
                if std.starts_with('-') && std[1..].bytes().all(|b| b == b'0' || b == b'.') {
                    std.remove(0);
                }
                assert_eq!(number(value, decimals), std, "{value}");
            }
        }
    }

    fn short(value: f64, decimals: usize, max_digits: usize) -> String {
        let mut s = String::from("X");
        push_short_number(&mut s, value, decimals, max_digits);
        s[1..].to_string()
    }

    #[test]
    fn short_numbers_drop_trailing_zeros_and_digits_past_the_limit() {
        assert_eq!(short(1.0, 3, 8), "1");
        assert_eq!(short(1.25, 3, 8), "1.25");
        assert_eq!(short(-0.0004, 3, 8), "0");
        assert_eq!(short(-0.0006, 3, 8), "-0.001");
        assert_eq!(short(0.1234, 4, 8), "0.1234");
        // 12345.6789 has 9 digits: one decimal goes, rounded from the value.
        assert_eq!(short(12345.6789, 4, 8), "12345.679");
        // Rounding can add a digit: 99999.9996 is 100000.000, 9 digits, so 100000.00 -> 100000.
        assert_eq!(short(99999.9996, 3, 8), "100000");
        assert_eq!(short(123456789.4, 3, 8), "123456789");
        assert_eq!(short(2.5, 0, 8), "3");
    }

    #[test]
    fn preamble_names_the_source_and_modes() {
        assert_eq!(preamble("part (v2).ngc", Units::Mm), "(ger: translated from part v2.ngc)\nG21\nG90\nG17\n");
    }
}
