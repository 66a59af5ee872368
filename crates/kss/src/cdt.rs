//! An exact constrained triangulation of points and non-crossing segments.
//!
//! The triangulation never looks at coordinates: it asks a [`Predicates`]
//! implementation for the lexicographic order of two vertices, the sign of
//! an orientation, and whether a vertex is certainly inside a circle. With
//! exact answers to the first two, the result is a valid triangulation of
//! the convex hull whatever the magnitudes (no triangle is flat, every
//! segment is an edge); the third only steers the choice towards the
//! constrained Delaunay triangulation, and a caller may answer `false`
//! whenever it is unsure.
//!
//! The steps: the vertices are inserted one by one in a biased randomized
//! order (each located by a walk, joined to the triangle or the hull edges
//! around it, and made Delaunay around it by Lawson flips where the circle
//! test is certain); each segment that is not yet an edge is inserted by
//! flipping the edges that cross it (Sloan's method: an edge whose
//! quadrilateral is strictly convex is flipped, the others wait their
//! turn); a last round of flips restores the Delaunay property around the
//! new edges, never flipping a segment. Edges inside an obstacle (between
//! two vertices of one convex polygon) are never flipped.
//!
//! Why it is not a crate: the triangulation crates work on doubles, and
//! the structure's vertices are exact rationals at a rational instant
//! (positions that coincide in doubles, magnitudes outside the doubles'
//! range, and the infinitesimally shrunk copy that the construction uses
//! when polygons touch).

use std::cmp::Ordering;
use std::collections::{HashSet, VecDeque};

use crate::num::Sign;

/// The geometric questions the triangulation asks about its vertices
/// (indices into the caller's point list).
pub trait Predicates {
    /// The lexicographic order of `a` and `b` (x first, then y);
    /// `Equal` only for coincident points.
    fn cmp(&self, a: usize, b: usize) -> Ordering;
    /// The sign of the orientation of `(a, b, c)`: positive for a
    /// counter-clockwise turn.
    fn orient(&self, a: usize, b: usize, c: usize) -> Sign;
    /// Whether `d` is certainly strictly inside the circle through the
    /// counter-clockwise triangle `(a, b, c)`. Answering `false` when
    /// unsure keeps the triangulation valid (it may then not be Delaunay).
    fn in_circle(&self, a: usize, b: usize, c: usize, d: usize) -> bool;
    /// Whether an edge between `a` and `b` lies on or inside a convex
    /// obstacle whose boundary edges are all segments (both are vertices
    /// of it): the shape of the triangulation there does not matter, and
    /// such an edge is never flipped for the Delaunay property. Without it,
    /// the flips inside a polygon of many vertices, nearly cocircular
    /// ones above all, can number in the square of its vertex count. The
    /// default: no edge is.
    fn same_obstacle(&self, _a: usize, _b: usize) -> bool {
        false
    }
    /// An approximate position of `a`, for the order in which the vertices
    /// are inserted (only the speed depends on it; `None` where there is
    /// none). The default: none.
    fn position_hint(&self, _a: usize) -> Option<[f64; 2]> {
        None
    }
}

/// Why a triangulation could not be built (each is a degenerate input,
/// not a numerical failure: the predicates are exact).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CdtError {
    /// Two vertices coincide.
    #[error("vertices {0} and {1} coincide")]
    Coincident(usize, usize),
    /// All vertices lie on one line (or there are fewer than three).
    #[error("the vertices are collinear")]
    Collinear,
    /// A vertex lies on a segment between its ends.
    #[error("vertex {2} lies on the segment from {0} to {1}")]
    VertexOnSegment(usize, usize, usize),
    /// Segments cross: each listed segment crosses one inserted before it
    /// (in the order given), and is not an edge.
    #[error("{} segments cross others", .0.len())]
    Crossing(Vec<[usize; 2]>),
    /// The flips that insert a segment did not end (not expected with
    /// exact predicates).
    #[error("inserting the segment from {0} to {1} did not end")]
    Stuck(usize, usize),
}

const NONE: u32 = u32::MAX;

/// A triangle mesh: counter-clockwise triangles and, for each side `i`
/// (from corner `i` to corner `i + 1`), the triangle across it.
struct Mesh {
    tri: Vec<[u32; 3]>,
    nbr: Vec<[u32; 3]>,
    /// One triangle at each vertex.
    at: Vec<u32>,
}

impl Mesh {
    /// The side index of the directed edge `a → b` in triangle `t`.
    fn side(&self, t: u32, a: u32, b: u32) -> Option<usize> {
        let c = self.tri[t as usize];
        (0..3).find(|&i| c[i] == a && c[(i + 1) % 3] == b)
    }

    fn corner(&self, t: u32, a: u32) -> usize {
        let c = self.tri[t as usize];
        (0..3)
            .find(|&i| c[i] == a)
            .expect("a triangle at a vertex has it as a corner")
    }

    /// The triangle and side holding the directed edge `a → b`.
    fn find(&self, a: u32, b: u32) -> Option<(u32, usize)> {
        let start = self.at[a as usize];
        let mut t = start;
        // clockwise around `a`, across the side that ends at `a`
        loop {
            let i = self.corner(t, a);
            if self.tri[t as usize][(i + 1) % 3] == b {
                return Some((t, i));
            }
            let n = self.nbr[t as usize][(i + 2) % 3];
            if n == NONE {
                break;
            }
            t = n;
            if t == start {
                return None;
            }
        }
        // counter-clockwise from the start, up to the hull
        t = start;
        loop {
            let i = self.corner(t, a);
            let n = self.nbr[t as usize][i];
            if n == NONE || n == start {
                return None;
            }
            t = n;
            let j = self.corner(t, a);
            if self.tri[t as usize][(j + 1) % 3] == b {
                return Some((t, j));
            }
        }
    }

    /// Push the triangles at vertex `a` onto `out` (every one: around `a`
    /// both ways from [`Mesh::at`], up to the hull).
    fn fan(&self, a: u32, out: &mut Vec<u32>) {
        let start = self.at[a as usize];
        let mut t = start;
        // clockwise, across the side that ends at `a`
        loop {
            out.push(t);
            let i = self.corner(t, a);
            let n = self.nbr[t as usize][(i + 2) % 3];
            if n == start {
                return;
            }
            if n == NONE {
                break;
            }
            t = n;
        }
        // counter-clockwise from the start, across the side that begins at `a`
        t = start;
        loop {
            let i = self.corner(t, a);
            let n = self.nbr[t as usize][i];
            if n == NONE {
                return;
            }
            t = n;
            out.push(t);
        }
    }

