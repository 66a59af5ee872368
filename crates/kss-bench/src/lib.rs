//! Benchmarks of kss against what a user would pick instead, on the same
//! workloads, in one run on one machine.
//!
//! The baselines live here and never in the `kss` library's dependencies:
//!
//! - **brute**: the library's exact all-pairs reference (`kss::run` with
//!   [`kss::StructureKind::Brute`]); `plain` and `hierarchical` go through
//!   `kss::run` too and are measured as soon as the library implements them;
//! - **sweep** ([`sweep`]): a kinetic sort-and-sweep broad phase (kinetic
//!   sorted lists of bounding-box endpoints on x and y, exact swap times) with
//!   the library's exact pair time of impact for overlapping boxes; exact;
//! - **parry-toi** ([`parry::run_toi`]): all-pairs time of impact with
//!   parry2d-f64's `cast_shapes`, event-driven, recomputing a polygon's pairs
//!   when its motion changes (what a practitioner with a geometry library
//!   writes first); floating point;
//! - **parry-step** ([`parry::run_step`]): fixed time step with continuous
//!   collision detection (swept bounding boxes, sort-and-sweep, `cast_shapes`
//!   for candidate pairs each step, TOI sub-steps), as rapier and Box2D do.
//!
//! [`workload`] defines the workloads (generated with `kss::gen` and fixed
//! seeds), [`harness`] runs every method on every workload under a time
//! budget (each cell in a child process when an executable is given, which
//! also measures the method's own peak memory: resident, and live heap bytes
//! with allocations through [`heap`]'s counting allocator), [`compare`] counts missed
//! and wrong-time collisions against the exact reference, [`report`]
//! writes the Markdown table, the SVG plots and the machine description,
//! and [`docs`] writes the page `docs/benchmarks.md` from the results files
//! kept in the repository (`kss-bench docs`).
//!
//! The `kss-bench` binary (`src/main.rs`) only parses the arguments
//! ([`cli`]) and calls [`command::bench`], which runs the harness and prints
//! the report (or, for `kss-bench docs`, [`command::docs`]):
//!
//! ```sh
//! cargo build --release -p kss-bench
//! ./target/release/kss-bench --quick
//! ```

// (`deny`, not `forbid`: the counting allocator in `heap` is the one
// exception)
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod cli;
pub mod command;
pub mod compare;
pub mod docs;
pub mod exact;
pub mod harness;
pub mod heap;
pub mod method;
pub mod parry;
pub mod report;
pub mod sweep;
pub mod workload;

pub use method::Method;

/// One reported collision, as every method reports it: polygons `a < b`
/// (byte-wise) touch at `time` (rounded to a double for the exact methods).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Event {
    /// Collision time.
    pub time: f64,
    /// Byte-wise smaller id.
    pub a: String,
    /// Byte-wise larger id.
    pub b: String,
}

/// What one method did on one scenario (besides its events).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Counters {
    /// Collisions reported.
    pub collisions: u64,
    /// Events processed: for kinetic methods every certificate failure,
    /// collision and flight-plan change; for the fixed-step method the
    /// number of steps and TOI sub-steps.
    pub events: u64,
    /// Largest number of scheduled certificates (pair times, swap
    /// certificates); 0 for the fixed-step method.
    pub certificates_max: u64,
    /// Narrow-phase queries (pair time-of-impact computations).
    pub pair_tests: u64,
    /// The library's structures: `events` by kind (`kss run --stats`'s
    /// `events_by_kind`: certificate failures by kind, `pop` and
    /// `initial_pop` for the hierarchy's refinements, `collision`,
    /// `flight_plan_change`); empty for the other methods.
    #[serde(default)]
    pub events_by_kind: std::collections::BTreeMap<String, u64>,
    /// The library's structures: the wall time, in seconds, that this run
    /// spent before its first event (the exact world with its validation,
    /// the structure and its certificates: `RunStats::build_seconds`), so
    /// that the rest of the run's wall time is its events'; `None` for the
    /// other methods.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub build_seconds: Option<f64>,
    /// The library's structures: the wall time, in seconds, of this run's
    /// events after its construction, up to its end
    /// (`RunStats::events_seconds`: the events with their responses, not
    /// freeing the structure afterwards); `None` for the other methods and
    /// in results recorded without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub events_seconds: Option<f64>,
}

