//! Exact degeneracies on the integer lattice: [`simultaneous`], [`grazing`]
//! and [`parallel`], built by a [`Lattice`] of small integer polygons.

use super::InvalidParams;
use std::f64::consts::TAU;

use super::hull::hull_i64;
use super::{check_mode_until, check_or_panic};
use crate::rng::Rng;
use crate::scenario::{CollisionMode, FlightPlanChange, PolygonSpec, Scenario};

/// A pair of polygons whose first contact is planned: `a < b` (byte-wise)
/// first touch exactly at `time` (their closed sets are disjoint before it).
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedContact {
    /// Byte-wise smaller id.
    pub a: String,
    /// Byte-wise larger id.
    pub b: String,
    /// The exact instant of first contact (a small integer).
    pub time: f64,
}

/// Parameters of [`simultaneous`].
#[derive(Clone, Debug, PartialEq)]
pub struct SimultaneousParams {
    /// Number of pairs first touching at the common instant.
    pub pairs: usize,
    /// Also three polygons meeting at one point at that instant.
    pub triple: bool,
    /// Collision mode.
    pub mode: CollisionMode,
    /// End of the interval (default: a little after the contacts).
    pub until: Option<f64>,
    /// Small shapes and short times (for test sweeps).
    pub small: bool,
    /// The seed (shapes, offsets, velocities, orientation).
    pub seed: u64,
}

impl Default for SimultaneousParams {
    fn default() -> Self {
        SimultaneousParams {
            pairs: 3,
            triple: true,
            mode: CollisionMode::Stop,
            until: None,
            small: false,
            seed: 0,
        }
    }
}

impl SimultaneousParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), InvalidParams> {
        if self.pairs == 0 && !self.triple {
            return Err(InvalidParams(
                "no pairs and no triple: nothing to generate".to_string(),
            ));
        }
        if self.pairs > 100_000 {
            return Err(InvalidParams(format!(
                "pairs is {}: at most 100000",
                self.pairs
            )));
        }
        check_mode_until(self.until)
    }
}

/// Parameters of [`grazing`] and [`parallel`].
#[derive(Clone, Debug, PartialEq)]
pub struct DegenerateParams {
    /// Number of pairs.
    pub pairs: usize,
    /// Collision mode.
    pub mode: CollisionMode,
    /// End of the interval (default: a little after the last planned contact).
    pub until: Option<f64>,
    /// Small shapes and short times (for test sweeps).
    pub small: bool,
    /// The seed (shapes, offsets, velocities, orientation).
    pub seed: u64,
}

impl Default for DegenerateParams {
    fn default() -> Self {
        DegenerateParams {
            pairs: 4,
            mode: CollisionMode::Stop,
            until: None,
            small: false,
            seed: 0,
        }
    }
}

impl DegenerateParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), InvalidParams> {
        if self.pairs == 0 {
            return Err(InvalidParams("pairs is 0: nothing to generate".to_string()));
        }
        if self.pairs > 100_000 {
            return Err(InvalidParams(format!(
                "pairs is {}: at most 100000",
                self.pairs
            )));
        }
        check_mode_until(self.until)
    }
}

/// Several pairs of lattice polygons that first touch at exactly the same
/// instant `T` (vertex–edge, vertex–vertex or edge–edge, chosen at random),
/// and, with `triple`, three polygons whose apexes meet at one point at `T`.
/// Pairs live in lanes far apart. Pairs are `a<i>`/`b<i>`, the triple
/// `t0`, `t1`, `t2`.
///
/// # Panics
///
/// If [`SimultaneousParams::check`] fails.
pub fn simultaneous(params: &SimultaneousParams) -> Scenario {
    simultaneous_with_contacts(params).0
}

/// [`simultaneous`] with the planned first contacts.
///
/// # Panics
///
/// If [`SimultaneousParams::check`] fails.
pub fn simultaneous_with_contacts(params: &SimultaneousParams) -> (Scenario, Vec<PlannedContact>) {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 4);
    let t = rng.range_i64(1, if params.small { 3 } else { 4 });
    let mut lat = Lattice::new(params.small);
    for i in 0..params.pairs {
        let kind = if rng.chance(0.25) {
            PairKind::FlushApproach
        } else {
            PairKind::Approach
        };
        lat.pair(&mut rng, kind, t, i);
    }
    if params.triple {
        lat.triple(&mut rng, t, params.pairs);
    }
    lat.finish(&mut rng, params.mode, params.until)
}