    /// The edge `{a, b}` in either direction.
    fn find_either(&self, a: u32, b: u32) -> Option<(u32, usize)> {
        self.find(a, b).or_else(|| self.find(b, a))
    }

    /// Point the side of `t` that holds `a → b` at `to`.
    fn link(&mut self, t: u32, a: u32, b: u32, to: u32) {
        if t == NONE {
            return;
        }
        let i = self
            .side(t, a, b)
            .expect("the neighbour holds the shared side");
        self.nbr[t as usize][i] = to;
    }

    /// Flip the edge on side `i` of `t`: triangles `(a, b, c)` and
    /// `(b, a, d)` become `(c, a, d)` and `(d, b, c)`. Returns `c, d`.
    fn flip(&mut self, t: u32, i: usize) -> (u32, u32) {
        let u = self.nbr[t as usize][i];
        let [a, b, c] = [0, 1, 2].map(|k| self.tri[t as usize][(i + k) % 3]);
        let j = self.side(u, b, a).expect("the neighbour holds the edge");
        let d = self.tri[u as usize][(j + 2) % 3];
        let n_bc = self.nbr[t as usize][(i + 1) % 3];
        let n_ca = self.nbr[t as usize][(i + 2) % 3];
        let n_ad = self.nbr[u as usize][(j + 1) % 3];
        let n_db = self.nbr[u as usize][(j + 2) % 3];
        self.tri[t as usize] = [c, a, d];
        self.nbr[t as usize] = [n_ca, n_ad, u];
        self.tri[u as usize] = [d, b, c];
        self.nbr[u as usize] = [n_db, n_bc, t];
        self.link(n_ad, d, a, t);
        self.link(n_bc, c, b, u);
        self.at[a as usize] = t;
        self.at[c as usize] = t;
        self.at[b as usize] = u;
        self.at[d as usize] = u;
        (c, d)
    }
}

/// Triangulate the `n` vertices with every segment of `segments` as an
/// edge. Returns counter-clockwise triangles covering the convex hull.
///
/// Segments may repeat, in either direction; a segment from a vertex to
/// itself is an error of the caller (it panics in debug builds).
pub fn triangulate(
    n: usize,
    segments: &[[usize; 2]],
    p: &impl Predicates,
) -> Result<Vec<[usize; 3]>, CdtError> {
    let mesh = triangulate_mesh(n, segments, p)?;
    Ok(mesh.tri.iter().map(|t| t.map(|v| v as usize)).collect())
}

/// [`triangulate`], with each triangle's neighbours: for side `i` (from
/// corner `i` to corner `i + 1`), the index of the triangle across it,
/// `None` on the convex hull.
pub fn triangulate_adjacent(
    n: usize,
    segments: &[[usize; 2]],
    p: &impl Predicates,
) -> Result<TrianglesAdjacent, CdtError> {
    let mesh = triangulate_mesh(n, segments, p)?;
    let across = |x: u32| (x != NONE).then_some(x);
    Ok((
        mesh.tri.iter().map(|t| t.map(|v| v as usize)).collect(),
        mesh.nbr.iter().map(|t| t.map(across)).collect(),
    ))
}

/// The triangles of [`triangulate_adjacent`] and their neighbours.
pub type TrianglesAdjacent = (Vec<[usize; 3]>, Vec<[Option<u32>; 3]>);

/// A triangulation as [`triangulate`] makes it, with its adjacency: which
/// triangle lies across each side and which one holds a directed edge, in
/// time proportional to the triangles at the edge's first vertex.
pub struct Triangulation(Mesh);

impl Triangulation {
    /// The number of triangles.
    pub fn len(&self) -> usize {
        self.0.tri.len()
    }

    /// Whether there is no triangle.
    pub fn is_empty(&self) -> bool {
        self.0.tri.is_empty()
    }

    /// Triangle `t`, counter-clockwise.
    pub fn triangle(&self, t: usize) -> [usize; 3] {
        self.0.tri[t].map(|v| v as usize)
    }

    /// The triangle across side `i` of triangle `t` (from corner `i` to
    /// corner `i + 1`), `None` on the convex hull.
    pub fn across(&self, t: usize, i: usize) -> Option<usize> {
        let n = self.0.nbr[t][i];
        (n != NONE).then_some(n as usize)
    }

    /// The triangle with the directed edge `a → b` as a side (on its left),
    /// `None` if `a → b` is no side of a triangle (on the hull, or no edge).
    pub fn left_of(&self, a: usize, b: usize) -> Option<usize> {
        self.0.find(a as u32, b as u32).map(|(t, _)| t as usize)
    }
}

/// [`triangulate`] as a [`Triangulation`], with its adjacency.
pub fn triangulate_with_adjacency(
    n: usize,
    segments: &[[usize; 2]],
    p: &impl Predicates,
) -> Result<Triangulation, CdtError> {
    triangulate_mesh(n, segments, p).map(Triangulation)
}

/// The mesh of [`triangulate`].
fn triangulate_mesh(
    n: usize,
    segments: &[[usize; 2]],
    p: &impl Predicates,
) -> Result<Mesh, CdtError> {
    let mut mesh = delaunay(n, p)?;
    let mut fixed: HashSet<(u32, u32), foldhash::fast::FixedState> =
        HashSet::with_capacity_and_hasher(segments.len(), Default::default());
    let mut crossing = Vec::new();
    for &[u, v] in segments {
        debug_assert_ne!(u, v, "a segment joins two vertices");
        let (u, v) = (u as u32, v as u32);
        let key = (u.min(v), u.max(v));
        if fixed.contains(&key) {
            continue;
        }
        match insert_segment(&mut mesh, u, v, &fixed, p) {
            Ok(fresh) => {
                fixed.insert(key);
                legalize(&mut mesh, fresh, &fixed, p);
            }
            // (found before any flip: the mesh is unchanged)
            Err(Cross) => crossing.push([u as usize, v as usize]),
            Err(Other(e)) => return Err(e),
        }
    }
    if !crossing.is_empty() {
        return Err(CdtError::Crossing(crossing));
    }
    Ok(mesh)
}

