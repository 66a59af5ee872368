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
//! The steps: a sweep in lexicographic order builds a first triangulation
//! (each vertex joined to the hull edges it sees); Lawson flips make it
//! Delaunay where the circle test is certain; each segment that is not yet
//! an edge is inserted by flipping the edges that cross it (Sloan's method:
//! an edge whose quadrilateral is strictly convex is flipped, the others
//! wait their turn); a last round of flips restores the Delaunay property
//! around the new edges, never flipping a segment.
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
    let mut mesh = sweep(n, p)?;
    let fixed: HashSet<(u32, u32), foldhash::fast::FixedState> = HashSet::default();
    let all: Vec<(u32, u32)> = interior_edges(&mesh);
    legalize(&mut mesh, all, &fixed, p);
    let mut fixed = fixed;
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
    Ok(mesh.tri.iter().map(|t| t.map(|v| v as usize)).collect())
}

/// Every interior edge once.
fn interior_edges(mesh: &Mesh) -> Vec<(u32, u32)> {
    let mut out = Vec::with_capacity(3 * mesh.tri.len() / 2);
    for (t, c) in mesh.tri.iter().enumerate() {
        for i in 0..3 {
            let u = mesh.nbr[t][i];
            if u != NONE && (t as u32) < u {
                out.push((c[i], c[(i + 1) % 3]));
            }
        }
    }
    out
}

/// The sweep: vertices in lexicographic order, each joined to the hull
/// edges it sees strictly.
fn sweep(n: usize, p: &impl Predicates) -> Result<Mesh, CdtError> {
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| p.cmp(a, b));
    for w in order.windows(2) {
        if p.cmp(w[0], w[1]) == Ordering::Equal {
            return Err(CdtError::Coincident(w[0], w[1]));
        }
    }
    if n < 3 {
        return Err(CdtError::Collinear);
    }
    // the collinear start: order[0..k] on one line, in order along it
    let mut k = 2;
    while k < n && p.orient(order[0], order[1], order[k]) == Sign::Zero {
        k += 1;
    }
    if k == n {
        return Err(CdtError::Collinear);
    }
    let mut mesh = Mesh {
        tri: Vec::with_capacity(2 * n),
        nbr: Vec::with_capacity(2 * n),
        at: vec![NONE; n],
    };
    // the hull, counter-clockwise, and for each hull edge `v → next[v]`
    // the triangle holding it
    let mut next = vec![NONE; n];
    let mut prev = vec![NONE; n];
    let mut edge_tri = vec![NONE; n];
    let apex = order[k] as u32;
    let ccw = p.orient(order[0], order[1], order[k]) == Sign::Positive;
    for i in 0..k - 1 {
        let (x, y) = (order[i] as u32, order[i + 1] as u32);
        let t = mesh.tri.len() as u32;
        let (c, n_prev_side, n_next_side) = if ccw {
            // (x, y, apex): sides x→y (hull), y→apex (next fan), apex→x (previous)
            ([x, y, apex], 2, 1)
        } else {
            // (y, x, apex): sides y→x (hull), x→apex (previous), apex→y (next)
            ([y, x, apex], 1, 2)
        };
        let mut nb = [NONE; 3];
        if i > 0 {
            nb[n_prev_side] = t - 1;
        }
        if i + 2 < k {
            nb[n_next_side] = t + 1;
        }
        mesh.tri.push(c);
        mesh.nbr.push(nb);
        mesh.at[x as usize] = t;
        mesh.at[y as usize] = t;
        mesh.at[apex as usize] = t;
        next[c[0] as usize] = c[1];
        prev[c[1] as usize] = c[0];
        edge_tri[c[0] as usize] = t;
    }
    let (first, last) = (order[0] as u32, order[k - 1] as u32);
    let last_t = mesh.tri.len() as u32 - 1;
    if ccw {
        // hull: order[0] → … → order[k−1] → apex → order[0]
        next[last as usize] = apex;
        prev[apex as usize] = last;
        edge_tri[last as usize] = last_t;
        next[apex as usize] = first;
        prev[first as usize] = apex;
        edge_tri[apex as usize] = 0;
    } else {
        // hull: order[k−1] → … → order[0] → apex → order[k−1]
        next[first as usize] = apex;
        prev[apex as usize] = first;
        edge_tri[first as usize] = 0;
        next[apex as usize] = last;
        prev[last as usize] = apex;
        edge_tri[apex as usize] = last_t;
    }
    let sees = |a: u32, b: u32, v: usize| p.orient(a as usize, b as usize, v) == Sign::Negative;
    let mut q = apex;
    for &v in &order[k + 1..] {
        // the hull edges `v` sees form one chain; the last vertex added
        // (the lexicographic maximum so far) ends one of them
        let mut right = q;
        while sees(right, next[right as usize], v) {
            right = next[right as usize];
        }
        let mut left = q;
        while sees(prev[left as usize], left, v) {
            left = prev[left as usize];
        }
        if left == right {
            // not expected; find a seen edge anywhere on the hull
            let mut x = q;
            loop {
                if sees(x, next[x as usize], v) {
                    break;
                }
                x = next[x as usize];
                if x == q {
                    return Err(CdtError::Collinear);
                }
            }
            left = x;
            right = next[x as usize];
            while sees(right, next[right as usize], v) {
                right = next[right as usize];
            }
            while sees(prev[left as usize], left, v) {
                left = prev[left as usize];
            }
        }
        let v32 = v as u32;
        let mut a = left;
        let mut before = NONE;
        let first_new = mesh.tri.len() as u32;
        while a != right {
            let b = next[a as usize];
            let t = mesh.tri.len() as u32;
            let below = edge_tri[a as usize];
            // (b, a, v): sides b→a (the old hull edge), a→v, v→b
            mesh.tri.push([b, a, v32]);
            mesh.nbr.push([below, before, NONE]);
            mesh.link(below, a, b, t);
            if before != NONE {
                mesh.nbr[before as usize][2] = t;
            }
            mesh.at[a as usize] = t;
            mesh.at[b as usize] = t;
            mesh.at[v] = t;
            if a != left {
                next[a as usize] = NONE;
                prev[a as usize] = NONE;
            }
            before = t;
            a = b;
        }
        let last_new = mesh.tri.len() as u32 - 1;
        next[left as usize] = v32;
        prev[v] = left;
        edge_tri[left as usize] = first_new;
        next[v] = right;
        prev[right as usize] = v32;
        edge_tri[v] = last_new;
        q = v32;
    }
    Ok(mesh)
}

/// Lawson's flips from the edges in `todo`: an edge that is not a segment,
/// whose far corner is certainly inside the circle of its near triangle
/// and whose quadrilateral is strictly convex, is flipped.
fn legalize(
    mesh: &mut Mesh,
    mut todo: Vec<(u32, u32)>,
    fixed: &HashSet<(u32, u32), foldhash::fast::FixedState>,
    p: &impl Predicates,
) {
    while let Some((a, b)) = todo.pop() {
        if fixed.contains(&(a.min(b), a.max(b))) {
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
    let side = |w: u32| p.orient(u as usize, v as usize, w as usize);
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
