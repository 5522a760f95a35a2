//! The rig description as it is written in a rig file (serde, unknown keys
//! refused). [`crate::compile::lower`] checks it and turns it into a
//! [`crate::compile::Lowered`], one program per drive mode.
//!
//! A rig is a 1-D lumped network: nodes (masses) joined to each other or to
//! ground by elements; drives move or push nodes; outputs combine element forces
//! and node motions. Every coefficient names a parameter of the rig (or is a
//! number, or switches from one parameter to another when an element breaks).

use serde::Deserialize;

use crate::base::{ParamScope, Scale};

/// A whole rig file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigDesc {
    /// Identifier (`"tensile4"`); campaigns name shipped rigs by it.
    pub id: String,
    /// One line on what the rig is.
    #[serde(default)]
    pub doc: String,
    /// Parameters, in the order of every parameter vector.
    pub params: Vec<ParamDesc>,
    /// Nodes (masses). `"ground"` is implicit and fixed.
    pub nodes: Vec<NodeDesc>,
    /// Elements between two nodes or a node and ground.
    pub elements: Vec<ElementDesc>,
    /// Drives; each belongs to a drive mode (`"velocity"`, the default mode of
    /// an experiment, or `"force"`, an experiment driven by a force table).
    #[serde(default)]
    pub drives: Vec<DriveDesc>,
    /// Digital controllers: sampled at fixed instants, their command held
    /// between them and applied to a node as a force.
    #[serde(default)]
    pub controllers: Vec<ControllerDesc>,
    /// Outputs; output 0 is fitted to the measured record.
    pub outputs: Vec<OutputDesc>,
    /// How far the run can reach, for the RK4 stability bound of nonlinear laws.
    #[serde(default)]
    pub reach: Option<ReachDesc>,
}

/// One parameter.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamDesc {
    /// Name in campaign and result files.
    pub name: String,
    /// SI unit.
    pub unit: String,
    /// What it is.
    #[serde(default)]
    pub doc: String,
    /// Rig-wide (default) or per experiment.
    #[serde(default = "rig_scope")]
    pub scope: ParamScope,
    /// Value used when a campaign does not give one.
    #[serde(default)]
    pub default: Option<f64>,
    /// Search scale (default linear).
    #[serde(default)]
    pub scale: Scale,
    /// Physical domain (`"positive"`, `"nonnegative"` or `"any"`): a
    /// campaign's value, bound or `init` outside it is refused. Without it,
    /// derived from the parameter's roles, unit and scale
    /// ([`super::domain::of`]).
    #[serde(default)]
    pub domain: Option<super::domain::Domain>,
}

fn rig_scope() -> ParamScope {
    ParamScope::Rig
}

/// A node: a lumped mass.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NodeDesc {
    /// Name (not `"ground"`).
    pub name: String,
    /// Mass parameter (kg).
    pub mass: Coef,
}

/// A coefficient: a parameter name, a number, or a parameter that switches to
/// another once an element has broken (`c1 → c1_post` at fracture).
#[derive(Debug, Clone)]
pub enum Coef {
    /// A literal in the law's unit.
    Number(f64),
    /// A parameter by name.
    Param(String),
    /// `before` until element `broken` breaks, `after` from then on.
    Switch(SwitchCoef),
}

