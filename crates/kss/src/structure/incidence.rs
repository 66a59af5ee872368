//! Which partition triangles and corridors lie on a body, without a scan of
//! the whole structure: a pop looks for the triangles with a corner at the
//! popped vertex and the corridors along its body, and a removal for the
//! triangles and corridors on the removed bodies. A scan of every triangle
//! and corridor costs `O(k)` per operation; the index answers in time
//! proportional to the body's share of the structure (amortized).
//!
//! The triangles and corridors are kept in [`Slots`], vectors that note which
//! entries were written (an `IndexMut`, a `push`) since the index last
//! looked. The index keeps, per body, a list of ids that is a superset of
//! the triangles (corridors) on it: at a query it first adds each written
//! entry to the lists of the bodies it is on now, then filters the asked
//! list down to the entries still on the body. A list never misses an entry
//! on its body, because an entry can only come onto a body by a write, and
//! every write is noted. When more writes are noted than the structure has
//! entries, the notes are dropped and the next query rebuilds the lists in
//! one scan (so neither the notes nor the lists outgrow the structure).

use std::cell::{Cell, RefCell};
use std::ops::{Deref, Index, IndexMut};

use super::{Corridor, Obj, PartitionTriangle};
use crate::world::BodyId;

/// A vector of the structure's triangles or corridors that notes the ids of
/// the entries written since [`Slots::take_writes`] last took them (module
/// docs). Reading is through the slice it dereferences to; writing through
/// `IndexMut`, [`Slots::push`] and [`Slots::truncate`].
#[derive(Clone, Debug)]
pub struct Slots<T> {
    items: Vec<T>,
    /// Ids written since the notes were last taken.
    written: RefCell<Vec<u32>>,
    /// Whether the notes are incomplete (too many writes, or a new vector):
    /// every entry counts as written.
    all: Cell<bool>,
}

impl<T> Default for Slots<T> {
    fn default() -> Slots<T> {
        Slots::from(Vec::new())
    }
}

impl<T> From<Vec<T>> for Slots<T> {
    fn from(items: Vec<T>) -> Slots<T> {
        Slots {
            items,
            written: RefCell::new(Vec::new()),
            all: Cell::new(true),
        }
    }
}

impl<T: PartialEq> PartialEq for Slots<T> {
    fn eq(&self, other: &Slots<T>) -> bool {
        self.items == other.items
    }
}

impl<T> Deref for Slots<T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        &self.items
    }
}

impl<'a, T> IntoIterator for &'a Slots<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> std::slice::Iter<'a, T> {
        self.items.iter()
    }
}

impl<T> Index<usize> for Slots<T> {
    type Output = T;
    fn index(&self, i: usize) -> &T {
        &self.items[i]
    }
}

impl<T> IndexMut<usize> for Slots<T> {
    fn index_mut(&mut self, i: usize) -> &mut T {
        self.note(i);
        &mut self.items[i]
    }
}

impl<T> Slots<T> {
    /// Entry `i`, for a write that keeps it on the same bodies (a
    /// corridor's chain lengths, middle bridge or triangle sides; a
    /// triangle's corner moved to another vertex of its polygon): not noted,
    /// since the index reads only the bodies an entry lies on. Most writes
    /// of the event loop are such (a middle bridge set by each
    /// normalization). The index's queries are checked against a scan of
    /// the whole structure in debug builds.
    pub fn on_same_bodies(&mut self, i: usize) -> &mut T {
        &mut self.items[i]
    }

    fn note(&mut self, i: usize) {
        if self.all.get() {
            return;
        }
        let w = self.written.get_mut();
        if w.len() > self.items.len().max(64) {
            w.clear();
            self.all.set(true);
        } else {
            w.push(i as u32);
        }
    }

    /// Append an entry (noted as written).
    pub fn push(&mut self, x: T) {
        self.items.push(x);
        self.note(self.items.len() - 1);
    }

    /// Keep the first `len` entries.
    pub fn truncate(&mut self, len: usize) {
        self.items.truncate(len);
    }

    /// The entries as a vector.
    pub fn into_vec(self) -> Vec<T> {
        self.items
    }

    /// Move the ids written since the last call into `buf` (empty; its
    /// buffer becomes the notes', so that neither is allocated again) and
    /// return `true`, or return `false` if every entry counts as written;
    /// the notes start again.
    fn take_writes(&self, buf: &mut Vec<u32>) -> bool {
        debug_assert!(buf.is_empty());
        let all = self.all.replace(false);
        std::mem::swap(&mut *self.written.borrow_mut(), buf);
        if all {
            buf.clear();
        }
        !all
    }
}