/// Pairs of lattice polygons that touch tangentially: relative motion exactly
/// parallel to the separating line, so that a vertex slides along the line of
/// an edge and reaches it, or two vertices graze each other for an instant.
/// Each pair has its own integer contact time.
///
/// # Panics
///
/// If [`DegenerateParams::check`] fails.
pub fn grazing(params: &DegenerateParams) -> Scenario {
    grazing_with_contacts(params).0
}

/// [`grazing`] with the planned first contacts.
///
/// # Panics
///
/// If [`DegenerateParams::check`] fails.
pub fn grazing_with_contacts(params: &DegenerateParams) -> (Scenario, Vec<PlannedContact>) {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 5);
    let mut lat = Lattice::new(params.small);
    for i in 0..params.pairs {
        let t = rng.range_i64(1, if params.small { 3 } else { 4 });
        lat.pair(&mut rng, PairKind::Graze, t, i);
    }
    lat.finish(&mut rng, params.mode, params.until)
}

/// Pairs of lattice polygons with edges on a common line: sliding along it
/// until their corners meet and the edges go on flush, or edges hitting each
/// other flat. Each pair has its own integer contact time.
///
/// # Panics
///
/// If [`DegenerateParams::check`] fails.
pub fn parallel(params: &DegenerateParams) -> Scenario {
    parallel_with_contacts(params).0
}

/// [`parallel`] with the planned first contacts.
///
/// # Panics
///
/// If [`DegenerateParams::check`] fails.
pub fn parallel_with_contacts(params: &DegenerateParams) -> (Scenario, Vec<PlannedContact>) {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 6);
    let mut lat = Lattice::new(params.small);
    for i in 0..params.pairs {
        let t = rng.range_i64(1, if params.small { 3 } else { 4 });
        let kind = if rng.chance(0.65) {
            PairKind::Slide
        } else {
            PairKind::FlushApproach
        };
        lat.pair(&mut rng, kind, t, i);
    }
    lat.finish(&mut rng, params.mode, params.until)
}

/// How the two polygons of a lattice pair meet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PairKind {
    /// B comes down onto A, with a random sideways component.
    Approach,
    /// Two horizontal edges come together flat, overlapping.
    FlushApproach,
    /// Sideways motion along the separating line; at least one face is a vertex.
    Graze,
    /// Sideways motion along the separating line; both faces are edges.
    Slide,
}

/// A polygon being built on the lattice (canonical frame).
struct LatticeBody {
    id: String,
    vertices: Vec<[i64; 2]>,
    /// Position at the contact time `t`.
    pos_t: [i64; 2],
    velocity: [i64; 2],
    fixed: bool,
    /// The contact time of its group.
    t: i64,
}

/// Builds degenerate scenes in a canonical frame: in each pair, A is below the
/// horizontal separating line and B above it. Lanes are far apart along x. At
/// the end an orientation-preserving integer matrix and a power-of-two scale
/// are applied to everything, which keeps every contact time and every
/// degeneracy exact.
struct Lattice {
    bodies: Vec<LatticeBody>,
    contacts: Vec<(String, String, i64)>,
    small: bool,
}

const LANE: i64 = 160;

impl Lattice {
    fn new(small: bool) -> Lattice {
        Lattice {
            bodies: Vec::new(),
            contacts: Vec::new(),
            small,
        }
    }

    fn radius(&self, rng: &mut Rng) -> i64 {
        rng.range_i64(2, if self.small { 4 } else { 5 })
    }

    fn target_n(&self, rng: &mut Rng) -> usize {
        rng.range_usize(3, if self.small { 9 } else { 12 })
    }

