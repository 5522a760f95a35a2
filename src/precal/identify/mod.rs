//! Classical identification tools from the seed documents (`rigfit identify
//! <method>`): closed-form or linear-least-squares estimates that seed and check
//! a search, each run on a CSV record and each turning into a campaign fragment.
//!
//! - [`rfs`] and [`dpe`]: restoring-force surface and direct parameter
//!   estimation of a base-excited SDOF rig (document 000, §3.2–3.3);
//! - [`frf`] and [`modal`]: H1/H2 frequency-response estimates with coherence
//!   and a rational-fraction modal fit (documents 003 and 002); [`impedance`]:
//!   their two-degree-of-freedom form, the 2 × 2 impedance and receptance
//!   matrices of document 003 from two impacts;
//! - [`idim`]: inverse-model least squares for a driven mass with viscous and
//!   Coulomb friction (the EMPS benchmark's IDIM-LS, document 004's friction
//!   rig);
//! - [`transmissibility`]: transmissibility, the frequency-domain ARX model,
//!   the element stiffness and damping from a low-order transmissibility model,
//!   and the experimental sensitivity functions (document 002, §2.1.2, §2.2);
//! - [`columns`], [`signal`], [`lsq`]: the CSV reader, filters and differences,
//!   and the least-squares solve they share; [`plot`]: their SVG figures.

pub mod columns;
pub mod dpe;
pub mod frf;
pub mod idim;
pub mod impedance;
pub mod lsq;
pub mod modal;
pub mod nimiso;
pub mod plot;
pub mod rfs;
pub mod signal;
pub mod transmissibility;
