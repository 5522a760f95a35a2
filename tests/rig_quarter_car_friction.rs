//! The quarter car of seed document 002 with the strut seal's Coulomb friction
//! (`tests/data/quarter_car_friction/`: the shipped `quarter_car` rig plus a
//! `stick_slip` element in the strut): the campaign recovers the strut, the seal's slip
//! force and its tangential stiffness from a synthetic sprung-mass
//! acceleration record down to the noise floor, and no candidate of the search
//! chatters (the firing rule of `Transition::fires` holds a seal that sticks
//! at the slip limit at a turning point). Not a shipped rig: the GPU leaves
//! the CPU reference at such a stick decision (README, `quarter_car`).

mod seed_rigs_common;

use seed_rigs_common::recover;

#[test]
fn the_campaign_recovers_the_strut_and_its_seal_without_chattering() {
    let r = recover(
        "../tests/data/quarter_car_friction/campaign.json",
        "../tests/data/quarter_car_friction/reference_params.json",
        64,
        30,
        2,
    );
    for name in ["k2", "c2", "c2_high", "v_knee", "k_b", "play", "f_s", "k_s"] {
        assert!(r.determined(name), "{name} undetermined");
    }
    assert_eq!(r.summary.diverged_runs, 0, "runs flagged as chattering");
    r.assert_recovered(1.02, 0.05);
}