    fn pair(&mut self, rng: &mut Rng, kind: PairKind, t: i64, lane: usize) {
        let (edge_a, edge_b) = match kind {
            PairKind::Approach => (rng.chance(0.5), rng.chance(0.5)),
            PairKind::FlushApproach | PairKind::Slide => (true, true),
            PairKind::Graze => match rng.below(3) {
                0 => (false, false),
                1 => (true, false),
                _ => (false, true),
            },
        };
        let (ra, na) = (self.radius(rng), self.target_n(rng));
        let a = lattice_polygon(rng, na, ra);
        let a = with_face(rng, a, edge_a, true);
        let (rb, nb) = (self.radius(rng), self.target_n(rng));
        let b = lattice_polygon(rng, nb, rb);
        let b = with_face(rng, b, edge_b, false);
        let (ha, a1, a2) = face(&a, true);
        let (lb, b1, b2) = face(&b, false);
        let dir = if rng.chance(0.5) { 1 } else { -1 };
        let s = match kind {
            PairKind::Approach => rng.range_i64(a1 - b2, a2 - b1),
            PairKind::FlushApproach => rng.range_i64(a1 - b2 + 1, a2 - b1 - 1),
            PairKind::Graze | PairKind::Slide => {
                if dir > 0 {
                    a1 - b2
                } else {
                    a2 - b1
                }
            }
        };
        let w = match kind {
            PairKind::Approach => [rng.range_i64(-2, 2), -rng.range_i64(1, 3)],
            PairKind::FlushApproach => [0, -rng.range_i64(1, 3)],
            PairKind::Graze | PairKind::Slide => [dir * rng.range_i64(1, 3), 0],
        };
        let fixed = rng.chance(0.3);
        let va = if fixed {
            [0, 0]
        } else {
            [rng.range_i64(-2, 2), rng.range_i64(-2, 2)]
        };
        let origin = [lane as i64 * LANE, 0];
        let (ida, idb) = (format!("a{lane}"), format!("b{lane}"));
        self.contacts.push((ida.clone(), idb.clone(), t));
        self.bodies.push(LatticeBody {
            id: ida,
            vertices: a,
            pos_t: origin,
            velocity: va,
            fixed,
            t,
        });
        self.bodies.push(LatticeBody {
            id: idb,
            vertices: b,
            pos_t: [origin[0] + s, origin[1] + ha - lb],
            velocity: [va[0] + w[0], va[1] + w[1]],
            fixed: false,
            t,
        });
    }

    /// Three polygons in disjoint angular sectors around a common apex, each
    /// moving towards the apex from inside its sector: they meet at the apex at
    /// time `t`, and only there.
    fn triple(&mut self, rng: &mut Rng, t: i64, lane: usize) {
        let k = rng.range_i64(3, 5);
        // First quadrant, directions between (4,1) and (1,4).
        let c1: Vec<[i64; 2]> = vec![[0, 0], [4, 1], [k, k], [1, 4]];
        // Its mirror image in the y axis (order reversed to stay CCW).
        let mut c2: Vec<[i64; 2]> = c1.iter().map(|p| [-p[0], p[1]]).collect();
        c2.reverse();
        c2.rotate_right(1);
        // Pointing down, directions between (-1,-3) and (1,-3).
        let c3: Vec<[i64; 2]> = vec![[0, 0], [-1, -3], [0, -4], [1, -3]];
        let mut shapes = [c1, c2, c3];
        for shape in shapes.iter_mut() {
            let f = rng.range_i64(1, 2);
            for p in shape.iter_mut() {
                *p = [p[0] * f, p[1] * f];
            }
        }
        let m = [
            rng.range_i64(1, 2),
            rng.range_i64(1, 2),
            rng.range_i64(1, 2),
        ];
        let vel = [[-m[0], -m[0]], [m[1], -m[1]], [0, m[2]]];
        let fixed_one = if rng.chance(0.3) {
            Some(rng.below(3) as usize)
        } else {
            None
        };
        let apex = [lane as i64 * LANE, 0];
        let ids = ["t0", "t1", "t2"];
        for (i, shape) in shapes.into_iter().enumerate() {
            let fixed = fixed_one == Some(i);
            self.bodies.push(LatticeBody {
                id: ids[i].to_string(),
                vertices: shape,
                pos_t: apex,
                velocity: if fixed { [0, 0] } else { vel[i] },
                fixed,
                t,
            });
        }
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            self.contacts
                .push((ids[i].to_string(), ids[j].to_string(), t));
        }
    }

    /// Applies a random orientation-preserving lattice map and dyadic scale,
    /// adds flight-plan changes at or after the contacts, and builds the
    /// scenario.
    fn finish(
        self,
        rng: &mut Rng,
        mode: CollisionMode,
        until: Option<f64>,
    ) -> (Scenario, Vec<PlannedContact>) {
        const MAPS: [[i64; 4]; 6] = [
            [1, 0, 0, 1],
            [1, 1, 0, 1],
            [1, 0, 1, 1],
            [1, -1, 1, 1],
            [2, 1, 1, 1],
            [1, 2, 0, 1],
        ];
        const ROTS: [[i64; 4]; 4] = [[1, 0, 0, 1], [0, -1, 1, 0], [-1, 0, 0, -1], [0, 1, -1, 0]];
        let a = *rng.pick(&MAPS).expect("maps");
        let r = *rng.pick(&ROTS).expect("rotations");
        // m = r * a, row-major [m00, m01, m10, m11].
        let m = [
            r[0] * a[0] + r[1] * a[2],
            r[0] * a[1] + r[1] * a[3],
            r[2] * a[0] + r[3] * a[2],
            r[2] * a[1] + r[3] * a[3],
        ];
        let scale = 0.5f64.powi(rng.range_i64(0, 3) as i32);
        let map = |p: [i64; 2]| -> [f64; 2] {
            [
                (m[0] * p[0] + m[1] * p[1]) as f64 * scale,
                (m[2] * p[0] + m[3] * p[1]) as f64 * scale,
            ]
        };
        let t_max = self.bodies.iter().map(|b| b.t).max().unwrap_or(1);
        let until = until
            .unwrap_or_else(|| (t_max + rng.range_i64(0, if self.small { 2 } else { 3 })) as f64);
        let mut polygons = Vec::new();
        let mut changes = Vec::new();
        for body in &self.bodies {
            let p0 = [
                body.pos_t[0] - body.t * body.velocity[0],
                body.pos_t[1] - body.t * body.velocity[1],
            ];
            polygons.push(PolygonSpec {
                id: body.id.clone(),
                vertices: body.vertices.iter().map(|&v| map(v)).collect(),
                position: map(p0),
                velocity: map(body.velocity),
                fixed: body.fixed,
            });
            // A change exactly at the contact (it must act after the
            // collision) or later; never before, which keeps the contacts.
            if !body.fixed && rng.chance(0.25) {
                let time = body.t + rng.range_i64(0, 2);
                if (time as f64) <= until {
                    let v = [rng.range_i64(-2, 2), rng.range_i64(-2, 2)];
                    changes.push(FlightPlanChange {
                        time: time as f64,
                        id: body.id.clone(),
                        velocity: map(v),
                    });
                }
            }
        }
        let contacts = self
            .contacts
            .into_iter()
            .map(|(a, b, t)| {
                let (a, b) = if a.as_bytes() <= b.as_bytes() {
                    (a, b)
                } else {
                    (b, a)
                };
                PlannedContact {
                    a,
                    b,
                    time: t as f64,
                }
            })
            .collect();
        (
            Scenario {
                until,
                on_collision: mode,
                polygons,
                flight_plan_changes: changes,
                ..Default::default()
            },
            contacts,
        )
    }
}

