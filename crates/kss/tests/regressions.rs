//! Regression scenarios: every `testdata/regressions/NAME.json` is a
//! minimized configuration on which a kinetic structure can disagree with
//! the brute-force reference or fail its audit. Most are degenerate
//! `bounce` runs: grazing contacts; sliding along a common line;
//! flight-plan changes that lift a sliding contact; a pop at an instant
//! where the motions change; approximation vertices of several bodies on
//! one line; a merge of a vertex that a certificate still names; a sliding
//! pair whose flight plan changes at an instant with another collision; an
//! approximation edge sliding along a real vertex after a pop, after a
//! bounce, or after two polygons touch without a collision (with the
//! hierarchy), and the pops that follow such a touch, which must wait for
//! the instant's last event and are dropped when the reference takes over;
//! a rebuild for just after an instant where two polygons slide along each
//! other, or three meet at a point; a pop next to a corridor whose chain
//! wraps the whole popped polygon, after local removals (the quick bench's
//! grazing-p50); pops at one instant, done in the structure and
//! finished together, of which a later one cannot be done in place after
//! an earlier one's triangle collapses changed faces between two other
//! bodies (`pops_of_an_instant_then_one_not_in_place_*`); a polygon resting on another where the structure must be
//! built afresh (from the infinitesimally shrunk copy); a pop that must not put a
//! partition triangle's side across a polygon; a middle bridge along flush
//! edges of both its bodies, which would hide a contact on that line; a
//! corridor that another corridor's operation decomposes by the motions
//! from before a collision response that then changes them; two points of
//! the hull that meet at a collision response which takes them off their
//! common line; a collision response at an instant whose structure waits
//! for a rebuild (three pairs of the `simultaneous` family touching at
//! once), where the corridors' resting corners and straight junctions are
//! not read (`resting_corners_not_read_while_a_rebuild_waits`: a debug
//! build asserted there on a chain whose length lagged behind its ends);
//! a walk's candidate whose junction has the points of a certificate known
//! to hold but another of them as its vertex, whose clearance the
//! certificate does not show
//! (`known_junction_at_another_vertex_of_its_certificate`, the `grazing`
//! family with every polygon approximated);
//! the search for an instant just after a refinement that a local repair
//! starts from the far queue's failures, some of whose points the
//! refinement moved: their enclosures bound the search, no exact time is
//! made on the moved points
//! (`repair_search_while_a_refinement_moved_far_certificate_points`, the
//! `simultaneous` family with every polygon approximated);
//! settled contacts repaired by a local retriangulation (a
//! vertex on another polygon's edge at every instant tried, a region grown
//! by two polygons whose corridor is degenerate at the same instant or past
//! a boundary bridge that the region's polygons cross, a repair after the
//! collision response, an instant whose hull is convex just after the
//! contact); local operations that cycle at one instant; coordinates,
//! sizes and velocities across the whole range of doubles (near 1e308,
//! subnormal, 1e-300 beside 1e300, a 1e-18 triangle among unit ones,
//! scales 2^±1000 in one scene, bounces at t = 1e-307 between polygons
//! moving at 5e307, a collision at t = 6.7e-109 of polygons at 6e269, one
//! moving at 2.6e304: the `extreme_*` files), among them pops of the
//! hierarchy beside polygons moving at 1e169 to 7e306 whose repair must not
//! cut a polygon off the hull at a lone hull vertex or leave an empty
//! corridor's bridge entering a polygon (`extreme_hierarchy_*`), and
//! bounces of a polygon of area below 1e-200 off a fixed one, whose
//! impulse is below the doubles' range (`extreme_bounce_of_a_*`).
//! Each gives exactly brute's collisions (exact times, pairs, order,
//! repeats and contact points) with `plain` and `hierarchical`, with the
//! audit after every event, the hierarchy both approximating every polygon
//! (as when the files were found: their polygons are small) and with its
//! default. The scenario files are read with `kss::json` and run through
//! [`kss::run`], as `kss run FILE --structure S --audit` runs them.

use std::path::{Path, PathBuf};

use kss::json::parse_scenario;
use kss::{run, RunOptions, RunStats, StructureKind, DEFAULT_APPROXIMATE_ABOVE};

