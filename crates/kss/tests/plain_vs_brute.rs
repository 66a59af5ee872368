//! The kinetic separation structure (`plain`) against the brute-force
//! reference: identical collision events (exact times, same pairs, same
//! order) on every generator family, degenerate ones included, with the
//! structure's audit after every event (internal ones too). `KSS_SLOW=1`
//! sweeps 100,000 scenarios instead of the CI subset.

use kss::gen::{churn, generate_small, ChurnParams, Family};
use kss::{run, CollisionMode, RunOptions, Scenario, StructureKind, DEFAULT_APPROXIMATE_ABOVE};

mod common;

use common::{collision, events, events_above, Collision};

/// Which polygons the hierarchy approximates in a sweep.
#[derive(Clone, Copy, PartialEq)]
enum Approximated {
    /// Every polygon (`approximate_above` 0).
    All,
    /// The polygons with more vertices than the mean of the scene's
    /// smallest and largest vertex counts: a mix of approximated polygons
    /// and polygons that take part as they are, or none approximated where
    /// all have one size.
    Larger,
}

/// The `approximate_above` of [`Approximated::Larger`] for `s`, and
/// whether the scene mixes approximated polygons with polygons taken as
/// they are.
fn middle_count(s: &Scenario) -> (usize, bool) {
    let counts = s
        .polygons
        .iter()
        .chain(s.insertions.iter().map(|i| &i.polygon))
        .map(|p| p.vertices.len());
    let (lo, hi) = counts.fold((usize::MAX, 0), |(lo, hi), n| (lo.min(n), hi.max(n)));
    ((lo + hi) / 2, lo < hi)
}

fn seeds() -> u64 {
    match std::env::var("KSS_SLOW") {
        Ok(_) => 100_000 / Family::ALL.len() as u64 + 1,
        Err(_) => std::env::var("KSS_SEEDS")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(400),
    }
}

/// The generic families: the local operations must handle every event.
const GENERIC: [Family; 3] = [Family::Flypast, Family::Gas, Family::Far];

/// The degenerate families (simultaneous contacts, grazing, sliding along a
/// common line): where several degeneracies coincide at one instant the
/// structure may fall back to a local repair or, rarely, a rebuild for just
/// after it (counted, and bounded here so that the local operations stay
/// the rule).
const DEGENERATE: [Family; 3] = [Family::Simultaneous, Family::Grazing, Family::Parallel];

#[test]
fn plain_matches_brute_on_generic_families() {
    let (total, rebuilds) = sweep(&GENERIC, StructureKind::Plain, Approximated::All);
    assert_eq!(
        rebuilds, 0,
        "rebuilds on generic families ({total} scenarios)"
    );
}

/// The degenerate families: same events as the reference, with the audit
/// after every event. Where the local operations cannot resolve an instant
/// the region around the polygons involved is triangulated again (a local
/// repair); a rebuild of the whole structure stays rare: at most one
/// scenario in 5000 (over the 50,001 degenerate scenarios of `KSS_SLOW=1`
/// at commit 2419cf7: none with plain, 3 with the hierarchy). On CI's 1200
/// that allows none.
#[test]
fn plain_matches_brute_on_degenerate_families() {
    let (total, rebuilds) = sweep(&DEGENERATE, StructureKind::Plain, Approximated::All);
    assert_rebuilds_rare(StructureKind::Plain, total, rebuilds);
}

fn assert_rebuilds_rare(structure: StructureKind, total: usize, rebuilds: u64) {
    assert!(
        rebuilds * 5000 <= total as u64,
        "{}: {rebuilds} rebuilds in {total} degenerate scenarios",
        structure.name()
    );
}

/// The hierarchical structure on the generic families, every polygon
/// approximated: same events as the reference, with the audit
/// (approximations included) after every event.
#[test]
fn hierarchical_matches_brute_on_generic_families() {
    let (total, rebuilds) = sweep(&GENERIC, StructureKind::Hierarchical, Approximated::All);
    assert_eq!(
        rebuilds, 0,
        "rebuilds on generic families ({total} scenarios)"
    );
}

#[test]
fn hierarchical_matches_brute_on_degenerate_families() {
    let (total, rebuilds) = sweep(&DEGENERATE, StructureKind::Hierarchical, Approximated::All);
    assert_rebuilds_rare(StructureKind::Hierarchical, total, rebuilds);
}

/// The hierarchy with only the larger polygons of each scene approximated
/// (the others take part as they are, as with the default on small
/// polygons): the same events as the reference on every family, with the
/// audit after every event.
#[test]
fn hierarchical_with_the_larger_polygons_approximated_matches_brute() {
    let families: Vec<Family> = GENERIC.iter().chain(&DEGENERATE).copied().collect();
    let (total, rebuilds) = sweep(&families, StructureKind::Hierarchical, Approximated::Larger);
    assert_rebuilds_rare(StructureKind::Hierarchical, total, rebuilds);
}

/// The collisions of a run of `s` with `structure` (no audit), the
/// hierarchy approximating the polygons of more than `above` vertices; the
/// run must succeed.
fn collisions(s: &Scenario, structure: StructureKind, above: usize) -> Vec<Collision> {
    let options = RunOptions {
        structure,
        approximate_above: above,
        ..Default::default()
    };
    let mut out = Vec::new();
    run(s, &options, &mut |e| out.push(collision(e)))
        .unwrap_or_else(|e| panic!("{} with {above}: {e}", structure.name()));
    out
}

