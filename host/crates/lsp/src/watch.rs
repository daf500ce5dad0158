//! Follows the files an open program's analysis reads besides its text: its
//! config (`ger.toml`, or the one given), a CAMotics project beside it, and
//! the wizards (`NAME.wasm` in its wizards folder). When one changes, the
//! programs that read it are analysed again, and the folder's wizards
//! described again. Folders are watched, not files: editors save by
//! writing a new file and renaming it over the old one. The server does
//! its own watching, so every editor gets it, whether or not its client
//! offers `workspace/didChangeWatchedFiles`.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use notify::{Event, EventKind, RecursiveMode, Watcher};

use ger_engine::canonical_path;

/// What one open program depends on, canonical.
pub struct Watched {
    pub config: PathBuf,
    pub folder: PathBuf,
    pub wizards: PathBuf,
}

impl Watched {
    pub fn new(config: &Path, folder: &Path, wizards: &Path) -> Watched {
        Watched { config: canonical_path(config), folder: canonical_path(folder), wizards: canonical_path(wizards) }
    }

    /// Whether a change to `path` (canonical) changes the program's analysis.
    pub fn reads(&self, path: &Path) -> bool {
        let in_folder = |folder: &Path, extension: &str| {
            path.parent() == Some(folder) && path.extension().is_some_and(|e| e == extension)
        };
        path == self.config || in_folder(&self.wizards, "wasm") || in_folder(&self.folder, "camotics")
    }
}

/// What the watcher asks of the server.
pub trait Follower {
    /// What each open program depends on now.
    fn watched(&self) -> Vec<Watched>;
    /// These files changed (canonical paths).
    fn files_changed(&self, paths: &[PathBuf]);
    fn stopping(&self) -> bool;
}

/// Follows `follower`'s files on the calling thread until it stops. A
/// platform with no watcher leaves the server without this: changes then
/// show at the program's next edit, as before.
pub fn follow(follower: &dyn Follower) {
    let (tx, rx) = mpsc::channel();
    let Ok(mut watcher) = notify::recommended_watcher(tx) else { return };
    let (mut folders, mut missing) = (HashSet::new(), HashSet::new());
    while !follower.stopping() {
        let watched = follower.watched();
        // A folder that was missing and is there now (a wizards folder made
        // after the program was opened): what is in it is new to the analyses.
        let mut appeared = Vec::new();
        for w in &watched {
            for folder in [w.config.parent(), Some(w.folder.as_path()), Some(w.wizards.as_path())].into_iter().flatten()
            {
                if folders.contains(folder) {
                    continue;
                }
                if watcher.watch(folder, RecursiveMode::NonRecursive).is_err() {
                    missing.insert(folder.to_path_buf());
                    continue;
                }
                folders.insert(folder.to_path_buf());
                if missing.remove(folder) {
                    let entries = std::fs::read_dir(folder).into_iter().flatten().flatten();
                    appeared.extend(entries.map(|entry| canonical_path(&entry.path())));
                }
            }
        }
        if !appeared.is_empty() {
            follower.files_changed(&appeared);
        }
        let first = match rx.recv_timeout(Duration::from_millis(250)) {
            Ok(event) => event,
            Err(RecvTimeoutError::Timeout) => continue,
            Err(RecvTimeoutError::Disconnected) => return,
        };
        // Saves come in bursts: let them settle, then react once.
        std::thread::sleep(Duration::from_millis(50));
        let mut paths = Vec::new();
        for event in std::iter::once(first).chain(rx.try_iter()) {
            let Ok(Event { kind, paths: named, .. }) = event else { continue };
            if !matches!(kind, EventKind::Access(_)) {
                paths.extend(named.iter().map(|p| canonical_path(p)));
            }
        }
        if paths.iter().any(|path| watched.iter().any(|w| w.reads(path))) {
            follower.files_changed(&paths);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_program_reads_its_config_its_wizards_and_a_camotics_project_beside_it() {
        let w = Watched {
            config: PathBuf::from("/p/ger.toml"),
            folder: PathBuf::from("/p"),
            wizards: PathBuf::from("/p/wizards"),
        };
        assert!(w.reads(Path::new("/p/ger.toml")));
        assert!(w.reads(Path::new("/p/wizards/pocket.wasm")));
        assert!(w.reads(Path::new("/p/job.camotics")));
        // The program itself (the editor's text is what counts), a wizard's
        // source, another folder's config: no.
        assert!(!w.reads(Path::new("/p/part.nc")));
        assert!(!w.reads(Path::new("/p/wizards/pocket/src/lib.rs")));
        assert!(!w.reads(Path::new("/q/ger.toml")));
    }
}
