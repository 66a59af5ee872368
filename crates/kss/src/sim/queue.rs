//! Indexed priority queue of kinetic events, with stable keys.
//!
//! [`EventQueue`] is the event queue of the kinetic simulator. It knows nothing
//! about geometry: it orders opaque payloads `E` by a priority `P` (in the
//! simulator, the exact failure time of a certificate) and hands out stable,
//! copyable [`EventKey`]s so that a scheduled event can later be cancelled or
//! moved to another time in `O(log n)`.
//!
//! # Deterministic order
//!
//! Events are popped in increasing order of the triple
//! `(priority, tie, seq)`:
//!
//! 1. smaller `priority` first (compared with [`Ord`] on `P`);
//! 2. among equal priorities, smaller `tie` first (the `u64` given to
//!    [`EventQueue::schedule`]; the simulator derives it from the identity of
//!    the certificate, so events at the same instant are processed in an order
//!    that does not depend on how the queue happened to be built);
//! 3. among equal `(priority, tie)`, insertion order: every call to
//!    [`EventQueue::schedule`] takes the next value of a monotone sequence
//!    number `seq`, and the older event comes first. (A caller that holds
//!    an event back and schedules it later in the place it would have had
//!    takes its number earlier, [`EventQueue::reserve_seq`], and schedules
//!    with it, [`EventQueue::schedule_at_seq`].)
//!
//! [`EventQueue::reschedule`] changes only the priority: the event keeps its
//! `tie` **and its original sequence number**. (To make a rescheduled event
//! count as "new" for rule 3, cancel it and schedule it again; it then gets a
//! new key.) Since the triple is unique for every live event, the order is a
//! strict total order and the whole pop sequence is a deterministic function
//! of the sequence of operations, independent of heap layout details.
//!
//! # Keys
//!
//! An [`EventKey`] is a slot index plus a generation counter. A slot is reused
//! (most recently freed first) after its event was popped, cancelled or
//! cleared, but the reused slot gets a new generation, so a key is dead forever
//! once its event has left the queue: every operation with a dead key is a
//! no-op that returns `None`/`false`. A slot whose 32-bit generation counter is
//! exhausted is retired (never reused) rather than wrapped around, so stale keys
//! can never come back to life. Keys are only meaningful for the queue that
//! issued them.
//!
//! # Design
//!
//! The queue is an *indexed* implicit `D`-ary min-heap:
//!
//! * a slot table holds, for every slot, its generation, the event
//!   (`priority`, `tie`, `seq`, payload) if the slot is occupied, and either
//!   the event's current heap position (kept up to date on every move) or the
//!   next free slot;
//! * the heap array holds the slot indices with an enclosure of each event's
//!   priority ([`Enclosed`], widened to `f32` bounds: 12-byte nodes), so
//!   sifting moves small values with a hole (no swaps) and never moves
//!   priorities or payloads,
//!   which matters because exact times are large (the crate's exact time
//!   type, `num::Time`, is 72 bytes); and a comparison whose enclosures are
//!   apart reads the heap array only, not the two slots (most comparisons:
//!   distinct failure times rarely share an enclosure), which keeps a sift
//!   within a few cache lines of one array.
//!
//! Cancel and reschedule therefore find the event in `O(1)` and repair the
//! heap in `O(log n)`. Nothing is ever deleted lazily: the heap contains
//! exactly the live events, and the slot table never has more slots than the
//! largest number of simultaneously live events (plus retired slots, one per
//! 2^32 reuses of a slot). A run that processes millions of events with a
//! bounded number of live certificates uses bounded memory.
//!
//! Priorities can be expensive to compare (exact times may fall back to
//! big-integer arithmetic), so the implementation minimises calls to
//! [`Ord::cmp`] on `P`: each heap comparison calls `P::cmp` at most once (not
//! at all when the enclosures decide) and only looks at `tie` and `seq` on
//! equality, and the downward repair (used by
//! `pop`, `cancel` and by `reschedule` to a later time) is *bottom-up*: the
//! hole first goes down to a leaf along the path of smallest children, using
//! only `D - 1` comparisons per level, and the displaced event then climbs
//! back up, which usually stops after one or two comparisons because the event
//! taken from the end of the heap is large. For a binary heap this is about
//! `log2 n` comparisons per pop instead of `2 log2 n` for the textbook sift.
//! `reschedule` compares the new priority with the old one (one comparison) to
//! decide the direction.
//!
//! ## Arity and layout: what was measured
//!
//! The arity `D` is a const parameter, default [`DEFAULT_ARITY`] = 4. A 4-ary
//! heap has half as many levels as a binary one, which makes upward sifts
//! (schedule, earlier reschedule) cheaper, but its bottom-up downward sifts
//! need `3 log4 n = 1.5 log2 n` comparisons instead of `log2 n`. With the
//! enclosures in the heap array most comparisons cost a few instructions on
//! one array, so the extra comparisons cost less than the levels saved.
//!
//! Workload of `benches/queue.rs`: 10^4 live events; per processed event, pop
//! the minimum, schedule a replacement, and for 4 random other events either
//! reschedule or cancel and schedule again (new times uniform in
//! `now + [1, 2^20]`). Criterion's median time per processed event
//! (`cargo bench -p kss --bench queue`, 2026-11-30 on the 2-core development
//! machine, which is noisy: the unchanged rows moved by up to 15 % between
//! two runs); the rows without enclosures are the same heap holding slot
//! indices only (every comparison reads both slots), run by the same bench at
//! commit ebcc722 minutes before the others:
//!
//! ```text
//!                                      heap comparisons  ns/event
//!                                      per event         u64 time   128-byte time
//! EventQueue, D = 4 (default)              34.8             413        477
//! EventQueue, D = 2                        30.2             470        506
//! EventQueue without enclosures, D = 4     34.8             500        640
//! EventQueue without enclosures, D = 2     30.2             495        603
//! std BinaryHeap, lazy delete              82.7             864       2223
//! keyed_priority_queue 0.4                 41.0             618       1152
//! ```
//!
//! The 128-byte time is a stand-in for the exact time type: compared by a
//! floating-point enclosure (also its [`Enclosed`] enclosure), with an
//! atomic statistics counter bumped per comparison. The lazy heap holds about
//! 31,000 entries for the 10,000 live events. In the kinetic structure
//! (exact 72-byte times, about 6,000 live certificates on the gasmix of
//! `kss-bench`) a whole run with slot indices alone and `D = 2` takes 0.7 %
//! more instructions than this layout (callgrind: 0.8626e9 against 0.8565e9
//! on the gasmix, 1.3765e9 against 1.3662e9 on the 1000 16-gons to
//! t = 0.6; the arity accounts for 0.05 % of it), and
//! `f64` bounds (24-byte nodes) 0.1 to 0.2 % fewer than `f32` ones, for
//! twice the heap array (0.19 MB more peak heap on those 16-gons).
//!
//! # Current time and statistics
//!
//! The queue tracks [`EventQueue::now`], the priority of the last popped event
//! (`None` before the first pop), and debug-asserts that pops are monotone
//! non-decreasing. Scheduling an event earlier than `now` is allowed by the
//! queue, but popping it trips that debug assertion: in a kinetic simulation it
//! means a certificate failure was detected in the past. [`EventQueue::clear`]
//! keeps `now`.
//!
//! [`EventQueue::max_len`] is the largest number of simultaneously live events
//! since creation or since the last [`EventQueue::reset_max_len`]; the
//! simulator reports it as the maximum number of scheduled certificates.
//! [`EventQueue::stats`] also counts operations.

