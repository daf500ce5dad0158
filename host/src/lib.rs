//! ger: a G-code emulatoR, verifiER and transpilER for 3-axis mills and routers.
//!
//! The module tree is the pipeline (see ARCHITECTURE.md at the repository root):
//! [`lex`] -> [`parse`] -> [`passes`] 00..05 -> [`emit`], with [`cli`] the only
//! module that touches argv, files or terminals, and [`output`] the one way a
//! file is written.

pub mod check;
pub mod cli;
pub mod config;
pub mod diag;
pub mod emit;
pub mod expand;
pub mod geom;
pub mod lex;
pub mod output;
pub mod parse;
pub mod passes;
pub mod pulses;
pub mod render;
pub mod sim;
pub mod state;
pub mod statement;
pub mod tools;
