//! How the structure sees the bodies: through vertex ids, neighbours along
//! the boundary and moving positions, never through the polygons directly.
//!
//! For the plain structure a body is seen as its real polygon (ids `0..n`,
//! steps modulo `n`). For the hierarchical structure (issue 4) a body is
//! seen as its current outer approximation: the ids are the exposed indices
//! of its replicated edge array, and vertex `k` is the approximation vertex
//! `av(pred_S(k), k)` (see [`crate::hier`]); an id whose edge has length
//! zero (three exposed lines through one real vertex) is hidden, its vertex
//! being the next one's. Everything in `structure/`
//! reads geometry through a [`Geo`], so the same operations serve both.

use std::sync::Arc;

use super::memo::PointKey;
use super::{Att, Obj};
use crate::geom::{MidRad, Point};
use crate::hier::{EdgeArray, Exposed};
use crate::motion::{Frame, LinearPoint};
use crate::num::{Interval, Rational, Sign, Time};
use crate::world::{BodyId, World};

/// The most entries an [`EnclosureMemo`] has (a power of two).
const MEMO_MAX: usize = 1 << 10;

/// One entry of an [`EnclosureMemo`]: the approximation vertex `av(i, k)`
/// as `(k, i)` (`k = u32::MAX`: empty; `i`'s top bit, [`CHECKED`], set
/// where `i` was found to be the id before `k` in the exposed set of the
/// memo's `checked` version) and the enclosures of its position at time 0
/// (the velocity terms are the frame's own).
type MemoEntry = (u32, u32, [Interval; 2]);

/// The flag of an [`EnclosureMemo`] entry's `i` that it was checked
/// against the exposed set of the memo's `checked` version (an entry's
/// ids are below it: a point with an id at or above it is not kept).
const CHECKED: u32 = 1 << 31;

/// The linear enclosures of a body's recently seen approximation vertices,
/// direct-mapped by exposed id, for one frame (the memo's key): at an
/// event the same few points are enclosed for many predicates. An entry
/// names the body-frame point itself, `av(i, k)` with `i` the id before
/// `k`, so a pop or a merge (which changes which point an exposed id names)
/// leaves every other entry valid; a frame's uid is never reused, and a
/// motion change (a new frame) starts the memo again. An entry read with
/// the exposed set of one version is flagged for it: asked again while the
/// set is unchanged, it answers without the search for the id before `k`
/// (a new version clears the flags, one pass over the slots). It grows
/// with the approximation, keeping its entries. A clone starts empty.
pub struct EnclosureMemo {
    uid: std::cell::Cell<u64>,
    /// The exposed set's [`Exposed::version`] that the flagged entries were
    /// checked against.
    checked: std::cell::Cell<u64>,
    slots: std::cell::RefCell<Vec<MemoEntry>>,
}

const EMPTY_ENTRY: MemoEntry = (u32::MAX, 0, [Interval { lo: 0.0, hi: 0.0 }; 2]);

impl EnclosureMemo {
    /// An empty memo sized for an approximation of `n` vertices (`2n`
    /// rounded up to a power of two, at least 8 and at most 1024 entries:
    /// with one slot per vertex, a quarter of the lookups on the 64-gon
    /// swarm missed on slots that two exposed ids share).
    pub fn new(n: usize) -> EnclosureMemo {
        EnclosureMemo {
            uid: std::cell::Cell::new(0),
            checked: std::cell::Cell::new(0),
            slots: std::cell::RefCell::new(vec![EMPTY_ENTRY; Self::size(n)]),
        }
    }

    fn size(n: usize) -> usize {
        (2 * n).next_power_of_two().clamp(8, MEMO_MAX)
    }

    /// The slot of exposed id `k` among `len` (a multiplicative hash: the
    /// ids of a coarse approximation are multiples of a power of two).
    fn slot(len: usize, k: u32) -> usize {
        let bits = len.trailing_zeros();
        (k.wrapping_mul(0x9E37_79B1) >> (32 - bits)) as usize
    }

    /// Make `version` the one the flags are for, clearing them if it was
    /// another.
    fn check_against(&self, slots: &mut [MemoEntry], version: u64) {
        if self.checked.get() != version {
            for e in slots.iter_mut() {
                e.1 &= !CHECKED;
            }
            self.checked.set(version);
        }
    }

    /// The entry of exposed id `k` (its `i` and enclosures) if it was
    /// checked against the exposed set of version `version` (the set it is
    /// asked for: its contents are the same, so `k` is exposed and `i` is
    /// the id before it), without a search for that id.
    fn get_current(&self, uid: u64, k: u32, version: u64) -> Option<(u32, [Interval; 2])> {
        if self.uid.get() != uid || self.checked.get() != version {
            return None;
        }
        let slots = self.slots.borrow();
        let e = slots[Self::slot(slots.len(), k)];
        (e.0 == k && e.1 & CHECKED != 0).then_some((e.1 & !CHECKED, e.2))
    }

    /// The entry of `av(i, k)`, flagged as checked against the exposed set
    /// of version `version` (where `i` is the id before `k`).
    fn get(&self, uid: u64, (k, i): (u32, u32), version: u64) -> Option<[Interval; 2]> {
        if self.uid.get() != uid {
            return None;
        }
        let mut slots = self.slots.borrow_mut();
        let at = Self::slot(slots.len(), k);
        let e = slots[at];
        if e.0 != k || e.1 & !CHECKED != i {
            return None;
        }
        self.check_against(&mut slots, version);
        slots[at].1 = i | CHECKED;
        Some(e.2)
    }

    /// Keep `e` for `av(i, k)` of the frame `uid`, the approximation having
    /// `n` vertices and `i` the id before `k` in its exposed set of version
    /// `version`.
    fn put(&self, uid: u64, (k, i): (u32, u32), version: u64, n: usize, e: [Interval; 2]) {
        // (an id with the flag's bit is not kept: an entry's id then never
        // reads as another)
        if i >= CHECKED || k == u32::MAX {
            return;
        }
        let mut slots = self.slots.borrow_mut();
        let want = Self::size(n);
        if self.uid.get() != uid {
            slots.fill(EMPTY_ENTRY);
            self.uid.set(uid);
        }
        if want > slots.len() {
            // (grown with the approximation, its entries kept: each moves
            // to its slot in the larger table)
            let old = std::mem::replace(&mut *slots, vec![EMPTY_ENTRY; want]);
            for e in old.into_iter().filter(|e| e.0 != u32::MAX) {
                slots[Self::slot(want, e.0)] = e;
            }
        }
        self.check_against(&mut slots, version);
        let at = Self::slot(slots.len(), k);
        slots[at] = (k, i | CHECKED, e);
    }
}

impl Clone for EnclosureMemo {
    fn clone(&self) -> EnclosureMemo {
        EnclosureMemo {
            uid: std::cell::Cell::new(0),
            checked: std::cell::Cell::new(0),
            slots: std::cell::RefCell::new(vec![EMPTY_ENTRY; self.slots.borrow().len()]),
        }
    }
}

impl std::fmt::Debug for EnclosureMemo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "EnclosureMemo({} slots)", self.slots.borrow().len())
    }
}

/// A vertex as the structure sees it, held compactly to compute its moving
/// position later (a deferred failure time keeps its three points this
/// way): its body's frame, and its real vertex or the approximation vertex
/// `av(i, k)` of the body's static edge array, all shared, nothing copied.
#[derive(Clone, Debug)]
pub struct PointRef {
    frame: Arc<Frame>,
    src: PointSrc,
}

#[derive(Clone, Debug)]
enum PointSrc {
    Real(Arc<crate::geom::BodyPolygon>, u32),
    Approx(Arc<EdgeArray>, u32, u32),
}

impl PointRef {
    /// Whether `self` and `other` move by one frame (the same motion).
    pub fn same_frame(&self, other: &PointRef) -> bool {
        Arc::ptr_eq(&self.frame, &other.frame)
    }

    /// Which point this is, as [`Geo::point_id`] named it when the
    /// reference was taken: its frame's [`Frame::uid`] and its body-frame
    /// point.
    pub fn id(&self) -> (u64, (u32, u32)) {
        let key = match self.src {
            PointSrc::Real(_, v) => (u32::MAX, v),
            PointSrc::Approx(_, i, k) => (i, k),
        };
        (self.frame.uid(), key)
    }

    /// The moving world position for the frame it was taken with.
    pub fn linear(&self) -> LinearPoint {
        match &self.src {
            PointSrc::Real(shape, v) => self.frame.vertex(shape, *v as usize),
            PointSrc::Approx(array, i, k) => {
                let h = array
                    .av(*i as usize, *k as usize)
                    .expect("an approximation vertex of the array");
                self.frame.homogeneous(&h.x, &h.y, &h.w)
            }
        }
    }
}

