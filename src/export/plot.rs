//! Line plots of parameter maps (PNG): series against a parameter, shaded
//! intervals, reference lines, ticks and labels in a small bitmap font.

use image::{Rgb, RgbImage};

use super::png::wu_line;

/// A curve of the plot.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points `(x, y)`, in order of x.
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: [u8; 3],
}

/// A plot: series over `x_range × y_range`, shaded x intervals, reference lines.
#[derive(Clone, Debug, Default)]
pub struct Plot {
    /// Title above the frame.
    pub title: String,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
    /// Shaded x intervals with their colour and legend label.
    pub bands: Vec<(f64, f64, [u8; 3], String)>,
    /// Horizontal reference lines (y, colour).
    pub hlines: Vec<(f64, [u8; 3])>,
    /// Vertical reference lines (x, colour).
    pub vlines: Vec<(f64, [u8; 3])>,
    /// y range (`None`: from the data).
    pub y_range: Option<(f64, f64)>,
}

/// 5×7 glyphs, one byte per row (bit 4 is the leftmost pixel).
fn glyph(c: char) -> [u8; 7] {
    match c.to_ascii_uppercase() {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        '.' => [0, 0, 0, 0, 0, 0x0C, 0x0C],
        ',' => [0, 0, 0, 0, 0x0C, 0x04, 0x08],
        '-' => [0, 0, 0, 0x1F, 0, 0, 0],
        '+' => [0, 0x04, 0x04, 0x1F, 0x04, 0x04, 0],
        '=' => [0, 0, 0x1F, 0, 0x1F, 0, 0],
        '/' => [0x01, 0x01, 0x02, 0x04, 0x08, 0x10, 0x10],
        '(' => [0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02],
        ')' => [0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08],
        '<' => [0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02],
        '>' => [0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08],
        ':' => [0, 0x0C, 0x0C, 0, 0x0C, 0x0C, 0],
        'A' => [0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11],
        'B' => [0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E],
        'C' => [0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E],
        'D' => [0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C],
        'E' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F],
        'F' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10],
        'G' => [0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F],
        'H' => [0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11],
        'I' => [0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E],
        'J' => [0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C],
        'K' => [0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11],
        'L' => [0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F],
        'M' => [0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11],
        'N' => [0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11],
        'O' => [0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E],
        'P' => [0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10],
        'Q' => [0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D],
        'R' => [0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11],
        'S' => [0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E],
        'T' => [0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04],
        'U' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E],
        'V' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04],
        'W' => [0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A],
        'X' => [0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11],
        'Y' => [0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04],
        'Z' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F],
        _ => [0; 7],
    }
}

/// Draws `text` with its top-left corner at `(x, y)`, `scale` pixels per font pixel.
fn text(img: &mut RgbImage, x: i64, y: i64, s: &str, color: [u8; 3], scale: i64) {
    for (k, c) in s.chars().enumerate() {
        let g = glyph(c);
        for (row, bits) in g.iter().enumerate() {
            for col in 0..5 {
                if bits & (0x10 >> col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let (px, py) = (x + (k as i64 * 6 + col) * scale + dx, y + row as i64 * scale + dy);
                        if px >= 0 && py >= 0 && (px as u32) < img.width() && (py as u32) < img.height() {
                            img.put_pixel(px as u32, py as u32, Rgb(color));
                        }
                    }
                }
            }
        }
    }
}

fn text_width(s: &str, scale: i64) -> i64 {
    s.chars().count() as i64 * 6 * scale
}

/// A short label for a tick value.
fn tick_label(v: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.starts_with("-0") && s.trim_start_matches(['-', '0', '.']).is_empty() { s[1..].to_string() } else { s }
}

/// A "nice" tick step for a range.
fn tick_step(span: f64, ticks: f64) -> f64 {
    let raw = span / ticks;
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| *s >= raw).unwrap_or(10.0 * mag)
}

