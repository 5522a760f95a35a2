//! Checkpoint files: the [`SearchState`] plus the campaign fingerprint, as JSON,
//! written atomically.
//!
//! JSON parsers may round a float's last bit, so every float is stored as its
//! IEEE-754 bit pattern, `{"f64": "3ff0000000000000"}`; a resumed search then
//! continues from exactly the state it stopped in.

use std::path::Path;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Number, Value};

use super::SearchError;
use super::state::SearchState;
use crate::fsutil::atomic_write;

const FORMAT: &str = "rigfit-search-checkpoint";
const VERSION: u32 = 1;

/// What a checkpoint must agree with to be resumed: ordered `key → value` items
/// ("model" → "tensile4", "data.sha" → …). The search adds its own items (genes,
/// population, seed, operators) to whatever the caller passes.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Fingerprint {
    items: Vec<(String, String)>,
}

impl Fingerprint {
    /// An empty fingerprint.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or replaces) an item.
    pub fn with(mut self, key: impl Into<String>, value: impl Into<String>) -> Self {
        self.insert(key.into(), value.into());
        self
    }

    /// Adds (or replaces) an item in place.
    pub fn insert(&mut self, key: String, value: String) {
        match self.items.iter_mut().find(|(k, _)| *k == key) {
            Some(item) => item.1 = value,
            None => self.items.push((key, value)),
        }
    }

    /// The items in insertion order.
    pub fn items(&self) -> &[(String, String)] {
        &self.items
    }

