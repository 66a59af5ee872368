//! Shared by the differential tests: a run's collision events and
//! statistics.

use kss::num::Time;
use kss::{run, CollisionEvent, RunOptions, RunStats, Scenario, StructureKind};

/// Collision events as (time, a, b).
pub type Events = Vec<(Time, String, String)>;

/// The collision events and statistics of a run of `s` with `structure`,
/// with the audit after every event if `audit`. The hierarchy approximates
/// every polygon here (`approximate_above` 0): the generated polygons are
/// small, and with the default most of them would take part as they are.
#[allow(dead_code)] // (not every test binary that shares this module uses it)
pub fn events(
    s: &Scenario,
    structure: StructureKind,
    audit: bool,
) -> Result<(Events, RunStats), String> {
    events_above(s, structure, audit, 0)
}

/// [`events`] with the hierarchy approximating only the polygons of more
/// than `above` vertices.
#[allow(dead_code)] // (not every test binary that shares this module uses it)
pub fn events_above(
    s: &Scenario,
    structure: StructureKind,
    audit: bool,
    above: usize,
) -> Result<(Events, RunStats), String> {
    let mut out = Vec::new();
    let opts = RunOptions {
        structure,
        audit,
        approximate_above: above,
        ..Default::default()
    };
    let stats = run(s, &opts, &mut |e| {
        out.push((e.time.clone(), e.a.clone(), e.b.clone()))
    })
    .map_err(|e| e.to_string())?;
    Ok((out, stats))
}

/// One collision event with every field compared exactly: the time, the
/// pair, whether the pair collides again at that instant, and the contact
/// point's bits where it is finite (where it is not, `kss run` prints no
/// point).
#[allow(dead_code)] // (not every test binary that shares this module uses it)
pub type Collision = (Time, String, String, bool, Option<[u64; 2]>);

/// `e` as a [`Collision`].
#[allow(dead_code)]
pub fn collision(e: &CollisionEvent) -> Collision {
    let point = e
        .point
        .iter()
        .all(|x| x.is_finite())
        .then(|| e.point.map(f64::to_bits));
    (e.time.clone(), e.a.clone(), e.b.clone(), e.again, point)
}