use std::cmp::Ordering;
use std::fmt;
use std::iter::FusedIterator;

/// Arity used by [`EventQueue`] when none is given. See the module docs for the
/// measurements behind the choice.
pub const DEFAULT_ARITY: usize = 4;

/// Marker for "no slot" in the free list.
const NONE: u32 = u32::MAX;

/// A priority with a cheap enclosure of its value, for the heap to compare
/// without reading the priority itself (module docs, "Design").
///
/// The enclosure must agree with [`Ord`]: whenever `a.enclosure().1 <
/// b.enclosure().0`, `a < b`. A NaN bound never decides (every comparison
/// with it is false), so `(f64::NAN, f64::NAN)` is always allowed.
pub trait Enclosed {
    /// `(lo, hi)` with `lo ≤` the value `≤ hi` in the sense above.
    fn enclosure(&self) -> (f64, f64);
}

/// Integers convert to `f64` monotonically (rounding to nearest never
/// reverses an order), so the converted value is an enclosure of itself.
macro_rules! enclosed_int {
    ($($t:ty),*) => {$(
        impl Enclosed for $t {
            #[inline]
            fn enclosure(&self) -> (f64, f64) {
                let x = *self as f64;
                (x, x)
            }
        }
    )*};
}
enclosed_int!(u8, u16, u32, u64, usize, i8, i16, i32, i64, isize);

impl Enclosed for crate::num::Time {
    #[inline]
    fn enclosure(&self) -> (f64, f64) {
        let iv = self.interval();
        (iv.lo, iv.hi)
    }
}

/// A heap entry: the slot of an event and its priority's enclosure,
/// widened to `f32` bounds (12 bytes a node; the enclosures of distinct
/// failure times are still apart nearly always).
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: f32,
    hi: f32,
    slot: u32,
}

impl Node {
    /// The node of slot `slot`, whose event has priority `priority`.
    fn of<P: Enclosed>(slot: u32, priority: &P) -> Node {
        let (lo, hi) = priority.enclosure();
        Node {
            lo: f32_down(lo),
            hi: f32_up(hi),
            slot,
        }
    }
}

/// The largest `f32` at most `x` (NaN for NaN).
fn f32_down(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x {
        y.next_down()
    } else {
        y
    }
}

/// The smallest `f32` at least `x` (NaN for NaN).
fn f32_up(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) < x {
        y.next_up()
    } else {
        y
    }
}

/// Stable handle to an event scheduled in an [`EventQueue`].
///
/// A key is a slot index plus the generation of that slot at the time the event
/// was scheduled. It stays valid while the event is in the queue (including
/// across [`EventQueue::reschedule`]) and is dead forever once the event has
/// been popped, cancelled or cleared: operations with a dead key are no-ops
/// returning `None`/`false`, even after the slot has been reused.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct EventKey {
    index: u32,
    generation: u32,
}

impl EventKey {
    /// Slot index of the key (for diagnostics; slots are reused).
    pub fn index(self) -> u32 {
        self.index
    }

    /// Generation of the slot when the key was issued (for diagnostics).
    pub fn generation(self) -> u32 {
        self.generation
    }
}

impl fmt::Display for EventKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}.{}", self.index, self.generation)
    }
}

/// Operation counters of an [`EventQueue`], see [`EventQueue::stats`].
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub struct QueueStats {
    /// Number of successful [`EventQueue::schedule`] calls.
    pub scheduled: u64,
    /// Number of events returned by [`EventQueue::pop`].
    pub popped: u64,
    /// Number of events removed by [`EventQueue::cancel`] (not by `clear`).
    pub cancelled: u64,
    /// Number of successful [`EventQueue::reschedule`] calls.
    pub rescheduled: u64,
    /// Largest number of simultaneously live events since creation or since
    /// the last [`EventQueue::reset_max_len`].
    pub max_len: usize,
}

/// A scheduled event: the full ordering key and the payload.
#[derive(Clone, Debug)]
struct Entry<P, E> {
    priority: P,
    tie: u64,
    seq: u64,
    payload: E,
}

