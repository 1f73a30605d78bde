//! The core's global allocator: mimalloc for blocks under [`DIRECT_MAP_BYTES`], and every
//! bigger block its own anonymous memory map, handed back to the system when it is freed;
//! with a count of the bytes the core holds ([`allocated_bytes`]).
//!
//! Why mimalloc: a step allocates and frees many small blocks (rapier's per-substep
//! buffers, the probe's paths). Under glibc's malloc, which the core used
//! before, an episode batch on two threads lost more to the second thread than two
//! independent processes lose to each other; mimalloc gives each thread a heap of its own
//! and hands frees from another thread back without a lock. `cargo run --release -p
//! env_core --example batch_scaling 3`, the two builds alternated twice, means per run
//! with the resets, 16 episodes on two threads over one: wrist mode no map 1.68-1.75x ->
//! 1.81-1.82x, occupancy 1.82-1.89x -> 1.92-1.95x, GPIS 1.88-1.89x -> 1.91-1.96x; probe
//! mode no map 1.81-1.83x -> 1.83-1.91x, occupancy 1.79-1.80x -> 1.90-1.91x, GPIS 1.86-1.87x ->
//! 1.92x; one thread 1-3 % faster. Only the core's blocks: Python's, numpy's and torch's
//! stay with glibc.
//!
//! Why maps for big blocks: glibc maps big blocks itself, but its threshold moves. Each
//! time a mapped block is freed it raises the threshold to that block's size (up to 32
//! MiB), so the next GPIS buffers of a few MiB (the grid cache is 8 bytes per cell and row:
//! 3.3 MB at 128 rows on 40 × 80 cells) came from the heap instead, between small blocks
//! that outlive them. Freed, they left holes `malloc_trim` could not return: over the
//! soak, resident memory after the trim grew 4.4 % in 4 rounds (7.5 % over the full run)
//! while the live heap grew 1.6 % at its peaks. A map per big block returns its pages when
//! it goes, whatever the small blocks around do. Cost: a map and its page faults per big
//! block; the core reuses its big buffers across episodes (a `Gpis` keeps its storage on
//! `clear`), so they are mapped when an env is built or a map outgrows its storage.
//!
//! mimalloc frees a page's memory back to the system a delay after the page empties, when
//! its thread next allocates: a helper thread asleep after a reset kept its empty pages,
//! and resident memory after the trim grew 1.85 % over the soak. The core sets the delay to
//! 0 ([`PURGE_DELAY`]), as fast in `batch_scaling`: +0.92 % (`python -m benchmarks.soak`).
//!
//! Why the count: glibc's `mallinfo2`, the soak's leak check, sees none of the core's
//! blocks. Each thread adds the bytes it allocates and takes away those it frees on a
//! counter of its own cache line (one of [`SHARDS`], so the batch's threads never write
//! the same line); [`allocated_bytes`] sums them.
//!
//! One of the two modules of the project with `unsafe` code (an allocator is nothing else;
//! the other is the batch's `episode::shared_tiles`): each block says why it holds.

#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicIsize, AtomicUsize, Ordering};

use mimalloc::MiMalloc;

/// Blocks at least this large are mapped directly.
pub const DIRECT_MAP_BYTES: usize = 1 << 20;

/// Alignment a fresh map always has (the smallest page size of the platforms we build for).
const MAP_ALIGN: usize = 4096;

static MAPPED: AtomicUsize = AtomicUsize::new(0);

/// Bytes of the core's blocks mapped directly now (their requested sizes).
pub fn direct_mapped_bytes() -> usize {
    MAPPED.load(Ordering::Relaxed)
}

/// mimalloc's option `mi_option_purge_delay` (`mimalloc.h` of its v3, which the crate
/// builds; the crate's bindings leave this one out), set to 0 before its first block.
pub const PURGE_DELAY: std::ffi::c_int = 15;

static CONFIGURED: AtomicBool = AtomicBool::new(false);

