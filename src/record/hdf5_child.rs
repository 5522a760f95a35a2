//! HDF5 read in a child process, so that a crash inside libhdf5 is an error
//! about one file and not the end of the process that asked.
//!
//! libhdf5 is C, and some releases crash on some corrupted files (Debian 12's
//! 1.10.8 dies by SIGSEGV on a few; 1.14 reports errors instead): no safe
//! Rust can catch that. A program that sets [`read_in_child`] (the `rigfit`
//! binary does, at start) has [`super::hdf5::read`] start that program again
//! as `rigfit __read-hdf5` ([`SUBCOMMAND`]), tethered to the caller
//! (`base::tether`): the file's bytes go to its standard input, it
//! reads them in its own process and writes its [`answer`] to its standard
//! output. A child that dies by a signal, or ends without a whole answer, is
//! a [`FormatError`] of the file. Where nothing sets the switch (the library
//! used directly: the Python package, the tests) HDF5 is read in process.
//!
//! The answer is binary, so that every `f64` (NaN payloads, -0.0, ±inf)
//! comes back with its bits: the tag `MAGIC`, then `0` and a record or `1`
//! and an error. A record is its format, its channel count and each channel
//! (name, unit, timing, values); an error its format and three texts. Counts
//! and lengths are `u64`, numbers their IEEE bits, both little-endian; a
//! text is its length and UTF-8 bytes; an optional field is `0`, or `1` and
//! the field. Nothing may follow the end.

use std::path::PathBuf;
use std::sync::OnceLock;

use super::{Format, FormatError, Record, bits};

/// The hidden subcommand of the `rigfit` binary that reads HDF5 for its parent.
pub const SUBCOMMAND: &str = "__read-hdf5";

/// The first bytes of every answer, with the encoding's version.
const MAGIC: &[u8; 12] = b"rigfit-hdf5\x01";

/// The program started to read HDF5; set once, by [`read_in_child`].
static CHILD_EXE: OnceLock<PathBuf> = OnceLock::new();

/// Makes every HDF5 read of this process (MATLAB v7.3 included) run `exe
/// __read-hdf5` and take the record from it. `exe` is a `rigfit` binary,
/// normally this process's own (`std::env::current_exe()`). The first call
/// wins; later ones change nothing.
pub fn read_in_child(exe: PathBuf) {
    let _ = CHILD_EXE.set(exe);
}

/// The program set by [`read_in_child`], if any.
#[cfg(feature = "hdf5")]
pub(crate) fn child_exe() -> Option<&'static std::path::Path> {
    CHILD_EXE.get().map(PathBuf::as_path)
}

/// The child's side: reads `bytes` as HDF5 in this process and encodes the
/// record or the error as the answer its parent decodes.
pub fn answer(bytes: &[u8]) -> Vec<u8> {
    encode(&super::hdf5::read_in_process(bytes))
}

fn format_code(format: Format) -> u8 {
    match format {
        Format::Csv => 0,
        Format::Tdms => 1,
        Format::Hdf5 => 2,
        Format::Mat => 3,
        Format::Uff => 4,
        Format::Memory => 5,
    }
}

/// The answer for `result`.
fn encode(result: &Result<Record, FormatError>) -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    match result {
        Ok(record) => {
            out.push(0);
            out.push(format_code(record.format));
            bits::channels(&mut out, &record.channels);
        }
        Err(e) => {
            out.push(1);
            out.push(format_code(e.format));
            for s in [&e.at, &e.expected, &e.found] {
                bits::text(&mut out, s);
            }
        }
    }
    out
}

#[cfg(any(feature = "hdf5", test))]
use decoding::decode;

/// The parent's reading of an answer (only a build that reads HDF5 starts a
/// child to answer).
#[cfg(any(feature = "hdf5", test))]
mod decoding {
    use super::{Format, FormatError, MAGIC, Record};
    use crate::record::{Channel, Waveform};