mod common;

use common::{collision, Collision};

/// How a scenario is run, named as on the `kss run` command line:
/// `brute`; `plain` with the audit; `hierarchical` with the audit,
/// approximating every polygon (`--approximate-above 0`); and
/// `hierarchical-default`, the hierarchy with the audit and its default
/// `approximate_above`.
fn options(structure: &str) -> RunOptions {
    let (kind, approximate_above) = match structure {
        "brute" => (StructureKind::Brute, DEFAULT_APPROXIMATE_ABOVE),
        "plain" => (StructureKind::Plain, DEFAULT_APPROXIMATE_ABOVE),
        "hierarchical" => (StructureKind::Hierarchical, 0),
        "hierarchical-default" => (StructureKind::Hierarchical, DEFAULT_APPROXIMATE_ABOVE),
        other => panic!("no structure {other:?}"),
    };
    RunOptions {
        structure: kind,
        audit: kind != StructureKind::Brute,
        approximate_above,
        ..Default::default()
    }
}

/// The collisions and statistics of `file` run with `structure` (see
/// [`options`]); the run must succeed.
fn run_file(file: &Path, structure: &str) -> (Vec<Collision>, RunStats) {
    let text = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let scenario = parse_scenario(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let mut collisions = Vec::new();
    let stats = run(&scenario, &options(structure), &mut |e| {
        collisions.push(collision(e))
    })
    .unwrap_or_else(|e| panic!("{} with {structure}: {e}", file.display()));
    (collisions, stats)
}

/// The scenario files `testdata/FOLDER/*.json`, sorted.
fn scenarios_in(folder: &str) -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata")
        .join(folder);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("the {folder} folder: {e}"))
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    files
}

#[test]
fn regression_scenarios_agree_with_the_reference() {
    let files = scenarios_in("regressions");
    assert!(files.len() >= 8, "regression scenarios missing");
    for f in &files {
        let (want, _) = run_file(f, "brute");
        assert!(!want.is_empty(), "{}: no collision to check", f.display());
        for structure in ["plain", "hierarchical", "hierarchical-default"] {
            let (got, _) = run_file(f, structure);
            assert_eq!(got, want, "{} with {structure}", f.display());
        }
    }
}

/// The statistics of the regression scenario `NAME` run with `structure`
/// (see [`options`]: with the audit).
fn stats_of(name: &str, structure: &str) -> RunStats {
    let file = scenarios_in("regressions")
        .into_iter()
        .find(|p| p.ends_with(name))
        .expect("the scenario");
    run_file(&file, structure).1
}