impl<'de> Deserialize<'de> for Coef {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Coef;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a parameter name, a number, or {\"before\", \"after\", \"broken\"}")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Coef, E> {
                Ok(Coef::Param(v.to_string()))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Coef, E> {
                Ok(Coef::Number(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Coef, E> {
                Ok(Coef::Number(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Coef, E> {
                Ok(Coef::Number(v as f64))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, m: A) -> Result<Coef, A::Error> {
                SwitchCoef::deserialize(serde::de::value::MapAccessDeserializer::new(m))
                    .map(Coef::Switch)
            }
        }
        d.deserialize_any(V)
    }
}

/// See [`Coef::Switch`].
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwitchCoef {
    /// Coefficient while the element is intact.
    pub before: Box<Coef>,
    /// Coefficient once it has broken.
    pub after: Box<Coef>,
    /// A breakable element.
    pub broken: String,
}

/// An element between `between[0]` (a) and `between[1]` (b): elongation
/// `e = x_b − x_a`, rate `ė = v_b − v_a`. Its force `F` (tension positive) acts
/// as `+F` on a and `−F` on b.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElementDesc {
    /// Name, for outputs and messages.
    pub name: String,
    /// The two nodes; either may be `"ground"`.
    pub between: [String; 2],
    /// The spring part.
    #[serde(default)]
    pub spring: Option<SpringLaw>,
    /// The damper part.
    #[serde(default)]
    pub damper: Option<DamperLaw>,
    /// A Coulomb slider with tangential stiffness (its own internal state).
    #[serde(default)]
    pub friction: Option<FrictionLaw>,
    /// The element carries force only in contact (see [`GapDesc`]).
    #[serde(default)]
    pub gap: Option<GapDesc>,
    /// The spring and (viscous) damper sit in series with a play of their own,
    /// whose position is an internal state (see [`BacklashDesc`]).
    #[serde(default)]
    pub backlash: Option<BacklashDesc>,
    /// The element breaks for good when its elongation reaches this (m).
    #[serde(default)]
    pub breaks_at: Option<Coef>,
}

/// Spring laws `F_s(e)`.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case", deny_unknown_fields)]
pub enum SpringLaw {
    /// `k·e`.
    Linear {
        /// Stiffness (N/m).
        k: Coef,
    },
    /// `Σ a_i·eⁱ`, degree ≤ 5.
    Polynomial {
        /// `a_0 … a_n` (N/mⁱ).
        coeffs: Vec<Coef>,
    },
    /// `k·e` up to `limit`, `Σ a_i·eⁱ` beyond (a located switch).
    LinearThenPolynomial {
        /// Stiffness below the limit (N/m).
        k: Coef,
        /// Elongation where the polynomial starts (m).
        limit: Coef,
        /// `a_0 … a_n` (N/mⁱ), degree ≤ 5.
        coeffs: Vec<Coef>,
    },
    /// `(a/b)(e^{b·e} − 1) + c·e` up to the knee `e* = ln((k − c)/a)/b`, then
    /// linear with slope `k` (C¹ at the knee; `e* = 0` when `k ≤ a + c`).
    ExpLinear {
        /// N/m.
        a: Coef,
        /// 1/m.
        b: Coef,
        /// N/m.
        c: Coef,
        /// Stiffness beyond the knee (N/m).
        k: Coef,
    },
    /// `k·|e|^β·sign(e)`.
    PowerLaw {
        /// N/m^β.
        k: Coef,
        /// Exponent β > 0.
        beta: Coef,
    },
    /// A formula of the elongation `x` (m) and the rig's parameters, in N
    /// (`"k*x + k3*x^3"`; see `crate::compile::front::expr` for the grammar).
    Expression {
        /// The formula.
        force: String,
    },
}

/// Damper laws `F_d(ė)`.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case", deny_unknown_fields)]
pub enum DamperLaw {
    /// `c·ė`.
    Viscous {
        /// N·s/m.
        c: Coef,
    },
    /// `c·|ė|^α·sign(ė)`.
    PowerLaw {
        /// N·(s/m)^α.
        c: Coef,
        /// Exponent α > 0.
        alpha: Coef,
    },
    /// `c·ė` for `|ė| ≤ v_knee`, slope `c_high` beyond (bilinear in ė).
    Saturating {
        /// N·s/m.
        c: Coef,
        /// N·s/m beyond the knee.
        c_high: Coef,
        /// Knee velocity (m/s).
        v_knee: Coef,
    },
    /// `c_tension·ė` for `ė ≥ 0`, `c_compression·ė` below.
    Asymmetric {
        /// N·s/m.
        c_tension: Coef,
        /// N·s/m.
        c_compression: Coef,
    },
    /// A formula of the rate `v` (m/s) and the rig's parameters, in N
    /// (`"c*v*abs(v)"`; see `crate::compile::front::expr` for the grammar).
    Expression {
        /// The formula.
        force: String,
    },
}

/// Coulomb friction with stick-slip: a spring `k_t` in series with a slider of
/// limit `f_c`; the slider's position is a state, the element sticks, slips
/// forward or slips backward (located events).
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case", deny_unknown_fields)]
pub enum FrictionLaw {
    /// See [`FrictionLaw`].
    StickSlip {
        /// Slip force (N).
        f_c: Coef,
        /// Tangential (pre-sliding) stiffness (N/m).
        k_t: Coef,
    },
}

/// Backlash with its own play state (the "physical backlash model"): the
/// element's spring `F_s` and viscous damper `c` act in series with a play of
/// half-width `b`, whose position `p` (`|p| ≤ b`) is an internal state. The
/// element's force is `F = F_s(e − p) + c·(ė − ṗ)`. In play `F = 0`, so
/// `ṗ = ė + F_s(e − p)/c`; in contact `p` stands at `±b`, `ṗ = 0` and
/// `F = F_s(e ∓ b) + c·ė`. Play → contact when `p` reaches `±b`, contact →
/// play when `F` changes sign (located events). Needs a spring and a viscous
/// damper with `c > 0`; no gap, no friction on the same element.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BacklashDesc {
    /// Half-width of the play, `b` (m, ≥ 0).
    pub half_width: Coef,
}

/// A gap: one-sided contact (force only once `e > size`, from `e − size`) or
/// two-sided free play (from `e − size` above `size`, `e + size` below `−size`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GapDesc {
    /// `"tension"` (contact once stretched past the gap), `"compression"` (once
    /// compressed past it) or `"free_play"` (both).
    pub kind: GapKind,
    /// Gap size (m, ≥ 0).
    pub size: Coef,
}

/// See [`GapDesc`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GapKind {
    /// Contact for `e > size`.
    Tension,
    /// Contact for `e < −size`.
    Compression,
    /// Contact on both sides.
    FreePlay,
}

/// A drive: what moves or pushes a node in one drive mode.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveDesc {
    /// `"velocity"` (default) or `"force"`: which experiments it applies to.
    #[serde(default = "velocity_mode")]
    pub mode: String,
    /// The node it acts on (for `base_acceleration`: every node).
    #[serde(default)]
    pub node: Option<String>,
    /// The law.
    pub law: DriveLaw,
}