/// A body seen through its outer approximation.
#[derive(Clone, Debug)]
pub struct Approx {
    /// The body's replicated edge array.
    pub array: Arc<EdgeArray>,
    /// The exposed indices: the current approximation ([`Approx::exposed`];
    /// changed only by [`Approx::pop`], [`Approx::merge`] and
    /// [`Approx::unmerge`], which keep `hidden_ids` with it).
    exposed: Exposed,
    /// The exposed ids that are [`Approx::hidden`], in increasing order
    /// (few: three exposed lines through one real vertex), so that the
    /// visible ids are the exposed set without them: a walk of `k` steps
    /// round the approximation is a rank and a select in the exposed set,
    /// corrected by this list, and no second set is kept.
    hidden_ids: Vec<u32>,
    /// Recent enclosures of its vertices ([`Geo::enclose_linear`]).
    pub memo: EnclosureMemo,
    /// A box of its vertices in the body's grid coordinates, with the
    /// exposed set's [`Exposed::last_removal`] when it was computed
    /// ([`Geo::loose_box`]): the approximation has only shrunk since while
    /// that stays.
    pub grid_box: GridBox,
}

/// An [`Approx`]'s kept box of its vertices: `Some((version, box))` or
/// `None`, held as the version 0 (an exposed set's
/// [`Exposed::last_removal`] is never 0) so that it takes no word for
/// the option.
#[derive(Debug)]
pub struct GridBox(std::cell::Cell<(u64, [Interval; 2])>);

impl Default for GridBox {
    fn default() -> GridBox {
        GridBox(std::cell::Cell::new((
            0,
            [Interval { lo: 0.0, hi: 0.0 }; 2],
        )))
    }
}

impl GridBox {
    /// The box and the version it was computed for, if any.
    pub fn get(&self) -> Option<(u64, [Interval; 2])> {
        let (v, g) = self.0.get();
        (v != 0).then_some((v, g))
    }

    /// Keep `b` (`None`: none).
    pub fn set(&self, b: Option<(u64, [Interval; 2])>) {
        let none = (0, [Interval { lo: 0.0, hi: 0.0 }; 2]);
        self.0.set(b.unwrap_or(none));
    }
}

impl Clone for GridBox {
    fn clone(&self) -> GridBox {
        GridBox(std::cell::Cell::new(self.0.get()))
    }
}

/// The slot of a direct-mapped table of `len` entries (a power of two)
/// for the hash of `h` (a multiplicative hash: its top bits).
pub(crate) fn slot(h: u64, len: usize) -> usize {
    (h.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - len.trailing_zeros())) as usize
}

/// The direct-mapped table of a view's cache whose entries are small
/// values: each entry holds its own key, so a slot that another key took
/// only misses. A clone starts empty.
pub struct Cells<T: Copy> {
    cells: Box<[std::cell::Cell<T>]>,
    empty: T,
}

impl<T: Copy> Cells<T> {
    /// `len` (a power of two) entries, each `empty`.
    fn new(len: usize, empty: T) -> Cells<T> {
        Cells {
            cells: (0..len).map(|_| std::cell::Cell::new(empty)).collect(),
            empty,
        }
    }

    /// The entry for hash `h`.
    #[inline]
    fn at(&self, h: u64) -> &std::cell::Cell<T> {
        &self.cells[slot(h, self.cells.len())]
    }
}

impl<T: Copy> Clone for Cells<T> {
    fn clone(&self) -> Cells<T> {
        Cells::new(self.cells.len(), self.empty)
    }
}

impl<T: Copy> std::fmt::Debug for Cells<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Cells({} entries)", self.cells.len())
    }
}

/// One entry of a [`LinkMemo`]: the exposed set's version, the body and id
/// (`body << 32 | id`), and the neighbour.
type LinkEntry = (u64, u64, u32);

/// Recent visible neighbours of exposed ids ([`Approx::prev_visible`],
/// [`Approx::next_visible`]), direct-mapped, for each direction: an entry
/// holds the body, the id and the exposed set's version, and answers for
/// that set only ([`Exposed::version`] is never reused, so a pop or a
/// merge leaves every entry of the body unused). One per [`Shapes`].
#[derive(Clone, Debug)]
pub struct LinkMemo {
    prev: Cells<LinkEntry>,
    next: Cells<LinkEntry>,
}

impl Default for LinkMemo {
    fn default() -> LinkMemo {
        LinkMemo {
            prev: Cells::new(256, (0, 0, 0)),
            next: Cells::new(256, (0, 0, 0)),
        }
    }
}

impl LinkMemo {
    /// The neighbour of id `k` of body `b` seen through `ap`, kept in
    /// `cells`, or computed by `walk` and kept.
    #[inline]
    fn answer(
        cells: &Cells<LinkEntry>,
        (b, ap): (BodyId, &Approx),
        k: usize,
        walk: impl FnOnce(&Approx) -> usize,
    ) -> usize {
        let version = ap.exposed.version();
        let id = Att::vertex(b, k as u32).word();
        let cell = cells.at(id ^ version.rotate_left(32));
        let (v, key, n) = cell.get();
        if v == version && key == id {
            debug_assert_eq!(
                n as usize,
                walk(ap),
                "the link memo answers for another set"
            );
            return n as usize;
        }
        let n = walk(ap);
        cell.set((version, id, n as u32));
        n
    }

    /// [`Approx::prev_visible`] of body `b`'s approximation `ap`.
    pub fn prev_visible(&self, b: BodyId, ap: &Approx, k: usize) -> usize {
        Self::answer(&self.prev, (b, ap), k, |ap| ap.prev_visible(k))
    }

    /// [`Approx::next_visible`] of body `b`'s approximation `ap`.
    pub fn next_visible(&self, b: BodyId, ap: &Approx, k: usize) -> usize {
        Self::answer(&self.next, (b, ap), k, |ap| ap.next_visible(k))
    }
}

/// The number of entries of a [`FacesCache`], a power of two.
const FACES: usize = 256;

/// The words a [`FacesCache`] entry is keyed by.
pub(crate) type FacesKey = [u64; 15];

/// One entry of a [`FacesCache`].
type FacesEntry = Option<(FacesKey, Time, bool, Option<super::local::Certs>)>;

/// Recent answers of [`super::Kss::faces_valid_on`], direct-mapped: a
/// corridor's validity is a function of its two bodies' views (frame uid
/// and exposed version), its ends, chain lengths and middle bridge, the
/// side and the instant, which an entry holds in full: the key's words,
/// and the instant itself, which must be known to be the same
/// (`Time::is_known_same`: the same exact value or the same deferred
/// root, never forced), since two instants can share an enclosure. One
/// per [`Shapes`]; a clone starts empty.
///
/// An answer read on one side of an instant is also kept for the other
/// side when no sign it read depended on the side: every turn and every
/// dot product was decided by the f64 filters on an enclosure of the
/// instant itself, so it is the sign at the instant and on both sides of
/// it ([`FacesCache::exact_reads`] counts the others). A pop checks its
/// corridors just before the instant and normalizes them just after it.
pub struct FacesCache(std::cell::RefCell<Vec<FacesEntry>>, std::cell::Cell<u64>);

impl Default for FacesCache {
    fn default() -> FacesCache {
        FacesCache(
            std::cell::RefCell::new(vec![None; FACES]),
            std::cell::Cell::new(0),
        )
    }
}

impl Clone for FacesCache {
    fn clone(&self) -> FacesCache {
        FacesCache::default()
    }
}

impl std::fmt::Debug for FacesCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "FacesCache({} entries)", FACES)
    }
}

impl FacesCache {
    fn slot(key: &FacesKey) -> usize {
        let h = key
            .iter()
            .fold(0u64, |h, &w| (h ^ w).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        slot(h, FACES)
    }

    /// The answer kept for `key` at instant `t`, if any.
    pub(crate) fn get(&self, key: &FacesKey, t: &Time) -> Option<bool> {
        match &self.0.borrow()[Self::slot(key)] {
            Some((k, at, v, _)) if k == key && at.is_known_same(t) => Some(*v),
            _ => None,
        }
    }

    /// The junction certificates kept with a valid answer for `key` at
    /// instant `t` ([`super::Kss::corridor_certs`]), if any.
    pub(crate) fn certs(&self, key: &FacesKey, t: &Time) -> Option<super::local::Certs> {
        match &self.0.borrow()[Self::slot(key)] {
            Some((k, at, true, Some(certs))) if k == key && at.is_known_same(t) => {
                Some(certs.clone())
            }
            _ => None,
        }
    }

    /// Keep answer `v` for `key` at instant `t`, with the junction
    /// certificates read off the faces where the answer is `true`.
    pub(crate) fn put(&self, key: FacesKey, t: &Time, v: bool, certs: Option<super::local::Certs>) {
        self.0.borrow_mut()[Self::slot(&key)] = Some((key, t.clone(), v, certs));
    }

    /// How many signs were read on one side of an instant past the f64
    /// filters so far ([`super::local::turn_on`] and
    /// [`super::local::between_on`]): a validity computed while this
    /// count stays the same read only signs at the instant itself.
    pub(crate) fn exact_reads(&self) -> u64 {
        self.1.get()
    }

    /// Count one sign read past the filters ([`FacesCache::exact_reads`]).
    pub(crate) fn note_exact_read(&self) {
        self.1.set(self.1.get().wrapping_add(1));
    }
}

/// The number of entries of a [`PointCache`], a power of two.
const POINTS: usize = 64;

/// One entry of a [`PointCache`]: the key `[body << 32 | id, frame uid,
/// exposed version]` and the exact moving position.
type PointEntry = Option<([u64; 3], LinearPoint)>;

/// The exact moving positions of recently used approximation vertices
/// ([`Geo::point`]): the exact predicates of an event ask for the same
/// few points, and each is a homogeneous intersection of two lines of the
/// edge array carried by the frame. Direct-mapped; keyed by everything the
/// point depends on (the body and id, the frame's [`Frame::uid`] and the
/// approximation's [`Exposed::version`], both never reused); debug builds
/// check every hit. One per [`Shapes`]; a clone starts empty.
pub struct PointCache(std::cell::RefCell<Vec<PointEntry>>);

impl Default for PointCache {
    fn default() -> PointCache {
        PointCache(std::cell::RefCell::new(vec![None; POINTS]))
    }
}

impl Clone for PointCache {
    fn clone(&self) -> PointCache {
        PointCache::default()
    }
}

impl std::fmt::Debug for PointCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PointCache({POINTS} entries)")
    }
}

