//! Writing a file: the one way ger writes one, whichever command it is.
//!
//! What is at the path decides how:
//! - a regular file, or nothing yet: a temporary file in the same folder,
//!   fsynced and renamed over the path at [`OutputFile::commit`], with the old
//!   file's mode (and owner, where ger may set it). Until then the old file is
//!   untouched; an output dropped without a commit (an error, a panic) removes
//!   its temporary file, and so does Ctrl-C, SIGTERM or SIGHUP (Unix);
//! - a symlink: its target, by the rule above (the link stays a link);
//! - a device, a FIFO, a socket, or `-` (standard output): written directly,
//!   with no temporary file; [`OutputFile::withheld`] keeps what is written
//!   in an unnamed spool until the commit, so that a failed run writes nothing.

use std::fs::{File, Metadata};
use std::io::{self, BufWriter, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

use tempfile::NamedTempFile;

/// Symlinks followed before giving up, as Linux's own limit.
const MAX_LINKS: usize = 40;

/// What writing to a path means, by what is there now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A regular file, or nothing: replaced whole.
    Replace,
    /// A device, FIFO or socket: written as it comes.
    Direct,
    Folder,
}

fn kind(metadata: Option<&Metadata>) -> Kind {
    match metadata {
        None => Kind::Replace,
        Some(m) if m.is_dir() => Kind::Folder,
        Some(m) if m.is_file() => Kind::Replace,
        Some(_) => Kind::Direct,
    }
}

/// The path a chain of symlinks ends at (which may not exist yet: writing
/// through a dangling link creates its target, as the shell's `>` does).
fn resolve(path: &Path) -> io::Result<PathBuf> {
    let mut path = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&path) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = std::fs::read_link(&path)?;
                // A relative target is relative to the link's folder.
                path = path.parent().map_or_else(|| target.clone(), |folder| folder.join(&target));
            }
            Ok(_) => return Ok(path),
            Err(err) if err.kind() == io::ErrorKind::NotFound => return Ok(path),
            Err(err) => return Err(err),
        }
    }
    Err(io::Error::other(format!("more than {MAX_LINKS} symbolic links")))
}

/// What is at `path` now, if anything.
fn existing(path: &Path) -> io::Result<Option<Metadata>> {
    match std::fs::metadata(path) {
        Ok(metadata) => Ok(Some(metadata)),
        Err(err) if err.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(err) => Err(err),
    }
}

/// The temporary files that exist now, for the signal handler to remove.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    // Every change to the list is one push or removal: a panic cannot leave it half-changed.
    LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// The signal that came while a temporary file existed (0: none), set in
/// the signal handler itself, so that it is seen even when the work ends
/// before the thread that acts on the signal has run.
#[cfg(unix)]
static CAUGHT: std::sync::LazyLock<std::sync::Arc<std::sync::atomic::AtomicUsize>> =
    std::sync::LazyLock::new(Default::default);

/// Removes the temporary files, then ends as `signal` would have.
#[cfg(unix)]
fn end_by(signal: libc::c_int) -> ! {
    // Held to the end: no commit can rename a file once this has started.
    let live = live();
    for path in live.iter() {
        let _ = std::fs::remove_file(path);
    }
    let _ = signal_hook::low_level::emulate_default_handler(signal);
    std::process::exit(128 + signal)
}

/// On Ctrl-C, SIGTERM or SIGHUP: remove the temporary files, then end as
/// the signal would have. Installed with the first temporary file.
#[cfg(unix)]
fn remove_on_signal() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    static INSTALLED: std::sync::Once = std::sync::Once::new();
    INSTALLED.call_once(|| {
        // A signal ger was started ignoring (`nohup`, a shell's `&` without job
        // control) must stay ignored: a handler would make it end ger.
        let ignored = |signal| {
            let mut action: libc::sigaction = unsafe { std::mem::zeroed() };
            // SAFETY: a query only (no new action), into a value of the type it fills.
            let queried = unsafe { libc::sigaction(signal, std::ptr::null(), &mut action) } == 0;
            queried && action.sa_sigaction == libc::SIG_IGN
        };
        let wanted: Vec<_> = [SIGINT, SIGTERM, SIGHUP].into_iter().filter(|s| !ignored(*s)).collect();
        for signal in &wanted {
            let _ = signal_hook::flag::register_usize(*signal, CAUGHT.clone(), *signal as usize);
        }
        // Without the handler a signal still ends ger; only the temporary file would stay.
        let Ok(mut signals) = signal_hook::iterator::Signals::new(wanted) else { return };
        let _ = std::thread::Builder::new().name("ger signals".to_string()).spawn(move || {
            if let Some(signal) = signals.forever().next() {
                end_by(signal);
            }
        });
    });
}

/// Ends ger as the signal would have, if one came while an output was being
/// written: called last, so that a Ctrl-C during the run is never answered
/// by a normal exit because the work happened to finish first.
pub fn end_as_signalled() {
    #[cfg(unix)]
    match CAUGHT.load(std::sync::atomic::Ordering::SeqCst) {
        0 => {}
        signal => end_by(signal as libc::c_int),
    }
}

