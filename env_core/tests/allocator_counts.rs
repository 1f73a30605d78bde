//! The core's allocator counts the bytes it holds (`env_core::allocator::allocated_bytes`),
//! small blocks and big ones alike, whichever thread allocates or frees them. One test in
//! its own binary: no other test allocates meanwhile.

use env_core::allocator::allocated_bytes;

/// A block mimalloc keeps on pages of its own.
const BIG: usize = 1 << 20;

#[test]
fn blocks_are_counted_while_they_live_whichever_thread_frees_them() {
    let before = allocated_bytes();
    let small: Vec<u8> = vec![7; 100_000];
    let big: Vec<u8> = vec![9; 8 * BIG];
    let held = allocated_bytes() - before;
    assert!(
        (small.len() + big.len()..small.len() + big.len() + 4096).contains(&held),
        "{held} bytes counted for blocks of {} and {}",
        small.len(),
        big.len()
    );
    // Allocated here, freed on another thread: its count goes down on that thread's shard.
    std::thread::spawn(move || drop((small, big)))
        .join()
        .expect("the thread frees the blocks");
    let after = allocated_bytes();
    assert!(
        after < before + 4096,
        "{} bytes still counted after the blocks were freed",
        after - before
    );
    // Grown (mimalloc moves it to a bigger block), then freed: the count follows.
    let mut growing: Vec<u64> = Vec::with_capacity(1000);
    growing.extend(0..1000);
    growing.reserve_exact(BIG / 8);
    assert!(allocated_bytes() - after >= BIG);
    assert!(growing.iter().enumerate().all(|(i, &x)| x == i as u64));
    drop(growing);
    assert!(allocated_bytes() < after + 4096);
}