impl<P: Ord, E> Entry<P, E> {
    /// The documented strict order: `(priority, tie, seq)`, calling `P::cmp`
    /// exactly once (the heap asks only where the enclosures do not decide).
    #[inline]
    fn precedes(&self, other: &Self) -> bool {
        match self.priority.cmp(&other.priority) {
            Ordering::Less => true,
            Ordering::Greater => false,
            Ordering::Equal => (self.tie, self.seq) < (other.tie, other.seq),
        }
    }
}

/// A slot of the slot table. `pos` is the heap position of the slot's event
/// while the slot is occupied (`entry` is `Some`), and the next free slot (or
/// [`NONE`]) while it is free.
#[derive(Clone, Debug)]
struct Slot<P, E> {
    generation: u32,
    pos: u32,
    entry: Option<Entry<P, E>>,
}

/// Indexed `D`-ary min-heap of events with stable keys; see the
/// [module docs](self) for the order rule and the design.
///
/// `P` is the priority (an exact event time), `E` the payload, `D` the heap
/// arity (at least 2).
#[derive(Clone, Debug)]
pub struct EventQueue<P, E, const D: usize = DEFAULT_ARITY> {
    /// The implicit heap: slot indices of the live events, each with its
    /// priority's enclosure.
    heap: Vec<Node>,
    /// Slot table: events, generations, heap positions / free-list links.
    slots: Vec<Slot<P, E>>,
    /// Head of the free-slot list.
    free_head: u32,
    /// Next insertion sequence number.
    next_seq: u64,
    /// Priority of the last popped event.
    now: Option<P>,
    /// Operation counters and `max_len`.
    stats: QueueStats,
}

impl<P: Ord + Clone + Enclosed, E, const D: usize> Default for EventQueue<P, E, D> {
    fn default() -> Self {
        Self::new()
    }
}

impl<P: Ord + Clone + Enclosed, E, const D: usize> EventQueue<P, E, D> {
    /// Creates an empty queue.
    pub fn new() -> Self {
        Self::with_capacity(0)
    }

    /// Creates an empty queue with room for `capacity` live events.
    pub fn with_capacity(capacity: usize) -> Self {
        const { assert!(D >= 2, "EventQueue arity must be at least 2") };
        Self {
            heap: Vec::with_capacity(capacity),
            slots: Vec::with_capacity(capacity),
            free_head: NONE,
            next_seq: 0,
            now: None,
            stats: QueueStats::default(),
        }
    }

    /// Number of live (scheduled, not yet popped or cancelled) events.
    pub fn len(&self) -> usize {
        self.heap.len()
    }

    /// Whether the queue has no live event.
    pub fn is_empty(&self) -> bool {
        self.heap.is_empty()
    }

    /// Schedules `payload` at `priority` with tie-breaker `tie` and returns its
    /// key. Among events with equal priority, smaller `tie` pops first, then
    /// the earlier scheduled one.
    ///
    /// # Panics
    ///
    /// If more than `u32::MAX - 1` slots would be needed.
    pub fn schedule(&mut self, priority: P, tie: u64, payload: E) -> EventKey {
        let seq = self.reserve_seq();
        self.schedule_at_seq(priority, tie, seq, payload)
    }

    /// Takes the next insertion sequence number without scheduling anything,
    /// for an event that is scheduled later with it
    /// ([`EventQueue::schedule_at_seq`]) and is to keep the place in the
    /// order (rule 3) that it would have had if scheduled now.
    pub fn reserve_seq(&mut self) -> u64 {
        let seq = self.next_seq;
        self.next_seq += 1;
        seq
    }

    /// [`EventQueue::schedule`] with a sequence number taken earlier by
    /// [`EventQueue::reserve_seq`] (each number at most once, as the order
    /// needs the triple to be unique among live events; debug builds check
    /// that it was reserved).
    pub fn schedule_at_seq(&mut self, priority: P, tie: u64, seq: u64, payload: E) -> EventKey {
        debug_assert!(seq < self.next_seq, "a sequence number never reserved");
        let slot = self.alloc_slot(Entry {
            priority,
            tie,
            seq,
            payload,
        });
        let pos = self.heap.len();
        self.heap.push(Node::of(slot, &self.entry(slot).priority));
        self.sift_up(pos);
        self.stats.scheduled += 1;
        self.stats.max_len = self.stats.max_len.max(self.heap.len());
        self.key_of(slot)
    }

    /// Removes the event of `key` and returns its payload, or `None` if the key
    /// is dead.
    pub fn cancel(&mut self, key: EventKey) -> Option<E> {
        let pos = self.position(key)?;
        let slot = self.remove_at(pos);
        let (_, entry) = self.free_slot(slot);
        self.stats.cancelled += 1;
        Some(entry.payload)
    }

    /// Moves the event of `key` to `new_priority`, keeping its key, its `tie`
    /// and its original insertion sequence number. Returns `false` (and does
    /// nothing) if the key is dead.
    pub fn reschedule(&mut self, key: EventKey, new_priority: P) -> bool {
        let Some(pos) = self.position(key) else {
            return false;
        };
        self.heap[pos] = Node::of(key.index, &new_priority);
        let entry = self.entry_mut(key.index);
        let direction = new_priority.cmp(&entry.priority);
        entry.priority = new_priority;
        match direction {
            Ordering::Less => self.sift_up(pos),
            Ordering::Greater => self.sift_down(pos),
            Ordering::Equal => {}
        }
        self.stats.rescheduled += 1;
        true
    }

    /// Priority and payload of the live event of `key`, or `None` if the key is
    /// dead.
    pub fn get(&self, key: EventKey) -> Option<(&P, &E)> {
        self.position(key)?;
        let entry = self.entry(key.index);
        Some((&entry.priority, &entry.payload))
    }

    /// Mutable access to the payload of the live event of `key` (its priority
    /// can only be changed with [`reschedule`](Self::reschedule)).
    pub fn payload_mut(&mut self, key: EventKey) -> Option<&mut E> {
        self.position(key)?;
        Some(&mut self.entry_mut(key.index).payload)
    }

