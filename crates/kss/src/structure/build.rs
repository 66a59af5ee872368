//! Construction of the structure at one instant from an exact constrained
//! triangulation of the free space ([`crate::cdt`]).
//!
//! The vertices are the polygons' vertices at a rational instant, compared
//! with exact predicates (a midpoint–radius filter first): the
//! triangulation is valid whatever the magnitudes and however close the
//! polygons are. Where polygons touch (a vertex on another polygon's edge,
//! two vertices at one point) the free space has no triangulation; the
//! construction then triangulates an infinitesimally shrunk copy instead
//! (each polygon scaled about its centroid by `1 − ε`, with `ε` symbolic),
//! and the caller checks that candidate exactly.

use std::cell::{OnceCell, RefCell};
use std::cmp::Ordering;
use std::collections::HashMap;

/// A map with the fast fixed hasher (keys are indices and points).
type FastMap<K, V> = HashMap<K, V, foldhash::fast::FixedState>;

use super::geo::Geo;
use super::{Att, CorrId, Corridor, Kss, Obj, PartitionTriangle, TriId};
use crate::cdt::{self, CdtError};
use crate::geom::{
    in_circle_box_bound, in_circle_in_box, in_circle_mid_rad, in_circle_static, orient,
    orient_box_bound, orient_in_box, orient_mid_rad, MidRad, Point,
};
use crate::num::{Rational, Sign};
use crate::world::BodyId;

/// Why the structure could not be built.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BuildError {
    /// The free space has no triangulation, even shrunk infinitesimally
    /// (or its triangulation does not make a structure).
    #[error("the free space has no valid triangulation: {0}")]
    Degenerate(String),
}

/// The exact position of an attachment point at time `t` (`None` for `ω`).
pub fn position(world: &Geo, a: Att, t: &Rational) -> Option<Point> {
    match a.obj {
        Obj::Omega => None,
        Obj::Body(_) => world.position(a, t),
    }
}

/// Build the structure for the alive bodies of `world` at time `t`.
///
/// The free space is triangulated exactly at `t`. If it has no
/// triangulation (polygons touch at `t`, as when one slides along
/// another), the triangulation of an infinitesimally shrunk copy is taken:
/// each polygon scaled about its centroid by `1 − ε` for a symbolic `ε > 0`,
/// so that touching polygons are apart. Every triangle of that copy has a
/// positive or zero orientation at `t` (zero between two polygons in
/// contact). Such a build is only a candidate: [`Perturbed::Yes`] tells the
/// caller to check it exactly (faces and bridges) before using it.
pub fn build(world: &Geo, t: &Rational) -> Result<(Kss, Perturbed), BuildError> {
    match build_with(world, t, false) {
        Ok(kss) => Ok((kss, Perturbed::No)),
        Err(_) => build_with(world, t, true).map(|kss| (kss, Perturbed::Yes)),
    }
}

/// Whether a build used the shrunk copy (and must be checked exactly).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Perturbed {
    /// Built from the positions themselves.
    No,
    /// Built from the infinitesimally shrunk polygons: a candidate to check.
    Yes,
}

/// The place of a vertex that has none ([`Geo::mid_rad`] is `None`):
/// not-a-number at an infinite radius, so that every filter on it is
/// undecided (a real place's radius is finite).
const UNPLACED: MidRad = MidRad {
    x: f64::NAN,
    y: f64::NAN,
    r: f64::INFINITY,
};

