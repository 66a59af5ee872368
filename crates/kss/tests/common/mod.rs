//! Shared by the differential tests: a run's collision events and
//! statistics.

use kss::num::Time;
use kss::{run, RunOptions, RunStats, Scenario, StructureKind};

/// Collision events as (time, a, b).
pub type Events = Vec<(Time, String, String)>;

/// The collision events and statistics of a run of `s` with `structure`,
/// with the audit after every event if `audit`.
pub fn events(
    s: &Scenario,
    structure: StructureKind,
    audit: bool,
) -> Result<(Events, RunStats), String> {
    let mut out = Vec::new();
    let opts = RunOptions {
        structure,
        audit,
        ..Default::default()
    };
    let stats = run(s, &opts, &mut |e| {
        out.push((e.time.clone(), e.a.clone(), e.b.clone()))
    })
    .map_err(|e| e.to_string())?;
    Ok((out, stats))
}
