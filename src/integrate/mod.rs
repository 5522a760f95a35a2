//! Fixed-step classic RK4, the f64 reference every other path is held to.
//!
//! The integrator knows nothing of any rig: it drives a [`System`] over a
//! [`SampleGrid`] and hands each measurement sample to an observer. A system may
//! carry one-way *switches* (fracture, for the tensile rig); the step in which a
//! switch fires is split at the located crossing, so the post-switch history keeps
//! the fourth order of the method instead of dropping to first order.

mod grid;
mod rk4;
pub mod test_systems;

pub use grid::SampleGrid;
pub use rk4::{CROSSING_ITERATIONS, Integrator, hermite_crossing, rk4_step, walk_grid};

/// A system of first-order ODEs, `dy/dt = f(t, y)`, in the current regime.
pub trait System {
    /// Number of state variables.
    fn dim(&self) -> usize;

    /// Writes `dy/dt` at `(t, y)` into `dy`.
    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]);

    /// While a one-way switch is still pending, returns the switching function
    /// `g(t, y)` and its time derivative `dg/dt`; the switch fires when `g`
    /// reaches zero from below. `None` once nothing is pending.
    fn pending_switch(&self, _t: f64, _y: &[f64]) -> Option<(f64, f64)> {
        None
    }

    /// Moves the system into its post-switch regime.
    fn fire_switch(&mut self, _t: f64) {}
}
