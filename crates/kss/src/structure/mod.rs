//! The kinetic separation structure (KSS) for convex polygons, section 2 of
//! Kirkpatrick & Speckmann, specialised to convex objects (see
//! `ARCHITECTURE.md` and `docs/design/structure.md` for the conventions and
//! the rules).
//!
//! The free space between the `k` polygons and the point at infinity `ω` is
//! cut by `2k − 2` *partition triangles* (corners on three different objects)
//! into `3k − 3` *corridors*; each corridor lies between two objects, is
//! bounded by two end-edges (sides of partition triangles) and two convex
//! chains, and is split by at most one *middle bridge* into at most two
//! pseudo-triangles.
//!
//! Conventions (all orientations counter-clockwise, free space on the left):
//!
//! * a partition triangle's corners `c[0], c[1], c[2]` are in CCW order; its
//!   side `i` is `(c[i], c[i+1])` and the corridor across it is `corr[i]`;
//! * a corridor's end `s` is side `(p, q)` of its triangle `s.0`; then
//!   `a = obj(p)` (never `ω`), `b = obj(q)`, `a_s = p`, `b_s = q`. Its end
//!   `t` is side `(b_t, a_t)` of triangle `t.0`. The A-chain runs from `a_s`
//!   clockwise around `A` (decreasing vertex index) over `len_a` edges to
//!   `a_t`; the B-chain from `b_t` clockwise over `len_b` edges to `b_s`.
//!   An empty corridor has `s` and `t` on the same edge and no chain edges.
//! * the middle bridge, if any, joins `α = a_s − i` and `β = b_t − j`
//!   (offsets along the chains); the face next to end `s` has the A-chain from
//!   `a_s` to `α` and the B-chain from `β` to `b_s`.

pub mod audit;
pub mod build;
pub mod certs;
pub mod coarsen;
pub mod counters;
pub mod events;
pub mod faces;
pub mod geo;
pub mod incidence;
pub mod kinetic;
pub mod local;
pub(crate) mod memo;
pub mod ops;
pub mod pop;
pub mod refine;
pub mod remove;
pub mod view;

use crate::world::BodyId;
use incidence::{Incidence, Slots};

/// Why an operation of the structure failed. The text says where and what;
/// the variant says which kind of failure it is, and so what the engine does
/// next.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum StructureError {
    /// A local operation (a slide, flip, pop, normalization, removal or
    /// insertion in place) found no valid configuration: an instant where
    /// several degeneracies coincide. The engine falls back to a local
    /// repair, a rebuild for just after the instant, or the reference.
    #[error("{0}")]
    Local(String),
    /// No structure can be built at the instant (polygons overlap or touch
    /// where the construction needs them apart).
    #[error("{0}")]
    Build(String),
    /// An invariant does not hold: found by the audit, or by the exact
    /// check of a candidate structure built from the shrunk copy.
    #[error("{0}")]
    Invariant(String),
}

impl StructureError {
    /// The same failure, its text prefixed by `what` (where it happened).
    pub fn within(self, what: impl std::fmt::Display) -> StructureError {
        match self {
            StructureError::Local(s) => StructureError::Local(format!("{what}: {s}")),
            StructureError::Build(s) => StructureError::Build(format!("{what}: {s}")),
            StructureError::Invariant(s) => StructureError::Invariant(format!("{what}: {s}")),
        }
    }
}

impl From<crate::hier::HierarchyError> for StructureError {
    fn from(e: crate::hier::HierarchyError) -> StructureError {
        StructureError::Invariant(e.0)
    }
}

impl From<build::BuildError> for StructureError {
    fn from(e: build::BuildError) -> StructureError {
        StructureError::Build(e.to_string())
    }
}

/// An object: a body, or the point at infinity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Obj {
    /// A polygon of the world.
    Body(BodyId),
    /// The point at infinity.
    Omega,
}

/// A point a bridge can end at: a vertex of a body, or `ω`.
///
/// Ordered by object (bodies by index, `ω` last), then vertex id: the
/// order of their words ([`Att::word`]), which is what is compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Att {
    /// The object.
    pub obj: Obj,
    /// The vertex index (0 for `ω`).
    pub v: u32,
}

// (a body id is never zero inside, so `ω` takes no room of its own: an
// object is four bytes and a point eight, a triple of points 24)
const _: () = assert!(std::mem::size_of::<Obj>() == 4 && std::mem::size_of::<Att>() == 8);

