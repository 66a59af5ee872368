//! The replicated edge array of one body polygon (design note §B.1).

use super::HierarchyError;
use std::f64::consts::PI;

use super::exposed::Exposed;
use super::levels;
use crate::geom::{cross_sign_wide, BodyPolygon, Point};
use crate::motion::{Frame, LinearPoint};
use crate::num::{Int, Interval, Rational, Sign};

/// One entry of an [`EdgeArray`]: the supporting line `nx·x + ny·y = c` of
/// the polygon in the body's integer grid (the polygon lies in
/// `nx·x + ny·y <= c`), and its base segment from base vertex `start` to base
/// vertex `end` (`start == end` for a zero-length entry).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// Outward normal, x (integer; not normalized).
    pub nx: Int,
    /// Outward normal, y.
    pub ny: Int,
    /// Offset: `nx·X + ny·Y` for the base vertices `(X, Y)` of the entry.
    pub c: Int,
    /// Base vertex where the base segment starts.
    pub start: usize,
    /// Base vertex where the base segment ends: `start + 1 (mod n)` for a
    /// real edge, `start` for a zero-length entry.
    pub end: usize,
}

impl Entry {
    /// Whether the base segment has length zero (an inserted copy of a vertex).
    pub fn is_zero_length(&self) -> bool {
        self.start == self.end
    }

    /// The sign of `nx·x + ny·y − c` at the integer grid point `(x, y)`:
    /// negative strictly inside the half-plane, zero on the line.
    pub fn side(&self, x: &Int, y: &Int) -> Sign {
        Sign::of(&(&self.nx * x + &self.ny * y - &self.c))
    }

    /// [`Entry::side`] for a point in homogeneous grid coordinates (`w > 0`).
    pub fn side_hom(&self, p: &HomPoint) -> Sign {
        Sign::of(&(&self.nx * &p.x + &self.ny * &p.y - &self.c * &p.w))
    }
}

/// A body-frame point in homogeneous integer coordinates on the body
/// polygon's grid: the point `(x/w, y/w)·2^exp` with `w > 0`, where `exp` is
/// [`BodyPolygon::exp`]. Not reduced (no gcd is taken).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HomPoint {
    /// x numerator.
    pub x: Int,
    /// y numerator.
    pub y: Int,
    /// Positive common denominator.
    pub w: Int,
}

impl HomPoint {
    /// Base vertex `v` of `body` with `w = 1`.
    pub fn vertex(body: &BodyPolygon, v: usize) -> HomPoint {
        let (x, y) = body.int_vertex(v);
        HomPoint {
            x: x.clone(),
            y: y.clone(),
            w: Int::ONE,
        }
    }

    /// Whether this is exactly base vertex `v` of `body`.
    pub fn is_vertex(&self, body: &BodyPolygon, v: usize) -> bool {
        let (x, y) = body.int_vertex(v);
        self.x == x * &self.w && self.y == y * &self.w
    }

    /// The exact body-frame point, for a grid exponent `exp`
    /// ([`BodyPolygon::exp`]).
    pub fn to_point(&self, exp: i64) -> Point {
        let s = Rational::from_dyadic(Int::ONE, exp);
        Point {
            x: Rational::new(self.x.clone(), self.w.clone()).mul(&s),
            y: Rational::new(self.y.clone(), self.w.clone()).mul(&s),
        }
    }

    /// The moving world point: see [`Frame::homogeneous`]. `frame` must be
    /// the frame of the body polygon whose grid this point is on.
    pub fn moving(&self, frame: &Frame) -> LinearPoint {
        frame.homogeneous(&self.x, &self.y, &self.w)
    }
}

/// The replicated edge array of a body polygon (§B.1): `M = 2^h` supporting
/// lines in counter-clockwise order of their normals.
///
/// Layout: entry 0 is real edge 0; after real edge `i` (from vertex `i` to
/// `i + 1`) come the zero-length entries inserted at vertex `i + 1`, then real
/// edge `i + 1`; the zero-length entries at vertex 0 close the array. Every
/// real edge appears exactly once, in order. With no zero-length entry
/// (`M = n`, e.g. a regular `2^k`-gon) entry `k` is real edge `k`.
///
/// Invariants (checked exactly by [`EdgeArray::check`]):
/// - every line supports the polygon: its base vertices are on it and the
///   polygon is in its half-plane `<= c`;
/// - consecutive normals (cyclically) turn counter-clockwise by an angle in
///   `(0, π/2)`, and the array winds exactly once;
/// - `n <= M <= 4n`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EdgeArray {
    h: u32,
    n: usize,
    entries: Vec<Entry>,
    /// Enclosures of each entry's `nx, ny, c` (the filter's input,
    /// converted once).
    ivs: Enclosures,
    edge_entry: Vec<usize>,
    coarsest_level: u32,
}

/// The entries' coefficients as f64 enclosures: derived from the entries,
/// so two arrays with equal entries compare equal whatever these hold.
#[derive(Clone, Debug)]
struct Enclosures(Vec<[Interval; 3]>);

