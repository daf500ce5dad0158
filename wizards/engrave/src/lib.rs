//! `Engrave "TEXT" HEIGHT [DEPTH] [ALIGN] [SPACING]`: engraves TEXT in a
//! single-stroke font (capitals, digits, `- + . , : / #`; lower case is cut
//! as capitals), HEIGHT the capitals' height, DEPTH below the current Z
//! (default a twentieth of HEIGHT).
//!
//! The text's baseline runs along +X from the current XY: ALIGN `"left"`
//! (default) starts it there, `"centre"` centres it there, `"right"` ends it
//! there. SPACING is the gap between characters as a fraction of HEIGHT
//! (default 1/3). Each stroke is one feed down, along, and a rapid up to a
//! quarter of HEIGHT above the current Z, over which the tool moves to the
//! next. Afterwards the tool is back at the call's position.

mod font;

use ger_wizard_sdk::*;

/// The font's grid: a glyph is this many units wide, its capitals this high.
const GLYPH_WIDTH: f64 = 4.0;
const CAP_HEIGHT: f64 = 6.0;

struct Engrave;

impl Wizard for Engrave {
    fn describe() -> Description {
        Description::new(
            "Engrave",
            "engraves a line of text in a single-stroke font from the current position",
            "Engrave \"TEXT\" HEIGHT [DEPTH] [ALIGN] [SPACING]",
        )
        .param("TEXT", "what to engrave, in double quotes")
        .param("HEIGHT", "height of the capitals")
        .optional("DEPTH", "depth below the current Z (default HEIGHT / 20)")
        .optional("ALIGN", "\"left\" (default), \"centre\" or \"right\" of the current position")
        .optional("SPACING", "gap between characters, as a fraction of HEIGHT (default 1/3)")
    }

    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
        let text = args.text(0)?;
        let height = args.positive(1)?;
        let depth = args.optional_positive(2)?.unwrap_or(height / 20.0);
        // Where the current position is along the text, as a fraction of its width.
        let align = [0.0, 0.5, 1.0, 0.5][args.choice(3, &["left", "centre", "right", "center"])?];
        let spacing = args.optional_number(4)?.unwrap_or(1.0 / 3.0);
        if spacing < 0.0 {
            return Err(format!("SPACING (argument 5) must be 0 or more, not {spacing}"));
        }
        let glyphs = text
            .chars()
            .map(|c| {
                font::glyph(c).ok_or_else(|| {
                    format!("the font has no `{}` (it has A-Z, 0-9, space and - + . , : / #)", c.escape_default())
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let feed = state.feed.ok_or("no feed rate is set: give an F before calling Engrave")?;
        let scale = height / CAP_HEIGHT;
        let advance = (GLYPH_WIDTH + spacing * CAP_HEIGHT) * scale;
        let width = if glyphs.is_empty() { 0.0 } else { advance * glyphs.len() as f64 - spacing * height };
        let [x0, y0, top] = state.position;
        let left = x0 - align * width;
        let (above, bottom) = (top + height / 4.0, top - depth);
        let mut out = vec![comment(format!("Engrave \"{text}\", {height} high, {depth} deep"))];
        out.push(g0().z(above).into());
        for (n, strokes) in glyphs.iter().enumerate() {
            let origin = left + advance * n as f64;
            for stroke in strokes.iter() {
                let at = |(x, y): (f64, f64)| (origin + x * scale, y0 + y * scale);
                let (x, y) = at(stroke[0]);
                out.push(g0().xy(x, y).into());
                out.push(g1().z(bottom).f(feed).into());
                for point in &stroke[1..] {
                    let (x, y) = at(*point);
                    out.push(g1().xy(x, y).into());
                }
                out.push(g0().z(above).into());
            }
        }
        out.push(g0().xy(x0, y0).into());
        out.push(g0().z(top).into());
        Ok(state.in_absolute(out))
    }
}

export_wizard!(Engrave);