/// Scenes with insertions, removals and flight-plan changes at coinciding
/// instants (`gen::churn`, seeds 0 to 7 in every mode, as `kss gen churn
/// --seed S --mode M` writes them): `plain` and `hierarchical` (approximating
/// every polygon, those of more than 6 vertices, and with its default,
/// which takes these as they are) report exactly brute's collisions, and
/// the inserted polygons (ids `c...`) take part in them.
#[test]
fn churn_scenes_give_identical_events_with_every_structure() {
    let mut inserted_collisions = 0;
    for mode in [
        CollisionMode::Stop,
        CollisionMode::Remove,
        CollisionMode::Bounce,
    ] {
        for seed in 0..8 {
            let s = churn(&ChurnParams {
                mode,
                seed,
                ..Default::default()
            });
            let want = collisions(&s, StructureKind::Brute, DEFAULT_APPROXIMATE_ABOVE);
            inserted_collisions += want
                .iter()
                .filter(|(_, a, b, _, _)| a.starts_with('c') || b.starts_with('c'))
                .count();
            for (structure, above) in [
                (StructureKind::Plain, DEFAULT_APPROXIMATE_ABOVE),
                (StructureKind::Hierarchical, 0),
                (StructureKind::Hierarchical, 6),
                (StructureKind::Hierarchical, DEFAULT_APPROXIMATE_ABOVE),
            ] {
                assert_eq!(
                    collisions(&s, structure, above),
                    want,
                    "seed {seed} {mode:?}: {} with approximate_above {above} and brute differ",
                    structure.name()
                );
            }
        }
    }
    assert!(inserted_collisions >= 10, "{inserted_collisions}");
}

/// Run every seed of `families` with the reference and `structure`; returns
/// the number of scenarios and the degenerate rebuilds `structure` needed.
fn sweep(families: &[Family], structure: StructureKind, approx: Approximated) -> (usize, u64) {
    let mut total = 0usize;
    let mut rebuilds = 0u64;
    let mut stand_ins = 0u64;
    let mut repairs = 0u64;
    let mut with_events = 0usize;
    let mut failures = Vec::new();
    // the seeds that needed a global rebuild or the reference's stand-in
    let mut fallbacks: Vec<String> = Vec::new();
    // runs that ended with an error, and runs that finished with other
    // events than the reference's (the worse kind: a silent disagreement)
    let (mut errors, mut disagreements) = (0usize, 0usize);
    // scenes with approximated polygons beside polygons taken as they are
    let mut mixed = 0usize;
    // corridors taken as an operation left them on the signs of the
    // junctions it made (`trusted_checks`)
    let mut trusted = 0u64;
    for &family in families {
        for seed in 0..seeds() {
            let s = generate_small(family, seed);
            let (want, _) = events(&s, StructureKind::Brute, false).expect("brute runs");
            let above = match approx {
                Approximated::All => 0,
                Approximated::Larger => {
                    let (above, mix) = middle_count(&s);
                    mixed += usize::from(mix && structure == StructureKind::Hierarchical);
                    above
                }
            };
            let got = events_above(&s, structure, true, above).map(|(got, stats)| {
                rebuilds += stats.degenerate_rebuilds;
                stand_ins += stats.stand_ins;
                if stats.stand_ins > 0 || stats.degenerate_rebuilds > 0 {
                    fallbacks.push(format!(
                        "{} seed {seed}: {} rebuilds, {} stand-ins",
                        family.name(),
                        stats.degenerate_rebuilds,
                        stats.stand_ins
                    ));
                }
                repairs += stats.local_repairs;
                trusted += stats.work.get("trusted_checks").copied().unwrap_or(0);
                got
            });
            total += 1;
            with_events += usize::from(!want.is_empty());
            match got {
                Ok(got) if got == want => {}
                Ok(got) => {
                    disagreements += 1;
                    failures.push(format!(
                        "{} seed {seed}: {} events, brute {} (first difference at {:?})",
                        family.name(),
                        got.len(),
                        want.len(),
                        got.iter().zip(&want).position(|(a, b)| a != b)
                    ))
                }
                Err(e) => {
                    errors += 1;
                    failures.push(format!("{} seed {seed}: {e}", family.name()))
                }
            }
        }
    }
    eprintln!(
        "{}: {total} scenarios ({mixed} mixing approximated polygons with others), \
         {with_events} with collisions, {} failures \
         ({errors} errors, {disagreements} disagreements), {rebuilds} rebuilds, \
         {repairs} local repairs, {stand_ins} stand-ins of the reference, \
         {trusted} corridors taken on their new junctions' signs",
        structure.name(),
        failures.len()
    );
    // disagreements first: they matter most
    failures.sort_by_key(|f| f.contains("internal error"));
    for f in failures.iter().take(30) {
        eprintln!("  {f}");
    }
    for f in fallbacks.iter().take(40) {
        eprintln!("  fallback: {f}");
    }
    assert!(failures.is_empty());
    // the reference stands in only where polygons rest in contact, which
    // the generic families never make, and the degenerate ones rarely
    let generic = families.iter().all(|f| GENERIC.contains(f));
    assert!(
        if generic {
            stand_ins == 0
        } else {
            stand_ins * 1000 <= total as u64
        },
        "{stand_ins} stand-ins of the reference in {total} scenarios"
    );
    assert!(
        with_events * 3 > total,
        "the sweep must exercise collisions"
    );
    assert!(
        approx == Approximated::All || mixed * 3 > total,
        "only {mixed} of {total} scenes mix approximated polygons with others"
    );
    // the sweep exercises the corridors taken on the signs of an
    // operation's new junctions, without their clearance (the audit above
    // would see a face wrapped around a vertex; debug builds assert the
    // clearance of each)
    assert!(trusted > 0, "no corridor taken on its signs");
    (total, rebuilds)
}