impl Counters {
    /// Events of one kind (0 if the method does not report it).
    pub fn kind(&self, kind: &str) -> u64 {
        self.events_by_kind.get(kind).copied().unwrap_or(0)
    }

    /// The hierarchy's pops: approximation vertices refined while running
    /// (`pop`) and before the start (`initial_pop`); 0 for other methods.
    pub fn pops(&self) -> u64 {
        self.kind("pop") + self.kind("initial_pop")
    }

    /// Wall time per event after the construction, in nanoseconds, from one
    /// run: the run's events time over its events
    /// ([`Counters::events_seconds`]); in results recorded without it,
    /// `(wall − build) / events` with the construction timed inside the run
    /// that took `wall_seconds` ([`Counters::build_seconds`]). `None`
    /// without those times or without events.
    pub fn ns_per_event_after_build(&self, wall_seconds: f64) -> Option<f64> {
        if self.events == 0 {
            return None;
        }
        let after = match (self.events_seconds, self.build_seconds) {
            (Some(e), _) => e,
            (None, Some(b)) => (wall_seconds - b).max(0.0),
            (None, None) => return None,
        };
        Some(after * 1e9 / self.events as f64)
    }
}

/// Why a method could not finish a scenario.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Failure {
    /// The library does not implement this structure yet.
    NotImplemented,
    /// The method does not support this scenario (the message says why).
    Unsupported(String),
    /// The time budget ran out.
    Budget,
    /// Anything else (a bug).
    Error(String),
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::NotImplemented => f.write_str("not implemented yet"),
            Failure::Unsupported(m) => write!(f, "unsupported: {m}"),
            Failure::Budget => f.write_str("over budget"),
            Failure::Error(m) => write!(f, "error: {m}"),
        }
    }
}

/// Orders two ids byte-wise, as the contract does.
pub(crate) fn ordered<'a>(x: &'a str, y: &'a str) -> (&'a str, &'a str) {
    if x.as_bytes() <= y.as_bytes() {
        (x, y)
    } else {
        (y, x)
    }
}

/// A wall-clock deadline checked cooperatively by the baselines.
#[derive(Clone, Copy, Debug)]
pub struct Deadline(Option<std::time::Instant>);

impl Deadline {
    /// No deadline.
    pub const NONE: Deadline = Deadline(None);

    /// `seconds` from now.
    pub fn after(seconds: f64) -> Deadline {
        Deadline(std::time::Instant::now().checked_add(std::time::Duration::from_secs_f64(seconds)))
    }

    /// Whether the deadline has passed.
    pub fn passed(&self) -> bool {
        self.0.is_some_and(|d| std::time::Instant::now() >= d)
    }
}

#[cfg(test)]
mod tests {
    use super::Counters;

    /// The time per event after the construction is the run's events time
    /// over its events; in results without that time, the run's wall time
    /// less its own construction over its events; nothing without either
    /// time or without events.
    #[test]
    fn time_after_build_is_the_runs_events_time_per_event() {
        let mut c = Counters {
            events: 4,
            build_seconds: Some(0.25),
            events_seconds: Some(0.125),
            ..Default::default()
        };
        assert_eq!(c.ns_per_event_after_build(0.5), Some(0.03125e9));
        c.events_seconds = None;
        assert_eq!(c.ns_per_event_after_build(0.5), Some(0.0625e9));
        c.events = 0;
        assert_eq!(c.ns_per_event_after_build(0.5), None);
        c.events = 4;
        c.build_seconds = None;
        assert_eq!(c.ns_per_event_after_build(0.5), None);
    }
}