/// Sets the core's mimalloc options, once (a race sets them twice, to the same values).
fn configure() {
    if !CONFIGURED.load(Ordering::Relaxed) {
        // SAFETY: setting an option touches mimalloc's option table only, never a block.
        unsafe { libmimalloc_sys::mi_option_set(PURGE_DELAY, 0) };
        CONFIGURED.store(true, Ordering::Relaxed);
    }
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

/// Bytes the core holds now: every live block of its allocator, small or mapped (their
/// requested sizes). Cost: a read of each of the [`SHARDS`] counters.
pub fn allocated_bytes() -> usize {
    let held: isize = HELD
        .iter()
        .map(|shard| shard.0.load(Ordering::Relaxed))
        .sum();
    held.max(0) as usize
}

/// The allocator (see the module's header).
pub struct CoreAllocator;

fn is_direct(layout: &Layout) -> bool {
    cfg!(target_os = "linux") && layout.size() >= DIRECT_MAP_BYTES && layout.align() <= MAP_ALIGN
}

#[cfg(target_os = "linux")]
mod maps {
    use std::ptr;

    /// A fresh zeroed map of `size` bytes, or null.
    pub(super) unsafe fn map(size: usize) -> *mut u8 {
        // SAFETY: an anonymous private map asks nothing of its arguments but a size.
        let p = unsafe {
            libc::mmap(
                ptr::null_mut(),
                size,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                -1,
                0,
            )
        };
        if p == libc::MAP_FAILED {
            ptr::null_mut()
        } else {
            p.cast()
        }
    }

    /// Unmaps a map made by [`map`] or [`remap`] with this size.
    pub(super) unsafe fn unmap(p: *mut u8, size: usize) {
        // SAFETY: the caller passes a live map and its size.
        unsafe { libc::munmap(p.cast(), size) };
    }

    /// Grows or shrinks a map (moving it if need be), or null with the map untouched.
    pub(super) unsafe fn remap(p: *mut u8, old: usize, new: usize) -> *mut u8 {
        // SAFETY: the caller passes a live map and its size.
        let q = unsafe { libc::mremap(p.cast(), old, new, libc::MREMAP_MAYMOVE) };
        if q == libc::MAP_FAILED {
            ptr::null_mut()
        } else {
            q.cast()
        }
    }
}

#[cfg(not(target_os = "linux"))]
mod maps {
    // Never called: `is_direct` is false off Linux.
    pub(super) unsafe fn map(_: usize) -> *mut u8 {
        unreachable!()
    }
    pub(super) unsafe fn unmap(_: *mut u8, _: usize) {
        unreachable!()
    }
    pub(super) unsafe fn remap(_: *mut u8, _: usize, _: usize) -> *mut u8 {
        unreachable!()
    }
}

// SAFETY: every block is either mimalloc's or a map of its layout's size, and
// which one follows from the layout alone (`is_direct`), which the caller passes unchanged
// to `dealloc` and `realloc`; maps are page-aligned, at least the alignment asked for.
unsafe impl GlobalAlloc for CoreAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !is_direct(&layout) {
            configure();
            // SAFETY: forwarded as received.
            return counted(unsafe { MiMalloc.alloc(layout) }, layout.size());
        }
        // SAFETY: a size, nothing more.
        let p = unsafe { maps::map(layout.size()) };
        if !p.is_null() {
            MAPPED.fetch_add(layout.size(), Ordering::Relaxed);
            count(layout.size() as isize);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !is_direct(&layout) {
            configure();
            // SAFETY: forwarded as received.
            return counted(unsafe { MiMalloc.alloc_zeroed(layout) }, layout.size());
        }
        // SAFETY: a fresh anonymous map is zeroed already.
        unsafe { self.alloc(layout) }
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        if !is_direct(&layout) {
            count(-(layout.size() as isize));
            // SAFETY: forwarded as received.
            return unsafe { MiMalloc.dealloc(p, layout) };
        }
        // SAFETY: a direct block is a map of exactly this size.
        unsafe { maps::unmap(p, layout.size()) };
        MAPPED.fetch_sub(layout.size(), Ordering::Relaxed);
        count(-(layout.size() as isize));
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY (for the layout): `realloc`'s contract gives a valid size for this align.
        let new_layout = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
        match (is_direct(&layout), is_direct(&new_layout)) {
            (false, false) => {
                // SAFETY: forwarded as received.
                let q = unsafe { MiMalloc.realloc(p, layout, new_size) };
                if !q.is_null() {
                    count(new_size as isize - layout.size() as isize);
                }
                q
            }
            (true, true) => {
                // SAFETY: a direct block is a map of exactly the old size.
                let q = unsafe { maps::remap(p, layout.size(), new_size) };
                if !q.is_null() {
                    MAPPED.fetch_add(new_size, Ordering::Relaxed);
                    MAPPED.fetch_sub(layout.size(), Ordering::Relaxed);
                    count(new_size as isize - layout.size() as isize);
                }
                q
            }
            // Across the threshold: a new block, the bytes copied, the old one freed.
            _ => {
                // SAFETY: `new_layout` is valid (above); the copy stays within both blocks.
                unsafe {
                    let q = self.alloc(new_layout);
                    if !q.is_null() {
                        std::ptr::copy_nonoverlapping(p, q, layout.size().min(new_size));
                        self.dealloc(p, layout);
                    }
                    q
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mimalloc_purges_empty_pages_at_once() {
        let block = vec![1u8; 1000];
        assert_eq!(purge_delay_ms(), 0);
        drop(block);
    }

    #[test]
    fn a_big_block_is_a_page_aligned_map_and_keeps_its_bytes_when_it_grows() {
        // glibc's own maps start 16 bytes into their first page: a page-aligned start is ours.
        let mut big: Vec<f64> = (0..DIRECT_MAP_BYTES / 8).map(|i| i as f64).collect();
        assert_eq!(big.as_ptr() as usize % MAP_ALIGN, 0);
        big.reserve_exact(3 * DIRECT_MAP_BYTES / 8);
        assert_eq!(big.as_ptr() as usize % MAP_ALIGN, 0);
        assert!(big.iter().enumerate().all(|(i, &x)| x == i as f64));
    }

    #[test]
    fn a_block_that_crosses_the_threshold_keeps_its_bytes_both_ways() {
        let mut v: Vec<u8> = (0..1000u32).map(|i| i as u8).collect();
        v.reserve_exact(2 * DIRECT_MAP_BYTES);
        assert_eq!(v.as_ptr() as usize % MAP_ALIGN, 0);
        v.shrink_to_fit();
        assert_eq!(v.len(), 1000);
        assert!(v.iter().enumerate().all(|(i, &x)| x == i as u8));
    }
}
