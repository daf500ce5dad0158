//! ger's wizard runtime: [`WasmWizards`] implements `ger_core`'s `Wizards`
//! by running WebAssembly components from a wizards directory in a sandbox
//! (see `wit/wizard.wit` for the contract).
//!
//! - [`catalog`] finds wizards in a directory by name;
//! - [`build`] turns a wizard's sources (Rust, Python, JavaScript) into `.wasm`;
//! - [`cache`] keeps compiled components on disk by content hash, signed;
//! - [`runtime`] runs calls in a sandbox, within [`Limits`];
//! - `render` turns a wizard's typed statements into ger's statements.

pub mod build;
pub mod cache;
pub mod catalog;
mod render;
pub mod runtime;

pub use runtime::{Limits, WasmWizards};
