//! The tools and stock a program is simulated with, and where each came
//! from. `ger.toml`'s `[[tools]]` and `[stock]` always win; what they leave
//! out comes from a CAMotics project beside the program ([`camotics`]), then
//! from the comments the CAM system wrote in it ([`comments`]); tool 1 is
//! then the default quarter-inch endmill. Nothing here reads files: the CLI
//! hands in the program's text and the project's.

pub mod camotics;
pub mod comments;

use std::collections::BTreeMap;
use std::fmt;
use std::io::BufRead;

use serde::Serialize;

use crate::config::{Bounds, Config, StockConfig, Tool};
use crate::lex::{Lexed, Lexer, Lines, TokenKind};
use crate::statement::{Dialect, Units};
use comments::{Block, Described, Found};

/// Where a tool of the table in force came from.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "from", rename_all = "kebab-case")]
pub enum ToolSource {
    /// `[[tools]]` in this config file.
    Config { file: String },
    /// The tools of this CAMotics project.
    Camotics { file: String },
    /// A comment the CAM system wrote at this line of the program.
    Comment { line: u32 },
    /// Nothing describes tool 1: it is a quarter-inch endmill.
    Default,
}

impl fmt::Display for ToolSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ToolSource::Config { file } => write!(f, "from {file}"),
            ToolSource::Camotics { file } => write!(f, "from the CAMotics project {file}"),
            ToolSource::Comment { line } => write!(f, "from the program's comment at line {line}"),
            ToolSource::Default => write!(f, "the default"),
        }
    }
}

/// At most this many tools are taken from a program's comments or a project.
pub const MAX_DESCRIBED: usize = 1000;

/// A tool a comment describes, with its line and the unit of its lengths
/// (`None`: the machine's).
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    pub described: Described,
    pub units: Option<Units>,
    pub line: u32,
}

/// What a program's comments describe.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProgramTools {
    /// The first description of each tool number.
    pub tools: BTreeMap<u32, Entry>,
    /// The first `STOCK/BLOCK`, its unit (`None`: the machine's) and its line.
    pub stock: Option<(Block, Option<Units>, u32)>,
}

/// Reads the comments of a program, a line at a time, giving each
/// description the tool it belongs to: its own number, else the tool of the
/// next tool change if one comes before the next move, else the tool loaded
/// then (tool 1 before any `M06`). Lengths are in the unit the comment
/// names, else in the program's where it is (the units in force, or before
/// any `G20`/`G21` the first one's), else in the machine's.
///
/// Only the lines that can matter are lexed (with ger's own lexer, so a
/// comment is what the translation takes for one): those with a T word, an
/// M06, a G20 or G21, a `;`, a comment over several lines (lexed whole), a
/// comment that says something of a tool or the stock, and every line while
/// a description waits for the move that settles it. The rest of a long
/// program, its moves and their remarks, is passed over at the cost of
/// finding each line's end and its comments' parentheses.
pub fn scan(reader: impl BufRead, dialect: Dialect) -> ProgramTools {
    let mut scan = Scan { loaded: 1, selected: 1, ..Scan::default() };
    let mut lines = Lines::new(reader);
    let mut line = Vec::new();
    let mut number = 0u32;
    // Lines to lex together, from line `first`: a comment may span them.
    let mut chunk = Vec::new();
    let mut first = 0;
    let mut depth = 0usize;
    while let Ok(Some(_)) = lines.read(&mut line) {
        number += 1;
        let inside = depth > 0;
        if !(inside || scan.pending.is_some() || scan.in_list || relevant(&line)) {
            continue;
        }
        for &b in &line {
            match b {
                b'(' => depth += 1,
                b')' => depth = depth.saturating_sub(1),
                _ => {}
            }
        }
        if chunk.is_empty() {
            first = number;
        }
        chunk.extend_from_slice(&line);
        chunk.push(b'\n');
        // A comment never closed is let go of at CHUNK bytes: the translation reports it.
        if depth == 0 || chunk.len() > CHUNK {
            scan.lex(&chunk, first, dialect);
            chunk.clear();
            depth = 0;
        }
    }
    if !chunk.is_empty() {
        scan.lex(&chunk, first, dialect);
    }
    if let Some(entry) = scan.pending.take() {
        scan.add(scan.loaded, entry);
    }
    let first_units = scan.first_units;
    let mut found = scan.found;
    for entry in found.tools.values_mut() {
        entry.units = entry.units.or(first_units);
    }
    if let Some((_, units, _)) = &mut found.stock {
        *units = units.or(first_units);
    }
    found
}

