//! The campaign's `"search": {"profiles": …}` setting.

use serde::{Deserialize, Deserializer, Serialize};

/// Profile likelihoods after the polish (see [`super::Profiles`]): how many
/// grid points each parameter gets and how far they reach.
///
/// In a campaign, `"profiles": {"points": 12, "span": 3.0}`; `"profiles":
/// true` takes every default and `false` (or no key) runs none.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileSettings {
    /// Grid points per parameter besides the optimum, half on each side
    /// (default 12; at least 2). A side the first grid does not close gets
    /// as many again, out to the bound.
    #[serde(default = "default_points")]
    pub points: usize,
    /// How far the grid reaches on each side of the optimum, in covariance
    /// half-widths (`1.96 σ` in the gene's scale; default 3.0, > 0); the
    /// elite's spread, where wider, is taken instead.
    #[serde(default = "default_span")]
    pub span: f64,
    /// Levenberg–Marquardt iterations per round at most (default 30); each
    /// scores one batch of every moving grid point and its stencil.
    #[serde(default = "default_iterations")]
    pub max_iterations: usize,
}

impl Default for ProfileSettings {
    fn default() -> Self {
        Self {
            points: default_points(),
            span: default_span(),
            max_iterations: default_iterations(),
        }
    }
}

fn default_points() -> usize {
    12
}
fn default_span() -> f64 {
    3.0
}
fn default_iterations() -> usize {
    30
}

impl ProfileSettings {
    /// The first setting outside its range: `(field, expected, found)`.
    pub fn invalid(&self) -> Option<(&'static str, &'static str, String)> {
        if self.points < 2 {
            return Some(("points", "at least 2", self.points.to_string()));
        }
        if !(self.span > 0.0 && self.span.is_finite()) {
            return Some(("span", "a number > 0", self.span.to_string()));
        }
        None
    }
}

/// `"profiles"` as a campaign may write it: `true` (the defaults), `false`
/// or `null` (none), or the settings' object.
pub(crate) fn deserialize_profiles<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<ProfileSettings>, D::Error> {
    struct Visit;
    impl<'de> serde::de::Visitor<'de> for Visit {
        type Value = Option<ProfileSettings>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("true, false or an object such as {\"points\": 12, \"span\": 3.0}")
        }

        fn visit_bool<E>(self, on: bool) -> Result<Self::Value, E> {
            Ok(on.then(ProfileSettings::default))
        }

        fn visit_unit<E>(self) -> Result<Self::Value, E> {
            Ok(None)
        }

        fn visit_none<E>(self) -> Result<Self::Value, E> {
            Ok(None)
        }

        fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
            ProfileSettings::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                .map(Some)
        }
    }
    d.deserialize_any(Visit)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Deserialize)]
    struct Holder {
        #[serde(default, deserialize_with = "deserialize_profiles")]
        profiles: Option<ProfileSettings>,
    }

    fn read(text: &str) -> Result<Option<ProfileSettings>, String> {
        serde_json::from_str::<Holder>(text)
            .map(|h| h.profiles)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn true_false_and_objects_are_read() {
        assert_eq!(read(r#"{}"#).unwrap(), None);
        assert_eq!(read(r#"{"profiles": false}"#).unwrap(), None);
        assert_eq!(
            read(r#"{"profiles": true}"#).unwrap(),
            Some(ProfileSettings::default())
        );
        let s = read(r#"{"profiles": {"points": 8}}"#).unwrap().unwrap();
        assert_eq!((s.points, s.span), (8, 3.0));
        let e = read(r#"{"profiles": {"pionts": 8}}"#).unwrap_err();
        assert!(e.contains("pionts"), "{e}");
        assert!(read(r#"{"profiles": 3}"#).is_err());
    }

    #[test]
    fn ranges_are_checked() {
        let s = ProfileSettings {
            points: 1,
            ..ProfileSettings::default()
        };
        assert_eq!(s.invalid().unwrap().0, "points");
        let s = ProfileSettings {
            span: 0.0,
            ..ProfileSettings::default()
        };
        assert_eq!(s.invalid().unwrap().0, "span");
        assert!(ProfileSettings::default().invalid().is_none());
    }
}