    /// Whether `key` refers to a live event.
    pub fn contains(&self, key: EventKey) -> bool {
        self.position(key).is_some()
    }

    /// The next event to pop: its key, priority, tie-breaker and payload.
    pub fn peek(&self) -> Option<(EventKey, &P, u64, &E)> {
        let slot = self.heap.first()?.slot;
        let entry = self.entry(slot);
        Some((
            self.key_of(slot),
            &entry.priority,
            entry.tie,
            &entry.payload,
        ))
    }

    /// Removes and returns the first event in the documented order, and sets
    /// [`now`](Self::now) to its priority. The returned key is dead.
    ///
    /// Debug builds assert that the popped priority is not smaller than the
    /// previous `now`.
    pub fn pop(&mut self) -> Option<(EventKey, P, E)> {
        if self.heap.is_empty() {
            return None;
        }
        let slot = self.remove_at(0);
        let (key, entry) = self.free_slot(slot);
        debug_assert!(
            self.now.as_ref().is_none_or(|now| *now <= entry.priority),
            "EventQueue::pop: event earlier than the current time"
        );
        self.now = Some(entry.priority.clone());
        self.stats.popped += 1;
        Some((key, entry.priority, entry.payload))
    }

    /// Removes every event (all their keys become dead). `now` and the
    /// statistics are kept.
    pub fn clear(&mut self) {
        while let Some(node) = self.heap.pop() {
            self.free_slot(node.slot);
        }
    }

    /// Priority of the last popped event, `None` before the first pop.
    pub fn now(&self) -> Option<&P> {
        self.now.as_ref()
    }

    /// Largest number of simultaneously live events since creation or since
    /// the last [`reset_max_len`](Self::reset_max_len).
    pub fn max_len(&self) -> usize {
        self.stats.max_len
    }

    /// Restarts the [`max_len`](Self::max_len) statistic from the current
    /// [`len`](Self::len).
    pub fn reset_max_len(&mut self) {
        self.stats.max_len = self.heap.len();
    }

    /// Operation counters and `max_len`.
    pub fn stats(&self) -> QueueStats {
        self.stats
    }

    /// Iterates over the live events as `(key, priority, tie, payload)`, in
    /// unspecified (heap) order.
    pub fn iter(&self) -> Iter<'_, P, E> {
        Iter {
            heap: self.heap.iter(),
            slots: &self.slots,
        }
    }

    // ----- internals -------------------------------------------------------

    /// Heap position of a live key.
    #[inline]
    fn position(&self, key: EventKey) -> Option<usize> {
        let slot = self.slots.get(key.index as usize)?;
        if slot.generation == key.generation && slot.entry.is_some() {
            Some(slot.pos as usize)
        } else {
            None
        }
    }

    /// Current key of an occupied slot.
    #[inline]
    fn key_of(&self, slot: u32) -> EventKey {
        EventKey {
            index: slot,
            generation: self.slots[slot as usize].generation,
        }
    }

    /// Event of an occupied slot.
    #[inline]
    fn entry(&self, slot: u32) -> &Entry<P, E> {
        self.slots[slot as usize]
            .entry
            .as_ref()
            .expect("EventQueue: live slot without event")
    }

    /// Event of an occupied slot, mutably.
    #[inline]
    fn entry_mut(&mut self, slot: u32) -> &mut Entry<P, E> {
        self.slots[slot as usize]
            .entry
            .as_mut()
            .expect("EventQueue: live slot without event")
    }

    /// Whether the event of node `a` precedes the one of node `b`: by the
    /// enclosures where they are apart, else by the events.
    #[inline]
    fn precedes(&self, a: Node, b: Node) -> bool {
        if a.hi < b.lo {
            return true;
        }
        if b.hi < a.lo {
            return false;
        }
        self.entry(a.slot).precedes(self.entry(b.slot))
    }

    /// Records that node `node` is at heap position `pos`.
    #[inline]
    fn place(&mut self, pos: usize, node: Node) {
        self.heap[pos] = node;
        self.slots[node.slot as usize].pos = pos as u32;
    }

    /// Takes a free slot (or a new one) for `entry`.
    fn alloc_slot(&mut self, entry: Entry<P, E>) -> u32 {
        if self.free_head != NONE {
            let index = self.free_head;
            let slot = &mut self.slots[index as usize];
            self.free_head = slot.pos;
            slot.entry = Some(entry);
            index
        } else {
            let index = self.slots.len();
            assert!(index < NONE as usize, "EventQueue: too many slots");
            self.slots.push(Slot {
                generation: 0,
                pos: 0,
                entry: Some(entry),
            });
            index as u32
        }
    }

    /// Frees an occupied slot that has already left the heap; returns the (now
    /// dead) key and the event.
    fn free_slot(&mut self, index: u32) -> (EventKey, Entry<P, E>) {
        let slot = &mut self.slots[index as usize];
        let entry = slot.entry.take().expect("EventQueue: freeing a free slot");
        let key = EventKey {
            index,
            generation: slot.generation,
        };
        if slot.generation < u32::MAX {
            slot.generation += 1;
            slot.pos = self.free_head;
            self.free_head = index;
        }
        // else: generations exhausted, the slot is retired (never reused).
        (key, entry)
    }

    /// Removes the entry at heap position `pos`, restores the heap and returns
    /// the removed slot.
    fn remove_at(&mut self, pos: usize) -> u32 {
        let removed = self.heap.swap_remove(pos);
        if pos < self.heap.len() {
            // The former last entry now sits at `pos`.
            if pos > 0 && self.precedes(self.heap[pos], self.heap[(pos - 1) / D]) {
                self.sift_up(pos);
            } else {
                self.sift_down(pos);
            }
        }
        removed.slot
    }

    /// Moves the event at heap position `pos` up to its place.
    fn sift_up(&mut self, mut pos: usize) {
        let moving = self.heap[pos];
        while pos > 0 {
            let parent = (pos - 1) / D;
            let above = self.heap[parent];
            if !self.precedes(moving, above) {
                break;
            }
            self.place(pos, above);
            pos = parent;
        }
        self.place(pos, moving);
    }

    /// Moves the event at heap position `start` down to its place (bottom-up:
    /// the hole first goes down to a leaf along the smallest children, then the
    /// event climbs back up, never above `start`). Requires that the event
    /// does not precede the parent of `start`.
    fn sift_down(&mut self, start: usize) {
        let moving = self.heap[start];
        let len = self.heap.len();
        let mut pos = start;
        loop {
            let first = D * pos + 1;
            if first >= len {
                break;
            }
            let end = (first + D).min(len);
            let mut best = first;
            let mut best_node = self.heap[first];
            for child in first + 1..end {
                let child_node = self.heap[child];
                if self.precedes(child_node, best_node) {
                    best = child;
                    best_node = child_node;
                }
            }
            self.place(pos, best_node);
            pos = best;
        }
        while pos > start {
            let parent = (pos - 1) / D;
            let above = self.heap[parent];
            if !self.precedes(moving, above) {
                break;
            }
            self.place(pos, above);
            pos = parent;
        }
        self.place(pos, moving);
    }
}

