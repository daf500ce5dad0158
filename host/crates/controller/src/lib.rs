//! The controller a translation is written for. ger's output is one
//! dialect; a controller may lack some of it (GRBL has no M06, no tool
//! table, no `%`) or want more (a Fanuc's O number and `%` framing). A
//! [`Profile`] says what each one takes, as data (`profile.rs`), and a
//! [`Writer`] turns the translated statements into its lines.
//!
//! The translation itself does not change: only what comes out of it.

mod arcs;
pub mod profile;
mod writer;

pub use profile::Profile;
pub use writer::{length, Writer};