/// The polygons' vertices at an instant, as the triangulation sees them:
/// exact positions (computed when the filter does not decide), and with
/// `shrink`, each moved by `ε` times its offset towards its polygon's
/// centroid.
pub(super) struct Vertices<'g, 'w> {
    world: &'g Geo<'w>,
    t: &'g Rational,
    atts: Vec<Att>,
    /// Each vertex's midpoint and radius at `t`, or [`UNPLACED`] (whose
    /// filters never decide) where it has none.
    mids: Vec<MidRad>,
    /// The [`orient_box_bound`] and [`in_circle_box_bound`] of `mids`:
    /// most orientations and circle tests are decided by one comparison
    /// with these before the filters of their own radii.
    orient_bound: f64,
    in_circle_bound: f64,
    /// Each vertex's exact position at `t`, computed where a filter cannot
    /// decide (boxed: most are never computed, and an empty cell is one
    /// word rather than a point's four integers).
    exact: Vec<OnceCell<Box<Point>>>,
    shrink: bool,
    /// The centroids at `t` of the bodies met so far (for `shrink`; a map,
    /// so that a local triangulation costs its own size, not the scene's).
    centroids: RefCell<FastMap<u32, Point>>,
    /// Each vertex's offset towards its body's centroid (boxed, as `exact`).
    towards: Vec<OnceCell<Box<Point>>>,
}

impl<'g, 'w> Vertices<'g, 'w> {
    /// The vertices of `atts` (all on bodies) at `t`.
    pub(super) fn new(world: &'g Geo<'w>, t: &'g Rational, atts: Vec<Att>, shrink: bool) -> Self {
        let tiv = t.interval();
        let mids: Vec<MidRad> = atts
            .iter()
            .map(|&a| world.mid_rad(a, tiv).unwrap_or(UNPLACED))
            .collect();
        let n = atts.len();
        Vertices {
            world,
            t,
            atts,
            orient_bound: orient_box_bound(&mids),
            in_circle_bound: in_circle_box_bound(&mids),
            mids,
            exact: (0..n).map(|_| OnceCell::new()).collect(),
            shrink,
            centroids: RefCell::default(),
            towards: (0..n).map(|_| OnceCell::new()).collect(),
        }
    }

    fn exact(&self, i: usize) -> &Point {
        self.exact[i].get_or_init(|| {
            Box::new(
                self.world
                    .position(self.atts[i], self.t)
                    .expect("a vertex on a body"),
            )
        })
    }

    /// The offset of vertex `i` towards its body's centroid.
    fn towards(&self, i: usize) -> &Point {
        self.towards[i].get_or_init(|| {
            let Obj::Body(b) = self.atts[i].obj else {
                unreachable!("the vertices are on bodies")
            };
            let c = self
                .centroids
                .borrow_mut()
                .entry(b.raw())
                .or_insert_with(|| {
                    let body = self.world.world.body(b);
                    body.traj.position_at(self.t).add(body.centroid())
                })
                .clone();
            Box::new(c.sub(self.exact(i)))
        })
    }

    fn cmp_coord(&self, a: usize, b: usize, x: bool) -> Ordering {
        let (p, q) = (self.mids[a], self.mids[b]);
        let filtered = if x { p.cmp_x(q) } else { p.cmp_y(q) };
        let c = filtered.unwrap_or_else(|| {
            let (p, q) = (self.exact(a), self.exact(b));
            if x {
                p.x.cmp(&q.x)
            } else {
                p.y.cmp(&q.y)
            }
        });
        if c != Ordering::Equal || !self.shrink {
            return c;
        }
        let (p, q) = (self.towards(a), self.towards(b));
        if x {
            p.x.cmp(&q.x)
        } else {
            p.y.cmp(&q.y)
        }
    }
}

impl cdt::Predicates for Vertices<'_, '_> {
    fn cmp(&self, a: usize, b: usize) -> Ordering {
        self.cmp_coord(a, b, true)
            .then_with(|| self.cmp_coord(a, b, false))
    }

    fn orient(&self, a: usize, b: usize, c: usize) -> Sign {
        let (u, v, w) = (self.mids[a], self.mids[b], self.mids[c]);
        if let Some(s) =
            orient_in_box(u, v, w, self.orient_bound).or_else(|| orient_mid_rad(u, v, w))
        {
            return s;
        }
        let (p, q, r) = (self.exact(a), self.exact(b), self.exact(c));
        let s = orient(p, q, r);
        if s != Sign::Zero || !self.shrink {
            return s;
        }
        // the terms of ε and ε² of the shrunk copy's orientation
        let (tp, tq, tr) = (self.towards(a), self.towards(b), self.towards(c));
        let (dq, dr) = (tq.sub(tp), tr.sub(tp));
        let first = q.sub(p).cross(&dr).add(&dq.cross(&r.sub(p)));
        match first.sign() {
            Sign::Zero => dq.cross(&dr).sign(),
            s => s,
        }
    }