impl PartialEq for Enclosures {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Eq for Enclosures {}

/// `(x, y) · (u, v)`.
fn dot(a: (&Int, &Int), b: (&Int, &Int)) -> Int {
    a.0 * b.0 + a.1 * b.1
}

/// `(x, y) × (u, v)`.
fn cross(a: (&Int, &Int), b: (&Int, &Int)) -> Int {
    a.0 * b.1 - a.1 * b.0
}

/// Whether the counter-clockwise turn from normal `a` to normal `b` is in
/// `(0, π/2)`: `a × b > 0` and `a · b > 0`, exactly.
fn acute(a: (&Int, &Int), b: (&Int, &Int)) -> bool {
    let exact = || cross(a, b) > Int::ZERO && dot(a, b) > Int::ZERO;
    if let (Some(p), Some(q)) = (narrow(a), narrow(b)) {
        // (a · b = p0·q0 − (−p1)·q1)
        let acute = cross_sign_wide(p.0, p.1, q.0, q.1) == Sign::Positive
            && cross_sign_wide(p.0, -p.1, q.1, q.0) == Sign::Positive;
        debug_assert_eq!(acute, exact(), "the i128 turn from {a:?} to {b:?}");
        return acute;
    }
    exact()
}

/// `a × b > 0`, exactly ([`cross`]'s sign).
fn cross_positive(a: (&Int, &Int), b: (&Int, &Int)) -> bool {
    if let (Some(p), Some(q)) = (narrow(a), narrow(b)) {
        let positive = cross_sign_wide(p.0, p.1, q.0, q.1) == Sign::Positive;
        debug_assert_eq!(positive, cross(a, b) > Int::ZERO, "the i128 cross product");
        return positive;
    }
    cross(a, b) > Int::ZERO
}

/// The vector as `i128`s where both components are below `2^126` in
/// magnitude, as [`cross_sign_wide`] takes them.
fn narrow(p: (&Int, &Int)) -> Option<(i128, i128)> {
    let (x, y) = (i128::try_from(p.0).ok()?, i128::try_from(p.1).ok()?);
    ((x.unsigned_abs() | y.unsigned_abs()) < 1 << 126).then_some((x, y))
}

fn bit_len(v: &Int) -> usize {
    use dashu_base::{BitTest, UnsignedAbs};
    v.clone().unsigned_abs().bit_len()
}

/// A unit vector approximately along the integer vector `(x, y) ≠ 0`
/// (scaled down first if the integers do not fit a double).
fn approx_unit(x: &Int, y: &Int) -> [f64; 2] {
    let bits = bit_len(x).max(bit_len(y));
    let (fx, fy) = if bits > 1000 {
        let s = bits - 1000;
        ((x >> s).to_f64().value(), (y >> s).to_f64().value())
    } else {
        (x.to_f64().value(), y.to_f64().value())
    };
    let r = fx.hypot(fy);
    [fx / r, fy / r]
}

fn as_pair(p: &(Int, Int)) -> (&Int, &Int) {
    (&p.0, &p.1)
}

/// How many entries each vertex gets (`r_v >= 1`: the real edge that starts
/// there plus `r_v − 1` zero-length copies before it), and the total `M`.
///
/// The counts are *choices*, not geometric decisions: they are made in
/// `f64` from approximate exterior angles and only affect constants (how
/// evenly the normals are spread), never correctness; the one exact input is
/// `acute[v]` (exterior angle below `π/2`), which forces a copy where the
/// array invariant needs one.
///
/// Rule (§B.1 with `n' = max(n, 5)` so that every piece stays below `π/2`
/// even for triangles and quadrilaterals): `r_v = max(1, ⌈α_v·n'/2π⌉)`
/// (with a slack of `1/100` so that regular polygons, whose angles are
/// `2π/n` only up to the rounding of their coordinates, are not replicated),
/// so `Σ r_v <= n' + n` and every piece turns by at most `1.0101·2π/n'`; then
/// `M = 2^⌈log2 Σ r_v⌉ <= 4n`, and the `M − Σ r_v` padding entries go first in
/// proportion to `α_v`, the rest one each to the vertices with the largest
/// gap `α_v/r_v`. `O(n)` (expected, for the selection).
/// See [`replication_counts`]: `r_v = ⌈α_v·n'/2π − SLACK⌉`, so each piece
/// turns by at most `2π/n' / (1 − SLACK)`.
const SLACK: f64 = 0.01;

fn replication_counts(alpha: &[f64], acute_at: &[bool]) -> (Vec<usize>, usize) {
    let n = alpha.len();
    let n_eff = n.max(5);
    let total: f64 = alpha.iter().sum();
    let mut r: Vec<usize> = (0..n)
        .map(|v| {
            let x = alpha[v] / total * n_eff as f64;
            let c = ((x - SLACK).ceil().max(1.0)) as usize;
            if acute_at[v] {
                c
            } else {
                c.max(2)
            }
        })
        .collect();
    // Σ r_v <= n' + n holds in exact arithmetic (each r_v <= α_v·n'/2π + 1,
    // and the forced copies only repair f64 error); clamp anyway so that the
    // bound M <= 4n never depends on rounding.
    let cap = n + n_eff;
    let mut m: usize = r.iter().sum();
    for v in 0..n {
        let floor = if acute_at[v] { 1 } else { 2 };
        while m > cap && r[v] > floor {
            r[v] -= 1;
            m -= 1;
        }
    }
    let big_m = m.next_power_of_two();
    let mut left = big_m - m;
    if left > 0 {
        let l = left as f64;
        for v in 0..n {
            let e = ((l * alpha[v] / total).floor() as usize).min(left);
            r[v] += e;
            left -= e;
        }
        while left > 0 {
            let k = left.min(n);
            let mut idx: Vec<usize> = (0..n).collect();
            if k < n {
                let gap = |v: usize| alpha[v] / r[v] as f64;
                idx.select_nth_unstable_by(k - 1, |&a, &b| gap(b).total_cmp(&gap(a)));
            }
            for &v in &idx[..k] {
                r[v] += 1;
            }
            left -= k;
        }
    }
    (r, big_m)
}

/// The normals of `count >= 1` zero-length entries at a vertex whose edge
/// normals are `a` (before) and `b` (after): strictly inside the cone from
/// `a` to `b`, strictly increasing, every step from `a` through them to `b`
/// turning by less than `π/2` (all checked exactly).
///
/// First choice: integer roundings of `K·(cos φ_j, sin φ_j)` for the evenly
/// spaced angles `φ_j` (chosen in `f64`: not a geometric decision; `K >= 256·n'`
/// keeps the rounding far below the spacing, which is at least about
/// `1/n'`). If the exact check rejects them (only conceivable at vertices with
/// a tiny exterior angle), [`exact_fallback_normals`] is used instead.
fn copy_normals(
    a: &(Int, Int),
    b: &(Int, Int),
    ua: [f64; 2],
    alpha: f64,
    count: usize,
    scale: f64,
) -> Vec<(Int, Int)> {
    let phi = ua[1].atan2(ua[0]);
    let step = alpha / (count + 1) as f64;
    let cands: Vec<(Int, Int)> = (1..=count)
        .map(|j| {
            let (s, c) = (phi + step * j as f64).sin_cos();
            (
                Int::from((scale * c).round() as i64),
                Int::from((scale * s).round() as i64),
            )
        })
        .collect();
    if valid_fan(a, &cands, b) {
        cands
    } else {
        exact_fallback_normals(a, b, count)
    }
}

/// Whether `a, mids..., b` is a fan of normals strictly inside the cone
/// `(a, b)` (itself less than `π`), strictly increasing, each step acute.
fn valid_fan(a: &(Int, Int), mids: &[(Int, Int)], b: &(Int, Int)) -> bool {
    let mut prev = as_pair(a);
    for m in mids {
        let m = as_pair(m);
        if !(acute(prev, m) && cross_positive(as_pair(a), m) && cross_positive(m, as_pair(b))) {
            return false;
        }
        prev = m;
    }
    acute(prev, as_pair(b))
}

/// `count >= 1` normals with the guarantees of [`copy_normals`], from exact
/// integer combinations only:
/// - exterior angle below `π/2` (`a·b > 0`): the note's `(r−j)·a + j·b`
///   (`r = count + 1`): positive combinations, so inside the cone and
///   increasing (consecutive cross products are `r·(a × b) > 0`);
/// - otherwise first `c = rot90(a − b)`: `a × c = |a|² − a·b > 0`,
///   `c × b = |b|² − a·b > 0`, `a·c = c·b = a × b > 0`, so both steps are
///   acute; the other copies are `(count−j)·a + j·c` inside `(a, c)`.
fn exact_fallback_normals(a: &(Int, Int), b: &(Int, Int), count: usize) -> Vec<(Int, Int)> {
    let combo = |p: usize, u: &(Int, Int), q: usize, v: &(Int, Int)| {
        let (p, q) = (Int::from(p), Int::from(q));
        (&p * &u.0 + &q * &v.0, &p * &u.1 + &q * &v.1)
    };
    if dot(as_pair(a), as_pair(b)) > Int::ZERO {
        (1..=count).map(|j| combo(count + 1 - j, a, j, b)).collect()
    } else {
        let c = (&b.1 - &a.1, &a.0 - &b.0); // rot90(a − b) = (−(a−b).y, (a−b).x)
        let mut out: Vec<(Int, Int)> = (1..count).map(|j| combo(count - j, a, j, &c)).collect();
        out.push(c);
        out
    }
}

/// The entry of the line with outward normal `(nx, ny)` through base
/// vertex `start` of `body` (base segment `start` to `end`), with the
/// enclosures of its normal and offset. Where the normal and the vertex's
/// coordinates are `i128` and the offset `c = nx·x + ny·y` is too (checked:
/// an overflow takes the other way), `c` and the enclosures come from
/// `i128` (`Interval::of_int` of an integer that fits is
/// `Interval::of_i128`): no product of big integers, no conversion of one.
fn line_entry(
    body: &BodyPolygon,
    (nx, ny): (Int, Int),
    start: usize,
    end: usize,
) -> (Entry, [Interval; 3]) {
    let small = body.small_vertices().and_then(|v| {
        let [x, y] = v[start];
        let (a, b) = (i128::try_from(&nx).ok()?, i128::try_from(&ny).ok()?);
        let c = a.checked_mul(x)?.checked_add(b.checked_mul(y)?)?;
        Some([a, b, c])
    });
    let (c, iv) = match small {
        Some(abc) => (Int::from(abc[2]), abc.map(Interval::of_i128)),
        None => {
            let (x, y) = body.int_vertex(start);
            let c = &nx * x + &ny * y;
            let iv = [&nx, &ny, &c].map(Interval::of_int);
            (c, iv)
        }
    };
    debug_assert!(
        {
            let (x, y) = body.int_vertex(start);
            c == &nx * x + &ny * y && iv == [&nx, &ny, &c].map(Interval::of_int)
        },
        "the offset of a line through vertex {start}"
    );
    let e = Entry {
        nx,
        ny,
        c,
        start,
        end,
    };
    (e, iv)
}

impl EdgeArray {
    /// Build the array of `body` in `O(n)` (expected; plus `O(M)` entries).
    pub fn new(body: &BodyPolygon) -> EdgeArray {
        let n = body.len();
        // (with coordinates of at most 100 bits, each normal in `i128`
        // too, from the vertices when asked: their products' signs
        // compared in 256 bits, no big integer, and no second vector)
        let small = body.small_vertices();
        let small_normal = |i: usize| -> Option<(i128, i128)> {
            let v = small?;
            let ([x0, y0], [x1, y1]) = (v[i], v[(i + 1) % n]);
            Some((y1 - y0, x0 - x1))
        };
        let normals: Vec<(Int, Int)> = (0..n)
            .map(|i| match small_normal(i) {
                Some((x, y)) => (Int::from(x), Int::from(y)),
                None => {
                    let (x0, y0) = body.int_vertex(i);
                    let (x1, y1) = body.int_vertex((i + 1) % n);
                    // outward normal of a counter-clockwise edge: (dy, −dx)
                    (y1 - y0, x0 - x1)
                }
            })
            .collect();
        let units: Vec<[f64; 2]> = normals
            .iter()
            .enumerate()
            .map(|(i, p)| match small_normal(i) {
                // (`as` rounds an `i128` to the nearest double; below 2^53
                // both conversions are exact)
                Some((x, y)) => {
                    let (fx, fy) = (x as f64, y as f64);
                    let r = fx.hypot(fy);
                    let u = [fx / r, fy / r];
                    debug_assert!(
                        (x.unsigned_abs() | y.unsigned_abs()) >= 1 << 53
                            || u == approx_unit(&p.0, &p.1),
                        "the unit of normal {i}"
                    );
                    u
                }
                _ => approx_unit(&p.0, &p.1),
            })
            .collect();
        // exterior angle at vertex v: from the normal of edge v−1 to that of edge v
        let prev = |v: usize| (v + n - 1) % n;
        let alpha: Vec<f64> = (0..n)
            .map(|v| {
                let (a, b) = (units[prev(v)], units[v]);
                let cr = a[0] * b[1] - a[1] * b[0];
                let d = a[0] * b[0] + a[1] * b[1];
                cr.atan2(d).clamp(0.0, PI)
            })
            .collect();
        let acute_at: Vec<bool> = (0..n)
            .map(|v| match small_normal(prev(v)).zip(small_normal(v)) {
                // a · b = a0·b0 − a1·(−b1)
                Some(((a0, a1), (b0, b1))) => {
                    let acute = cross_sign_wide(a0, a1, -b1, b0) == Sign::Positive;
                    debug_assert_eq!(
                        acute,
                        dot(as_pair(&normals[prev(v)]), as_pair(&normals[v])) > Int::ZERO,
                        "the 256-bit dot product at vertex {v}"
                    );
                    acute
                }
                None => dot(as_pair(&normals[prev(v)]), as_pair(&normals[v])) > Int::ZERO,
            })
            .collect();
        let (r, m) = replication_counts(&alpha, &acute_at);
        let h = m.trailing_zeros();
        let n_eff = n.max(5);
        let scale = (1u64 << ((usize::BITS - n_eff.leading_zeros()) + 8).min(60)) as f64;

        let mut entries = Vec::with_capacity(m);
        let mut ivs = Vec::with_capacity(m);
        let mut edge_entry = Vec::with_capacity(n);
        for i in 0..n {
            let v = (i + 1) % n;
            edge_entry.push(entries.len());
            let (e, iv) = line_entry(body, normals[i].clone(), i, v);
            entries.push(e);
            ivs.push(iv);
            if r[v] > 1 {
                for normal in copy_normals(
                    &normals[i],
                    &normals[v],
                    units[i],
                    alpha[v],
                    r[v] - 1,
                    scale,
                ) {
                    let (e, iv) = line_entry(body, normal, v, v);
                    entries.push(e);
                    ivs.push(iv);
                }
            }
        }
        debug_assert_eq!(entries.len(), m);
        let ivs = Enclosures(ivs);
        let mut array = EdgeArray {
            h,
            n,
            entries,
            ivs,
            edge_entry,
            coarsest_level: 0,
        };
        array.coarsest_level = array.find_coarsest_level();
        array
    }