#[cfg(not(unix))]
fn remove_on_signal() {}

/// A regular file being replaced: the temporary file beside it, until the commit.
pub struct Replacement {
    temp: NamedTempFile,
    target: PathBuf,
    /// The file replaced, if there is one.
    old: Option<Metadata>,
    /// Dropped after `temp`, which removes the file unless it was committed.
    _listed: Listed,
}

impl Replacement {
    /// A temporary file for `path` (a symlink's target, if it is a link), which must be a
    /// regular file or not exist. It takes the old file's extension, for
    /// tools that look at names, and its mode (or, for a new file, what the umask allows).
    pub fn new(path: &Path) -> io::Result<Replacement> {
        let target = resolve(path)?;
        let old = existing(&target)?;
        if kind(old.as_ref()) != Kind::Replace {
            return Err(io::Error::other("not a regular file"));
        }
        Replacement::of(target, old)
    }

    fn of(target: PathBuf, old: Option<Metadata>) -> io::Result<Replacement> {
        let folder = target.parent().filter(|f| !f.as_os_str().is_empty()).unwrap_or(Path::new("."));
        let suffix = target.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
        let mut builder = tempfile::Builder::new();
        builder.suffix(&suffix);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            // Narrowed by the umask, as any new file is; an old file's exact mode is set below.
            let mode = old.as_ref().map_or(0o666, |m| m.permissions().mode() & 0o777);
            builder.permissions(std::fs::Permissions::from_mode(mode));
        }
        remove_on_signal();
        // Listed before a signal can find it made but not listed.
        let mut list = live();
        let temp = builder.tempfile_in(folder)?;
        let listed = Listed::new(&mut list, temp.path());
        drop(list);
        let replacement = Replacement { temp, target, old, _listed: listed };
        #[cfg(unix)]
        replacement.keep_owner_and_mode()?;
        Ok(replacement)
    }

    /// Gives the temporary file the old file's owner (where ger may: as root,
    /// or a group it is in) and then its mode, before anything is written to it.
    #[cfg(unix)]
    fn keep_owner_and_mode(&self) -> io::Result<()> {
        use std::os::unix::fs::MetadataExt;
        let Some(old) = &self.old else { return Ok(()) };
        let file = self.temp.as_file();
        let new = file.metadata()?;
        if (new.uid(), new.gid()) != (old.uid(), old.gid()) {
            // Not allowed is not an error: the file is then the writer's, as any editor leaves it.
            let _ = std::os::unix::fs::fchown(file, Some(old.uid()), Some(old.gid()));
        }
        // After the owner: changing it clears set-user-ID and set-group-ID.
        file.set_permissions(old.permissions())
    }

    /// Where the temporary file is, for a tool that writes the file itself.
    pub fn path(&self) -> &Path {
        self.temp.path()
    }

    /// Makes what was written the file: synced to disk, then renamed over the old one.
    pub fn commit(self) -> io::Result<()> {
        self.temp.as_file().sync_all()?;
        #[cfg(not(unix))]
        if let Some(old) = &self.old {
            self.temp.as_file().set_permissions(old.permissions())?;
        }
        let folder = self.target.parent().filter(|f| !f.as_os_str().is_empty()).unwrap_or(Path::new("."));
        {
            let mut list = live();
            self.temp.persist(&self.target).map_err(|err| err.error)?;
            list.retain(|p| *p != self._listed.0);
        }
        // The rename itself reaches the disk with the folder; a file system that
        // cannot sync a folder has still renamed the file.
        if let Ok(folder) = File::open(folder) {
            let _ = folder.sync_all();
        }
        Ok(())
    }
}

/// A temporary file's place in the list of those that exist, taken off when dropped.
struct Listed(PathBuf);

impl Listed {
    fn new(list: &mut Vec<PathBuf>, path: &Path) -> Listed {
        list.push(path.to_path_buf());
        Listed(path.to_path_buf())
    }
}

impl Drop for Listed {
    fn drop(&mut self) {
        live().retain(|p| *p != self.0);
    }
}

/// Where an output goes.
enum Sink {
    /// Boxed: the old file's metadata makes it large.
    Replace(BufWriter<Box<Replacement>>),
    Direct(BufWriter<ReaderGone<Box<dyn Write + Send>>>),
    /// Direct, but only at the commit: until then in an unnamed file the system removes with the process.
    Withheld {
        spool: BufWriter<File>,
        out: ReaderGone<Box<dyn Write + Send>>,
    },
}

impl Write for Replacement {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.temp.as_file_mut().write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// A file (or standard output) being written; see the module's rules.
pub struct OutputFile {
    sink: Sink,
}

impl OutputFile {
    /// An output to `path`, by what is there; `-` is standard output.
    pub fn create(path: &Path) -> io::Result<OutputFile> {
        OutputFile::open(path, false)
    }

    /// As [`OutputFile::create`], but a device, FIFO or standard output gets
    /// nothing until the commit: for `ger run`, which writes nothing when the program has errors.
    pub fn withheld(path: &Path) -> io::Result<OutputFile> {
        OutputFile::open(path, true)
    }

