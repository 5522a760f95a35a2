//! GPU packing of the tensile4 model: the per-run slots read by
//! `shaders/model_tensile4.wgsl` (keep the slot order in sync with its
//! `rig_load`), with the constants the CPU derives per run precomputed here.

use super::GpuModel;
use super::tensile::{Prepared, ix};

/// Slot names, in packing order; `shaders/model_tensile4.wgsl` reads `P_<NAME>`.
pub const SLOTS: [&str; 31] = [
    "K1",
    "C1",
    "C1_POST",
    "INV_M1",
    "INV_M2",
    "INV_M3",
    "INV_M4",
    "K_LIN",
    "E_YIELD",
    "A0",
    "A1",
    "A2",
    "A3",
    "A4",
    "A5",
    "E_FRACTURE",
    "C2",
    "K3",
    "C3",
    "SLACK_A_OVER_B",
    "SLACK_B",
    "SLACK_C",
    "K4_LIN",
    "C4",
    "GAP",
    "D_STAR",
    "G_STAR",
    "VELOCITY",
    "RAMP",
    "V_OVER_R",
    "V2_OVER_R",
];

/// The packed `e_fracture` of a specimen that never breaks (m).
pub const NEVER_BREAKS: f64 = 1e30;

/// Packs a full tensile parameter vector into [`SLOTS`] order. The slack knee
/// `d*` needs a logarithm, which is computed here in f64 (lavapipe's f64 `log`
/// is wrong); masses are packed as reciprocals; `v/r` (the drive exponent's
/// rate) and `v²/r` are packed as the CPU computes them (0 when there is no
/// ramp, where the kernel discards them).
pub fn pack(params: &[f64], out: &mut Vec<f64>) {
    let p = params;
    let prep = Prepared::new(p);
    let start = out.len();
    out.extend_from_slice(&[
        p[ix::K1],
        p[ix::C1],
        p[ix::C1_POST],
        1.0 / p[ix::M1],
        1.0 / p[ix::M2],
        1.0 / p[ix::M3],
        1.0 / p[ix::M4],
        p[ix::K_LIN],
        p[ix::E_YIELD],
    ]);
    out.extend_from_slice(&p[ix::A0..ix::A0 + 6]);
    out.extend_from_slice(&[
        // The kernels compare against a finite number: +∞ (never breaks)
        // becomes an elongation no run reaches, finite in f32 too.
        p[ix::E_FRACTURE].min(NEVER_BREAKS),
        p[ix::C2],
        p[ix::K3],
        p[ix::C3],
        p[ix::SLACK_A] / p[ix::SLACK_B],
        p[ix::SLACK_B],
        p[ix::SLACK_C],
        p[ix::K4_LIN],
        p[ix::C4],
        p[ix::GAP],
        prep.d_star,
        prep.g_star,
        p[ix::VELOCITY],
        p[ix::RAMP],
        if p[ix::RAMP] > 0.0 {
            p[ix::VELOCITY] / p[ix::RAMP]
        } else {
            0.0
        },
        if p[ix::RAMP] > 0.0 {
            p[ix::VELOCITY] * p[ix::VELOCITY] / p[ix::RAMP]
        } else {
            0.0
        },
    ]);
    debug_assert_eq!(out.len() - start, SLOTS.len());
}

/// The tensile4 plug-in for the GPU kernels.
pub const TENSILE4_GPU: GpuModel = GpuModel::Handwritten {
    wgsl: crate::gpu::shaders::MODEL_TENSILE4,
    slots: &SLOTS,
    pack,
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::tensile::REFERENCE;

    #[test]
    fn pack_fills_every_slot_once() {
        let mut out = Vec::new();
        pack(&REFERENCE, &mut out);
        assert_eq!(out.len(), SLOTS.len());
        assert!(out.iter().all(|v| v.is_finite()));
    }
}
