//! Modal analysis of a linearised rig: natural frequencies and mode shapes.
//!
//! For `M·ẍ + K·x = 0` with diagonal `M`, the substitution `x = M^{-1/2}·u` turns
//! the generalised problem `K·φ = ω²·M·φ` into the symmetric one
//! `M^{-1/2}·K·M^{-1/2}·u = ω²·u`, solved with nalgebra's symmetric eigen
//! decomposition. The mass-normalised shape is `φ = M^{-1/2}·u` (`φᵀ·M·φ = 1`).

use std::fmt;

use nalgebra::{DMatrix, SymmetricEigen};
use serde::{Deserialize, Serialize};

use crate::model::Linearised;

/// Why a linearised rig cannot be analysed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModesError {
    /// The stiffness matrix does not match the number of degrees of freedom.
    #[error("stiffness matrix has {found} entries, expected {expected} for the dofs given")]
    Size {
        /// `dofs²`.
        expected: usize,
        /// Entries found.
        found: usize,
    },
    /// A mass is not positive and finite.
    #[error("mass of dof '{dof}' is {mass} kg, expected a finite value > 0")]
    Mass {
        /// Name of the dof.
        dof: String,
        /// The offending mass (kg).
        mass: f64,
    },
    /// A stiffness entry is not a finite number: a law is not finite (or not
    /// differentiable) where the rig is linearised.
    #[error(
        "the linearisation is not finite: stiffness entry ({row}, {column}) is {value} N/m, \
         expected a finite number (a law is not finite where the rig is linearised)"
    )]
    NotFinite {
        /// Row's dof.
        row: String,
        /// Column's dof.
        column: String,
        /// The entry (NaN or ±∞).
        value: f64,
    },
}

/// One natural mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// Natural angular frequency (rad/s).
    pub omega: f64,
    /// Mode shape scaled so that its largest |component| is 1 and that component
    /// is positive (m per unit modal coordinate).
    pub shape: Vec<f64>,
    /// Modal mass `φᵀ·M·φ` of [`Mode::shape`] (kg); divide the shape by its square
    /// root for the mass-normalised shape.
    pub modal_mass: f64,
    /// Share of the mode's kinetic energy carried by each dof, `m_i·φ_i² / Σ`;
    /// sums to 1.
    pub energy_share: Vec<f64>,
    /// Index of the dof with the largest energy share.
    pub dominant: usize,
}

impl Mode {
    /// The mass-normalised shape, `φ / √(φᵀ·M·φ)`, so that `φᵀ·M·φ = 1`.
    pub fn mass_normalised(&self) -> Vec<f64> {
        let s = self.modal_mass.sqrt();
        self.shape.iter().map(|x| x / s).collect()
    }
}

/// Natural modes of a linearised rig, sorted by increasing frequency.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeReport {
    /// Name of each degree of freedom, in the order of every shape vector.
    pub dofs: Vec<String>,
    /// The modes, lowest frequency first.
    pub modes: Vec<Mode>,
}

impl ModeReport {
    /// Computes the modes of `lin`. Eigenvalues that rounding pushes slightly
    /// below zero (rigid-body modes) are reported as 0 Hz.
    pub fn new(lin: &Linearised) -> Result<Self, ModesError> {
        let n = lin.dofs.len();
        if lin.stiffness.len() != n * n || lin.mass.len() != n {
            return Err(ModesError::Size {
                expected: n * n,
                found: lin.stiffness.len(),
            });
        }
        for (dof, &mass) in lin.dofs.iter().zip(&lin.mass) {
            if !(mass.is_finite() && mass > 0.0) {
                return Err(ModesError::Mass {
                    dof: (*dof).to_string(),
                    mass,
                });
            }
        }
        if let Some(k) = lin.stiffness.iter().position(|x| !x.is_finite()) {
            return Err(ModesError::NotFinite {
                row: lin.dofs[k / n].to_string(),
                column: lin.dofs[k % n].to_string(),
                value: lin.stiffness[k],
            });
        }
        let inv_sqrt: Vec<f64> = lin.mass.iter().map(|m| 1.0 / m.sqrt()).collect();
        let a = DMatrix::from_fn(n, n, |i, j| {
            // Symmetrise so that tiny asymmetries from assembly cannot leak in.
            let kij = 0.5 * (lin.stiffness[i * n + j] + lin.stiffness[j * n + i]);
            inv_sqrt[i] * kij * inv_sqrt[j]
        });
        let eig = SymmetricEigen::new(a);
        let mut modes: Vec<Mode> = (0..n)
            .map(|c| {
                let omega = eig.eigenvalues[c].max(0.0).sqrt();
                let phi: Vec<f64> = (0..n)
                    .map(|i| inv_sqrt[i] * eig.eigenvectors[(i, c)])
                    .collect();
                Self::mode(omega, phi, &lin.mass)
            })
            .collect();
        modes.sort_by(|a, b| a.omega.total_cmp(&b.omega));
        Ok(Self {
            dofs: lin.dofs.iter().map(|d| (*d).to_string()).collect(),
            modes,
        })
    }

    fn mode(omega: f64, phi: Vec<f64>, mass: &[f64]) -> Mode {
        let peak = phi
            .iter()
            .copied()
            .max_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap_or(1.0);
        let shape: Vec<f64> = phi.iter().map(|x| x / peak).collect();
        let energy: Vec<f64> = shape.iter().zip(mass).map(|(x, m)| m * x * x).collect();
        let modal_mass: f64 = energy.iter().sum();
        let energy_share: Vec<f64> = energy.iter().map(|e| e / modal_mass).collect();
        let dominant = (0..energy_share.len())
            .max_by(|&a, &b| energy_share[a].total_cmp(&energy_share[b]))
            .unwrap_or(0);
        Mode {
            frequency_hz: omega / std::f64::consts::TAU,
            omega,
            shape,
            modal_mass,
            energy_share,
            dominant,
        }
    }

    /// The mode whose kinetic energy `dof` dominates most strongly, if any mode is
    /// dominated by it.
    pub fn dominated_by(&self, dof: &str) -> Option<&Mode> {
        let i = self.dofs.iter().position(|d| d == dof)?;
        self.modes
            .iter()
            .filter(|m| m.dominant == i)
            .max_by(|a, b| a.energy_share[i].total_cmp(&b.energy_share[i]))
    }
}

impl fmt::Display for ModeReport {
    /// A table: one row per mode with its frequency, dominant dof and energy
    /// share, then the shape (max |component| = 1) per dof.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let w = self.dofs.iter().map(|d| d.len()).max().unwrap_or(0).max(9);
        write!(
            f,
            "{:>4}  {:>12}  {:<w$}  {:>6}",
            "mode", "freq (Hz)", "dominant", "share"
        )?;
        for d in &self.dofs {
            write!(f, "  {d:>w$}")?;
        }
        writeln!(f)?;
        for (k, m) in self.modes.iter().enumerate() {
            let dom = &self.dofs[m.dominant];
            let share = 100.0 * m.energy_share[m.dominant];
            write!(
                f,
                "{:>4}  {:>12.2}  {dom:<w$}  {share:>5.1}%",
                k + 1,
                m.frequency_hz
            )?;
            for x in &m.shape {
                write!(f, "  {x:>w$.4}")?;
            }
            writeln!(f)?;
        }
        Ok(())
    }
}
