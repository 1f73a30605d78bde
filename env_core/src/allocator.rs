//! The core's global allocator: mimalloc (the C library's v3, built by the `mimalloc` crate
//! with `local_dynamic_tls` and `no_thp`, `Cargo.toml`), its options ([`configure`]), and
//! a count of the bytes the core holds ([`allocated_bytes`]).
//!
//! Why mimalloc: a step allocates and frees many small blocks (rapier's per-substep
//! buffers, the probe's paths). Under glibc's malloc an episode batch on two threads lost
//! more to the second thread than two independent processes lose to each other; mimalloc
//! gives each thread a heap of its own and hands frees from another thread back without a
//! lock. It also returns a page's memory to the system once the page is empty, big blocks'
//! pages included, so the GPIS buffers of a few MiB that come and go between small blocks
//! that outlive them leave no holes (under glibc, whose threshold for mapping big blocks
//! moves, they did, and resident memory crept while the live heap stayed flat). Only the
//! core's blocks: Python's, numpy's and torch's stay with glibc.
//!
//! mimalloc returns an empty page's memory a delay after it empties (1 s by default), when
//! a thread next allocates or frees: a batch's worker asleep after a run kept its empty
//! pages meanwhile. [`configure`] sets the delay to 0; the Python module calls it when it
//! is imported.
//!
//! Why the count: glibc's `mallinfo2`, the soak's leak check, sees none of the core's
//! blocks, and mimalloc cannot say which bytes are live in a release build (its statistics
//! are compiled out; a walk of its heap misses the big blocks it maps for themselves; its
//! committed memory moves in whole chunks of its arenas). Each thread adds the bytes it
//! allocates and takes away those it frees on a counter of its own cache line (one of
//! [`SHARDS`], so the batch's threads never write the same line); [`allocated_bytes`]
//! sums them.
//!
//! The one module of the project with `unsafe` code (an allocator is nothing else): each
//! block says why it holds.

#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout};
use std::cell::Cell;
use std::sync::atomic::{AtomicIsize, AtomicUsize, Ordering};

use mimalloc::MiMalloc;

/// mimalloc's option `mi_option_purge_delay` (`mimalloc.h` of its v3, which the crate
/// builds; the crate's bindings leave this one out).
pub const PURGE_DELAY: std::ffi::c_int = 15;

/// Sets the core's mimalloc options: its purge delay to 0. They apply from then on.
pub fn configure() {
    // SAFETY: setting an option touches mimalloc's option table only, never a block.
    unsafe { libmimalloc_sys::mi_option_set(PURGE_DELAY, 0) };
}

/// mimalloc's purge delay now, ms.
pub fn purge_delay_ms() -> std::ffi::c_long {
    // SAFETY: reads mimalloc's option table.
    unsafe { libmimalloc_sys::mi_option_get(PURGE_DELAY) }
}

/// Counters of the bytes held: threads take them in turn (more threads than this share).
pub const SHARDS: usize = 64;

/// One thread's count of bytes allocated minus bytes freed (negative where it frees blocks
/// other threads allocated), alone on its cache lines.
#[repr(align(128))]
struct Shard(AtomicIsize);

static HELD: [Shard; SHARDS] = [const { Shard(AtomicIsize::new(0)) }; SHARDS];
static NEXT_SHARD: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// This thread's shard, taken at its first allocation (`usize::MAX` until then). A
    /// constant initialiser and no destructor: reading it never allocates.
    static MY_SHARD: Cell<usize> = const { Cell::new(usize::MAX) };
}

/// Adds `bytes` (negative: takes them away) to the calling thread's count.
fn count(bytes: isize) {
    let shard = MY_SHARD
        .try_with(|mine| {
            if mine.get() == usize::MAX {
                mine.set(NEXT_SHARD.fetch_add(1, Ordering::Relaxed) % SHARDS);
            }
            mine.get()
        })
        // A thread's last frees, after its thread-locals are gone.
        .unwrap_or(0);
    HELD[shard].0.fetch_add(bytes, Ordering::Relaxed);
}

/// `p`, a fresh block of `size` bytes (or null: nothing to count), counted.
fn counted(p: *mut u8, size: usize) -> *mut u8 {
    if !p.is_null() {
        count(size as isize);
    }
    p
}

/// Bytes the core holds now: every live block (their requested sizes). Cost: a read of each of the [`SHARDS`] counters.
pub fn allocated_bytes() -> usize {
    let held: isize = HELD
        .iter()
        .map(|shard| shard.0.load(Ordering::Relaxed))
        .sum();
    held.max(0) as usize
}

/// The allocator (see the module's header): mimalloc, counted.
pub struct CoreAllocator;

// SAFETY: every call is forwarded to mimalloc unchanged; the count only reads sizes.
unsafe impl GlobalAlloc for CoreAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded as received.
        counted(unsafe { MiMalloc.alloc(layout) }, layout.size())
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded as received.
        counted(unsafe { MiMalloc.alloc_zeroed(layout) }, layout.size())
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        count(-(layout.size() as isize));
        // SAFETY: forwarded as received.
        unsafe { MiMalloc.dealloc(p, layout) }
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: forwarded as received.
        let q = unsafe { MiMalloc.realloc(p, layout, new_size) };
        if !q.is_null() {
            count(new_size as isize - layout.size() as isize);
        }
        q
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configure_sets_the_purge_delay_to_zero() {
        configure();
        assert_eq!(purge_delay_ms(), 0);
    }
}
