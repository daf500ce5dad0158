//! The tools and stock CAM systems describe in their programs' comments.
//! Each rule reads one pattern a family of posts writes; [`read`] tries them
//! in turn on the text of one comment. Pure: text in, values out.
//!
//! Lengths are left in the unit the comment writes them in: the comment's own
//! when it names one (`6 mm`, `1/4"`, `{0.25 inch}`; a fraction is in
//! inches), else the program's, which [`super::scan`] settles.

use crate::config::ToolKind;
use crate::statement::Units;

/// What one comment says.
#[derive(Clone, Debug, PartialEq)]
pub enum Found {
    Tool(Described),
    Stock(Block),
    /// Estlcam's `(Required tools:)`: the comments after it name the tools, in the order they are used.
    ToolList,
}

/// A tool as a comment describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct Described {
    /// The tool number the comment gives. Without one, it describes the tool
    /// of the next tool change, or the tool loaded (see [`super::scan`]).
    pub number: Option<u32>,
    pub kind: ToolKind,
    pub diameter: f64,
    /// The point's included angle, for the kinds with a point.
    pub tip_angle: Option<f64>,
    pub flute_length: Option<f64>,
    /// The unit the comment names for its lengths; `None`: the program's.
    pub units: Option<Units>,
}

/// CutViewer's `STOCK/BLOCK`: the block's size, and where program zero is
/// measured from its lower-left-bottom corner, in the program's unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Block {
    pub size: [f64; 3],
    pub origin: [f64; 3],
}

/// The included angle a chamfer mill, V-bit or engraver has when nothing says.
const CONE_ANGLE: f64 = 90.0;

/// Reads one comment's text (without its parentheses or `;`).
pub fn read(comment: &str) -> Option<Found> {
    let text = comment.trim();
    if is_tool_list(text) {
        return Some(Found::ToolList);
    }
    // Every tool and stock has a number in it: most comments of a program have none.
    if !text.bytes().any(|b| b.is_ascii_digit()) {
        return None;
    }
    if let Some(found) = cutviewer(text) {
        return Some(found);
    }
    fusion(text)
        .or_else(|| mastercam(text))
        .or_else(|| mastercam_table(text))
        .or_else(|| numbered(text))
        .or_else(|| labelled(text))
        .map(Found::Tool)
}

/// Reads a name an Estlcam tool list gives (`End mill 3/8`): a tool of the
/// next tool change, if the name has a size.
pub fn listed_name(text: &str) -> Option<Described> {
    let (shape, size) = name(text)?;
    Some(size.describe(None, shape.unwrap_or(Shape::Flat)))
}

/// Fusion 360, Inventor CAM and HSMWorks (every post Autodesk ships):
/// `T1 D=6. CR=0. - ZMIN=-5. - flat end mill`, with `TAPER=90deg` for tools
/// with a point or taper and, in some posts, the tool's own name after a
/// last ` - `. `CR` is the corner radius: `D/2` is a ball. `TAPER` is a
/// drill's point angle, but a chamfer or tapered mill's angle from its axis.
fn fusion(text: &str) -> Option<Described> {
    let (number, rest) = tool_number(text)?;
    let mut parts = rest.split(" - ");
    let head = parts.next()?;
    let mut diameter = None;
    let mut corner = 0.0;
    let mut taper = None;
    for field in head.split_whitespace() {
        let (key, value) = field.split_once('=')?;
        match key.to_ascii_uppercase().as_str() {
            "D" => diameter = Some(plain_number(value)?),
            "CR" => corner = plain_number(value)?,
            "TAPER" => taper = Some(plain_number(value.trim_end_matches(|c: char| c.is_ascii_alphabetic()))?),
            _ => return None,
        }
    }
    let diameter = diameter?;
    // The type is the first part that is not ZMIN=/ZMAX=.
    let kind = words(parts.find(|p| !p.contains('='))?);
    let shape = shape_of(&kind).unwrap_or(Shape::Flat);
    let shape =
        if shape == Shape::Flat && corner > 0.0 && corner >= diameter / 2.0 - 1e-9 { Shape::Ball } else { shape };
    // Fusion's chamfer and tapered mills give their taper angle; drills, spot drills and countersinks their point's.
    let from_axis = kind.iter().any(|w| w.starts_with("CHAMFER") || w.starts_with("TAPER"));
    let tip_angle = taper.map(|a| if from_axis { 2.0 * a } else { a });
    Some(Described { number: Some(number), ..shape.describe(diameter, tip_angle) })
}

