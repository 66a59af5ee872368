//! Pictures: a snapshot of the scene at one instant, drawn as an SVG string,
//! optionally with the kinetic separation structure over it ([`overlay`]).

pub mod overlay;

pub use crate::structure::view::StructureOverlay;

/// One polygon as drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct SnapshotPolygon {
    /// Its id.
    pub id: String,
    /// World coordinates of its vertices at the snapshot time (display only).
    pub vertices: Vec<[f64; 2]>,
    /// Whether it is fixed.
    pub fixed: bool,
    /// Its velocity at the snapshot time.
    pub velocity: [f64; 2],
}

/// The scene at one instant, for display.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Snapshot {
    /// The time shown.
    pub time: f64,
    /// The polygons still in the scene.
    pub polygons: Vec<SnapshotPolygon>,
    /// The kinetic separation structure at that instant, if drawn.
    pub structure: Option<StructureOverlay>,
}

/// How [`svg`] draws a snapshot.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Width of the picture in pixels.
    pub width: u32,
    /// Height of the picture in pixels.
    pub height: u32,
    /// Empty border around the drawing, in pixels.
    pub margin: f64,
    /// Write each polygon's id at its centre.
    pub show_ids: bool,
    /// Draw each moving polygon's velocity as an arrow from its centre.
    pub show_velocities: bool,
    /// An arrow shows the displacement over this many time units.
    pub velocity_scale: f64,
    /// The world rectangle shown, `[x_min, y_min, x_max, y_max]`; `None`: fit
    /// every polygon.
    pub view: Option<[f64; 4]>,
    /// Draw the snapshot's structure, if it has one.
    pub show_structure: bool,
    /// With the structure, draw a legend box in the top right corner.
    pub show_legend: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 800,
            height: 600,
            margin: 24.0,
            show_ids: true,
            show_velocities: true,
            velocity_scale: 1.0,
            view: None,
            show_structure: true,
            show_legend: true,
        }
    }
}

