//! Kernels specialised to a batch: per-run values that are the same in every run
//! (the fixed parameters of a campaign, the grid of a fixed clock offset) are
//! baked into the fitness kernel as constants, so the compiler folds them into
//! the arithmetic instead of keeping them in registers.
//!
//! In a calibration only a handful of parameters are free; the rest are the same
//! in every generation, so one specialised kernel serves the whole run. Which
//! kernel scores a batch depends on that batch alone (its shared values), so
//! a batch gets the same bits whatever was evaluated before it, and a resumed
//! calibration repeats an uninterrupted one. A
//! specialised kernel computes what the generic one computes, from the same
//! values: the baked constants are the exact values the host would upload. The
//! driver's compiler may still regroup arithmetic on folded constants, so the
//! two agree to rounding (tests/gpu_specialised_kernels.rs holds them to 1e-11
//! relative in f64 and 1e-4 in f32), not always bit for bit.

use crate::eval::Precision;

/// Batches with fewer runs than this are scored by the generic kernel: a
/// compile would cost more than it saves.
pub const MIN_RUNS: usize = 64;

/// Specialised kernels an evaluator keeps; the oldest goes first. A calibration
/// needs one (its fixed parameters do not change between generations).
pub const MAX_KERNELS: usize = 4;

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

/// Whether two baked sets are the same slots with the same bits.
pub fn same(a: &[Option<f64>], b: &[Option<f64>]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| match (x, y) {
            (None, None) => true,
            (Some(x), Some(y)) => x.to_bits() == y.to_bits(),
            _ => false,
        })
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
    fn same_compares_slots_and_bits() {
        let a = vec![Some(1.0), None, Some(3.0)];
        assert!(same(&a, &a.clone()));
        assert!(!same(&a, &[Some(1.0), Some(2.0), Some(3.0)]));
        assert!(!same(&a, &[Some(1.0), None, Some(3.5)]));
        assert!(!same(&[Some(0.0)], &[Some(-0.0)]));
        assert_eq!(count(&a), 2);
    }
}
