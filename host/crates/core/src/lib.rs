//! The translator of ger: G-code text in, simple G-code out.
//!
//! The module tree is the pipeline (see ARCHITECTURE.md at the repository
//! root): [`lex`] -> [`parse`] -> [`passes`] 00..05 -> [`emit`], driven by a
//! [`config::Config`] and watched by [`state`]. Wizard calls go to a
//! [`wizard::Wizards`], which this crate only names: the WebAssembly runtime
//! that implements it is the `ger-wasm` crate. Nothing here touches a
//! terminal, a socket or a thread pool; the only files it reads are the
//! ones a caller asks [`passes::Library`] or [`tools`] to look at.

pub mod config;
pub mod diag;
pub mod emit;
pub mod geom;
pub mod lex;
pub mod macros;
pub mod parse;
pub mod passes;
pub mod state;
pub mod statement;
pub mod tools;
pub mod wizard;
