//! The median, the one order statistic several layers take.

/// The median of `values` (the mean of the middle two for an even count; NaN
/// for none), sorting them in place by `total_cmp`.
pub fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => values[n / 2],
        _ => 0.5 * (values[n / 2 - 1] + values[n / 2]),
    }
}
