//! The core's global allocator: the system's malloc, except that every block of at least
//! [`DIRECT_MAP_BYTES`] is its own anonymous memory map, handed back to the system when it
//! is freed.
//!
//! Why: glibc maps big blocks itself, but its threshold moves. Each time a mapped block is
//! freed it raises the threshold to that block's size (up to 32 MiB), so the next GPIS
//! buffers of a few MiB (the grid cache is 8 bytes per cell and row: 3.3 MB at 128 rows on
//! 40 × 80 cells) come from the heap instead, between small blocks that outlive them. Freed,
//! they leave holes `malloc_trim` cannot return. Over the soak, resident memory after the
//! trim grew 4.4 % in 4 rounds (7.5 % over the full run) while the live heap grew 1.6 % at
//! its peaks. With every block of 1 MiB or more mapped (glibc's `MALLOC_MMAP_THRESHOLD_`
//! fixed at 1 MiB for the whole process) the growth was 1.85 %, the live heap's own. This
//! allocator does that for the core's allocations only, leaving Python's, numpy's and
//! torch's (whose big tensors come and go every minibatch) to glibc's policy.
//!
//! Cost: a map and its page faults per big block. The core reuses its big buffers across
//! episodes (a `Gpis` keeps its storage on `clear`), so they are mapped when an env is
//! built or a map outgrows its storage, not per step; the reset's workspaces are smaller.
//! [`direct_mapped_bytes`] counts the mapped blocks, which glibc's `mallinfo2` no longer
//! sees (the soak's live heap adds it).
//!
//! One of the two modules of the project with `unsafe` code (an allocator is nothing else;
//! the other is the batch's `episode::shared_tiles`): each block says why it holds.

#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Blocks at least this large are mapped directly.
pub const DIRECT_MAP_BYTES: usize = 1 << 20;

/// Alignment a fresh map always has (the smallest page size of the platforms we build for).
const MAP_ALIGN: usize = 4096;

static MAPPED: AtomicUsize = AtomicUsize::new(0);

/// Bytes of the core's blocks mapped directly now (their requested sizes).
pub fn direct_mapped_bytes() -> usize {
    MAPPED.load(Ordering::Relaxed)
}

/// The allocator (see the module's header).
pub struct DirectMapAllocator;

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

// SAFETY: every block is either the system allocator's or a map of its layout's size, and
// which one follows from the layout alone (`is_direct`), which the caller passes unchanged
// to `dealloc` and `realloc`; maps are page-aligned, at least the alignment asked for.
unsafe impl GlobalAlloc for DirectMapAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !is_direct(&layout) {
            // SAFETY: forwarded as received.
            return unsafe { System.alloc(layout) };
        }
        // SAFETY: a size, nothing more.
        let p = unsafe { maps::map(layout.size()) };
        if !p.is_null() {
            MAPPED.fetch_add(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !is_direct(&layout) {
            // SAFETY: forwarded as received.
            return unsafe { System.alloc_zeroed(layout) };
        }
        // SAFETY: a fresh anonymous map is zeroed already.
        unsafe { self.alloc(layout) }
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        if !is_direct(&layout) {
            // SAFETY: forwarded as received.
            return unsafe { System.dealloc(p, layout) };
        }
        // SAFETY: a direct block is a map of exactly this size.
        unsafe { maps::unmap(p, layout.size()) };
        MAPPED.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY (for the layout): `realloc`'s contract gives a valid size for this align.
        let new_layout = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
        match (is_direct(&layout), is_direct(&new_layout)) {
            // SAFETY: forwarded as received.
            (false, false) => unsafe { System.realloc(p, layout, new_size) },
            (true, true) => {
                // SAFETY: a direct block is a map of exactly the old size.
                let q = unsafe { maps::remap(p, layout.size(), new_size) };
                if !q.is_null() {
                    MAPPED.fetch_add(new_size, Ordering::Relaxed);
                    MAPPED.fetch_sub(layout.size(), Ordering::Relaxed);
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