/// Iterator over the live events of an [`EventQueue`], yielding
/// `(key, priority, tie, payload)` in unspecified order; see
/// [`EventQueue::iter`].
#[derive(Clone, Debug)]
pub struct Iter<'a, P, E> {
    heap: std::slice::Iter<'a, Node>,
    slots: &'a [Slot<P, E>],
}

impl<'a, P, E> Iterator for Iter<'a, P, E> {
    type Item = (EventKey, &'a P, u64, &'a E);

    fn next(&mut self) -> Option<Self::Item> {
        let index = self.heap.next()?.slot;
        let slot = &self.slots[index as usize];
        let entry = slot
            .entry
            .as_ref()
            .expect("EventQueue: live slot without event");
        let key = EventKey {
            index,
            generation: slot.generation,
        };
        Some((key, &entry.priority, entry.tie, &entry.payload))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.heap.size_hint()
    }
}

impl<P, E> ExactSizeIterator for Iter<'_, P, E> {}

impl<P, E> FusedIterator for Iter<'_, P, E> {}

impl<'a, P: Ord + Clone + Enclosed, E, const D: usize> IntoIterator for &'a EventQueue<P, E, D> {
    type Item = (EventKey, &'a P, u64, &'a E);
    type IntoIter = Iter<'a, P, E>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small deterministic PRNG (xorshift64*), to keep the library free of a
    /// `rand` dependency.
    struct XorShift(u64);

    impl XorShift {
        fn new(seed: u64) -> Self {
            Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
        }
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

    /// Checks the heap property and the slot table against each other.
    fn check_invariants<P: Ord + Clone + Enclosed, E, const D: usize>(q: &EventQueue<P, E, D>) {
        for (pos, &node) in q.heap.iter().enumerate() {
            if pos > 0 {
                assert!(!q.precedes(node, q.heap[(pos - 1) / D]), "heap order");
            }
            let slot = node.slot;
            assert_eq!(q.slots[slot as usize].pos as usize, pos, "slot position");
            let entry = q.slots[slot as usize].entry.as_ref().expect("a live slot");
            let (lo, hi) = entry.priority.enclosure();
            assert_eq!(
                (f32_down(lo).to_bits(), f32_up(hi).to_bits()),
                (node.lo.to_bits(), node.hi.to_bits()),
                "the node's enclosure is its priority's"
            );
        }
        let occupied = q.slots.iter().filter(|s| s.entry.is_some()).count();
        assert_eq!(occupied, q.heap.len());
        // Every vacant slot is either on the free list (once) or retired.
        let mut on_free_list = vec![false; q.slots.len()];
        let mut f = q.free_head;
        while f != NONE {
            assert!(q.slots[f as usize].entry.is_none());
            assert!(!on_free_list[f as usize], "free list cycle");
            on_free_list[f as usize] = true;
            f = q.slots[f as usize].pos;
        }
        for (i, slot) in q.slots.iter().enumerate() {
            if slot.entry.is_none() && !on_free_list[i] {
                assert_eq!(slot.generation, u32::MAX, "leaked slot");
            }
        }
    }

    fn drain<P: Ord + Clone + Enclosed, E, const D: usize>(
        q: &mut EventQueue<P, E, D>,
    ) -> Vec<(P, E)> {
        std::iter::from_fn(|| q.pop().map(|(_, p, e)| (p, e))).collect()
    }

    #[test]
    fn pops_in_priority_order() {
        let mut q: EventQueue<i64, &str> = EventQueue::new();
        assert!(q.is_empty());
        assert_eq!(q.peek(), None);
        assert_eq!(q.pop(), None);
        q.schedule(5, 0, "e");
        q.schedule(1, 0, "a");
        q.schedule(3, 0, "c");
        q.schedule(2, 0, "b");
        q.schedule(4, 0, "d");
        assert_eq!(q.len(), 5);
        assert_eq!(q.peek().map(|(_, p, t, e)| (*p, t, *e)), Some((1, 0, "a")));
        check_invariants(&q);
        let order: Vec<_> = drain(&mut q).into_iter().map(|(_, e)| e).collect();
        assert_eq!(order, ["a", "b", "c", "d", "e"]);
        assert_eq!(q.now(), Some(&5));
        assert!(q.is_empty());
    }

    #[test]
    fn ties_then_insertion_order() {
        let mut q: EventQueue<u32, u32, 4> = EventQueue::new();
        q.schedule(7, 2, 0);
        q.schedule(7, 1, 1);
        q.schedule(7, 2, 2);
        q.schedule(7, 1, 3);
        q.schedule(6, 9, 4);
        q.schedule(7, 0, 5);
        let order: Vec<_> = drain(&mut q).into_iter().map(|(_, e)| e).collect();
        assert_eq!(order, [4, 5, 1, 3, 0, 2]);
    }

