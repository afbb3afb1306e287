//! Plots of parameter maps (PNG), drawn with plotters in DejaVu Sans: series
//! against a parameter, shaded intervals, reference lines, a legend.

use std::sync::Once;

use anyhow::{Result, anyhow};
use image::RgbImage;
use plotters::prelude::*;

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

/// A plot: series over an x range, shaded x intervals, reference lines.
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
    /// Shaded x intervals with their colour and legend label (empty: no legend entry).
    pub bands: Vec<(f64, f64, [u8; 3], String)>,
    /// Horizontal reference lines (y, colour).
    pub hlines: Vec<(f64, [u8; 3])>,
    /// Vertical reference lines (x, colour).
    pub vlines: Vec<(f64, [u8; 3])>,
    /// y range (`None`: from the data).
    pub y_range: Option<(f64, f64)>,
}

/// The font every plot is written in, registered once.
fn register_font() -> Result<()> {
    static ONCE: Once = Once::new();
    let mut result = Ok(());
    ONCE.call_once(|| {
        result = plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| anyhow!("the embedded DejaVu Sans font does not load"));
    });
    result
}

fn rgb(c: [u8; 3]) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

impl Plot {
    /// The x and y ranges: the series' x extent, and `y_range` or the data's.
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let points = || self.series.iter().flat_map(|s| s.points.iter().copied());
        let (mut x0, mut x1) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
        if !(x0.is_finite() && x1.is_finite() && x0 < x1) {
            (x0, x1) = (0.0, 1.0);
        }
        let y = self.y_range.unwrap_or_else(|| {
            let (a, b) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
            if a < b { (a, b) } else { (a - 1.0, a + 1.0) }
        });
        ((x0, x1), y)
    }

    /// The plot as a `width × height` picture.
    ///
    /// # Errors
    /// The font does not load, or plotters fails to draw.
    pub fn render(&self, width: u32, height: u32) -> Result<RgbImage> {
        register_font()?;
        let mut buf = vec![255u8; width as usize * height as usize * 3];
        let draw = |e| anyhow!("cannot draw the plot: {e}");
        {
            let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
            root.fill(&WHITE).map_err(draw)?;
            let ((x0, x1), (y0, y1)) = self.ranges();
            let mut chart = ChartBuilder::on(&root)
                .caption(&self.title, ("sans-serif", 24))
                .margin(16)
                .x_label_area_size(48)
                .y_label_area_size(64)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(draw)?;
            chart
                .configure_mesh()
                .x_desc(&self.x_label)
                .y_desc(&self.y_label)
                .label_style(("sans-serif", 15))
                .axis_desc_style(("sans-serif", 18))
                .light_line_style(RGBColor(236, 236, 236))
                .draw()
                .map_err(draw)?;
            for (a, b, c, label) in &self.bands {
                let colour = rgb(*c);
                let drawn = chart
                    .draw_series(std::iter::once(Rectangle::new([(*a, y0), (*b, y1)], colour.mix(0.75).filled())))
                    .map_err(draw)?;
                if !label.is_empty() {
                    drawn
                        .label(label)
                        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 18, y + 6)], colour.filled()));
                }
            }
            for (y, c) in &self.hlines {
                chart.draw_series(LineSeries::new([(x0, *y), (x1, *y)], rgb(*c).stroke_width(1))).map_err(draw)?;
            }
            for (x, c) in &self.vlines {
                chart.draw_series(LineSeries::new([(*x, y0), (*x, y1)], rgb(*c).stroke_width(1))).map_err(draw)?;
            }
            for s in &self.series {
                let colour = rgb(s.color);
                let inside = s.points.iter().copied().filter(|p| p.1.is_finite()).map(|(x, y)| (x, y.clamp(y0, y1)));
                chart
                    .draw_series(LineSeries::new(inside, colour.stroke_width(2)))
                    .map_err(draw)?
                    .label(&s.label)
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], colour.stroke_width(2)));
            }
            chart
                .configure_series_labels()
                .label_font(("sans-serif", 15))
                .background_style(WHITE.mix(0.9))
                .border_style(RGBColor(120, 120, 120))
                .position(SeriesLabelPosition::UpperLeft)
                .draw()
                .map_err(draw)?;
            root.present().map_err(draw)?;
        }
        RgbImage::from_raw(width, height, buf)
            .ok_or_else(|| anyhow!("internal error: plot buffer size (please report)"))
    }
}

