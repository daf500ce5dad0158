//! ger as a library: the one way into its translator, simulator and verifier
//! for the command line, `ger view`, and any program embedding it (a sender,
//! a CAM system, an editor, a test rig).
//!
//! A [`Program`] holds a [`Source`] (a file, standard input, or text in
//! memory), the machine's [`Config`](ger_core::config::Config) and the
//! wizards it may call, and answers: the translation as a stream of events
//! after any pass ([`Program::events`]), as text ([`Program::write_translation`]);
//! where it cuts ([`Program::extent`], [`Program::stock`]); the part it cuts
//! ([`Program::simulate`]); the verifier's findings and summary
//! ([`Program::check`]); its toolpath ([`Program::toolpath`],
//! [`Program::toolpath_pieces`]). Long passes tell a [`Progress`].
//!
//! ```
//! use ger_engine::core::config::Config;
//! use ger_engine::{Program, Resolution, Silent, Source};
//!
//! let text = "G20 G90\nM06 T1\nM03 S10000\nG00 X0 Y0 Z0.1\nG01 Z-0.1 F30\nG01 X2\nG00 Z0.5\nM30\n";
//! // The default machine: inches, tool 1 a quarter-inch endmill.
//! let mut program = Program::new(Source::text("slot.nc", ".", text), Config::default());
//! let (stock, _) = program.stock(&mut Silent);
//! let simulation = program.simulation(stock, Resolution { cell: Some(0.01), ..Resolution::default() }).unwrap();
//! let (verdict, _part) = program.check(simulation, &[], &mut Silent);
//! assert!(verdict.findings.iter().all(|f| !f.diagnostic.is_error()));
//! let cut = verdict.summary.cut_box.expect("the slot");
//! assert!((cut.min[2] + 0.1).abs() < 0.011 && (cut.max[0] - 2.125).abs() < 0.011, "{cut:?}");
//! ```
//!
//! Nothing here knows argv or terminals: errors are values ([`ReadError`],
//! [`ConfigError`], [`Refused`]), diagnostics are collected in a [`Report`]
//! that renders them as rustc does when asked.

mod library;
mod machine;
mod program;
mod progress;
mod report;
mod source;

pub use machine::{ConfigError, Purpose, Settings};
pub use program::{
    carve, default_tolerance, place_design, stock_of, Culprit, Extent, Job, Program, Refused, Resolution,
};
pub use progress::{Progress, Silent};
pub use report::Report;
pub use source::{canonical_path, ReadError, Source};

// What a caller needs to use the answers, from the crates that make them.
pub use ger_check as check;
pub use ger_compare as compare;
pub use ger_core as core;
pub use ger_render as render;
pub use ger_sim as sim;

#[cfg(test)]
mod tests;