    #[test]
    fn reschedule_keeps_key_tie_and_sequence() {
        let mut q: EventQueue<u32, &str> = EventQueue::new();
        let a = q.schedule(10, 0, "a");
        let b = q.schedule(20, 0, "b");
        let c = q.schedule(30, 0, "c");
        // Move c before a and b.
        assert!(q.reschedule(c, 5));
        assert_eq!(q.get(c), Some((&5, &"c")));
        assert_eq!(q.peek().map(|(k, ..)| k), Some(c));
        // Move c to the same time as b: c was scheduled after b, so b first.
        assert!(q.reschedule(c, 20));
        // Move a to the same time too: a was scheduled first.
        assert!(q.reschedule(a, 20));
        assert!(q.reschedule(a, 20)); // same priority: no-op that succeeds
        check_invariants(&q);
        let order: Vec<_> = drain(&mut q).into_iter().map(|(_, e)| e).collect();
        assert_eq!(order, ["a", "b", "c"]);
        assert!(!q.contains(b));
        assert_eq!(q.stats().rescheduled, 4);
    }

    #[test]
    fn cancel_returns_payload_once() {
        let mut q: EventQueue<u32, String> = EventQueue::new();
        let a = q.schedule(1, 0, "a".to_string());
        let b = q.schedule(2, 0, "b".to_string());
        let c = q.schedule(3, 0, "c".to_string());
        assert_eq!(q.cancel(b).as_deref(), Some("b"));
        assert_eq!(q.cancel(b), None);
        assert!(!q.contains(b));
        assert!(!q.reschedule(b, 0));
        assert_eq!(q.get(b), None);
        assert_eq!(q.payload_mut(b), None);
        q.payload_mut(c).unwrap().push('!');
        assert_eq!(q.len(), 2);
        assert_eq!(q.pop(), Some((a, 1, "a".into())));
        assert_eq!(q.pop(), Some((c, 3, "c!".into())));
        let s = q.stats();
        assert_eq!((s.scheduled, s.popped, s.cancelled), (3, 2, 1));
    }

    #[test]
    fn dead_keys_stay_dead_after_slot_reuse() {
        let mut q: EventQueue<u32, u32> = EventQueue::new();
        let a = q.schedule(1, 0, 100);
        let (popped, _, _) = q.pop().unwrap();
        assert_eq!(popped, a);
        // The slot is reused with a new generation.
        let b = q.schedule(2, 0, 200);
        assert_eq!(a.index(), b.index());
        assert_ne!(a, b);
        assert!(!q.contains(a));
        assert_eq!(q.get(a), None);
        assert_eq!(q.cancel(a), None);
        assert!(!q.reschedule(a, 0));
        assert_eq!(q.get(b), Some((&2, &200)));
        assert_eq!(q.cancel(b), Some(200));
        let c = q.schedule(3, 0, 300);
        assert_eq!(c.index(), a.index());
        assert!(!q.contains(a) && !q.contains(b) && q.contains(c));
        // clear kills every key.
        let d = q.schedule(4, 0, 400);
        q.clear();
        assert!(q.is_empty());
        assert!(!q.contains(c) && !q.contains(d));
        let e = q.schedule(5, 0, 500);
        assert!(!q.contains(c) && !q.contains(d) && q.contains(e));
        // A key that was never issued.
        assert!(!q.contains(EventKey {
            index: 1000,
            generation: 0
        }));
        check_invariants(&q);
    }

    #[test]
    fn exhausted_slot_is_retired() {
        let mut q: EventQueue<u32, u32> = EventQueue::new();
        let a = q.schedule(1, 0, 1);
        q.slots[a.index as usize].generation = u32::MAX;
        let a = q.key_of(a.index);
        assert_eq!(q.cancel(a), Some(1));
        let b = q.schedule(1, 0, 2);
        assert_ne!(a.index(), b.index());
        assert!(!q.contains(a));
        assert_eq!(q.get(b), Some((&1, &2)));
        check_invariants(&q);
    }