/// The bodies an entry lies on.
trait OnBodies {
    /// Each body the entry lies on (a body may repeat), `None` for `ω`.
    fn bodies(&self) -> [Option<BodyId>; 3];
}

/// The body of object `o`, if it is one.
fn body_of(o: Obj) -> Option<BodyId> {
    match o {
        Obj::Body(b) => Some(b),
        Obj::Omega => None,
    }
}

impl OnBodies for PartitionTriangle {
    fn bodies(&self) -> [Option<BodyId>; 3] {
        self.c.map(|c| body_of(c.obj))
    }
}

impl OnBodies for Corridor {
    fn bodies(&self) -> [Option<BodyId>; 3] {
        [body_of(self.a), body_of(self.b), None]
    }
}

/// Per body, a superset of the ids of the entries of one [`Slots`] that lie
/// on it (module docs).
#[derive(Clone, Debug, Default)]
struct Lists {
    of: Vec<Vec<u32>>,
    /// Per body, the length of its list after it was last filtered.
    clean: Vec<usize>,
    /// The written ids being replayed (kept for its buffer).
    writes: Vec<u32>,
    /// Per body, its number of entries, counted for a rebuild (kept for its
    /// buffer).
    count: Vec<u32>,
}

impl Lists {
    fn add(&mut self, b: BodyId, id: u32) {
        let i = b.index();
        if i >= self.of.len() {
            self.of.resize_with(i + 1, Vec::new);
            self.clean.resize(i + 1, 0);
        }
        self.of[i].push(id);
    }

    /// Bring the lists up to date with the writes to `slots`, then filter
    /// body `b`'s list down to the entries on it, sorted; returns it.
    fn on<T: OnBodies>(&mut self, slots: &Slots<T>, b: BodyId) -> Vec<u32> {
        let mut writes = std::mem::take(&mut self.writes);
        if slots.take_writes(&mut writes) {
            for id in writes.drain(..) {
                if let Some(x) = slots.get(id as usize) {
                    for b in x.bodies().into_iter().flatten() {
                        self.add(b, id);
                        // (a list that doubled since it was last filtered
                        // is filtered now, so that no list outgrows its
                        // body's share)
                        if self.of[b.index()].len() > 2 * self.clean[b.index()].max(16) {
                            self.filter(slots, b);
                        }
                    }
                }
            }
        } else {
            // (each list emptied, its buffer kept for the same body and
            // grown once to the body's count, rather than doubled entry by
            // entry)
            self.of.iter_mut().for_each(Vec::clear);
            self.clean.iter_mut().for_each(|c| *c = 0);
            let count = &mut self.count;
            count.clear();
            count.resize(self.of.len(), 0);
            for x in slots.iter() {
                for b in x.bodies().into_iter().flatten() {
                    let i = b.index();
                    if i >= count.len() {
                        count.resize(i + 1, 0);
                    }
                    count[i] += 1;
                }
            }
            if self.of.len() < count.len() {
                self.of.resize_with(count.len(), Vec::new);
                self.clean.resize(count.len(), 0);
            }
            for (list, &n) in self.of.iter_mut().zip(count.iter()) {
                list.reserve_exact(n as usize);
            }
            for (id, x) in slots.iter().enumerate() {
                for b in x.bodies().into_iter().flatten() {
                    self.add(b, id as u32);
                }
            }
        }
        self.writes = writes;
        if b.index() >= self.of.len() {
            return Vec::new();
        }
        self.filter(slots, b);
        self.of[b.index()].clone()
    }

    fn filter<T: OnBodies>(&mut self, slots: &Slots<T>, b: BodyId) {
        let list = &mut self.of[b.index()];
        list.sort_unstable();
        list.dedup();
        list.retain(|&id| {
            slots
                .get(id as usize)
                .is_some_and(|x| x.bodies().contains(&Some(b)))
        });
        self.clean[b.index()] = list.len();
    }
}

/// The index of the triangles and the corridors on each body (module docs).
#[derive(Clone, Debug, Default)]
pub struct Incidence {
    tris: RefCell<Lists>,
    corrs: RefCell<Lists>,
}

impl Incidence {
    /// The ids, in increasing order, of the triangles of `tris` with a
    /// corner on body `b`.
    pub fn tris_on(&self, tris: &Slots<PartitionTriangle>, b: BodyId) -> Vec<u32> {
        self.tris.borrow_mut().on(tris, b)
    }

    /// The ids, in increasing order, of the corridors of `corrs` with a
    /// side on body `b`.
    pub fn corrs_on(&self, corrs: &Slots<Corridor>, b: BodyId) -> Vec<u32> {
        self.corrs.borrow_mut().on(corrs, b)
    }
}