impl PointCache {
    fn slot(key: &[u64; 3]) -> usize {
        slot(
            key[0] ^ key[1].rotate_left(20) ^ key[2].rotate_left(40),
            POINTS,
        )
    }

    fn get(&self, key: &[u64; 3]) -> Option<LinearPoint> {
        match &self.0.borrow()[Self::slot(key)] {
            Some((k, p)) if k == key => Some(p.clone()),
            _ => None,
        }
    }

    fn put(&self, key: [u64; 3], p: &LinearPoint) {
        self.0.borrow_mut()[Self::slot(&key)] = Some((key, p.clone()));
    }
}

/// How each body is seen: the real polygon, or an approximation.
#[derive(Clone, Debug, Default)]
pub struct Shapes {
    /// Per body (by index); missing or `None`: the real polygon. Boxed:
    /// an approximation is 200 bytes, and the placement of every vertex
    /// asks whether its body has one, which a vector of pointers answers
    /// from 8 bytes a body (a cache line for eight bodies).
    pub per: Vec<Option<Box<Approx>>>,
    /// Recently placed points ([`Geo::mid_rad`]).
    pub mids: MidCache,
    /// Recent corridor validity answers ([`super::Kss::faces_valid_on`]).
    pub faces: FacesCache,
    /// Recent exact positions of approximation vertices ([`Geo::point`]).
    pub points: PointCache,
    /// Recent visible neighbours of approximation ids.
    pub links: LinkMemo,
}

/// One entry of a [`MidCache`]: the key `[body << 32 | id, frame uid,
/// exposed version (0: the real polygon), t.lo bits, t.hi bits]` and the
/// midpoint–radius form of the point's position at a time in `t`.
type MidEntry = ([u64; 5], Option<MidRad>);

/// The point cache of [`Geo::mid_rad`], direct-mapped (one per
/// [`Shapes`]).
#[derive(Clone, Debug)]
pub struct MidCache(Cells<MidEntry>);

impl Default for MidCache {
    fn default() -> MidCache {
        MidCache(Cells::new(256, ([0; 5], None)))
    }
}

thread_local! {
    /// Every body seen as its real polygon: the empty [`Shapes`] (one per
    /// thread: a memo's cells are not shared between threads).
    static REAL: &'static Shapes = Box::leak(Box::default());
}

impl Approx {
    /// Calls `f(k, i)` for each visible (not [`Approx::hidden`]) exposed
    /// id `k` in increasing order, `i` being the exposed id before it
    /// (cyclically): one pass over the set, each vertex's point read once
    /// (`hidden` asks a predecessor and a successor for every id).
    #[inline]
    pub fn each_visible(&self, mut f: impl FnMut(usize, usize)) {
        let ks: Vec<usize> = self.exposed.iter().collect();
        let n = ks.len();
        if n == 0 {
            return;
        }
        // (the real vertex that the point of `ks[e]`, `av(i, k)` with `i`
        // the id before it, is, if any: `here` for `e`, `first` for 0)
        let first = self.array.av_is_real(ks[n - 1], ks[0]);
        let mut here = first;
        for e in 0..n {
            let next = if e + 1 == n {
                first
            } else {
                self.array.av_is_real(ks[e], ks[e + 1])
            };
            let hidden = matches!((here, next), (Some(u), Some(v)) if u == v);
            debug_assert_eq!(hidden, self.hidden(ks[e]));
            if !hidden {
                f(ks[e], ks[(e + n - 1) % n]);
            }
            here = next;
        }
    }

    /// Whether exposed id `k` is hidden: its edge has length zero (three
    /// exposed lines through one real vertex), so its vertex coincides with
    /// the next one, which stands for both.
    pub fn hidden(&self, k: usize) -> bool {
        let (Some(i), Some(j)) = (self.exposed.pred(k), self.exposed.succ(k)) else {
            return false;
        };
        self.hidden_between(i, k, j)
    }

    /// An approximation of exposed set `exposed` of `array`.
    pub fn new(array: Arc<EdgeArray>, exposed: Exposed) -> Approx {
        let memo = EnclosureMemo::new(exposed.len());
        let mut ap = Approx {
            array,
            exposed,
            hidden_ids: Vec::new(),
            memo,
            grid_box: Default::default(),
        };
        let hidden: Vec<u32> = ap
            .exposed
            .iter()
            .filter(|&k| ap.hidden(k))
            .map(|k| k as u32)
            .collect();
        ap.hidden_ids = hidden;
        ap
    }

    /// The exposed indices: the current approximation.
    pub fn exposed(&self) -> &Exposed {
        &self.exposed
    }

    /// Pop the vertex with id `k` ([`EdgeArray::pop`]): the id inserted.
    pub fn pop(&mut self, k: usize) -> Option<usize> {
        let t = self.array.pop(&mut self.exposed, k)?;
        self.sync_hidden(t);
        Some(t)
    }

    /// Merge id `k` away if [`EdgeArray::merge_ok`]; whether it did.
    /// `body` is the polygon approximated: a box of the vertices kept for
    /// [`Geo::loose_box`] takes in the merge's new vertices.
    pub fn merge(&mut self, k: usize, body: &crate::geom::BodyPolygon) -> bool {
        let before = self.exposed.last_removal();
        let merged = self.array.merge(&mut self.exposed, k);
        if merged {
            self.sync_hidden(k);
            // (the ids around `k`, which need not be in the set)
            let neighbours = (self.exposed.pred(k), self.exposed.succ(k));
            self.grow_grid_box(before, neighbours, body);
        }
        merged
    }

    /// A box of its visible vertices' enclosures in the grid of `body` (the
    /// polygon approximated), computed afresh; `None` where an enclosure is
    /// not finite.
    pub fn vertices_grid_box(&self, body: &crate::geom::BodyPolygon) -> Option<[Interval; 2]> {
        let mut out: Option<[Interval; 2]> = None;
        let mut failed = false;
        // (the visible vertices in one pass, each `av(i, k)` with the
        // exposed id `i` before it, as `vertex_enclose` reads it)
        self.each_visible(|k, i| {
            let e = match self.array.av_is_real(i, k) {
                Some(v) => Some(body.int_vertex_enclosure(v)),
                None => self.array.av_enclose(i, k),
            };
            debug_assert_eq!(e, self.array.vertex_enclose(body, &self.exposed, k));
            match e {
                Some(e) => {
                    out = Some(match out {
                        None => e,
                        Some(o) => [o[0].hull(&e[0]), o[1].hull(&e[1])],
                    })
                }
                None => failed = true,
            }
        });
        if failed {
            None
        } else {
            out
        }
    }

    /// After a merge of the id between `p` and `q` (exposed set's
    /// [`Exposed::last_removal`] `before` it): the approximation grew by a
    /// triangle whose only new vertex is `q`'s (`p`'s is kept, but may have
    /// become visible), so the box of its vertices in the grid (if it was
    /// that of `before`) with those two vertices' enclosures is a box of
    /// them all, looser than one computed afresh (it keeps the vertices
    /// merged away), and valid for the new set.
    fn grow_grid_box(
        &self,
        before: u64,
        (p, q): (Option<usize>, Option<usize>),
        body: &crate::geom::BodyPolygon,
    ) {
        let grown = match (self.grid_box.get(), p, q) {
            (Some((v, g)), Some(p), Some(q)) if v == before => [p, q]
                .into_iter()
                .filter(|&x| !self.hidden(x))
                .try_fold(g, |g, x| {
                    let e = self.array.vertex_enclose(body, &self.exposed, x)?;
                    Some([g[0].hull(&e[0]), g[1].hull(&e[1])])
                }),
            _ => None,
        };
        self.grid_box
            .set(grown.map(|g| (self.exposed.last_removal(), g)));
    }

    /// Put back id `k`, merged away just before (a merge taken back).
    pub fn unmerge(&mut self, k: usize) {
        if self.exposed.insert(k) {
            self.sync_hidden(k);
        }
    }

    /// Which body-frame point exposed id `k`, after exposed id `i`, is:
    /// `(u32::MAX, v)` for real vertex `v`, else `(i, k)` for the
    /// approximation vertex `av(i, k)` (the key of [`Geo::linear_key`]).
    fn point_of(&self, i: usize, k: usize) -> (u32, u32) {
        match self.array.av_is_real(i, k) {
            Some(v) => (u32::MAX, v as u32),
            None => (i as u32, k as u32),
        }
    }

