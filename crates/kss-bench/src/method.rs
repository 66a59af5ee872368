//! The methods compared, and running one of them on a scenario.

use kss::{RunError, RunOptions, Scenario, StructureKind};

use crate::{Counters, Deadline, Event, Failure};

/// A collision-detection method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// kss's exact all-pairs reference (`kss::run`, brute).
    Brute,
    /// kss's kinetic separation structure without hierarchy (`kss::run`, plain).
    Plain,
    /// kss's separation-sensitive structure (`kss::run`, hierarchical), with
    /// its default [`kss::DEFAULT_APPROXIMATE_ABOVE`]: polygons of at most
    /// that many vertices take part as they are.
    Hierarchical,
    /// The hierarchical structure approximating every polygon
    /// (`approximate_above` 0), for comparing with the default.
    HierarchicalAll,
    /// Kinetic sort-and-sweep with exact pair times ([`crate::sweep`]).
    Sweep,
    /// parry2d-f64 time of impact, all pairs, event-driven.
    ParryToi,
    /// parry2d-f64 fixed time step `1 / per_unit` with CCD.
    ParryStep {
        /// Steps per unit of simulated time.
        per_unit: u32,
    },
}

impl Method {
    /// The methods of a default run (the fixed-step method at two step sizes).
    pub fn defaults() -> Vec<Method> {
        vec![
            Method::Brute,
            Method::Plain,
            Method::Hierarchical,
            Method::Sweep,
            Method::ParryToi,
            Method::ParryStep { per_unit: 30 },
            Method::ParryStep { per_unit: 240 },
        ]
    }

    /// The name on the command line: `brute`, `plain`, `hierarchical`,
    /// `hierarchical-all`, `sweep`, `parry-toi`, `parry-step:N` (time step
    /// 1/N).
    pub fn name(&self) -> String {
        match self {
            Method::Brute => "brute".into(),
            Method::Plain => "plain".into(),
            Method::Hierarchical => "hierarchical".into(),
            Method::HierarchicalAll => "hierarchical-all".into(),
            Method::Sweep => "sweep".into(),
            Method::ParryToi => "parry-toi".into(),
            Method::ParryStep { per_unit } => format!("parry-step:{per_unit}"),
        }
    }

    /// A label for tables and plots.
    pub fn label(&self) -> String {
        match self {
            Method::ParryStep { per_unit } => format!("parry-step dt=1/{per_unit}"),
            m => m.name(),
        }
    }

    /// Parses [`Method::name`].
    pub fn parse(s: &str) -> Result<Method, String> {
        Ok(match s {
            "brute" => Method::Brute,
            "plain" => Method::Plain,
            "hierarchical" => Method::Hierarchical,
            "hierarchical-all" => Method::HierarchicalAll,
            "sweep" => Method::Sweep,
            "parry-toi" => Method::ParryToi,
            _ => {
                let Some(n) = s.strip_prefix("parry-step:") else {
                    return Err(format!(
                        "unknown method {s:?}: use brute, plain, hierarchical, hierarchical-all, sweep, parry-toi or parry-step:N (time step 1/N)"
                    ));
                };
                let per_unit: u32 = n
                    .parse()
                    .ok()
                    .filter(|&n| n > 0)
                    .ok_or_else(|| format!("{s:?}: N must be a positive integer"))?;
                Method::ParryStep { per_unit }
            }
        })
    }

    /// Whether the method is exact (its events must equal brute's).
    pub fn is_exact(&self) -> bool {
        matches!(
            self,
            Method::Brute
                | Method::Plain
                | Method::Hierarchical
                | Method::HierarchicalAll
                | Method::Sweep
        )
    }

    /// Runs the method on `scenario`, collecting its events.
    pub fn run(
        &self,
        scenario: &Scenario,
        deadline: Deadline,
    ) -> Result<(Vec<Event>, Counters), Failure> {
        self.run_scaled(scenario, 1.0, deadline)
    }