/// The most of a comment left open that the scan holds.
const CHUNK: usize = 1 << 16;

/// Whether a line may hold what the scan looks for: a T word, an M06, a
/// G20 or G21, a `;`, a comment left open or closed that was not opened, or
/// a comment that [`comments::read`] finds something in. In doubt, yes.
fn relevant(line: &[u8]) -> bool {
    let mut rest = line;
    let mut parentheses = false;
    // The bytes worth a second look, found by a table: most of a move's are digits.
    while let Some(at) = rest.iter().position(|&b| MARKED[usize::from(b)]) {
        let after = &rest[at + 1..];
        let found = match rest[at] {
            b'G' | b'g' => code(after, &[b"20", b"21"]),
            b'M' | b'm' => code(after, &[b"6"]),
            b'(' | b')' => {
                parentheses = true;
                false
            }
            _ => true,
        };
        if found {
            return true;
        }
        rest = after;
    }
    parentheses && says_something(line)
}

/// Whether the comments of a line (its parentheses balanced, or it is
/// lexed to be sure) tell the scan anything.
fn says_something(line: &[u8]) -> bool {
    let (mut depth, mut start) = (0usize, 0);
    for (at, &b) in line.iter().enumerate() {
        match b {
            b'(' => {
                if depth == 0 {
                    start = at + 1;
                }
                depth += 1;
            }
            b')' if depth == 0 => return true,
            b')' => {
                depth -= 1;
                if depth == 0 && std::str::from_utf8(&line[start..at]).map_or(true, |c| comments::read(c).is_some()) {
                    return true;
                }
            }
            _ => {}
        }
    }
    depth > 0
}

const MARKED: [bool; 256] = {
    let mut marked = [false; 256];
    let bytes = b"();TtGgMm";
    let mut i = 0;
    while i < bytes.len() {
        marked[bytes[i] as usize] = true;
        i += 1;
    }
    marked
};

/// Whether `rest`, past spaces and leading zeros, starts with one of `numbers`.
fn code(rest: &[u8], numbers: &[&[u8]]) -> bool {
    let skip = rest.iter().take_while(|b| **b == b' ' || **b == b'0').count();
    numbers.iter().any(|n| rest[skip..].starts_with(n))
}

#[derive(Default)]
struct Scan {
    found: ProgramTools,
    /// The first tool described without a number, until the tool change or move it belongs to.
    pending: Option<Entry>,
    /// Inside Estlcam's list of required tools.
    in_list: bool,
    /// The last T word, and the tool the last M06 loaded.
    selected: u32,
    loaded: u32,
    /// An M06 in the block being read.
    changing: bool,
    units: Option<Units>,
    first_units: Option<Units>,
}

impl Scan {
    /// Follows the tokens of `text`, which starts at line `first` of the program.
    fn lex(&mut self, text: &[u8], first: u32, dialect: Dialect) {
        for item in Lexer::in_dialect(text, dialect) {
            let Lexed::Token(token) = item else { continue };
            match token.kind {
                TokenKind::Comment(text) => self.comment(&text, token.span.line + first - 1),
                TokenKind::Word { letter, value } => {
                    self.in_list = false;
                    match letter {
                        'T' if value >= 0.0 && value.fract() == 0.0 && value <= f64::from(u32::MAX) => {
                            self.selected = value as u32;
                            if let Some(entry) = self.pending.take() {
                                self.add(self.selected, entry);
                            }
                        }
                        'M' if value == 6.0 => self.changing = true,
                        'G' if value == 20.0 || value == 21.0 => {
                            let units = if value == 20.0 { Units::Inch } else { Units::Mm };
                            self.units = Some(units);
                            self.first_units.get_or_insert(units);
                        }
                        'X' | 'Y' | 'Z' => {
                            if let Some(entry) = self.pending.take() {
                                self.add(self.loaded, entry);
                            }
                        }
                        _ => {}
                    }
                }
                TokenKind::End => {
                    // M06 loads the tool its block (or an earlier one) selects.
                    if std::mem::take(&mut self.changing) {
                        self.loaded = self.selected;
                    }
                }
                _ => self.in_list = false,
            }
        }
    }

    fn comment(&mut self, text: &str, line: u32) {
        let listed = if self.in_list { comments::listed_name(text).map(Found::Tool) } else { None };
        match listed.or_else(|| comments::read(text)) {
            Some(Found::Tool(described)) => {
                let entry = Entry { units: described.units.or(self.units), described, line };
                match entry.described.number {
                    Some(number) => self.add(number, entry),
                    None => {
                        self.pending.get_or_insert(entry);
                    }
                }
            }
            Some(Found::Stock(block)) => {
                let units = self.units;
                self.found.stock.get_or_insert((block, units, line));
            }
            Some(Found::ToolList) => self.in_list = true,
            None => {}
        }
    }

