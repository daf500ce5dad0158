//! What each G and M code means in ger, for hover and completion: read from
//! the README's table of codes, the one place it is written, built into the
//! server.

use std::collections::BTreeMap;
use std::sync::OnceLock;

const README: &str = include_str!("../../../../README.md");

/// One row of the table: a code (or a family of codes) in both dialects.
#[derive(Debug)]
pub struct Row {
    /// The table it is in: "Moves", "Offsets", ...
    pub section: String,
    /// The first cell: the code as written, with its words.
    pub form: String,
    /// ✓ or ✗ in the strict and lenient dialects; `None` in the table of
    /// codes refused in both.
    pub strict: Option<bool>,
    pub lenient: Option<bool>,
    /// What it becomes, or why it is refused.
    pub meaning: String,
}

impl Row {
    /// The row as hover text (Markdown).
    pub fn markdown(&self) -> String {
        let mark = |accepted: bool| if accepted { "accepted" } else { "refused" };
        let dialects = match (self.strict, self.lenient) {
            (Some(strict), Some(lenient)) => format!("strict: {}, lenient: {}", mark(strict), mark(lenient)),
            _ => "refused in both dialects".to_string(),
        };
        format!("**{}** ({}; {dialects})\n\n{}", self.form, self.section, self.meaning)
    }
}

/// The table, by code (`G02`, `M98`, `G59.1`).
pub struct Codes {
    rows: Vec<Row>,
    by_code: BTreeMap<String, Vec<usize>>,
    /// The row for an M code no other row names.
    other_m: Option<usize>,
}

/// The README's table, read once.
pub fn codes() -> &'static Codes {
    static CODES: OnceLock<Codes> = OnceLock::new();
    CODES.get_or_init(|| Codes::read(README))
}

impl Codes {
    /// The rows of the tables in `markdown`'s "## Codes" section.
    fn read(markdown: &str) -> Codes {
        let mut codes = Codes { rows: Vec::new(), by_code: BTreeMap::new(), other_m: None };
        let Some(start) = markdown.find("\n## Codes\n") else { return codes };
        let section = &markdown[start + 1..];
        let end = section[3..].find("\n## ").map_or(section.len(), |e| e + 3);
        let mut heading = String::new();
        for line in section[..end].lines() {
            if let Some(title) = line.strip_prefix("### ") {
                heading = title.to_string();
                continue;
            }
            let Some(cells) = row_cells(line) else { continue };
            let row = match cells.as_slice() {
                [form, strict, lenient, meaning] => Row {
                    section: heading.clone(),
                    form: form.to_string(),
                    strict: Some(strict.contains('✓')),
                    lenient: Some(lenient.contains('✓')),
                    meaning: plain_links(meaning),
                },
                [form, why] => Row {
                    section: heading.clone(),
                    form: form.to_string(),
                    strict: None,
                    lenient: None,
                    meaning: plain_links(why),
                },
                _ => continue,
            };
            let index = codes.rows.len();
            if row.form.starts_with("any other M code") {
                codes.other_m = Some(index);
            } else {
                for code in codes_in(&row.form) {
                    codes.by_code.entry(code).or_default().push(index);
                }
            }
            codes.rows.push(row);
        }
        codes
    }

    /// The rows about `code`, as [`name`] writes it.
    pub fn rows(&self, code: &str) -> Vec<&Row> {
        match self.by_code.get(code) {
            Some(rows) => rows.iter().map(|&i| &self.rows[i]).collect(),
            None if code.starts_with('M') => self.other_m.map(|i| &self.rows[i]).into_iter().collect(),
            None => Vec::new(),
        }
    }

    /// Every code the table names, with its rows.
    pub fn all(&self) -> impl Iterator<Item = (&str, Vec<&Row>)> {
        self.by_code.iter().map(|(code, rows)| (code.as_str(), rows.iter().map(|&i| &self.rows[i]).collect()))
    }
}

/// A code as the table writes it: the letter, two digits at least, and a
/// decimal if it has one (`G01`, `G59.1`, `M198`).
pub fn name(letter: char, value: f64) -> String {
    let whole = value.trunc();
    let tenths = ((value - whole) * 10.0).round() as u32;
    if tenths == 0 {
        format!("{letter}{:02}", whole as u64)
    } else {
        format!("{letter}{:02}.{tenths}", whole as u64)
    }
}

/// The cells of a table row (`| a | b |`), not of its header or rule.
fn row_cells(line: &str) -> Option<Vec<&str>> {
    let inner = line.strip_prefix('|')?.strip_suffix('|')?;
    let cells: Vec<&str> = inner.split(" | ").map(str::trim).collect();
    let header = cells[0] == "code" || cells[0].starts_with("---");
    (!header).then_some(cells)
}