    /// Whether exposed id `k` is in the list of hidden ids.
    #[inline]
    fn listed_hidden(&self, k: usize) -> bool {
        !self.hidden_ids.is_empty() && self.hidden_ids.binary_search(&(k as u32)).is_ok()
    }

    /// Bring the list of hidden ids up to date after id `x` entered or
    /// left the exposed set: only `x` and its two exposed neighbours (whose
    /// neighbour `x` is or was) can have become hidden or visible.
    fn sync_hidden(&mut self, x: usize) {
        let set =
            |list: &mut Vec<u32>, y: usize, on: bool| match (list.binary_search(&(y as u32)), on) {
                (Err(at), true) => list.insert(at, y as u32),
                (Ok(at), false) => {
                    list.remove(at);
                }
                _ => {}
            };
        let s = &self.exposed;
        let mut ids: arrayvec::ArrayVec<(usize, bool), 3> = arrayvec::ArrayVec::new();
        if let (Some(p), Some(q)) = (s.pred(x), s.succ(x)) {
            ids.push((p, self.hidden(p)));
            ids.push((q, self.hidden(q)));
        }
        ids.push((x, s.contains(x) && self.hidden(x)));
        for (y, on) in ids {
            set(&mut self.hidden_ids, y, on);
        }
        debug_assert_eq!(
            self.hidden_ids,
            self.exposed
                .iter()
                .filter(|&k| self.hidden(k))
                .map(|k| k as u32)
                .collect::<Vec<_>>(),
            "the list of hidden ids is not the exposed ids that are hidden"
        );
    }

    /// The number of visible ids (the ids of [`Approx::each_visible`]).
    pub fn visible_len(&self) -> usize {
        self.exposed.len() - self.hidden_ids.len()
    }

    /// The number of visible ids below `k`.
    fn visible_rank(&self, k: usize) -> usize {
        let below = self.hidden_ids.partition_point(|&h| (h as usize) < k);
        self.exposed.rank(k) - below
    }

    /// The visible id with `r` visible ids below it (`r` below
    /// [`Approx::visible_len`]): the exposed id of rank `r + c`, `c` the
    /// hidden ids up to it, found by raising `c` until it holds (at once
    /// when no id is hidden).
    fn visible_select(&self, r: usize) -> usize {
        let mut c = 0;
        loop {
            let e = self.exposed.select(r + c).expect("a rank below the length");
            let upto = self.hidden_ids.partition_point(|&h| h as usize <= e);
            if upto == c {
                return e;
            }
            c = upto;
        }
    }

    /// The visible id after `k` (counter-clockwise): the first exposed id
    /// after `k` that is not [`Approx::hidden`], or `k` when there is none.
    pub fn next_visible(&self, k: usize) -> usize {
        let s = &self.exposed;
        let mut x = s.succ(k).expect("a non-empty set");
        while x != k && self.listed_hidden(x) {
            x = s.succ(x).expect("a non-empty set");
        }
        debug_assert_eq!(x, self.next_visible_walk(k));
        x
    }

    /// The visible id before `k` (clockwise), as [`Approx::next_visible`]
    /// in the other direction.
    pub fn prev_visible(&self, k: usize) -> usize {
        let s = &self.exposed;
        let mut x = s.pred(k).expect("a non-empty set");
        while x != k && self.listed_hidden(x) {
            x = s.pred(x).expect("a non-empty set");
        }
        debug_assert_eq!(x, self.prev_visible_walk(k));
        x
    }

    /// The visible id `k` steps clockwise from `from` (walking
    /// [`Approx::prev_visible`] `k` times): a rank and a select.
    pub fn cw(&self, from: usize, k: u32) -> usize {
        // (a few steps are cheaper as predecessors than as a rank and a
        // select, each a pass over a Fenwick tree)
        if k <= 8 {
            let mut x = from;
            for _ in 0..k {
                x = self.prev_visible(x);
            }
            return x;
        }
        let l = self.visible_len();
        if l == 0 {
            return from;
        }
        // (each step lowers the rank by one, cyclically; a hidden `from`
        // has the rank of the visible id after it)
        let r = self.visible_rank(from) as u64;
        let l64 = l as u64;
        let target = (r + l64 - u64::from(k) % l64) % l64;
        self.visible_select(target as usize)
    }

    /// The number of clockwise steps ([`Approx::prev_visible`]) from
    /// `from` to `to`, with `0` for `to == from`, if at most `limit`;
    /// `None` if the walk never meets `to` (a hidden or unexposed `to`).
    pub fn cw_distance(&self, from: usize, to: usize, limit: u32) -> Option<u32> {
        if from == to {
            return Some(0);
        }
        let visible = |x: usize| self.exposed.contains(x) && !self.listed_hidden(x);
        if !visible(to) {
            return None;
        }
        let l = self.visible_len() as u64;
        let (rf, rt) = (self.visible_rank(from) as u64, self.visible_rank(to) as u64);
        let d = if visible(from) {
            (rf + l - rt) % l
        } else {
            (rf + l - rt + l - 1) % l + 1
        };
        let d = u32::try_from(d).ok()?;
        (d <= limit).then_some(d)
    }

    /// [`Approx::next_visible`] by walking the exposed set (debug checks).
    fn next_visible_walk(&self, k: usize) -> usize {
        let s = &self.exposed;
        let mut x = s.succ(k).expect("a non-empty set");
        while self.hidden(x) && x != k {
            x = s.succ(x).expect("a non-empty set");
        }
        x
    }

    /// [`Approx::prev_visible`] by walking the exposed set (debug checks).
    fn prev_visible_walk(&self, k: usize) -> usize {
        let s = &self.exposed;
        let mut x = s.pred(k).expect("a non-empty set");
        while self.hidden(x) && x != k {
            x = s.pred(x).expect("a non-empty set");
        }
        x
    }

    /// [`Approx::hidden`] of exposed id `k` given the exposed ids `i`
    /// before it and `j` after it.
    #[inline]
    fn hidden_between(&self, i: usize, k: usize, j: usize) -> bool {
        match (self.array.av_is_real(i, k), self.array.av_is_real(k, j)) {
            (Some(u), Some(v)) => u == v,
            _ => false,
        }
    }
}

impl Shapes {
    /// Every body seen as its real polygon (the plain structure).
    pub fn real() -> &'static Shapes {
        REAL.with(|r| *r)
    }

    /// The approximation of body `b`, if it is seen through one.
    pub fn approx(&self, b: BodyId) -> Option<&Approx> {
        self.per.get(b.index()).and_then(Option::as_deref)
    }
}

/// A turn read as the turn of its third point with the real edge of an
/// approximation edge's line ([`Geo::edge_line`]).
pub(crate) struct EdgeLine<'a> {
    /// The memo keys of `(x, V_from, V_to)`.
    pub keys: [super::memo::PointKey; 3],
    /// Their frames.
    pub frames: [&'a Arc<Frame>; 3],
    /// The body of the edge.
    pub body: BodyId,
    /// The third point.
    pub x: Att,
    /// The real edge's vertex where the turn's edge starts.
    pub from: usize,
    /// The real edge's vertex where the turn's edge ends.
    pub to: usize,
}

/// The world together with how the structure sees each body. Dereferences
/// to the [`World`] for everything else (motions, liveness, ids).
#[derive(Clone, Copy, Debug)]
pub struct Geo<'a> {
    /// The bodies and their motions.
    pub world: &'a World,
    /// How each body is seen.
    pub shapes: &'a Shapes,
}

impl std::ops::Deref for Geo<'_> {
    type Target = World;
    fn deref(&self) -> &World {
        self.world
    }
}

