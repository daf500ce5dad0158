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

use notify::{Event, EventKind, RecommendedWatcher, RecursiveMode, Watcher};

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

/// The folders watched, shared by the worker, which adds a program's
/// before it reads them (so that no change after the read goes unseen),
/// and the watching thread, which tries again those that were missing.
pub struct Folders {
    watcher: RecommendedWatcher,
    watched: HashSet<PathBuf>,
    missing: HashSet<PathBuf>,
}

/// Events from the watcher, for [`follow`].
pub type Events = mpsc::Receiver<notify::Result<Event>>;

impl Folders {
    /// A watcher and its events; `None` on a platform with none: changes
    /// then show at the program's next edit.
    pub fn new() -> Option<(Folders, Events)> {
        let (tx, rx) = mpsc::channel();
        let watcher = notify::recommended_watcher(tx).ok()?;
        Some((Folders { watcher, watched: HashSet::new(), missing: HashSet::new() }, rx))
    }

    /// Watches the folders `program` reads; the files in those of them that
    /// were missing before and are there now (a wizards folder made after
    /// the program was opened), which are new to its analysis.
    pub fn add(&mut self, program: &Watched) -> Vec<PathBuf> {
        let mut appeared = Vec::new();
        let folders = [program.config.parent(), Some(program.folder.as_path()), Some(program.wizards.as_path())];
        for folder in folders.into_iter().flatten() {
            if self.watched.contains(folder) {
                continue;
            }
            if self.watcher.watch(folder, RecursiveMode::NonRecursive).is_err() {
                self.missing.insert(folder.to_path_buf());
                continue;
            }
            self.watched.insert(folder.to_path_buf());
            if self.missing.remove(folder) {
                let entries = std::fs::read_dir(folder).into_iter().flatten().flatten();
                appeared.extend(entries.map(|entry| canonical_path(&entry.path())));
            }
        }
        appeared
    }
}

/// What the watching thread asks of the server.
pub trait Follower {
    /// What each open program depends on now.
    fn watched(&self) -> Vec<Watched>;
    /// Watches what `program` reads (see [`Folders::add`]).
    fn watch(&self, program: &Watched) -> Vec<PathBuf>;
    /// These files changed (canonical paths); those no open program reads
    /// are passed over.
    fn files_changed(&self, paths: &[PathBuf]);
    fn stopping(&self) -> bool;
}

/// Follows `follower`'s files on the calling thread until it stops.
pub fn follow(follower: &dyn Follower, events: &Events) {
    while !follower.stopping() {
        let appeared: Vec<PathBuf> = follower.watched().iter().flat_map(|w| follower.watch(w)).collect();
        if !appeared.is_empty() {
            follower.files_changed(&appeared);
        }
        let first = match events.recv_timeout(Duration::from_millis(250)) {
            Ok(event) => event,
            Err(RecvTimeoutError::Timeout) => continue,
            Err(RecvTimeoutError::Disconnected) => return,
        };
        // Saves come in bursts: let them settle, then react once.
        std::thread::sleep(Duration::from_millis(50));
        let mut paths = Vec::new();
        for event in std::iter::once(first).chain(events.try_iter()) {
            let Ok(Event { kind, paths: named, .. }) = event else { continue };
            if !matches!(kind, EventKind::Access(_)) {
                paths.extend(named.iter().map(|p| canonical_path(p)));
            }
        }
        // Judged by the follower against the programs open now, not those
        // of the loop's start: one opened since may read these files.
        if !paths.is_empty() {
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

    /// A follower with no program open until the watching thread has
    /// started waiting for events, as when an editor opens a program and
    /// saves a wizard beside it within the thread's first wait.
    struct OpenedLate {
        asked: std::sync::Mutex<Option<mpsc::Sender<()>>>,
        changed: mpsc::Sender<Vec<PathBuf>>,
        stopping: std::sync::atomic::AtomicBool,
    }

    impl Follower for OpenedLate {
        fn watched(&self) -> Vec<Watched> {
            // The first call finds nothing open and says so.
            if let Some(asked) = self.asked.lock().unwrap().take() {
                asked.send(()).unwrap();
            }
            Vec::new()
        }
        fn watch(&self, _: &Watched) -> Vec<PathBuf> {
            Vec::new()
        }
        fn files_changed(&self, paths: &[PathBuf]) {
            self.changed.send(paths.to_vec()).unwrap();
        }
        fn stopping(&self) -> bool {
            self.stopping.load(std::sync::atomic::Ordering::SeqCst)
        }
    }

    #[test]
    fn a_change_just_after_a_program_opens_reaches_the_follower() {
        let (asked_tx, asked) = mpsc::channel();
        let (changed_tx, changed) = mpsc::channel();
        let follower =
            OpenedLate { asked: std::sync::Mutex::new(Some(asked_tx)), changed: changed_tx, stopping: false.into() };
        let (events_tx, events) = mpsc::channel();
        let follower = &follower;
        std::thread::scope(|scope| {
            scope.spawn(move || follow(follower, &events));
            asked.recv().unwrap();
            let wizard = PathBuf::from("/p/wizards/bc.wasm");
            let event = Event::new(EventKind::Create(notify::event::CreateKind::File)).add_path(wizard.clone());
            events_tx.send(Ok(event)).unwrap();
            let reported = changed.recv_timeout(Duration::from_secs(10));
            follower.stopping.store(true, std::sync::atomic::Ordering::SeqCst);
            assert_eq!(reported, Ok(vec![wizard]));
        });
    }
}