/// Mastercam's classic Fanuc posts (MPFAN and those made from it):
/// `( 1/2 FLAT ENDMILL TOOL - 1 DIA. OFF. - 1 LEN. - 1 DIA. - .5)`, the name
/// before `TOOL -` or after its number, the diameter last.
fn mastercam(text: &str) -> Option<Described> {
    let upper = text.to_ascii_uppercase();
    let at = upper.find("TOOL")?;
    let after = upper[at + 4..].trim_start().strip_prefix('-')?.trim_start();
    let digits = after.len() - after.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    let number: u32 = after[..digits].parse().ok()?;
    let offset = after.find("DIA. OFF.")?;
    let last = upper.rfind("DIA.")?;
    let diameter = plain_number(upper[last + 4..].trim_start().strip_prefix('-')?.trim())?;
    let title = format!("{} {}", &upper[..at], &after[digits..offset]);
    let shape = shape_of(&words(&title)).unwrap_or(Shape::Flat);
    let angle = named_angle(&title);
    Some(Described { number: Some(number), ..shape.describe(diameter, angle) })
}

/// Mastercam's newer posts: a table row `T1 | 1/4 FLAT ENDMILL | H1 | D1 | ...`,
/// the size at the start of the name (the D field is an offset register),
/// or in a `TOOL DIA. - .25` field where the post writes one.
fn mastercam_table(text: &str) -> Option<Described> {
    let mut fields = text.split('|');
    let (number, rest) = tool_number(fields.next()?.trim())?;
    if !rest.trim().is_empty() {
        return None;
    }
    let title = fields.next()?;
    let shape = shape_of(&words(title)).unwrap_or(Shape::Flat);
    let stated = fields.find_map(|f| {
        let upper = f.to_ascii_uppercase();
        let at = upper.find("DIA.")?;
        plain_number(upper[at + 4..].trim_start().strip_prefix('-')?.trim())
    });
    let described = match stated {
        Some(diameter) => shape.describe(diameter, named_angle(title)),
        None => name(title)?.1.describe(None, shape),
    };
    Some(Described { number: Some(number), ..described })
}

/// A numbered list of tools with names: Vectric's header (`(1 = End Mill
/// {6 mm})`, `(T2 = Ball Nose {1/8 inch})`), the headers machinists write
/// on Haas and Fanuc controls (`(T1 = 1/2" END MILL 03-0086)`, `(T5 - .25
/// SPOT DRILL)`, `(TOOL 1 = 1IN FACE MILL)`) and CamBam's (`( T1 : 6.0 )`).
/// The name must give the tool's size.
fn numbered(text: &str) -> Option<Described> {
    let upper = text.to_ascii_uppercase();
    let (number, rest) = match tool_number(text) {
        Some(found) => found,
        None => {
            // "TOOL 1 = ..." and Vectric's bare "1 = ...".
            let rest = upper.strip_prefix("TOOL").map_or(text, |_| &text[4..]).trim_start();
            let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
            (rest[..digits].parse().ok()?, &rest[digits..])
        }
    };
    let rest = rest.trim_start();
    let text = rest.strip_prefix(['=', ':', '-']).filter(|text| !text.starts_with('='))?;
    let (shape, size) = name(text)?;
    // A name with no tool's word in it must be the size alone, as CamBam's.
    if shape.is_none() && (tokens(text).len() > 2 || !matches!(tokens(text).first(), Some(Token::Number { .. }))) {
        return None;
    }
    Some(Described { number: Some(number), ..size.describe(None, shape.unwrap_or(Shape::Flat)) })
}

/// A tool named or measured without a number, for the tool of the next tool
/// change (or the loaded one): Vectric's `(Tool: End Mill {0.25 inch})`
/// after each change, FreeCAD's `(TC: 5mm Endmill)` before it, Estlcam's
/// `(Change tool: End mill 1/8)`, and `(Tool-Diameter: 4.0mm)` (viaconstructor),
/// `(Tool Diameter: 6.35)`, `(Tool Dia = .25)`.
fn labelled(text: &str) -> Option<Described> {
    let upper = text.to_ascii_uppercase();
    for label in ["TOOL-DIAMETER", "TOOL DIAMETER", "TOOL DIA", "CUTTER DIAMETER"] {
        if let Some(value) = upper.strip_prefix(label) {
            // Only punctuation between the label and the number: `:`, `=`, `. -`.
            let tokens = tokens(value);
            let first = tokens.iter().position(|t| !matches!(t, Token::Symbol { .. }))?;
            return Some(length(&tokens, first)?.describe(None, Shape::Flat));
        }
    }
    let at = ["TOOL:", "TC:"].into_iter().find_map(|label| {
        let at = upper.find(label)?;
        let starts_word = at == 0 || !upper.as_bytes()[at - 1].is_ascii_alphanumeric();
        starts_word.then_some(at + label.len())
    })?;
    let (shape, size) = name(&text[at..])?;
    Some(size.describe(None, shape.unwrap_or(Shape::Flat)))
}