/// A random lattice polygon: about `n` points near a circle of radius `r`,
/// rounded to integers, and their strict convex hull (at least 3 vertices).
fn lattice_polygon(rng: &mut Rng, n: usize, r: i64) -> Vec<[i64; 2]> {
    loop {
        let phase = rng.range_f64(0.0, TAU);
        let step = TAU / n as f64;
        let pts: Vec<[i64; 2]> = (0..n)
            .map(|i| {
                let a = phase + (i as f64 + 0.15 + 0.7 * rng.next_f64()) * step;
                let (s, c) = a.sin_cos();
                [(r as f64 * c).round() as i64, (r as f64 * s).round() as i64]
            })
            .collect();
        let hull = hull_i64(pts);
        if hull.len() >= 3 {
            return hull;
        }
    }
}

/// Adds a new top (`top`) or bottom face to `poly`, one row beyond it: an
/// edge (`edge`) or a single vertex.
fn with_face(rng: &mut Rng, mut poly: Vec<[i64; 2]>, edge: bool, top: bool) -> Vec<[i64; 2]> {
    let xmin = poly.iter().map(|p| p[0]).min().expect("non-empty");
    let xmax = poly.iter().map(|p| p[0]).max().expect("non-empty");
    let y = if top {
        poly.iter().map(|p| p[1]).max().expect("non-empty") + 1
    } else {
        poly.iter().map(|p| p[1]).min().expect("non-empty") - 1
    };
    if edge {
        let x1 = rng.range_i64(xmin, xmax - 1);
        let x2 = rng.range_i64(x1 + 1, xmax);
        poly.push([x1, y]);
        poly.push([x2, y]);
    } else {
        poly.push([rng.range_i64(xmin, xmax), y]);
    }
    hull_i64(poly)
}

/// The top (`top`) or bottom face of a lattice polygon: `(y, x_min, x_max)`.
fn face(poly: &[[i64; 2]], top: bool) -> (i64, i64, i64) {
    let y = if top {
        poly.iter().map(|p| p[1]).max()
    } else {
        poly.iter().map(|p| p[1]).min()
    }
    .expect("non-empty");
    let xs = poly.iter().filter(|p| p[1] == y).map(|p| p[0]);
    let lo = xs.clone().min().expect("non-empty");
    let hi = xs.max().expect("non-empty");
    (y, lo, hi)
}
