//! A record's channels as bytes that keep every bit: each channel's name, its
//! unit and its timing (each `0`, or `1` and the field), then its values,
//! every count and length a little-endian `u64` given before what it counts,
//! every number its IEEE bits, little-endian, every text its length and UTF-8
//! bytes. The HDF5 child's answer carries a record so
//! ([`super::hdf5_child`]), and a record lent from memory is digested so
//! ([`super::lent::Loan::digest_bytes`]): two records give the same bytes
//! exactly when they hold the same names, units, timings and bits.

use super::Channel;

/// Appends `channels`: their count, then each channel.
pub(crate) fn channels(out: &mut Vec<u8>, channels: &[Channel]) {
    count(out, channels.len());
    for c in channels {
        text(out, &c.name);
        match &c.unit {
            Some(unit) => {
                out.push(1);
                text(out, unit);
            }
            None => out.push(0),
        }
        match c.timing {
            Some(w) => {
                out.push(1);
                number(out, w.start);
                number(out, w.increment);
            }
            None => out.push(0),
        }
        count(out, c.values.len());
        out.reserve(8 * c.values.len());
        for &v in &c.values {
            number(out, v);
        }
    }
}

/// Appends a count or length.
pub(crate) fn count(out: &mut Vec<u8>, n: usize) {
    out.extend_from_slice(&(n as u64).to_le_bytes());
}

/// Appends a number's bits.
pub(crate) fn number(out: &mut Vec<u8>, x: f64) {
    out.extend_from_slice(&x.to_bits().to_le_bytes());
}

/// Appends a text: its length, then its UTF-8 bytes.
pub(crate) fn text(out: &mut Vec<u8>, s: &str) {
    count(out, s.len());
    out.extend_from_slice(s.as_bytes());
}