impl<'a> Geo<'a> {
    /// Every body seen as its real polygon.
    pub fn plain(world: &'a World) -> Geo<'a> {
        Geo {
            world,
            shapes: Shapes::real(),
        }
    }

    /// The number of vertices body `b` is seen with.
    pub fn count(&self, b: BodyId) -> u32 {
        match self.shapes.approx(b) {
            None => self.world.body(b).shape.len() as u32,
            Some(a) => a.visible_len() as u32,
        }
    }

    /// One more than the largest vertex id body `b` can have.
    pub fn id_bound(&self, b: BodyId) -> usize {
        match self.shapes.approx(b) {
            None => self.world.body(b).shape.len(),
            Some(a) => a.array.m(),
        }
    }

    /// The vertex ids of body `b`, counter-clockwise.
    pub fn ids(&self, b: BodyId) -> Vec<u32> {
        match self.shapes.approx(b) {
            None => (0..self.world.body(b).shape.len() as u32).collect(),
            Some(a) => {
                let mut out = Vec::with_capacity(a.exposed.len());
                a.each_visible(|k, _| out.push(k as u32));
                out
            }
        }
    }

    /// The vertex `k` steps clockwise from `a` (`ω` stays `ω`).
    pub fn cw(&self, a: Att, k: u32) -> Att {
        let Obj::Body(b) = a.obj else {
            return a;
        };
        let v = match self.shapes.approx(b) {
            None => {
                let n = self.world.body(b).shape.len() as u32;
                // (one step, the common case, without a division)
                match (k, a.v) {
                    (1, 0) => n - 1,
                    (1, v) => v - 1,
                    _ => (a.v + n - (k % n)) % n,
                }
            }
            Some(ap) if k == 1 => self.shapes.links.prev_visible(b, ap, a.v as usize) as u32,
            Some(ap) => ap.cw(a.v as usize, k) as u32,
        };
        Att { obj: a.obj, v }
    }

    /// The number of clockwise steps from `from` to `to` on one body (less
    /// than the body's vertex count; `None` if `to` is not met within
    /// `limit` steps).
    pub fn cw_distance(&self, from: Att, to: Att, limit: u32) -> Option<u32> {
        let (Obj::Body(b), Obj::Body(c)) = (from.obj, to.obj) else {
            return None;
        };
        if b != c {
            return None;
        }
        match self.shapes.approx(b) {
            None => {
                let n = self.world.body(b).shape.len() as u32;
                let d = (from.v + n - to.v) % n;
                (d <= limit).then_some(d)
            }
            Some(ap) => ap.cw_distance(from.v as usize, to.v as usize, limit),
        }
    }

    /// The counter-clockwise neighbour of `a` (`ω` stays `ω`).
    pub fn ccw(&self, a: Att) -> Att {
        let Obj::Body(b) = a.obj else {
            return a;
        };
        let v = match self.shapes.approx(b) {
            None => {
                let v = a.v + 1;
                if v == self.world.body(b).shape.len() as u32 {
                    0
                } else {
                    v
                }
            }
            Some(ap) => self.shapes.links.next_visible(b, ap, a.v as usize) as u32,
        };
        Att { obj: a.obj, v }
    }

    /// Whether `a` is a real polygon vertex (always, unless its body is seen
    /// through an approximation and `a` is an approximation vertex).
    pub fn is_real(&self, a: Att) -> bool {
        let Obj::Body(b) = a.obj else {
            return true;
        };
        match self.shapes.approx(b) {
            None => true,
            Some(ap) => ap
                .exposed
                .pred(a.v as usize)
                .is_some_and(|i| ap.array.av_is_real(i, a.v as usize).is_some()),
        }
    }

    /// The moving position of vertex `a` (a finite point).
    pub fn point(&self, a: Att) -> LinearPoint {
        let Obj::Body(b) = a.obj else {
            unreachable!("a finite point was expected")
        };
        let body = self.world.body(b);
        match self.shapes.approx(b) {
            None => body.vertex(a.v as usize),
            Some(ap) => {
                let key = [a.word(), body.frame.uid(), ap.exposed.version()];
                if let Some(p) = self.shapes.points.get(&key) {
                    debug_assert_eq!(
                        p,
                        ap.array
                            .vertex_of(&body.shape, &ap.exposed, a.v as usize)
                            .expect("an exposed id with an approximation vertex")
                            .moving(&body.frame),
                        "the point cache answers for another point: {a:?}"
                    );
                    return p;
                }
                let h = ap
                    .array
                    .vertex_of(&body.shape, &ap.exposed, a.v as usize)
                    .expect("an exposed id with an approximation vertex");
                let p = h.moving(&body.frame);
                self.shapes.points.put(key, &p);
                p
            }
        }
    }

    /// What vertex `a` is, for [`super::memo`]: its body's frame and its
    /// body-frame point (`None` for `ω`).
    pub(crate) fn point_key(&self, a: Att) -> Option<(PointKey, &'a Arc<Frame>)> {
        let Obj::Body(b) = a.obj else {
            return None;
        };
        let body = self.world.body(b);
        let key = match self.shapes.approx(b) {
            None => PointKey::real(&body.frame, a.v as usize),
            Some(ap) => {
                let k = a.v as usize;
                let i = match ap
                    .memo
                    .get_current(body.frame.uid(), a.v, ap.exposed.version())
                {
                    Some((i, _)) => i as usize,
                    None => ap.exposed.pred(k)?,
                };
                debug_assert_eq!(Some(i), ap.exposed.pred(k));
                match ap.array.av_is_real(i, k) {
                    Some(v) => PointKey::real(&body.frame, v),
                    None => PointKey::approx(&body.frame, i, k),
                }
            }
        };
        Some((key, &body.frame))
    }

    /// The sign of `orient(u, v, w)` just after (`after`) or before `t`,
    /// exactly, through the instant's memo of exact turns
    /// ([`super::memo`]); `compute` is the exact evaluation.
    pub(crate) fn memo_turn(
        &self,
        [u, v, w]: [Att; 3],
        t: &Time,
        after: bool,
        compute: impl FnOnce() -> Sign,
    ) -> Sign {
        match (self.point_key(u), self.point_key(v), self.point_key(w)) {
            (Some((ku, fu)), Some((kv, fv)), Some((kw, fw))) => {
                super::memo::turn([ku, kv, kw], [fu, fv, fw], t, after, compute)
            }
            _ => {
                super::counters::bump(super::counters::Counter::TurnsExact);
                compute()
            }
        }
    }

    /// The sign of `orient(u, v, w)` just after (`after`) or before `t`, if
    /// the instant's memo knows it ([`super::memo`]).
    pub(crate) fn memo_peek(&self, [u, v, w]: [Att; 3], t: &Time, after: bool) -> Option<Sign> {
        let keys = [
            self.point_key(u)?.0,
            self.point_key(v)?.0,
            self.point_key(w)?.0,
        ];
        super::memo::peek(keys, t, after).or_else(|| {
            let s = self
                .edge_line([u, v, w])
                .and_then(|line| super::memo::peek(line.keys, t, after))?;
            #[cfg(debug_assertions)]
            {
                let direct =
                    crate::motion::orient_poly(&self.point(u), &self.point(v), &self.point(w))
                        .signs_around(t);
                debug_assert_eq!(
                    s,
                    direct[usize::from(after)],
                    "the memo's turn of the real edge of {:?}'s line is not its own",
                    [u, v, w]
                );
            }
            Some(s)
        })
    }

    /// The sign of `orient(u, v, w)` at `t` itself, if the instant's memo
    /// knows it ([`super::memo`]).
    pub(crate) fn memo_peek_at(&self, [u, v, w]: [Att; 3], t: &Time) -> Option<Sign> {
        let keys = [
            self.point_key(u)?.0,
            self.point_key(v)?.0,
            self.point_key(w)?.0,
        ];
        super::memo::peek_at(keys, t)
    }

    /// Tell the instant's memo that `orient(u, v, w)` has sign `s` at `t`
    /// itself (computed exactly).
    pub(crate) fn memo_record_at(&self, [u, v, w]: [Att; 3], t: &Time, s: Sign) {
        if let (Some((ku, fu)), Some((kv, fv)), Some((kw, fw))) =
            (self.point_key(u), self.point_key(v), self.point_key(w))
        {
            super::memo::record_at([ku, kv, kw], [fu, fv, fw], t, s);
        }
    }

    /// Tell the instant's memo that `orient(u, v, w)` has sign `s` just
    /// after (`after`) or before `t` (computed exactly).
    pub(crate) fn memo_record(&self, [u, v, w]: [Att; 3], t: &Time, after: bool, s: Sign) {
        if let (Some((ku, fu)), Some((kv, fv)), Some((kw, fw))) =
            (self.point_key(u), self.point_key(v), self.point_key(w))
        {
            super::memo::record([ku, kv, kw], [fu, fv, fw], t, after, s);
        }
        // (and as the turn with the real edge of its line, where it has one)
        if let Some(line) = self.edge_line([u, v, w]) {
            super::memo::record(line.keys, line.frames, t, after, s);
        }
    }

    /// For a turn `pts` two of whose points, `p` then `q` in its cyclic
    /// order, are the ends of an approximation edge (`q` the vertex after
    /// `p` in the exposed set, or `p` the one after `q`) whose line is a
    /// real polygon edge `V_s → V_e`, the third point `x` on another body:
    /// the turn `(x, V_s, V_e)` (`V_e → V_s` where `q` comes before `p`)
    /// that has its sign at every time. The approximation edge contains the
    /// real edge and runs the same way (an outer approximation touches each
    /// of its lines along the line's real edge), so `orient(x, p, q)` is a
    /// positive multiple of `orient(x, V_s, V_e)`. `None` where the turn
    /// has no such edge (on a real polygon, its edges are their own).
    pub(crate) fn edge_line(&self, pts: [Att; 3]) -> Option<EdgeLine<'a>> {
        for r in 0..3 {
            let (x, p, q) = (pts[r], pts[(r + 1) % 3], pts[(r + 2) % 3]);
            let (Obj::Body(b), Obj::Body(bx)) = (p.obj, x.obj) else {
                continue;
            };
            if q.obj != p.obj || bx == b {
                continue;
            }
            let Some(ap) = self.shapes.approx(b) else {
                continue;
            };
            let s = ap.exposed();
            let (pk, qk) = (p.v as usize, q.v as usize);
            // the edge's entry, and whether p → q runs along it
            let (k, forward) = if s.contains(pk) && s.succ(pk) == Some(qk) {
                (pk, true)
            } else if s.contains(qk) && s.succ(qk) == Some(pk) {
                (qk, false)
            } else {
                continue;
            };
            let e = ap.array.entry(k);
            if e.is_zero_length() {
                continue;
            }
            let (from, to) = if forward {
                (e.start, e.end)
            } else {
                (e.end, e.start)
            };
            let frame = &self.world.body(b).frame;
            let (kx, fx) = self.point_key(x)?;
            return Some(EdgeLine {
                keys: [
                    kx,
                    super::memo::PointKey::real(frame, from),
                    super::memo::PointKey::real(frame, to),
                ],
                frames: [fx, frame, frame],
                body: b,
                x,
                from,
                to,
            });
        }
        None
    }