/// CutViewer's tool and stock statements, which CutViewer-ready posts (and
/// Carbide Create) write: `TOOL/MILL,diameter,corner radius,height,taper
/// angle` (the taper from the axis), `TOOL/DRILL,diameter,point angle,height`,
/// `TOOL/CHAMFER,diameter,angle from the axis,height,chamfer length`,
/// `TOOL/CDRILL,pilot diameter,pilot angle,pilot height,diameter,angle,height`,
/// and `STOCK/BLOCK,length,width,height,x origin,y origin,z origin`.
fn cutviewer(text: &str) -> Option<Found> {
    let upper = text.to_ascii_uppercase();
    let (kind, values) = upper.split_once(',')?;
    let kind = kind.replace(' ', "");
    let values: Vec<f64> = values.split(',').map(|v| plain_number(v.trim())).collect::<Option<_>>()?;
    let at = |i: usize| values.get(i).copied().unwrap_or(0.0);
    let positive = |x: f64| (x > 0.0).then_some(x);
    let described = match kind.as_str() {
        "STOCK/BLOCK" if values.len() >= 6 => {
            return Some(Found::Stock(Block { size: [at(0), at(1), at(2)], origin: [at(3), at(4), at(5)] }));
        }
        "TOOL/MILL" if values.len() >= 2 => {
            let (diameter, corner, height, taper) = (at(0), at(1), at(2), at(3));
            if taper > 0.0 && taper < 90.0 {
                // A taper widens the tool up its height: a V-bit's tip is nearly a point.
                let top = diameter + 2.0 * height * taper.to_radians().tan();
                Shape::Cone.describe(top, Some(2.0 * taper))
            } else {
                let shape = if corner > 0.0 && corner >= diameter / 2.0 - 1e-9 { Shape::Ball } else { Shape::Flat };
                Described { flute_length: positive(height), ..shape.describe(diameter, None) }
            }
        }
        "TOOL/DRILL" if values.len() >= 2 => {
            Described { flute_length: positive(at(2)), ..Shape::Drill.describe(at(0), positive(at(1))) }
        }
        "TOOL/CHAMFER" if values.len() >= 2 => Shape::Cone.describe(at(0), positive(2.0 * at(1))),
        // The body's countersink, which is what shows on the part; the pilot is narrower.
        "TOOL/CDRILL" if values.len() >= 5 => Shape::Centre.describe(at(3), positive(at(4))),
        _ => return None,
    };
    Some(Found::Tool(described))
}

fn is_tool_list(text: &str) -> bool {
    text.eq_ignore_ascii_case("Required tools:")
}

/// `T1 ...`, `T01 ...`: the number and the rest.
fn tool_number(text: &str) -> Option<(u32, &str)> {
    let rest = text.strip_prefix(['T', 't'])?;
    let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    let number = rest[..digits].parse().ok()?;
    let rest = &rest[digits..];
    (!rest.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '.')).then_some((number, rest))
}

/// `6`, `6.`, `.25`, `-3.175`, `+2`: a finite number and nothing else.
fn plain_number(text: &str) -> Option<f64> {
    let digits = text.trim_start_matches(['-', '+']);
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit() || c == '.') || digits == "." {
        return None;
    }
    text.parse::<f64>().ok().filter(|x| x.is_finite())
}

/// What a name's words say the tool is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Shape {
    /// Flat end mills, face mills, slot mills, router bits, and bull noses,
    /// whose corner radius the simulation leaves out.
    Flat,
    Ball,
    Drill,
    /// Spot and centre drills.
    Centre,
    /// Chamfer mills, countersinks, V-bits, engravers, tapered mills.
    Cone,
}