/// Settled contacts that the local operations cannot resolve are repaired
/// by triangulating again the region around the polygons involved, not by
/// rebuilding the whole structure: three polygons meeting at a point and
/// bouncing apart (`gen_small simultaneous 2`), a contact whose region must
/// take both polygons (`gen_small grazing 110`: around either alone, a
/// bridge of the region's boundary crosses the other), and one where the
/// first instant tried leaves a corridor without a decomposition just after
/// the contact (`gen_small simultaneous 371`), and a settled contact found
/// while another contact of the instant awaits its response, handled again
/// after it (`gen_small simultaneous 852`). Two where at every instant
/// tried a polygon's vertex lies on the other's edge (the doubles of the
/// region put a vertex on a constraint), triangulated from a slightly shrunk
/// copy of the region and checked exactly: a polygon sliding along a fixed one
/// (minimized from `gen_small parallel 1325`), and a vertex left on an
/// edge after a response (from `gen_small simultaneous 1426`), with both
/// structures. And one whose region around the two polygons of the contact
/// takes a corridor between two others that is degenerate at the same
/// instant and has no decomposition just after it; the region grows by
/// those two (minimized from `gen_small grazing 2668`). And local
/// operations that fail at an instant with a collision: the region around
/// the failing certificate's polygons is repaired after the response, the
/// events deferred meanwhile scheduled again (from `gen_small simultaneous
/// 4298`), with both structures. And a repair whose triangulation, at an
/// instant tried, has a hull that is not convex just after the contact: the
/// instant is refused before the splice (two polygons, `gen_small
/// simultaneous 4187`). And a region whose boundary bridge (between two
/// polygons outside it) a polygon of the region crosses at once, the
/// triangle beyond inverted just after the instant: the region grows by
/// those two polygons (from `gen_small grazing 2447`; its constraints cross
/// at every instant tried). And a region whose corridor between two polygons
/// outside it (colliding at the same instant) holds junctions against the
/// motion, which the repair accepts there, and whose set takes the polygons
/// of the partition triangle whose collapse failed, not only those of the
/// certificate popped (`gen_small grazing 15498`, four points on one line at
/// the last instant of the run).
/// The local operations alone follow three of them (`gen_small simultaneous
/// 4298`, `simultaneous 4187` and `grazing 2447`: a corridor's middle bridge
/// is also walked, or taken between two vertices that touch, when junctions
/// are held against the motion); for them the test requires no rebuild, no
/// stand-in and fewer than 100 events.
#[test]
fn settled_contacts_are_repaired_locally() {
    for followed in [
        "local_repair_after_failed_operations_and_a_response.json",
        "local_repair_hull_turn_checked_just_after.json",
        "local_repair_grown_past_a_crossed_bridge.json",
    ] {
        for structure in ["plain", "hierarchical"] {
            let v = stats_of(followed, structure);
            assert_eq!(v.degenerate_rebuilds, 0, "{followed} {structure}: {v:?}");
            assert_eq!(v.stand_ins, 0, "{followed} {structure}: {v:?}");
            assert!(v.events_processed < 100, "{followed} {structure}: {v:?}");
        }
    }
    for name in [
        "local_repair_three_meet_at_a_point.json",
        "local_repair_around_both_bodies.json",
        "local_repair_after_a_trial_normalization.json",
        "local_repair_after_the_response.json",
        "local_repair_while_two_polygons_slide.json",
        "local_repair_with_a_vertex_on_an_edge.json",
        "local_repair_grown_by_a_neighbouring_degeneracy.json",
        "local_repair_past_a_corridor_degenerate_at_the_same_instant.json",
    ] {
        let v = stats_of(name, "plain");
        assert_eq!(v.degenerate_rebuilds, 0, "{name}: {v:?}");
        assert!(v.local_repairs >= 1, "{name}: {v:?}");
    }
    for name in [
        "local_repair_while_two_polygons_slide.json",
        "local_repair_with_a_vertex_on_an_edge.json",
    ] {
        let v = stats_of(name, "hierarchical");
        assert_eq!(v.degenerate_rebuilds, 0, "{name}: {v:?}");
        assert!(v.local_repairs >= 1, "{name}: {v:?}");
    }
}

/// `gen_small grazing 4197` (two polygons): at one instant two touches of
/// the pair undo each other's operation, the same certificates failing in
/// turn. A certificate handled a fourth time at one instant is taken as a
/// cycle, which the alternate normalization
/// (`Kinetic::alternate_normalization`: the decomposition holding the
/// fewest junctions against the motion) breaks, with no rebuild, no
/// stand-in and fewer than 100 events; a local repair of the region around
/// the polygons of the last certificates handled is the fallback.
#[test]
fn local_operations_that_cycle_are_followed_locally() {
    for structure in ["plain", "hierarchical"] {
        let v = stats_of("local_operations_cycle_at_an_instant.json", structure);
        assert_eq!(v.degenerate_rebuilds, 0, "{structure}: {v:?}");
        assert_eq!(v.stand_ins, 0, "{structure}: {v:?}");
        assert!(v.events_processed < 100, "{structure}: {v:?}");
    }
}