    fn in_circle(&self, a: usize, b: usize, c: usize, d: usize) -> bool {
        let [p, q, r, s] = [a, b, c, d].map(|i| self.mids[i]);
        in_circle_in_box(p, q, r, s, self.in_circle_bound)
            .or_else(|| in_circle_static(p, q, r, s))
            .or_else(|| in_circle_mid_rad(p, q, r, s))
            == Some(Sign::Positive)
    }

    /// Two vertices of one body (polygon or approximation, convex, its
    /// edges segments of every triangulation here; the shrunk copy too):
    /// the segment between them is one of its edges or inside it.
    fn same_obstacle(&self, a: usize, b: usize) -> bool {
        self.atts[a].obj == self.atts[b].obj
    }

    fn position_hint(&self, a: usize) -> Option<[f64; 2]> {
        let m = self.mids[a];
        m.r.is_finite().then_some([m.x, m.y])
    }
}

fn build_with(world: &Geo, t: &Rational, shrink: bool) -> Result<Kss, BuildError> {
    // Global vertex numbering.
    let mut atts: Vec<Att> = Vec::new();
    let mut edges: Vec<[usize; 2]> = Vec::new();
    for (i, body) in world.bodies().iter().enumerate() {
        if !body.alive {
            continue;
        }
        let base = atts.len();
        let ids = world.ids(BodyId::new(i as u32));
        let n = ids.len();
        for (x, &v) in ids.iter().enumerate() {
            atts.push(Att::vertex(BodyId::new(i as u32), v));
            edges.push([base + x, base + (x + 1) % n]);
        }
    }
    let alive = world.alive_count();
    if alive < 2 {
        return Ok(Kss::default());
    }
    let vertices = Vertices::new(world, t, atts, shrink);
    let (tris, nbr) = cdt::triangulate_adjacent(vertices.atts.len(), &edges, &vertices)
        .map_err(|e: CdtError| BuildError::Degenerate(e.to_string()))?;
    let atts = vertices.atts;
    // Convex hull edges (CCW): the triangle sides with no triangle across,
    // in the order of their ends, each with its triangle and side.
    let mut hull: Vec<((usize, usize), (usize, usize))> = Vec::new();
    for (ti, tri) in tris.iter().enumerate() {
        for i in 0..3 {
            if nbr[ti][i].is_none() {
                hull.push(((tri[i], tri[(i + 1) % 3]), (ti, i)));
            }
        }
    }
    hull.sort_unstable();
    let same = |x: usize, y: usize| atts[x].obj == atts[y].obj;
    // Free-space triangles as attachment triples (ω for the infinite ones),
    // and each triangle's face (`NO_FACE` inside a polygon).
    const NO_FACE: usize = usize::MAX;
    let mut faces: Vec<[Att; 3]> = Vec::with_capacity(tris.len() + hull.len());
    let mut face_tri: Vec<usize> = Vec::with_capacity(tris.len());
    let mut tri_face: Vec<usize> = vec![NO_FACE; tris.len()];
    for (ti, tri) in tris.iter().enumerate() {
        let [u, v, w] = *tri;
        if same(u, v) && same(v, w) {
            continue; // inside a polygon
        }
        tri_face[ti] = faces.len();
        face_tri.push(ti);
        faces.push([atts[u], atts[v], atts[w]]);
    }
    let first_hull_face = faces.len();
    for &((u, v), _) in &hull {
        faces.push([atts[v], atts[u], Att::OMEGA]);
    }
    // (the hull edges by their first and their last vertex)
    let mut hull_from: FastMap<usize, usize> =
        FastMap::with_capacity_and_hasher(hull.len(), Default::default());
    let mut hull_to: FastMap<usize, usize> =
        FastMap::with_capacity_and_hasher(hull.len(), Default::default());
    for (k, &((u, v), _)) in hull.iter().enumerate() {
        hull_from.insert(u, k);
        hull_to.insert(v, k);
    }
    // Check that two corners on one body are adjacent on it (no chords).
    for f in &faces {
        for i in 0..3 {
            let (x, y) = (f[i], f[(i + 1) % 3]);
            if let (Obj::Body(b), true) = (x.obj, x.obj == y.obj) {
                if world.ccw(x) != y && world.ccw(y) != x {
                    return Err(BuildError::Degenerate(format!(
                        "a triangle side cuts through body {}",
                        world.body(b).id
                    )));
                }
            }
        }
    }
    // Adjacency: the face and side across side `i` of face `f` (`None`
    // into a polygon). A triangle's face has its triangle's corners in
    // order; the ω-face of hull edge `u → v` is `(v, u, ω)`, across its
    // first side from the edge's triangle, across its second from the
    // ω-face of the hull edge that ends at `u` (at that one's third side),
    // across its third from the one that begins at `v`.
    let across = |f: usize, i: usize| -> Option<(usize, usize)> {
        if f < first_hull_face {
            let ti = face_tri[f];
            let tri = tris[ti];
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            match nbr[ti][i].map(|n| n as usize) {
                Some(n) => {
                    let g = tri_face[n];
                    let j = (0..3).find(|&j| tris[n][j] == b && tris[n][(j + 1) % 3] == a)?;
                    (g != NO_FACE).then_some((g, j))
                }
                None => {
                    let k = hull.binary_search_by(|h| h.0.cmp(&(a, b))).ok()?;
                    Some((first_hull_face + k, 0))
                }
            }
        } else {
            let k = f - first_hull_face;
            let ((u, v), (ti, ts)) = hull[k];
            match i {
                0 => Some((tri_face[ti], ts)).filter(|&(g, _)| g != NO_FACE),
                1 => hull_to.get(&u).map(|&j| (first_hull_face + j, 2)),
                _ => hull_from.get(&v).map(|&j| (first_hull_face + j, 1)),
            }
        }
    };
    #[cfg(debug_assertions)]
    {
        // the same as the faces' sides, matched by their points
        let mut side_of: FastMap<(Att, Att), (usize, usize)> =
            FastMap::with_capacity_and_hasher(3 * faces.len(), Default::default());
        for (fi, f) in faces.iter().enumerate() {
            for i in 0..3 {
                side_of.insert((f[i], f[(i + 1) % 3]), (fi, i));
            }
        }
        for (fi, f) in faces.iter().enumerate() {
            for i in 0..3 {
                let (x, y) = (f[i], f[(i + 1) % 3]);
                if x.obj != y.obj {
                    debug_assert_eq!(
                        across(fi, i),
                        side_of.get(&(y, x)).copied(),
                        "the face across side {i} of face {fi}"
                    );
                }
            }
        }
    }
    let mut face_kss_tri: Vec<u32> = vec![u32::MAX; faces.len()];
    let mut kss_tri_face: Vec<usize> = Vec::new();
    let mut kss = Kss::default();
    for (fi, f) in faces.iter().enumerate() {
        if is_partition(f) {
            face_kss_tri[fi] = kss.tris.len() as u32;
            kss_tri_face.push(fi);
            kss.tris.push(PartitionTriangle {
                c: *f,
                corr: [CorrId(u32::MAX); 3],
            });
        }
    }
    // Walk each corridor from a partition-triangle side whose first corner is finite.
    for (ti, &start) in kss_tri_face.iter().enumerate() {
        for i in 0..3 {
            let tri = &kss.tris[ti];
            if tri.corr[i] != CorrId(u32::MAX) {
                continue;
            }
            let (p, q) = (tri.c[i], tri.c[(i + 1) % 3]);
            if p.is_omega() {
                continue;
            }
            let (mut len_a, mut len_b) = (0u32, 0u32);
            // the side we cross: its face and its index there
            let (mut f, mut side) = (start, i);
            let end = loop {
                let (fj, sj) = across(f, side)
                    .ok_or_else(|| BuildError::Degenerate("a side without neighbour".into()))?;
                let g = &faces[fj];
                if is_partition(g) {
                    break (TriId(face_kss_tri[fj]), sj as u8);
                }
                let ((x, y), on_a) = cross_two_object_face(g, sj, p.obj);
                if on_a {
                    len_a += 1;
                } else {
                    len_b += 1;
                }
                side = (0..3)
                    .find(|&k| g[k] == x && g[(k + 1) % 3] == y)
                    .expect("the side crossed is a side of its face");
                f = fj;
            };
            let k = CorrId(kss.corrs.len() as u32);
            kss.corrs.push(Corridor {
                a: p.obj,
                b: q.obj,
                s: (TriId(ti as u32), i as u8),
                t: end,
                len_a,
                len_b,
                mid: None,
            });
            kss.tris[ti].corr[i] = k;
            kss.tris[end.0 .0 as usize].corr[end.1 as usize] = k;
        }
    }
    if kss.tris.iter().any(|t| t.corr.contains(&CorrId(u32::MAX))) {
        return Err(BuildError::Degenerate(
            "a partition-triangle side without corridor".into(),
        ));
    }
    Ok(kss)
}