/// One word per point (the certificate maps hash triples of them on every
/// event): the body index (`u32::MAX` for `ω`) and the vertex id.
impl std::hash::Hash for Att {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        state.write_u64(self.word());
    }
}

/// (one comparison of two words: the structure sorts triples of points,
/// and keys ordered maps with them, on every event)
impl Ord for Att {
    #[inline]
    fn cmp(&self, other: &Att) -> std::cmp::Ordering {
        self.word().cmp(&other.word())
    }
}

impl PartialOrd for Att {
    #[inline]
    fn partial_cmp(&self, other: &Att) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Att {
    /// The point as one word: the body index (`u32::MAX` for `ω`) above
    /// the vertex id; two points are equal exactly when their words are.
    pub fn word(self) -> u64 {
        let obj = match self.obj {
            Obj::Body(b) => b.raw(),
            Obj::Omega => u32::MAX,
        };
        (u64::from(obj) << 32) | u64::from(self.v)
    }

    /// The point whose [`Att::word`] is `w`.
    pub fn from_word(w: u64) -> Att {
        let (obj, v) = ((w >> 32) as u32, w as u32);
        Att {
            obj: if obj == u32::MAX {
                Obj::Omega
            } else {
                Obj::Body(crate::world::BodyId::new(obj))
            },
            v,
        }
    }

    /// The point at infinity.
    pub const OMEGA: Att = Att {
        obj: Obj::Omega,
        v: 0,
    };

    /// Vertex `v` of body `b`.
    pub fn vertex(b: BodyId, v: u32) -> Att {
        Att {
            obj: Obj::Body(b),
            v,
        }
    }

    /// Whether this is `ω`.
    pub fn is_omega(self) -> bool {
        self.obj == Obj::Omega
    }
}

/// Index of a partition triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TriId(pub u32);

/// Index of a corridor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CorrId(pub u32);

/// A partition triangle: corners on three different objects, CCW.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartitionTriangle {
    /// The corners, counter-clockwise.
    pub c: [Att; 3],
    /// `corr[i]` is the corridor across side `(c[i], c[i+1])`.
    pub corr: [CorrId; 3],
}

/// A corridor between two objects (module docs for the conventions).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Corridor {
    /// Object of `a_s` and `a_t` (never `ω`).
    pub a: Obj,
    /// The other object.
    pub b: Obj,
    /// End `s`: a triangle and the index of its side `(a_s, b_s)`.
    pub s: (TriId, u8),
    /// End `t`: a triangle and the index of its side `(b_t, a_t)`.
    pub t: (TriId, u8),
    /// Edges on the A-chain.
    pub len_a: u32,
    /// Edges on the B-chain (0 when `b` is `ω`).
    pub len_b: u32,
    /// The middle bridge as offsets `(i, j)`: `α = a_s − i`, `β = b_t − j`.
    pub mid: Option<(u32, u32)>,
}