/// The seed of the insertion order (any fixed value: the order must be the
/// same on every run, and only the speed depends on it).
const ORDER_SEED: u64 = 0x006b_7373_5f63_6474;

/// The Delaunay triangulation (where the circle test is certain) of the
/// vertices: inserted one by one in a biased randomized order
/// ([`insertion_order`]), each located by a walk from the previous one
/// ([`locate`]) and made Delaunay around by flips before the next. A
/// random order keeps the expected number of flips linear; an order along
/// a line (a sweep) does not: inserted in `x` order, the vertices of two
/// large polygons facing each other across a gap cost a number of flips in
/// the square of their count.
fn delaunay(n: usize, p: &impl Predicates) -> Result<Mesh, CdtError> {
    // (two vertices that coincide are found as they are inserted, where the
    // walk ends at a corner; only where none is off the first two's line
    // are they looked for here, so that coincident vertices are reported
    // as such rather than as collinear ones)
    let collinear = || match coincident(n, p) {
        Some((a, b)) => CdtError::Coincident(a, b),
        None => CdtError::Collinear,
    };
    if n < 3 {
        return Err(collinear());
    }
    let order = insertion_order(n, p);
    // the first triangle: the first two vertices and the first one off
    // their line
    let (a0, b0) = (order[0], order[1]);
    if p.cmp(a0, b0) == Ordering::Equal {
        return Err(CdtError::Coincident(a0, b0));
    }
    let Some(k) = (2..n).find(|&k| p.orient(a0, b0, order[k]) != Sign::Zero) else {
        return Err(collinear());
    };
    let c0 = order[k];
    let first = if p.orient(a0, b0, c0) == Sign::Positive {
        [a0, b0, c0]
    } else {
        [b0, a0, c0]
    }
    .map(|v| v as u32);
    let mut mesh = Mesh {
        tri: Vec::with_capacity(2 * n),
        nbr: Vec::with_capacity(2 * n),
        at: vec![NONE; n],
    };
    mesh.tri.push(first);
    mesh.nbr.push([NONE; 3]);
    // the hull, counter-clockwise (the interior on the left of `v → next[v]`)
    let mut hull = Hull {
        next: vec![NONE; n],
        prev: vec![NONE; n],
    };
    for i in 0..3 {
        let (x, y) = (first[i], first[(i + 1) % 3]);
        mesh.at[x as usize] = 0;
        hull.next[x as usize] = y;
        hull.prev[y as usize] = x;
    }
    let mut rng = crate::rng::Rng::new(ORDER_SEED);
    let mut hint = 0u32;
    // (the triangles at the new vertex whose far side is to test, one
    // buffer for all insertions)
    let mut stack: Vec<u32> = Vec::new();
    for (idx, &v) in order.iter().enumerate() {
        if idx < 2 || idx == k {
            continue;
        }
        let v32 = v as u32;
        match locate(&mesh, hint, v, p, &mut rng) {
            Located::Inside(t) => split_triangle(&mut mesh, t, v32),
            Located::OnSide(t, i) => split_side(&mut mesh, &mut hull, t, i, v32),
            Located::Outside(t, i) => attach_outside(&mut mesh, &mut hull, t, i, v32, p),
            Located::Corner(w) => return Err(CdtError::Coincident(v, w as usize)),
        };
        mesh.fan(v32, &mut stack);
        legalize_at(&mut mesh, v32, &mut stack, p);
        hint = mesh.at[v];
    }
    Ok(mesh)
}

/// Two of the `n` vertices that coincide, if any (neighbours in the
/// lexicographic order).
fn coincident(n: usize, p: &impl Predicates) -> Option<(usize, usize)> {
    let mut sorted: Vec<usize> = (0..n).collect();
    sorted.sort_by(|&a, &b| p.cmp(a, b));
    sorted
        .windows(2)
        .find(|w| p.cmp(w[0], w[1]) == Ordering::Equal)
        .map(|w| (w[0], w[1]))
}

/// The convex hull as a cycle of vertices (`NONE` for the others).
struct Hull {
    next: Vec<u32>,
    prev: Vec<u32>,
}

/// The insertion order: a biased randomized insertion order (the vertices
/// shuffled, then cut into rounds of doubling size), each round sorted
/// along a Hilbert curve through the approximate positions
/// ([`Predicates::position_hint`]) so that the walk from one vertex to the
/// next is short. Vertices without a hint end their round, in random order.
fn insertion_order(n: usize, p: &impl Predicates) -> Vec<usize> {
    let mut rng = crate::rng::Rng::new(ORDER_SEED);
    let mut order: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        let j = rng.below(i as u64 + 1) as usize;
        order.swap(i, j);
    }
    let hints: Vec<Option<[f64; 2]>> = (0..n)
        .map(|i| {
            p.position_hint(i)
                .filter(|h| h[0].is_finite() && h[1].is_finite())
        })
        .collect();
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for h in hints.iter().flatten() {
        for c in 0..2 {
            lo[c] = lo[c].min(h[c]);
            hi[c] = hi[c].max(h[c]);
        }
    }
    // (a cell of a 2^16 × 2^16 grid over the hints' box; a NaN of an
    // overflowing span becomes cell 0, which only costs speed)
    let cell =
        |x: f64, c: usize| ((x - lo[c]) / (hi[c] - lo[c]) * 65535.0).clamp(0.0, 65535.0) as u32;
    let keys: Vec<u64> = hints
        .iter()
        .map(|h| h.map_or(u64::MAX, |h| hilbert(cell(h[0], 0), cell(h[1], 1))))
        .collect();
    let (mut start, mut end) = (0, n.min(64));
    loop {
        order[start..end].sort_by_key(|&i| keys[i]);
        if end == n {
            break;
        }
        (start, end) = (end, n.min(2 * end));
    }
    order
}

/// The position of cell `(x, y)` (each below 2^16) along a Hilbert curve
/// through the 2^16 × 2^16 grid: one base-4 digit per bit of the
/// coordinates, from the top, each read with the coordinates turned as the
/// digits above left them (swapped, complemented, or both), four bits of
/// each at a time from [`HILBERT_CHUNKS`].
fn hilbert(x: u32, y: u32) -> u64 {
    let mut d = 0u64;
    let mut state = 0usize;
    for shift in [12, 8, 4, 0] {
        let xy = ((((x >> shift) & 15) << 4) | ((y >> shift) & 15)) as usize;
        let (digits, next) = HILBERT_CHUNKS[state][xy];
        d = (d << 8) | u64::from(digits);
        state = usize::from(next);
    }
    d
}