/// A polygon slides along a fixed one and its plan stops it with a vertex
/// on the other's vertex (minimized from `gen_small simultaneous 644`):
/// the corridor between them is pinched there, and the bridge of length
/// zero between the two resting vertices is the corridor's middle bridge. The same contact then left (a plan change takes the polygon
/// away) and pushed together (a plan change drives it into the other, a
/// collision at once): the corridor's two junctions at the bridge take
/// over again at the plan change. Both structures, no stand-in.
#[test]
fn a_vertex_resting_on_a_vertex_is_a_bridge_of_length_zero() {
    for name in [
        "resting_vertex_on_vertex_inside_a_corridor.json",
        "resting_vertex_on_vertex_then_apart.json",
        "resting_vertex_on_vertex_then_pushed_together.json",
    ] {
        for structure in ["plain", "hierarchical"] {
            let v = stats_of(name, structure);
            assert_eq!(v.stand_ins, 0, "{name} {structure}: {v:?}");
            assert_eq!(v.degenerate_rebuilds, 0, "{name} {structure}: {v:?}");
        }
    }
}

/// An edge resting on an identical edge of another polygon, both pairs of
/// endpoints coinciding. From `gen_small parallel 1117`: a polygon stops
/// so on a fixed one, backs off and comes back; the corridor between them
/// has a face that is a path traversed twice (from one pinch along the two
/// edges to the other and back). From `gen_small parallel 3388`
/// (minimized): two polygons stop as they meet so, the flush edges inside
/// both chains of their corridor, whose face beyond the bridge of length
/// zero has a cusp at it between two resting neighbours. Both structures
/// follow both, with no stand-in of the reference.
#[test]
fn an_edge_resting_on_an_identical_edge_is_followed() {
    for name in [
        "edge_resting_on_an_identical_edge.json",
        "edges_resting_flush_inside_a_corridor.json",
    ] {
        for structure in ["plain", "hierarchical"] {
            let v = stats_of(name, structure);
            assert_eq!(v.stand_ins, 0, "{name} {structure}: {v:?}");
            assert_eq!(v.degenerate_rebuilds, 0, "{name} {structure}: {v:?}");
            assert_eq!(v.collisions, 2, "{name} {structure}: {v:?}");
        }
    }
}

/// Degenerate instants where the corridor that has to be normalized has no
/// decomposition just after the instant until other failures of the same
/// instant are handled, and the choice of the decomposition that holds some
/// junctions against the motion decides whether the local operations
/// follow (no rebuild, no stand-in, no repair). Minimized from `gen_small grazing
/// 12625` (a bounce at a vertex-on-vertex contact while an end bridge lies
/// on a polygon edge's line: the middle bridge that goes with the end's
/// slide is found by walking it), `grazing 9761` (a vertex touches a vertex
/// as the hull changes: the corridor is pinched there, by a bridge between
/// the two touching vertices), `parallel 6469` and `parallel 10046` (two
/// operations can hand an edge back and forth at one instant: once a cycle
/// is seen, normalization takes the decomposition that holds the fewest
/// junctions against the motion).
#[test]
fn degenerate_instants_are_followed_without_a_rebuild() {
    for name in [
        "end_slide_at_a_bounce_with_a_walked_middle_bridge.json",
        "vertex_touch_pinches_a_corridor_at_a_hull_change.json",
        "operations_cycle_until_the_fewest_held_rule.json",
        "operations_cycle_until_the_fewest_held_rule_stand_in.json",
    ] {
        for structure in ["plain", "hierarchical"] {
            let v = stats_of(name, structure);
            assert_eq!(v.degenerate_rebuilds, 0, "{name} {structure}: {v:?}");
            assert_eq!(v.stand_ins, 0, "{name} {structure}: {v:?}");
            assert_eq!(v.local_repairs, 0, "{name} {structure}: {v:?}");
            assert!(v.events_processed < 100, "{name} {structure}: {v:?}");
        }
    }
}

/// `gen_small gas 369`: a pop whose every candidate inverts a partition
/// triangle at the popped vertex; the structure follows in place with an ear
/// slide after the pop (`crates/kss/src/structure/pop.rs`) instead of a rebuild, which
/// the statistics show (`refine_rebuilds` is 0).
#[test]
fn a_pop_that_inverts_a_triangle_is_repaired_in_place() {
    let v = stats_of("pop_repaired_by_an_ear_slide.json", "hierarchical");
    assert_eq!(v.refine_rebuilds, 0, "{v:?}");
    assert!(
        v.events_by_kind.get("pop").copied().unwrap_or(0) > 0,
        "{v:?}"
    );
}
