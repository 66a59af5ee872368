//! Construction of the structure at one instant from a constrained
//! triangulation of the free space (spade), checked with exact predicates.
//!
//! spade triangulates the vertices rounded to doubles; every triangle we keep
//! is then re-checked exactly (positive orientation with the exact
//! coordinates). If rounding made the triangulation invalid for the exact
//! coordinates (vertices closer than a few units in the last place), the
//! construction reports an error rather than building a wrong structure.

use std::collections::HashMap;

/// A map with the fast fixed hasher (keys are indices and points).
type FastMap<K, V> = HashMap<K, V, foldhash::fast::FixedState>;

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::geo::Geo;
use super::{Att, CorrId, Corridor, Kss, Obj, PartitionTriangle, TriId};
use crate::geom::{orient, Point};
use crate::num::{Rational, Sign};
use crate::world::BodyId;

/// Why the structure could not be built.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BuildError {
    /// The rounded triangulation is not valid for the exact coordinates.
    #[error("the free-space triangulation is not valid with exact coordinates: {0}")]
    Rounding(String),
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
/// The triangulation is first computed on the positions rounded to doubles.
/// If that fails (polygons touch at `t`, as when one slides along another,
/// or are closer than the rounding), it is retried on *shrunk* polygons:
/// each polygon scaled about its vertex centroid by `1 − ε` in doubles, so
/// that touching polygons are apart by about `ε` times their size. Only the
/// combinatorics come from the shrunk copy; every triangle is then oriented
/// with the exact coordinates, and a triangle that is flat there (between
/// two polygons in contact) takes the shrunk copy's orientation. Such a
/// build is only a candidate: [`Perturbed::Yes`] tells the caller to check
/// it exactly (faces and bridges) before using it.
pub fn build(world: &Geo, t: &Rational) -> Result<(Kss, Perturbed), BuildError> {
    match build_with(world, t, None) {
        Ok(kss) => Ok((kss, Perturbed::No)),
        Err(first) => {
            for shrink in SHRINKS {
                if let Ok(kss) = build_with(world, t, Some(shrink)) {
                    return Ok((kss, Perturbed::Yes));
                }
            }
            Err(first)
        }
    }
}

/// Whether a build used the shrunk copy (and must be checked exactly).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Perturbed {
    /// Built from the positions themselves.
    No,
    /// Built from shrunk polygons: a candidate to check.
    Yes,
}

/// The orientation a triangle of a triangulation computed on a *shrunk*
/// copy takes: its exact orientation `exact`, or, where that is zero (a
/// triangle flat between two polygons in contact), the shrunk copy's
/// `shrunk` (exact on its doubles); `None` where the two disagree (the
/// shrinking turned the triangle over: the triangulation is not valid).
pub(super) fn shrunk_orientation(exact: Sign, shrunk: Sign) -> Option<Sign> {
    match exact {
        Sign::Zero => Some(shrunk),
        s => (s == shrunk).then_some(s),
    }
}

/// The relative shrink factors tried, in order (the local repair uses the
/// first).
pub(super) const SHRINKS: [f64; 3] = [
    1.0 / (1u64 << 26) as f64,
    1.0 / (1u64 << 18) as f64,
    1.0 / (1u64 << 34) as f64,
];

