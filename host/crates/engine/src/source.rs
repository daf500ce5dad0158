//! A program to read, as often as a job needs it from its start.

use std::fs::File;
use std::io::{self, BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// A program: a file, which can be read again from the start; standard
/// input, held in memory so it can be too; or text held in memory under a
/// name, with the folder it belongs in (an editor's unsaved buffer).
#[derive(Clone, Debug)]
pub enum Source {
    File(PathBuf),
    Stdin(Arc<[u8]>),
    Text { name: String, dir: PathBuf, text: Arc<str> },
}

/// A program that could not be read.
#[derive(Debug, thiserror::Error)]
#[error("cannot read {name}: {cause}")]
pub struct ReadError {
    pub name: String,
    pub cause: io::Error,
}

impl Source {
    /// The file at `path`, opened once now so that a missing file is reported
    /// before anything runs; `-` is standard input, read whole.
    pub fn open_path(path: &Path) -> Result<Source, ReadError> {
        if path == Path::new("-") {
            return Source::stdin();
        }
        File::open(path).map_err(|cause| ReadError { name: path.display().to_string(), cause })?;
        Ok(Source::File(path.to_path_buf()))
    }

    /// Standard input, read whole.
    pub fn stdin() -> Result<Source, ReadError> {
        let mut buffer = Vec::new();
        io::stdin()
            .read_to_end(&mut buffer)
            .map_err(|cause| ReadError { name: "standard input".to_string(), cause })?;
        Ok(Source::Stdin(buffer.into()))
    }

    /// Text named `name` in the folder `dir` (where its config and subprograms are).
    pub fn text(name: impl Into<String>, dir: impl Into<PathBuf>, text: impl Into<Arc<str>>) -> Source {
        Source::Text { name: name.into(), dir: dir.into(), text: text.into() }
    }

    /// The name messages show.
    pub fn name(&self) -> String {
        match self {
            Source::File(path) => path.display().to_string(),
            Source::Stdin(_) => "<stdin>".to_string(),
            Source::Text { name, .. } => name.clone(),
        }
    }

    /// A fresh reader from the start of the program. A file that can no
    /// longer be opened reads as an error, which the lexer reports.
    pub fn open(&self) -> Box<dyn BufRead + '_> {
        match self {
            Source::File(path) => match File::open(path) {
                Ok(file) => Box::new(BufReader::with_capacity(1 << 16, file)),
                Err(err) => Box::new(FailingReader(Some(err))),
            },
            Source::Stdin(buffer) => Box::new(&buffer[..]),
            Source::Text { text, .. } => Box::new(text.as_bytes()),
        }
    }

    /// Bytes in the program, for progress (0 when unknown).
    pub fn size(&self) -> u64 {
        match self {
            Source::File(path) => std::fs::metadata(path).map_or(0, |m| m.len()),
            Source::Stdin(buffer) => buffer.len() as u64,
            Source::Text { text, .. } => text.len() as u64,
        }
    }

    /// The program's file, if it has one.
    pub fn path(&self) -> Option<PathBuf> {
        match self {
            Source::File(path) => Some(path.clone()),
            Source::Stdin(_) => None,
            Source::Text { name, dir, .. } => Some(dir.join(name)),
        }
    }

    /// The file `name` in the program's folder, named as the program's path
    /// names that folder (`ger.toml` for `part.nc`, `jobs/ger.toml` for
    /// `jobs/part.nc`), as messages show it.
    pub fn beside(&self, name: impl AsRef<Path>) -> PathBuf {
        match self {
            Source::File(path) => path.with_file_name(name.as_ref()),
            Source::Stdin(_) => name.as_ref().to_path_buf(),
            Source::Text { dir, .. } => dir.join(name),
        }
    }

    /// The program's folder (the working folder for standard input).
    pub fn dir(&self) -> PathBuf {
        match self {
            Source::File(path) => match path.parent() {
                Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
                _ => PathBuf::from("."),
            },
            Source::Stdin(_) => PathBuf::from("."),
            Source::Text { dir, .. } => dir.clone(),
        }
    }
}

/// A reader whose first read fails: the lexer turns that into a diagnostic.
struct FailingReader(Option<io::Error>);

impl Read for FailingReader {
    fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
        self.0.take().map_or(Ok(0), Err)
    }
}

impl BufRead for FailingReader {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        self.0.take().map_or(Ok(&[]), Err)
    }

    fn consume(&mut self, _: usize) {}
}

/// A reader that counts what the lexer has taken, for progress.
pub(crate) struct Counting<R> {
    pub inner: R,
    pub count: Arc<AtomicU64>,
}

impl<R: BufRead> Read for Counting<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.count.fetch_add(n as u64, Ordering::Relaxed);
        Ok(n)
    }
}

impl<R: BufRead> BufRead for Counting<R> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        self.inner.fill_buf()
    }

    fn consume(&mut self, amount: usize) {
        self.count.fetch_add(amount as u64, Ordering::Relaxed);
        self.inner.consume(amount)
    }
}

/// `path` with its folder's symlinks resolved, even when the file itself is
/// gone (an editor's save may delete it for a moment): how a watcher knows
/// the file an event names.
pub fn canonical_path(path: &Path) -> PathBuf {
    path.canonicalize().unwrap_or_else(|_| match (path.parent(), path.file_name()) {
        (Some(parent), Some(name)) => canonical_path(parent).join(name),
        _ => path.to_path_buf(),
    })
}
