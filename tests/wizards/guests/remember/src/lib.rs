//! `Remember`: looks for what an earlier call left behind, in a static, in a
//! small heap block and in a large one (past the part of a pooled memory
//! that is reset by copying), then leaves its own marks. It moves to X = the
//! argument plus the marks it found: the argument when every call starts afresh.
use std::sync::atomic::{AtomicU32, Ordering};

use ger_wizard_sdk::*;

static CALLS: AtomicU32 = AtomicU32::new(0);
const MARK: u8 = 0xA5;

struct Remember;

impl Wizard for Remember {
    fn describe() -> Description {
        Description::new("Remember", "counts what earlier calls left", "Remember X").param("X", "where to go")
    }

    fn expand(args: &Args, _: &State) -> Result<Vec<Statement>, String> {
        let mut found = CALLS.fetch_add(1, Ordering::Relaxed);
        // Allocated the same way each call, so a heap not reset would hand
        // back the blocks marked last time (leaked, so never freed).
        for size in [64, 4 << 20] {
            let layout = std::alloc::Layout::from_size_align(size, 8).unwrap();
            // SAFETY: a block of `size` bytes, never freed; its bytes are read
            // volatile because what an earlier call wrote there is the point.
            unsafe {
                let block = std::alloc::alloc(layout);
                for at in [block, block.add(size - 1)] {
                    found += u32::from(at.read_volatile() == MARK);
                    at.write_volatile(MARK);
                }
            }
        }
        Ok(vec![g1().x(args.number(0)? + f64::from(found)).into()])
    }
}

export_wizard!(Remember);
