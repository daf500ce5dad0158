//! The wizards in a directory: `NAME.wasm` files and the folders they are
//! built from. A call finds its wizard by name, ignoring case, `-` and `_`:
//! `BoltCircle` runs `boltcircle.wasm` or `bolt-circle.wasm`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::build::Source;

pub use ger_core::wizard::key;

/// One wizard: its component, and the folder it is built from, if any.
#[derive(Clone, Debug)]
pub struct Entry {
    /// The file or folder name, as found.
    pub name: String,
    /// Where the component is or will be: `DIR/NAME.wasm`.
    pub wasm: PathBuf,
    pub source: Option<Source>,
}

#[derive(Clone, Debug, Default)]
pub struct Catalog {
    entries: BTreeMap<String, Entry>,
}

impl Catalog {
    pub fn find(&self, name: &str) -> Option<&Entry> {
        self.entries.get(&key(name))
    }

    pub fn entries(&self) -> impl Iterator<Item = &Entry> {
        self.entries.values()
    }

    pub fn names(&self) -> Vec<String> {
        self.entries.values().map(|e| e.name.clone()).collect()
    }
}

/// A wizards directory that cannot be read.
#[derive(Debug, thiserror::Error)]
#[error("cannot read the wizards directory {}: {cause}", dir.display())]
pub struct ScanError {
    pub dir: std::path::PathBuf,
    pub cause: std::io::Error,
}

/// Looks through `dir` (not its subfolders' subfolders).
pub fn scan(dir: &Path) -> Result<Catalog, ScanError> {
    let read = std::fs::read_dir(dir).map_err(|cause| ScanError { dir: dir.to_path_buf(), cause })?;
    let mut entries = BTreeMap::new();
    for item in read.flatten() {
        let path = item.path();
        let Some(file_name) = path.file_name().and_then(|n| n.to_str()).map(str::to_string) else {
            continue;
        };
        // Build output and tool caches live beside the wizards.
        if file_name.starts_with('.') || file_name == "target" || file_name == "node_modules" {
            continue;
        }
        if path.is_dir() {
            if let Some(source) = Source::detect(&path) {
                let wasm = dir.join(format!("{file_name}.wasm"));
                let entry = Entry { name: file_name.clone(), wasm, source: Some(source) };
                entries.insert(key(&file_name), entry);
            }
        } else if let Some(stem) = file_name.strip_suffix(".wasm") {
            entries.entry(key(stem)).or_insert_with(|| Entry {
                name: stem.to_string(),
                wasm: path.clone(),
                source: None,
            });
        }
    }
    Ok(Catalog { entries })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_match_ignoring_case_dashes_and_underscores() {
        assert_eq!(key("BoltCircle"), "boltcircle");
        assert_eq!(key("bolt-circle"), "boltcircle");
        assert_eq!(key("BOLT_circle"), "boltcircle");
    }

    #[test]
    fn a_folder_with_sources_and_a_bare_wasm_are_both_wizards() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("bolt-circle")).unwrap();
        std::fs::write(dir.path().join("bolt-circle/Cargo.toml"), "").unwrap();
        std::fs::write(dir.path().join("Face.wasm"), b"").unwrap();
        std::fs::create_dir(dir.path().join("notes")).unwrap();
        std::fs::create_dir(dir.path().join("target")).unwrap();
        let catalog = scan(dir.path()).unwrap();
        assert_eq!(catalog.names(), ["bolt-circle", "Face"]);
        let entry = catalog.find("BoltCircle").unwrap();
        assert_eq!(entry.wasm, dir.path().join("bolt-circle.wasm"));
        assert!(catalog.find("face").unwrap().source.is_none());
        assert!(scan(&dir.path().join("missing"))
            .unwrap_err()
            .to_string()
            .contains("cannot read the wizards directory"));
    }
}
