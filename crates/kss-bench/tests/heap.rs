//! The counting allocator ([`kss_bench::heap`]) as the global allocator of
//! this test binary. A plain `main` (no test harness): the counters are
//! exact on one thread only, and the harness would run tests on several.

use kss_bench::heap;

#[global_allocator]
static ALLOCATOR: heap::Counting = heap::Counting;

fn main() {
    counts_live_bytes_their_peak_and_allocations();
    a_reset_starts_the_peak_at_the_live_bytes();
    println!("heap: 2 checks passed");
}

fn counts_live_bytes_their_peak_and_allocations() {
    assert!(heap::installed(), "the allocator has counted nothing");
    heap::reset();
    let before = heap::read().expect("installed");
    assert_eq!(before.allocations, 0);
    assert_eq!(before.peak_bytes, before.live_bytes);
    let mut v: Vec<u8> = Vec::with_capacity(1 << 20);
    v.push(1);
    let one = heap::read().expect("installed");
    assert_eq!(one.allocations, 1);
    assert_eq!(one.live_bytes, before.live_bytes + (1 << 20));
    assert_eq!(one.peak_bytes, one.live_bytes);
    // a reallocation counts as an allocation and moves the live bytes by
    // the difference
    v.reserve_exact(3 << 20);
    let grown = heap::read().expect("installed");
    assert_eq!(grown.allocations, 2);
    assert_eq!(grown.live_bytes, before.live_bytes + v.capacity() as u64);
    drop(v);
    let after = heap::read().expect("installed");
    assert_eq!(after.live_bytes, before.live_bytes);
    assert_eq!(after.peak_bytes, grown.live_bytes);
    assert_eq!(after.allocations, 2, "a free is not an allocation");
}

fn a_reset_starts_the_peak_at_the_live_bytes() {
    let big = vec![0u8; 1 << 22];
    drop(big);
    heap::reset();
    let r = heap::read().expect("installed");
    assert_eq!(r.peak_bytes, r.live_bytes);
    assert_eq!(r.allocations, 0);
    let small = vec![0u8; 1000];
    let r2 = heap::read().expect("installed");
    assert_eq!(r2.peak_bytes, r.live_bytes + 1000);
    assert_eq!(r2.allocations, 1);
    drop(small);
}
