//! Event-queue benchmark: a reschedule-heavy workload shaped like a kinetic
//! simulation.
//!
//! `LIVE` = 10^4 "certificates" each own exactly one scheduled event. One step
//! (= one benchmark iteration = one processed event) pops the earliest event,
//! schedules a replacement for its certificate, and touches 4 random other
//! certificates: each is either rescheduled to a new failure time or cancelled
//! and scheduled again (probability 1/2 each). New times are
//! `now + uniform(1..=2^20)`, ties are broken by certificate id.
//!
//! Compared queues:
//! * `kss::sim::EventQueue` (indexed heap, arity 2 and 4);
//! * `std::collections::BinaryHeap` with lazy deletion (a generation counter
//!   per certificate; stale entries are skipped when popped);
//! * `keyed_priority_queue::KeyedPriorityQueue` (indexed heap + hash map).
//!
//! Two time types: plain `u64` (group `kinetic_10k_u64`), and `Wide` (group
//! `kinetic_10k_wide`), a 128-byte stand-in for the crate's exact event time
//! whose comparisons are decided by an enclosure and bump an atomic counter.
//!
//! Criterion reports the time per iteration, i.e. per processed event. Before
//! the timed runs the benchmark prints, for each queue, the number of priority
//! comparisons per event (counted with a wrapper priority) and the number of
//! stored heap entries, which shows the growth of the lazy heap.
//!
//! Run with `cargo bench -p kss --bench queue`.

use std::cell::Cell;
use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;
use std::hint::black_box;
use std::sync::atomic::{AtomicU64, Ordering as AtomicOrdering};
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use keyed_priority_queue::KeyedPriorityQueue;
use kss::sim::{Enclosed, EventKey, EventQueue};

/// Number of live events.
const LIVE: usize = 10_000;
/// Spread of new event times after `now`.
const SPREAD: u64 = 1 << 20;
/// Random other events touched per step.
const TOUCHED: usize = 4;

/// xorshift64* PRNG (deterministic, no dependency).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// A time type for the workload.
trait Time: Ord + Clone + Enclosed {
    fn from_u64(t: u64) -> Self;
    fn to_u64(&self) -> u64;
}

impl Time for u64 {
    fn from_u64(t: u64) -> Self {
        t
    }
    fn to_u64(&self) -> u64 {
        *self
    }
}

thread_local! {
    static COMPARISONS: Cell<u64> = const { Cell::new(0) };
}

/// A `u64` time whose comparisons are counted.
#[derive(Clone, PartialEq, Eq, Debug)]
struct Counted(u64);

impl Ord for Counted {
    fn cmp(&self, other: &Self) -> Ordering {
        COMPARISONS.with(|c| c.set(c.get() + 1));
        self.0.cmp(&other.0)
    }
}