/// Escapes `&`, `<`, `>`, `"` and `'` for SVG text and attribute values.
pub(crate) fn escape_xml(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Characters that XML 1.0 does not allow at all.
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' && c != '\r' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

/// A distinct colour for the `i`-th moving polygon (golden-angle hues).
fn colour(i: usize) -> (String, String) {
    let hue = (i as f64 * 137.507_764_050_037_85) % 360.0;
    (
        format!("hsl({hue:.1},70%,60%)"),
        format!("hsl({hue:.1},70%,30%)"),
    )
}

/// Draws `snapshot` as a standalone SVG document (y axis pointing up): fixed
/// polygons grey, moving ones in distinct colours, optional ids and velocity
/// arrows, and a caption with the time. Polygons with non-finite coordinates
/// are left out. With [`Snapshot::structure`] and
/// [`RenderOptions::show_structure`], the structure is drawn over the
/// polygons in a group `<g id="structure">` (see [`overlay`]), with a legend.
///
/// ```
/// use kss::render::{svg, RenderOptions, Snapshot, SnapshotPolygon};
/// let snap = Snapshot {
///     time: 1.5,
///     polygons: vec![SnapshotPolygon {
///         id: "a<b".into(),
///         vertices: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
///         fixed: false,
///         velocity: [1.0, 0.0],
///     }],
///     structure: None,
/// };
/// let text = svg(&snap, &RenderOptions::default());
/// assert!(text.starts_with("<svg") && text.contains("a&lt;b") && text.contains("t = 1.5"));
/// ```
pub fn svg(snapshot: &Snapshot, options: &RenderOptions) -> String {
    use std::fmt::Write as _;

    let width = options.width.max(16) as f64;
    let height = options.height.max(16) as f64;
    let caption_h = 22.0;
    let margin = if options.margin.is_finite() {
        options.margin.clamp(0.0, width.min(height) / 3.0)
    } else {
        0.0
    };
    let polygons: Vec<&SnapshotPolygon> = snapshot
        .polygons
        .iter()
        .filter(|p| !p.vertices.is_empty() && p.vertices.iter().flatten().all(|x| x.is_finite()))
        .collect();

    // The world rectangle shown.
    let mut view = match options.view {
        Some(v) if v.iter().all(|x| x.is_finite()) && v[2] > v[0] && v[3] > v[1] => v,
        _ => {
            let mut b = [
                f64::INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
            ];
            for p in &polygons {
                for v in &p.vertices {
                    b[0] = b[0].min(v[0]);
                    b[1] = b[1].min(v[1]);
                    b[2] = b[2].max(v[0]);
                    b[3] = b[3].max(v[1]);
                }
            }
            if !b[0].is_finite() {
                b = [-1.0, -1.0, 1.0, 1.0];
            }
            b
        }
    };
    for (lo, hi) in [(0, 2), (1, 3)] {
        if view[hi] - view[lo] <= 0.0 || !(view[hi] - view[lo]).is_finite() {
            let pad = view[lo].abs().max(1.0) * 1e-3;
            view[lo] -= pad;
            view[hi] += pad;
        }
    }
    let structure = snapshot
        .structure
        .as_ref()
        .filter(|_| options.show_structure);
    // The legend gets a column of its own on the right when there is room.
    let legend = structure.filter(|o| options.show_legend && o.note.is_none());
    let legend_column = match legend {
        Some(_) if width >= 3.0 * overlay::LEGEND_WIDTH => overlay::LEGEND_WIDTH + 8.0,
        _ => 0.0,
    };
    let avail_w = (width - 2.0 * margin - legend_column).max(1.0);
    let avail_h = (height - 2.0 * margin - caption_h).max(1.0);
    let scale = (avail_w / (view[2] - view[0])).min(avail_h / (view[3] - view[1]));
    let off_x = margin + (avail_w - scale * (view[2] - view[0])) / 2.0;
    let off_y = margin + (avail_h - scale * (view[3] - view[1])) / 2.0;
    // World to screen, y flipped.
    let sx = |x: f64| off_x + (x - view[0]) * scale;
    let sy = |y: f64| off_y + (view[3] - y) * scale;

    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif">"#,
        w = width,
        h = height
    );
    out.push_str(
        "<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"7\" markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"#222\"/></marker></defs>\n",
    );
    let _ = writeln!(
        out,
        r#"<rect x="0" y="0" width="{width}" height="{height}" fill="white"/>"#
    );
    let clip_h = height - caption_h;
    let _ = writeln!(
        out,
        r#"<clipPath id="scene"><rect x="0" y="0" width="{width}" height="{clip_h}"/></clipPath>"#
    );
    out.push_str("<g clip-path=\"url(#scene)\">\n");

    let centre = |p: &SnapshotPolygon| -> [f64; 2] {
        let n = p.vertices.len() as f64;
        let s = p
            .vertices
            .iter()
            .fold([0.0, 0.0], |a, v| [a[0] + v[0], a[1] + v[1]]);
        [s[0] / n, s[1] / n]
    };

    let mut moving = 0usize;
    for p in &polygons {
        let (fill, stroke) = if p.fixed {
            ("#b0b0b0".to_string(), "#606060".to_string())
        } else {
            moving += 1;
            colour(moving - 1)
        };
        let mut points = String::with_capacity(p.vertices.len() * 16);
        for v in &p.vertices {
            let _ = write!(points, "{:.2},{:.2} ", sx(v[0]), sy(v[1]));
        }
        let _ = writeln!(
            out,
            r#"<polygon points="{}" fill="{fill}" fill-opacity="0.75" stroke="{stroke}" stroke-width="1.2" stroke-linejoin="round"><title>{}</title></polygon>"#,
            points.trim_end(),
            escape_xml(&p.id)
        );
    }
    if let Some(o) = structure {
        overlay::draw(&mut out, o, &sx, &sy);
    }
    if options.show_velocities {
        for p in polygons.iter().filter(|p| !p.fixed) {
            let v = p.velocity;
            if !(v[0].is_finite() && v[1].is_finite()) || (v[0] == 0.0 && v[1] == 0.0) {
                continue;
            }
            let c = centre(p);
            let k = options.velocity_scale;
            let (x1, y1) = (sx(c[0]), sy(c[1]));
            let (x2, y2) = (sx(c[0] + k * v[0]), sy(c[1] + k * v[1]));
            if !(x2.is_finite() && y2.is_finite()) || (x2 - x1).hypot(y2 - y1) < 2.0 {
                continue;
            }
            let _ = writeln!(
                out,
                r##"<line x1="{x1:.2}" y1="{y1:.2}" x2="{x2:.2}" y2="{y2:.2}" stroke="#222" stroke-width="1.5" marker-end="url(#arrow)"/>"##
            );
        }
    }
    if options.show_ids {
        for p in &polygons {
            let c = centre(p);
            let _ = writeln!(
                out,
                r##"<text x="{:.2}" y="{:.2}" font-size="12" text-anchor="middle" dominant-baseline="middle" fill="#111">{}</text>"##,
                sx(c[0]),
                sy(c[1]),
                escape_xml(&p.id)
            );
        }
    }
    out.push_str("</g>\n");
    if let Some(o) = legend {
        overlay::legend(&mut out, o, width, margin);
    }
    let note = match structure.and_then(|o| o.note.as_ref()) {
        Some(n) => format!(" · {}", escape_xml(n)),
        None => String::new(),
    };
    let _ = writeln!(
        out,
        r##"<text x="{:.2}" y="{:.2}" font-size="14" fill="#111">t = {} · {} polygon{}{note}</text>"##,
        margin.max(4.0),
        height - 7.0,
        snapshot.time,
        polygons.len(),
        if polygons.len() == 1 { "" } else { "s" }
    );
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn snap() -> Snapshot {
        Snapshot {
            time: 2.25,
            polygons: vec![
                SnapshotPolygon {
                    id: "wall".into(),
                    vertices: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 1.0], [0.0, 1.0]],
                    fixed: true,
                    velocity: [0.0, 0.0],
                },
                SnapshotPolygon {
                    id: "a&\"b'<>".into(),
                    vertices: vec![[2.0, 3.0], [4.0, 3.0], [3.0, 5.0]],
                    fixed: false,
                    velocity: [1.0, -1.0],
                },
                SnapshotPolygon {
                    id: "c".into(),
                    vertices: vec![[6.0, 3.0], [8.0, 3.0], [7.0, 5.0]],
                    fixed: false,
                    velocity: [0.0, 0.0],
                },
            ],
            structure: None,
        }
    }

    #[test]
    fn draws_every_polygon_escaped() {
        let s = svg(&snap(), &RenderOptions::default());
        assert!(s.starts_with("<svg") && s.trim_end().ends_with("</svg>"));
        assert_eq!(s.matches("<polygon").count(), 3);
        assert!(s.contains("a&amp;&quot;b&apos;&lt;&gt;"));
        assert!(!s.contains("a&\"b"));
        assert!(s.contains("#b0b0b0"));
        assert_eq!(s.matches("marker-end").count(), 1);
        assert!(s.contains("t = 2.25"));
    }

    #[test]
    fn y_axis_points_up() {
        let s = svg(&snap(), &RenderOptions::default());
        // The wall (y in [0, 1]) is drawn below the triangles (larger screen y).
        let first_y = |k: usize| -> f64 {
            s.split("<polygon points=\"")
                .nth(k)
                .unwrap()
                .split([',', ' '])
                .nth(1)
                .unwrap()
                .parse()
                .unwrap()
        };
        assert!(first_y(1) > first_y(2) + 100.0);
    }

    #[test]
    fn options_and_degenerate_input() {
        let o = RenderOptions {
            show_ids: false,
            show_velocities: false,
            view: Some([0.0, 0.0, 4.0, 4.0]),
            ..Default::default()
        };
        let s = svg(&snap(), &o);
        assert!(!s.contains("<text x=\"") || s.matches("<text").count() == 1);
        assert!(!s.contains("marker-end"));
        let empty = svg(&Snapshot::default(), &RenderOptions::default());
        assert!(empty.contains("0 polygons") && !empty.contains("NaN"));
        let point = Snapshot {
            time: 0.0,
            polygons: vec![SnapshotPolygon {
                id: "p".into(),
                vertices: vec![[1.0, 1.0]],
                fixed: false,
                velocity: [f64::NAN, 0.0],
            }],
            structure: None,
        };
        let s = svg(&point, &RenderOptions::default());
        assert!(!s.contains("NaN") && !s.contains("inf"));
    }

    #[test]
    fn draws_the_structure_overlay() {
        let mut snap = snap();
        snap.structure = Some(StructureOverlay {
            triangles: vec![[[4.0, 3.0], [6.0, 3.0], [5.0, 4.0]]],
            infinite_triangles: 3,
            corridors: vec![
                crate::structure::view::CorridorOverlay {
                    omega: false,
                    faces: vec![
                        vec![[4.0, 3.0], [3.0, 5.0], [7.0, 5.0], [6.0, 3.0]],
                        vec![[0.0, 1.0], [1.0, 1.0]],
                    ],
                },
                crate::structure::view::CorridorOverlay {
                    omega: true,
                    faces: vec![],
                },
            ],
            end_edges: vec![[[4.0, 3.0], [6.0, 3.0]]],
            middle_bridges: vec![[[3.0, 5.0], [7.0, 5.0]]],
            omega_rays: vec![([3.0, 5.0], [0.0, 1.0])],
            certificates: vec![crate::structure::view::CertificateOverlay {
                points: [[4.0, 3.0], [6.0, 3.0], [5.0, 4.0]],
                kind: "triangle",
                time: 2.75,
            }],
            approximations: vec![vec![
                ([3.0, 5.0], true),
                ([5.0, 2.0], false),
                ([7.0, 5.0], true),
            ]],
            note: None,
        });
        let s = svg(&snap, &RenderOptions::default());
        assert_eq!(s.matches("<g id=\"structure\">").count(), 1);
        assert_eq!(s.matches("class=\"partition-triangle\"").count(), 1);
        assert_eq!(s.matches("class=\"corridor-face\"").count(), 1);
        assert_eq!(s.matches("class=\"middle-bridge\"").count(), 1);
        assert_eq!(s.matches("class=\"end-edge\"").count(), 1);
        assert_eq!(s.matches("class=\"omega-ray\"").count(), 1);
        assert_eq!(s.matches("class=\"certificate\"").count(), 1);
        assert_eq!(s.matches("class=\"approximation\"").count(), 1);
        assert_eq!(s.matches("class=\"approximation-vertex\"").count(), 1);
        assert!(s.contains("approximation (1 vertices not real)"));
        assert!(s.contains("1: t = 2.75") && s.contains("id=\"legend\""));
        assert_eq!(s.matches("<g").count(), s.matches("</g>").count());
        let off = svg(
            &snap,
            &RenderOptions {
                show_structure: false,
                ..Default::default()
            },
        );
        assert!(!off.contains("structure") && !off.contains("legend"));
        snap.structure.as_mut().unwrap().note = Some("not drawn".into());
        let noted = svg(&snap, &RenderOptions::default());
        assert!(noted.contains("· not drawn") && !noted.contains("partition-triangle"));
    }
}
