//! How a long job tells its caller how far it has got.

/// Told how far each pass over the program has got, in bytes of the program
/// read. A job may make several passes (finding the stock, then cutting it),
/// each begun and ended.
pub trait Progress {
    /// A pass named `job` ("bounds", "cutting", "checking") begins over `total` bytes.
    fn begin(&mut self, job: &'static str, total: u64) {
        let _ = (job, total);
    }

    /// `done` bytes of the program have been read.
    fn advance(&mut self, done: u64) {
        let _ = done;
    }

    /// The pass is over.
    fn end(&mut self) {}

    /// Whether the caller no longer wants the pass (an editor's newer text
    /// makes it stale): asked as often as `advance` is told, and the pass
    /// stops early when it says so.
    fn stopped(&self) -> bool {
        false
    }
}

/// Progress nobody is told of.
pub struct Silent;

impl Progress for Silent {}
