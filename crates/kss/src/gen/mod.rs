//! Scenario generators, shared by the `kss gen` command, the tests and the
//! benchmarks.
//!
//! Every generator is a pure function of its parameters (seeded through the
//! hand-written [`Rng`], so a seed gives the same scenario forever) and returns
//! a [`Scenario`] that is valid per the contract: counter-clockwise strictly
//! convex polygons, unique ids, pairwise disjoint closed polygons at time 0,
//! flight-plan changes in `(0, until]`.
//!
//! The families ([`Family`]):
//!
//! - [`flypast`]: two congruent regular n-gons passing each other at a chosen
//!   minimum distance (or colliding);
//! - [`gas`]: many random convex polygons with random velocities, optionally in
//!   a box of four fixed walls;
//! - [`simultaneous`], [`grazing`], [`parallel`]: exact degeneracies (several
//!   pairs first touching at one instant, three polygons meeting at one point,
//!   tangential grazing contacts, edges sliding flush along a common line),
//!   built on small integers and dyadic numbers so that the degeneracies hold
//!   exactly in double arithmetic, not just approximately;
//! - [`far`]: a gas scene translated to coordinates around 10^6, slowed down.
//!
//! Beside the families, [`swarm`] makes the benchmarks' swarms: regular
//! n-gons in a box of walls, velocities in [-1, 1]², simulated long enough
//! for about 12 collisions per polygon ([`swarm_until`]), and [`churn`]
//! makes scenes whose polygons enter and leave while they run (the
//! contract's `insertions` and `removals`); neither has a small instance for
//! the test sweeps.
//!
//! [`generate_small`] makes a small random instance of any family, for
//! differential test sweeps over thousands of seeds. [`demo`] is the built-in
//! scene of `kss demo`.
//!
//! [`flypast`]: fn@flypast
//! [`gas`]: fn@gas
//! [`swarm`]: fn@swarm
//! [`churn`]: fn@churn
//! [`demo`]: fn@demo

use crate::rng::Rng;
use crate::scenario::{CollisionMode, Scenario};

mod churn;
mod degenerate;
mod demo;
mod flypast;
mod gas;
mod hull;
mod swarm;
#[cfg(test)]
mod tests;

pub use churn::{churn, ChurnParams};
pub use degenerate::{
    grazing, grazing_with_contacts, parallel, parallel_with_contacts, simultaneous,
    simultaneous_with_contacts, DegenerateParams, PlannedContact, SimultaneousParams,
};
pub use demo::demo;
pub use flypast::{flypast, flypast_with_info, regular_polygon, FlypastInfo, FlypastParams};
pub use gas::{far, gas, FarParams, GasParams};
#[cfg(test)]
pub(crate) use hull::hull_i64;
pub use hull::{orient_exact, strict_convex_hull};
pub use swarm::{swarm, swarm_until, SwarmParams};

// ---------------------------------------------------------------------------
// Families
// ---------------------------------------------------------------------------

/// The generator families.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// Two congruent regular n-gons passing each other ([`flypast`](fn@flypast)).
    Flypast,
    /// Random convex polygons in random motion ([`gas`](fn@gas)).
    Gas,
    /// Pairs first touching at exactly one common instant, and three polygons
    /// meeting at one point ([`simultaneous`]).
    Simultaneous,
    /// Tangential grazing contacts ([`grazing`]).
    Grazing,
    /// Motion parallel to edges, edges flush ([`parallel`]).
    Parallel,
    /// A gas scene far from the origin ([`far`]).
    Far,
}

impl Family {
    /// Every family, in a fixed order.
    pub const ALL: [Family; 6] = [
        Family::Flypast,
        Family::Gas,
        Family::Simultaneous,
        Family::Grazing,
        Family::Parallel,
        Family::Far,
    ];