    /// Vertex `a` as a [`PointRef`] (`None` for `ω` or an id that is not
    /// exposed): [`PointRef::linear`] is [`Geo::point`]`(a)` for the motion
    /// of now.
    pub fn point_ref(&self, a: Att) -> Option<PointRef> {
        let (b, key) = self.linear_key(a)?;
        self.point_ref_of(b, key)
    }

    /// The body-frame point `key` of body `b` (the second part of a
    /// [`Geo::point_id`]) as a [`PointRef`], moving by the body's frame of
    /// now (`None` for an approximation vertex of a body that is not
    /// approximated).
    fn point_ref_of(&self, b: BodyId, (i, k): (u32, u32)) -> Option<PointRef> {
        let body = self.world.body(b);
        let src = if i == u32::MAX {
            PointSrc::Real(body.shape.clone(), k)
        } else {
            PointSrc::Approx(self.shapes.approx(b)?.array.clone(), i, k)
        };
        Some(PointRef {
            frame: body.frame.clone(),
            src,
        })
    }

    /// Enclosures `[x0, x1, y0, y1]` of `a`'s moving position `(x0 + x1·t,
    /// y0 + y1·t)` (see [`crate::motion::Frame::linear_enclosure`]; `None`
    /// for `ω`).
    pub fn enclose_linear(&self, a: Att) -> Option<[Interval; 4]> {
        let Obj::Body(b) = a.obj else {
            return None;
        };
        let Some(ap) = self.shapes.approx(b) else {
            // a real vertex: its input doubles and one sum per coordinate,
            // cheaper than a memo
            let body = self.world.body(b);
            let v = body.shape.f64_vertices()[a.v as usize];
            return Some(body.frame.linear_enclosure_of_vertex(v));
        };
        let frame = &self.world.body(b).frame;
        let k = a.v as usize;
        // (an entry checked against the set as it is needs no search for
        // the id before `k`)
        let version = ap.exposed.version();
        if let Some((_i, [x0, y0])) = ap.memo.get_current(frame.uid(), a.v, version) {
            debug_assert!(ap.exposed.contains(k) && ap.exposed.pred(k) == Some(_i as usize));
            let [x1, y1] = frame.velocity_enclosure();
            return Some([x0, x1, y0, y1]);
        }
        if !ap.exposed.contains(k) {
            return None;
        }
        let i = ap.exposed.pred(k)?;
        self.approx_linear(b, ap, frame, k, i)
    }

    /// [`Geo::enclose_linear`] of exposed id `k` of body `b`'s
    /// approximation `ap` (moving by `frame`), `i` the exposed id before
    /// it: from the memo, else computed and kept.
    #[inline(always)]
    fn approx_linear(
        &self,
        b: BodyId,
        ap: &Approx,
        frame: &Frame,
        k: usize,
        i: usize,
    ) -> Option<[Interval; 4]> {
        let ki = (k as u32, i as u32);
        let version = ap.exposed.version();
        if let Some([x0, y0]) = ap.memo.get(frame.uid(), ki, version) {
            let [x1, y1] = frame.velocity_enclosure();
            return Some([x0, x1, y0, y1]);
        }
        // (the key `linear_key` would find, from the predecessor given)
        let at = ap.point_of(i, k);
        debug_assert_eq!(
            self.linear_key(Att::vertex(b, k as u32)),
            Some((b, at)),
            "the point's key"
        );
        let e = self.linear_fresh(b, at)?;
        ap.memo
            .put(frame.uid(), ki, version, ap.exposed.len(), [e[0], e[2]]);
        Some(e)
    }

    /// The vertices of body `b` as it is seen ([`Geo::ids`], in that
    /// order) with their positions at a time in `t` ([`Geo::mid_rad`]'s
    /// values; `None` each without `t`): one pass round the approximation,
    /// each vertex's exposed predecessor at hand where the point cache
    /// misses.
    pub fn placed_ring(&self, b: BodyId, t: Option<Interval>) -> (Vec<Att>, Vec<Option<MidRad>>) {
        let body = self.world.body(b);
        let Some(ap) = self.shapes.approx(b) else {
            let n = body.shape.len();
            let ring: Vec<Att> = (0..n as u32).map(|v| Att::vertex(b, v)).collect();
            let places = match t {
                Some(t) => {
                    let tm = crate::geom::TimeMidRad::of(t);
                    let vs = body.shape.f64_vertices();
                    (0..n)
                        .map(|v| body.frame.mid_rad_of_vertex(vs[v], tm))
                        .collect()
                }
                None => vec![None; n],
            };
            return (ring, places);
        };
        let mut ring = Vec::with_capacity(ap.visible_len());
        let mut places = Vec::with_capacity(ap.visible_len());
        ap.each_visible(|k, i| {
            let x = Att::vertex(b, k as u32);
            ring.push(x);
            places.push(t.and_then(|t| {
                self.mid_rad_cached(x, t, || self.approx_linear(b, ap, &body.frame, k, i))
            }));
        });
        #[cfg(debug_assertions)]
        for (&x, &m) in ring.iter().zip(&places) {
            debug_assert_eq!(m, t.and_then(|t| self.mid_rad(x, t)), "{x:?}");
        }
        (ring, places)
    }

    /// What point `a` is: its body's [`Frame::uid`] and its body-frame
    /// point (`(u32::MAX, v)` for real vertex `v`, `(i, k)` for the
    /// approximation vertex `av(i, k)`); `None` for `ω` or an id that is
    /// not exposed. Two equal ids are the same moving point.
    pub fn point_id(&self, a: Att) -> Option<(u64, (u32, u32))> {
        let (b, key) = self.linear_key(a)?;
        Some((self.world.body(b).frame.uid(), key))
    }

    /// The exposed id before vertex `a`'s in its body's approximation
    /// (`u32::MAX` for a vertex of a polygon that is not approximated;
    /// `None` for `ω` or an id that is not exposed): with `a`'s id, which
    /// body-frame point `a` is now, whatever the approximation becomes
    /// later ([`Geo::point_ref_after`] reads it back).
    pub fn pred_id(&self, a: Att) -> Option<u32> {
        let Obj::Body(b) = a.obj else {
            return None;
        };
        let Some(ap) = self.shapes.approx(b) else {
            return Some(u32::MAX);
        };
        let uid = self.world.body(b).frame.uid();
        if let Some((i, _)) = ap.memo.get_current(uid, a.v, ap.exposed.version()) {
            return Some(i);
        }
        let k = a.v as usize;
        if !ap.exposed.contains(k) {
            return None;
        }
        ap.exposed.pred(k).map(|i| i as u32)
    }

    /// The point of body `b` that vertex id `k` was while `i` was the
    /// exposed id before it ([`Geo::pred_id`]), as a [`PointRef`] moving
    /// by the body's frame of now.
    pub fn point_ref_after(&self, b: BodyId, i: u32, k: u32) -> Option<PointRef> {
        let key = if i == u32::MAX {
            (u32::MAX, k)
        } else {
            self.shapes.approx(b)?.point_of(i as usize, k as usize)
        };
        self.point_ref_of(b, key)
    }

    /// The body of `a` and which body-frame point it is: `(u32::MAX, v)`
    /// for real vertex `v`, `(i, k)` for
    /// the approximation vertex `av(i, k)` (`None` for `ω` or an id that is
    /// not exposed).
    fn linear_key(&self, a: Att) -> Option<(BodyId, (u32, u32))> {
        let Obj::Body(b) = a.obj else {
            return None;
        };
        let key = match self.shapes.approx(b) {
            None => (u32::MAX, a.v),
            Some(ap) => {
                let k = a.v as usize;
                // (an enclosure memo entry read with the set as it is names
                // the id before `k`, which is exposed)
                let uid = self.world.body(b).frame.uid();
                if let Some((i, _)) = ap.memo.get_current(uid, a.v, ap.exposed.version()) {
                    debug_assert!(ap.exposed.contains(k) && ap.exposed.pred(k) == Some(i as usize));
                    return Some((b, ap.point_of(i as usize, k)));
                }
                if !ap.exposed.contains(k) {
                    return None;
                }
                ap.point_of(ap.exposed.pred(k)?, k)
            }
        };
        Some((b, key))
    }

    /// [`Geo::enclose_linear`] of the point `key` of body `b`, computed
    /// afresh (not from the memo).
    fn linear_fresh(&self, b: BodyId, key: (u32, u32)) -> Option<[Interval; 4]> {
        let body = self.world.body(b);
        if key.0 == u32::MAX {
            let v = body.shape.f64_vertices()[key.1 as usize];
            return Some(body.frame.linear_enclosure_of_vertex(v));
        }
        let ap = self.shapes.approx(b)?;
        let [x, y] = ap.array.av_enclose(key.0 as usize, key.1 as usize)?;
        Some(body.frame.linear_enclosure(x, y))
    }