    /// The coarsest layer whose consecutive kept lines all turn by less than
    /// `π/2`, searched from the top: costs `O(M / 2^ℓ)` for the answer `ℓ`.
    /// Layer 0 always qualifies (array invariant).
    fn find_coarsest_level(&self) -> u32 {
        let m = self.m();
        (0..=self.h)
            .rev()
            .find(|&l| {
                let step = 1usize << l;
                (0..m)
                    .step_by(step)
                    .all(|k| self.turn_is_acute(k, (k + step) & (m - 1)))
            })
            .unwrap_or(0)
    }

    /// The number of entries `M = 2^h`.
    pub fn m(&self) -> usize {
        self.entries.len()
    }

    /// `h = log2 M`.
    pub fn h(&self) -> u32 {
        self.h
    }

    /// The number `n` of vertices of the body polygon.
    pub fn vertex_count(&self) -> usize {
        self.n
    }

    /// Entry `k < M`.
    pub fn entry(&self, k: usize) -> &Entry {
        &self.entries[k]
    }

    /// Mutable access for corruption tests (the exact checks only: the
    /// filter's enclosures keep the entry's old values).
    #[cfg(test)]
    pub(super) fn entry_mut(&mut self, k: usize) -> &mut Entry {
        &mut self.entries[k]
    }