/// For a turn of the coordinates (bit 0: swapped, bit 1: complemented) and
/// four bits of each (`x` above `y`), the four digits of [`hilbert`] they
/// give (two bits each, the first above) and the turn after them.
const HILBERT_CHUNKS: [[(u8, u8); 256]; 4] = hilbert_chunks();

const fn hilbert_chunks() -> [[(u8, u8); 256]; 4] {
    let mut table = [[(0u8, 0u8); 256]; 4];
    let mut turn = 0;
    while turn < 4 {
        let mut xy = 0;
        while xy < 256 {
            let (mut swap, mut flip) = (turn & 1 != 0, turn & 2 != 0);
            let mut digits = 0u8;
            let mut bit = 4;
            while bit > 0 {
                bit -= 1;
                let (mut rx, mut ry) = ((xy >> (4 + bit)) & 1, (xy >> bit) & 1);
                if flip {
                    (rx, ry) = (rx ^ 1, ry ^ 1);
                }
                if swap {
                    (rx, ry) = (ry, rx);
                }
                digits = (digits << 2) | ((3 * rx) ^ ry) as u8;
                // (complementing both and swapping commute: a turn is the
                // two flags, whatever the order they were set in)
                if ry == 0 {
                    flip ^= rx == 1;
                    swap = !swap;
                }
            }
            table[turn][xy] = (digits, (swap as u8) | ((flip as u8) << 1));
            xy += 1;
        }
        turn += 1;
    }
    table
}

/// Where a new vertex lies in the mesh.
enum Located {
    /// Strictly inside triangle `t`.
    Inside(u32),
    /// On side `i` of triangle `t`, strictly between its ends.
    OnSide(u32, usize),
    /// Outside the hull, strictly beyond side `i` of triangle `t` (a hull
    /// edge).
    Outside(u32, usize),
    /// At this vertex.
    Corner(u32),
}

/// Locate vertex `v` by a walk from triangle `start`: across a side that
/// `v` is strictly beyond, chosen from a random first side and never back
/// the way it came (a remembering stochastic walk, which ends on every
/// triangulation, Delaunay or not).
fn locate(
    mesh: &Mesh,
    start: u32,
    v: usize,
    p: &impl Predicates,
    rng: &mut crate::rng::Rng,
) -> Located {
    let mut t = start;
    let mut from = NONE;
    'walk: loop {
        let c = mesh.tri[t as usize];
        let r = rng.below(3) as usize;
        let mut zero = [false; 3];
        for s in 0..3 {
            let i = (r + s) % 3;
            let across = mesh.nbr[t as usize][i];
            // (the side it came by: `v` is strictly on this side of it)
            if across != NONE && across == from {
                continue;
            }
            match p.orient(c[i] as usize, c[(i + 1) % 3] as usize, v) {
                Sign::Negative if across == NONE => return Located::Outside(t, i),
                Sign::Negative => {
                    from = t;
                    t = across;
                    continue 'walk;
                }
                Sign::Zero => zero[i] = true,
                Sign::Positive => {}
            }
        }
        return match zero {
            [false, false, false] => Located::Inside(t),
            [true, false, false] => Located::OnSide(t, 0),
            [false, true, false] => Located::OnSide(t, 1),
            [false, false, true] => Located::OnSide(t, 2),
            // on two sides' lines: at their common corner
            [true, true, _] => Located::Corner(c[1]),
            [_, true, true] => Located::Corner(c[2]),
            [true, _, true] => Located::Corner(c[0]),
        };
    }
}

/// Split triangle `t` at `v`, strictly inside it, into three.
fn split_triangle(mesh: &mut Mesh, t: u32, v: u32) {
    let [a, b, c] = mesh.tri[t as usize];
    let [n_ab, n_bc, n_ca] = mesh.nbr[t as usize];
    let (t1, t2) = (mesh.tri.len() as u32, mesh.tri.len() as u32 + 1);
    mesh.tri[t as usize] = [a, b, v];
    mesh.nbr[t as usize] = [n_ab, t1, t2];
    mesh.tri.push([b, c, v]);
    mesh.nbr.push([n_bc, t2, t]);
    mesh.tri.push([c, a, v]);
    mesh.nbr.push([n_ca, t, t1]);
    mesh.link(n_bc, c, b, t1);
    mesh.link(n_ca, a, c, t2);
    mesh.at[a as usize] = t;
    mesh.at[b as usize] = t;
    mesh.at[v as usize] = t;
    mesh.at[c as usize] = t1;
}

/// Split the side `i` of `t` at `v`, strictly between its ends: its two
/// triangles (one on the hull) into four (two).
fn split_side(mesh: &mut Mesh, hull: &mut Hull, t: u32, i: usize, v: u32) {
    let c3 = mesh.tri[t as usize];
    let (a, b, c) = (c3[i], c3[(i + 1) % 3], c3[(i + 2) % 3]);
    let u = mesh.nbr[t as usize][i];
    let n_bc = mesh.nbr[t as usize][(i + 1) % 3];
    let n_ca = mesh.nbr[t as usize][(i + 2) % 3];
    // t = (a, v, c) and t1 = (v, b, c); across the side, u = (b, v, d) and
    // u1 = (v, a, d)
    let t1 = mesh.tri.len() as u32;
    let u1 = if u == NONE { NONE } else { t1 + 1 };
    mesh.tri[t as usize] = [a, v, c];
    mesh.nbr[t as usize] = [u1, t1, n_ca];
    mesh.tri.push([v, b, c]);
    mesh.nbr.push([u, n_bc, t]);
    mesh.link(n_bc, c, b, t1);
    mesh.at[a as usize] = t;
    mesh.at[c as usize] = t;
    mesh.at[v as usize] = t;
    mesh.at[b as usize] = t1;
    if u == NONE {
        hull.next[a as usize] = v;
        hull.prev[v as usize] = a;
        hull.next[v as usize] = b;
        hull.prev[b as usize] = v;
        return;
    }
    let j = mesh.side(u, b, a).expect("the neighbour holds the side");
    let d = mesh.tri[u as usize][(j + 2) % 3];
    let n_ad = mesh.nbr[u as usize][(j + 1) % 3];
    let n_db = mesh.nbr[u as usize][(j + 2) % 3];
    mesh.tri[u as usize] = [b, v, d];
    mesh.nbr[u as usize] = [t1, u1, n_db];
    mesh.tri.push([v, a, d]);
    mesh.nbr.push([t, n_ad, u]);
    mesh.link(n_ad, d, a, u1);
    mesh.at[d as usize] = u;
}

