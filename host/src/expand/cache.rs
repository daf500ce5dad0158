//! Compiled components on disk, keyed by a hash of the `.wasm` and of the
//! engine's settings, so a second run does not compile again and a changed
//! wizard (or a new ger) never gets a stale compilation.

use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};
use wasmtime::component::Component;
use wasmtime::Engine;

/// Where the compiled components of the wizards in `wizards` are kept.
pub fn dir(wizards: &Path) -> PathBuf {
    wizards.join("target").join("ger").join("cache")
}

/// `wasm` compiled for `engine`, from `cache` if it was compiled before.
/// A cache that cannot be read or written only costs a compilation.
pub fn load(engine: &Engine, wasm: &[u8], cache: &Path) -> wasmtime::Result<Component> {
    let path = cache.join(format!("{}.cwasm", key(engine, wasm)));
    if path.is_file() {
        // SAFETY: the file was written by `serialize` below for this same
        // engine configuration (the key covers it), and wasmtime checks its
        // header and version before trusting it. It is as trustworthy as the
        // directory it sits in, which also holds the .wasm being run.
        if let Ok(component) = unsafe { Component::deserialize_file(engine, &path) } {
            return Ok(component);
        }
    }
    let component = Component::new(engine, wasm)?;
    if let Ok(bytes) = component.serialize() {
        let _ = store(cache, &path, &bytes);
    }
    Ok(component)
}

/// Writes atomically: another ger running at the same time sees the whole
/// file or none.
fn store(cache: &Path, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    std::fs::create_dir_all(cache)?;
    let mut output = crate::output::OutputFile::create(path)?;
    std::io::Write::write_all(&mut output, bytes)?;
    output.commit()
}

/// SHA-256 of the wasm and of what makes a compilation valid for `engine`.
fn key(engine: &Engine, wasm: &[u8]) -> String {
    struct Sha(Sha256);
    impl Hasher for Sha {
        fn finish(&self) -> u64 {
            0 // never asked: the digest is read from `self.0`
        }
        fn write(&mut self, bytes: &[u8]) {
            self.0.update(bytes);
        }
    }
    let mut sha = Sha(Sha256::new());
    engine.precompile_compatibility_hash().hash(&mut sha);
    sha.0.update(wasm);
    sha.0.finalize().iter().map(|b| format!("{b:02x}")).collect()
}
