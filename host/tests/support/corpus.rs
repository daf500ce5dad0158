//! The real-world corpus, `../shared/corpus` beside the repository: its
//! `INDEX.tsv`, and which programs are a 3-axis mill's.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use super::process::Finished;

/// Files the index does not mark as other machines' but that are: with why.
const NOT_A_MILL: [(&str, &str); 4] = [
    ("gcode-rs/bondtech_estep.gcode", "3D printer (extruder calibration, M92 E)"),
    ("gcode-rs/makerblock_tinycnc.gcode", "pen plotter (M300 pen up/down)"),
    ("gcode-rs/plotter_owl.gcode", "pen plotter (M300 pen up/down)"),
    ("Hass-CNC-Programs/TEAMMACHINE-ENGRAVE.nc", "rotary engraving (A axis)"),
];

/// The corpus's folder, beside the repository.
pub fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpus")
}

/// One G-code file of the index.
pub struct Entry {
    /// Relative to the corpus's folder.
    pub path: String,
    pub source: String,
    /// `G20`, `G21` or `none`, as the index says.
    pub units: String,
    pub features: String,
    /// The program's text, outside comments, uses `#` parameters, `[ ]`
    /// expressions or O-word control flow, whatever the index says.
    pub programs_parameters: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Class {
    /// A 3-axis mill program.
    Mill,
    /// Uses `#` parameters, O-word control flow or macro B.
    Macro,
    /// LinuxCNC's reject suite: programs meant to be refused.
    Reject,
    /// Another machine's program: not run.
    Other(String),
}

impl Class {
    /// The class as the results tables name it.
    pub fn label(&self) -> &'static str {
        match self {
            Class::Mill => "mill",
            Class::Macro => "mill, macro programming",
            Class::Reject => "LinuxCNC reject suite",
            Class::Other(_) => "other machine",
        }
    }
}

impl Entry {
    pub fn class(&self) -> Class {
        let has = |feature: &str| self.features.contains(feature);
        if let Some((_, why)) = NOT_A_MILL.iter().find(|(path, _)| *path == self.path) {
            return Class::Other(why.to_string());
        }
        if has("ABC-axes") {
            return Class::Other("rotary axes".into());
        }
        if has("printer-M-codes") {
            return Class::Other("3D printer".into());
        }
        if self.source.contains("plasma") {
            return Class::Other("plasma/waterjet cutter".into());
        }
        if self.path.contains("lathe") {
            return Class::Other("lathe".into());
        }
        if self.source.contains("expected-error") {
            return Class::Reject;
        }
        let macro_feature =
            has("#vars") || has("IF/GOTO/WHILE") || has("O-word-subs/control") || has("G65/G66-macro-call");
        if macro_feature || self.programs_parameters {
            return Class::Macro;
        }
        Class::Mill
    }

    /// The unit to translate the program in, for `ger run --units`: its own.
    pub fn units(&self) -> &'static str {
        if self.units == "G21" {
            "mm"
        } else {
            "in"
        }
    }
}

/// The G-code files of the corpus's index, in its order.
pub fn entries(corpus: &Path) -> Vec<Entry> {
    let index = std::fs::read_to_string(corpus.join("INDEX.tsv")).unwrap();
    index
        .lines()
        .skip(1)
        .filter_map(|line| {
            let fields: Vec<&str> = line.split('\t').collect();
            (fields.len() >= 8 && fields[7] == "gcode").then(|| Entry {
                path: fields[0].into(),
                source: fields[3].into(),
                units: fields[4].into(),
                features: fields[6].into(),
                programs_parameters: std::fs::read(corpus.join(fields[0]))
                    .is_ok_and(|bytes| uses_macro_programming(&String::from_utf8_lossy(&bytes))),
            })
        })
        .collect()
}

/// Whether a program uses what only a parametric interpreter runs: `#`
/// parameters, `[ ]` expressions (`sqrt[2]`), or O-word control flow
/// (`o100 if`, `o<name> call`), outside its comments.
pub fn uses_macro_programming(text: &str) -> bool {
    const CONTROL: [&str; 12] =
        ["sub", "endsub", "call", "if", "elseif", "else", "endif", "while", "endwhile", "do", "repeat", "return"];
    text.lines().any(|line| {
        let code = without_comments(line).to_ascii_lowercase();
        if code.contains('#') || code.contains('[') {
            return true;
        }
        let mut words = code.split_whitespace();
        let o_word = words.next().is_some_and(|w| w.starts_with('o') && w.len() > 1);
        o_word && words.next().is_some_and(|w| CONTROL.contains(&w))
    })
}

/// A line's code: what `( )` comments and a `;` comment leave.
fn without_comments(line: &str) -> String {
    let mut code = String::new();
    let mut depth = 0usize;
    for c in line.chars() {
        match c {
            ';' if depth == 0 => break,
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            _ if depth == 0 => code.push(c),
            _ => {}
        }
    }
    code
}

/// The tools of the machine the corpus runs on: 1 to `TOOLS`, endmills of
/// `TOOL_DIAMETER` in the machine's unit.
pub const TOOLS: u32 = 20;
pub const TOOL_DIAMETER: f64 = 0.1;

/// Writes the machine the corpus runs on, a `ger.toml` in `dir`, and returns
/// its path: a full tool table (the corpus's programs name tools 1-20).
pub fn ger_config(dir: &Path) -> PathBuf {
    let config = dir.join("ger.toml");
    let tools: String = (1..=TOOLS)
        .map(|n| format!("[[tools]]\nnumber = {n}\nkind = \"endmill\"\ndiameter = {TOOL_DIAMETER}\n\n"))
        .collect();
    std::fs::write(&config, tools).unwrap();
    config
}

/// Runs `ger run --lenient` on a corpus file in `units` (the program's own)
/// on the machine of `config`, for at most `limit`.
pub fn translate(file: &Path, units: &str, config: &Path, limit: Duration) -> Finished {
    translate_for(file, units, config, "generic", limit)
}

/// [`translate`] for the controller `target` (`ger run --target`).
pub fn translate_for(file: &Path, units: &str, config: &Path, target: &str, limit: Duration) -> Finished {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ger"));
    command.args(["run", "--lenient", "--units", units, "--target", target, "--config"]);
    command.arg(config).arg(file).env("NO_COLOR", "1");
    super::process::run(&mut command, limit)
}

/// ger's first error message, for a table cell.
pub fn first_error(stderr: &str) -> String {
    let first = stderr.lines().find(|l| l.starts_with("error")).unwrap_or("error: (no message)");
    first.trim_start_matches("error: ").replace('|', "\\|")
}
