//! How the command line reports what stops it: errors carry their causes
//! (`anyhow` contexts over the libraries' typed errors) and are shown as one
//! line, "error: cannot write part.png: Permission denied (os error 13)";
//! errors that are shown with more (a config's source line, a help line)
//! are rendered where they happen, as a [`Shown`].

use std::fmt;
use std::path::Path;

/// An error already rendered as it is to be shown.
#[derive(Debug)]
pub struct Shown(pub String);

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0.trim_end())
    }
}

impl std::error::Error for Shown {}

/// An error with a help line under it.
pub fn with_help(message: impl fmt::Display, help: &str) -> anyhow::Error {
    Shown(plain_error(&message.to_string(), Some(help))).into()
}

/// The text that shows `err`: its own rendering, or "error: " and each
/// context with its causes, ending in a newline.
pub fn render(err: &anyhow::Error) -> String {
    match err.downcast_ref::<Shown>() {
        Some(Shown(text)) => text.clone(),
        None => plain_error(&format!("{err:#}"), None),
    }
}

/// A problem that is not in the program text, in the style of rustc.
pub fn plain_error(message: &str, help: Option<&str>) -> String {
    let mut text = format!("error: {message}\n");
    if let Some(help) = help {
        text.push_str(&format!("  = help: {help}\n"));
    }
    text
}

/// The context of an output that cannot be written: `-` is standard output.
pub fn cannot_write(path: &Path) -> String {
    if path == Path::new("-") {
        "cannot write standard output".to_string()
    } else {
        format!("cannot write {}", path.display())
    }
}