fn velocity_mode() -> String {
    "velocity".into()
}

/// Drive laws.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum DriveLaw {
    /// Prescribed motion `x = v·t − r·(1 − e^{−v·t/r})` (`x = v·t` for `r = 0`),
    /// at rest for `t ≤ 0`; the node's mass plays no part.
    VelocityRamp {
        /// Target velocity (m/s).
        velocity: Coef,
        /// Ramp length (m).
        ramp: Coef,
    },
    /// A force on the node from a table, `gain·table(t)` (N), 0 for `t < 0`;
    /// without `t`/`value` the experiment's table (campaign `"drive": {"force":
    /// …}`, inline or a column of the data file).
    ForceTable(TableDesc),
    /// Base acceleration `a(t) = gain·table(t)` (m/s²), 0 for `t < 0`: states
    /// are relative to the base and every node feels `−m·a(t)`. Without
    /// `t`/`value` (a `"force"`-mode drive) the experiment's table: a measured
    /// acceleration column of the data file (campaign `"drive": {"force":
    /// {"column": …}}`), used as it is, with no integration.
    BaseAccelerationTable(TableDesc),
    /// `s(t) = amplitude·sin(2π·frequency·t + phase)` for `t ≥ 0`, 0 before.
    Sine {
        /// What `s` is (see [`Quantity`]).
        quantity: Quantity,
        /// In the quantity's unit (N, m or m/s²).
        amplitude: Coef,
        /// Hz.
        frequency: Coef,
        /// rad (default 0).
        #[serde(default)]
        phase: Option<Coef>,
    },
    /// A linear sweep `s(t) = amplitude·sin(2π(f_start·t + rate·t²/2))` for
    /// `t ≥ 0`, 0 before: the frequency rises from `f_start` at `rate`.
    Chirp {
        /// What `s` is (see [`Quantity`]).
        quantity: Quantity,
        /// In the quantity's unit.
        amplitude: Coef,
        /// Hz at `t = 0`.
        f_start: Coef,
        /// Hz/s.
        rate: Coef,
    },
    /// An impact: `s(t) = amplitude·sin(π(t − start)/duration)` for
    /// `start ≤ t ≤ start + duration`, 0 otherwise; both ends are located
    /// switches (the pulse's own mode variable).
    HalfSine {
        /// What `s` is (see [`Quantity`]).
        quantity: Quantity,
        /// Peak, in the quantity's unit.
        amplitude: Coef,
        /// Pulse length (s, > 0).
        duration: Coef,
        /// Pulse start (s, default 0).
        #[serde(default)]
        start: Option<Coef>,
    },
}

/// The table of a [`DriveLaw::ForceTable`] or a [`DriveLaw::BaseAccelerationTable`]:
/// `t` and `value` both, or (a `"force"`-mode drive) neither.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableDesc {
    /// Times (s).
    #[serde(default)]
    pub t: Option<Vec<f64>>,
    /// Table values (N for a force, m/s² for an acceleration, or the table's
    /// unit where `gain` converts it).
    #[serde(default)]
    pub value: Option<Vec<f64>>,
    /// Drive units per table unit (default 1): for a force, a motor constant
    /// (N/V) for a table of voltages or a servo stiffness (N/m) for a table of
    /// reference positions; for an acceleration, an accelerometer's
    /// sensitivity for a table of volts or 9.81 for a table in g.
    #[serde(default)]
    pub gain: Option<Coef>,
}