/// `[text](#anchor)` as `text`: the README's anchors mean nothing in an editor.
fn plain_links(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(open) = rest.find('[') {
        let after = &rest[open + 1..];
        match after.find("](").and_then(|close| Some((close, after[close..].find(')')? + close))) {
            Some((close, end)) if !after[..close].contains('[') => {
                out.push_str(&rest[..open]);
                out.push_str(&after[..close]);
                rest = &after[end + 1..];
            }
            _ => {
                out.push_str(&rest[..=open]);
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// The G and M codes a first cell names: each code in its `quoted` parts,
/// and the ones between two quoted codes joined by ` ... ` (`G54` ... `G59`).
fn codes_in(form: &str) -> Vec<String> {
    let quoted: Vec<&str> = form.split('`').skip(1).step_by(2).collect();
    let mut found = Vec::new();
    for (i, part) in quoted.iter().enumerate() {
        let here: Vec<(char, f64)> = part.split_whitespace().filter_map(code_word).collect();
        let between = form.split('`').nth(2 * i + 2).unwrap_or("");
        let next = quoted.get(i + 1).and_then(|p| p.split_whitespace().next()).and_then(code_word);
        if let (Some(&(letter, from)), Some((to_letter, to)), true) = (here.first(), next, between.trim() == "...") {
            if letter == to_letter {
                // Whole codes count by one, decimal ones (G59.1 ... G59.3) by a tenth.
                let step = if from.fract() == 0.0 && to.fract() == 0.0 { 1.0 } else { 0.1 };
                let mut value = from;
                while value < to - step / 2.0 {
                    found.push(name(letter, value));
                    value += step;
                }
            }
        }
        found.extend(here.iter().map(|&(letter, value)| name(letter, value)));
    }
    found.sort();
    found.dedup();
    found
}

/// `G02`, `M98`, `G59.1` (a G or M and a number), not `Xn` or `Pw`.
fn code_word(word: &str) -> Option<(char, f64)> {
    let mut chars = word.chars();
    let letter = chars.next()?.to_ascii_uppercase();
    let number = chars.as_str();
    let digits =
        number.chars().all(|c| c.is_ascii_digit() || c == '.') && number.starts_with(|c: char| c.is_ascii_digit());
    (matches!(letter, 'G' | 'M') && digits).then(|| number.parse().ok()).flatten().map(|value| (letter, value))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_readme_rows_are_found_by_code() {
        let codes = codes();
        let g01 = codes.rows("G01");
        assert_eq!(g01.len(), 1);
        assert_eq!(g01[0].section, "Moves");
        assert_eq!((g01[0].strict, g01[0].lenient), (Some(true), Some(true)));
        assert!(g01[0].meaning.starts_with("a feed move"), "{}", g01[0].meaning);
        // G02 has a row for I/J/K, one for R and one for P or L turns.
        assert_eq!(codes.rows("G02").len(), 3);
        // Ranges: G54 ... G59, and G59.1 ... G59.3.
        assert!(codes.rows("G56")[0].form.contains("G54"));
        assert!(codes.rows("G59.2")[0].form.contains("G59.1"));
        // M02: accepted only in the lenient dialect.
        let m02 = codes.rows("M02");
        assert_eq!((m02[0].strict, m02[0].lenient), (Some(false), Some(true)));
        // Refused in both, and an M code no row names.
        assert_eq!(codes.rows("G96")[0].strict, None);
        assert!(codes.rows("M62")[0].form.starts_with("any other M code"));
        assert!(codes.rows("M64")[0].form.starts_with("any other M code"));
        assert!(codes.rows("G07").is_empty());
    }

    #[test]
    fn codes_are_named_as_the_table_writes_them() {
        assert_eq!(name('G', 1.0), "G01");
        assert_eq!(name('G', 59.1), "G59.1");
        assert_eq!(name('G', 5.0), "G05");
        assert_eq!(name('M', 198.0), "M198");
    }

    #[test]
    fn a_first_cell_names_its_codes_and_ranges() {
        assert_eq!(codes_in("`G02` / `G03 [Xn] [In]`"), ["G02", "G03"]);
        assert_eq!(codes_in("`G54` ... `G57`"), ["G54", "G55", "G56", "G57"]);
        assert_eq!(codes_in("`G38.2` ... `G38.4`, `G31`"), ["G31", "G38.2", "G38.3", "G38.4"]);
        assert_eq!(codes_in("`Xn Yn Zn Fn` alone"), Vec::<String>::new());
        assert_eq!(plain_links("see [Splines](#splines) and [x]"), "see Splines and [x]");
    }
}
