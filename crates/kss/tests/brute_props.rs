//! The brute-force reference against itself: the simple `O(n·m)` and the fast
//! Minkowski pair methods agree on thousands of generated scenarios (every
//! family, degenerate ones included), and results are invariant under
//! translation by a dyadic offset, consistent renaming, and scaling by a power
//! of two. Set `KSS_SLOW=1` for a larger sweep.

use kss::brute::PairMethod;
use kss::gen::{generate_small, Family};
use kss::num::Time;
use kss::{run, RunOptions, Scenario, StructureKind};

fn seeds() -> u64 {
    if std::env::var_os("KSS_SLOW").is_some() {
        5000
    } else {
        400
    }
}

fn events(s: &Scenario, method: PairMethod, audit: bool) -> Vec<(Time, String, String)> {
    let mut out = Vec::new();
    let opts = RunOptions {
        structure: StructureKind::Brute,
        audit,
        pair_method: method,
        ..Default::default()
    };
    run(s, &opts, &mut |e| {
        out.push((e.time.clone(), e.a.clone(), e.b.clone()))
    })
    .unwrap_or_else(|e| panic!("{e}"));
    out
}

#[test]
fn fast_and_simple_pair_methods_agree() {
    let mut total = 0usize;
    let mut with_events = 0usize;
    for family in Family::ALL {
        for seed in 0..seeds() {
            let s = generate_small(family, seed);
            // The audit after every event re-checks each cached pair time
            // with the other method as well.
            let fast = events(&s, PairMethod::Fast, true);
            let simple = events(&s, PairMethod::Simple, false);
            assert_eq!(fast, simple, "{} seed {seed}", family.name());
            total += 1;
            with_events += usize::from(!fast.is_empty());
        }
    }
    eprintln!("{total} scenarios, {with_events} with collisions");
    assert!(
        with_events * 3 > total,
        "the sweep must exercise collisions"
    );
}

fn transformed(s: &Scenario, f: impl Fn([f64; 2]) -> [f64; 2], scale_v: f64) -> Scenario {
    let mut t = s.clone();
    for p in &mut t.polygons {
        p.position = f(p.position);
        p.vertices = p
            .vertices
            .iter()
            .map(|v| [v[0] * scale_v, v[1] * scale_v])
            .collect();
        p.velocity = [p.velocity[0] * scale_v, p.velocity[1] * scale_v];
    }
    for c in &mut t.flight_plan_changes {
        c.velocity = [c.velocity[0] * scale_v, c.velocity[1] * scale_v];
    }
    t
}

/// Whether `x + y` is exact in doubles.
fn exact_sum(x: f64, y: f64) -> bool {
    use kss::num::Rational;
    let s = Rational::from_f64(x)
        .unwrap()
        .add(&Rational::from_f64(y).unwrap());
    Rational::from_f64(x + y).unwrap() == s
}

#[test]
fn invariant_under_dyadic_translation() {
    let (mut tested, mut skipped) = (0usize, 0usize);
    for family in Family::ALL {
        for seed in 0..seeds() / 5 {
            let s = generate_small(family, seed);
            let moved = transformed(&s, |p| [p[0] + 64.0, p[1] - 32.0], 1.0);
            // Only exact translations are meaningful: skip positions whose
            // shifted doubles would be rounded.
            let exact = s.polygons.iter().all(|p| {
                (p.position[0] + 64.0) - 64.0 == p.position[0]
                    && (p.position[1] - 32.0) + 32.0 == p.position[1]
                    && exact_sum(p.position[0], 64.0)
                    && exact_sum(p.position[1], -32.0)
            });
            if !exact {
                skipped += 1;
                continue;
            }
            tested += 1;
            assert_eq!(
                events(&s, PairMethod::Fast, false),
                events(&moved, PairMethod::Fast, false),
                "{} seed {seed}",
                family.name()
            );
        }
    }
    eprintln!("{tested} translated exactly, {skipped} skipped");
    assert!(tested > skipped, "most scenarios must translate exactly");
}

#[test]
fn invariant_under_power_of_two_scaling() {
    for family in Family::ALL {
        for seed in 0..seeds() / 5 {
            let s = generate_small(family, seed);
            for k in [-3, 5] {
                let f = 2f64.powi(k);
                let scaled = transformed(&s, |p| [p[0] * f, p[1] * f], f);
                assert_eq!(
                    events(&s, PairMethod::Fast, false),
                    events(&scaled, PairMethod::Fast, false),
                    "{} seed {seed} scale 2^{k}",
                    family.name()
                );
            }
        }
    }
}

#[test]
fn invariant_under_consistent_renaming() {
    for family in Family::ALL {
        for seed in 0..seeds() / 5 {
            let s = generate_small(family, seed);
            // reverse the byte order of ids by prefixing with a reversed rank
            let n = s.polygons.len();
            let rename = |id: &str| -> String {
                let rank = s.polygons.iter().position(|p| p.id == id).unwrap();
                format!("r{:03}-{id}", n - rank)
            };
            let mut r = s.clone();
            for p in &mut r.polygons {
                p.id = rename(&p.id);
            }
            for c in &mut r.flight_plan_changes {
                c.id = rename(&c.id);
            }
            let mut expected: Vec<(Time, String, String)> = events(&s, PairMethod::Fast, false)
                .into_iter()
                .map(|(t, a, b)| {
                    let (a, b) = (rename(&a), rename(&b));
                    if a < b {
                        (t, a, b)
                    } else {
                        (t, b, a)
                    }
                })
                .collect();
            // same instant: sorted by (a, b) under the new names
            expected.sort_by(|x, y| x.0.cmp(&y.0).then_with(|| (&x.1, &x.2).cmp(&(&y.1, &y.2))));
            let got = events(&r, PairMethod::Fast, false);
            // Stop mode ends at the first instant either way; bounce resolves
            // pairs in id order, which renaming may change, so compare the
            // first instant only there.
            if r.on_collision == kss::CollisionMode::Bounce {
                let first = |v: &Vec<(Time, String, String)>| {
                    v.iter()
                        .take_while(|e| Some(&e.0) == v.first().map(|f| &f.0))
                        .cloned()
                        .collect::<Vec<_>>()
                };
                assert_eq!(
                    first(&expected),
                    first(&got),
                    "{} seed {seed}",
                    family.name()
                );
            } else {
                assert_eq!(expected, got, "{} seed {seed}", family.name());
            }
        }
    }
}