    fn open(path: &Path, withheld: bool) -> io::Result<OutputFile> {
        let out: Box<dyn Write + Send> = if path == Path::new("-") {
            Box::new(io::stdout())
        } else {
            let target = resolve(path)?;
            let metadata = existing(&target)?;
            match kind(metadata.as_ref()) {
                Kind::Folder => return Err(io::Error::other("it is a folder")),
                Kind::Replace => {
                    let replacement = Replacement::of(target, metadata)?;
                    let writer = BufWriter::with_capacity(1 << 16, Box::new(replacement));
                    return Ok(OutputFile { sink: Sink::Replace(writer) });
                }
                // Opened now, so a FIFO's reader is waited for (as the shell's `>` does) before any work.
                Kind::Direct => Box::new(std::fs::OpenOptions::new().write(true).open(&target)?),
            }
        };
        let out = ReaderGone { inner: out, gone: false };
        let sink = if withheld {
            Sink::Withheld { spool: BufWriter::with_capacity(1 << 16, tempfile::tempfile()?), out }
        } else {
            Sink::Direct(BufWriter::with_capacity(1 << 16, out))
        };
        Ok(OutputFile { sink })
    }

    /// Finishes the output: a replaced file takes the new content whole; a
    /// withheld one gets what was written; a direct one is flushed.
    pub fn commit(self) -> io::Result<()> {
        match self.sink {
            Sink::Replace(writer) => writer.into_inner().map_err(io::IntoInnerError::into_error)?.commit(),
            Sink::Direct(mut writer) => writer.flush(),
            Sink::Withheld { spool, mut out } => {
                let mut spool = spool.into_inner().map_err(io::IntoInnerError::into_error)?;
                spool.rewind()?;
                io::copy(&mut spool, &mut out)?;
                out.flush()
            }
        }
    }
}

impl Write for OutputFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match &mut self.sink {
            Sink::Replace(writer) => writer.write(buf),
            Sink::Direct(writer) => writer.write(buf),
            Sink::Withheld { spool, .. } => spool.write(buf),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.sink {
            Sink::Replace(writer) => writer.flush(),
            Sink::Direct(writer) => writer.flush(),
            Sink::Withheld { spool, .. } => spool.flush(),
        }
    }
}

/// A pipe or FIFO whose reader has gone (`ger run x | head`) is not an
/// error: what is left is dropped.
struct ReaderGone<W> {
    inner: W,
    gone: bool,
}

impl<W: Write> Write for ReaderGone<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if self.gone {
            return Ok(buf.len());
        }
        match self.inner.write(buf) {
            Err(err) if err.kind() == io::ErrorKind::BrokenPipe => {
                self.gone = true;
                Ok(buf.len())
            }
            other => other,
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        if self.gone {
            return Ok(());
        }
        match self.inner.flush() {
            Err(err) if err.kind() == io::ErrorKind::BrokenPipe => {
                self.gone = true;
                Ok(())
            }
            other => other,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        names.sort();
        names
    }

    #[test]
    fn the_kind_of_a_path_decides_how_it_is_written() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("f");
        std::fs::write(&file, "x").unwrap();
        assert_eq!(kind(None), Kind::Replace);
        assert_eq!(kind(Some(&std::fs::metadata(&file).unwrap())), Kind::Replace);
        assert_eq!(kind(Some(&std::fs::metadata(dir.path()).unwrap())), Kind::Folder);
        #[cfg(unix)]
        {
            let fifo = dir.path().join("fifo");
            let name = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
            assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
            assert_eq!(kind(Some(&std::fs::metadata(&fifo).unwrap())), Kind::Direct);
        }
    }

    #[cfg(unix)]
    #[test]
    fn symlinks_are_followed_to_their_end_relative_to_their_folder() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        std::os::unix::fs::symlink("sub/middle", dir.path().join("first")).unwrap();
        std::os::unix::fs::symlink("end.png", dir.path().join("sub/middle")).unwrap();
        assert_eq!(resolve(&dir.path().join("first")).unwrap(), dir.path().join("sub/end.png"));
        std::os::unix::fs::symlink("loop", dir.path().join("loop")).unwrap();
        assert!(resolve(&dir.path().join("loop")).is_err());
    }

    #[test]
    fn an_output_not_committed_leaves_the_old_file_and_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.ngc");
        std::fs::write(&path, "old\n").unwrap();
        let mut output = OutputFile::create(&path).unwrap();
        output.write_all(&[b'x'; 1 << 17]).unwrap();
        assert_eq!(names(dir.path()).len(), 2, "the temporary file is beside it");
        drop(output);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old\n");
        assert_eq!(names(dir.path()), ["out.ngc"]);
    }

    #[test]
    fn a_committed_output_replaces_the_file_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.ngc");
        std::fs::write(&path, "a much longer old content\n").unwrap();
        let mut output = OutputFile::create(&path).unwrap();
        output.write_all(b"new\n").unwrap();
        output.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new\n");
        assert_eq!(names(dir.path()), ["out.ngc"]);
    }
}
