//! Benchmarks of the exact kernel: certificate construction (`orient_poly`),
//! failure times (`first_failure_after`), time comparisons and sign
//! evaluations, on inputs shaped like a simulation's (bodies with full-mantissa
//! double coordinates, at unit and 1e6 scales, on linear trajectories).
//!
//! The last target, `filter_fractions`, times nothing: it prints the share of
//! time comparisons the f64 interval filter decides (the rest need exact
//! big-integer arithmetic) for (a) random times, (b) an event-queue workload
//! (failure times of random certificates pushed through a `BinaryHeap`), in a
//! generic and in a tie-heavy (grid-aligned) variant, and (c) deliberate
//! near-ties.
//!
//! Run with `cargo bench -p kss --bench kernel`.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use kss::geom::{BodyPolygon, Point};
use kss::motion::{orient_poly, Frame, LinearPoint, Trajectory};
use kss::num::{filter_stats, reset_filter_stats, FilterStats, Int, Poly, Rational, Time};
use kss::rng::Rng;

/// A convex body moving on one linear trajectory, in integer frame form.
struct Body {
    poly: BodyPolygon,
    frame: Frame,
}

impl Body {
    fn vertex(&self, i: usize) -> LinearPoint {
        self.frame.vertex(&self.poly, i % self.poly.len())
    }
}

/// How coordinates are drawn.
#[derive(Clone, Copy)]
enum Style {
    /// Full-mantissa doubles (e.g. 0.1234567…) at scale `extent`.
    Generic { extent: f64 },
    /// Grid-aligned values (multiples of 1/4, integer velocities): many
    /// certificates fail at exactly the same times.
    Grid,
}

/// A jittered regular polygon (3 to 8 vertices) on a linear trajectory.
fn random_body(rng: &mut Rng, style: Style) -> Body {
    loop {
        let n = rng.range_usize(3, 8);
        let verts: Vec<[f64; 2]> = match style {
            Style::Generic { .. } => {
                let r = rng.range_f64(0.5, 5.0);
                let phase = rng.range_f64(0.0, 1.0);
                (0..n)
                    .map(|k| {
                        let a = std::f64::consts::TAU * (k as f64 + phase) / n as f64;
                        let rr = r * rng.range_f64(0.97, 1.03);
                        [rr * a.cos(), rr * a.sin()]
                    })
                    .collect()
            }
            Style::Grid => {
                let w = rng.range_i64(1, 4) as f64;
                let h = rng.range_i64(1, 4) as f64;
                vec![[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]]
            }
        };
        let Ok(poly) = BodyPolygon::new(&verts) else {
            continue;
        };
        let (t0, pos, vel) = match style {
            Style::Generic { extent } => (
                rng.range_f64(0.0, 100.0),
                [
                    rng.range_f64(-extent, extent),
                    rng.range_f64(-extent, extent),
                ],
                [rng.range_f64(-50.0, 50.0), rng.range_f64(-50.0, 50.0)],
            ),
            Style::Grid => (
                0.0,
                [
                    rng.range_i64(-40, 40) as f64 * 0.25,
                    rng.range_i64(-40, 40) as f64 * 0.25,
                ],
                [rng.range_i64(-3, 3) as f64, rng.range_i64(-3, 3) as f64],
            ),
        };
        let traj = Trajectory::through(
            &Rational::from_f64(t0).expect("finite"),
            &Point::from_f64(pos).expect("finite"),
            Point::from_f64(vel).expect("finite"),
        );
        let frame = Frame::new(&traj, &poly);
        return Body { poly, frame };
    }
}

/// A uniform index in `[0, n)`.
fn idx(rng: &mut Rng, n: usize) -> usize {
    rng.below(n as u64) as usize
}

fn random_bodies(rng: &mut Rng, n: usize, style: Style) -> Vec<Body> {
    (0..n).map(|_| random_body(rng, style)).collect()
}

/// Three moving points whose orientation is a certificate: an edge of one
/// body and a vertex of another (`quadratic == false`, degree <= 1), or
/// vertices of three different bodies (degree 2).
fn random_triple(rng: &mut Rng, bodies: &[Body], quadratic: bool) -> [LinearPoint; 3] {
    let n = bodies.len();
    let a = idx(rng, n);
    let b = (a + 1 + idx(rng, n - 1)) % n;
    if quadratic {
        let mut c = idx(rng, n);
        while c == a || c == b {
            c = idx(rng, n);
        }
        [
            bodies[a].vertex(idx(rng, 8)),
            bodies[b].vertex(idx(rng, 8)),
            bodies[c].vertex(idx(rng, 8)),
        ]
    } else {
        let i = idx(rng, 8);
        [
            bodies[a].vertex(i),
            bodies[a].vertex(i + 1),
            bodies[b].vertex(idx(rng, 8)),
        ]
    }
}

fn random_certs(rng: &mut Rng, bodies: &[Body], n: usize, quadratic: bool) -> Vec<Poly> {
    (0..n)
        .map(|_| {
            let [p, q, r] = random_triple(rng, bodies, quadratic);
            orient_poly(&p, &q, &r)
        })
        .collect()
}

