//! How an experiment drives the rig.

use serde::{Deserialize, Serialize};

/// A piecewise-linear function of time, held constant beyond its ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PiecewiseLinear {
    /// Breakpoint times (s), strictly increasing.
    pub t: Vec<f64>,
    /// Values at the breakpoints.
    pub value: Vec<f64>,
}

impl PiecewiseLinear {
    /// Value at time `t`: linear between breakpoints, the end values beyond them.
    pub fn at(&self, t: f64) -> f64 {
        let n = self.t.len();
        if n == 0 {
            return 0.0;
        }
        if t <= self.t[0] {
            return self.value[0];
        }
        if t >= self.t[n - 1] {
            return self.value[n - 1];
        }
        let i = self.segment(t);
        let w = (t - self.t[i]) / (self.t[i + 1] - self.t[i]);
        self.value[i] + w * (self.value[i + 1] - self.value[i])
    }

    /// The largest `i` with `t[i] ≤ t`, for `t` strictly inside the table:
    /// guessed from the mean spacing and walked at most two breakpoints each
    /// way, which finds it at once on a record's uniform grid; where the walk
    /// does not bracket `t`, the binary search. Either way the one segment
    /// holding `t`, so [`Self::at`] gives the same bits as with the search
    /// alone (the lanes and the reference look a drive up at every RK4
    /// stage: on a 24 841-sample record the search was a quarter of the
    /// CPU's time).
    fn segment(&self, t: f64) -> usize {
        let (x, n) = (&self.t, self.t.len());
        let u = (t - x[0]) / (x[n - 1] - x[0]) * (n - 1) as f64;
        let i = walk(x, t, (u as usize).min(n - 2));
        if x[i] <= t && t < x[i + 1] {
            i
        } else {
            x.partition_point(|&b| b <= t) - 1
        }
    }

    /// What a kernel's `table_at` reads just before the breakpoints:
    /// `+1/Δt` when every breakpoint lies on the uniform grid `t₀ + i·Δt` to
    /// within `1e-9·Δt` (a record's own sample grid: then the value at `t` is
    /// interpolated at the fractional index `(t − t₀)/Δt` with no search and
    /// no breakpoint read, and differs from [`Self::at`] by the rounding of
    /// that index alone); `−1/Δt` when the grid is only uniform enough for
    /// [`Self::uniform_inverse_spacing`]'s guess and corrections; `0` for a
    /// binary search.
    pub fn kernel_header(&self) -> f64 {
        let inv = self.uniform_inverse_spacing();
        if inv == 0.0 {
            return 0.0;
        }
        let n = self.t.len();
        let (t0, dt) = (self.t[0], (self.t[n - 1] - self.t[0]) / (n - 1) as f64);
        let exact = self
            .t
            .iter()
            .enumerate()
            .all(|(i, &x)| (x - (t0 + i as f64 * dt)).abs() <= 1e-9 * dt);
        if exact { inv } else { -inv }
    }

    /// `1/Δt` when the breakpoints lie on a uniform grid closely enough that
    /// `⌊(t − t₀)/Δt⌋`, computed in f64 or in f32 from the f32-rounded
    /// breakpoints, is within two breakpoints of the segment holding `t`;
    /// `0` otherwise. A kernel then finds the segment from the spacing and two
    /// corrections each way instead of a binary search (a record's own sample
    /// grid always qualifies). Each breakpoint must lie within a quarter of a
    /// spacing of the grid, in both precisions, and the table is limited to
    /// 2²¹ breakpoints, so that the f32 index arithmetic (one rounding of
    /// `t − t₀` and one of the product, each at most half a spacing there) keeps
    /// the guess within the corrections' reach.
    pub fn uniform_inverse_spacing(&self) -> f64 {
        const MAX_LEN: usize = 1 << 21;
        let n = self.t.len();
        if !(2..=MAX_LEN).contains(&n) {
            return 0.0;
        }
        let on_grid = |t: &[f64]| -> Option<f64> {
            let (t0, tn) = (t[0], t[n - 1]);
            let dt = (tn - t0) / (n - 1) as f64;
            let ok = dt > 0.0
                && dt.is_finite()
                && t.iter()
                    .enumerate()
                    .all(|(i, &x)| (x - (t0 + i as f64 * dt)).abs() <= 0.25 * dt);
            ok.then_some(dt)
        };
        let rounded: Vec<f64> = self.t.iter().map(|&x| f64::from(x as f32)).collect();
        match (on_grid(&self.t), on_grid(&rounded)) {
            (Some(dt), Some(_)) => 1.0 / dt,
            _ => 0.0,
        }
    }
}

