// What the run loop (shared/rig_run.wgsl) reads of a rig's controllers, for
// a rig without any: stitched in place of the generated sample clock
// (src/gpu/shaders.rs; src/compile/back/wgsl/clock.rs writes it for a rig
// with controllers). RIG_SAMPLED is a compile-time false, so the driver's
// compiler drops every sampling branch: the kernels are those of a rig
// before controllers existed.

const RIG_SAMPLED: bool = false;
const SAMPLE_SNAP: real = real(0.0);

// No instant ever comes.
fn rig_instant(rg: RigRegime) -> real {
    return REAL_MAX;
}

fn rig_sample_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigRegime {
    return rg;
}

fn rig_sample(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigRegime {
    return rg;
}
