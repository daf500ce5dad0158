//! Hover texts from an analysis: what a length word is on the machine,
//! where the tool is after a line and when the planned run gets there, and
//! what a wizard says about itself.

use ger_engine::check::duration;
use ger_engine::core::emit::push_number;
use ger_engine::core::statement::{Distance, Units};

use crate::analysis::Analysis;
use crate::WizardInfo;

/// A word under the cursor.
pub struct Word<'a> {
    pub letter: char,
    pub value: f64,
    /// As the program writes it: `X1.`, `x-.5`.
    pub written: &'a str,
    /// Its 1-based line.
    pub line: u32,
    /// Whether its line has a G10, whose R is an angle.
    pub on_g10: bool,
}

/// A length word's value in the machine's unit; for X, Y or Z on a line
/// that moves, that axis's machine coordinate after the line. `None` for
/// a word that is not a length, or a line the analysis never reached.
pub fn word_text(word: &Word, analysis: &Analysis) -> Option<String> {
    let axis = "XYZ".find(word.letter);
    let length = axis.is_some() || matches!(word.letter, 'I' | 'J' | 'K') || (word.letter == 'R' && !word.on_g10);
    if !length {
        return None;
    }
    let state = analysis.state_at(word.line)?;
    let machine = analysis.units;
    let unit = machine.abbreviation();
    let number = |value: f64| {
        let mut text = String::new();
        push_number(&mut text, value, machine.decimals());
        text
    };
    let written = word.written;
    let mut text = if state.polar && axis == Some(state.plane.axes().1) {
        format!("**{written}**: an angle, in degrees (polar coordinates, G16)")
    } else if state.units == machine {
        format!("**{written}**: {} {unit}", number(word.value))
    } else {
        let value = number(word.value * state.units.factor_to(machine));
        let (program, code) = (unit_name(state.units), state.units.code());
        format!("**{written}** is **{value} {unit}** on this machine (the program is in {program} here, {code})")
    };
    if let (Some(axis), Some((moved, at))) = (axis, analysis.position_after(word.line)) {
        if moved == word.line {
            let how = match state.distance {
                Distance::Incremental => "relative, G91".to_string(),
                Distance::Absolute if state.zero == [0.0; 3] => "absolute, G90".to_string(),
                Distance::Absolute => {
                    format!("absolute, G90, from program zero at machine {}", place(state.zero, machine))
                }
            };
            text.push_str(&format!(
                "\n\nMachine **{}{}** {unit} after this line ({how})",
                word.letter,
                number(at[axis])
            ));
        }
    }
    Some(text)
}

fn unit_name(units: Units) -> &'static str {
    match units {
        Units::Inch => "inches",
        Units::Mm => "millimetres",
    }
}

/// Where the tool is after 1-based `line`, in machine coordinates, and
/// when the planned run reaches the line.
pub fn line_text(line: u32, analysis: &Analysis) -> String {
    let units = analysis.units.abbreviation();
    let mut text = match analysis.position_after(line) {
        None => "Before the first move: the tool is at machine zero (X0 Y0 Z0)".to_string(),
        Some((moved, at)) => {
            let place = place(at, analysis.units);
            if moved == line {
                format!("After line {line}: **{place}** {units}, in machine coordinates")
            } else {
                format!("After line {line} (no move on it; the last before it is on line {moved}): **{place}** {units}, in machine coordinates")
            }
        }
    };
    if let (Some(reached), Some(planned)) = (analysis.reached(line), &analysis.planned) {
        text.push_str(&format!(
            "\n\nThe planned run reaches line {line} at **{}** of {}, on {}",
            duration(reached),
            duration(planned.seconds),
            planned.profile
        ));
    }
    text
}

/// A position as `X1.000 Y2.000 Z3.000`, in `units`.
pub fn place(at: [f64; 3], units: Units) -> String {
    let mut place = String::new();
    for (axis, value) in ["X", "Y", "Z"].iter().zip(at) {
        if !place.is_empty() {
            place.push(' ');
        }
        place.push_str(axis);
        push_number(&mut place, value, units.decimals());
    }
    place
}

/// The wizard `name` calls, as the folder's catalog describes it.
pub fn wizard_hover(name: &str, catalog: &[WizardInfo]) -> String {
    use ger_engine::core::wizard::key;
    match catalog.iter().find(|w| key(&w.name) == key(name)) {
        Some(wizard) => wizard_text(wizard),
        None => format!("**{name}**: a wizard call; no wizard of that name is described in the wizards folder"),
    }
}

/// A wizard's usage, summary and parameters.
pub fn wizard_text(wizard: &WizardInfo) -> String {
    let mut text = format!("**{}** (wizard)\n\n`{}`\n\n{}", wizard.name, wizard.usage, wizard.summary);
    for param in &wizard.params {
        let optional = if param.optional { " (optional)" } else { "" };
        text.push_str(&format!("\n- `{}`{optional}: {}", param.name, param.description));
    }
    text
}