impl Plot {
    /// Renders the plot.
    pub fn render(&self, width: u32, height: u32) -> RgbImage {
        let mut img = RgbImage::from_pixel(width, height, Rgb([255, 255, 255]));
        let (w, h) = (width as f64, height as f64);
        let (left, right, top, bottom) = (80.0, 20.0, 40.0, 110.0);
        let pts = self.series.iter().flat_map(|s| s.points.iter());
        let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY);
        for &(x, y) in pts {
            if x.is_finite() && y.is_finite() {
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
        if let Some((a, b)) = self.y_range {
            (y0, y1) = (a, b);
        }
        if x0.partial_cmp(&x1) != Some(std::cmp::Ordering::Less) {
            (x0, x1) = (x0.min(0.0) - 1.0, x1.max(0.0) + 1.0);
        }
        if y0.partial_cmp(&y1) != Some(std::cmp::Ordering::Less) {
            (y0, y1) = (y0.min(0.0) - 1.0, y1.max(0.0) + 1.0);
        }
        let sx = |x: f64| left + (x - x0) / (x1 - x0) * (w - left - right);
        let sy = |y: f64| h - bottom - (y - y0) / (y1 - y0) * (h - top - bottom);
        // Bands, then the frame, grid, lines and curves.
        for (a, b, color, _) in &self.bands {
            let (pa, pb) = (sx(a.max(x0)).round() as u32, sx(b.min(x1)).round() as u32);
            for x in pa..=pb.min(width - 1) {
                for y in top as u32..(h - bottom) as u32 {
                    img.put_pixel(x, y, Rgb(*color));
                }
            }
        }
        let mut cov = vec![0f32; (width * height) as usize];
        let stroke = |img: &mut RgbImage, cov: &mut Vec<f32>, a: (f64, f64), b: (f64, f64), color: [u8; 3]| {
            cov.iter_mut().for_each(|c| *c = 0.0);
            wu_line(cov, width as usize, height as usize, a, b);
            wu_line(cov, width as usize, height as usize, (a.0, a.1 + 1.0), (b.0, b.1 + 1.0));
            for (i, c) in cov.iter().enumerate() {
                if *c > 0.0 {
                    let (x, y) = (i as u32 % width, i as u32 / width);
                    let old = img.get_pixel(x, y).0;
                    let t = f64::from(*c);
                    img.put_pixel(
                        x,
                        y,
                        Rgb([0, 1, 2].map(|k| (f64::from(old[k]) * (1.0 - t) + f64::from(color[k]) * t) as u8)),
                    );
                }
            }
        };
        let grey = [200, 200, 200];
        let (xs, ys) = (tick_step(x1 - x0, 6.0), tick_step(y1 - y0, 6.0));
        let mut t = (x0 / xs).ceil() * xs;
        while t <= x1 + 1e-12 {
            let x = sx(t);
            stroke(&mut img, &mut cov, (x, top), (x, h - bottom), grey);
            let label = tick_label(t, xs);
            text(&mut img, x as i64 - text_width(&label, 1) / 2, (h - bottom + 8.0) as i64, &label, [0, 0, 0], 1);
            t += xs;
        }
        let mut t = (y0 / ys).ceil() * ys;
        while t <= y1 + 1e-12 {
            let y = sy(t);
            stroke(&mut img, &mut cov, (left, y), (w - right, y), grey);
            let label = tick_label(t, ys);
            text(&mut img, left as i64 - 8 - text_width(&label, 1), y as i64 - 3, &label, [0, 0, 0], 1);
            t += ys;
        }
        for &(y, color) in &self.hlines {
            if (y0..=y1).contains(&y) {
                stroke(&mut img, &mut cov, (left, sy(y)), (w - right, sy(y)), color);
            }
        }
        for &(x, color) in &self.vlines {
            if (x0..=x1).contains(&x) {
                stroke(&mut img, &mut cov, (sx(x), top), (sx(x), h - bottom), color);
            }
        }
        for s in &self.series {
            for pair in s.points.windows(2) {
                let clip = |y: f64| y.clamp(y0 - 0.05 * (y1 - y0), y1 + 0.05 * (y1 - y0));
                let (a, b) = (pair[0], pair[1]);
                if a.1.is_finite() && b.1.is_finite() {
                    stroke(&mut img, &mut cov, (sx(a.0), sy(clip(a.1))), (sx(b.0), sy(clip(b.1))), s.color);
                }
            }
        }
        // Repaint the margins over curves that left the frame.
        for y in 0..height {
            for x in 0..width {
                let (xf, yf) = (f64::from(x), f64::from(y));
                if xf < left || xf > w - right || yf < top || yf > h - bottom {
                    img.put_pixel(x, y, Rgb([255, 255, 255]));
                }
            }
        }
        let black = [0, 0, 0];
        for (a, b) in [((left, top), (w - right, top)), ((left, h - bottom), (w - right, h - bottom))] {
            stroke(&mut img, &mut cov, a, b, black);
        }
        for (a, b) in [((left, top), (left, h - bottom)), ((w - right, top), (w - right, h - bottom))] {
            stroke(&mut img, &mut cov, a, b, black);
        }
        // Tick labels again (the margin repaint erased them), title, axis labels, legend.
        let mut t = (x0 / xs).ceil() * xs;
        while t <= x1 + 1e-12 {
            let label = tick_label(t, xs);
            text(&mut img, sx(t) as i64 - text_width(&label, 1) / 2, (h - bottom + 8.0) as i64, &label, black, 1);
            t += xs;
        }
        let mut t = (y0 / ys).ceil() * ys;
        while t <= y1 + 1e-12 {
            let label = tick_label(t, ys);
            text(&mut img, left as i64 - 8 - text_width(&label, 1), sy(t) as i64 - 3, &label, black, 1);
            t += ys;
        }
        text(&mut img, (w / 2.0) as i64 - text_width(&self.title, 2) / 2, 12, &self.title, black, 2);
        let xl = (w / 2.0) as i64 - text_width(&self.x_label, 1) / 2;
        text(&mut img, xl, (h - bottom + 24.0) as i64, &self.x_label, black, 1);
        text(&mut img, 8, top as i64 - 14, &self.y_label, black, 1);
        let mut lx = left as i64;
        let ly = (h - bottom + 48.0) as i64;
        let mut row = 0;
        for (label, color, band) in self
            .series
            .iter()
            .map(|s| (&s.label, s.color, false))
            .chain(self.bands.iter().map(|b| (&b.3, b.2, true)))
            .filter(|(label, _, _)| !label.is_empty())
        {
            let width_needed = 30 + text_width(label, 1);
            if lx + width_needed > width as i64 - 10 {
                lx = left as i64;
                row += 1;
            }
            let y = ly + row * 16;
            for dx in 0..20 {
                for dy in if band { -4..5 } else { 0..2 } {
                    let (px, py) = ((lx + dx) as u32, (y + 3 + dy) as u32);
                    if px < width && py < height {
                        img.put_pixel(px, py, Rgb(color));
                    }
                }
            }
            text(&mut img, lx + 26, y, label, black, 1);
            lx += width_needed + 16;
        }
        img
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round() {
        assert_eq!(tick_step(0.2, 6.0), 0.05);
        assert_eq!(tick_label(-0.0, 0.05), "0.00");
        assert_eq!(tick_label(0.1, 0.05), "0.10");
    }

    #[test]
    fn a_plot_draws_its_curve() {
        let plot = Plot {
            title: "T".into(),
            series: vec![Series { label: "Y".into(), points: vec![(0.0, 0.0), (1.0, 1.0)], color: [255, 0, 0] }],
            ..Plot::default()
        };
        let img = plot.render(300, 300);
        let red = img.pixels().filter(|p| p.0[0] > 200 && p.0[1] < 80).count();
        assert!(red > 100, "{red}");
    }
}