/// A map of a parameter plane with labelled axes and a legend: `pixels`
/// (row 0 at the top, the largest y) drawn over `x` and `y` (label, from,
/// to), and one legend entry per colour, to the right.
///
/// # Errors
/// The font does not load, or plotters fails to draw.
pub fn framed_map(
    title: &str,
    x: (&str, f64, f64),
    y: (&str, f64, f64),
    pixels: &RgbImage,
    legend: &[([u8; 3], String)],
) -> Result<RgbImage> {
    register_font()?;
    let (map_side, legend_width) = (720u32, 260u32);
    let (width, height) = (map_side + legend_width, map_side);
    let mut buf = vec![255u8; width as usize * height as usize * 3];
    let draw = |e| anyhow!("cannot draw the map: {e}");
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(draw)?;
        let (left, right) = root.split_horizontally(map_side);
        let mut chart = ChartBuilder::on(&left)
            .caption(title, ("sans-serif", 22))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(56)
            .build_cartesian_2d(x.1..x.2, y.1..y.2)
            .map_err(draw)?;
        chart
            .configure_mesh()
            .x_desc(x.0)
            .y_desc(y.0)
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 18))
            .disable_mesh()
            .draw()
            .map_err(draw)?;
        let (w, h) = (pixels.width() as usize, pixels.height() as usize);
        let (dx, dy) = ((x.2 - x.1) / w as f64, (y.2 - y.1) / h as f64);
        chart
            .draw_series((0..h).flat_map(|row| (0..w).map(move |col| (row, col))).map(|(row, col)| {
                let p = pixels.get_pixel(col as u32, row as u32).0;
                let (px, py) = (x.1 + col as f64 * dx, y.2 - (row + 1) as f64 * dy);
                Rectangle::new([(px, py), (px + dx, py + dy)], RGBColor(p[0], p[1], p[2]).filled())
            }))
            .map_err(draw)?;
        for (i, (c, label)) in legend.iter().enumerate() {
            let top = 60 + 28 * i as i32;
            right.draw(&Rectangle::new([(10, top), (34, top + 18)], rgb(*c).filled())).map_err(draw)?;
            right.draw(&Rectangle::new([(10, top), (34, top + 18)], RGBColor(90, 90, 90))).map_err(draw)?;
            right.draw(&Text::new(label.clone(), (42, top + 1), ("sans-serif", 16))).map_err(draw)?;
        }
        root.present().map_err(draw)?;
    }
    RgbImage::from_raw(width, height, buf).ok_or_else(|| anyhow!("internal error: map buffer size (please report)"))
}

/// A sheet of equal tiles (`tiles`: rows of columns, `tile` pixels a side)
/// with a header above each column and a name left of each row.
///
/// # Errors
/// The font does not load, or plotters fails to draw.
pub fn labelled_sheet(tiles: &RgbImage, tile: u32, columns: &[String], rows: &[String]) -> Result<RgbImage> {
    register_font()?;
    let (left, top) = (130u32, 44u32);
    let (width, height) = (left + tiles.width(), top + tiles.height());
    let mut buf = vec![255u8; width as usize * height as usize * 3];
    let draw = |e| anyhow!("cannot draw the sheet: {e}");
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(draw)?;
        for (c, text) in columns.iter().enumerate() {
            let x = (left + tile * c as u32 + 6) as i32;
            root.draw(&Text::new(text.clone(), (x, 14), ("sans-serif", 15))).map_err(draw)?;
        }
        for (r, text) in rows.iter().enumerate() {
            let y = (top + tile * r as u32 + tile / 2) as i32;
            root.draw(&Text::new(text.clone(), (8, y), ("sans-serif", 16))).map_err(draw)?;
        }
        root.present().map_err(draw)?;
    }
    let mut sheet = RgbImage::from_raw(width, height, buf)
        .ok_or_else(|| anyhow!("internal error: sheet buffer size (please report)"))?;
    image::imageops::replace(&mut sheet, tiles, i64::from(left), i64::from(top));
    Ok(sheet)
}
