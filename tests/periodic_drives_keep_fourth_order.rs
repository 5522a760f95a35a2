//! A rig driven by a sine or chirp from `t = 0` integrates at RK4's fourth
//! order: the step from 0 sees the drive as it starts. (Taking the drive's
//! value before the start at `t = 0` itself made every such run first order
//! in the step, and the shipped quarter car's error twenty times larger.)

use std::path::Path;

use rigfit::campaign::Campaign;
use rigfit::job::gene_specs;
use rigfit::model::step_error::{output_0, rms_difference};

/// Output 0's RMS error at 1, 2 and 4 RK4 steps per sample against 64, with
/// the free parameters mid-range.
fn errors(campaign: &str) -> Vec<f64> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("campaigns")
        .join(campaign);
    let c = Campaign::load(&path).unwrap();
    let mid: Vec<f64> = gene_specs(&c).iter().map(|g| g.at_fraction(0.5)).collect();
    let batch = c.batch(&[mid]);
    let x = &c.problem.experiments[0];
    let (params, offset) = (batch.params_of(0, 0), batch.offsets[0][0]);
    let run =
        |n: usize| output_0(&c.model, params, &x.drive, &x.grid(offset, n), &x.window).unwrap();
    let fine = run(64);
    [1, 2, 4]
        .iter()
        .map(|&n| rms_difference(&run(n), &fine))
        .collect()
}

#[test]
fn a_chirp_displacement_drive_converges_at_fourth_order() {
    // The quarter car on a wheel pan that moves as a chirp from t = 0.
    let e = errors("quarter_car_synthetic.json");
    println!("quarter car: {e:?}");
    for w in e.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            ratio > 12.0,
            "halving the step divides the error by {ratio:.2}"
        );
    }
}

#[test]
fn a_chirp_base_acceleration_stays_accurate_from_the_first_step() {
    // The inertial rig's slip table accelerates as a chirp from t = 0; its
    // power-law damping is not smooth at rest, so only the size is checked.
    let e = errors("inertial_sdof_synthetic.json");
    println!("inertial rig: {e:?}");
    assert!(e[0] < 1e-7 && e[2] < e[0] / 4.0, "{e:?}");
}
