//! The campaign file exactly as written: serde structs with
//! `deny_unknown_fields`, no checks beyond types. [`super::Campaign::load`] turns
//! them into a validated [`super::Campaign`].

use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;

use serde::de::{self, MapAccess, Visitor, value::MapAccessDeserializer};
use serde::{Deserialize, Deserializer};

use crate::base::Scale;
use crate::base::data::Column;
use crate::eval::{Backend, PrecisionChoice};
use crate::search::SearchSettings;

/// The whole campaign file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawCampaign {
    /// `"name"`: campaign name, non-empty, no `/` or `\`; names the default
    /// output folder.
    pub name: String,
    /// `"description"`: optional free text.
    pub description: Option<String>,
    /// `"model"`: the key of the retired hand-written tensile model, kept only
    /// to refuse it with the replacement (`"rig": "tensile4"`) named.
    pub model: Option<serde_json::Value>,
    /// `"rig"`: a rig description (see `rigs/`): a shipped rig's id, a rig file
    /// (relative to the campaign's folder) or the rig itself, inline.
    pub rig: Option<serde_json::Value>,
    /// `"params"`: parameters shared by every experiment, by model parameter
    /// name (value in the parameter's SI unit). Parameters with a model default
    /// may be left out. A name given twice is refused.
    #[serde(default, deserialize_with = "unique_keys")]
    pub params: BTreeMap<String, RawParam>,
    /// `"experiments"`: at least one.
    pub experiments: Vec<RawExperiment>,
    /// `"validation"`: records in the form of `experiments`, never fitted:
    /// simulated at the fitted values and scored apart (optional). They take
    /// the shared `params` and fixed values of their own; a free value of
    /// their own (a range in their `params`, `offset` or `initial`) is
    /// refused, as nothing fits it.
    pub validation: Option<Vec<RawExperiment>>,
    /// `"solver"`: integration settings (all optional).
    #[serde(default)]
    pub solver: RawSolver,
    /// `"search"`: genetic-algorithm settings ([`SearchSettings`]); needed by
    /// `rigfit run` only.
    pub search: Option<SearchSettings>,
    /// `"output"`: results folder, relative to the campaign file's folder
    /// (default `results/<name>`).
    pub output: Option<PathBuf>,
}

/// One experiment.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawExperiment {
    /// `"name"`: unique within the campaign, non-empty, no `.`; prefixes the
    /// experiment's own genes (`"v2.k_lin"`).
    pub name: String,
    /// `"data"`: the measured force history.
    pub data: RawData,
    /// `"drive"`: `"velocity"` (default), `{"force": {"t": [s…], "value": [N…]}}`
    /// or `{"force": {"column": "vir_V"}}` (a column of the data file).
    #[serde(default)]
    pub drive: RawDrive,
    /// `"fit_window"`: record-time span scored by the fitness (default: the
    /// whole record).
    pub fit_window: Option<RawWindow>,
    /// `"offset"` (s): `t_model = t_record + offset`; a number (fixed) or
    /// `{"min", "max", "init"?}` (free, linear). Default 0.
    pub offset: Option<RawParam>,
    /// `"weight"`: weight of this experiment in the joint fitness (> 0,
    /// default 1).
    #[serde(default = "one")]
    pub weight: f64,
    /// `"channels"`: the record's measured columns, each fitted against one
    /// of the rig's outputs (instead of `data.column` against output 0).
    #[serde(default)]
    pub channels: Option<Vec<RawChannel>>,
    /// `"params"`: overrides of experiment-scope parameters for this experiment
    /// alone. A name given twice is refused.
    #[serde(default, deserialize_with = "unique_keys")]
    pub params: BTreeMap<String, RawParam>,
    /// `"initial"`: the state the run starts from, by the rig's state names
    /// (`x_<node>` m, `v_<node>` m/s, `s_<friction element>` m, `p_<backlash
    /// element>` m); states left
    /// out start at 0. A compiled rig (`"rig"`) only.
    #[serde(default, deserialize_with = "unique_keys")]
    pub initial: BTreeMap<String, RawInitial>,
}

/// One state's initial value: a number (fixed), `{"min", "max", "init"?}`
/// (free: this experiment's own gene) or `{"column", …}` (from the data file).
#[derive(Debug, Clone, PartialEq)]
pub enum RawInitial {
    /// A value, or a range to search, as a parameter.
    Param(RawParam),
    /// Taken from the experiment's data file.
    Data(RawInitialData),
}

/// An initial value taken from a column of the experiment's data file: the
/// value at the first sample (or the slope there, for a velocity) of a
/// least-squares polynomial of degree `min(2, samples − 1)` through the
/// record's first `samples` samples.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawInitialData {
    /// `"column"`: header name or 0-based index.
    pub column: Column,
    /// `"scale"`: multiplier to the state's unit (m; 1e-3 for mm). Default 1.
    #[serde(default = "one")]
    pub scale: f64,
    /// `"samples"`: how many of the first samples the fit takes (default 1
    /// for a value: the first sample itself; 3 for a slope: the one-sided
    /// second-order difference `(−3x₀ + 4x₁ − x₂)/(2·dt)`).
    pub samples: Option<usize>,
    /// `"slope"`: take the fit's slope (a velocity from a displacement
    /// column) rather than its value. Default: true for a `v_` state.
    pub slope: Option<bool>,
}

