//! Kinetic simulation machinery.
//!
//! For now this holds the [event queue](queue): an indexed priority queue
//! with stable keys, generic over the event time type, which the kinetic
//! simulator uses to schedule certificate failures.

pub mod queue;

pub use queue::{Enclosed, EventKey, EventQueue, Iter, QueueStats, DEFAULT_ARITY};