    fn format_of(code: u8) -> Option<Format> {
        Some(match code {
            0 => Format::Csv,
            1 => Format::Tdms,
            2 => Format::Hdf5,
            3 => Format::Mat,
            4 => Format::Uff,
            5 => Format::Memory,
            _ => return None,
        })
    }

    /// What `answer` holds; `None` unless it is one whole answer, nothing missing
    /// and nothing after it.
    pub(super) fn decode(answer: &[u8]) -> Option<Result<Record, FormatError>> {
        let mut r = Reader(answer.strip_prefix(MAGIC)?);
        let result = match r.byte()? {
            0 => {
                let format = format_of(r.byte()?)?;
                let n = r.count(1)?;
                let mut channels = Vec::with_capacity(n);
                for _ in 0..n {
                    let name = r.text()?;
                    let unit = match r.byte()? {
                        0 => None,
                        1 => Some(r.text()?),
                        _ => return None,
                    };
                    let timing = match r.byte()? {
                        0 => None,
                        1 => Some(Waveform {
                            start: r.number()?,
                            increment: r.number()?,
                        }),
                        _ => return None,
                    };
                    let len = r.count(8)?;
                    let values = (0..len).map(|_| r.number()).collect::<Option<_>>()?;
                    channels.push(Channel {
                        name,
                        unit,
                        values,
                        timing,
                    });
                }
                Ok(Record { format, channels })
            }
            1 => Err(FormatError {
                format: format_of(r.byte()?)?,
                at: r.text()?,
                expected: r.text()?,
                found: r.text()?,
            }),
            _ => return None,
        };
        r.0.is_empty().then_some(result)
    }

    /// The answer's bytes not yet decoded.
    struct Reader<'a>(&'a [u8]);

    impl Reader<'_> {
        fn take(&mut self, n: usize) -> Option<&[u8]> {
            let (head, rest) = self.0.split_at_checked(n)?;
            self.0 = rest;
            Some(head)
        }

        fn byte(&mut self) -> Option<u8> {
            Some(self.take(1)?[0])
        }

        fn u64(&mut self) -> Option<u64> {
            Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
        }

        /// A count of items of at least `each` bytes, which the bytes left can
        /// hold (so that a broken answer never makes a large allocation).
        fn count(&mut self, each: usize) -> Option<usize> {
            let n = usize::try_from(self.u64()?).ok()?;
            (n.checked_mul(each)? <= self.0.len()).then_some(n)
        }

        fn number(&mut self) -> Option<f64> {
            Some(f64::from_bits(self.u64()?))
        }

        fn text(&mut self) -> Option<String> {
            let n = self.count(1)?;
            String::from_utf8(self.take(n)?.to_vec()).ok()
        }
    }
}

#[cfg(feature = "hdf5")]
pub(crate) use parent::read;

/// The parent's side: the child started, fed, heard and judged.
#[cfg(feature = "hdf5")]
mod parent {
    use std::io::{Read, Write};
    use std::path::Path;
    use std::process::{Command, ExitStatus, Stdio};

    use super::{Format, FormatError, Record, SUBCOMMAND, decode};

    /// The most of the child's standard error kept, for a message (bytes).
    const MOST_STDERR: u64 = 64 * 1024;

    /// What the error of a failed child says was expected.
    const EXPECTED: &str = "an HDF5 file libhdf5 reads";

    /// The longest answer a file of `file_len` bytes can give: 8 bytes a
    /// sample, and at most the reader's filter ratio plus one samples a byte
    /// of the file (`MOST_FILTER_RATIO` in `hdf5.rs`), with room for the
    /// names; a child that writes more is stopped.
    fn most_answer(file_len: usize) -> usize {
        let per_byte = 8 * (crate::record::hdf5::MOST_FILTER_RATIO + 1);
        file_len.saturating_mul(per_byte).saturating_add(64 << 20)
    }

    fn failed(found: String) -> FormatError {
        FormatError {
            format: Format::Hdf5,
            at: "file".to_string(),
            expected: EXPECTED.to_string(),
            found,
        }
    }