impl Shape {
    fn describe(self, diameter: f64, tip_angle: Option<f64>) -> Described {
        let tip_angle = tip_angle.filter(|a| *a > 0.0 && *a < 180.0);
        let (kind, tip_angle) = match self {
            Shape::Flat => (ToolKind::Endmill, None),
            Shape::Ball => (ToolKind::Ballmill, None),
            Shape::Drill => (ToolKind::Drill, tip_angle),
            Shape::Centre => (ToolKind::CenterDrill, tip_angle),
            Shape::Cone => (ToolKind::Drill, Some(tip_angle.unwrap_or(CONE_ANGLE))),
        };
        Described { number: None, kind, diameter, tip_angle, flute_length: None, units: None }
    }
}

/// The shape the words of a name give, if any word names a tool.
fn shape_of(words: &[String]) -> Option<Shape> {
    let has = |w: &str| words.iter().any(|x| x == w);
    let starts = |w: &str| words.iter().any(|x| x.starts_with(w));
    let pair = |a: &str, b: &str| words.windows(2).any(|p| p[0] == a && p[1] == b);
    if starts("BALL") {
        Some(Shape::Ball)
    } else if pair("CENTER", "DRILL") || pair("CENTRE", "DRILL") || has("CENTERDRILL") || starts("SPOT") {
        Some(Shape::Centre)
    } else if starts("CHAMFER")
        || starts("COUNTERSINK")
        || pair("COUNTER", "SINK")
        || has("VBIT")
        || pair("V", "BIT")
        || pair("V", "CUTTER")
        || pair("V", "GROOVE")
        || starts("ENGRAV")
        || starts("TAPER")
    {
        Some(Shape::Cone)
    } else if starts("DRILL") {
        Some(Shape::Drill)
    } else if ["MILL", "ENDMILL", "END", "FLAT", "FACE", "SLOT", "BULL", "BULLNOSE", "ROUTER", "BIT", "CUTTER"]
        .iter()
        .any(|w| has(w))
        || starts("REAM")
    {
        Some(Shape::Flat)
    } else {
        None
    }
}

/// The words of a text, in capitals.
fn words(text: &str) -> Vec<String> {
    text.split(|c: char| !c.is_ascii_alphabetic()).filter(|w| !w.is_empty()).map(str::to_ascii_uppercase).collect()
}

/// A piece of a name.
#[derive(Clone, Debug, PartialEq)]
enum Token {
    /// A number, with whether it was a fraction (`1/4`, `1-1/2`) and whether
    /// white space came before it.
    Number {
        value: f64,
        fraction: bool,
        spaced: bool,
    },
    Word {
        text: String,
        spaced: bool,
    },
    Symbol {
        symbol: char,
        spaced: bool,
    },
}

impl Token {
    fn spaced(&self) -> bool {
        match self {
            Token::Number { spaced, .. } | Token::Word { spaced, .. } | Token::Symbol { spaced, .. } => *spaced,
        }
    }

    fn word(&self) -> Option<&str> {
        match self {
            Token::Word { text, .. } => Some(text),
            _ => None,
        }
    }

    fn is_symbol(&self, c: char) -> bool {
        matches!(self, Token::Symbol { symbol, .. } if *symbol == c)
    }
}

fn tokens(text: &str) -> Vec<Token> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    let mut spaced = true;
    let digits = |from: usize| (from..chars.len()).take_while(|&k| chars[k].is_ascii_digit()).count();
    let parse = |from: usize, to: usize| chars[from..to].iter().collect::<String>().parse::<f64>().ok();
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            spaced = true;
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit)) {
            let whole = digits(i);
            let mut end = i + whole;
            let fraction_at = |at: usize| {
                let top = digits(at);
                let bottom = if top > 0 && chars.get(at + top) == Some(&'/') { digits(at + top + 1) } else { 0 };
                (bottom > 0).then_some((top, bottom))
            };
            let token = if let Some((top, bottom)) = fraction_at(i) {
                end = i + top + 1 + bottom;
                let value = parse(i, i + top).zip(parse(i + top + 1, end)).map(|(a, b)| a / b);
                value.map(|value| Token::Number { value, fraction: true, spaced })
            } else if whole > 0 && chars.get(end) == Some(&'-') && fraction_at(end + 1).is_some() {
                // 1-1/2: a whole number and a fraction.
                let (top, bottom) = fraction_at(end + 1).unwrap_or((0, 0));
                let at = end + 1;
                let whole_value = parse(i, end);
                end = at + top + 1 + bottom;
                let part = parse(at, at + top).zip(parse(at + top + 1, end)).map(|(a, b)| a / b);
                whole_value.zip(part).map(|(w, p)| Token::Number { value: w + p, fraction: true, spaced })
            } else {
                if chars.get(end) == Some(&'.') {
                    end += 1 + digits(end + 1);
                }
                parse(i, end).map(|value| Token::Number { value, fraction: false, spaced })
            };
            match token {
                Some(token) if matches!(token, Token::Number { value, .. } if value.is_finite()) => out.push(token),
                _ => return Vec::new(),
            }
            i = end;
        } else if c.is_alphabetic() {
            let end = (i..chars.len()).find(|&k| !chars[k].is_alphabetic()).unwrap_or(chars.len());
            out.push(Token::Word { text: chars[i..end].iter().collect::<String>().to_uppercase(), spaced });
            i = end;
        } else {
            out.push(Token::Symbol { symbol: c, spaced });
            i += 1;
        }
        spaced = false;
    }
    out
}