    /// [`Geo::enclose_linear`] in midpoint–radius form (the input of the
    /// certificate filters): a vertex of a polygon that is not approximated
    /// straight from its input doubles and its frame
    /// ([`Frame::linear_mr_of_vertex`]), an approximation vertex from its
    /// cached enclosures. `None` for `ω` or where a value is not finite.
    #[inline]
    pub fn linear_mr(&self, a: Att) -> Option<[crate::geom::Mr; 4]> {
        let Obj::Body(b) = a.obj else {
            return None;
        };
        if self.shapes.approx(b).is_none() {
            let body = self.world.body(b);
            let v = body.shape.f64_vertices()[a.v as usize];
            return body.frame.linear_mr_of_vertex(v);
        }
        let [x0, x1, y0, y1] = self.enclose_linear(a)?;
        Some([
            crate::geom::Mr::of(x0)?,
            crate::geom::Mr::of(x1)?,
            crate::geom::Mr::of(y0)?,
            crate::geom::Mr::of(y1)?,
        ])
    }

    /// Whether the cached enclosure of `a` ([`Geo::enclose_linear`]) is
    /// the one computed afresh (the audit's check that the memo never
    /// answers for another point).
    pub fn enclosure_cache_agrees(&self, a: Att) -> bool {
        match self.linear_key(a) {
            None => self.enclose_linear(a).is_none(),
            Some((b, key)) => self.enclose_linear(a) == self.linear_fresh(b, key),
        }
    }

    /// The position of `a` at a time in `t` in midpoint–radius form (`None`
    /// for `ω` or where a value is not finite). A vertex of a polygon that
    /// is not approximated comes straight from its input doubles and its
    /// frame's midpoint–radius terms ([`Frame::mid_rad_of_vertex`]: a few
    /// products, cheaper than a cache lookup). An approximation vertex is
    /// [`MidRad::at`] of [`Geo::enclose_linear`] through a small cache
    /// ([`MidCache`]): at an event the same few points are placed for many
    /// predicates. An entry is keyed by everything the value depends on:
    /// the body and id, the body's frame ([`Frame::uid`], never reused: a
    /// motion change is a new frame), the approximation's contents
    /// ([`Exposed::version`], never reused) and the two ends of `t`,
    /// compared exactly; debug builds check every hit against a fresh
    /// computation.
    pub fn mid_rad(&self, a: Att, t: Interval) -> Option<MidRad> {
        let Obj::Body(b) = a.obj else {
            return None;
        };
        if self.shapes.approx(b).is_none() {
            // a real vertex: from its input doubles and the frame's terms,
            // cheaper than the cache
            let body = self.world.body(b);
            let v = body.shape.f64_vertices()[a.v as usize];
            return body
                .frame
                .mid_rad_of_vertex(v, crate::geom::TimeMidRad::of(t));
        }
        self.mid_rad_cached(a, t, || self.enclose_linear(a))
    }

    /// [`Geo::mid_rad`] of approximation vertex `a` through the point cache,
    /// with `linear` its [`Geo::enclose_linear`] where the cache misses.
    fn mid_rad_cached(
        &self,
        a: Att,
        t: Interval,
        linear: impl FnOnce() -> Option<[Interval; 4]>,
    ) -> Option<MidRad> {
        let Obj::Body(b) = a.obj else {
            return None;
        };
        let [version, uid] = self.view_words(b);
        let id = a.word();
        let key = [id, uid, version, t.lo.to_bits(), t.hi.to_bits()];
        let cell = self
            .shapes
            .mids
            .0
            .at(id ^ uid.rotate_left(20) ^ version.rotate_left(40));
        let (k, m) = cell.get();
        // (word by word: an array comparison would call `memcmp`)
        if k.iter().zip(&key).fold(0, |d, (x, y)| d | (x ^ y)) == 0 {
            debug_assert_eq!(
                m,
                self.enclose_linear(a).and_then(|l| MidRad::at(l, t)),
                "the point cache answers for another point: {a:?}"
            );
            return m;
        }
        let m = linear().and_then(|l| MidRad::at(l, t));
        cell.set((key, m));
        m
    }

    /// What body `b`'s vertices are as this view sees them, as two words:
    /// its approximation's [`Exposed::version`] (0 for the real polygon)
    /// and its frame's [`Frame::uid`].
    pub(crate) fn view_words(&self, b: BodyId) -> [u64; 2] {
        let version = self.shapes.approx(b).map_or(0, |ap| ap.exposed.version());
        [version, self.world.body(b).frame.uid()]
    }

    /// [`Geo::view_words`] of object `o` (zeros for `ω`, which has no view).
    pub(crate) fn obj_view_words(&self, o: Obj) -> [u64; 2] {
        match o {
            Obj::Body(b) => self.view_words(b),
            Obj::Omega => [0, 0],
        }
    }

    /// An enclosure of `a`'s position at a time in `t` (the f64 filter of
    /// the orientation tests; `None` for `ω`).
    pub fn enclose(&self, a: Att, t: Interval) -> Option<[Interval; 2]> {
        let [x0, x1, y0, y1] = self.enclose_linear(a)?;
        Some([x0 + x1 * t, y0 + y1 * t])
    }

    /// A box `[x, y]` that holds, at any time in `t`, every vertex that
    /// body `b` is seen with, as [`Geo::seen_box`], but for an
    /// approximation a box of its vertices in the body's grid (kept while
    /// the approximation only shrinks: computed again after a merge, not
    /// after a pop) placed by the frame: O(1) per call instead of an
    /// enclosure per vertex, and looser (a filter's box).
    pub fn loose_box(&self, b: BodyId, t: Interval) -> Option<[Interval; 2]> {
        let Some(ap) = self.shapes.approx(b) else {
            return self.seen_box(b, t);
        };
        // (kept while the approximation only shrinks: pops insert lines,
        // only merges remove them)
        let version = ap.exposed.last_removal();
        let grid = match ap.grid_box.get() {
            Some((v, g)) if v == version => g,
            _ => match ap.vertices_grid_box(&self.world.body(b).shape) {
                Some(g) => {
                    ap.grid_box.set(Some((version, g)));
                    g
                }
                None => return self.seen_box(b, t),
            },
        };
        let [x, y] = self.world.body(b).frame.enclose(grid[0], grid[1], t);
        let out = [x, y]
            .iter()
            .all(|i| i.lo.is_finite() && i.hi.is_finite())
            .then_some([x, y]);
        #[cfg(debug_assertions)]
        if let (Some(o), Some(s)) = (out, self.seen_box(b, t)) {
            let holds = |o: Interval, s: Interval| o.lo <= s.lo && s.hi <= o.hi;
            debug_assert!(
                holds(o[0], s[0]) && holds(o[1], s[1]),
                "the loose box {o:?} of {b:?} misses part of its box {s:?}"
            );
        }
        out
    }

    /// A box `[x, y]` that holds, at any time in `t`, every vertex that
    /// body `b` is seen with: its polygon's bounding box placed by the
    /// frame (the real polygon), or the hull of its approximation
    /// vertices' enclosures; `None` when an enclosure is not finite.
    pub fn seen_box(&self, b: BodyId, t: Interval) -> Option<[Interval; 2]> {
        let body = self.world.body(b);
        let boxed = match self.shapes.approx(b) {
            None => {
                let [x0, x1, y0, y1] = body.shape.bounds();
                let o = Interval::point(0.0);
                let [px, py] = body.frame.enclose(o, o, t);
                let p = Interval::point;
                let (lx, hx) = ((px + p(x0)).lo, (px + p(x1)).hi);
                let (ly, hy) = ((py + p(y0)).lo, (py + p(y1)).hi);
                [Interval { lo: lx, hi: hx }, Interval { lo: ly, hi: hy }]
            }
            Some(ap) => {
                let mut out: Option<[Interval; 2]> = None;
                for k in ap.exposed.iter().filter(|&k| !ap.listed_hidden(k)) {
                    let e = self.enclose(Att::vertex(b, k as u32), t)?;
                    out = Some(match out {
                        None => e,
                        Some(o) => [o[0].hull(&e[0]), o[1].hull(&e[1])],
                    });
                }
                out?
            }
        };
        boxed
            .iter()
            .all(|i| i.lo.is_finite() && i.hi.is_finite())
            .then_some(boxed)
    }

    /// The sign of `orient(u, v, w)` at a time in `t` if the f64 filter
    /// decides it and it is not zero (then it is also the sign just before
    /// and just after that time); `None` otherwise.
    pub fn orient_filtered(&self, u: Att, v: Att, w: Att, t: Interval) -> Option<Sign> {
        super::counters::bump(super::counters::Counter::TurnsFiltered);
        // the midpoint–radius filter first (cheapest, on the cached
        // points), then the intervals
        if let (Some(a), Some(b), Some(c)) =
            (self.mid_rad(u, t), self.mid_rad(v, t), self.mid_rad(w, t))
        {
            if let Some(s) = crate::geom::orient_mid_rad(a, b, c) {
                #[cfg(debug_assertions)]
                {
                    let at = |[x0, x1, y0, y1]: [Interval; 4]| [x0 + x1 * t, y0 + y1 * t];
                    let lin = [u, v, w].map(|x| self.enclose_linear(x).map(at));
                    if let [Some(eu), Some(ev), Some(ew)] = lin {
                        if let Some(other) = crate::geom::orient_enclosed(eu, ev, ew) {
                            assert_eq!(s, other, "the two filters disagree on {u:?} {v:?} {w:?}");
                        }
                    }
                }
                return Some(s);
            }
        }
        self.orient_intervals(u, v, w, t)
    }