impl<'de> Deserialize<'de> for RawInitial {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        let has_column = v.as_object().is_some_and(|m| m.contains_key("column"));
        if has_column {
            RawInitialData::deserialize(v)
                .map(RawInitial::Data)
                .map_err(de::Error::custom)
        } else {
            RawParam::deserialize(v)
                .map(RawInitial::Param)
                .map_err(|e| {
                    de::Error::custom(format!(
                        "{e}; an initial state is a number (fixed), {{\"min\", \"max\", \"init\"?}} \
                         (free) or {{\"column\", \"scale\"?, \"samples\"?, \"slope\"?}} (from the data)"
                    ))
                })
        }
    }
}

/// A JSON object as a map, refusing a key given twice: serde's own maps keep
/// the last value silently, while a duplicate struct field is refused.
pub(crate) fn unique_keys<'de, D, V>(d: D) -> Result<BTreeMap<String, V>, D::Error>
where
    D: Deserializer<'de>,
    V: Deserialize<'de>,
{
    struct Unique<V>(std::marker::PhantomData<V>);
    impl<'de, V: Deserialize<'de>> Visitor<'de> for Unique<V> {
        type Value = BTreeMap<String, V>;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("an object of parameter values by name")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(key) = map.next_key::<String>()? {
                if out.contains_key(&key) {
                    return Err(de::Error::custom(format!(
                        "parameter '{}' is given twice; give each parameter once",
                        crate::base::text::echo_bare(&key)
                    )));
                }
                let value = map.next_value()?;
                out.insert(key, value);
            }
            Ok(out)
        }
    }
    d.deserialize_map(Unique(std::marker::PhantomData))
}

fn one() -> f64 {
    1.0
}

/// Where an experiment's measured history is.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawData {
    /// `"file"`: CSV path, relative to the campaign file's folder.
    pub file: PathBuf,
    /// `"time_column"`: header name or 0-based index (default: 0, the first).
    pub time_column: Option<Column>,
    /// `"column"` (or `"force_column"`): the measured output's column (the
    /// rig's output 0, a force, a displacement or an acceleration), header
    /// name or 0-based index (default: 1, the second).
    #[serde(default, alias = "column")]
    pub force_column: Option<Column>,
    /// `"time_scale"`: multiplier to seconds (default 1; 1e-3 for ms).
    #[serde(default = "one")]
    pub time_scale: f64,
    /// `"scale"` (or `"force_scale"`): multiplier to the unit of the rig's
    /// output 0 (default 1; 1e3 for kN into N, 1e-3 for mm into m).
    #[serde(default = "one", alias = "scale")]
    pub force_scale: f64,
    /// `"encoding"`: the file's text encoding, one of
    /// [`crate::base::encoding::ENCODING_NAMES`] (default: detected).
    #[serde(default)]
    pub encoding: Option<crate::base::encoding::Encoding>,
    /// `"decimal"`: the numbers' decimal mark, `"."` or `","` (default: a
    /// point, or a comma with `;` or tab separators).
    #[serde(default)]
    pub decimal: Option<crate::base::data::Decimal>,
    /// `"format"`: the record's format (`"csv"`, `"tdms"`, `"hdf5"`, `"mat"`,
    /// `"uff"`); default: told by the file's first bytes and its extension.
    #[serde(default)]
    pub format: Option<crate::record::Format>,
}

/// One measured channel of an experiment: a column of its record against
/// one of the rig's outputs.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawChannel {
    /// `"output"`: the rig output it measures, by name.
    pub output: String,
    /// `"column"`: its column in the data file (header name or 0-based index).
    pub column: Column,
    /// `"scale"`: multiplier to the output's unit (default 1).
    #[serde(default = "one")]
    pub scale: f64,
    /// `"weight"`: its weight in the joint fitness, times the experiment's
    /// (> 0, default 1).
    #[serde(default = "one")]
    pub weight: f64,
    /// `"fit_window"`: its scored span (default: the experiment's).
    #[serde(default)]
    pub fit_window: Option<RawWindow>,
}

/// How the actuator is driven.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RawDrive {
    /// Prescribed motion from the `velocity` and `ramp` parameters.
    #[default]
    Velocity,
    /// Force table on the actuator mass.
    Force(RawTable),
}

/// A piecewise-linear table: `t` and `value`, or a `column` of the
/// experiment's data file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawTable {
    /// `"t"`: breakpoint times (s), strictly increasing, at least 2.
    pub t: Option<Vec<f64>>,
    /// `"value"`: force at each breakpoint (N, or the unit the rig's drive
    /// `gain` converts).
    pub value: Option<Vec<f64>>,
    /// `"column"`: instead of `t` and `value`, this column of the
    /// experiment's data file (header name or 0-based index), one breakpoint
    /// per sample at the record's times (resampled with the record).
    pub column: Option<Column>,
}

