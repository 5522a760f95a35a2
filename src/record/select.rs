//! A record's channels chosen by a campaign's column keys — the same
//! `time_column`, `column` and scales as a CSV's — and turned into the
//! uniformly sampled series a fit reads.
//!
//! A column is named by its index in file order (0-based), by the channel's
//! full name (`tensile/force_N`, `/run1/force`, `rec.force`), or by the last
//! part of that name (`force_N`, `force`) when no other channel ends alike.
//! Time comes from the time column when the campaign names one, otherwise
//! from the measured channel's own waveform timing where the file states it,
//! otherwise from the first channel (as in a CSV).

use std::path::Path;

use super::{Channel, Record, Waveform};
use crate::base::data::{Column, DataError, Series, names_shown, uniform};
use crate::base::text::echo_bare;

/// The measured channel of a record chosen and sampled uniformly.
#[derive(Debug, Clone, PartialEq)]
pub struct Chosen {
    /// Times (s) and values (scaled) of the measured channel.
    pub series: Series,
    /// The measured channel's full name in the file.
    pub channel: String,
    /// The unit the file records for the measured channel.
    pub unit: Option<String>,
    /// The time channel's full name, none where the time comes from the
    /// measured channel's waveform timing.
    pub time_channel: Option<String>,
    /// The unit the file records for the time channel (none where the time
    /// comes from the channel's waveform timing, which is in seconds).
    pub time_unit: Option<String>,
}

/// What a campaign asks of a record: its column keys and scales.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection<'a> {
    /// The time column, where the campaign names one.
    pub time: Option<&'a Column>,
    /// The measured column.
    pub column: &'a Column,
    /// Multiplier turning the time column into seconds.
    pub time_scale: f64,
    /// Multiplier turning the measured column into the rig output's unit.
    pub scale: f64,
}

impl Record {
    /// The index of the channel `column` names, or why there is none.
    pub fn find(&self, column: &Column, file: &Path) -> Result<usize, DataError> {
        let missing = |found: String| DataError::Record {
            file: file.to_path_buf(),
            what: format!("column {column}"),
            expected: format!("one of its {}", self.listing()),
            found,
        };
        match column {
            Column::Index(i) if *i < self.channels.len() => Ok(*i),
            Column::Index(_) => Err(missing("no such index".into())),
            Column::Name(n) => {
                let wanted = n.trim_start_matches('/');
                let full = |c: &Channel| c.name.trim_start_matches('/') == wanted;
                if let Some(i) = self.channels.iter().position(full) {
                    return Ok(i);
                }
                let tail = |c: &Channel| {
                    let name = c.name.as_str();
                    name.strip_suffix(wanted)
                        .is_some_and(|head| head.ends_with('/') || head.ends_with('.'))
                };
                let hits: Vec<usize> = (0..self.channels.len())
                    .filter(|&i| tail(&self.channels[i]))
                    .collect();
                match hits.as_slice() {
                    [i] => Ok(*i),
                    [] => Err(missing("no channel of that name".into())),
                    many => Err(DataError::Record {
                        file: file.to_path_buf(),
                        what: format!("column {column}"),
                        expected: "one channel: name it in full".into(),
                        found: names_shown(many.iter().map(|&i| self.channels[i].name.as_str())),
                    }),
                }
            }
        }
    }

    /// The channels for a message: their count and (at most twelve) names.
    pub fn listing(&self) -> String {
        format!(
            "{} channel(s): {}",
            self.channels.len(),
            names_shown(self.channels.iter().map(|c| c.name.as_str()))
        )
    }

    /// The measured channel `sel` chooses, with its times, scaled, checked
    /// (finite, strictly increasing time) and sampled uniformly as a CSV
    /// record is.
    pub fn choose(&self, sel: &Selection<'_>, file: &Path) -> Result<Chosen, DataError> {
        let m = self.find(sel.column, file)?;
        let measured = &self.channels[m];
        let err = |what: String, expected: &str, found: String| DataError::Record {
            file: file.to_path_buf(),
            what,
            expected: expected.to_string(),
            found,
        };
        let time = match (sel.time, measured.timing) {
            (Some(c), _) => Some(self.find(c, file)?),
            (None, Some(_)) => None,
            (None, None) if m != 0 => Some(0),
            (None, None) => {
                return Err(err(
                    format!("channel '{}'", echo_bare(&measured.name)),
                    "a time: the campaign's \"time_column\", or a channel with its own \
                     waveform timing",
                    format!(
                        "neither, and it is the first channel; the {}",
                        self.listing()
                    ),
                ));
            }
        };
        let (t, time_unit, time_channel) = match time {
            Some(i) => {
                let c = &self.channels[i];
                if c.values.len() != measured.values.len() {
                    return Err(err(
                        format!("time channel '{}'", echo_bare(&c.name)),
                        &format!(
                            "as many samples as channel '{}' ({})",
                            echo_bare(&measured.name),
                            measured.values.len()
                        ),
                        c.values.len().to_string(),
                    ));
                }
                let t = scaled(c, sel.time_scale, file)?;
                (t, c.unit.clone(), Some(c.name.clone()))
            }
            None => {
                if sel.time_scale != 1.0 {
                    return Err(err(
                        format!("channel '{}'", echo_bare(&measured.name)),
                        "\"time_scale\" 1: its times come from the file's waveform timing, in \
                         seconds (name a \"time_column\" to scale a time channel)",
                        crate::base::text::number(sel.time_scale),
                    ));
                }
                let Some(Waveform { start, increment }) = measured.timing else {
                    unreachable!("chosen above: the channel has timing");
                };
                let n = measured.values.len();
                let t = (0..n).map(|k| start + k as f64 * increment).collect();
                (t, None, None)
            }
        };
        let values = scaled(measured, sel.scale, file)?;
        // Finite after `scaled`: no NaN to compare.
        if let Some(k) = t.windows(2).position(|w| w[1] <= w[0]) {
            return Err(err(
                format!("time at sample {}", k + 1),
                "a strictly increasing time",
                format!("{} s after {} s", t[k + 1], t[k]),
            ));
        }
        if t.len() < 2 {
            return Err(DataError::TooFewSamples {
                file: file.to_path_buf(),
                found: t.len(),
            });
        }
        Ok(Chosen {
            series: uniform(t, values, file)?,
            channel: measured.name.clone(),
            unit: measured.unit.clone(),
            time_channel,
            time_unit,
        })
    }
}