/// Join `v`, outside the hull and strictly beyond its edge on side `i` of
/// `t`, to every hull edge it sees strictly (one chain).
fn attach_outside(mesh: &mut Mesh, hull: &mut Hull, t: u32, i: usize, v: u32, p: &impl Predicates) {
    let sees = |a: u32, b: u32| p.orient(a as usize, b as usize, v as usize) == Sign::Negative;
    let c3 = mesh.tri[t as usize];
    let (mut left, mut right) = (c3[i], c3[(i + 1) % 3]);
    while sees(right, hull.next[right as usize]) {
        right = hull.next[right as usize];
    }
    while sees(hull.prev[left as usize], left) {
        left = hull.prev[left as usize];
    }
    let mut a = left;
    let mut before = NONE;
    while a != right {
        let b = hull.next[a as usize];
        let t = mesh.tri.len() as u32;
        let below = mesh.find(a, b).map_or(NONE, |(tb, _)| tb);
        // (b, a, v): sides b→a (the old hull edge), a→v, v→b
        mesh.tri.push([b, a, v]);
        mesh.nbr.push([below, before, NONE]);
        mesh.link(below, a, b, t);
        if before != NONE {
            mesh.nbr[before as usize][2] = t;
        }
        mesh.at[a as usize] = t;
        mesh.at[b as usize] = t;
        mesh.at[v as usize] = t;
        if a != left {
            hull.next[a as usize] = NONE;
            hull.prev[a as usize] = NONE;
        }
        before = t;
        a = b;
    }
    hull.next[left as usize] = v;
    hull.prev[v as usize] = left;
    hull.next[v as usize] = right;
    hull.prev[right as usize] = v;
}

/// Lawson's flips from the edges in `todo`: an edge that is not a segment
/// nor inside an obstacle ([`Predicates::same_obstacle`]), whose far corner is certainly inside the circle of its near triangle
/// and whose quadrilateral is strictly convex, is flipped.
fn legalize(
    mesh: &mut Mesh,
    mut todo: Vec<(u32, u32)>,
    fixed: &HashSet<(u32, u32), foldhash::fast::FixedState>,
    p: &impl Predicates,
) {
    while let Some((a, b)) = todo.pop() {
        if fixed.contains(&(a.min(b), a.max(b))) || p.same_obstacle(a as usize, b as usize) {
            continue;
        }
        let Some((t, i)) = mesh.find_either(a, b) else {
            continue; // flipped away meanwhile
        };
        let u = mesh.nbr[t as usize][i];
        if u == NONE {
            continue;
        }
        let c = mesh.tri[t as usize];
        let (a, b, c) = (c[i], c[(i + 1) % 3], c[(i + 2) % 3]);
        let j = mesh.side(u, b, a).expect("the neighbour holds the edge");
        let d = mesh.tri[u as usize][(j + 2) % 3];
        let (au, bu, cu, du) = (a as usize, b as usize, c as usize, d as usize);
        if !p.in_circle(au, bu, cu, du) {
            continue;
        }
        if p.orient(cu, au, du) != Sign::Positive || p.orient(du, bu, cu) != Sign::Positive {
            continue;
        }
        mesh.flip(t, i);
        todo.extend([(a, d), (d, b), (b, c), (c, a)]);
    }
}

/// Lawson's flips around a new vertex `v`, from the triangles at `v` in
/// `stack`: the side of each opposite `v` is tested as in [`legalize`] and,
/// when flipped, both new triangles (each with `v` as a corner) are tested
/// again. The sides at `v` need no test: an edge from the new vertex is
/// locally Delaunay once the sides opposite it are. No edge search, no
/// segment set (there are none yet). Empties `stack`.
fn legalize_at(mesh: &mut Mesh, v: u32, stack: &mut Vec<u32>, p: &impl Predicates) {
    while let Some(t) = stack.pop() {
        let c = mesh.tri[t as usize];
        let i = (mesh.corner(t, v) + 1) % 3;
        let u = mesh.nbr[t as usize][i];
        if u == NONE {
            continue;
        }
        let (a, b) = (c[i], c[(i + 1) % 3]);
        let (au, bu, vu) = (a as usize, b as usize, v as usize);
        if p.same_obstacle(au, bu) {
            continue;
        }
        let j = mesh.side(u, b, a).expect("the neighbour holds the edge");
        let du = mesh.tri[u as usize][(j + 2) % 3] as usize;
        if !p.in_circle(au, bu, vu, du) {
            continue;
        }
        if p.orient(vu, au, du) != Sign::Positive || p.orient(du, bu, vu) != Sign::Positive {
            continue;
        }
        // (t, u) = (a, b, v), (b, a, d) become (v, a, d), (d, b, v)
        mesh.flip(t, i);
        stack.extend([t, u]);
    }
}

/// Why a segment was not inserted.
enum Refused {
    /// It crosses a segment (found before any flip).
    Cross,
    /// Any other reason.
    Other(CdtError),
}
use Refused::{Cross, Other};

