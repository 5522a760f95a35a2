//! A finished job's folder read back: what its `result.json` says (the
//! campaign file, the fitted values, the seed and the backend), and the one
//! way rigfit changes that file afterwards ([`update_result`]: a top-level key
//! set or replaced, every other byte kept).
//!
//! `rigfit validate` uses both: it reopens a job, simulates records at the
//! fitted values and writes its findings into the same `result.json`.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use serde_json::Value;

use super::{JobError, MANIFEST_FILE};
use crate::base::fsutil::{atomic_write, read_description};
use crate::campaign::Campaign;

/// The result file inside a job's folder.
pub const RESULT_FILE: &str = "result.json";

/// A finished job, as its `result.json` describes it.
#[derive(Debug, Clone)]
pub struct Reopened {
    /// The job's folder.
    pub dir: PathBuf,
    /// The campaign file as the job wrote it (`campaign_file`): the path it
    /// was given, relative to the directory the job ran in unless absolute.
    /// [`Reopened::campaign_path`] finds it.
    pub campaign_file: PathBuf,
    /// The campaign's name (`campaign`).
    pub campaign: String,
    /// The rig's id (`rig`).
    pub rig: String,
    /// Every fitted and fixed value by name (`params`), in the parameter's
    /// SI unit (offsets in s): `"k1"`, `"v2.k_lin"`, `"v2.offset"`.
    pub params: BTreeMap<String, f64>,
    /// The search seed (`seed`).
    pub seed: u64,
    /// `"cpu"` or `"gpu"` (`backend`).
    pub backend: String,
    /// The whole file, parsed.
    pub json: Value,
}

/// Reads `dir/result.json`. A folder without one, or whose `result.json` is
/// not an object with `rigfit_version`, is refused as not a rigfit result;
/// a missing or mistyped key is refused naming the file and its JSON path.
pub fn reopen(dir: &Path) -> Result<Reopened, JobError> {
    let path = dir.join(RESULT_FILE);
    let refuse = |json_path: &str, reason: String| JobError::ResultFile {
        path: path.clone(),
        json_path: json_path.to_string(),
        reason,
    };
    if !dir.is_dir() {
        return Err(refuse(
            "(file)",
            format!("`{}` is not a folder", dir.display()),
        ));
    }
    let text = read_description(&path).map_err(|e| {
        let reason = if e.kind() == std::io::ErrorKind::NotFound {
            "not found: the folder is not a rigfit job's results (or the job has not finished)"
                .to_string()
        } else {
            format!("cannot be read: {e}")
        };
        refuse("(file)", reason)
    })?;
    let json: Value = serde_json::from_str(&text).map_err(|e| {
        refuse(
            "(file)",
            format!("is not JSON ({e}); the folder is not a rigfit job's results"),
        )
    })?;
    let Some(top) = json.as_object() else {
        return Err(refuse(
            "(top level)",
            "expected an object, as rigfit writes; the folder is not a rigfit job's results".into(),
        ));
    };
    if !top.get("rigfit_version").is_some_and(Value::is_string) {
        return Err(refuse(
            "rigfit_version",
            "missing: the file was not written by rigfit".into(),
        ));
    }
    let string = |key: &str| -> Result<String, JobError> {
        match top.get(key) {
            Some(Value::String(s)) => Ok(s.clone()),
            Some(other) => Err(refuse(key, format!("expected a string, found {other}"))),
            None => Err(refuse(key, "missing".into())),
        }
    };
    let campaign_file = PathBuf::from(string("campaign_file")?);
    let seed = match top.get("seed") {
        Some(v) => v.as_u64().ok_or_else(|| {
            refuse(
                "seed",
                format!("expected a non-negative integer, found {v}"),
            )
        })?,
        None => return Err(refuse("seed", "missing".into())),
    };
    let mut params = BTreeMap::new();
    match top.get("params") {
        Some(Value::Object(map)) => {
            for (name, v) in map {
                let x = v.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                    refuse(
                        &format!("params.{name}"),
                        format!("expected a finite number, found {v}"),
                    )
                })?;
                params.insert(name.clone(), x);
            }
        }
        Some(other) => {
            return Err(refuse(
                "params",
                format!("expected an object of values by name, found {other}"),
            ));
        }
        None => return Err(refuse("params", "missing".into())),
    }
    Ok(Reopened {
        dir: dir.to_path_buf(),
        campaign_file,
        campaign: string("campaign")?,
        rig: string("rig")?,
        params,
        seed,
        backend: string("backend")?,
        json,
    })
}