    /// All entries, in array order.
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// The base vertex where entry `k`'s base segment starts.
    pub fn base_vertex_of_entry_start(&self, k: usize) -> usize {
        self.entries[k].start
    }

    /// The base vertex where entry `k`'s base segment ends.
    pub fn base_vertex_of_entry_end(&self, k: usize) -> usize {
        self.entries[k].end
    }

    /// The array index of real edge `i` (from vertex `i` to `i + 1`).
    pub fn edge_entry(&self, i: usize) -> usize {
        self.edge_entry[i]
    }

    /// [`levels::level`] of index `k` in this array.
    pub fn level(&self, k: usize) -> u32 {
        levels::level(k, self.h)
    }

    /// [`levels::top`] in this array.
    pub fn top(&self, i: usize, j: usize) -> Option<usize> {
        levels::top(i, j, self.h)
    }

    /// Whether the counter-clockwise turn from normal `i` to normal `j` is in
    /// `(0, π/2)` (exact: `n_i × n_j > 0` and `n_i · n_j > 0`). For `j`
    /// after `i` in the array the turn through the interval is in `[0, 2π)`,
    /// so this decides the interval's turn, not just its value modulo `2π`.
    pub fn turn_is_acute(&self, i: usize, j: usize) -> bool {
        let (a, b) = (&self.entries[i], &self.entries[j]);
        acute((&a.nx, &a.ny), (&b.nx, &b.ny))
    }