/// The scored span, in record time.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawWindow {
    /// `"start"` (s): default the first sample.
    pub start: Option<f64>,
    /// `"end"` (s): default the last sample.
    pub end: Option<f64>,
}

/// Integration settings.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSolver {
    /// `"substeps"`: RK4 steps per sample interval, an integer ≥ 1 or `"auto"`
    /// (default).
    #[serde(default)]
    pub substeps: RawSubsteps,
    /// `"backend"`: `"auto"` (default), `"gpu"` or `"cpu"`.
    #[serde(default)]
    pub backend: Backend,
    /// `"precision"`: `"auto"` (default), `"f32"` or `"f64"`; on the CPU
    /// `"f32"` runs a compiled rig's native f32 lanes (f64, with a warning,
    /// for a model without them), anything else f64.
    #[serde(default)]
    pub precision: PrecisionChoice,
    /// `"tolerance"`: the RMS integration error of output 0 (output 0's
    /// unit, > 0) `"auto"` substeps allow; without it, 1 % of the record's
    /// noise estimated from the record.
    #[serde(default, deserialize_with = "positive_tolerance")]
    pub tolerance: Option<f64>,
}

/// A finite tolerance > 0.
fn positive_tolerance<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    let v = f64::deserialize(d)?;
    if v > 0.0 && v.is_finite() {
        Ok(Some(v))
    } else {
        Err(de::Error::custom(format!(
            "expected a tolerance > 0 in the unit of the rig's output 0, found {v}"
        )))
    }
}

/// `"substeps"`: a count or `"auto"`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum RawSubsteps {
    /// Choose from the stability bound.
    #[default]
    Auto,
    /// This many (checked against the stability bound).
    Count(u64),
}

/// A parameter value: a number (fixed) or a range (free).
#[derive(Debug, Clone, PartialEq)]
pub enum RawParam {
    /// Fixed at this value.
    Fixed(f64),
    /// Searched over a range.
    Free(RawRange),
}

/// A free parameter's range.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawRange {
    /// `"min"`: lower bound (parameter unit).
    pub min: f64,
    /// `"max"`: upper bound (parameter unit), > min.
    pub max: f64,
    /// `"scale"`: `"linear"` or `"log"` (default: the model's choice for the
    /// parameter; offsets are always linear).
    pub scale: Option<Scale>,
    /// `"init"`: a value seeded into the initial population, inside the range.
    pub init: Option<f64>,
}

impl<'de> Deserialize<'de> for RawParam {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RawParam;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number (fixed) or {\"min\", \"max\", \"scale\"?, \"init\"?} (free)")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawParam, E> {
                Ok(RawParam::Fixed(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawParam, E> {
                Ok(RawParam::Fixed(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<RawParam, E> {
                Ok(RawParam::Fixed(v as f64))
            }
            /// `null`: no value, i.e. +∞ ("never", for a threshold such as
            /// `e_fracture`); a model refuses it where a finite value is needed.
            fn visit_unit<E: de::Error>(self) -> Result<RawParam, E> {
                Ok(RawParam::Fixed(f64::INFINITY))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<RawParam, A::Error> {
                RawRange::deserialize(MapAccessDeserializer::new(map)).map(RawParam::Free)
            }
        }
        d.deserialize_any(V)
    }
}

impl<'de> Deserialize<'de> for RawSubsteps {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        int_or_str(
            d,
            "an integer ≥ 1 or \"auto\"",
            |v| (v > 0).then_some(RawSubsteps::Count(v)),
            |v| (v == "auto").then_some(RawSubsteps::Auto),
        )
    }
}

impl<'de> Deserialize<'de> for Column {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        int_or_str(
            d,
            "a column name or a 0-based column index",
            |v| Some(Column::Index(v as usize)),
            |v| Some(Column::Name(v.to_string())),
        )
    }
}

/// A value written as a non-negative integer or as a string, each read by
/// its own function; `None` refuses the value as unexpected, saying what was
/// `expected`.
fn int_or_str<'de, D: Deserializer<'de>, T>(
    d: D,
    expected: &'static str,
    int: fn(u64) -> Option<T>,
    text: fn(&str) -> Option<T>,
) -> Result<T, D::Error> {
    struct V<T> {
        expected: &'static str,
        int: fn(u64) -> Option<T>,
        text: fn(&str) -> Option<T>,
    }
    impl<T> Visitor<'_> for V<T> {
        type Value = T;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str(self.expected)
        }
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<T, E> {
            (self.int)(v).ok_or_else(|| E::invalid_value(de::Unexpected::Unsigned(v), &self))
        }
        fn visit_str<E: de::Error>(self, v: &str) -> Result<T, E> {
            (self.text)(v).ok_or_else(|| E::invalid_value(de::Unexpected::Str(v), &self))
        }
    }
    d.deserialize_any(V {
        expected,
        int,
        text,
    })
}
