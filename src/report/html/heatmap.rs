//! The correlation heat map as a static SVG (each cell with a `<title>` a
//! screen reader reads) and the table of the strongest pairs.

use std::fmt::Write as _;

use super::page::{esc, num};

/// A diverging colour for `r` in `[-1, 1]`: blue below 0, white at 0, red
/// above.
fn colour(r: f64) -> String {
    let r = r.clamp(-1.0, 1.0);
    let (end, w) = if r < 0.0 {
        ([33.0, 102.0, 172.0], -r)
    } else {
        ([178.0, 24.0, 43.0], r)
    };
    let mix = |i: usize| (255.0 + (end[i] - 255.0) * w).round() as u8;
    format!("#{:02x}{:02x}{:02x}", mix(0), mix(1), mix(2))
}

/// The heat map of `corr` over `genes` (`null` cells grey).
pub fn svg(genes: &[String], corr: &[Vec<Option<f64>>]) -> String {
    let n = genes.len();
    let cell = 34.0;
    let left = 12.0 + 7.0 * genes.iter().map(|g| g.chars().count()).max().unwrap_or(4) as f64;
    let top = 12.0;
    let legend = 70.0;
    let width = (left + n as f64 * cell + legend).max(240.0);
    let height = (top + n as f64 * cell + 0.75 * left).max(120.0);
    let mut s = format!(
        r#"<svg class="heat" viewBox="0 0 {width:.0} {height:.0}" width="{width:.0}" height="{height:.0}" role="img" aria-label="Correlation matrix of the {n} free parameters, from -1 (blue) to +1 (red); the table below lists the strongest pairs">"#
    );
    for (i, row) in corr.iter().enumerate().take(n) {
        for (j, r) in row.iter().enumerate().take(n) {
            let (x, y) = (left + j as f64 * cell, top + i as f64 * cell);
            let (fill, text) = match r {
                Some(r) => (colour(*r), format!("{r:.2}")),
                None => ("#cccccc".to_string(), "—".to_string()),
            };
            let _ = write!(
                s,
                r##"<rect x="{x:.1}" y="{y:.1}" width="{cell}" height="{cell}" fill="{fill}" stroke="#fff"><title>{} – {}: r = {text}</title></rect>"##,
                esc(&genes[i]),
                esc(&genes[j])
            );
            let ink = if r.is_some_and(|r| r.abs() > 0.6) {
                "cell inv"
            } else {
                "cell"
            };
            let _ = write!(
                s,
                r#"<text x="{:.1}" y="{:.1}" class="{ink}" aria-hidden="true">{}</text>"#,
                x + cell / 2.0,
                y + cell / 2.0 + 4.0,
                text.replacen("0.", ".", 1)
            );
        }
        let _ = write!(
            s,
            r#"<text x="{:.1}" y="{:.1}" class="row" aria-hidden="true">{}</text>"#,
            left - 6.0,
            top + i as f64 * cell + cell / 2.0 + 4.0,
            esc(&genes[i])
        );
    }
    for (j, g) in genes.iter().enumerate() {
        let (x, y) = (
            left + j as f64 * cell + cell / 2.0,
            top + n as f64 * cell + 8.0,
        );
        let _ = write!(
            s,
            r#"<text x="{x:.1}" y="{y:.1}" class="col" transform="rotate(45 {x:.1} {y:.1})" aria-hidden="true">{}</text>"#,
            esc(g)
        );
    }
    // The colour scale.
    let lx = left + n as f64 * cell + 24.0;
    let steps = 20;
    let h = (n as f64 * cell).max(80.0) / steps as f64;
    for k in 0..steps {
        let r = 1.0 - 2.0 * (k as f64 + 0.5) / steps as f64;
        let _ = write!(
            s,
            r#"<rect x="{lx:.1}" y="{:.1}" width="12" height="{:.2}" fill="{}"/>"#,
            top + k as f64 * h,
            h + 0.5,
            colour(r)
        );
    }
    for (r, y) in [
        ("+1", top),
        ("0", top + steps as f64 * h / 2.0),
        ("−1", top + steps as f64 * h),
    ] {
        let _ = write!(
            s,
            r#"<text x="{:.1}" y="{:.1}" class="tick" aria-hidden="true">{r}</text>"#,
            lx + 16.0,
            y + 4.0
        );
    }
    s.push_str("</svg>");
    s
}

/// The `top` strongest pairs (|r| descending) as table rows.
pub fn strongest_pairs(genes: &[String], corr: &[Vec<Option<f64>>], top: usize) -> String {
    let mut pairs = Vec::new();
    for (i, row) in corr.iter().enumerate() {
        for (j, r) in row.iter().enumerate().skip(i + 1) {
            if let (Some(r), Some(a), Some(b)) = (r, genes.get(i), genes.get(j)) {
                pairs.push((a, b, *r));
            }
        }
    }
    pairs.sort_by(|x, y| y.2.abs().total_cmp(&x.2.abs()));
    let mut s = String::new();
    for (a, b, r) in pairs.into_iter().take(top) {
        let _ = write!(
            s,
            "<tr><td>{}</td><td>{}</td><td class=\"num\">{}</td></tr>",
            esc(a),
            esc(b),
            num(r)
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_come_strongest_first_and_colours_diverge() {
        let g: Vec<String> = ["a", "b", "c"].map(String::from).to_vec();
        let c = vec![
            vec![Some(1.0), Some(0.2), Some(-0.9)],
            vec![Some(0.2), Some(1.0), None],
            vec![Some(-0.9), None, Some(1.0)],
        ];
        let rows = strongest_pairs(&g, &c, 5);
        assert!(
            rows.find("−0.9").unwrap() < rows.find("0.2").unwrap(),
            "{rows}"
        );
        assert_eq!(rows.matches("<tr>").count(), 2);
        assert_eq!(colour(0.0), "#ffffff");
        assert_eq!(colour(1.0), "#b2182b");
        assert!(svg(&g, &c).contains("<title>a – c: r = -0.90</title>"));
    }
}