    /// The approximation vertex `av(i, j) = L_i ∩ L_j` by Cramer's rule, in
    /// homogeneous grid coordinates with `W = n_i × n_j > 0`.
    ///
    /// Defined when the counter-clockwise turn from `n_i` to `n_j` is strictly
    /// between 0 and `π` (that is `W > 0`); `None` otherwise. Consecutive
    /// exposed lines of a valid exposed set turn by less than `π/2`.
    pub fn av(&self, i: usize, j: usize) -> Option<HomPoint> {
        let (a, b) = (&self.entries[i], &self.entries[j]);
        let w = &a.nx * &b.ny - &a.ny * &b.nx;
        if w <= Int::ZERO {
            return None;
        }
        Some(HomPoint {
            x: &a.c * &b.ny - &b.c * &a.ny,
            y: &a.nx * &b.c - &b.nx * &a.c,
            w,
        })
    }

    /// An enclosure of `av(i, j)` as `[x, y]` (the f64 filter's view; the
    /// turn must be in `(0, π)`, else `None`).
    pub fn av_enclose(&self, i: usize, j: usize) -> Option<[Interval; 2]> {
        let ([anx, any, ac], [bnx, bny, bc]) = (self.ivs.0[i], self.ivs.0[j]);
        let w = anx * bny - any * bnx;
        if w.lo <= 0.0 {
            return None;
        }
        Some([(ac * bny - bc * any) / w, (anx * bc - bnx * ac) / w])
    }

    /// An enclosure of [`EdgeArray::vertex_of`] in the body's integer grid
    /// coordinates, or `None` (not exposed, or the filter cannot tell).
    pub fn vertex_enclose(
        &self,
        body: &BodyPolygon,
        s: &Exposed,
        k: usize,
    ) -> Option<[Interval; 2]> {
        if !s.contains(k) {
            return None;
        }
        let i = s.pred(k)?;
        match self.av_is_real(i, k) {
            Some(v) => Some(body.int_vertex_enclosure(v)),
            None => self.av_enclose(i, k),
        }
    }

    /// `Some(v)` if `av(i, j)` is the real base vertex `v`: entry `i` ends at
    /// `v`, entry `j` starts at `v`, and every entry strictly between them
    /// (going up from `i`, cyclically) is a zero-length entry at `v`. `O(1)`.
    pub fn av_is_real(&self, i: usize, j: usize) -> Option<usize> {
        if i == j {
            return None;
        }
        let v = self.entries[i].end;
        if self.entries[j].start != v {
            return None;
        }
        // v's block: real edge v−1 (position 0), its copies, real edge v
        let first = self.edge_entry[if v == 0 { self.n - 1 } else { v - 1 }];
        let mask = self.m() - 1;
        let (pi, pj) = ((i + self.m() - first) & mask, (j + self.m() - first) & mask);
        (pi < pj).then_some(v)
    }

