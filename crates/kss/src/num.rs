//! Exact numbers (in progress).
/// Placeholder.
#[derive(Clone, Debug, PartialEq)]
pub struct Time(f64);
impl Time {
    /// Placeholder.
    pub fn to_f64(&self) -> f64 { self.0 }
}