/// The real roots of a set of certificates (irrational ones for quadratics).
fn roots_of(certs: &[Poly]) -> Vec<Time> {
    certs.iter().flat_map(|c| c.roots()).collect()
}

/// The next double above a finite `x` (`f64::next_up` needs Rust 1.86,
/// above the crate's MSRV).
fn next_up(x: f64) -> f64 {
    if x == 0.0 {
        f64::from_bits(1)
    } else if x > 0.0 {
        f64::from_bits(x.to_bits() + 1)
    } else {
        f64::from_bits(x.to_bits() - 1)
    }
}

/// Near-ties: each root against a double next to it, or against a root of
/// the certificate perturbed by one unit in its constant term.
fn near_tie_pairs(roots: &[Time]) -> Vec<(Time, Time)> {
    let mut out = Vec::new();
    for (k, r) in roots.iter().enumerate() {
        let x = r.to_f64();
        let other = match k % 3 {
            0 => Time::from_f64(x),
            1 => Time::from_f64(next_up(x)),
            _ => Time::from_f64(r.interval().lo),
        };
        if let Some(o) = other {
            out.push((r.clone(), o));
        }
    }
    out
}

fn perturbed_pairs(certs: &[Poly]) -> Vec<(Time, Time)> {
    let mut out = Vec::new();
    for c in certs {
        let p = Poly::new(
            c.coeff(0) + Int::ONE,
            c.coeff(1).clone(),
            c.coeff(2).clone(),
        );
        for (a, b) in c.roots().into_iter().zip(p.roots()) {
            out.push((a, b));
        }
    }
    out
}

fn config() -> Criterion {
    Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
}

/// `orient_poly` for two-body (linear) and three-body (quadratic)
/// certificates, at unit and 1e6 scales.
fn bench_certificates(c: &mut Criterion) {
    let mut rng = Rng::new(1);
    for (name, extent) in [("unit", 10.0), ("1e6", 1e6)] {
        let bodies = random_bodies(&mut rng, 16, Style::Generic { extent });
        for quadratic in [false, true] {
            let triples: Vec<[LinearPoint; 3]> = (0..256)
                .map(|_| random_triple(&mut rng, &bodies, quadratic))
                .collect();
            let kind = if quadratic {
                "three_body_quadratic"
            } else {
                "two_body_linear"
            };
            let mut i = 0;
            c.bench_function(&format!("orient_poly/{kind}/{name}"), |b| {
                b.iter(|| {
                    i = (i + 1) % triples.len();
                    let [p, q, r] = &triples[i];
                    black_box(orient_poly(p, q, r))
                })
            });
        }
    }
}

/// `first_failure_after` on linear and quadratic certificates.
fn bench_failure(c: &mut Criterion) {
    let mut rng = Rng::new(2);
    let bodies = random_bodies(&mut rng, 16, Style::Generic { extent: 1e3 });
    let now = Time::from_f64(50.0).expect("finite");
    for quadratic in [false, true] {
        let certs = random_certs(&mut rng, &bodies, 256, quadratic);
        let kind = if quadratic { "quadratic" } else { "linear" };
        let mut i = 0;
        c.bench_function(&format!("first_failure_after/{kind}"), |b| {
            b.iter(|| {
                i = (i + 1) % certs.len();
                black_box(certs[i].first_failure_after(&now))
            })
        });
    }
}

/// Time comparisons: random pairs (roots of certificates and doubles), and
/// near-ties that the filter cannot decide.
fn bench_compare(c: &mut Criterion) {
    let mut rng = Rng::new(3);
    let bodies = random_bodies(&mut rng, 16, Style::Generic { extent: 1e3 });
    let certs = random_certs(&mut rng, &bodies, 512, true);
    let mut times = roots_of(&certs);
    times.extend((0..256).map(|_| Time::from_f64(rng.range_f64(-100.0, 100.0)).expect("finite")));
    rng.shuffle(&mut times);
    let pairs: Vec<(Time, Time)> = times
        .chunks(2)
        .filter(|p| p.len() == 2)
        .map(|p| (p[0].clone(), p[1].clone()))
        .collect();
    let mut i = 0;
    c.bench_function("cmp/random", |b| {
        b.iter(|| {
            i = (i + 1) % pairs.len();
            black_box(pairs[i].0.cmp(&pairs[i].1))
        })
    });
    let roots = roots_of(&certs);
    let near = near_tie_pairs(&roots);
    let mut i = 0;
    c.bench_function("cmp/near_tie_root_vs_double", |b| {
        b.iter(|| {
            i = (i + 1) % near.len();
            black_box(near[i].0.cmp(&near[i].1))
        })
    });
    let perturbed = perturbed_pairs(&certs);
    let mut i = 0;
    c.bench_function("cmp/near_tie_root_vs_root", |b| {
        b.iter(|| {
            i = (i + 1) % perturbed.len();
            black_box(perturbed[i].0.cmp(&perturbed[i].1))
        })
    });
}