    /// The vertex with id `k` of the approximate polygon of the exposed set
    /// `s`: `av(pred_S(k), k)`, the start of the polygon's edge on `L_k`;
    /// the base vertex itself (`w = 1`) when it is real. `None` if `k` is not
    /// in `s` or the turn is not in `(0, π)`.
    pub fn vertex_of(&self, body: &BodyPolygon, s: &Exposed, k: usize) -> Option<HomPoint> {
        if !s.contains(k) {
            return None;
        }
        let i = s.pred(k)?;
        match self.av_is_real(i, k) {
            Some(v) => Some(HomPoint::vertex(body, v)),
            None => self.av(i, k),
        }
    }

    /// The level of the coarsest layer (see [`EdgeArray::coarsest`]).
    pub fn coarsest_level(&self) -> u32 {
        self.coarsest_level
    }

    /// The initial exposed set: the coarsest layer (the multiples of
    /// `2^ℓ`) whose consecutive kept lines all turn by less than `π/2`,
    /// decided exactly when the array is built. It has at most about
    /// `8·M/n' <= 32` lines (each entry turns by at most about `2π/n'`).
    pub fn coarsest(&self) -> Exposed {
        let step = 1usize << self.coarsest_level;
        Exposed::from_indices(self.m(), (0..self.m()).step_by(step))
    }

    /// Pop the vertex with id `k` (`k ∈ s`, `i = pred_S(k)`): insert
    /// `t = top(i, k)` and return it, so that `av(i, k)` is replaced by
    /// `av(i, t)` and `av(t, k)`, joined by an edge on `L_t`. `None` (and `s`
    /// unchanged) if `k` is not in `s` or `av(i, k)` is a real vertex (in
    /// particular when `i` and `k` are adjacent): nothing is hidden there, and
    /// popping would only add a zero-length edge.
    pub fn pop(&self, s: &mut Exposed, k: usize) -> Option<usize> {
        if !s.contains(k) {
            return None;
        }
        let i = s.pred(k)?;
        if self.av_is_real(i, k).is_some() {
            return None;
        }
        let t = self.top(i, k)?;
        s.insert(t);
        Some(t)
    }

    /// Whether `k` may leave `s`: with `p = pred_S(k)` and `q = succ_S(k)`,
    /// `[p, k]` and `[k, q]` are the two halves of the dyadic block `[p, q]`
    /// (so the merge exactly undoes the pop that inserted `k`; see
    /// [`levels::is_sibling_merge`]) and the turn from `L_p` to `L_q` is
    /// below `π/2`.
    pub fn merge_ok(&self, s: &Exposed, k: usize) -> bool {
        if !s.contains(k) || s.len() < 3 {
            return false;
        }
        let (Some(p), Some(q)) = (s.pred(k), s.succ(k)) else {
            return false;
        };
        levels::is_sibling_merge(p, k, q, self.h) && self.turn_is_acute(p, q)
    }

    /// Remove `k` from `s` if [`EdgeArray::merge_ok`]; whether it did.
    pub fn merge(&self, s: &mut Exposed, k: usize) -> bool {
        self.merge_ok(s, k) && s.remove(k)
    }

    /// The vertices of the approximate polygon of `s` in counter-clockwise
    /// order, as `(id, point)` with id `k` the vertex `av(pred_S(k), k)`
    /// ([`EdgeArray::vertex_of`]). For audits and display.
    pub fn approx_polygon(&self, body: &BodyPolygon, s: &Exposed) -> Vec<(usize, HomPoint)> {
        s.iter()
            .filter_map(|k| Some((k, self.vertex_of(body, s, k)?)))
            .collect()
    }

    /// Whether line `k` supports the polygon, checked locally in `O(1)`:
    /// its base vertices are on it and the vertices just before and after
    /// its base segment are strictly inside. For a convex polygon local
    /// support is global support (the polygon lies in the cone at the base
    /// segment spanned by the two neighbouring edges).
    fn supports_locally(&self, body: &BodyPolygon, k: usize) -> Result<(), HierarchyError> {
        let e = &self.entries[k];
        let n = self.n;
        let on = |v: usize| {
            let (x, y) = body.int_vertex(v);
            e.side(x, y)
        };
        if on(e.start) != Sign::Zero || on(e.end) != Sign::Zero {
            return Err(HierarchyError(format!(
                "entry {k}: a base vertex is not on its line"
            )));
        }
        if on((e.start + n - 1) % n) != Sign::Negative || on((e.end + 1) % n) != Sign::Negative {
            return Err(HierarchyError(format!(
                "entry {k}: a neighbouring vertex is not strictly inside"
            )));
        }
        Ok(())
    }

