//! The controllers' sample instants as time events: a step is split exactly
//! at every instant inside it (no crossing search: the time is known), the
//! held states are updated there, and the rest of the step follows. The f64
//! reference ([`super::events::EventStepper`]) and the lanes
//! ([`super::lanes::LaneRunner`]) both take their steps through
//! [`SampleClock::step`]; the kernels' run loop (`shaders/shared/rig_run.wgsl`)
//! makes the same decisions with the same arithmetic.
//!
//! An instant within [`SAMPLE_SNAP`] of a period of a step's end is taken at
//! that end (the usual case, a period that is a whole number of steps, where
//! the instant and the step's end differ by rounding only); one at or before a
//! step's start that was not taken yet (the first, at `t = 0`) is taken at the
//! start. Instants are counted, never re-derived from the time, so none is
//! taken twice or skipped.

use crate::compile::program::Sampling;

/// Fraction of the period within which an instant counts as at a step's end
/// in f64: far above the rounding of `phase + k·period` against the grid's
/// `t0 + i·h` (≈ 1e-12 of a millisecond period at 25 s), far below any
/// period a user writes.
pub const SAMPLE_SNAP: f64 = 1e-9;

/// The same for the f32 kernels, whose times round to 2e-6 s at 25 s: 1 %
/// of the period.
pub const SAMPLE_SNAP_F32: f64 = 1e-2;

/// A run's place in its controllers' schedule: the index of the next instant.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SampleClock {
    /// Index of the next instant not yet taken.
    pub next: u64,
}

impl SampleClock {
    /// Takes every instant not yet taken at or before `t` (within the snap),
    /// each by `update(ctx, t)`; nothing without controllers (`s` `None`).
    pub fn catch_up<C>(
        &mut self,
        s: Option<&Sampling>,
        ctx: &mut C,
        t: f64,
        update: &mut impl FnMut(&mut C, f64),
    ) {
        let Some(s) = s else { return };
        while s.instant(self.next) <= t + SAMPLE_SNAP * s.period {
            update(ctx, t);
            self.next += 1;
        }
    }

    /// One step of length `h` from `t`: `piece(ctx, ta, len)` over each part
    /// between the instants inside it, `update(ctx, tn)` at each of them and
    /// at the step's end where an instant falls there. Without controllers
    /// (`s` `None`) or an instant in it, one piece of exactly `h`.
    pub fn step<C>(
        &mut self,
        s: Option<&Sampling>,
        ctx: &mut C,
        t: f64,
        h: f64,
        piece: &mut impl FnMut(&mut C, f64, f64),
        update: &mut impl FnMut(&mut C, f64),
    ) {
        let Some(s) = s else {
            piece(ctx, t, h);
            return;
        };
        self.catch_up(Some(s), ctx, t, update);
        let end = t + h;
        let snap = SAMPLE_SNAP * s.period;
        let mut ta = t;
        loop {
            let tn = s.instant(self.next);
            if tn < end - snap {
                piece(ctx, ta, tn - ta);
                update(ctx, tn);
                self.next += 1;
                ta = tn;
            } else {
                piece(ctx, ta, if ta == t { h } else { end - ta });
                break;
            }
        }
        self.catch_up(Some(s), ctx, end, update);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sampling(period: f64, phase: f64) -> Sampling {
        Sampling {
            period,
            phase,
            names: vec![],
            update: vec![],
            initial: vec![],
        }
    }

    /// The pieces and updates of `steps` steps of `h` from 0.
    fn walk(s: &Sampling, h: f64, steps: usize) -> (Vec<(f64, f64)>, Vec<f64>) {
        let mut log = (vec![], vec![]);
        let mut clock = SampleClock::default();
        for i in 0..steps {
            clock.step(
                Some(s),
                &mut log,
                i as f64 * h,
                h,
                &mut |l, ta, len| l.0.push((ta, len)),
                &mut |l, tn| l.1.push(tn),
            );
        }
        log
    }

    #[test]
    fn a_period_of_whole_steps_splits_nothing() {
        let (pieces, updates) = walk(&sampling(3e-3, 0.0), 1e-3, 9);
        assert_eq!(pieces.len(), 9);
        assert!(pieces.iter().all(|&(_, len)| len == 1e-3));
        // t = 0 at the first step's start, then every third step's end.
        assert_eq!(updates.len(), 4);
        for (k, &u) in updates.iter().enumerate() {
            assert!((u - k as f64 * 3e-3).abs() < 1e-15, "{u}");
        }
    }

    #[test]
    fn an_instant_inside_a_step_splits_it_exactly_there() {
        let (pieces, updates) = walk(&sampling(0.7e-3, 0.0), 1e-3, 7);
        // Instants 0, 0.7, 1.4, …, 4.9 ms, and 7 × 0.7 = 4.9 < 7: eleven in
        // all (0 to 7.0 ms), the one at 7 ms at the last step's end.
        assert_eq!(updates.len(), 11);
        for (k, &u) in updates.iter().enumerate() {
            assert!((u - k as f64 * 0.7e-3).abs() < 1e-15, "{k}: {u}");
        }
        // The pieces tile [0, 7 ms] without gaps.
        let mut t = 0.0;
        for &(ta, len) in &pieces {
            assert!((ta - t).abs() < 1e-18);
            t = ta + len;
        }
        assert!((t - 7e-3).abs() < 1e-15);
        assert_eq!(pieces.len(), 7 + 9);
    }
}