    fn add(&mut self, number: u32, entry: Entry) {
        let tools = &mut self.found.tools;
        if tools.len() < MAX_DESCRIBED {
            tools.entry(number).or_insert(entry);
        }
    }
}

/// Settles `config`'s tool table and stock for a program: `[[tools]]` and
/// `[stock]` (from `config_file`) as they are; without them, the CAMotics
/// project's (named `project.0`), then what the program's comments
/// describe, converted to the machine's unit; tool 1 is the default if
/// nothing describes it. Every tool gets its source.
pub fn settle(
    config: &mut Config,
    config_file: Option<&str>,
    project: Option<(&str, &camotics::Project)>,
    program: &ProgramTools,
) {
    let units = config.units;
    if config.has_tool_table() {
        let file = config_file.unwrap_or("the config file").to_string();
        for (_, source) in &mut config.tool_sources {
            *source = ToolSource::Config { file: file.clone() };
        }
    } else {
        let mut table: Vec<(Tool, ToolSource)> = Vec::new();
        if let Some((file, project)) = project {
            for tool in project.tools.iter().take(MAX_DESCRIBED) {
                let tool = scaled(tool, Units::Mm.factor_to(units));
                table.push((tool, ToolSource::Camotics { file: file.to_string() }));
            }
        }
        for (&number, entry) in &program.tools {
            if table.iter().any(|(t, _)| t.number == number) {
                continue;
            }
            let d = &entry.described;
            let tool =
                Tool { flute_length: d.flute_length, tip_angle: d.tip_angle, ..Tool::new(number, d.kind, d.diameter) };
            let tool = scaled(&tool, entry.units.unwrap_or(units).factor_to(units));
            if usable(&tool, units) {
                table.push((tool, ToolSource::Comment { line: entry.line }));
            }
        }
        if !table.iter().any(|(t, _)| t.number == 1) {
            table.push((Tool::default_tool(units), ToolSource::Default));
        }
        config.tool_sources = table.iter().map(|(t, source)| (t.number, source.clone())).collect();
        config.tools = table.into_iter().map(|(t, _)| t).collect();
    }
    if config.stock == StockConfig::default() {
        config.stock = described_stock(units, project.map(|(_, p)| p), program).unwrap_or_default();
    }
}

/// The stock of a CAMotics project, else of a `STOCK/BLOCK` comment.
fn described_stock(units: Units, project: Option<&camotics::Project>, program: &ProgramTools) -> Option<StockConfig> {
    let box_of = |size: [f64; 3], origin: [f64; 3], factor: f64| {
        let size = size.map(|x| x * factor);
        let origin = origin.map(|x| x * factor);
        // What `[stock]` in ger.toml would accept.
        let bounds = Bounds::of(units);
        let sane = size.iter().all(|x| (bounds.smallest..=bounds.length).contains(x))
            && origin.iter().all(|x| x.abs() <= bounds.length);
        sane.then(|| StockConfig { size: Some(size), origin: Some(origin), ..StockConfig::default() })
    };
    match project.and_then(|p| p.workpiece) {
        Some(camotics::Workpiece::Bounds { min, max }) => {
            let size = std::array::from_fn(|i| max[i] - min[i]);
            return box_of(size, min.map(|x| -x), Units::Mm.factor_to(units));
        }
        Some(camotics::Workpiece::Automatic { margin_percent }) => {
            return Some(StockConfig { margin_percent: Some(margin_percent), ..StockConfig::default() });
        }
        None => {}
    }
    let (block, block_units, _) = program.stock?;
    box_of(block.size, block.origin, block_units.unwrap_or(units).factor_to(units))
}

fn scaled(tool: &Tool, factor: f64) -> Tool {
    Tool { diameter: tool.diameter * factor, flute_length: tool.flute_length.map(|l| l * factor), ..tool.clone() }
}

/// A tool the simulation can cut with: what `ger.toml` would accept, in `units`.
fn usable(tool: &Tool, units: Units) -> bool {
    let bounds = Bounds::of(units);
    let size = bounds.smallest..=bounds.tool;
    size.contains(&tool.diameter)
        && tool.flute_length.is_none_or(|l| size.contains(&l))
        && tool.tip_angle.is_none_or(|a| a > 0.0 && a < 180.0)
}

#[cfg(test)]
mod tests;
