//! Transmissibility, the frequency-domain ARX model, an element's stiffness and
//! damping from a low-order transmissibility model, and the experimental
//! sensitivity functions of *Data interrogation for vehicle suspensions* (§2.1.2 and §3.3; §2.2 and §3.4), one file
//! per method:
//!
//! - [`spectra`]: the block spectra every method reads (shared);
//! - [`ratio`]: the transmissibility and its coherence, and its figure;
//! - [`arx`](mod@arx): the frequency-domain ARX model (Eq. 4–6);
//! - [`element`]: `k` and `c` of one element from a low-order model;
//! - [`sensitivity`]: the sensitivity functions (Eq. 7–8, 10–11) and the
//!   strut's stiffness change.

pub mod arx;
pub mod element;
pub mod ratio;
pub mod sensitivity;
pub mod spectra;

pub use arx::{ArxForm, ArxLine, arx};
pub use element::{ElementFit, element_fit};
pub use ratio::figure;
pub use sensitivity::{
    StiffnessChange, StrutLines, StrutSensitivity, damping_sensitivity, mass_sensitivity,
    sensitivity_figure, stiffness_change, stiffness_sensitivity, strut_sensitivity,
    tire_receptances,
};
pub use spectra::{BlockSpectra, block_spectra, segment_for_averages};
