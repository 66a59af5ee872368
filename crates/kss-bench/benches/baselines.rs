//! Micro benchmarks of the narrow phases the baselines are built on: one
//! pair's exact next contact (the library's Minkowski-difference method, used
//! by brute and the kinetic sort-and-sweep) against parry2d-f64's
//! `cast_shapes`, for two regular n-gons approaching each other.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::hint::black_box;

use kss::brute::{contact_interval, PairMethod};
use kss::gen::{flypast, FlypastParams};
use kss::num::Rational;
use kss::world::{BodyId, World};
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query::{cast_shapes, ShapeCastOptions};
use parry2d_f64::shape::ConvexPolygon;

fn pair_time_of_impact(c: &mut Criterion) {
    let mut group = c.benchmark_group("pair_time_of_impact");
    for n in [8usize, 64, 1024] {
        // a colliding flypast: the pair touches once
        let scenario = flypast(&FlypastParams {
            n,
            gap: -0.01,
            ..FlypastParams::default()
        });
        let world = World::new(&scenario, None).expect("valid");
        let zero = Rational::zero();
        group.bench_with_input(BenchmarkId::new("kss_exact", n), &n, |b, _| {
            b.iter(|| {
                contact_interval(
                    black_box(&world),
                    BodyId::new(0),
                    BodyId::new(1),
                    PairMethod::Fast,
                )
                .next_contact(&zero)
            })
        });
        let shape = |i: usize| {
            let pts = scenario.polygons[i]
                .vertices
                .iter()
                .map(|v| Vector::new(v[0], v[1]))
                .collect();
            ConvexPolygon::from_convex_polyline_unmodified(pts).expect("convex")
        };
        let (sa, sb) = (shape(0), shape(1));
        let (pa, pb) = (&scenario.polygons[0], &scenario.polygons[1]);
        let pose = |p: [f64; 2]| Pose::from_translation(Vector::new(p[0], p[1]));
        let vel = |v: [f64; 2]| Vector::new(v[0], v[1]);
        group.bench_with_input(BenchmarkId::new("parry_cast_shapes", n), &n, |b, _| {
            b.iter(|| {
                cast_shapes(
                    &pose(pa.position),
                    vel(pa.velocity),
                    black_box(&sa),
                    &pose(pb.position),
                    vel(pb.velocity),
                    black_box(&sb),
                    ShapeCastOptions {
                        stop_at_penetration: false,
                        ..ShapeCastOptions::default()
                    },
                )
            })
        });
    }
    group.finish();
}

fn sweep_setup(c: &mut Criterion) {
    let mut group = c.benchmark_group("kinetic_sweep_build");
    group.sample_size(10);
    for k in [100usize, 1000] {
        let scenario = kss::gen::gas(&kss::gen::GasParams {
            k,
            walls: true,
            ..Default::default()
        });
        let world = World::new(&scenario, None).expect("valid");
        group.bench_with_input(BenchmarkId::from_parameter(k), &k, |b, _| {
            b.iter(|| kss_bench::sweep::Sweep::new(black_box(&world)))
        });
    }
    group.finish();
}

criterion_group!(benches, pair_time_of_impact, sweep_setup);
criterion_main!(benches);