    /// Reads `bytes` (holding the HDF5 signature) in `exe __read-hdf5`.
    pub(crate) fn read(exe: &Path, bytes: &[u8]) -> Result<Record, FormatError> {
        let mut cmd = Command::new(exe);
        cmd.arg(SUBCOMMAND);
        // Killed with this process (base/tether.rs), in a group of its own.
        let mut cmd = crate::base::tether::tethered(cmd);
        cmd.stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let mut child = cmd.spawn().map_err(|e| {
            failed(format!(
                "no process to read it: `{} {SUBCOMMAND}` could not be started: {e}",
                exe.display()
            ))
        })?;
        let (Some(mut stdin), Some(mut stdout), Some(mut stderr)) =
            (child.stdin.take(), child.stdout.take(), child.stderr.take())
        else {
            crate::base::tether::stop(&mut child);
            return Err(failed("no pipes to the process reading it".to_string()));
        };
        let most = most_answer(bytes.len());
        let (answer, status, said) = std::thread::scope(|s| {
            // Written from a thread of its own: the child may answer (or
            // die) before it has read everything, and a full pipe either
            // way would otherwise wait for the other forever. A child that
            // dies early makes the write fail, which its status then tells.
            s.spawn(move || {
                let _ = stdin.write_all(bytes);
            });
            let said = s.spawn(move || {
                let mut kept = Vec::new();
                let _ = (&mut stderr).take(MOST_STDERR).read_to_end(&mut kept);
                let _ = std::io::copy(&mut stderr, &mut std::io::sink());
                kept
            });
            let mut answer = Vec::new();
            let read = (&mut stdout).take(most as u64 + 1).read_to_end(&mut answer);
            if read.is_err() || answer.len() > most {
                crate::base::tether::stop(&mut child);
            }
            drop(stdout);
            let status = child.wait();
            (answer, status, said.join().unwrap_or_default())
        });
        let status = status.map_err(|e| failed(format!("the process reading it was lost: {e}")))?;
        if answer.len() > most {
            return Err(failed(format!(
                "an answer past {most} bytes from the process reading it, which was stopped"
            )));
        }
        match decode(&answer) {
            Some(result) if status.success() => result,
            _ => Err(failed(ended(status, answer.len(), &said))),
        }
    }

    /// How a child without a whole answer ended, for the error's `found`.
    fn ended(status: ExitStatus, answered: usize, said: &[u8]) -> String {
        if let Some(signal) = signal(status) {
            return format!(
                "libhdf5 crashed reading it (signal {signal}, {})",
                name(signal)
            );
        }
        let last = String::from_utf8_lossy(said);
        let last = last.lines().rev().find(|l| !l.trim().is_empty());
        let said = last
            .map(|l| format!(": {}", crate::base::text::echo_bare(l.trim())))
            .unwrap_or_default();
        match status.code() {
            Some(0) => format!(
                "{answered} bytes that are no whole answer from the process reading it{said}"
            ),
            Some(code) => {
                format!("the process reading it ended with exit status {code} and no answer{said}")
            }
            None => format!("the process reading it ended ({status}) with no answer{said}"),
        }
    }

    /// The signal that killed the child: its own status, or the tether's
    /// shell's 128 + N.
    fn signal(status: ExitStatus) -> Option<i32> {
        #[cfg(unix)]
        if let Some(signal) = std::os::unix::process::ExitStatusExt::signal(&status) {
            return Some(signal);
        }
        status
            .code()
            .filter(|c| (129..=128 + 64).contains(c))
            .map(|c| c - 128)
    }