impl PartialOrd for Counted {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// No enclosure (NaN never decides): the indexed queue compares every pair
/// of priorities it orders with `Ord`, so that the count is the number of
/// heap comparisons.
impl Enclosed for Counted {
    fn enclosure(&self) -> (f64, f64) {
        (f64::NAN, f64::NAN)
    }
}

impl Time for Counted {
    fn from_u64(t: u64) -> Self {
        Counted(t)
    }
    fn to_u64(&self) -> u64 {
        self.0
    }
}

/// Stand-in for the crate's exact event time: 128 bytes (an `f64` enclosure
/// plus an exact representation), compared by the enclosure when it decides,
/// and every comparison bumps a global statistics counter, as `num::Time`
/// does. Only its size and comparison cost matter here.
#[derive(Clone, PartialEq, Debug)]
struct Wide {
    lo: f64,
    hi: f64,
    exact: [u64; 14],
}

static WIDE_COMPARISONS: AtomicU64 = AtomicU64::new(0);

impl Eq for Wide {}

impl Ord for Wide {
    fn cmp(&self, other: &Self) -> Ordering {
        WIDE_COMPARISONS.fetch_add(1, AtomicOrdering::Relaxed);
        if self.hi < other.lo {
            Ordering::Less
        } else if other.hi < self.lo {
            Ordering::Greater
        } else {
            self.exact.cmp(&other.exact)
        }
    }
}

impl PartialOrd for Wide {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Enclosed for Wide {
    fn enclosure(&self) -> (f64, f64) {
        (self.lo, self.hi)
    }
}

impl Time for Wide {
    fn from_u64(t: u64) -> Self {
        let mut exact = [0; 14];
        exact[0] = t;
        // Integer times below 2^53 are exact doubles: point enclosures.
        Wide {
            lo: t as f64,
            hi: t as f64,
            exact,
        }
    }
    fn to_u64(&self) -> u64 {
        self.exact[0]
    }
}

/// Ordering key `(time, tie, seq)` compared like the indexed queue does: one
/// call to `T::cmp`, then the integers on equality.
#[derive(Clone, PartialEq, Eq, Debug)]
struct Key<T> {
    time: T,
    tie: u64,
    seq: u64,
}

impl<T: Ord> Ord for Key<T> {
    fn cmp(&self, other: &Self) -> Ordering {
        self.time
            .cmp(&other.time)
            .then_with(|| (self.tie, self.seq).cmp(&(other.tie, other.seq)))
    }
}

impl<T: Ord> PartialOrd for Key<T> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The operations the workload needs; every certificate `id < LIVE` has
/// exactly one live event.
trait Queue {
    type T: Time;
    fn schedule(&mut self, id: usize, time: Self::T);
    fn pop(&mut self) -> (usize, Self::T);
    fn reschedule(&mut self, id: usize, time: Self::T);
    fn cancel(&mut self, id: usize);
    /// Number of entries stored (live or stale).
    fn stored(&self) -> usize;
}

/// The indexed queue under test.
struct Indexed<T, const D: usize> {
    queue: EventQueue<T, usize, D>,
    keys: Vec<EventKey>,
}

impl<T: Time, const D: usize> Indexed<T, D> {
    fn new() -> Self {
        Self {
            queue: EventQueue::with_capacity(LIVE),
            keys: Vec::with_capacity(LIVE),
        }
    }
}

impl<T: Time, const D: usize> Queue for Indexed<T, D> {
    type T = T;
    fn schedule(&mut self, id: usize, time: T) {
        let key = self.queue.schedule(time, id as u64, id);
        if id == self.keys.len() {
            self.keys.push(key);
        } else {
            self.keys[id] = key;
        }
    }
    fn pop(&mut self) -> (usize, T) {
        let (_, time, id) = self.queue.pop().expect("live events");
        (id, time)
    }
    fn reschedule(&mut self, id: usize, time: T) {
        let ok = self.queue.reschedule(self.keys[id], time);
        debug_assert!(ok);
    }
    fn cancel(&mut self, id: usize) {
        let removed = self.queue.cancel(self.keys[id]);
        debug_assert_eq!(removed, Some(id));
    }
    fn stored(&self) -> usize {
        self.queue.len()
    }
}

/// `std::collections::BinaryHeap` with lazy deletion.
struct Lazy<T> {
    heap: BinaryHeap<Reverse<(Key<T>, usize, u32)>>,
    generation: Vec<u32>,
    /// Sequence number of the current event of each certificate.
    seq_of: Vec<u64>,
    next_seq: u64,
}

impl<T: Time> Lazy<T> {
    fn new() -> Self {
        Self {
            heap: BinaryHeap::with_capacity(LIVE),
            generation: vec![0; LIVE],
            seq_of: vec![0; LIVE],
            next_seq: 0,
        }
    }
    fn push(&mut self, id: usize, time: T, seq: u64) {
        let key = Key {
            time,
            tie: id as u64,
            seq,
        };
        self.heap.push(Reverse((key, id, self.generation[id])));
    }
}

impl<T: Time> Queue for Lazy<T> {
    type T = T;
    fn schedule(&mut self, id: usize, time: T) {
        let seq = self.next_seq;
        self.next_seq += 1;
        self.seq_of[id] = seq;
        self.push(id, time, seq);
    }
    fn pop(&mut self) -> (usize, T) {
        loop {
            let Reverse((key, id, generation)) = self.heap.pop().expect("live events");
            if generation == self.generation[id] {
                self.generation[id] += 1;
                return (id, key.time);
            }
        }
    }
    fn reschedule(&mut self, id: usize, time: T) {
        self.generation[id] += 1;
        self.push(id, time, self.seq_of[id]);
    }
    fn cancel(&mut self, id: usize) {
        self.generation[id] += 1;
    }
    fn stored(&self) -> usize {
        self.heap.len()
    }
}

/// `keyed_priority_queue::KeyedPriorityQueue` (a max-heap, hence `Reverse`).
struct Keyed<T: Ord> {
    queue: KeyedPriorityQueue<usize, Reverse<Key<T>>>,
    seq_of: Vec<u64>,
    next_seq: u64,
}

impl<T: Time> Keyed<T> {
    fn new() -> Self {
        Self {
            queue: KeyedPriorityQueue::with_capacity(LIVE),
            seq_of: vec![0; LIVE],
            next_seq: 0,
        }
    }
}

impl<T: Time> Queue for Keyed<T> {
    type T = T;
    fn schedule(&mut self, id: usize, time: T) {
        let seq = self.next_seq;
        self.next_seq += 1;
        self.seq_of[id] = seq;
        let key = Key {
            time,
            tie: id as u64,
            seq,
        };
        self.queue.push(id, Reverse(key));
    }
    fn pop(&mut self) -> (usize, T) {
        let (id, Reverse(key)) = self.queue.pop().expect("live events");
        (id, key.time)
    }
    fn reschedule(&mut self, id: usize, time: T) {
        let key = Key {
            time,
            tie: id as u64,
            seq: self.seq_of[id],
        };
        let old = self.queue.set_priority(&id, Reverse(key));
        debug_assert!(old.is_ok());
    }
    fn cancel(&mut self, id: usize) {
        let old = self.queue.remove(&id);
        debug_assert!(old.is_some());
    }
    fn stored(&self) -> usize {
        self.queue.len()
    }
}

/// A queue plus the workload's state.
struct Workload<Q> {
    queue: Q,
    rng: Rng,
}

impl<Q: Queue> Workload<Q> {
    fn new(mut queue: Q) -> Self {
        let mut rng = Rng(0x1234_5678_9ABC_DEF1);
        for id in 0..LIVE {
            queue.schedule(id, Q::T::from_u64(1 + rng.below(SPREAD)));
        }
        Self { queue, rng }
    }