/// Walks a guessed segment `i` of the breakpoints `x` at most two down, then
/// at most two up, towards the one holding `t` (as `table_at` does in the
/// shaders); it stays inside `0..x.len() - 1`.
fn walk(x: &[f64], t: f64, mut i: usize) -> usize {
    let n = x.len();
    for _ in 0..2 {
        if i > 0 && x[i] > t {
            i -= 1;
        }
    }
    for _ in 0..2 {
        if i + 2 < n && x[i + 1] <= t {
            i += 1;
        }
    }
    i
}

/// The actuator's drive mode for one experiment.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Drive {
    /// Prescribed displacement from the model's velocity and ramp parameters.
    #[default]
    Velocity,
    /// Actuator mass driven by a force table (t in s, force in N); zero for t < 0.
    Force(PiecewiseLinear),
}

impl Drive {
    /// The force table of a [`Drive::Force`].
    pub fn force_table(&self) -> Option<&PiecewiseLinear> {
        match self {
            Self::Force(t) => Some(t),
            Self::Velocity => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The segment `table_at` would take on a uniform table: the guess from
    /// the spacing, two corrections down, two up.
    fn guessed_segment(t: &[f64], inv: f64, x: f64) -> usize {
        let n = t.len();
        let lo = (((x - t[0]) * inv).floor().max(0.0) as usize).min(n - 2);
        walk(t, x, lo)
    }

    #[test]
    fn a_jittered_uniform_grid_finds_every_segment_from_its_spacing() {
        let dt = 1e-3;
        let t: Vec<f64> = (0..5000)
            .map(|i| i as f64 * dt + 0.2 * dt * ((i * 7919 % 11) as f64 / 10.0 - 0.5))
            .collect();
        let table = PiecewiseLinear {
            value: vec![0.0; t.len()],
            t: t.clone(),
        };
        let inv = table.uniform_inverse_spacing();
        assert!(inv > 0.0, "within a quarter spacing of the grid");
        for k in 1..40_000 {
            let x = k as f64 * 1.2345e-4;
            if x <= t[0] || x >= t[t.len() - 1] {
                continue;
            }
            let want = t.partition_point(|&b| b <= x) - 1;
            assert_eq!(guessed_segment(&t, inv, x), want, "t = {x}");
        }
    }

    #[test]
    fn the_guessed_segment_is_the_searched_one() {
        let uniform: Vec<f64> = (0..300).map(|i| 0.25 + i as f64 * 1e-3).collect();
        let uneven: Vec<f64> = (0..300)
            .map(|i| (i as f64).powf(1.7) * 1e-4 + ((i * 7919 % 13) as f64) * 1e-6)
            .collect();
        for t in [uniform, uneven] {
            let table = PiecewiseLinear {
                value: (0..t.len()).map(|i| (i as f64 * 0.37).sin()).collect(),
                t: t.clone(),
            };
            let (a, b) = (t[0], t[t.len() - 1]);
            for k in 1..5000 {
                let x = a + (b - a) * k as f64 / 5000.0;
                if x <= a || x >= b {
                    continue;
                }
                let want = t.partition_point(|&y| y <= x) - 1;
                assert_eq!(table.segment(x), want, "t = {x}");
            }
            // Breakpoints themselves, and just below them.
            for &x in &t[1..t.len() - 1] {
                assert_eq!(table.segment(x), t.partition_point(|&y| y <= x) - 1);
                let below = f64::from_bits(x.to_bits() - 1);
                assert_eq!(table.segment(below), t.partition_point(|&y| y <= below) - 1);
            }
        }
    }

    #[test]
    fn the_kernel_header_tells_exact_grids_from_rough_ones() {
        let exact = PiecewiseLinear {
            t: (0..100).map(|i| 0.5 + i as f64 * 1e-3).collect(),
            value: vec![0.0; 100],
        };
        assert_eq!(exact.kernel_header(), exact.uniform_inverse_spacing());
        assert!(exact.kernel_header() > 0.0);
        let mut rough = exact.clone();
        rough.t[7] += 1e-6 * 1e-3;
        assert_eq!(rough.kernel_header(), -rough.uniform_inverse_spacing());
        assert!(rough.kernel_header() < 0.0);
        let uneven = PiecewiseLinear {
            t: vec![0.0, 0.1, 0.5, 0.6],
            value: vec![0.0; 4],
        };
        assert_eq!(uneven.kernel_header(), 0.0);
    }

    #[test]
    fn uneven_breakpoints_keep_the_binary_search() {
        let table = PiecewiseLinear {
            t: vec![0.0, 0.1, 0.5, 0.6],
            value: vec![0.0; 4],
        };
        assert_eq!(table.uniform_inverse_spacing(), 0.0);
        let one = PiecewiseLinear {
            t: vec![0.0],
            value: vec![1.0],
        };
        assert_eq!(one.uniform_inverse_spacing(), 0.0);
    }
}