    /// A signal's name, for the common ways a process dies.
    fn name(signal: i32) -> &'static str {
        match signal {
            4 => "SIGILL",
            6 => "SIGABRT",
            7 => "SIGBUS",
            8 => "SIGFPE",
            9 => "SIGKILL",
            11 => "SIGSEGV",
            15 => "SIGTERM",
            _ => "a signal",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{Channel, Waveform};

    fn bits(record: &Record) -> Vec<Vec<u64>> {
        let values = |c: &Channel| c.values.iter().map(|v| v.to_bits()).collect();
        record.channels.iter().map(values).collect()
    }

    fn round_trip(result: &Result<Record, FormatError>) -> Result<Record, FormatError> {
        decode(&encode(result)).expect("a whole answer")
    }

    #[test]
    fn a_record_comes_back_with_every_bit() {
        let odd_nan = f64::from_bits(0x7ff8_0000_dead_beef);
        let record = Record {
            format: Format::Hdf5,
            channels: vec![
                Channel {
                    name: "/tensile/force_N".into(),
                    unit: Some("N".into()),
                    values: vec![
                        f64::NAN,
                        odd_nan,
                        -0.0,
                        0.0,
                        f64::INFINITY,
                        f64::NEG_INFINITY,
                    ],
                    timing: Some(Waveform {
                        start: -0.0,
                        increment: 1e-300,
                    }),
                },
                Channel {
                    name: "/empty".into(),
                    unit: None,
                    values: vec![],
                    timing: None,
                },
                Channel {
                    name: "s.µ".into(),
                    unit: Some(String::new()),
                    values: vec![f64::MIN_POSITIVE / 2.0, f64::MAX],
                    timing: Some(Waveform {
                        start: f64::NAN,
                        increment: f64::INFINITY,
                    }),
                },
            ],
        };
        let back = round_trip(&Ok(record.clone())).unwrap();
        assert_eq!(bits(&back), bits(&record));
        let names = |r: &Record| {
            let c = &r.channels;
            c.iter()
                .map(|c| (c.name.clone(), c.unit.clone()))
                .collect::<Vec<_>>()
        };
        assert_eq!(names(&back), names(&record));
        assert_eq!(back.format, Format::Hdf5);
        let timing = |r: &Record, i: usize| {
            r.channels[i]
                .timing
                .map(|w| (w.start.to_bits(), w.increment.to_bits()))
        };
        for i in 0..3 {
            assert_eq!(timing(&back, i), timing(&record, i));
        }
        let empty = Record {
            format: Format::Mat,
            channels: vec![],
        };
        assert_eq!(round_trip(&Ok(empty.clone())), Ok(empty));
    }

    #[test]
    fn an_error_comes_back_as_it_was() {
        let e = FormatError {
            format: Format::Hdf5,
            at: "dataset /big".into(),
            expected: "at most the file's 9 bytes of samples".into(),
            found: String::new(),
        };
        assert_eq!(round_trip(&Err(e.clone())), Err(e));
    }

    #[test]
    fn a_broken_answer_is_none() {
        let record = Record {
            format: Format::Hdf5,
            channels: vec![Channel {
                name: "x".into(),
                unit: Some("V".into()),
                values: vec![1.0, 2.0],
                timing: None,
            }],
        };
        let whole = encode(&Ok(record));
        for len in 0..whole.len() {
            assert_eq!(decode(&whole[..len]), None, "cut at {len}");
        }
        let mut longer = whole.clone();
        longer.push(0);
        assert_eq!(decode(&longer), None, "a byte after the end");
        let mut other = whole.clone();
        other[MAGIC.len() - 1] = 2;
        assert_eq!(decode(&other), None, "another version");
        // A count far past the bytes left is refused before any allocation.
        let mut huge = MAGIC.to_vec();
        huge.extend([0, 2]);
        huge.extend(u64::MAX.to_le_bytes());
        assert_eq!(decode(&huge), None);
        assert_eq!(decode(b""), None);
    }

    #[test]
    fn the_answer_reads_in_process() {
        let e = decode(&answer(b"not hdf5")).unwrap().unwrap_err();
        assert_eq!((e.format, e.at.as_str()), (Format::Hdf5, "file"));
        assert!(e.found.contains("no HDF5 signature"), "{e}");
    }
}