/// A size a name gives: a diameter, and the point angle when it says one.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Size {
    diameter: f64,
    units: Option<Units>,
    angle: Option<f64>,
}

impl Size {
    fn describe(self, number: Option<u32>, shape: Shape) -> Described {
        Described { number, units: self.units, ..shape.describe(self.diameter, self.angle) }
    }
}

/// A name's shape (if its words say) and size (it must give one).
fn name(text: &str) -> Option<(Option<Shape>, Size)> {
    let tokens = tokens(text);
    let shape = shape_of(&words(text));
    let diameter = (0..tokens.len()).find_map(|i| length(&tokens, i))?;
    let angle = named_angle(text);
    Some((shape, Size { angle, ..diameter }))
}

/// The length at `tokens[i]`, if it is one: a number with a unit, a
/// fraction (inches), or a plain number that is not an angle, a count, a
/// speed, a part number or a drill's number.
fn length(tokens: &[Token], i: usize) -> Option<Size> {
    let Token::Number { value, fraction, .. } = tokens[i] else { return None };
    if value <= 0.0 {
        return None;
    }
    let next = tokens.get(i + 1);
    let after = tokens.get(i + 2);
    if i > 0 && (tokens[i - 1].is_symbol('#') && !tokens[i].spaced()) {
        return None;
    }
    // Part numbers: 03-0086.
    let joined = |t: Option<&Token>| t.is_some_and(|t| !t.spaced());
    if next.is_some_and(|t| t.is_symbol('-'))
        && joined(next)
        && matches!(after, Some(Token::Number { .. }))
        && joined(after)
    {
        return None;
    }
    if i > 1 && tokens[i - 1].is_symbol('-') && !tokens[i].spaced() && !tokens[i - 1].spaced() {
        if let Token::Number { .. } = tokens[i - 2] {
            return None;
        }
    }
    let units = match next {
        Some(t) if t.is_symbol('"') || t.is_symbol('”') => Some(Units::Inch),
        Some(t) if t.is_symbol('\'') && after.is_some_and(|a| a.is_symbol('\'')) => Some(Units::Inch),
        Some(Token::Word { text, .. }) => match text.as_str() {
            "MM" | "MILLIMETER" | "MILLIMETERS" | "MILLIMETRE" | "MILLIMETRES" => Some(Units::Mm),
            "IN" | "INCH" | "INCHES" => Some(Units::Inch),
            // Angles, counts, speeds and radii lead with their number too.
            "DEG" | "DEGREE" | "DEGREES" | "POINT" | "FLUTE" | "FLUTES" | "FL" | "RAD" | "R" | "RPM" | "IPM"
            | "SFM" => return None,
            _ => None,
        },
        Some(t) if t.is_symbol('°') || t.is_symbol('%') => return None,
        _ => None,
    };
    let units = units.or(fraction.then_some(Units::Inch));
    Some(Size { diameter: value, units, angle: None })
}

/// The point or included angle a name gives: `60 deg`, `90°`, `135 Point Angle`, `90DEG`.
fn named_angle(text: &str) -> Option<f64> {
    let tokens = tokens(text);
    tokens.iter().enumerate().find_map(|(i, t)| {
        let Token::Number { value, fraction: false, .. } = *t else { return None };
        let next = tokens.get(i + 1)?;
        let angle = next.is_symbol('°') || matches!(next.word(), Some("DEG" | "DEGREE" | "DEGREES" | "POINT"));
        (angle && value > 0.0 && value < 180.0).then_some(value)
    })
}

#[cfg(test)]
mod tests;
