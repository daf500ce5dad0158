//! Follows the files a session depends on (the program, its config, a
//! CAMotics project beside it, the wizards' `.wasm`) and tells the session
//! when one changes. Folders are watched, not files: editors often save by
//! writing a new file and renaming it over the old one, which a watch on the
//! old file would not see.

use std::collections::HashSet;
use std::path::Path;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::Arc;
use std::time::Duration;

use notify::{Event, EventKind, RecommendedWatcher, RecursiveMode, Watcher};

use ger_engine::canonical_path as canonical;

use crate::session::Session;
use crate::Error;

/// Starts following `session`'s files on a thread of its own.
pub(crate) fn start(session: Arc<Session>) -> Result<(), Error> {
    let (tx, rx) = mpsc::channel();
    let watcher = notify::recommended_watcher(tx).map_err(Error::Watch)?;
    std::thread::Builder::new()
        .name("ger view watcher".to_string())
        .spawn(move || follow(watcher, &rx, &session))
        .map_err(|cause| Error::Start { what: "watch for changes", cause })?;
    Ok(())
}

fn follow(mut watcher: RecommendedWatcher, events: &mpsc::Receiver<notify::Result<Event>>, session: &Session) {
    // Wizards are the NAME.wasm files directly in the wizards folder; their
    // sources and build folders below it are not watched.
    let wizards = canonical(session.wizards());
    let mut watched = HashSet::new();
    if watcher.watch(&wizards, RecursiveMode::NonRecursive).is_ok() {
        watched.insert(wizards.clone());
    }
    loop {
        // The page may have opened another program since: watch its folder too.
        let (program, config) = session.watched();
        let (program, config) = (canonical(&program), canonical(&config));
        for folder in [program.parent(), config.parent()].into_iter().flatten() {
            if !watched.contains(folder) && watcher.watch(folder, RecursiveMode::NonRecursive).is_ok() {
                watched.insert(folder.to_path_buf());
            }
        }
        let first = match events.recv_timeout(Duration::from_millis(250)) {
            Ok(event) => event,
            Err(RecvTimeoutError::Timeout) => continue,
            Err(RecvTimeoutError::Disconnected) => return,
        };
        // Saves come in bursts: let them settle, then react once.
        std::thread::sleep(Duration::from_millis(50));
        let (mut file, mut machine) = (false, false);
        for event in std::iter::once(first).chain(events.try_iter()) {
            let Ok(event) = event else { continue };
            if matches!(event.kind, EventKind::Access(_)) {
                continue;
            }
            for path in event.paths.iter().map(|p| canonical(p)) {
                file |= path == program;
                let beside = |folder: &Path, extension: &str| {
                    path.parent() == Some(folder) && path.extension().is_some_and(|e| e == extension)
                };
                // A CAMotics project in the program's folder may give its tools and stock.
                machine |= path == config
                    || beside(&wizards, "wasm")
                    || program.parent().is_some_and(|folder| beside(folder, "camotics"));
            }
        }
        if file {
            session.file_changed();
        }
        if machine {
            session.machine_changed();
        }
    }
}
