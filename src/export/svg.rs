//! SVG output: 2D shapes as paths, dots and outlined quads; surfaces as
//! their faces seen from a view, flatly shaded like the PNG and painted far
//! to near.

use std::fmt::Write as _;

use super::png::face_colour;
use super::view::{Canvas, RasterSettings, project};
use crate::algebra::tolerance::DEGENERATE;
use crate::geometry::Shape;

/// The faces of a surface (2D or 3D) as an SVG picture of the settings'
/// size and view: each face a polygon in its flat shade (the PNG's light),
/// painted from the farthest to the nearest (painter's order by mean depth),
/// outlined in its own colour so that neighbours leave no hairline gap.
///
/// ```
/// use bcifs::export::{RasterSettings, svg_surface};
/// use bcifs::mesh::{PolyMesh, Scheme};
/// let cube = PolyMesh::cube().limit(Scheme::CatmullClark, 2).unwrap();
/// let text = svg_surface(&cube, &RasterSettings::default().with_size(300, 300));
/// assert_eq!(text.matches("<polygon").count(), cube.quads.len());
/// ```
pub fn svg_surface(shape: &Shape, settings: &RasterSettings) -> String {
    let (w, h) = (settings.width.max(1), settings.height.max(1));
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    let pts = project(shape, settings.view);
    if !pts.is_empty() {
        let canvas = Canvas::fit(&pts, w, h);
        let faces = shape
            .quads
            .iter()
            .map(|q| q.map(|i| i as usize).to_vec())
            .chain(shape.triangles.iter().map(|t| t.to_vec()));
        let mut painted: Vec<(f64, Vec<usize>, image::Rgb<u8>)> = faces
            .filter_map(|f| {
                let colour = face_colour(pts[f[0]], pts[f[1]], pts[f[2]])
                    .or_else(|| (f.len() == 4).then(|| face_colour(pts[f[0]], pts[f[2]], pts[f[3]])).flatten())?;
                let depth = f.iter().map(|&i| pts[i][2]).sum::<f64>() / f.len() as f64;
                Some((depth, f, colour))
            })
            .collect();
        painted.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, f, c) in painted {
            let hex = format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]);
            let _ = write!(
                out,
                "<polygon fill=\"{hex}\" stroke=\"{hex}\" stroke-width=\"0.6\" stroke-linejoin=\"round\" points=\""
            );
            for (k, &i) in f.iter().enumerate() {
                let (x, y) = canvas.px(pts[i]);
                let _ = write!(out, "{}{x:.2},{y:.2}", if k == 0 { "" } else { " " });
            }
            out.push_str("\"/>\n");
        }
    }
    out.push_str("</svg>\n");
    out
}

/// The shape as an SVG document `size` pixels wide: polylines as paths,
/// other vertices as dots, quads as outlined polygons. y points up.
pub fn svg(shape: &Shape, size: u32) -> String {
    let Some((lo, hi)) = shape.bounds() else {
        return format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{size}\" height=\"{size}\"/>\n");
    };
    let (w, h) = ((hi[0] - lo[0]).max(DEGENERATE), (hi[1] - lo[1]).max(DEGENERATE));
    let scale = f64::from(size) * 0.95 / w.max(h);
    let (width, height) = (w * scale / 0.95, h * scale / 0.95);
    let margin = f64::from(size) * 0.025;
    let px = |p: [f64; 3]| ((p[0] - lo[0]) * scale + margin, height - ((p[1] - lo[1]) * scale + margin));
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.2} {height:.2}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>"
    );
    let mut on_line = vec![false; shape.vertex_count()];
    for (first, count, closed) in shape.polylines() {
        let _ = write!(out, "<path fill=\"none\" stroke=\"#1b3a6b\" stroke-width=\"1\" stroke-linejoin=\"round\" d=\"");
        on_line[first..first + count].iter_mut().for_each(|x| *x = true);
        for i in first..first + count {
            let (x, y) = px(shape.point(i));
            let _ = write!(out, "{}{x:.3},{y:.3}", if i == first { "M" } else { " L" });
        }
        let _ = writeln!(out, "{}\"/>", if closed { " Z" } else { "" });
    }
    for q in &shape.quads {
        let pts: Vec<String> = q
            .iter()
            .map(|&i| {
                let (x, y) = px(shape.point(i as usize));
                format!("{x:.3},{y:.3}")
            })
            .collect();
        let _ = writeln!(
            out,
            "<polygon fill=\"#dfe7f2\" stroke=\"#1b3a6b\" stroke-width=\"0.3\" points=\"{}\"/>",
            pts.join(" ")
        );
        for &i in q {
            on_line[i as usize] = true;
        }
    }
    for (i, used) in on_line.iter().enumerate() {
        if !used {
            let (x, y) = px(shape.point(i));
            let _ = writeln!(out, "<circle cx=\"{x:.3}\" cy=\"{y:.3}\" r=\"0.6\" fill=\"#1b3a6b\"/>");
        }
    }
    out.push_str("</svg>\n");
    out
}