/// The kinetic separation structure's combinatorial state.
#[derive(Clone, Debug, Default)]
pub struct Kss {
    /// Partition triangles.
    pub tris: Slots<PartitionTriangle>,
    /// Corridors.
    pub corrs: Slots<Corridor>,
    /// Which triangles and corridors lie on each body.
    pub incidence: Incidence,
    /// Junctions `(prev, v, next)` of a corridor whose certificate keeps the
    /// sign opposite to the one it has just after the current instant: it
    /// fails at this instant and is handled as one of its events (see
    /// [`Kss::normalize`]); empty between event instants.
    pub held: std::collections::BTreeMap<CorrId, Vec<[Att; 3]>>,
    /// The certificate (canonical triple) whose failure is being handled:
    /// never held against the motion, or its event would repeat for ever.
    pub handling: Option<[Att; 3]>,
    /// How [`Kss::normalize`] chooses among the decompositions that hold
    /// some junctions against the motion: the first candidate that works,
    /// or, at this instant (one at which the operations were seen to
    /// cycle, [`kinetic::Kinetic::alternate_normalization`]), the one
    /// holding the fewest.
    pub fewest_held: Option<crate::num::Time>,
    /// The middle-bridge walks of the [`Kss::normalize`] call in progress
    /// (`None` outside one): a walk is a function of its corridor, start,
    /// diagonal type and side at the instant, and a normalization that finds
    /// no decomposition walks the same ones again for its candidates.
    pub(crate) walk_memo: std::cell::RefCell<Option<WalkMemo>>,
    /// Junction certificates known to keep their sign just after one
    /// instant (`known.0`), set by the kinetic layer around the
    /// normalization that follows an operation (`None` elsewhere): the
    /// stored certificates of the corridor that are queued strictly after
    /// that instant, at an instant at which nothing else fails. A junction
    /// checked just after that instant whose triple is one of them has its
    /// sign without a test ([`Kss::faces_valid_on`]); its clearance is
    /// tested (a certificate does not say which of its three points was
    /// the vertex of the junction it was made for: a junction on the same
    /// points at another vertex was never tested), but in the check that
    /// [`Kss::trust_op`] marks.
    pub(crate) known: Option<(crate::num::Time, local::Certs)>,
    /// Set by [`Kss::decompose`] around its first check, the one of the
    /// corridor as the operation left it, while [`Kss::known`] and
    /// [`Kss::op_alone`] are set: for the only failure of an instant, the
    /// operation's result is a pseudo-triangulation (the paper's local
    /// update), so that check reads the signs of the junctions the
    /// operation made and not their clearance (debug builds test the
    /// clearance all the same). Every other candidate (a walk's, a
    /// repair's, a removal's) is tested whole. (After other changes at the
    /// same instant the operation's result can wrap a face around a
    /// vertex: the differential tests over the grazing family find such
    /// faces.)
    pub(crate) trust_op: std::cell::Cell<bool>,
    /// Set by the kinetic layer around the normalizations that follow an
    /// operation that is the first change of the structure at its instant
    /// (no operation, pop, motion change, removal, insertion, repair or
    /// construction before it there).
    pub(crate) op_alone: bool,
}

/// What a middle-bridge walk of one normalization depends on: the
/// corridor, the start, the diagonal type and the side (`true`: after).
pub(crate) type WalkKey = (u32, (u32, u32), bool, bool);

/// A remembered walk: its key and where it ended (the middle bridge and
/// the steps it took), `None` if it found none.
pub(crate) type WalkMemoEntry = (WalkKey, Option<((u32, u32), u32)>);

/// What the positions that lead a walk into a cycle depend on: the
/// corridor, the diagonal type and the side (`true`: after).
pub(crate) type CycleKey = (u32, bool, bool);

/// The walks of one normalization ([`Kss::walk_memo`]): each walk's end,
/// and per corridor, diagonal type and side (`true`: after) the positions
/// `(i, j)` that a walk passed through on its way into a cycle, as a
/// bitset of `i·(len_b + 1) + j` (corridors whose positions fit in 4096
/// bits): a step is a function of the position alone, so a walk that
/// reaches one of them cycles too.
#[derive(Clone, Debug, Default)]
pub(crate) struct WalkMemo {
    /// The walks and where they ended.
    pub(crate) walks: Vec<WalkMemoEntry>,
    /// The positions that lead into a cycle.
    pub(crate) cycling: Vec<(CycleKey, Box<[u64; 64]>)>,
}

impl Kss {
    /// The corner of triangle `t` at index `i` (mod 3).
    pub fn corner(&self, t: TriId, i: usize) -> Att {
        self.tris[t.0 as usize].c[i % 3]
    }

    /// The end-edge endpoints `(a_s, b_s, a_t, b_t)` of a corridor.
    pub fn ends(&self, k: CorrId) -> (Att, Att, Att, Att) {
        let c = &self.corrs[k.0 as usize];
        let (ts, is) = (c.s.0, c.s.1 as usize);
        let (tt, it) = (c.t.0, c.t.1 as usize);
        (
            self.corner(ts, is),
            self.corner(ts, is + 1),
            self.corner(tt, it + 1),
            self.corner(tt, it),
        )
    }

    /// Print every corridor's ends, chain lengths and middle bridge (trace
    /// builds only, for debugging).
    #[cfg(feature = "trace")]
    pub fn trace_dump(&self) {
        for (i, c) in self.corrs.iter().enumerate() {
            let (a_s, b_s, a_t, b_t) = self.ends(CorrId(i as u32));
            let f = |x: Att| match x.obj {
                Obj::Body(b) => format!("{}.{}", b.raw(), x.v),
                Obj::Omega => "w".to_string(),
            };
            eprintln!(
                "  corridor {i}: s {}-{} t {}-{} len {}/{} mid {:?}",
                f(a_s),
                f(b_s),
                f(a_t),
                f(b_t),
                c.len_a,
                c.len_b,
                c.mid
            );
        }
    }
}
