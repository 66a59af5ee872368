//! The kinetic separation structure drawn over a snapshot: partition
//! triangles, corridor faces, end-edges, middle bridges, the bridges to the
//! point at infinity, and the certificates that fail next.
//!
//! The data drawn are plain doubles for display only ([`StructureOverlay`]);
//! they are extracted from the exact structure by
//! `structure::view::overlay` and never feed back into a simulation.

use crate::structure::view::{Segment, StructureOverlay};
use std::fmt::Write as _;

/// Light fills that alternate between corridors.
/// Outline colour of the hierarchy's outer approximations.
const APPROX_GREEN: &str = "#2e8b57";
const CORRIDOR_FILLS: [&str; 4] = ["#cfe3ff", "#d6f2cf", "#f3d9f5", "#ffe6c7"];
/// The fill of the finite partition triangles.
const TRIANGLE_FILL: &str = "#f7d46b";
/// The colour of certificates that fail next.
const CERT_RED: &str = "#d62020";
/// The colour of middle bridges.
const MID_BLUE: &str = "#1f4fd1";
/// Screen length of a ray to `ω`, in pixels.
const RAY_PX: f64 = 26.0;
/// Width of the legend box, in pixels.
pub(crate) const LEGEND_WIDTH: f64 = 232.0;

/// A time as a short label (six significant digits, no trailing zeros).
pub fn short_time(x: f64) -> String {
    if !x.is_finite() {
        return "?".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let digits = (5 - x.abs().log10().floor() as i64).clamp(0, 12) as usize;
    let s = format!("{x:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Whether every coordinate of `pts` is finite.
fn finite(pts: &[[f64; 2]]) -> bool {
    pts.iter().flatten().all(|x| x.is_finite())
}

/// Draws `overlay` as one SVG group `<g id="structure">` into `out`, with
/// `sx`, `sy` mapping world to screen coordinates.
pub(crate) fn draw(
    out: &mut String,
    overlay: &StructureOverlay,
    sx: &dyn Fn(f64) -> f64,
    sy: &dyn Fn(f64) -> f64,
) {
    let pts = |v: &[[f64; 2]]| -> String {
        let mut s = String::with_capacity(v.len() * 16);
        for p in v {
            let _ = write!(s, "{:.2},{:.2} ", sx(p[0]), sy(p[1]));
        }
        s.trim_end().to_string()
    };
    let line = |out: &mut String, s: &Segment, class: &str, style: &str| {
        if finite(s) {
            let _ = writeln!(
                out,
                r#"<line class="{class}" x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" {style}/>"#,
                sx(s[0][0]),
                sy(s[0][1]),
                sx(s[1][0]),
                sy(s[1][1])
            );
        }
    };
    out.push_str("<g id=\"structure\">\n");
    if overlay.note.is_some() {
        out.push_str("</g>\n");
        return;
    }
    for ap in &overlay.approximations {
        let outline: Vec<[f64; 2]> = ap.iter().map(|x| x.0).collect();
        if outline.len() < 3 || !finite(&outline) {
            continue;
        }
        let _ = writeln!(
            out,
            r##"<polygon class="approximation" points="{}" fill="none" stroke="{APPROX_GREEN}" stroke-width="1.1" stroke-linejoin="round"/>"##,
            pts(&outline)
        );
        for (p, real) in ap {
            if !real {
                let _ = writeln!(
                    out,
                    r##"<circle class="approximation-vertex" cx="{:.2}" cy="{:.2}" r="2" fill="{APPROX_GREEN}"/>"##,
                    sx(p[0]),
                    sy(p[1])
                );
            }
        }
    }
    for (ci, c) in overlay.corridors.iter().enumerate() {
        let fill = CORRIDOR_FILLS[ci % CORRIDOR_FILLS.len()];
        for f in c.faces.iter().filter(|f| f.len() >= 3 && finite(f)) {
            let _ = writeln!(
                out,
                r##"<polygon class="corridor-face" data-corridor="{ci}" points="{}" fill="{fill}" fill-opacity="0.55" stroke="#7a8699" stroke-width="0.6" stroke-linejoin="round"/>"##,
                pts(f)
            );
        }
    }
    for t in overlay.triangles.iter().filter(|t| finite(&t[..])) {
        let _ = writeln!(
            out,
            r##"<polygon class="partition-triangle" points="{}" fill="{TRIANGLE_FILL}" fill-opacity="0.35" stroke="#a07800" stroke-width="0.6" stroke-linejoin="round"/>"##,
            pts(&t[..])
        );
    }
    for (p, d) in &overlay.omega_rays {
        if !(finite(&[*p, *d])) {
            continue;
        }
        let (x1, y1) = (sx(p[0]), sy(p[1]));
        let (x2, y2) = (x1 + RAY_PX * d[0], y1 - RAY_PX * d[1]);
        let _ = writeln!(
            out,
            r##"<line class="omega-ray" x1="{x1:.2}" y1="{y1:.2}" x2="{x2:.2}" y2="{y2:.2}" stroke="#8a8a8a" stroke-width="0.8" stroke-dasharray="1.5 2.5"/>"##
        );
    }
    for s in &overlay.end_edges {
        line(
            out,
            s,
            "end-edge",
            r##"stroke="#33363d" stroke-width="0.9""##,
        );
    }
    for s in &overlay.middle_bridges {
        line(
            out,
            s,
            "middle-bridge",
            &format!(r#"stroke="{MID_BLUE}" stroke-width="1.3" stroke-dasharray="5 3""#),
        );
    }
    for (rank, c) in overlay.certificates.iter().enumerate() {
        if !finite(&c.points) {
            continue;
        }
        let element = if c.kind == "triangle" {
            format!(
                r#"<polygon class="certificate" points="{}" fill="{CERT_RED}" fill-opacity="0.18""#,
                pts(&c.points)
            )
        } else {
            format!(
                r#"<polyline class="certificate" points="{}" fill="none""#,
                pts(&c.points)
            )
        };
        let _ = writeln!(
            out,
            r#"{element} stroke="{CERT_RED}" stroke-width="2" stroke-linejoin="round"><title>{} {} fails at t = {}</title></{}>"#,
            rank + 1,
            c.kind,
            c.time,
            if c.kind == "triangle" {
                "polygon"
            } else {
                "polyline"
            }
        );
        let m = c.points[1];
        let _ = writeln!(
            out,
            r#"<circle cx="{:.2}" cy="{:.2}" r="2.5" fill="{CERT_RED}"/>"#,
            sx(m[0]),
            sy(m[1])
        );
        let _ = writeln!(
            out,
            r##"<text class="certificate-label" x="{:.2}" y="{:.2}" font-size="10" fill="{CERT_RED}" stroke="white" stroke-width="2.5" paint-order="stroke">{}: t = {}</text>"##,
            sx(m[0]) + 4.0,
            sy(m[1]) - 4.0 - 11.0 * (rank % 2) as f64,
            rank + 1,
            short_time(c.time)
        );
    }
    out.push_str("</g>\n");
}

/// Draws the legend of the structure in the top right corner of a picture
/// `width` pixels wide: the kinds of elements and the certificates that fail
/// next.
pub(crate) fn legend(out: &mut String, overlay: &StructureOverlay, width: f64, margin: f64) {
    let mut rows: Vec<(String, String)> = Vec::new();
    let swatch = |fill: &str, stroke: &str| {
        format!(
            r#"<rect x="0" y="-8" width="18" height="10" fill="{fill}" fill-opacity="0.6" stroke="{stroke}" stroke-width="0.6"/>"#
        )
    };
    let stroke = |style: &str| format!(r#"<line x1="0" y1="-3" x2="18" y2="-3" {style}/>"#);
    rows.push((
        swatch(TRIANGLE_FILL, "#a07800"),
        format!(
            "partition triangle ({} finite + {} at ω)",
            overlay.triangles.len(),
            overlay.infinite_triangles
        ),
    ));
    rows.push((
        swatch(CORRIDOR_FILLS[0], "#7a8699"),
        format!(
            "corridor face ({} in {} corridors)",
            overlay.face_count(),
            overlay.corridors.len()
        ),
    ));
    rows.push((
        stroke(r##"stroke="#33363d" stroke-width="0.9""##),
        "end-edge".into(),
    ));
    rows.push((
        stroke(&format!(
            r#"stroke="{MID_BLUE}" stroke-width="1.3" stroke-dasharray="5 3""#
        )),
        "middle bridge".into(),
    ));
    rows.push((
        stroke(r##"stroke="#8a8a8a" stroke-width="0.8" stroke-dasharray="1.5 2.5""##),
        "bridge to ω".into(),
    ));
    if !overlay.approximations.is_empty() {
        let hidden: usize = overlay
            .approximations
            .iter()
            .map(|a| a.iter().filter(|x| !x.1).count())
            .sum();
        rows.push((
            stroke(&format!(r#"stroke="{APPROX_GREEN}" stroke-width="1.1""#)),
            format!("approximation ({hidden} vertices not real)"),
        ));
    }
    rows.push((
        stroke(&format!(r#"stroke="{CERT_RED}" stroke-width="2""#)),
        "certificate failing next".into(),
    ));
    for (rank, c) in overlay.certificates.iter().enumerate() {
        rows.push((
            String::new(),
            format!("{}: {} at t = {}", rank + 1, c.kind, short_time(c.time)),
        ));
    }
    let row_h = 14.0;
    let w = LEGEND_WIDTH;
    let h = 8.0 + row_h * rows.len() as f64;
    let x = (width - margin.max(4.0) - w).max(0.0);
    let y = margin.max(4.0);
    let _ = writeln!(
        out,
        r##"<g id="legend" transform="translate({x:.2},{y:.2})" font-size="10" fill="#111"><rect x="0" y="0" width="{w}" height="{h}" fill="white" fill-opacity="0.88" stroke="#888" stroke-width="0.6" rx="3"/>"##
    );
    for (i, (mark, text)) in rows.iter().enumerate() {
        let ry = 4.0 + row_h * (i as f64 + 1.0) - 3.0;
        let _ = write!(
            out,
            r#"<g transform="translate(6,{ry:.1})">{mark}<text x="{}" y="0">{}</text></g>"#,
            if mark.is_empty() { 10 } else { 24 },
            super::escape_xml(text)
        );
        out.push('\n');
    }
    out.push_str("</g>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_times() {
        assert_eq!(short_time(0.0), "0");
        assert_eq!(short_time(12.5), "12.5");
        assert_eq!(short_time(1.0 / 3.0), "0.333333");
        assert_eq!(short_time(123456.7), "123457");
        assert_eq!(short_time(f64::NAN), "?");
    }
}