    /// Processes one event.
    fn step(&mut self) -> u64 {
        let (id, time) = self.queue.pop();
        let now = time.to_u64();
        let rng = &mut self.rng;
        self.queue
            .schedule(id, Q::T::from_u64(now + 1 + rng.below(SPREAD)));
        for _ in 0..TOUCHED {
            let other = rng.below(LIVE as u64) as usize;
            let new_time = Q::T::from_u64(now + 1 + rng.below(SPREAD));
            if rng.next() & 1 == 0 {
                self.queue.reschedule(other, new_time);
            } else {
                self.queue.cancel(other);
                self.queue.schedule(other, new_time);
            }
        }
        now
    }
}

/// Prints comparisons per event and stored entries for one queue.
fn report<Q: Queue<T = Counted>>(name: &str, queue: Q) {
    const WARM: usize = 100_000;
    const COUNTED: usize = 100_000;
    let mut w = Workload::new(queue);
    for _ in 0..WARM {
        w.step();
    }
    let before = COMPARISONS.with(Cell::get);
    for _ in 0..COUNTED {
        w.step();
    }
    let after = COMPARISONS.with(Cell::get);
    eprintln!(
        "{name:>24}: {:6.1} comparisons/event, {:6} stored entries for {LIVE} live",
        (after - before) as f64 / COUNTED as f64,
        w.queue.stored()
    );
}

/// Times one queue on the workload; one iteration processes one event.
fn bench_one<Q: Queue>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    queue: Q,
) {
    let mut w = Workload::new(queue);
    group.bench_function(name, |b| b.iter(|| black_box(w.step())));
}

/// Times all queues with time type `T`.
fn bench_group<T: Time>(c: &mut Criterion, name: &str) {
    let mut group = c.benchmark_group(name);
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .throughput(Throughput::Elements(1));
    bench_one(&mut group, "event_queue_d2", Indexed::<T, 2>::new());
    bench_one(&mut group, "event_queue_d4", Indexed::<T, 4>::new());
    bench_one(&mut group, "binary_heap_lazy", Lazy::<T>::new());
    bench_one(&mut group, "keyed_priority_queue", Keyed::<T>::new());
    group.finish();
}

fn bench_queues(c: &mut Criterion) {
    eprintln!(
        "queue workload: {LIVE} live events; per event 1 pop, 1 schedule and \
         {TOUCHED} x (reschedule or cancel + schedule)"
    );
    report("EventQueue<_, _, 2>", Indexed::<Counted, 2>::new());
    report("EventQueue<_, _, 4>", Indexed::<Counted, 4>::new());
    report("BinaryHeap (lazy)", Lazy::<Counted>::new());
    report("KeyedPriorityQueue", Keyed::<Counted>::new());
    bench_group::<u64>(c, "kinetic_10k_u64");
    bench_group::<Wide>(c, "kinetic_10k_wide");
}

criterion_group!(benches, bench_queues);
criterion_main!(benches);