fn build_with(world: &Geo, t: &Rational, shrink: Option<f64>) -> Result<Kss, BuildError> {
    // Global vertex numbering.
    let mut atts: Vec<Att> = Vec::new();
    let mut edges: Vec<[usize; 2]> = Vec::new();
    let mut pts: Vec<Point2<f64>> = Vec::new();
    // each vertex placed once in midpoint–radius form, for the filter of
    // the triangles' orientations
    let tiv = t.interval();
    let mut mids: Vec<Option<crate::geom::MidRad>> = Vec::new();
    for (i, body) in world.bodies().iter().enumerate() {
        if !body.alive {
            continue;
        }
        let base = atts.len();
        let ids = world.ids(BodyId(i as u32));
        let n = ids.len();
        for (x, &v) in ids.iter().enumerate() {
            let a = Att::vertex(BodyId(i as u32), v);
            atts.push(a);
            mids.push(world.mid_rad(a, tiv));
            // (the exact position is not kept: the filter decides almost
            // every orientation, and the few it does not place their
            // points again)
            let f = world.position(a, t).expect("a finite point").to_f64();
            pts.push(Point2::new(f[0], f[1]));
            edges.push([base + x, base + (x + 1) % n]);
        }
        if let Some(eps) = shrink {
            let body_pts = &mut pts[base..];
            let c = body_pts
                .iter()
                .fold([0.0, 0.0], |c, p| [c[0] + p.x, c[1] + p.y]);
            let c = [c[0] / n as f64, c[1] / n as f64];
            for p in body_pts {
                *p = Point2::new(p.x + eps * (c[0] - p.x), p.y + eps * (c[1] - p.y));
            }
        }
    }
    let alive = world.bodies().iter().filter(|b| b.alive).count();
    if alive < 2 {
        return Ok(Kss::default());
    }
    // the doubles triangulated, exactly (for the orientation of a triangle
    // that is flat in exact coordinates)
    let rounded: Vec<Point> = match shrink {
        Some(_) => pts
            .iter()
            .map(|p| Point::from_f64([p.x, p.y]).expect("finite"))
            .collect(),
        None => Vec::new(),
    };
    let mut conflict = false;
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(pts, edges, |_| conflict = true)
            .map_err(|e| BuildError::Rounding(format!("{e:?}")))?;
    if conflict || cdt.num_vertices() != atts.len() {
        return Err(BuildError::Rounding(
            "vertices or edges coincide after rounding to doubles".into(),
        ));
    }
    // All finite triangles, oriented CCW exactly.
    let raw: Vec<[usize; 3]> = cdt
        .inner_faces()
        .map(|f| f.vertices().map(|h| h.fix().index()))
        .collect();
    // the exact orientation at `t`, through the f64 filter (which decides
    // a sign only where it is the exact one at every time in `t`'s
    // enclosure)
    let exact = |u: usize| world.position(atts[u], t).expect("a finite point");
    let exact_sign = |[u, v, w]: [usize; 3]| {
        let filtered = match (mids[u], mids[v], mids[w]) {
            (Some(a), Some(b), Some(c)) => crate::geom::orient_mid_rad(a, b, c),
            _ => None,
        };
        filtered.unwrap_or_else(|| orient(&exact(u), &exact(v), &exact(w)))
    };
    let raw = match shrink {
        None => split_flat_triangles(raw, &exact, &exact_sign)?,
        Some(_) => raw,
    };
    let mut tris: Vec<[usize; 3]> = Vec::with_capacity(raw.len());
    let mut directed: FastMap<(usize, usize), ()> = FastMap::default();
    for [u, v, w] in raw {
        let sign = exact_sign([u, v, w]);
        let sign = match shrink {
            None => sign,
            Some(_) => shrunk_orientation(sign, orient(&rounded[u], &rounded[v], &rounded[w]))
                .ok_or_else(|| {
                    BuildError::Rounding(
                        "the shrunk triangulation is not valid with exact coordinates".into(),
                    )
                })?,
        };
        let tri = match sign {
            Sign::Positive => [u, v, w],
            Sign::Negative => [u, w, v],
            Sign::Zero => return Err(BuildError::Rounding("a flat triangle".into())),
        };
        for i in 0..3 {
            directed.insert((tri[i], tri[(i + 1) % 3]), ());
        }
        tris.push(tri);
    }
    // Convex hull edges (CCW): directed edges whose reverse is in no triangle.
    let mut hull: Vec<(usize, usize)> = directed
        .keys()
        .filter(|&&(u, v)| !directed.contains_key(&(v, u)))
        .copied()
        .collect();
    hull.sort_unstable();
    let same = |x: usize, y: usize| atts[x].obj == atts[y].obj;
    // Free-space triangles as attachment triples (ω for the infinite ones).
    let mut faces: Vec<[Att; 3]> = Vec::new();
    for tri in &tris {
        let [u, v, w] = *tri;
        if same(u, v) && same(v, w) {
            continue; // inside a polygon
        }
        faces.push([atts[u], atts[v], atts[w]]);
    }
    for &(u, v) in &hull {
        faces.push([atts[v], atts[u], Att::OMEGA]);
    }
    // Check that two corners on one body are adjacent on it (no chords).
    for f in &faces {
        for i in 0..3 {
            let (x, y) = (f[i], f[(i + 1) % 3]);
            if let (Obj::Body(b), true) = (x.obj, x.obj == y.obj) {
                if world.ccw(x) != y && world.ccw(y) != x {
                    return Err(BuildError::Rounding(format!(
                        "a triangle side cuts through body {}",
                        world.body(b).id
                    )));
                }
            }
        }
    }
    // Adjacency: directed side -> (face, side index).
    let mut side_of: FastMap<(Att, Att), (usize, usize)> =
        FastMap::with_capacity_and_hasher(3 * faces.len(), Default::default());
    for (fi, f) in faces.iter().enumerate() {
        for i in 0..3 {
            side_of.insert((f[i], f[(i + 1) % 3]), (fi, i));
        }
    }
    let mut tri_id: FastMap<usize, TriId> = FastMap::default();
    let mut kss = Kss::default();
    for (fi, f) in faces.iter().enumerate() {
        if is_partition(f) {
            tri_id.insert(fi, TriId(kss.tris.len() as u32));
            kss.tris.push(PartitionTriangle {
                c: *f,
                corr: [CorrId(u32::MAX); 3],
            });
        }
    }
    // Walk each corridor from a partition-triangle side whose first corner is finite.
    for ti in 0..kss.tris.len() {
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
            let (mut x, mut y) = (p, q); // the side we cross, in the current face's order
            let end = loop {
                let &(fj, sj) = side_of
                    .get(&(y, x))
                    .ok_or_else(|| BuildError::Rounding("a side without neighbour".into()))?;
                let g = &faces[fj];
                if is_partition(g) {
                    break (tri_id[&fj], sj as u8);
                }
                let on_a;
                ((x, y), on_a) = cross_two_object_face(g, sj, p.obj);
                if on_a {
                    len_a += 1;
                } else {
                    len_b += 1;
                }
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
        return Err(BuildError::Rounding(
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

/// Remove the triangles that are flat for the exact coordinates. Rounding to
/// doubles can make three points of one line a thin triangle: the
/// hierarchy's approximation vertices are rationals, and bodies with edges
/// on a common line put several vertices on it. A flat triangle `(u, v, w)`
/// with `v` between `u` and `w` is removed by splitting its long side at
/// `v`: the triangle across that side, `(w, u, x)`, becomes `(u, v, x)` and
/// `(v, w, x)`; on the hull there is no such triangle and the hull runs
/// through `v`.
fn split_flat_triangles(
    mut tris: Vec<[usize; 3]>,
    exact: &dyn Fn(usize) -> Point,
    sign: &dyn Fn([usize; 3]) -> Sign,
) -> Result<Vec<[usize; 3]>, BuildError> {
    let flat = |t: &[usize; 3]| sign(*t) == Sign::Zero;
    // `m` strictly between `a` and `b` on their line
    let between = |a: usize, m: usize, b: usize| {
        let pm = exact(m);
        exact(a).sub(&pm).dot(&exact(b).sub(&pm)).sign() == Sign::Negative
    };
    for _ in 0..4 * tris.len() + 16 {
        let Some(fi) = tris.iter().position(flat) else {
            return Ok(tris);
        };
        let [p, q, r] = tris[fi];
        let (u, v, w) = if between(q, p, r) {
            (q, p, r)
        } else if between(p, q, r) {
            (p, q, r)
        } else if between(p, r, q) {
            (p, r, q)
        } else {
            return Err(BuildError::Rounding(
                "a triangle with coincident corners".into(),
            ));
        };
        tris.swap_remove(fi);
        if let Some(gi) = tris.iter().position(|t| t.contains(&u) && t.contains(&w)) {
            let g = tris.swap_remove(gi);
            let x = *g
                .iter()
                .find(|&&y| y != u && y != w)
                .expect("a triangle has three corners");
            tris.push([u, v, x]);
            tris.push([v, w, x]);
        }
    }
    Err(BuildError::Rounding("a flat triangle".into()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gen::{generate_small, Family};
    use crate::structure::geo::Geo;
    use crate::world::World;

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
        let k = crate::structure::engine::Kinetic::new(&world, &at).unwrap();
        let now = crate::num::Time::from_rational(at.clone());
        let next = k
            .next_time()
            .expect("b reaches the end of a's edge")
            .clone();
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

    fn pt(x: i64, y: i64) -> Point {
        Point::from_f64([x as f64, y as f64]).expect("finite")
    }

    #[test]
    fn a_flat_triangle_is_split_at_its_middle_point() {
        // u, v, w on one line; x above it
        let exact = [pt(0, 0), pt(1, 0), pt(2, 0), pt(1, 1)];
        let sign = |t: [usize; 3]| orient(&exact[t[0]], &exact[t[1]], &exact[t[2]]);
        let point = |i: usize| exact[i].clone();
        let out = split_flat_triangles(vec![[0, 1, 2], [2, 0, 3]], &point, &sign).unwrap();
        assert_eq!(out.len(), 2);
        for t in &out {
            assert_ne!(orient(&exact[t[0]], &exact[t[1]], &exact[t[2]]), Sign::Zero);
            assert!(t.contains(&1) && t.contains(&3));
        }
        // on the hull: dropped
        assert!(split_flat_triangles(vec![[0, 1, 2]], &point, &sign)
            .unwrap()
            .is_empty());
        // coincident corners are an error
        let same = [pt(0, 0), pt(0, 0), pt(2, 0)];
        let sign = |t: [usize; 3]| orient(&same[t[0]], &same[t[1]], &same[t[2]]);
        let point = |i: usize| same[i].clone();
        assert!(split_flat_triangles(vec![[0, 1, 2]], &point, &sign).is_err());
    }
}