    #[test]
    fn now_and_max_len() {
        let mut q: EventQueue<u32, ()> = EventQueue::new();
        assert_eq!(q.now(), None);
        for t in [5, 3, 8, 1] {
            q.schedule(t, 0, ());
        }
        assert_eq!(q.max_len(), 4);
        q.pop();
        assert_eq!(q.now(), Some(&1));
        q.pop();
        assert_eq!(q.now(), Some(&3));
        q.reset_max_len();
        assert_eq!(q.max_len(), 2);
        q.schedule(3, 0, ()); // same instant as now is fine
        assert_eq!(q.max_len(), 3);
        assert_eq!(q.pop().map(|(_, p, _)| p), Some(3));
        q.clear();
        assert_eq!(q.now(), Some(&3));
        assert_eq!(q.max_len(), 3);
    }

    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "earlier than the current time")]
    fn pop_in_the_past_panics_in_debug() {
        let mut q: EventQueue<u32, ()> = EventQueue::new();
        q.schedule(5, 0, ());
        q.pop();
        q.schedule(4, 0, ());
        q.pop();
    }

    #[test]
    fn iter_visits_live_events() {
        let mut q: EventQueue<u32, u32, 3> = EventQueue::new();
        let keys: Vec<_> = (0..20)
            .map(|i| q.schedule(i * 7 % 20, i as u64, i))
            .collect();
        for k in keys.iter().step_by(3) {
            q.cancel(*k);
        }
        let mut seen: Vec<_> = q.iter().map(|(k, p, t, e)| (k, *p, t, *e)).collect();
        assert_eq!(q.iter().len(), q.len());
        seen.sort_by_key(|&(_, _, _, e)| e);
        let expected: Vec<_> = (0..20u32)
            .filter(|i| i % 3 != 0)
            .map(|i| (keys[i as usize], i * 7 % 20, i as u64, i))
            .collect();
        assert_eq!(seen, expected);
        assert_eq!((&q).into_iter().count(), expected.len());
    }

    /// Naive reference: a vector scanned for the minimum.
    #[derive(Default)]
    struct Reference {
        live: Vec<(EventKey, u64, u64, u64, u32)>, // key, priority, tie, seq, payload
        next_seq: u64,
    }

    impl Reference {
        fn min_index(&self) -> Option<usize> {
            (0..self.live.len()).min_by_key(|&i| {
                let (_, p, t, s, _) = self.live[i];
                (p, t, s)
            })
        }
        fn find(&self, key: EventKey) -> Option<usize> {
            self.live.iter().position(|e| e.0 == key)
        }
    }

    fn randomized<const D: usize>(seed: u64, steps: usize, time_range: u64) {
        let mut rng = XorShift::new(seed);
        let mut q: EventQueue<u64, u32, D> = EventQueue::new();
        let mut r = Reference::default();
        let mut dead: Vec<EventKey> = Vec::new();
        let mut now = 0u64;
        let mut max_len = 0;
        for step in 0..steps {
            // Bias towards growth early, towards shrinking late.
            let op = rng.below(100);
            let grow = if step < steps / 2 { 40 } else { 25 };
            if op < grow {
                let p = now + rng.below(time_range);
                let tie = rng.below(3);
                let payload = rng.next() as u32;
                let key = q.schedule(p, tie, payload);
                assert!(r.find(key).is_none() && !dead.contains(&key));
                r.live.push((key, p, tie, r.next_seq, payload));
                r.next_seq += 1;
            } else if op < grow + 15 {
                match r.min_index() {
                    None => assert_eq!(q.pop(), None),
                    Some(i) => {
                        let (k, p, _, _, e) = r.live.swap_remove(i);
                        assert_eq!(q.pop(), Some((k, p, e)));
                        now = p;
                        assert_eq!(q.now(), Some(&now));
                        dead.push(k);
                    }
                }
            } else if op < grow + 30 {
                if r.live.is_empty() {
                    continue;
                }
                let i = rng.below(r.live.len() as u64) as usize;
                let (k, _, _, _, e) = r.live.swap_remove(i);
                assert_eq!(q.cancel(k), Some(e));
                dead.push(k);
            } else if op < grow + 50 {
                if r.live.is_empty() {
                    continue;
                }
                let i = rng.below(r.live.len() as u64) as usize;
                let p = now + rng.below(time_range);
                assert!(q.reschedule(r.live[i].0, p));
                r.live[i].1 = p;
            } else if op < grow + 58 {
                // Operations with a dead key are no-ops.
                if dead.is_empty() {
                    continue;
                }
                let k = dead[rng.below(dead.len() as u64) as usize];
                assert!(!q.contains(k));
                assert_eq!(q.get(k), None);
                assert_eq!(q.cancel(k), None);
                assert!(!q.reschedule(k, now));
                assert_eq!(q.payload_mut(k), None);
            } else if op < grow + 59 && rng.below(20) == 0 {
                q.clear();
                dead.extend(r.live.drain(..).map(|e| e.0));
            } else {
                // Look-ups.
                if let Some(i) = r.min_index() {
                    let (k, p, t, _, e) = r.live[i];
                    assert_eq!(q.peek(), Some((k, &p, t, &e)));
                } else {
                    assert_eq!(q.peek(), None);
                }
                if !r.live.is_empty() {
                    let (k, p, _, _, e) = r.live[rng.below(r.live.len() as u64) as usize];
                    assert!(q.contains(k));
                    assert_eq!(q.get(k), Some((&p, &e)));
                }
            }
            max_len = max_len.max(r.live.len());
            assert_eq!(q.len(), r.live.len());
            assert_eq!(q.max_len(), max_len);
            if step % 97 == 0 {
                check_invariants(&q);
                let mut a: Vec<_> = q.iter().map(|(k, p, t, e)| (k, *p, t, *e)).collect();
                let mut b: Vec<_> = r.live.iter().map(|&(k, p, t, _, e)| (k, p, t, e)).collect();
                a.sort();
                b.sort();
                assert_eq!(a, b);
            }
        }
        check_invariants(&q);
        // Drain and compare the tail.
        while let Some(i) = r.min_index() {
            let (k, p, _, _, e) = r.live.swap_remove(i);
            assert_eq!(q.pop(), Some((k, p, e)));
        }
        assert_eq!(q.pop(), None);
    }

    #[test]
    fn randomized_against_reference() {
        for seed in 1..=6 {
            // Small time range: many equal priorities, exercising ties.
            randomized::<2>(seed, 6000, 8);
            randomized::<2>(seed, 6000, 1 << 20);
            randomized::<3>(seed, 3000, 16);
            randomized::<4>(seed, 6000, 8);
            randomized::<4>(seed, 6000, 1 << 20);
            randomized::<8>(seed, 3000, 64);
        }
    }

    #[test]
    fn f32_bounds_are_the_nearest_outward() {
        let mut rng = XorShift::new(7);
        let mut xs = vec![
            0.0,
            -0.0,
            1.0,
            0.1,
            -0.1,
            1e-310,
            -1e-310,
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::from(f32::MAX),
            16_777_217.0,
        ];
        xs.extend(
            (0..2000)
                .map(|_| f64::from_bits(rng.next()))
                .filter(|x| !x.is_nan()),
        );
        for x in xs {
            let (d, u) = (f32_down(x), f32_up(x));
            assert!(f64::from(d) <= x && x <= f64::from(u), "{x:e}: {d:e} {u:e}");
            assert!(
                d == f32::INFINITY || f64::from(d.next_up()) > x,
                "{x:e}: {d:e} not the largest"
            );
            assert!(
                u == f32::NEG_INFINITY || f64::from(u.next_down()) < x,
                "{x:e}: {u:e} not the smallest"
            );
        }
        assert!(f32_down(f64::NAN).is_nan() && f32_up(f64::NAN).is_nan());
    }

    /// A priority whose enclosure is wide and often overlaps others (a
    /// radius of 0 to 64 that depends on the value only), or NaN: the
    /// heap then decides some comparisons by the enclosures and the rest by
    /// `Ord`, which must give the same order.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
    struct Blurred(u64);

    impl Enclosed for Blurred {
        fn enclosure(&self) -> (f64, f64) {
            let r = (self.0.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 58) as f64;
            if self.0 % 97 == 0 {
                return (f64::NAN, f64::NAN);
            }
            (self.0 as f64 - r, self.0 as f64 + r)
        }
    }

    #[test]
    fn enclosures_that_overlap_give_the_order_of_the_priorities() {
        for seed in 1..=4 {
            let mut rng = XorShift::new(seed);
            let mut q: EventQueue<Blurred, usize> = EventQueue::new();
            // (key, priority, tie, seq)
            let mut live: Vec<(EventKey, u64, u64, usize)> = Vec::new();
            for seq in 0..3000 {
                let p = 1000 + rng.below(400);
                let tie = rng.below(2);
                live.push((q.schedule(Blurred(p), tie, seq), p, tie, seq));
                if rng.below(4) == 0 {
                    let i = rng.below(live.len() as u64) as usize;
                    let p = 1000 + rng.below(400);
                    assert!(q.reschedule(live[i].0, Blurred(p)));
                    live[i].1 = p;
                }
                if rng.below(5) == 0 {
                    let i = rng.below(live.len() as u64) as usize;
                    let (k, _, _, seq) = live.swap_remove(i);
                    assert_eq!(q.cancel(k), Some(seq));
                }
            }
            check_invariants(&q);
            live.sort_by_key(|&(_, p, tie, seq)| (p, tie, seq));
            for &(k, p, _, seq) in &live {
                assert_eq!(q.pop(), Some((k, Blurred(p), seq)));
            }
            assert_eq!(q.pop(), None);
        }
    }

    #[test]
    fn memory_stays_flat_over_a_million_events() {
        const LIVE: usize = 1000;
        let mut rng = XorShift::new(42);
        let mut q: EventQueue<u64, usize> = EventQueue::new();
        let mut keys: Vec<EventKey> = (0..LIVE)
            .map(|i| q.schedule(rng.below(1 << 16), 0, i))
            .collect();
        for _ in 0..1_000_000 {
            let (_, t, id) = q.pop().unwrap();
            keys[id] = q.schedule(t + 1 + rng.below(1 << 16), id as u64, id);
            let other = rng.below(LIVE as u64) as usize;
            if rng.below(2) == 0 {
                assert!(q.reschedule(keys[other], t + rng.below(1 << 16)));
            } else {
                assert_eq!(q.cancel(keys[other]), Some(other));
                keys[other] = q.schedule(t + rng.below(1 << 16), other as u64, other);
            }
        }
        assert_eq!(q.len(), LIVE);
        assert!(q.slots.len() <= LIVE + 1);
        assert!(q.heap.capacity() <= 2 * LIVE);
        assert!(q.max_len() <= LIVE + 1);
        check_invariants(&q);
    }

    mod prop {
        use super::super::*;
        use proptest::prelude::*;

        #[derive(Clone, Debug)]
        enum Op {
            Schedule(u8, u8),
            Pop,
            Cancel(usize),
            Reschedule(usize, u8),
        }

        fn op() -> impl Strategy<Value = Op> {
            prop_oneof![
                3 => (any::<u8>(), 0u8..3).prop_map(|(p, t)| Op::Schedule(p, t)),
                2 => Just(Op::Pop),
                1 => any::<usize>().prop_map(Op::Cancel),
                2 => (any::<usize>(), any::<u8>()).prop_map(|(i, p)| Op::Reschedule(i, p)),
            ]
        }

        proptest! {
            /// Every key ever issued (live or dead) is checked after each
            /// operation; pops follow the `(priority, tie, seq)` order of the
            /// current live set.
            #[test]
            fn matches_sorted_model(ops in proptest::collection::vec(op(), 0..200)) {
                let mut q: EventQueue<u32, usize, 4> = EventQueue::new();
                // (key, priority, tie, seq, alive)
                let mut model: Vec<(EventKey, u32, u64, u64, bool)> = Vec::new();
                let mut floor = 0u32;
                for op in ops {
                    match op {
                        Op::Schedule(p, t) => {
                            let p = floor + u32::from(p);
                            let seq = model.len() as u64;
                            let k = q.schedule(p, u64::from(t), model.len());
                            model.push((k, p, u64::from(t), seq, true));
                        }
                        Op::Pop => {
                            let best = model
                                .iter()
                                .enumerate()
                                .filter(|(_, m)| m.4)
                                .min_by_key(|(_, m)| (m.1, m.2, m.3))
                                .map(|(i, _)| i);
                            let got = q.pop();
                            match best {
                                None => prop_assert!(got.is_none()),
                                Some(i) => {
                                    prop_assert_eq!(got, Some((model[i].0, model[i].1, i)));
                                    model[i].4 = false;
                                    floor = model[i].1;
                                }
                            }
                        }
                        Op::Cancel(i) if !model.is_empty() => {
                            let i = i % model.len();
                            let got = q.cancel(model[i].0);
                            prop_assert_eq!(got, model[i].4.then_some(i));
                            model[i].4 = false;
                        }
                        Op::Reschedule(i, p) if !model.is_empty() => {
                            let i = i % model.len();
                            let p = floor + u32::from(p);
                            prop_assert_eq!(q.reschedule(model[i].0, p), model[i].4);
                            if model[i].4 {
                                model[i].1 = p;
                            }
                        }
                        _ => {}
                    }
                    for (i, m) in model.iter().enumerate() {
                        prop_assert_eq!(q.get(m.0), m.4.then_some((&m.1, &i)));
                    }
                    prop_assert_eq!(q.len(), model.iter().filter(|m| m.4).count());
                }
            }
        }
    }
}
