//! SVG output of 2D shapes.

use std::fmt::Write as _;

use crate::geometry::Shape;

/// The shape as an SVG document `size` pixels wide: polylines as paths,
/// other vertices as dots, quads as outlined polygons. y points up.
pub fn svg(shape: &Shape, size: u32) -> String {
    let Some((lo, hi)) = shape.bounds() else {
        return format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{size}\" height=\"{size}\"/>\n");
    };
    let (w, h) = ((hi[0] - lo[0]).max(1e-12), (hi[1] - lo[1]).max(1e-12));
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
