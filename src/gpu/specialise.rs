//! Kernels specialised to a batch: per-run values that are the same in every run
//! (the fixed parameters of a campaign, the grid of a fixed clock offset) are
//! baked into the fitness kernel as constants, so the compiler folds them into
//! the arithmetic instead of keeping them in registers.
//!
//! In a calibration only a handful of parameters are free; the rest are the same
//! in every generation, so one specialised kernel serves the whole run. A
//! specialised kernel computes what the generic one computes, from the same
//! values: the baked constants are the exact values the host would upload.

use crate::eval::Precision;

/// Batches with fewer runs than this are scored by the generic kernel: a
/// compile would cost more than it saves.
pub const MIN_RUNS: usize = 64;

/// `value` as the kernel stores it: rounded to f32 for [`Precision::F32`].
fn as_real(value: f64, precision: Precision) -> f64 {
    match precision {
        Precision::F64 => value,
        Precision::F32 => f64::from(value as f32),
    }
}

/// For each of the `stride` values of a run in `packed` (runs back to back),
/// `Some(v)` when every run has the same finite value `v` (after rounding to the
/// kernel's precision), else `None`.
pub fn constant_slots(packed: &[f64], stride: usize, precision: Precision) -> Vec<Option<f64>> {
    let runs = packed.len() / stride.max(1);
    (0..stride)
        .map(|j| {
            let first = as_real(*packed.get(j)?, precision);
            let same = (1..runs)
                .all(|r| as_real(packed[r * stride + j], precision).to_bits() == first.to_bits());
            (same && first.is_finite() && runs > 0).then_some(first)
        })
        .collect()
}

/// Whether a kernel with `baked` values can score a batch whose constant slots
/// are `constants`: every baked value must be a constant of the batch with the
/// same bits.
pub fn serves(baked: &[Option<f64>], constants: &[Option<f64>]) -> bool {
    baked.len() == constants.len()
        && baked.iter().zip(constants).all(|(b, c)| match (b, c) {
            (None, _) => true,
            (Some(b), Some(c)) => b.to_bits() == c.to_bits(),
            (Some(_), None) => false,
        })
}

/// The values baked in both `a` and `b` with the same bits: what to bake next
/// when a batch no longer fits the current kernel, so that the baked set only
/// ever shrinks and a run rebuilds at most once per slot.
pub fn intersect(a: &[Option<f64>], b: &[Option<f64>]) -> Vec<Option<f64>> {
    a.iter()
        .zip(b)
        .map(|(x, y)| match (x, y) {
            (Some(x), Some(y)) if x.to_bits() == y.to_bits() => Some(*x),
            _ => None,
        })
        .collect()
}

/// Number of baked values.
pub fn count(baked: &[Option<f64>]) -> usize {
    baked.iter().filter(|b| b.is_some()).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_slots_finds_shared_values_only() {
        // Three runs of stride 3: slot 0 varies, slot 1 is shared, slot 2 is NaN.
        let packed = [1.0, 5.0, f64::NAN, 2.0, 5.0, f64::NAN, 3.0, 5.0, f64::NAN];
        let c = constant_slots(&packed, 3, Precision::F64);
        assert_eq!(c, vec![None, Some(5.0), None]);
    }

    #[test]
    fn f32_constants_compare_after_rounding() {
        // Two f64 values that round to the same f32 are one f32 constant.
        let a = 0.1_f64;
        let b = a + 1e-12;
        let packed = [a, b];
        assert_eq!(constant_slots(&packed, 1, Precision::F64), vec![None]);
        assert_eq!(
            constant_slots(&packed, 1, Precision::F32),
            vec![Some(f64::from(0.1_f32))]
        );
    }

    #[test]
    fn serves_and_intersect() {
        let baked = vec![Some(1.0), None, Some(3.0)];
        assert!(serves(&baked, &[Some(1.0), Some(2.0), Some(3.0)]));
        assert!(!serves(&baked, &[Some(1.0), Some(2.0), None]));
        assert!(!serves(&baked, &[Some(1.5), Some(2.0), Some(3.0)]));
        let next = intersect(&baked, &[Some(1.0), Some(2.0), None]);
        assert_eq!(next, vec![Some(1.0), None, None]);
        assert_eq!(count(&next), 1);
    }
}
