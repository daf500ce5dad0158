//! Compiled components on disk, so a second run does not compile again.
//!
//! A compiled component is native code, which wasmtime runs without checking
//! it: an entry must never be trusted for coming from the right folder, since
//! a wizards folder (and its `target/`) may be shared, cloned or edited by
//! anyone. Each entry is therefore signed with a secret key that only this
//! user can read, kept outside the wizards folder ([`Key::user`]): an
//! HMAC-SHA256 over the `.wasm`'s hash, the engine's configuration (its
//! wasmtime version and settings) and the compiled bytes. An entry whose
//! signature does not verify (copied under another name, edited, cut short,
//! signed with another key) is a cache miss: the `.wasm` is compiled again
//! and the entry written anew. Without a key, nothing is read from the cache.

use std::hash::{Hash, Hasher};
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

use hmac::{Hmac, Mac};
use sha2::{Digest, Sha256};
use wasmtime::component::Component;
use wasmtime::Engine;

/// The SHA-256 of a `.wasm`: what a wizard is, for the cache and for its
/// random numbers.
pub type WasmDigest = [u8; 32];

/// Where the compiled components of the wizards in `wizards` are kept.
pub fn dir(wizards: &Path) -> PathBuf {
    wizards.join("target").join("ger").join("cache")
}

/// An entry starts with its signature.
const SIGNATURE: usize = 32;
/// Named in every signature, so a signature made for anything else never fits.
const PURPOSE: &[u8] = b"ger wizard cache entry, version 1";
const KEY_BYTES: usize = 32;

/// The secret that signs this user's cache entries.
pub struct Key([u8; KEY_BYTES]);

impl Key {
    /// This user's key, `$XDG_CACHE_HOME/ger/cache-key` (or
    /// `~/.cache/ger/cache-key`), made on first use. `None` when it cannot be
    /// read or made, or is readable by others: then the cache is not used.
    pub fn user() -> Option<Key> {
        let base = std::env::var_os("XDG_CACHE_HOME")
            .map(PathBuf::from)
            .filter(|p| p.is_absolute())
            .or_else(|| std::env::var_os("HOME").map(|home| PathBuf::from(home).join(".cache")))?;
        Key::load_or_make(&base.join("ger").join("cache-key")).ok()
    }

    /// The key in `path`, which is made (mode 0600, in a folder of mode 0700)
    /// if there is none. Two gers making it at once agree on one key.
    pub fn load_or_make(path: &Path) -> io::Result<Key> {
        match Key::load(path) {
            Err(err) if err.kind() == io::ErrorKind::NotFound => {}
            loaded => return loaded,
        }
        let folder = path.parent().ok_or_else(|| io::Error::other("a key file needs a folder"))?;
        let mut builder = std::fs::DirBuilder::new();
        builder.recursive(true);
        #[cfg(unix)]
        std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
        builder.create(folder)?;
        let mut key = [0; KEY_BYTES];
        getrandom::fill(&mut key).map_err(io::Error::other)?;
        // A temporary file is made with mode 0600; it gets its name only
        // once it is whole, and never over a key another ger made meanwhile.
        let mut temp = tempfile::NamedTempFile::new_in(folder)?;
        temp.write_all(&key)?;
        temp.as_file().sync_all()?;
        match temp.persist_noclobber(path) {
            Ok(_) => Ok(Key(key)),
            Err(err) if err.error.kind() == io::ErrorKind::AlreadyExists => Key::load(path),
            Err(err) => Err(err.error),
        }
    }

    fn load(path: &Path) -> io::Result<Key> {
        let mut file = std::fs::File::open(path)?;
        let meta = file.metadata()?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            if meta.permissions().mode() & 0o077 != 0 {
                return Err(io::Error::other("the cache key is open to other users"));
            }
        }
        if !meta.is_file() || meta.len() != KEY_BYTES as u64 {
            return Err(io::Error::other("the cache key is not a file of 32 bytes"));
        }
        let mut key = [0; KEY_BYTES];
        file.read_exact(&mut key)?;
        Ok(Key(key))
    }

    fn signature(&self, engine: &[u8; 32], wasm: &WasmDigest, compiled: &[u8]) -> Hmac<Sha256> {
        let mut mac = Hmac::<Sha256>::new_from_slice(&self.0).expect("HMAC takes a key of any length");
        for part in [PURPOSE, engine, wasm, compiled] {
            mac.update(part);
        }
        mac
    }
}