    /// [`Method::run`] on a scenario whose motions are `time_scale` times
    /// slower than usual: the fixed time step is `time_scale / N`, so that
    /// a step covers the same distance whatever the workload's time unit.
    pub fn run_scaled(
        &self,
        scenario: &Scenario,
        time_scale: f64,
        deadline: Deadline,
    ) -> Result<(Vec<Event>, Counters), Failure> {
        match self {
            Method::Brute | Method::Plain | Method::Hierarchical | Method::HierarchicalAll => {
                run_library(scenario, self.options())
            }
            Method::Sweep => crate::sweep::run(scenario, deadline),
            Method::ParryToi => crate::parry::run_toi(scenario, deadline),
            Method::ParryStep { per_unit } => {
                crate::parry::run_step(scenario, time_scale / f64::from(*per_unit), deadline)
            }
        }
    }
}

/// One of the library's structures through `kss::run` (no cooperative
/// deadline: the harness's child process is killed when over budget).
fn run_library(
    scenario: &Scenario,
    options: RunOptions,
) -> Result<(Vec<Event>, Counters), Failure> {
    let mut events = Vec::new();
    let stats = kss::run(scenario, &options, &mut |e| {
        events.push(Event {
            time: e.time.to_f64(),
            a: e.a.clone(),
            b: e.b.clone(),
        })
    })
    .map_err(|e| match e {
        RunError::NotImplemented(_) => Failure::NotImplemented,
        e => Failure::Error(e.to_string()),
    })?;
    let pair_tests = stats.events_by_kind.get("pair_computation").copied();
    Ok((
        events,
        Counters {
            collisions: stats.collisions,
            events: stats.events_processed,
            certificates_max: stats.certificates_max,
            pair_tests: pair_tests.unwrap_or(0),
            events_by_kind: stats.events_by_kind,
            build_seconds: Some(stats.build_seconds),
            events_seconds: Some(stats.events_seconds),
        },
    ))
}

impl Method {
    /// Whether the method is one of the library's structures (through
    /// `kss::run`).
    pub fn is_library(&self) -> bool {
        matches!(
            self,
            Method::Brute | Method::Plain | Method::Hierarchical | Method::HierarchicalAll
        )
    }

    /// The options of `kss::run` for one of the library's structures.
    fn options(&self) -> RunOptions {
        let structure = match self {
            Method::Brute => StructureKind::Brute,
            Method::Plain => StructureKind::Plain,
            _ => StructureKind::Hierarchical,
        };
        RunOptions {
            structure,
            approximate_above: match self {
                Method::HierarchicalAll => 0,
                _ => kss::DEFAULT_APPROXIMATE_ABOVE,
            },
            ..Default::default()
        }
    }
}

/// The construction-only run of [`Method::build_seconds`]: `kss::run` up
/// to the smallest positive normal double (the scenario's contract wants
/// `until > 0`), so that nothing but the world (with its validation) and
/// the structure with its certificates is built.
pub const BUILD_UNTIL: f64 = f64::MIN_POSITIVE;

impl Method {
    /// For the library's structures: the wall time of `kss::run` on
    /// `scenario` stopped at [`BUILD_UNTIL`] (building the world, validating
    /// it, building the structure and scheduling its certificates), and the
    /// events processed by then (normally none). `None` for the other
    /// methods.
    pub fn build_seconds(&self, scenario: &Scenario) -> Option<Result<(f64, u64), Failure>> {
        if !self.is_library() {
            return None;
        }
        let options = RunOptions {
            until: Some(BUILD_UNTIL),
            ..self.options()
        };
        let start = std::time::Instant::now();
        let result = kss::run(scenario, &options, &mut |_| {});
        let seconds = start.elapsed().as_secs_f64();
        Some(
            result
                .map(|stats| (seconds, stats.events_processed))
                .map_err(|e| match e {
                    RunError::NotImplemented(_) => Failure::NotImplemented,
                    e => Failure::Error(e.to_string()),
                }),
        )
    }
}