/// Whether a face of the free-space triangulation has its corners on three
/// different objects (a partition triangle).
pub(super) fn is_partition(f: &[Att; 3]) -> bool {
    f[0].obj != f[1].obj && f[1].obj != f[2].obj && f[0].obj != f[2].obj
}

/// One step of a corridor walk through a two-object face `g` entered across
/// its side `sj`: the face has one polygon edge and one other bridge to
/// leave by. Returns that exit side, A-first (the next face holds it as
/// `(y, x)`), and whether the polygon edge is on object `a` (the corridor's
/// A-chain) rather than on the other one.
pub(super) fn cross_two_object_face(g: &[Att; 3], sj: usize, a: Obj) -> ((Att, Att), bool) {
    let (s1, s2) = ((sj + 1) % 3, (sj + 2) % 3);
    let side = |k: usize| (g[k], g[(k + 1) % 3]);
    let (edge, exit) = if side(s1).0.obj == side(s1).1.obj {
        (s1, s2)
    } else {
        (s2, s1)
    };
    (side(exit), side(edge).0.obj == a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gen::{generate_small, Family};
    use crate::structure::geo::Geo;
    use crate::world::World;

    /// Every filter of the triangulation is undecided on a vertex without
    /// a place, wherever it stands among the points.
    #[test]
    fn an_unplaced_vertex_decides_no_filter() {
        let m = |x: f64, y: f64| MidRad { x, y, r: 0.0 };
        let (p, q, r) = (m(0.0, 0.0), m(1.0, 0.0), m(0.0, 1.0));
        let u = UNPLACED;
        assert_eq!(orient_mid_rad(p, q, r), Some(Sign::Positive));
        for [a, b, c] in [[u, q, r], [p, u, r], [p, q, u]] {
            assert_eq!(orient_mid_rad(a, b, c), None);
        }
        for [a, b, c, d] in [[u, q, r, p], [p, u, r, q], [p, q, u, r], [p, q, r, u]] {
            assert_eq!(in_circle_static(a, b, c, d), None);
            assert_eq!(in_circle_mid_rad(a, b, c, d), None);
        }
        assert_eq!(
            (u.cmp_x(p), p.cmp_x(u), u.cmp_y(p), p.cmp_y(u)),
            (None, None, None, None)
        );
    }

    #[test]
    fn construction_topology_on_generated_scenes() {
        let mut built = 0;
        for family in Family::ALL {
            for seed in 0..60 {
                let s = generate_small(family, seed);
                let world = World::new(&s, None).unwrap();
                let world = Geo::plain(&world);
                match build(&world, &Rational::zero()) {
                    Ok((mut kss, _)) => {
                        kss.check_topology(&world)
                            .unwrap_or_else(|e| panic!("{} seed {seed}: {e}", family.name()));
                        let t0 = crate::num::Time::zero();
                        kss.place_middle_bridges(&world, &t0);
                        kss.check_faces(&world, &t0)
                            .unwrap_or_else(|e| panic!("{} seed {seed}: {e}", family.name()));
                        built += 1;
                    }
                    Err(e) => panic!("{} seed {seed}: {e}", family.name()),
                }
            }
        }
        assert_eq!(built, 360);
    }
}

#[cfg(test)]
mod larger_tests {
    use super::*;
    use crate::gen::{flypast, gas, FlypastParams, GasParams};
    use crate::num::Time;
    use crate::world::World;

    fn check(s: &crate::Scenario) {
        let world = World::new(s, None).unwrap();
        let world = Geo::plain(&world);
        let (mut kss, _) = build(&world, &Rational::zero()).unwrap();
        kss.check_topology(&world).unwrap();
        kss.place_middle_bridges(&world, &Time::zero());
        kss.check_faces(&world, &Time::zero()).unwrap();
    }

    #[test]
    fn gas_scenes_with_walls() {
        for (k, n, seed) in [(50, 8, 1), (200, 6, 2), (20, 64, 3)] {
            check(&gas(&GasParams {
                k,
                min_n: n,
                max_n: n,
                walls: true,
                seed,
                ..Default::default()
            }));
        }
    }

    #[test]
    fn flypast_large_polygons() {
        for n in [16, 1024, 1 << 14] {
            check(&flypast(&FlypastParams {
                n,
                ..Default::default()
            }));
        }
    }

    #[test]
    fn polygons_in_contact_are_built_from_a_shrunk_copy_and_checked() {
        // b slides along a's side (testdata/regressions/
        // rebuild_while_two_polygons_slide.json): from t = 3 on, b's vertex
        // (4, 2) runs along a's edge from (6, 0) to (-1, 5); at t = 13/4
        // the rounded triangulation has a side through b, the shrunk copy
        // has flat triangles between the two
        let poly =
            |id: &str, v: &[[f64; 2]], p: [f64; 2], vel: [f64; 2]| crate::scenario::PolygonSpec {
                id: id.into(),
                vertices: v.to_vec(),
                position: p,
                velocity: vel,
                fixed: false,
            };
        let s = crate::Scenario {
            until: 4.0,
            on_collision: crate::scenario::CollisionMode::Bounce,
            polygons: vec![
                poly(
                    "a",
                    &[
                        [6.0, 0.0],
                        [-1.0, 5.0],
                        [-6.0, 0.0],
                        [-2.0, -6.0],
                        [3.0, -5.0],
                        [6.0, -4.0],
                    ],
                    [-160.0, -160.0],
                    [0.0, 0.0],
                ),
                poly(
                    "b",
                    &[
                        [2.0, 4.0],
                        [-5.0, 3.0],
                        [-6.0, 2.0],
                        [-3.0, -3.0],
                        [1.0, -5.0],
                        [3.0, -3.0],
                        [4.0, 2.0],
                    ],
                    [-158.0, -176.0],
                    [3.0, 3.0],
                ),
                poly(
                    "c",
                    &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
                    [-100.0, -100.0],
                    [0.0, 0.0],
                ),
            ],
            flight_plan_changes: vec![crate::scenario::FlightPlanChange {
                time: 3.0,
                id: "b".into(),
                velocity: [-3.5, 2.5],
            }],
            ..Default::default()
        };
        let world = World::new(&s, None).unwrap();
        let world = Geo::plain(&world);
        let at = Rational::from_f64(3.25).unwrap();
        let (_, perturbed) = build(&world, &at).unwrap();
        assert_eq!(perturbed, Perturbed::Yes);
        // the engine takes it only after the exact checks; then the audit
        let k = crate::structure::kinetic::Kinetic::new(&world, &at).unwrap();
        let now = crate::num::Time::from_rational(at.clone());
        let next = k.next_time().expect("b reaches the end of a's edge");
        assert!(next > now);
        let later = now.rational_between(&next);
        k.audit(&world, &now, &later).unwrap();
        // apart polygons take the direct path
        let s = gas(&GasParams {
            k: 30,
            seed: 4,
            ..Default::default()
        });
        let world = World::new(&s, None).unwrap();
        let world = Geo::plain(&world);
        assert_eq!(build(&world, &Rational::zero()).unwrap().1, Perturbed::No);
    }
}
