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
use crate::base::fsutil::atomic_write;

const FORMAT: &str = "rigfit-search-checkpoint";
/// 2: the method's state in `state.solver` (1 held the GA's population at
/// the state's top).
const VERSION: u32 = 2;

/// What a checkpoint must agree with to be resumed: ordered `key → value` items
/// ("rig" → "tensile4", "data.sha" → …). The search adds its own items (genes,
/// population, seed, method and its settings) to whatever the caller passes.
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

    /// Adds (or replaces) an item whose value is `value` as compact JSON
    /// (a setting's object, the genes).
    pub fn insert_json<T: Serialize + ?Sized>(&mut self, key: &str, value: &T) {
        let text = serde_json::to_string(value).unwrap_or_default();
        self.insert(key.into(), text);
    }

    /// Adds (or replaces) an item in place.
    pub fn insert(&mut self, key: String, value: String) {
        match self.items.iter_mut().find(|(k, _)| *k == key) {
            Some(item) => item.1 = value,
            None => self.items.push((key, value)),
        }
    }

    /// Adds the item `"<what> <path>"` → a digest of the file's bytes (FNV-1a
    /// 64, hex), so that a changed input is named on resume by its own key
    /// (`data file v2.csv: 1f… → 9a…`) instead of one digest of them all. A
    /// file that cannot be read gets its error as the value.
    pub fn with_file(self, what: &str, path: &Path) -> Self {
        // Read as the loader read it: a regular file within the record limit.
        let value =
            match crate::base::fsutil::read_input(path, crate::base::fsutil::MAX_RECORD_BYTES) {
                Ok(bytes) => {
                    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
                    for b in bytes {
                        h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
                    }
                    format!("{h:016x}")
                }
                Err(e) => format!("unreadable: {e}"),
            };
        self.with(format!("{what} {}", path.display()), value)
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

/// How many numbers a JSON tree holds: each is written as a bit pattern of
/// about 28 bytes, so the file's text is allocated once.
fn numbers(v: &Value) -> usize {
    match v {
        Value::Number(_) => 1,
        Value::Array(a) => a.iter().map(numbers).sum(),
        Value::Object(m) => m.values().map(numbers).sum(),
        _ => 0,
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

/// The file as read; [`Checkpoint::save_parts`] writes these fields in this
/// order, with the fingerprint's digest (for people) after the version.
#[derive(Deserialize)]
struct FileForm {
    format: String,
    version: u32,
    checkpoint: WithFloats,
}

impl Checkpoint {
    /// Writes the checkpoint to `path` atomically (see [`atomic_write`]).
    pub fn save(&self, path: &Path) -> Result<(), SearchError> {
        Self::save_parts(
            &self.fingerprint,
            &self.state,
            self.state.solver.clone(),
            path,
        )
    }

    /// [`Self::save`] from borrowed parts and the method's state `solver`
    /// (which takes the place of `state.solver`), moved into the file's tree
    /// rather than copied: for a large population it is the one big tree.
    ///
    /// Floats are written as their bit patterns straight into the file's bytes:
    /// a JSON object per float costs hundreds of bytes in memory, which for a
    /// population of 10⁶ came to gigabytes.
    pub fn save_parts(
        fingerprint: &Fingerprint,
        state: &SearchState,
        solver: Value,
        path: &Path,
    ) -> Result<(), SearchError> {
        #[derive(Serialize)]
        struct Parts<'a> {
            fingerprint: &'a Fingerprint,
            state: &'a SearchState,
        }
        let io = |source| SearchError::Io {
            action: "writing checkpoint",
            path: path.into(),
            source,
        };
        let mut value =
            serde_json::to_value(Parts { fingerprint, state }).map_err(|e| io(e.into()))?;
        let floats = numbers(&value) + numbers(&solver);
        value["state"]["solver"] = solver;
        let mut bytes = Vec::with_capacity(4096 + 28 * floats);
        let head = serde_json::json!(FORMAT);
        bytes.extend_from_slice(br#"{"format":"#);
        serde_json::to_writer(&mut bytes, &head).map_err(|e| io(e.into()))?;
        bytes.extend_from_slice(format!(r#","version":{VERSION},"digest":"#).as_bytes());
        serde_json::to_writer(&mut bytes, &fingerprint.digest()).map_err(|e| io(e.into()))?;
        bytes.extend_from_slice(br#","checkpoint":"#);
        write_with_bits(&value, &mut bytes).map_err(|e| io(e.into()))?;
        bytes.push(b'}');
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
        serde_json::from_value(file.checkpoint.0).map_err(|e| bad(e.to_string()))
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

/// Writes `v` as JSON with every float as `{"f64": "<bits>"}`; the same bytes
/// as serialising the converted tree, without building it.
fn write_with_bits(v: &Value, out: &mut Vec<u8>) -> serde_json::Result<()> {
    match v {
        Value::Number(n) if !n.is_i64() && !n.is_u64() => {
            let bits = n.as_f64().unwrap_or(f64::NAN).to_bits();
            out.extend_from_slice(format!(r#"{{"f64":"{bits:016x}"}}"#).as_bytes());
        }
        Value::Array(a) => {
            out.push(b'[');
            for (i, x) in a.iter().enumerate() {
                if i > 0 {
                    out.push(b',');
                }
                write_with_bits(x, out)?;
            }
            out.push(b']');
        }
        Value::Object(m) => {
            out.push(b'{');
            for (i, (k, x)) in m.iter().enumerate() {
                if i > 0 {
                    out.push(b',');
                }
                serde_json::to_writer(&mut *out, k)?;
                out.push(b':');
                write_with_bits(x, out)?;
            }
            out.push(b'}');
        }
        other => serde_json::to_writer(&mut *out, other)?,
    }
    Ok(())
}

/// A JSON value whose `{"f64": "<bits>"}` objects were turned back into
/// numbers while parsing, so no object is built per float.
struct WithFloats(Value);

impl<'de> Deserialize<'de> for WithFloats {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(FloatsVisitor).map(WithFloats)
    }
}

struct FloatsVisitor;

impl<'de> serde::de::Visitor<'de> for FloatsVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(Value::from(v))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
        Ok(Value::from(v))
    }
    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        Ok(Number::from_f64(v).map_or(Value::Null, Value::Number))
    }
    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_owned()))
    }
    fn visit_string<E>(self, v: String) -> Result<Value, E> {
        Ok(Value::String(v))
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::with_capacity(seq.size_hint().unwrap_or(0));
        while let Some(WithFloats(v)) = seq.next_element()? {
            items.push(v);
        }
        Ok(Value::Array(items))
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        use serde::de::Error;
        let mut m = Map::new();
        while let Some((k, WithFloats(v))) = map.next_entry::<String, WithFloats>()? {
            m.insert(k, v);
        }
        if m.len() == 1
            && let Some(v) = m.get("f64")
        {
            let hex = v
                .as_str()
                .ok_or_else(|| A::Error::custom("`f64` entry is not a string"))?;
            let bits = u64::from_str_radix(hex, 16)
                .map_err(|e| A::Error::custom(format!("bad float bits `{hex}`: {e}")))?;
            let x = f64::from_bits(bits);
            return Number::from_f64(x)
                .map(Value::Number)
                .ok_or_else(|| A::Error::custom(format!("non-finite float {x} in checkpoint")));
        }
        Ok(Value::Object(m))
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
        let mut text = Vec::new();
        write_with_bits(&v, &mut text).unwrap();
        let parsed: WithFloats = serde_json::from_slice(&text).unwrap();
        let back: Vec<f64> = serde_json::from_value(parsed.0).unwrap();
        for (a, b) in xs.iter().zip(&back) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }

    /// The file's float form built as a tree, as earlier versions wrote it.
    fn floats_as_objects(v: Value) -> Value {
        match v {
            Value::Number(n) if !n.is_i64() && !n.is_u64() => {
                let bits = n.as_f64().unwrap().to_bits();
                serde_json::json!({ "f64": format!("{bits:016x}") })
            }
            Value::Array(a) => Value::Array(a.into_iter().map(floats_as_objects).collect()),
            Value::Object(m) => Value::Object(
                m.into_iter()
                    .map(|(k, v)| (k, floats_as_objects(v)))
                    .collect(),
            ),
            other => other,
        }
    }

    #[test]
    fn streamed_floats_are_the_bytes_of_the_tree_form() {
        let v = serde_json::json!({
            "b": [[0.1, 2.0, -3.5e-300], [1e30]],
            "a": {"n": 3, "s": "x\"y", "f": 0.25, "z": null, "t": true},
            "u": 18446744073709551615u64
        });
        let mut streamed = Vec::new();
        write_with_bits(&v, &mut streamed).unwrap();
        assert_eq!(
            String::from_utf8(streamed.clone()).unwrap(),
            serde_json::to_string(&floats_as_objects(v.clone())).unwrap()
        );
        let back: WithFloats = serde_json::from_slice(&streamed).unwrap();
        assert_eq!(back.0, v);
    }

    #[test]
    fn changes_name_keys() {
        let a = Fingerprint::new()
            .with("rig", "tensile4")
            .with("data", "abc");
        let b = Fingerprint::new()
            .with("rig", "tensile4")
            .with("data", "abd")
            .with("x", "1");
        let ch = b.changes_from(&a);
        let keys: Vec<_> = ch.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["data", "x"]);
        assert!(ch[0].1.contains("abc → abd"));
        assert_ne!(a.digest(), b.digest());
    }

    #[test]
    fn a_changed_file_is_named_by_its_own_key() {
        let dir = tempfile::tempdir().unwrap();
        let (c, d) = (dir.path().join("c.json"), dir.path().join("v2.csv"));
        std::fs::write(&c, "{}").unwrap();
        std::fs::write(&d, "t_s,force_N\n0,1\n").unwrap();
        let of = || {
            Fingerprint::new()
                .with_file("campaign file", &c)
                .with_file("data file", &d)
        };
        let saved = of();
        assert!(of().changes_from(&saved).is_empty());
        std::fs::write(&d, "t_s,force_N\n0,2\n").unwrap();
        let changes = of().changes_from(&saved);
        assert_eq!(changes.len(), 1, "{changes:?}");
        assert_eq!(changes[0].0, format!("data file {}", d.display()));
    }
}
