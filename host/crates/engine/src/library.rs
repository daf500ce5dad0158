//! Where a program's subprograms come from: its own text, read again when a
//! call names one not seen yet, and files of their own beside it.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use ger_core::config::DialectConfig;
use ger_core::macros::Wanted;
use ger_core::passes::{self, Library};
use ger_core::statement::Dialect;

use crate::source::Source;

/// The subprograms of `source`, and the program itself again, for M47.
pub(crate) fn library<'a>(source: &'a Source, dialect: &'a DialectConfig) -> Library<'a> {
    let library = Library::scanning(move || Library::scan(source.open(), dialect))
        .with_restart(move || Box::new(passes::parse(source.open(), dialect)));
    match dialect.name {
        Dialect::Lenient => library
            .with_files(move |number| program_file(&source.dir(), number, dialect))
            .with_program_texts(move |wanted| match wanted {
                Wanted::Program(number) => program_text(&source.dir(), number),
                Wanted::Subroutine(label) => subroutine_text(&source.dir(), &dialect.subroutine_path, label),
            }),
        Dialect::Strict => library,
    }
}

/// A program kept in a file of its own beside the calling one, as a Fanuc or
/// Haas keeps programs by number: a G-code file whose name holds the number
/// (`O1002.nc`, `o01002.tap`, `bracket_o1002.cnc`) and whose first O word is it.
fn program_file(dir: &Path, number: u32, dialect: &DialectConfig) -> Option<(String, passes::Body)> {
    candidates(dir, number).into_iter().find_map(|path| {
        let file = File::open(&path).ok()?;
        let body = Library::scan_file(BufReader::new(file), number, dialect)?;
        Some((path.file_name()?.to_string_lossy().into_owned(), body))
    })
}

/// The text of the first file [`program_file`] would take, for the
/// interpreter stage (which checks its first O word itself).
fn program_text(dir: &Path, number: u32) -> Option<(String, Vec<u8>)> {
    candidates(dir, number).into_iter().find_map(|path| {
        let text = std::fs::read(&path).ok()?;
        Some((path.file_name()?.to_string_lossy().into_owned(), text))
    })
}

/// LinuxCNC's `o<name> call` of a subroutine the program does not define:
/// `name.ngc` (the label in lower case, as LinuxCNC names the file) in the
/// program's folder, then in each of `[dialect] subroutine_path`'s.
fn subroutine_text(dir: &Path, path: &[PathBuf], label: &str) -> Option<(String, Vec<u8>)> {
    // A label is a word of the program: it may not climb out of the folders.
    if label.is_empty() || label.contains(['/', '\\']) || label.starts_with('.') {
        return None;
    }
    let file = format!("{label}.ngc");
    std::iter::once(dir).chain(path.iter().map(PathBuf::as_path)).find_map(|folder| {
        let path = folder.join(&file);
        // A regular file only: a FIFO or device named so would never end.
        let text = path.is_file().then(|| std::fs::read(&path).ok()).flatten()?;
        Some((path.display().to_string(), text))
    })
}

/// The files whose names say they hold program `number`, in order.
fn candidates(dir: &Path, number: u32) -> Vec<PathBuf> {
    const EXTENSIONS: [&str; 7] = ["nc", "ngc", "tap", "cnc", "gcode", "txt", ""];
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let mut candidates: Vec<PathBuf> = entries
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| {
            let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
            let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
            path.is_file() && EXTENSIONS.contains(&extension.as_str()) && names_program(stem, number)
        })
        .collect();
    candidates.sort();
    candidates
}

/// Whether a file's name ends with program `number`: `O1002`, `1002`,
/// `O01002`, `part-o1002`.
fn names_program(stem: &str, number: u32) -> bool {
    let stem = stem.to_ascii_lowercase();
    let digits = stem.len() - stem.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let (head, tail) = stem.split_at(stem.len() - digits);
    let head = head.strip_suffix('o').unwrap_or(head);
    digits > 0
        && tail.parse::<u32>() == Ok(number)
        && (head.is_empty() || !head.ends_with(|c: char| c.is_ascii_alphanumeric()))
}

#[cfg(test)]
mod tests {
    use super::names_program;

    #[test]
    fn a_file_names_the_program_whose_number_ends_its_name() {
        for stem in ["O1002", "o01002", "1002", "bracket_o1002", "part-O1002"] {
            assert!(names_program(stem, 1002), "{stem}");
        }
        for stem in ["O10020", "bracketo1002", "O1003", "part", "x1002"] {
            assert!(!names_program(stem, 1002), "{stem}");
        }
    }
}
