//! Comparing a method's events with the exact reference.
//!
//! Events are matched pair by pair: the i-th collision of a pair in the
//! method's output against the i-th collision of that pair in the reference.
//! A match whose time differs by more than the contract's relative tolerance
//! (1e-12) counts as a *wrong time*; a reference collision with no
//! counterpart is *missed*; a reported collision with no counterpart is
//! *extra*. In `bounce` mode trajectories diverge after the first difference
//! (the contract expects floating-point divergence), so the meaningful number
//! there is the *agreeing prefix*: how many leading events agree.

use std::collections::HashMap;

use crate::Event;

/// The contract's relative tolerance on reported times.
pub const REL_TOL: f64 = 1e-12;

/// Whether `t` is within the contract's tolerance of the exact `reference`.
pub fn close(t: f64, reference: f64) -> bool {
    (t - reference).abs() <= REL_TOL * reference.abs().max(f64::MIN_POSITIVE)
}

/// The counts of a comparison.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Comparison {
    /// Events of the reference.
    pub reference: u64,
    /// Matched with a time within tolerance.
    pub matched: u64,
    /// Matched pair, time outside tolerance.
    pub wrong_time: u64,
    /// Reference collisions not reported.
    pub missed: u64,
    /// Reported collisions not in the reference.
    pub extra: u64,
    /// Leading events that agree (pair and time within tolerance; two
    /// neighbouring events may come in either order).
    pub agreeing_prefix: u64,
    /// Identical output (same pairs in the same order, times within tolerance).
    pub identical: bool,
}

fn same(x: &Event, y: &Event) -> bool {
    x.a == y.a && x.b == y.b && close(x.time, y.time)
}

/// Compares `got` with the exact `reference`.
pub fn compare(reference: &[Event], got: &[Event]) -> Comparison {
    // per pair: the reference's times and the method's
    type Times = (Vec<f64>, Vec<f64>);
    let mut by_pair: HashMap<(&str, &str), Times> = HashMap::new();
    for e in reference {
        by_pair
            .entry((e.a.as_str(), e.b.as_str()))
            .or_default()
            .0
            .push(e.time);
    }
    for e in got {
        by_pair
            .entry((e.a.as_str(), e.b.as_str()))
            .or_default()
            .1
            .push(e.time);
    }
    let mut c = Comparison {
        reference: reference.len() as u64,
        ..Comparison::default()
    };
    for (r, g) in by_pair.values() {
        let common = r.len().min(g.len());
        for i in 0..common {
            if close(g[i], r[i]) {
                c.matched += 1;
            } else {
                c.wrong_time += 1;
            }
        }
        c.missed += (r.len() - common) as u64;
        c.extra += (g.len() - common) as u64;
    }
    let mut i = 0;
    while i < reference.len() && i < got.len() {
        if same(&got[i], &reference[i]) {
            i += 1;
        } else if i + 1 < reference.len()
            && i + 1 < got.len()
            && same(&got[i], &reference[i + 1])
            && same(&got[i + 1], &reference[i])
        {
            i += 2;
        } else {
            break;
        }
    }
    c.agreeing_prefix = i as u64;
    c.identical = i == reference.len() && i == got.len();
    c
}