impl Reopened {
    /// The places the campaign file may be, in the order tried: an absolute
    /// `campaign_file` as written; a relative one first against the current
    /// directory (where the job most likely ran, as `rigfit run` resolves
    /// it), then against the result folder's parent (a job run from the
    /// folder above its results, `rigfit run c.json --out results/x`, moved
    /// with them).
    pub fn campaign_candidates(&self) -> Vec<PathBuf> {
        if self.campaign_file.is_absolute() {
            return vec![self.campaign_file.clone()];
        }
        let mut out = vec![self.campaign_file.clone()];
        if let Some(parent) = self.dir.parent() {
            let beside = parent.join(&self.campaign_file);
            if beside != self.campaign_file {
                out.push(beside);
            }
        }
        out
    }

    /// The first of [`Reopened::campaign_candidates`] that is a file; the
    /// error names every place looked at.
    pub fn campaign_path(&self) -> Result<PathBuf, JobError> {
        let candidates = self.campaign_candidates();
        if let Some(p) = candidates.iter().find(|p| p.is_file()) {
            return Ok(p.clone());
        }
        let looked: Vec<String> = candidates
            .iter()
            .map(|p| format!("`{}`", p.display()))
            .collect();
        Err(JobError::ResultFile {
            path: self.dir.join(RESULT_FILE),
            json_path: "campaign_file".into(),
            reason: format!(
                "the campaign file is not at {} (relative paths are tried against the \
                 current directory, then against the result folder's parent)",
                looked.join(" or ")
            ),
        })
    }

    /// The value of a fitted or fixed parameter by its name in `params`.
    pub fn param(&self, name: &str) -> Option<f64> {
        self.params.get(name).copied()
    }
}

/// The job's campaign (`campaign`, loaded by the caller from
/// [`Reopened::campaign_path`] or elsewhere) with every value the job
/// reported set and fixed ([`Campaign::apply_param_file`] on its
/// `result.json`): what the job fitted, ready to simulate.
pub fn fitted_campaign(reopened: &Reopened, campaign: &Campaign) -> Result<Campaign, JobError> {
    let mut fitted = campaign.clone();
    fitted.apply_param_file(&reopened.dir.join(RESULT_FILE))?;
    Ok(fitted)
}

/// Sets (or replaces) the top-level `key` of `dir/result.json` to `value`
/// and writes the file back atomically. Every other byte of the file is
/// kept: a replaced key keeps its place, a new one goes last. Refused: a
/// `result.json` that is a symbolic link or not a plain file, one that the
/// folder's manifest (`rigfit-files.json`) does not list as rigfit's, one
/// that is not a rigfit result ([`reopen`]).
pub fn update_result(dir: &Path, key: &str, value: Value) -> Result<(), JobError> {
    update_result_keys(dir, vec![(key.to_string(), value)])
}

/// [`update_result`] of several top-level keys at once, in one write.
pub fn update_result_keys(dir: &Path, entries: Vec<(String, Value)>) -> Result<(), JobError> {
    let path = dir.join(RESULT_FILE);
    let foreign = |what: String| JobError::ForeignFile {
        path: path.clone(),
        what,
    };
    match fs::symlink_metadata(&path) {
        Ok(m) if m.is_symlink() => {
            return Err(foreign(
                "is a symbolic link; rigfit never writes through a link".into(),
            ));
        }
        Ok(m) if !m.is_file() => return Err(foreign("is not a plain file".into())),
        _ => {}
    }
    if !manifest_lists(dir, RESULT_FILE)? {
        return Err(foreign(format!(
            "was not written by rigfit (it is not in {MANIFEST_FILE})"
        )));
    }
    reopen(dir)?;
    let text = read_description(&path).map_err(|e| JobError::ResultFile {
        path: path.clone(),
        json_path: "(file)".into(),
        reason: format!("cannot be read: {e}"),
    })?;
    let mut next = text;
    for (key, value) in &entries {
        next = set_top_level(&next, key, value).ok_or_else(|| JobError::ResultFile {
            path: path.clone(),
            json_path: "(top level)".into(),
            reason: "expected an object".into(),
        })?;
    }
    atomic_write(&path, next.as_bytes()).map_err(|source| JobError::Write { path, source })
}

/// Whether the folder's manifest lists `name`. A manifest that is missing
/// lists nothing; one that cannot be read or parsed is refused.
fn manifest_lists(dir: &Path, name: &str) -> Result<bool, JobError> {
    let path = dir.join(MANIFEST_FILE);
    let text = match read_description(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => {
            return Err(JobError::ForeignFile {
                path,
                what: format!("cannot be read ({e})"),
            });
        }
    };
    let json: Value = serde_json::from_str(&text).map_err(|e| JobError::ForeignFile {
        path: path.clone(),
        what: format!("is not a rigfit manifest ({e})"),
    })?;
    let files = json.get("files").and_then(Value::as_array);
    Ok(files.is_some_and(|f| f.iter().any(|x| x.as_str() == Some(name))))
}