    /// Check every invariant of the array against `body` (the polygon it was
    /// built from), exactly, in `O(M + n)`.
    pub fn check(&self, body: &BodyPolygon) -> Result<(), HierarchyError> {
        let (n, m) = (self.n, self.m());
        if body.len() != n {
            return Err(HierarchyError(format!(
                "built for {n} vertices, body has {}",
                body.len()
            )));
        }
        if m != 1 << self.h || m < n || m > 4 * n {
            return Err(HierarchyError(format!(
                "M = {m} (h = {}) for n = {n}",
                self.h
            )));
        }
        if self.edge_entry.len() != n || self.edge_entry[0] != 0 {
            return Err(HierarchyError("real edge 0 is not entry 0".into()));
        }
        for i in 0..n {
            let k = self.edge_entry[i];
            let next = if i + 1 < n { self.edge_entry[i + 1] } else { m };
            if next <= k {
                return Err(HierarchyError(format!(
                    "real edges {i} and {} out of order",
                    i + 1
                )));
            }
            let e = &self.entries[k];
            let v = (i + 1) % n;
            let (x0, y0) = body.int_vertex(i);
            let (x1, y1) = body.int_vertex(v);
            if e.start != i || e.end != v || e.nx != y1 - y0 || e.ny != x0 - x1 {
                return Err(HierarchyError(format!("entry {k} is not real edge {i}")));
            }
            if let Some(bad) = (k + 1..next).find(|&j| {
                let z = &self.entries[j];
                z.start != v || z.end != v
            }) {
                return Err(HierarchyError(format!(
                    "entry {bad} is not a zero-length entry at vertex {v}"
                )));
            }
        }
        for k in 0..m {
            self.supports_locally(body, k)?;
            if !self.turn_is_acute(k, (k + 1) & (m - 1)) {
                return Err(HierarchyError(format!(
                    "entries {k} and {}: turn not in (0, π/2)",
                    k + 1
                )));
            }
        }
        // Consecutive turns in (0, π/2) and real edges in order: the normals
        // wind exactly once, because the real edge normals do (the polygon
        // is convex) and each inserted run lies in its vertex's cone.
        let l = self.coarsest_level;
        let step = 1usize << l;
        let layer_ok = |step: usize| {
            (0..m)
                .step_by(step)
                .all(|k| self.turn_is_acute(k, (k + step) & (m - 1)))
        };
        if !layer_ok(step) || (l < self.h && layer_ok(2 * step)) {
            return Err(HierarchyError(format!(
                "{l} is not the coarsest acute layer"
            )));
        }
        Ok(())
    }

    /// Check an exposed set exactly: every gap between consecutive elements
    /// is a dyadic block (so the set is the leaf set of a binary refinement
    /// of the whole cycle: equivalently, it is reachable from the coarsest
    /// layer by pops and merges), every gap turns by an angle in `(0, π/2)`,
    /// and every exposed line supports the polygon (so the approximate
    /// polygon contains it). `O(|S| log M)`; the array itself is assumed
    /// valid ([`EdgeArray::check`]).
    pub fn check_exposed(&self, body: &BodyPolygon, s: &Exposed) -> Result<(), HierarchyError> {
        if s.universe() != self.m() {
            return Err(HierarchyError(format!(
                "exposed set over {} indices, array has {}",
                s.universe(),
                self.m()
            )));
        }
        let first = s
            .select(0)
            .ok_or_else(|| HierarchyError("empty exposed set".into()))?;
        let mut i = first;
        loop {
            let j = s.succ(i).expect("non-empty");
            if !levels::is_dyadic(i, j, self.h) {
                return Err(HierarchyError(format!(
                    "gap ({i}, {j}) is not a dyadic block"
                )));
            }
            if !self.turn_is_acute(i, j) {
                return Err(HierarchyError(format!(
                    "gap ({i}, {j}) does not turn by less than π/2"
                )));
            }
            self.supports_locally(body, j)?;
            if j == first {
                return Ok(());
            }
            i = j;
        }
    }