    /// A short digest of all items (FNV-1a 64, hex) for logs and result files.
    pub fn digest(&self) -> String {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for (k, v) in &self.items {
            for b in k.bytes().chain([0]).chain(v.bytes()).chain([0]) {
                h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
        format!("{h:016x}")
    }

    /// Differences from `saved` to `self`, as `(key, line)`, in key order.
    pub fn changes_from(&self, saved: &Fingerprint) -> Vec<(String, String)> {
        let get =
            |f: &Fingerprint, k: &str| f.items.iter().find(|(x, _)| x == k).map(|(_, v)| v.clone());
        let mut keys: Vec<&String> = saved
            .items
            .iter()
            .chain(&self.items)
            .map(|(k, _)| k)
            .collect();
        keys.sort();
        keys.dedup();
        keys.into_iter()
            .filter_map(|k| {
                let line = match (get(saved, k), get(self, k)) {
                    (Some(a), Some(b)) if a == b => return None,
                    (Some(a), Some(b)) => format!("{k}: {} → {}", short(&a), short(&b)),
                    (Some(a), None) => format!("{k}: {} → (absent)", short(&a)),
                    (None, Some(b)) => format!("{k}: (absent) → {}", short(&b)),
                    (None, None) => return None,
                };
                Some((k.clone(), line))
            })
            .collect()
    }
}

fn short(s: &str) -> String {
    const MAX: usize = 60;
    match s.char_indices().nth(MAX) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// A saved search: fingerprint and state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// What the search was run on.
    pub fingerprint: Fingerprint,
    /// Where it stood.
    pub state: SearchState,
}

#[derive(Serialize, Deserialize)]
struct FileForm {
    format: String,
    version: u32,
    digest: String,
    checkpoint: Value,
}

impl Checkpoint {
    /// Writes the checkpoint to `path` atomically (see [`atomic_write`]).
    pub fn save(&self, path: &Path) -> Result<(), SearchError> {
        let io = |source| SearchError::Io {
            action: "writing checkpoint",
            path: path.into(),
            source,
        };
        let value = serde_json::to_value(self).map_err(|e| io(e.into()))?;
        let file = FileForm {
            format: FORMAT.into(),
            version: VERSION,
            digest: self.fingerprint.digest(),
            checkpoint: floats_to_bits(value),
        };
        let bytes = serde_json::to_vec(&file).map_err(|e| io(e.into()))?;
        atomic_write(path, &bytes).map_err(io)
    }

    /// Reads a checkpoint written by [`Self::save`].
    pub fn load(path: &Path) -> Result<Self, SearchError> {
        let bad = |reason: String| SearchError::CheckpointFormat {
            path: path.into(),
            reason,
        };
        let bytes = std::fs::read(path).map_err(|source| SearchError::Io {
            action: "reading checkpoint",
            path: path.into(),
            source,
        })?;
        let file: FileForm = serde_json::from_slice(&bytes).map_err(|e| bad(e.to_string()))?;
        if file.format != FORMAT || file.version != VERSION {
            return Err(bad(format!(
                "format `{}` version {}, expected `{FORMAT}` version {VERSION}",
                file.format, file.version
            )));
        }
        let value = bits_to_floats(file.checkpoint).map_err(bad)?;
        serde_json::from_value(value).map_err(|e| bad(e.to_string()))
    }

    /// Fails with [`SearchError::FingerprintMismatch`] naming every changed key
    /// when `expected` differs from the saved fingerprint.
    pub fn verify(&self, expected: &Fingerprint, path: &Path) -> Result<(), SearchError> {
        let changes = expected.changes_from(&self.fingerprint);
        if changes.is_empty() {
            return Ok(());
        }
        let (changed_keys, changes) = changes.into_iter().unzip();
        Err(SearchError::FingerprintMismatch {
            path: path.into(),
            changed_keys,
            changes,
        })
    }
}

fn floats_to_bits(v: Value) -> Value {
    match v {
        Value::Number(n) if !n.is_i64() && !n.is_u64() => {
            let bits = n.as_f64().unwrap_or(f64::NAN).to_bits();
            let mut m = Map::new();
            m.insert("f64".into(), Value::String(format!("{bits:016x}")));
            Value::Object(m)
        }
        Value::Array(a) => Value::Array(a.into_iter().map(floats_to_bits).collect()),
        Value::Object(m) => {
            Value::Object(m.into_iter().map(|(k, v)| (k, floats_to_bits(v))).collect())
        }
        other => other,
    }
}

fn bits_to_floats(v: Value) -> Result<Value, String> {
    match v {
        Value::Object(m) if m.len() == 1 && m.contains_key("f64") => {
            let hex = m["f64"].as_str().ok_or("`f64` entry is not a string")?;
            let bits =
                u64::from_str_radix(hex, 16).map_err(|e| format!("bad float bits `{hex}`: {e}"))?;
            let x = f64::from_bits(bits);
            Number::from_f64(x)
                .map(Value::Number)
                .ok_or_else(|| format!("non-finite float {x} in checkpoint"))
        }
        Value::Array(a) => a
            .into_iter()
            .map(bits_to_floats)
            .collect::<Result<_, _>>()
            .map(Value::Array),
        Value::Object(m) => m
            .into_iter()
            .map(|(k, v)| bits_to_floats(v).map(|v| (k, v)))
            .collect::<Result<_, _>>()
            .map(Value::Object),
        other => Ok(other),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn awkward_floats_round_trip_bit_for_bit() {
        let xs: [f64; 6] = [
            0.1 + 0.2,
            1.0e30,
            5e-324,
            -2.2250738585072014e-308,
            1.0 / 3.0,
            2.0,
        ];
        let v = serde_json::to_value(xs).unwrap();
        let text = serde_json::to_string(&floats_to_bits(v)).unwrap();
        let back: Vec<f64> =
            serde_json::from_value(bits_to_floats(serde_json::from_str(&text).unwrap()).unwrap())
                .unwrap();
        for (a, b) in xs.iter().zip(&back) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }

    #[test]
    fn changes_name_keys() {
        let a = Fingerprint::new()
            .with("model", "tensile4")
            .with("data", "abc");
        let b = Fingerprint::new()
            .with("model", "tensile4")
            .with("data", "abd")
            .with("x", "1");
        let ch = b.changes_from(&a);
        let keys: Vec<_> = ch.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["data", "x"]);
        assert!(ch[0].1.contains("abc → abd"));
        assert_ne!(a.digest(), b.digest());
    }
}