/// `text` (a JSON object, as rigfit writes it: pretty, two spaces) with the
/// top-level `key` set to `value`: the old value's text replaced where the
/// key is, else the key added last. `None` when `text` is not an object.
fn set_top_level(text: &str, key: &str, value: &Value) -> Option<String> {
    let parsed: Value = serde_json::from_str(text).ok()?;
    parsed.as_object()?;
    // Nested lines one level in; a JSON string never holds a raw newline.
    let pretty = serde_json::to_string_pretty(value)
        .expect("a JSON value serialises")
        .replace('\n', "\n  ");
    let spans = top_level_spans(text)?;
    if let Some(&(_, start, end)) = spans.iter().find(|(k, _, _)| k == key) {
        return Some(format!("{}{pretty}{}", &text[..start], &text[end..]));
    }
    let close = text.rfind('}')?;
    let head = text[..close].trim_end();
    let key_text = serde_json::to_string(key).expect("a string serialises");
    let sep = if spans.is_empty() { "" } else { "," };
    Some(format!(
        "{head}{sep}\n  {key_text}: {pretty}\n{}",
        &text[close..]
    ))
}

/// Each top-level key of the JSON object `text` with the byte span of its
/// value; `None` when `text` is not a well-formed object.
fn top_level_spans(text: &str) -> Option<Vec<(String, usize, usize)>> {
    let bytes = text.as_bytes();
    let skip_ws = |mut i: usize| {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        i
    };
    // The end of the string starting at `i` (a `"`), one past its closing quote.
    let string_end = |mut i: usize| {
        i += 1;
        while i < bytes.len() {
            match bytes[i] {
                b'\\' => i += 2,
                b'"' => return Some(i + 1),
                _ => i += 1,
            }
        }
        None
    };
    let mut i = skip_ws(0);
    if bytes.get(i) != Some(&b'{') {
        return None;
    }
    i += 1;
    let mut out = Vec::new();
    loop {
        i = skip_ws(i);
        match bytes.get(i)? {
            b'}' => return Some(out),
            b',' => {
                i += 1;
                continue;
            }
            b'"' => {}
            _ => return None,
        }
        let key_end = string_end(i)?;
        let key: String = serde_json::from_str(&text[i..key_end]).ok()?;
        i = skip_ws(key_end);
        if bytes.get(i) != Some(&b':') {
            return None;
        }
        let start = skip_ws(i + 1);
        // The value ends at the first `,` or `}` outside strings and brackets.
        let mut depth = 0usize;
        let mut j = start;
        while j < bytes.len() {
            match bytes[j] {
                b'"' => {
                    j = string_end(j)?;
                    continue;
                }
                b'{' | b'[' => depth += 1,
                b'}' | b']' if depth > 0 => depth -= 1,
                b',' | b'}' if depth == 0 => break,
                _ => {}
            }
            j += 1;
        }
        let mut end = j;
        while end > start && bytes[end - 1].is_ascii_whitespace() {
            end -= 1;
        }
        out.push((key, start, end));
        i = j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    const RESULT: &str = "{\n  \"rigfit_version\": \"0.1.0\",\n  \"campaign\": \"c\",\n  \
        \"campaign_file\": \"campaigns/c.json\",\n  \"rig\": \"sdof\",\n  \"seed\": 7,\n  \
        \"backend\": \"cpu\",\n  \"params\": {\n    \"k\": 40000.0,\n    \"v.offset\": 0.0\n  },\n  \
        \"warnings\": [\n    \"a, \\\"quoted\\\" } note\"\n  ]\n}";

    /// A job folder as rigfit leaves it: the result and the manifest naming it.
    fn job(text: &str) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join(RESULT_FILE), text).unwrap();
        let manifest = json!({"about": "files written by rigfit", "files": [RESULT_FILE]});
        fs::write(dir.path().join(MANIFEST_FILE), manifest.to_string()).unwrap();
        dir
    }

    #[test]
    fn a_result_is_read_back() {
        let dir = job(RESULT);
        let r = reopen(dir.path()).unwrap();
        assert_eq!(r.campaign_file, PathBuf::from("campaigns/c.json"));
        assert_eq!(r.rig, "sdof");
        assert_eq!(r.seed, 7);
        assert_eq!(r.backend, "cpu");
        assert_eq!(r.param("k"), Some(40000.0));
        assert_eq!(r.param("v.offset"), Some(0.0));
        assert_eq!(r.json["warnings"][0], "a, \"quoted\" } note");
        let c = r.campaign_candidates();
        assert_eq!(c[0], PathBuf::from("campaigns/c.json"));
        assert_eq!(c[1], dir.path().parent().unwrap().join("campaigns/c.json"));
        let err = r.campaign_path().unwrap_err().to_string();
        assert!(
            err.contains("campaign_file") && err.contains("is not at"),
            "{err}"
        );
    }

    #[test]
    fn what_is_not_a_result_is_refused_naming_the_file_and_key() {
        let empty = tempfile::tempdir().unwrap();
        let err = reopen(empty.path()).unwrap_err().to_string();
        assert!(
            err.contains("result.json") && err.contains("not a rigfit job"),
            "{err}"
        );
        let cases = [
            ("[1, 2]", "(top level)"),
            ("{\"a\": 1}", "rigfit_version"),
            ("not json", "is not JSON"),
            (&RESULT.replace("\"seed\": 7", "\"seed\": -1"), "seed"),
            (
                &RESULT.replace("\"k\": 40000.0", "\"k\": \"soft\""),
                "params.k",
            ),
            (
                &RESULT.replace("\"campaign_file\": \"campaigns/c.json\",", ""),
                "campaign_file: missing",
            ),
        ];
        for (text, needle) in cases {
            let dir = job(text);
            let err = reopen(dir.path()).unwrap_err().to_string();
            assert!(
                err.contains("result.json") && err.contains(needle),
                "{needle}: {err}"
            );
        }
    }

    #[test]
    fn a_key_is_replaced_in_place_or_added_last_and_the_rest_kept() {
        let dir = job(RESULT);
        update_result(dir.path(), "seed", json!(8)).unwrap();
        let text = fs::read_to_string(dir.path().join(RESULT_FILE)).unwrap();
        assert_eq!(text, RESULT.replace("\"seed\": 7", "\"seed\": 8"));
        let v = json!({"experiments": [{"name": "w", "r2": 0.99}], "factor": 2.0});
        update_result(dir.path(), "validation", v.clone()).unwrap();
        update_result(dir.path(), "validation", v.clone()).unwrap();
        let text = fs::read_to_string(dir.path().join(RESULT_FILE)).unwrap();
        let back: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back["validation"], v);
        assert_eq!(back["warnings"][0], "a, \"quoted\" } note");
        let keys: Vec<&String> = back.as_object().unwrap().keys().collect();
        assert_eq!(keys.len(), 9);
        assert!(
            text.starts_with(&RESULT.replace("\"seed\": 7", "\"seed\": 8")[..RESULT.len() - 2])
        );
        assert!(text.ends_with("\"factor\": 2.0\n  }\n}"), "{text}");
        let r = reopen(dir.path()).unwrap();
        assert_eq!(r.seed, 8);
    }

    #[test]
    fn a_result_not_rigfits_or_behind_a_link_is_never_written() {
        let dir = job(RESULT);
        fs::remove_file(dir.path().join(MANIFEST_FILE)).unwrap();
        let err = update_result(dir.path(), "seed", json!(8)).unwrap_err();
        assert!(err.to_string().contains("not written by rigfit"), "{err}");
        assert_eq!(
            fs::read_to_string(dir.path().join(RESULT_FILE)).unwrap(),
            RESULT
        );

        let elsewhere = tempfile::tempdir().unwrap();
        let target = elsewhere.path().join("mine.json");
        fs::write(&target, RESULT).unwrap();
        let linked = job(RESULT);
        fs::remove_file(linked.path().join(RESULT_FILE)).unwrap();
        std::os::unix::fs::symlink(&target, linked.path().join(RESULT_FILE)).unwrap();
        let err = update_result(linked.path(), "seed", json!(8)).unwrap_err();
        assert!(err.to_string().contains("symbolic link"), "{err}");
        assert_eq!(fs::read_to_string(&target).unwrap(), RESULT);
    }

    #[test]
    fn spans_cover_every_top_level_value() {
        let spans = top_level_spans(RESULT).unwrap();
        let keys: Vec<&str> = spans.iter().map(|(k, _, _)| k.as_str()).collect();
        assert_eq!(
            keys,
            [
                "rigfit_version",
                "campaign",
                "campaign_file",
                "rig",
                "seed",
                "backend",
                "params",
                "warnings"
            ]
        );
        for (k, s, e) in &spans {
            let v: Value = serde_json::from_str(&RESULT[*s..*e]).unwrap();
            assert_eq!(v, serde_json::from_str::<Value>(RESULT).unwrap()[k]);
        }
        assert_eq!(
            set_top_level("{}", "a", &json!(1)).unwrap(),
            "{\n  \"a\": 1\n}"
        );
        assert!(set_top_level("[1]", "a", &json!(1)).is_none());
    }
}
