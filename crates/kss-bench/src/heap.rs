//! A counting global allocator: the live heap bytes, their peak and the
//! number of allocations, for the cells' memory figures.
//!
//! The `kss-bench` binary installs [`Counting`] as its global allocator
//! (`src/main.rs`); each cell's child process resets the counters
//! ([`reset`]) just before the method's run and reads them ([`read`]) just
//! after it. Unlike the peak resident size (`VmHWM`), which also counts the
//! binary's pages and whatever the system allocator keeps mapped, the peak of
//! live heap bytes depends on what the method allocates, so it compares two
//! versions of the code (two runs of one binary have differed by 10 KB at
//! most, on 2 of the perf set's 66 cells).
//!
//! The counters are plain relaxed loads and stores, not read-modify-write
//! operations: the allocator then costs a few instructions per call, so the
//! wall times it runs beside are not distorted, and the counts are exact
//! for a single-threaded process (every method measured here runs on one
//! thread; with several threads, updates could be lost).
//!
//! Not a crate: the counting allocators on crates.io either keep no peak
//! that can be reset between the scene's construction and the run
//! (`stats_alloc`, `cap`), copy the block on every `realloc` (`peak_alloc`,
//! which changes the very allocation pattern being measured), or pay
//! several atomic read-modify-writes per allocation, which would slow the
//! allocation-heavy methods more than the others in the wall-time columns.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering::Relaxed};

/// Live heap bytes (requested sizes).
static LIVE: AtomicUsize = AtomicUsize::new(0);
/// The largest [`LIVE`] since the last [`reset`].
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// Allocations (`alloc`, `alloc_zeroed` and `realloc` calls) since the last
/// [`reset`].
static CALLS: AtomicU64 = AtomicU64::new(0);
/// Allocations since the process started: zero when [`Counting`] is not
/// the global allocator.
static EVER: AtomicU64 = AtomicU64::new(0);

/// The system allocator, counting (install it with `#[global_allocator]`).
#[derive(Clone, Copy, Debug, Default)]
pub struct Counting;

#[inline]
fn grew(by: usize) {
    let live = LIVE.load(Relaxed) + by;
    LIVE.store(live, Relaxed);
    if live > PEAK.load(Relaxed) {
        PEAK.store(live, Relaxed);
    }
    CALLS.store(CALLS.load(Relaxed) + 1, Relaxed);
    EVER.store(EVER.load(Relaxed) + 1, Relaxed);
}

#[inline]
fn shrank(by: usize) {
    LIVE.store(LIVE.load(Relaxed).saturating_sub(by), Relaxed);
}

// SAFETY: every call is forwarded unchanged to `System`, which upholds the
// `GlobalAlloc` contract; the counters only observe the sizes.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract for `alloc`, passed on.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract for `alloc_zeroed`, passed on.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract for `dealloc`, passed on.
        unsafe { System.dealloc(ptr, layout) };
        shrank(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller's contract for `realloc`, passed on.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            shrank(layout.size());
            grew(new_size);
        }
        p
    }
}

/// What the counters read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HeapUse {
    /// Live heap bytes now.
    pub live_bytes: u64,
    /// The largest number of live heap bytes since the last [`reset`].
    pub peak_bytes: u64,
    /// Allocations (`alloc`, `alloc_zeroed`, `realloc`) since the last
    /// [`reset`].
    pub allocations: u64,
}

/// Whether [`Counting`] is this process's global allocator (it has counted
/// an allocation).
pub fn installed() -> bool {
    EVER.load(Relaxed) > 0
}

/// Start a measurement: the peak becomes the live bytes now, the
/// allocation count zero.
pub fn reset() {
    PEAK.store(LIVE.load(Relaxed), Relaxed);
    CALLS.store(0, Relaxed);
}

/// The counters now; `None` unless [`installed`].
pub fn read() -> Option<HeapUse> {
    installed().then(|| HeapUse {
        live_bytes: LIVE.load(Relaxed) as u64,
        peak_bytes: PEAK.load(Relaxed) as u64,
        allocations: CALLS.load(Relaxed),
    })
}