/// `wasm` (whose SHA-256 is `digest`) compiled for `engine`, from `cache` if
/// an entry signed with `key` is there. A cache that cannot be read or
/// written only costs a compilation.
pub fn load(
    engine: &Engine,
    wasm: &[u8],
    digest: &WasmDigest,
    cache: &Path,
    key: Option<&Key>,
) -> wasmtime::Result<Component> {
    let Some(key) = key else {
        return Component::new(engine, wasm);
    };
    let engine_digest = engine_digest(engine);
    let path = cache.join(format!("{}.cwasm", name(&engine_digest, digest)));
    // Compiled code is a few times the size of its .wasm; a bigger entry is not read.
    let largest = wasm.len() as u64 * 32 + (16 << 20);
    if let Some(component) = verified(engine, &path, largest, key, &engine_digest, digest) {
        return Ok(component);
    }
    let component = Component::new(engine, wasm)?;
    if let Ok(compiled) = component.serialize() {
        let signature = key.signature(&engine_digest, digest, &compiled).finalize().into_bytes();
        let _ = store(cache, &path, &[&signature[..], &compiled]);
    }
    Ok(component)
}

/// The component in the entry at `path`, if its signature verifies.
fn verified(
    engine: &Engine,
    path: &Path,
    largest: u64,
    key: &Key,
    engine_digest: &[u8; 32],
    wasm: &WasmDigest,
) -> Option<Component> {
    // Only a regular file is read: a FIFO would hang ger, a link to a
    // device fill its memory (and `store` replaces either by an entry).
    let meta = std::fs::symlink_metadata(path).ok()?;
    if !meta.is_file() || meta.len() > largest {
        return None;
    }
    let entry = std::fs::read(path).ok()?;
    let (signature, compiled) = entry.split_at_checked(SIGNATURE)?;
    key.signature(engine_digest, wasm, compiled).verify_slice(signature).ok()?;
    // SAFETY: these very bytes (read once, into memory, so the file changing
    // now cannot matter) carry a signature that only a ger holding this
    // user's secret key can make, over this .wasm's hash and this engine's
    // configuration: they are what `serialize` wrote for this component here.
    unsafe { Component::deserialize(engine, compiled) }.ok()
}

/// Writes atomically: another ger running at the same time sees the whole
/// file or none.
fn store(cache: &Path, path: &Path, parts: &[&[u8]]) -> io::Result<()> {
    std::fs::create_dir_all(cache)?;
    // Not `OutputFile`, which writes through a symlink: the wizards folder
    // may be anyone's, and an entry must never be a way to write elsewhere.
    // A rename replaces whatever is at `path`, link or file, by the entry.
    let mut temp = tempfile::NamedTempFile::new_in(cache)?;
    for part in parts {
        temp.write_all(part)?;
    }
    temp.persist(path)?;
    Ok(())
}

/// SHA-256 of what makes a compilation valid for `engine`.
fn engine_digest(engine: &Engine) -> [u8; 32] {
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
    sha.0.finalize().into()
}

/// An entry's file name: one for each .wasm and engine configuration.
fn name(engine: &[u8; 32], wasm: &WasmDigest) -> String {
    let mut sha = Sha256::new();
    sha.update(engine);
    sha.update(wasm);
    sha.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn a_key_is_made_private_once_and_one_open_to_others_is_refused() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("ger").join("cache-key");
        let made = Key::load_or_make(&path).unwrap();
        assert_eq!(std::fs::metadata(&path).unwrap().permissions().mode() & 0o777, 0o600);
        assert_eq!(std::fs::metadata(path.parent().unwrap()).unwrap().permissions().mode() & 0o777, 0o700);
        assert_eq!(Key::load_or_make(&path).unwrap().0, made.0, "made again");
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o644)).unwrap();
        assert!(Key::load_or_make(&path).is_err());
        // A key that cannot be made (its folder would be under a file) is no key.
        let blocked = dir.path().join("file");
        std::fs::write(&blocked, "").unwrap();
        assert!(Key::load_or_make(&blocked.join("cache-key")).is_err());
    }
}