/// A channel's values times `scale`, each finite, or the first that is not.
fn scaled(c: &Channel, scale: f64, file: &Path) -> Result<Vec<f64>, DataError> {
    let mut out = Vec::with_capacity(c.values.len());
    for (k, &v) in c.values.iter().enumerate() {
        let s = v * scale;
        if !s.is_finite() {
            let found = if v.is_finite() {
                format!("{v:e} × {scale:e}")
            } else {
                format!("{v}")
            };
            return Err(DataError::Record {
                file: file.to_path_buf(),
                what: format!("channel '{}', sample {k}", echo_bare(&c.name)),
                expected: "a finite number (after scaling)".into(),
                found,
            });
        }
        out.push(s);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::Format;

    fn channel(name: &str, values: Vec<f64>, timing: Option<Waveform>) -> Channel {
        Channel {
            name: name.into(),
            unit: None,
            values,
            timing,
        }
    }

    fn record() -> Record {
        Record {
            format: Format::Tdms,
            channels: vec![
                channel("run/t_s", vec![0.0, 1e-3, 2e-3], None),
                channel(
                    "run/force_N",
                    vec![1.0, 2.0, 3.0],
                    Some(Waveform {
                        start: 0.5,
                        increment: 0.25,
                    }),
                ),
                channel("other/force_N", vec![4.0, 5.0, 6.0], None),
            ],
        }
    }

    fn sel<'a>(time: Option<&'a Column>, column: &'a Column) -> Selection<'a> {
        Selection {
            time,
            column,
            time_scale: 1.0,
            scale: 2.0,
        }
    }

    #[test]
    fn names_match_in_full_or_by_a_unique_last_part() {
        let (r, f) = (record(), Path::new("r.tdms"));
        assert_eq!(r.find(&Column::Name("run/force_N".into()), f).unwrap(), 1);
        assert_eq!(r.find(&Column::Name("/run/force_N".into()), f).unwrap(), 1);
        assert_eq!(r.find(&Column::Name("t_s".into()), f).unwrap(), 0);
        let e = r.find(&Column::Name("force_N".into()), f).unwrap_err();
        assert!(e.to_string().contains("name it in full"), "{e}");
        let e = r.find(&Column::Name("N".into()), f).unwrap_err();
        assert!(e.to_string().contains("3 channel(s): run/t_s"), "{e}");
    }

    #[test]
    fn time_comes_from_the_column_the_waveform_or_the_first_channel() {
        let (r, f) = (record(), Path::new("r.tdms"));
        let (t, force) = (Column::Index(0), Column::Name("run/force_N".into()));
        let by_column = r.choose(&sel(Some(&t), &force), f).unwrap();
        assert_eq!(by_column.series.force, vec![2.0, 4.0, 6.0]);
        assert!((by_column.series.dt - 1e-3).abs() < 1e-15);
        let by_wave = r.choose(&sel(None, &force), f).unwrap();
        assert_eq!(by_wave.series.t, vec![0.5, 0.75, 1.0]);
        let other = Column::Index(2);
        let by_first = r.choose(&sel(None, &other), f).unwrap();
        assert_eq!(by_first.series.t[0], 0.0);
        let e = r
            .choose(&sel(None, &Column::Index(0)), f)
            .unwrap_err()
            .to_string();
        assert!(e.contains("\"time_column\""), "{e}");
    }

    #[test]
    fn waveform_timing_refuses_a_time_scale_and_bad_samples_are_named() {
        let (mut r, f) = (record(), Path::new("r.tdms"));
        let force = Column::Index(1);
        let mut s = sel(None, &force);
        s.time_scale = 1e-3;
        assert!(
            r.choose(&s, f)
                .unwrap_err()
                .to_string()
                .contains("time_scale")
        );
        r.channels[1].values[2] = f64::NAN;
        let e = r.choose(&sel(None, &force), f).unwrap_err().to_string();
        assert!(e.contains("sample 2") && e.contains("NaN"), "{e}");
    }
}