/// `sign_at` of quadratic certificates at rational times and at the
/// (irrational) roots of other certificates, and at their own roots (which
/// always needs the exact path).
fn bench_sign(c: &mut Criterion) {
    let mut rng = Rng::new(4);
    let bodies = random_bodies(&mut rng, 16, Style::Generic { extent: 1e3 });
    let certs = random_certs(&mut rng, &bodies, 256, true);
    let rational: Vec<Time> = (0..256)
        .map(|_| Time::from_f64(rng.range_f64(0.0, 100.0)).expect("finite"))
        .collect();
    let roots = roots_of(&certs);
    let own: Vec<(usize, Time)> = certs
        .iter()
        .enumerate()
        .flat_map(|(k, c)| c.roots().into_iter().map(move |r| (k, r)))
        .collect();
    let mut i = 0;
    c.bench_function("sign_at/rational", |b| {
        b.iter(|| {
            i = (i + 1) % certs.len();
            black_box(certs[i].sign_at(&rational[i]))
        })
    });
    let mut i = 0;
    c.bench_function("sign_at/foreign_root", |b| {
        b.iter(|| {
            i = (i + 1) % certs.len();
            black_box(certs[i].sign_at(&roots[(i * 7 + 3) % roots.len()]))
        })
    });
    let mut i = 0;
    c.bench_function("sign_at/own_root", |b| {
        b.iter(|| {
            i = (i + 1) % own.len();
            black_box(certs[own[i].0].sign_at(&own[i].1))
        })
    });
}

fn report(what: &str, s: FilterStats) {
    println!(
        "filter fraction, {what}: {:.4} ({} filtered, {} exact)",
        s.filter_fraction(),
        s.filtered,
        s.exact
    );
}

/// The event-queue workload: failure times of random certificates after
/// `now`, then pushed through a min-heap and popped in order.
fn queue_workload(rng: &mut Rng, style: Style, label: &str) {
    let bodies = random_bodies(rng, 24, style);
    let mut certs = random_certs(rng, &bodies, 3000, false);
    certs.extend(random_certs(rng, &bodies, 3000, true));
    let now = Time::zero();
    reset_filter_stats();
    let failures: Vec<Time> = certs
        .iter()
        .filter_map(|c| c.first_failure_after(&now))
        .collect();
    report(
        &format!(
            "{label}: first_failure_after of {} certificates (signs + comparisons)",
            certs.len()
        ),
        filter_stats(),
    );
    reset_filter_stats();
    let mut heap = BinaryHeap::new();
    for t in &failures {
        heap.push(Reverse(t.clone()));
    }
    let mut popped = Vec::with_capacity(failures.len());
    while let Some(Reverse(t)) = heap.pop() {
        popped.push(t);
    }
    let s = filter_stats();
    // (outside the measurement) the order is right; count the exact ties
    assert!(popped.windows(2).all(|w| w[0] <= w[1]));
    let ties = popped.windows(2).filter(|w| w[0] == w[1]).count();
    report(
        &format!(
            "{label}: BinaryHeap of {} failure times ({ties} equal to their predecessor)",
            failures.len()
        ),
        s,
    );
}

/// Not a timed benchmark: prints the filter fractions of three workloads.
fn filter_fractions(_c: &mut Criterion) {
    let mut rng = Rng::new(5);
    // (a) random times: roots of random certificates and random doubles
    let bodies = random_bodies(&mut rng, 16, Style::Generic { extent: 1e3 });
    let certs = random_certs(&mut rng, &bodies, 2000, true);
    let mut times = roots_of(&certs);
    times.extend((0..1000).map(|_| Time::from_f64(rng.range_f64(-100.0, 100.0)).expect("finite")));
    rng.shuffle(&mut times);
    reset_filter_stats();
    for p in times.chunks(2).filter(|p| p.len() == 2) {
        black_box(p[0].cmp(&p[1]));
    }
    report(
        &format!("(a) {} random pairs of times", times.len() / 2),
        filter_stats(),
    );

    // (b) event-queue workloads
    queue_workload(
        &mut rng,
        Style::Generic { extent: 1e3 },
        "(b) generic scene",
    );
    queue_workload(&mut rng, Style::Grid, "(b') grid-aligned scene");

    // (c) deliberate near-ties
    let near = near_tie_pairs(&roots_of(&certs));
    reset_filter_stats();
    for (a, b) in &near {
        black_box(a.cmp(b));
    }
    report(
        &format!("(c) {} near-ties, root vs adjacent double", near.len()),
        filter_stats(),
    );
    let perturbed = perturbed_pairs(&certs);
    reset_filter_stats();
    for (a, b) in &perturbed {
        black_box(a.cmp(b));
    }
    report(
        &format!(
            "(c) {} near-ties, root vs root of perturbed certificate",
            perturbed.len()
        ),
        filter_stats(),
    );
}

criterion_group! {
    name = kernel;
    config = config();
    targets = bench_certificates, bench_failure, bench_compare, bench_sign, filter_fractions
}
criterion_main!(kernel);