    /// [`Geo::orient_filtered`]'s second stage alone, the interval filter:
    /// for a turn whose points' midpoint–radius filter at `t` already left
    /// it undecided.
    pub fn orient_intervals(&self, u: Att, v: Att, w: Att, t: Interval) -> Option<Sign> {
        let lin = [
            self.enclose_linear(u)?,
            self.enclose_linear(v)?,
            self.enclose_linear(w)?,
        ];
        let at = |[x0, x1, y0, y1]: [Interval; 4]| [x0 + x1 * t, y0 + y1 * t];
        let s = crate::geom::orient_enclosed(at(lin[0]), at(lin[1]), at(lin[2]));
        if s.is_none() {
            super::counters::bump(super::counters::Counter::TurnsUndecided);
        }
        s
    }

    /// The sign of `(u − v)·(w − v)` at a time in `t` if the f64 filters
    /// decide it (midpoint–radius, [`crate::geom::dot_mid_rad`], then
    /// intervals) and it is not zero; `None` otherwise.
    pub fn dot_filtered(&self, u: Att, v: Att, w: Att, t: Interval) -> Option<Sign> {
        // the midpoint–radius filter first, on the cached points, as for
        // the turns
        if let (Some(a), Some(b), Some(c)) =
            (self.mid_rad(u, t), self.mid_rad(v, t), self.mid_rad(w, t))
        {
            if let Some(s) = crate::geom::dot_mid_rad(b, a, c) {
                return Some(s);
            }
        }
        let [ux, uy] = self.enclose(u, t)?;
        let [vx, vy] = self.enclose(v, t)?;
        let [wx, wy] = self.enclose(w, t)?;
        let d = (ux - vx) * (wx - vx) + (uy - vy) * (wy - vy);
        d.sign().filter(|&s| s != Sign::Zero)
    }

    /// The exact position of `a` at rational time `t` (`None` for `ω`).
    pub fn position(&self, a: Att, t: &Rational) -> Option<Point> {
        let Obj::Body(b) = a.obj else {
            return None;
        };
        let body = self.world.body(b);
        match self.shapes.approx(b) {
            None => Some(body.vertex_at(a.v as usize, t)),
            Some(ap) => {
                // a real vertex from the polygon's own coordinates (no
                // homogeneous point to reduce)
                let k = a.v as usize;
                let real = ap.exposed.contains(k).then(|| ap.exposed.pred(k));
                if let Some(v) = real.flatten().and_then(|i| ap.array.av_is_real(i, k)) {
                    return Some(body.vertex_at(v, t));
                }
                let h = ap
                    .array
                    .vertex_of(&body.shape, &ap.exposed, a.v as usize)
                    .expect("an exposed id with an approximation vertex");
                Some(body.traj.position_at(t).add(&h.to_point(body.shape.exp())))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An enclosure memo entry answers without the id before its vertex
    /// only for the exposed set's version it was last checked against: a
    /// new version clears every flag, and an entry read again with its id
    /// before is flagged for the new one; a new frame empties the memo, and
    /// a larger approximation grows it with its entries.
    #[test]
    fn an_enclosure_memo_entry_answers_by_version_only_once_checked() {
        let memo = EnclosureMemo::new(8);
        let e = |x: f64| [Interval { lo: x, hi: x + 1.0 }; 2];
        memo.put(7, (3, 1), 100, 8, e(1.0));
        memo.put(7, (5, 3), 100, 8, e(2.0));
        assert_eq!(memo.get_current(7, 3, 100), Some((1, e(1.0))));
        assert_eq!(memo.get_current(7, 5, 100), Some((3, e(2.0))));
        assert_eq!(memo.get_current(8, 3, 100), None, "another frame");
        // a pop or a merge: a new version, nothing answers by it yet
        assert_eq!(memo.get_current(7, 3, 101), None);
        assert_eq!(memo.get(7, (3, 2), 101), None, "another point");
        assert_eq!(memo.get(7, (3, 1), 101), Some(e(1.0)));
        assert_eq!(memo.get_current(7, 3, 101), Some((1, e(1.0))));
        assert_eq!(memo.get_current(7, 5, 101), None, "not checked again");
        assert_eq!(memo.get_current(7, 3, 100), None, "the old version");
        memo.put(9, (5, 3), 101, 8, e(3.0));
        assert_eq!(memo.get(7, (3, 1), 101), None, "the memo of another frame");
        assert_eq!(memo.get(9, (3, 1), 101), None, "emptied for the new frame");
        assert_eq!(memo.get_current(9, 5, 101), Some((3, e(3.0))));
        // grown for a larger approximation, the entries stay
        memo.put(9, (3, 1), 101, 8, e(4.0));
        memo.put(9, (40, 38), 101, 64, e(7.0));
        assert_eq!(memo.slots.borrow().len(), 128);
        assert_eq!(memo.get_current(9, 3, 101), Some((1, e(4.0))));
        assert_eq!(memo.get_current(9, 5, 101), Some((3, e(3.0))));
        assert_eq!(memo.get_current(9, 40, 101), Some((38, e(7.0))));
    }

    /// `Approx::cw`, `Approx::cw_distance` and the visible ranks agree with
    /// walks of `Approx::prev_visible` over the exposed set, for every id,
    /// as pops and merges change the approximation of a 37-gon (whose edge
    /// array repeats edges: ids that become hidden); each merge grows the
    /// box kept for `Geo::loose_box` to hold the new approximation.
    #[test]
    fn walks_round_an_approximation_are_ranks_in_its_visible_set() {
        let pts = crate::gen::regular_polygon(37, 100.0, 0.1);
        let body = crate::geom::BodyPolygon::new(&pts).expect("a convex polygon");
        let array = Arc::new(EdgeArray::new(&body));
        let exposed = array.coarsest();
        let mut ap = Approx::new(array, exposed);
        let check = |ap: &Approx| {
            let walked: Vec<usize> = ap.exposed().iter().filter(|&k| !ap.hidden(k)).collect();
            assert_eq!(ap.visible_len(), walked.len());
            for (r, &k) in walked.iter().enumerate() {
                assert_eq!(ap.visible_select(r), k);
                assert_eq!(ap.visible_rank(k), r);
            }
            let m = ap.exposed().universe();
            for from in (0..m).filter(|&k| ap.exposed().contains(k)) {
                let mut x = from;
                for k in 0..(2 * walked.len() as u32 + 3) {
                    assert_eq!(ap.cw(from, k), x, "{k} steps from {from}");
                    x = ap.prev_visible(x);
                }
                for &to in &walked {
                    // the walk's own count, up to one full round
                    let mut y = from;
                    let mut d = 0u32;
                    let expect = loop {
                        if y == to {
                            break Some(d);
                        }
                        y = ap.prev_visible(y);
                        d += 1;
                        if y == from || d > walked.len() as u32 + 1 {
                            break None;
                        }
                    };
                    assert_eq!(ap.cw_distance(from, to, u32::MAX), expect);
                    if let Some(d) = expect.filter(|&d| d > 0) {
                        assert_eq!(ap.cw_distance(from, to, d - 1), None);
                    }
                }
            }
        };
        check(&ap);
        // pop the first vertex that pops, again and again, then merge back
        let mut popped = Vec::new();
        let mut hidden = 0;
        for _ in 0..200 {
            let ks: Vec<usize> = ap.exposed().iter().collect();
            let Some(t) = ks.iter().find_map(|&k| ap.pop(k)) else {
                break;
            };
            popped.push(t);
            check(&ap);
            hidden = hidden.max(ap.exposed().len() - ap.visible_len());
        }
        assert!(popped.len() > 10, "only {} pops", popped.len());
        assert!(hidden > 0, "no id was hidden");
        // (the box kept for `Geo::loose_box`, set here as it computes it)
        let fresh = |ap: &Approx| ap.vertices_grid_box(&body).expect("finite");
        ap.grid_box
            .set(Some((ap.exposed().last_removal(), fresh(&ap))));
        let mut merges = 0;
        for &t in popped.iter().rev() {
            if ap.merge(t, &body) {
                merges += 1;
                // a merge grows the kept box to hold the new vertices
                let (v, kept) = ap.grid_box.get().expect("grown, not dropped");
                assert_eq!(v, ap.exposed().last_removal());
                let now = fresh(&ap);
                let holds = |o: Interval, s: Interval| o.lo <= s.lo && s.hi <= o.hi;
                assert!(holds(kept[0], now[0]) && holds(kept[1], now[1]));
                check(&ap);
                ap.unmerge(t);
                check(&ap);
                assert!(ap.merge(t, &body));
                check(&ap);
            }
        }
        assert!(merges > 10, "only {merges} merges");
    }
}
