//! `rigfit identify <method>`: classical identification tools from the papers
//! the shipped rigs come from, each writing a campaign fragment and an SVG
//! figure. One file per method; the options they share are in `common`.

mod arx;
mod common;
mod frf;
mod idim;
mod impedance;
mod nimiso;
mod rfs;
mod sensitivity;

use std::path::Path;

use anyhow::Result;
use clap::{Args, Subcommand};

use super::output::Output;

/// `rigfit identify`.
#[derive(Debug, Args)]
pub struct IdentifyArgs {
    /// The method.
    #[command(subcommand)]
    pub method: Method,
}

/// The identification methods.
#[derive(Debug, Subcommand)]
pub enum Method {
    /// Restoring-force surface and direct parameter estimation of a base-excited
    /// SDOF rig.
    #[command(
        after_help = "As in \"A New Fatigue Testing Rig Based on Inertial Forces\", §3.2–3.3.\n\n\
        Example:\n  \
        rigfit identify rfs rig.csv --x x_m --accel a_ms2 --mass 9 \\\n    \
        --terms linear,cubic,power-stiffness,viscous,cubic-damping,power-damping \\\n    \
        --out sdof.json --svg rfs.svg\n\n\
        Input: CSV with a time column (s), the relative displacement of the mass (m)\n\
        and the base acceleration (m/s²); columns by header name or 1-based position."
    )]
    Rfs(rfs::RfsArgs),
    /// H1/H2 frequency response with coherence and a modal fit.
    #[command(
        after_help = "As in \"Experimental Investigations of Lubricated Bearing Stiffness\" (a thesis\n\
        chapter on a high-speed bearing test rig) and in the paper on data interrogation\n\
        for vehicle suspensions (ASME, 2005).\n\n\
        Example:\n  \
        rigfit identify frf hammer.csv --input force_N --output x_m --modes 2 \\\n    \
        --f-min 5 --f-max 80 --csv frf.csv --svg frf.svg --out modes.json\n\n\
        Input: CSV with a time column (s), the input force (N) and the response\n\
        (m, m/s or m/s², see --response)."
    )]
    Frf(frf::FrfArgs),
    /// Inverse-model least squares for a driven mass with friction (EMPS IDIM-LS).
    #[command(after_help = "Example:\n  \
        rigfit identify idim tests/data/emps/emps_position_voltage.csv \\\n    \
        --position position_m --force controller_voltage_V --gain 35.15065188248547 \\\n    \
        --sample-rate 1000 --out emps.json --svg emps.svg\n\n\
        Input: CSV with the position (m) and the applied force (N, or a signal times --gain).")]
    Idim(idim::IdimArgs),
    /// Reverse-path nonlinear MISO analysis of a force-driven rig (Bendat).
    #[command(
        after_help = "As in \"Non-linear signal analysis applied to surface wear condition monitoring\n\
        in reciprocating sliding testing machines\".\n\n\
        Example:\n  \
        rigfit identify nimiso rig.csv --motion x_m --force force_N --nonlinear cubic \\\n    \
        --f-min 3 --f-max 38 --out rig.json --svg paths.svg\n\n\
        Input: CSV with a time column (s), the measured motion (m) and the applied force (N)."
    )]
    Nimiso(nimiso::NimisoArgs),
    /// Transmissibility, frequency-domain ARX coefficients and the stiffness and
    /// damping of the element between two measured points.
    #[command(
        after_help = "As in the paper on data interrogation for vehicle suspensions (ASME, 2005),\n\
        §2.1.2; the equation numbers here are that paper's.\n\n\
        Example (the strut of the quarter car, unsprung to sprung mass):\n  \
        rigfit identify arx car.csv --input unsprung_acceleration \\\n    \
        --output sprung_acceleration --mass 350 --names k2,c2 --f-min 0.5 --f-max 30 \\\n    \
        --out strut.json --svg strut.svg\n\n\
        The tire (wheel pan to unsprung mass, carrying both masses):\n  \
        rigfit identify arx car.csv --input wheel_pan_acceleration \\\n    \
        --output unsprung_acceleration,sprung_acceleration --mass 40,350 --names k1,c1 ...\n\n\
        Input: CSV with a time column (s), the reference channel and the response\n\
        channels, all the same quantity (accelerations, velocities or displacements)."
    )]
    Arx(arx::ArxArgs),
    /// The 2 × 2 impedance and receptance matrices of a point mass in x and y
    /// from two impacts, with K, C and M fitted.
    #[command(
        after_help = "The two-degree-of-freedom form of the FRF method in \"Experimental Investigations\n\
        of Lubricated Bearing Stiffness\".\n\n\
        Example:\n  \
        rigfit identify impedance hx.csv hy.csv --force force_N --x x_m --y y_m \\\n    \
        --mass 3 --f-min 20 --f-max 400 --out bearing.json --svg impedance.svg\n\n\
        Input: two CSV records of equal rate, the first struck in x, the second in y,\n\
        each with a time column (s), the hammer force (N) and the x and y displacements (m)."
    )]
    Impedance(impedance::ImpedanceArgs),
    /// The change of a quarter car's strut stiffness between two records, by the
    /// experimental sensitivity functions.
    #[command(
        after_help = "As in the paper on data interrogation for vehicle suspensions (ASME, 2005),\n\
        §2.2 and §3.4; the equation numbers here are that paper's.\n\n\
        Example:\n  \
        rigfit identify sensitivity base.csv changed.csv --wheel-pan wheel_pan_acceleration \\\n    \
        --unsprung unsprung_acceleration --sprung sprung_acceleration \\\n    \
        --k1 1.751e5 --c1 1751 --f-min 5 --f-max 15 --name k2 --base-value 3e4 --svg dk.svg\n\n\
        Input: two CSV records (before and after the change), each with a time column (s)\n\
        and the wheel pan's, the unsprung mass's and the sprung mass's motion, all the same\n\
        quantity. The tire force of Eq. 10 stands in for a load cell."
    )]
    Sensitivity(sensitivity::SensitivityArgs),
}

/// Runs one identification method, once the files it would write are
/// checked against its inputs and what exists.
pub fn identify(args: &IdentifyArgs, out: &Output) -> Result<()> {
    let (common, inputs, csv): (&common::Common, Vec<&Path>, Option<&Path>) = match &args.method {
        Method::Rfs(a) => (&a.common, vec![&a.data], None),
        Method::Frf(a) => (&a.common, vec![&a.data], a.csv.as_deref()),
        Method::Idim(a) => (&a.common, vec![&a.data], None),
        Method::Nimiso(a) => (&a.common, vec![&a.data], None),
        Method::Arx(a) => (&a.common, vec![&a.data], a.csv.as_deref()),
        Method::Impedance(a) => (&a.common, vec![&a.x_test, &a.y_test], None),
        Method::Sensitivity(a) => (&a.common, vec![&a.base, &a.changed], None),
    };
    common.check_files(&[("--csv", csv)], &inputs)?;
    match &args.method {
        Method::Rfs(a) => rfs::rfs(a, out),
        Method::Frf(a) => frf::frf(a, out),
        Method::Idim(a) => idim::idim(a, out),
        Method::Nimiso(a) => nimiso::nimiso(a, out),
        Method::Arx(a) => arx::arx(a, out),
        Method::Impedance(a) => impedance::impedance(a, out),
        Method::Sensitivity(a) => sensitivity::sensitivity(a, out),
    }
}