    /// The family's name on the command line (`"flypast"`, `"gas"`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Family::Flypast => "flypast",
            Family::Gas => "gas",
            Family::Simultaneous => "simultaneous",
            Family::Grazing => "grazing",
            Family::Parallel => "parallel",
            Family::Far => "far",
        }
    }

    /// The family called `name` (as given by [`Family::name`]), if any.
    pub fn from_name(name: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == name)
    }

    /// A one-line description of the family.
    pub fn description(self) -> &'static str {
        match self {
            Family::Flypast => "two congruent regular n-gons passing each other at a chosen gap",
            Family::Gas => "random convex polygons with random velocities, optionally in a box",
            Family::Simultaneous => {
                "pairs first touching at one exact instant; three polygons meeting at a point"
            }
            Family::Grazing => {
                "tangential contacts: a vertex sliding along an edge's line, vertex-vertex grazes"
            }
            Family::Parallel => {
                "motion parallel to edges: edges flush, sliding along a common line"
            }
            Family::Far => "a gas scene translated to coordinates around 1e6, slowed down",
        }
    }
}

/// A collision mode drawn uniformly among stop, remove and bounce.
fn random_mode(rng: &mut Rng) -> CollisionMode {
    match rng.below(3) {
        0 => CollisionMode::Stop,
        1 => CollisionMode::Remove,
        _ => CollisionMode::Bounce,
    }
}

/// A small random instance of `family` for differential test sweeps: 2 to 8
/// polygons of 3 to about 12 vertices, a short `until`, a collision mode drawn
/// among stop, remove and bounce. The same `(family, seed)` always gives the
/// same scenario.
pub fn generate_small(family: Family, seed: u64) -> Scenario {
    let mut rng = Rng::with_stream(seed, 0x5ca1_ab1e ^ family as u64);
    let mode = random_mode(&mut rng);
    let sub_seed = rng.next_u64();
    match family {
        Family::Flypast => {
            let diameter = rng.range_f64(0.5, 2.0);
            let gap = match rng.below(4) {
                0 => 0.0,
                1 => -rng.range_f64(0.01, 0.3) * diameter,
                _ => rng.range_f64(0.001, 0.3) * diameter,
            };
            flypast(&FlypastParams {
                n: rng.range_usize(3, 12),
                diameter,
                gap,
                a_moving: rng.chance(0.5),
                speed: rng.range_f64(0.5, 2.0),
                mode,
                seed: sub_seed,
            })
        }
        Family::Gas | Family::Far => {
            let walls = rng.chance(0.4);
            let k = if walls {
                rng.range_usize(1, 4)
            } else {
                rng.range_usize(2, 8)
            };
            let min_n = rng.range_usize(3, 8);
            let gas_params = GasParams {
                k,
                min_n,
                max_n: rng.range_usize(min_n, 12),
                walls,
                mode,
                until: rng.range_f64(1.0, 4.0),
                max_speed: rng.range_f64(0.3, 2.0),
                changes: rng.range_usize(0, 3),
                seed: sub_seed,
            };
            if family == Family::Gas {
                gas(&gas_params)
            } else {
                far(&FarParams {
                    gas: gas_params,
                    offset: 1.0e6,
                    slowdown: 1024.0,
                })
            }
        }
        Family::Simultaneous => {
            let triple = rng.chance(0.5);
            let pairs = if triple {
                rng.range_usize(0, 2)
            } else {
                rng.range_usize(1, 3)
            };
            simultaneous(&SimultaneousParams {
                pairs,
                triple,
                mode,
                until: None,
                small: true,
                seed: sub_seed,
            })
        }
        Family::Grazing => grazing(&DegenerateParams {
            pairs: rng.range_usize(1, 4),
            mode,
            until: None,
            small: true,
            seed: sub_seed,
        }),
        Family::Parallel => parallel(&DegenerateParams {
            pairs: rng.range_usize(1, 4),
            mode,
            until: None,
            small: true,
            seed: sub_seed,
        }),
    }
}

/// Why a generator refused its parameters: the message names the parameter
/// and the rule it breaks.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct InvalidParams(pub String);

/// Panics with the message of a failed parameter check.
fn check_or_panic(check: Result<(), InvalidParams>) {
    if let Err(msg) = check {
        panic!("invalid generator parameters: {msg}");
    }
}

fn check_mode_until(until: Option<f64>) -> Result<(), InvalidParams> {
    match until {
        Some(u) if !(u.is_finite() && u > 0.0) => Err(InvalidParams(format!(
            "until is {u}: it must be a finite number > 0"
        ))),
        _ => Ok(()),
    }
}

/// Number of decimal digits of `x`.
fn digits(x: usize) -> usize {
    x.to_string().len()
}