/// A digital controller: at every sample instant `t_k = phase + k·period`
/// (k = 0, 1, …) each discrete state is set, all at once, from its update
/// law, which reads the rig at that instant and the states' values before
/// it; the command state is then held until the next instant and pushes
/// `node` with `gain·command` (N).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerDesc {
    /// Name, for messages and outputs (`{"controller": name}`).
    pub name: String,
    /// `"velocity"` (default) or `"force"`: which experiments it runs in, as
    /// for a drive.
    #[serde(default = "velocity_mode")]
    pub mode: String,
    /// Sample period (s, > 0).
    pub period: f64,
    /// Time of the first sample instant (s, ≥ 0; default 0).
    #[serde(default)]
    pub phase: f64,
    /// The discrete states, in the order they are listed in messages.
    pub states: Vec<DiscreteStateDesc>,
    /// The state that is the held command.
    pub command: String,
    /// Where the command acts.
    pub acts_on: ControllerForce,
}

/// One discrete state of a [`ControllerDesc`].
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiscreteStateDesc {
    /// Name, as update laws read it.
    pub name: String,
    /// Its new value at a sample instant: a formula (the expression
    /// language of the laws) of the rig's parameters, its outputs by name,
    /// the controller's states (their values before the instant), `t` (s),
    /// `period` (s) and, in `"force"` mode, `reference` (the experiment's
    /// table).
    pub update: String,
    /// Value before the first instant (default 0): a number or a parameter.
    #[serde(default)]
    pub initial: Option<Coef>,
}

/// The force a controller's command applies: `gain·command` on `node`
/// (N; `+` pushes the node in its positive direction).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerForce {
    /// The node pushed.
    pub node: String,
    /// N per command unit (a motor constant in N/V; default 1).
    #[serde(default = "unit_gain")]
    pub gain: Coef,
}

/// What a sine, chirp or half-sine drive's signal `s(t)` is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// A force on the node (N).
    Force,
    /// The node's prescribed displacement (m); its velocity and acceleration
    /// are the signal's derivatives and its mass plays no part.
    Displacement,
    /// The base's acceleration (m/s²): no node; states are relative to the
    /// base and every node feels `−m·s(t)`.
    BaseAcceleration,
}

/// An output: a sum of terms.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputDesc {
    /// Name (`"load_cell_force"`).
    pub name: String,
    /// Unit, for files and plots.
    pub unit: String,
    /// Terms, added.
    pub sum: Vec<TermDesc>,
}

/// One term of an output: at most one of the fields, times `gain`; a term
/// with none is the constant `gain` (a sensor's zero offset).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TermDesc {
    /// An element's force (N).
    #[serde(default)]
    pub force: Option<String>,
    /// A node's displacement (m).
    #[serde(default)]
    pub displacement: Option<String>,
    /// A node's velocity (m/s).
    #[serde(default)]
    pub velocity: Option<String>,
    /// A node's acceleration (m/s²).
    #[serde(default)]
    pub acceleration: Option<String>,
    /// A controller's held command (in its own unit, V for a voltage).
    #[serde(default)]
    pub controller: Option<String>,
    /// The frame a displacement, velocity or acceleration is measured in:
    /// required on those terms in a rig whose base moves (a base-acceleration
    /// drive in any drive mode), optional elsewhere (both frames are then the
    /// same), refused on the other terms.
    #[serde(default)]
    pub frame: Option<Frame>,
    /// Factor (default 1; −1 makes a difference): a number, or a
    /// parameter's name (a sensor's sensitivity, fitted or fixed).
    #[serde(default = "unit_gain")]
    pub gain: Coef,
}

/// The frame of a node's motion in an output term.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Frame {
    /// Relative to the fixed ground: what an accelerometer or a laser
    /// vibrometer on the node reads (the node's motion relative to the base
    /// plus the base's own).
    Absolute,
    /// Relative to the moving base: what a sensor between the base and the
    /// node reads (the rig's states under base acceleration).
    Relative,
}

fn unit_gain() -> Coef {
    Coef::Number(1.0)
}

/// Largest elongation (m) and elongation rate (m/s) any element reaches, for the
/// stability bound of nonlinear laws (default 0.01 m and 10 m/s, or the largest
/// `breaks_at` bound).
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReachDesc {
    /// m.
    pub elongation: f64,
    /// m/s.
    pub rate: f64,
}
