//! The core's allocator counts its mapped blocks exactly (a process of its own: no other
//! test allocates meanwhile).

use env_core::allocator::{direct_mapped_bytes, DIRECT_MAP_BYTES};

#[test]
fn mapped_bytes_rise_with_big_blocks_follow_a_remap_and_fall_back_when_freed() {
    let before = direct_mapped_bytes();
    let small = vec![1u8; DIRECT_MAP_BYTES - 1];
    assert_eq!(direct_mapped_bytes(), before, "a small block is mimalloc's");
    let mut big = vec![2u8; DIRECT_MAP_BYTES];
    assert_eq!(direct_mapped_bytes(), before + DIRECT_MAP_BYTES);
    big.reserve_exact(DIRECT_MAP_BYTES);
    assert_eq!(direct_mapped_bytes(), before + big.capacity());
    drop(big);
    drop(small);
    assert_eq!(direct_mapped_bytes(), before);
}