/// Make `u — v` an edge by flipping the edges that cross it. Returns the
/// new edges that do not cross it (to legalize).
fn insert_segment(
    mesh: &mut Mesh,
    u: u32,
    v: u32,
    fixed: &HashSet<(u32, u32), foldhash::fast::FixedState>,
    p: &impl Predicates,
) -> Result<Vec<(u32, u32)>, Refused> {
    if mesh.find_either(u, v).is_some() {
        return Ok(Vec::new());
    }
    // (an end of the segment is on its line: no predicate asked, which
    // could only answer zero after its filter, exactly)
    let side = |w: u32| {
        if w == u || w == v {
            Sign::Zero
        } else {
            p.orient(u as usize, v as usize, w as usize)
        }
    };
    let on = |w: u32| {
        Other(CdtError::VertexOnSegment(
            u as usize, v as usize, w as usize,
        ))
    };
    // the triangle at `u` whose far side the segment leaves by: its
    // corners after `u` are right (x) and left (y) of `u → v`
    let start = mesh.at[u as usize];
    let mut t = start;
    let mut first = None;
    let mut turned = false;
    loop {
        let i = mesh.corner(t, u);
        let c = mesh.tri[t as usize];
        let (x, y) = (c[(i + 1) % 3], c[(i + 2) % 3]);
        let (sx, sy) = (side(x), side(y));
        match (sx, sy) {
            (Sign::Negative, Sign::Positive) => {
                first = Some((t, (i + 1) % 3));
                break;
            }
            (Sign::Zero, Sign::Positive) => return Err(on(x)),
            (Sign::Negative, Sign::Zero) => return Err(on(y)),
            _ => {}
        }
        // around `u`: clockwise first, then counter-clockwise from the start
        let n = if turned {
            mesh.nbr[t as usize][i]
        } else {
            mesh.nbr[t as usize][(i + 2) % 3]
        };
        if n == start {
            break;
        }
        if n == NONE {
            if turned {
                break;
            }
            turned = true;
            let i0 = mesh.corner(start, u);
            let n0 = mesh.nbr[start as usize][i0];
            if n0 == NONE {
                break;
            }
            t = n0;
            continue;
        }
        t = n;
    }
    let Some((mut t, mut i)) = first else {
        // no triangle at `u` toward `v`: not expected inside the hull
        return Err(Cross);
    };
    // walk along the segment, collecting the crossed edges (x right, y left)
    let mut crossed: VecDeque<(u32, u32)> = VecDeque::new();
    loop {
        let c = mesh.tri[t as usize];
        let (x, y) = (c[i], c[(i + 1) % 3]);
        if fixed.contains(&(x.min(y), x.max(y))) {
            return Err(Cross);
        }
        crossed.push_back((x, y));
        let w_t = mesh.nbr[t as usize][i];
        if w_t == NONE {
            return Err(Cross); // not expected: the hull is convex
        }
        let j = mesh.side(w_t, y, x).expect("the neighbour holds the edge");
        let w = mesh.tri[w_t as usize][(j + 2) % 3];
        if w == v {
            break;
        }
        t = w_t;
        match side(w) {
            // w right of the segment: leave by w → y (side j + 2)
            Sign::Negative => i = (j + 2) % 3,
            // w left of it: leave by x → w (side j + 1)
            Sign::Positive => i = (j + 1) % 3,
            Sign::Zero => return Err(on(w)),
        }
    }
    // Sloan: flip each crossing edge whose quadrilateral is strictly
    // convex; an edge that still crosses goes back in the queue
    let mut fresh = Vec::new();
    let limit = 16 * crossed.len() * crossed.len() + 64;
    let mut steps = 0;
    while let Some((a, b)) = crossed.pop_front() {
        steps += 1;
        if steps > limit {
            // not expected with exact predicates and no vertex on the
            // segment; the mesh is valid but the caller cannot use it
            return Err(Other(CdtError::Stuck(u as usize, v as usize)));
        }
        let (t, i) = mesh
            .find_either(a, b)
            .expect("a crossing edge stays until it is flipped");
        let nb = mesh.nbr[t as usize][i];
        let c3 = mesh.tri[t as usize];
        let (a, b, c) = (c3[i], c3[(i + 1) % 3], c3[(i + 2) % 3]);
        let j = mesh.side(nb, b, a).expect("the neighbour holds the edge");
        let d = mesh.tri[nb as usize][(j + 2) % 3];
        let convex = p.orient(c as usize, a as usize, d as usize) == Sign::Positive
            && p.orient(d as usize, b as usize, c as usize) == Sign::Positive;
        if !convex {
            crossed.push_back((a, b));
            continue;
        }
        mesh.flip(t, i);
        let (sc, sd) = (side(c), side(d));
        let crosses = sc != Sign::Zero && sd != Sign::Zero && sc != sd;
        if crosses {
            crossed.push_back((c, d));
        } else if (c.min(d), c.max(d)) != (u.min(v), u.max(v)) {
            fresh.push((c, d));
        }
    }
    Ok(fresh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// Integer points with exact predicates (i128), and the exact
    /// circle test.
    struct Ints(Vec<[i64; 2]>);

    impl Predicates for Ints {
        fn cmp(&self, a: usize, b: usize) -> Ordering {
            self.0[a].cmp(&self.0[b])
        }
        fn orient(&self, a: usize, b: usize, c: usize) -> Sign {
            let [a, b, c] = [a, b, c].map(|i| self.0[i].map(|x| x as i128));
            let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            sign(d)
        }
        fn in_circle(&self, a: usize, b: usize, c: usize, d: usize) -> bool {
            let o = self.0[d].map(|x| x as i128);
            let r = [a, b, c].map(|i| {
                let x = self.0[i][0] as i128 - o[0];
                let y = self.0[i][1] as i128 - o[1];
                [x, y, x * x + y * y]
            });
            let det = r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0])
                + r[1][2] * (r[2][0] * r[0][1] - r[2][1] * r[0][0])
                + r[2][2] * (r[0][0] * r[1][1] - r[0][1] * r[1][0]);
            det > 0
        }
    }

    fn sign(d: i128) -> Sign {
        match d.cmp(&0) {
            Ordering::Less => Sign::Negative,
            Ordering::Equal => Sign::Zero,
            Ordering::Greater => Sign::Positive,
        }
    }

    /// Every triangle counter-clockwise; the triangles tile the hull (the
    /// areas add up to the hull's, and every interior edge is shared by
    /// two triangles in opposite directions); every segment an edge;
    /// Delaunay where no segment blocks.
    fn check(pts: &[[i64; 2]], segments: &[[usize; 2]], tris: &[[usize; 3]], delaunay: bool) {
        let p = Ints(pts.to_vec());
        let mut directed = HashSet::new();
        let mut area2: i128 = 0;
        for t in tris {
            assert_eq!(p.orient(t[0], t[1], t[2]), Sign::Positive, "{t:?}");
            let [a, b, c] = t.map(|i| pts[i].map(|x| x as i128));
            area2 += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            for i in 0..3 {
                assert!(directed.insert((t[i], t[(i + 1) % 3])), "edge twice");
            }
        }
        // the hull's area (the generators' strict hull)
        let hull: Vec<[i128; 2]> = crate::gen::hull_i64(pts.to_vec())
            .iter()
            .map(|q| q.map(|x| x as i128))
            .collect();
        let mut hull2 = 0;
        for i in 0..hull.len() {
            let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
            hull2 += a[0] * b[1] - a[1] * b[0];
        }
        assert_eq!(area2, hull2, "the triangles tile the hull");
        // every vertex is a corner
        let mut seen = vec![false; pts.len()];
        for t in tris {
            for &v in t {
                seen[v] = true;
            }
        }
        assert!(seen.iter().all(|&x| x), "every vertex is a corner");
        for &[u, v] in segments {
            assert!(
                directed.contains(&(u, v)) || directed.contains(&(v, u)),
                "segment {u}-{v} is an edge"
            );
        }
        if delaunay {
            let fixed: HashSet<(usize, usize)> = segments
                .iter()
                .map(|&[u, v]| (u.min(v), u.max(v)))
                .collect();
            let by_edge: std::collections::HashMap<(usize, usize), usize> = tris
                .iter()
                .enumerate()
                .flat_map(|(k, t)| (0..3).map(move |i| ((t[i], t[(i + 1) % 3]), k)))
                .collect();
            for t in tris {
                for i in 0..3 {
                    let (a, b, c) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
                    if fixed.contains(&(a.min(b), a.max(b))) {
                        continue;
                    }
                    if let Some(&k) = by_edge.get(&(b, a)) {
                        let d = *tris[k].iter().find(|&&x| x != a && x != b).unwrap();
                        assert!(!p.in_circle(a, b, c, d), "locally Delaunay");
                    }
                }
            }
        }
    }

    /// The Hilbert key by table, four bits at a time, is the textbook
    /// one computed a bit at a time, on the grid's corners and edges and
    /// on random cells; and on a 64 × 64 grid of cells, consecutive keys
    /// are neighbouring cells.
    #[test]
    fn the_hilbert_key_by_table_is_the_bitwise_one() {
        fn bitwise(mut x: u32, mut y: u32) -> u64 {
            const SIDE: u32 = 1 << 16;
            let mut d = 0u64;
            let mut s = SIDE / 2;
            while s > 0 {
                let rx = u64::from(x & s != 0);
                let ry = u64::from(y & s != 0);
                d += u64::from(s) * u64::from(s) * ((3 * rx) ^ ry);
                if ry == 0 {
                    if rx == 1 {
                        x = SIDE - 1 - x;
                        y = SIDE - 1 - y;
                    }
                    std::mem::swap(&mut x, &mut y);
                }
                s /= 2;
            }
            d
        }
        let mut rng = crate::rng::Rng::new(17);
        let edges = [
            0, 1, 2, 15, 16, 255, 256, 4095, 4096, 32767, 32768, 65534, 65535,
        ];
        let mut cells: Vec<(u32, u32)> = edges
            .iter()
            .flat_map(|&x| edges.iter().map(move |&y| (x, y)))
            .collect();
        cells.extend((0..100_000).map(|_| (rng.below(1 << 16) as u32, rng.below(1 << 16) as u32)));
        for (x, y) in cells {
            assert_eq!(hilbert(x, y), bitwise(x, y), "cell ({x}, {y})");
        }
        // (consecutive keys are neighbouring cells: a curve)
        let mut at = vec![(0u32, 0u32); 1 << 12];
        for x in 0..64 {
            for y in 0..64 {
                let d = hilbert(x << 10, y << 10) >> 20;
                at[d as usize] = (x, y);
            }
        }
        for w in at.windows(2) {
            let (a, b) = (w[0], w[1]);
            assert_eq!(a.0.abs_diff(b.0) + a.1.abs_diff(b.1), 1, "{a:?} then {b:?}");
        }
    }

    /// Two polygons of 3000 vertices each (regular ones rounded to the
    /// grid, on circles of radius 10^7) facing each other across a gap of
    /// about 3: the number of circle tests stays linear in the vertex
    /// count (inserted along a line, they numbered in its square), and the
    /// result is a valid constrained triangulation.
    #[test]
    fn two_large_polygons_across_a_small_gap_take_linear_work() {
        struct Counting {
            ints: Ints,
            body: Vec<usize>,
            circle_tests: std::cell::Cell<u64>,
        }
        impl Predicates for Counting {
            fn cmp(&self, a: usize, b: usize) -> Ordering {
                self.ints.cmp(a, b)
            }
            fn orient(&self, a: usize, b: usize, c: usize) -> Sign {
                self.ints.orient(a, b, c)
            }
            fn in_circle(&self, a: usize, b: usize, c: usize, d: usize) -> bool {
                self.circle_tests.set(self.circle_tests.get() + 1);
                self.ints.in_circle(a, b, c, d)
            }
            fn same_obstacle(&self, a: usize, b: usize) -> bool {
                self.body[a] == self.body[b]
            }
            fn position_hint(&self, a: usize) -> Option<[f64; 2]> {
                Some(self.ints.0[a].map(|x| x as f64))
            }
        }
        let r = 1e7;
        let ring = |cx: i64, cy: i64| {
            let pts: Vec<[i64; 2]> = (0..3000)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / 3000.0;
                    [
                        cx + (r * a.cos()).round() as i64,
                        cy + (r * a.sin()).round() as i64,
                    ]
                })
                .collect();
            crate::gen::hull_i64(pts)
        };
        let (first, second) = (ring(0, 0), ring(14_142_200, 14_142_200));
        let mut pts = first.clone();
        pts.extend(&second);
        let body: Vec<usize> = (0..pts.len())
            .map(|i| usize::from(i >= first.len()))
            .collect();
        let mut segments = Vec::new();
        for (base, n) in [(0, first.len()), (first.len(), second.len())] {
            segments.extend((0..n).map(|i| [base + i, base + (i + 1) % n]));
        }
        let p = Counting {
            ints: Ints(pts.clone()),
            body,
            circle_tests: std::cell::Cell::new(0),
        };
        let tris = triangulate(pts.len(), &segments, &p).expect("a triangulation");
        check(&pts, &segments, &tris, false);
        let n = pts.len() as u64;
        let tests = p.circle_tests.get();
        assert!(tests <= 20 * n, "{tests} circle tests for {n} vertices");
    }

    #[test]
    fn random_points_are_delaunay() {
        let mut rng = Rng::new(7);
        for n in [3, 4, 5, 10, 50, 300] {
            let mut pts: Vec<[i64; 2]> = Vec::new();
            while pts.len() < n {
                let q = [rng.below(1000) as i64, rng.below(1000) as i64];
                if !pts.contains(&q) {
                    pts.push(q);
                }
            }
            let p = Ints(pts.clone());
            match triangulate(n, &[], &p) {
                Ok(tris) => check(&pts, &[], &tris, true),
                Err(CdtError::Collinear) => {}
                Err(e) => panic!("{e}"),
            }
        }
    }

    #[test]
    fn grids_and_collinear_starts() {
        // a grid: many collinear and cocircular points
        let mut pts = Vec::new();
        for x in 0..7 {
            for y in 0..5 {
                pts.push([x * 3, y * 3]);
            }
        }
        let p = Ints(pts.clone());
        let tris = triangulate(pts.len(), &[], &p).unwrap();
        check(&pts, &[], &tris, true);
        assert_eq!(tris.len(), 2 * 6 * 4);
        // a long collinear start, then a point off the line
        let mut pts: Vec<[i64; 2]> = (0..10).map(|i| [i, 2 * i]).collect();
        pts.push([20, -3]);
        pts.push([-5, 40]);
        let p = Ints(pts.clone());
        let tris = triangulate(pts.len(), &[], &p).unwrap();
        check(&pts, &[], &tris, true);
        // all collinear, coincident
        let p = Ints(vec![[0, 0], [1, 1], [2, 2]]);
        assert_eq!(triangulate(3, &[], &p), Err(CdtError::Collinear));
        let p = Ints(vec![[0, 0], [1, 1], [0, 0], [4, 0]]);
        assert!(matches!(
            triangulate(4, &[], &p),
            Err(CdtError::Coincident(_, _))
        ));
        // coincident vertices are reported as such wherever they come in
        // the insertion order: all collinear, two alone, or among many
        let p = Ints(vec![[0, 0], [1, 1], [2, 2], [1, 1]]);
        assert_eq!(triangulate(4, &[], &p), Err(CdtError::Coincident(1, 3)));
        let p = Ints(vec![[5, 5], [5, 5]]);
        assert!(matches!(
            triangulate(2, &[], &p),
            Err(CdtError::Coincident(_, _))
        ));
        let grid: Vec<[i64; 2]> = (0..40).map(|i| [(i * 7) % 11, (i * 5) % 13]).collect();
        for twin in [0, 17, 39] {
            let mut pts = grid.clone();
            pts.push(pts[twin]);
            let p = Ints(pts.clone());
            match triangulate(pts.len(), &[], &p) {
                Err(CdtError::Coincident(a, b)) => assert_eq!(pts[a], pts[b], "{twin}"),
                other => panic!("{twin}: {other:?}"),
            }
        }
    }

    /// Random disjoint convex polygons (boxes cut at the corners), their
    /// edges as segments.
    #[test]
    fn polygon_edges_are_edges() {
        let mut rng = Rng::new(11);
        for round in 0..40 {
            let mut pts: Vec<[i64; 2]> = Vec::new();
            let mut segs = Vec::new();
            let cells = 2 + round % 5;
            for cx in 0..cells {
                for cy in 0..cells {
                    if rng.below(4) == 0 {
                        continue;
                    }
                    // a long thin or a squat octagon inside the cell
                    let (x0, y0) = (cx as i64 * 100, cy as i64 * 100);
                    let w = 10 + rng.below(85) as i64;
                    let h = 2 + rng.below(90) as i64;
                    let c = 1 + rng.below(1.max(w.min(h) as u64 / 3)) as i64;
                    let ring = [
                        [x0 + c, y0],
                        [x0 + w - c, y0],
                        [x0 + w, y0 + c],
                        [x0 + w, y0 + h - c],
                        [x0 + w - c, y0 + h],
                        [x0 + c, y0 + h],
                        [x0, y0 + h - c],
                        [x0, y0 + c],
                    ];
                    let mut ring: Vec<[i64; 2]> = ring.to_vec();
                    ring.dedup();
                    let base = pts.len();
                    let k = ring.len();
                    pts.extend(ring);
                    for i in 0..k {
                        segs.push([base + i, base + (i + 1) % k]);
                    }
                }
            }
            if pts.len() < 3 {
                continue;
            }
            let p = Ints(pts.clone());
            let tris = triangulate(pts.len(), &segs, &p).unwrap();
            check(&pts, &segs, &tris, true);
        }
    }

    #[test]
    fn long_segments_across_many_triangles() {
        // two long horizontal bars with a cloud of points between and
        // around them
        let mut rng = Rng::new(3);
        let mut pts: Vec<[i64; 2]> = vec![[0, 0], [1000, 1], [1000, 3], [0, 2]];
        let mut segs = vec![[0, 1], [1, 2], [2, 3], [3, 0]];
        pts.extend([[5, 500], [990, 499], [990, 502], [5, 503]]);
        segs.extend([[4, 5], [5, 6], [6, 7], [7, 4]]);
        while pts.len() < 200 {
            let q = [rng.below(1000) as i64, 5 + rng.below(490) as i64];
            if !pts.contains(&q) {
                pts.push(q);
            }
        }
        let p = Ints(pts.clone());
        let tris = triangulate(pts.len(), &segs, &p).unwrap();
        check(&pts, &segs, &tris, true);
    }

    #[test]
    fn degenerate_segments_are_errors() {
        // a vertex on a segment
        let pts = vec![[0, 0], [4, 0], [2, 0], [2, 3]];
        let p = Ints(pts);
        assert_eq!(
            triangulate(4, &[[0, 1]], &p),
            Err(CdtError::VertexOnSegment(0, 1, 2))
        );
        // crossing segments
        let pts = vec![[0, 0], [4, 4], [0, 4], [4, 0], [9, 9]];
        let p = Ints(pts);
        assert_eq!(
            triangulate(5, &[[0, 1], [2, 3], [1, 4]], &p),
            Err(CdtError::Crossing(vec![[2, 3]]))
        );
    }
}