    /// Brute-force containment: every base vertex is in every exposed
    /// half-plane, exactly. `O(n·|S|)`; for tests and deep audits.
    pub fn check_containment_brute(
        &self,
        body: &BodyPolygon,
        s: &Exposed,
    ) -> Result<(), HierarchyError> {
        for k in s.iter() {
            let e = &self.entries[k];
            for v in 0..body.len() {
                let (x, y) = body.int_vertex(v);
                if e.side(x, y) == Sign::Positive {
                    return Err(HierarchyError(format!(
                        "vertex {v} is outside exposed line {k}"
                    )));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn random_cone(rng: &mut Rng, bits: u32) -> ((Int, Int), (Int, Int)) {
        loop {
            let mut r = || Int::from(rng.range_i64(-(1 << bits), 1 << bits));
            let (a, b) = ((r(), r()), (r(), r()));
            if cross(as_pair(&a), as_pair(&b)) > Int::ZERO {
                return (a, b);
            }
        }
    }

    /// The `i128` forms of the turn tests agree with the big integers' on
    /// vectors on both sides of their `2^126` limit (where the big integers
    /// decide), opposite and equal ones included.
    #[test]
    fn hier_narrow_turns_agree_with_the_big_integers() {
        let mut rng = Rng::new(11);
        let mut narrow_seen = 0;
        for round in 0..4000 {
            // (right shifts of 59 and 32 bits, none, left shifts of 64 and
            // 65: magnitudes up to 2^3, 2^30, 2^62, 2^126, 2^127)
            let shift = [59i32, 32, 0, -64, -65][round % 5];
            let mut r = || {
                let x = Int::from(rng.range_i64(-(1 << 62), 1 << 62));
                if shift >= 0 {
                    x >> shift as usize
                } else {
                    x << (-shift) as usize
                }
            };
            let a = (r(), r());
            let b = match round % 7 {
                0 => (-a.0.clone(), -a.1.clone()),
                1 => a.clone(),
                _ => (r(), r()),
            };
            let (a, b) = (as_pair(&a), as_pair(&b));
            narrow_seen += usize::from(narrow(a).is_some() && narrow(b).is_some());
            assert_eq!(
                acute(a, b),
                cross(a, b) > Int::ZERO && dot(a, b) > Int::ZERO,
                "{a:?} {b:?}"
            );
            assert_eq!(cross_positive(a, b), cross(a, b) > Int::ZERO, "{a:?} {b:?}");
        }
        assert!(narrow_seen > 1000 && narrow_seen < 3900, "{narrow_seen}");
    }

    /// Every entry's offset is `nx·x + ny·y` at its base vertex and its
    /// enclosures are those of its integers, on polygons whose grid
    /// integers are small, whose offsets overflow an `i128` (so the big
    /// integers make them), and whose coordinates have over 100 bits (no
    /// `i128` form at all).
    #[test]
    fn hier_entry_lines_pass_through_their_base_vertices() {
        let ring = |n: usize, r: f64, c: [f64; 2]| -> Vec<[f64; 2]> {
            crate::gen::regular_polygon(n, r, 0.3)
                .into_iter()
                .map(|[x, y]| [x + c[0], y + c[1]])
                .collect()
        };
        // (a coordinate of 1e-30 beside ones of 1: over 150 bits on the
        // common unit)
        let tiny = vec![[1e-30, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let polygons = [
            ring(8, 4.0, [0.0, 0.0]),
            ring(64, 1.0, [0.0, 0.0]),
            ring(64, 1.0, [1e6, -3e5]),
            ring(8, 1.0, [3e12, 1.0]),
            tiny,
        ];
        // (offsets that fit an `i128`, that overflow it on `i128`
        // coordinates, and lines of a polygon without `i128` coordinates)
        let mut kinds = [0; 3];
        for verts in &polygons {
            let body = BodyPolygon::new(verts).unwrap();
            let arr = EdgeArray::new(&body);
            for (k, e) in arr.entries().iter().enumerate() {
                let (x, y) = body.int_vertex(e.start);
                assert_eq!(e.c, &e.nx * x + &e.ny * y, "entry {k}");
                assert_eq!(
                    arr.ivs.0[k],
                    [&e.nx, &e.ny, &e.c].map(Interval::of_int),
                    "entry {k}"
                );
                kinds[match (body.small_vertices(), i128::try_from(&e.c)) {
                    (None, _) => 2,
                    (Some(_), Ok(_)) => 0,
                    (Some(_), Err(_)) => 1,
                }] += 1;
            }
        }
        assert!(kinds.iter().all(|&x| x > 0), "{kinds:?}");
    }

    #[test]
    fn hier_exact_fallback_is_a_valid_fan() {
        let mut rng = Rng::new(5);
        let (mut acute_seen, mut obtuse_seen) = (0, 0);
        for round in 0..2000 {
            let (a, b) = random_cone(&mut rng, if round % 2 == 0 { 4 } else { 40 });
            if dot(as_pair(&a), as_pair(&b)) > Int::ZERO {
                acute_seen += 1;
            } else {
                obtuse_seen += 1;
            }
            let count = 1 + rng.below(9) as usize;
            let fan = exact_fallback_normals(&a, &b, count);
            assert_eq!(fan.len(), count);
            assert!(valid_fan(&a, &fan, &b), "{a:?} {b:?} {count}");
            // the f64 path with a useless scale falls back, still valid
            let (ua, ub) = (approx_unit(&a.0, &a.1), approx_unit(&b.0, &b.1));
            let alpha = (ua[0] * ub[1] - ua[1] * ub[0]).atan2(ua[0] * ub[0] + ua[1] * ub[1]);
            for scale in [1.0, 1024.0] {
                let fan = copy_normals(&a, &b, ua, alpha, count, scale);
                assert_eq!(fan.len(), count);
                assert!(valid_fan(&a, &fan, &b));
            }
        }
        assert!(acute_seen > 100 && obtuse_seen > 100);
    }

    #[test]
    fn hier_replication_counts_bounds() {
        let mut rng = Rng::new(9);
        for _ in 0..500 {
            let n = rng.range_usize(3, 300);
            let mut alpha: Vec<f64> = (0..n).map(|_| rng.next_f64().powi(4)).collect();
            let s: f64 = alpha.iter().sum();
            alpha
                .iter_mut()
                .for_each(|a| *a *= std::f64::consts::TAU / s);
            if alpha.iter().any(|&a| a >= PI) {
                continue;
            }
            let acute_at: Vec<bool> = alpha.iter().map(|&a| a < PI / 2.0).collect();
            let (r, m) = replication_counts(&alpha, &acute_at);
            assert!(m.is_power_of_two() && m >= n && m <= 4 * n);
            assert_eq!(r.iter().sum::<usize>(), m);
            let n_eff = n.max(5) as f64;
            for v in 0..n {
                assert!(r[v] >= 1 && (acute_at[v] || r[v] >= 2));
                assert!(alpha[v] / r[v] as f64 <= std::f64::consts::TAU / n_eff / (1.0 - SLACK));
            }
        }
    }
}
