//! Contours as Bézier fractals (the Bézier-fractal contours paper): segments files of quadratic
//! Bézier arcs and line segments, their IFS in the paper's convention, and
//! the automaton of a whole contour.

mod automaton;
mod fit;
mod segments;

pub use automaton::{ContourError, chain, contour_design};
pub use fit::{Fit, FitError, FitSettings, Ipan, fit_contour, otsu};
pub use segments::{
    CASTELJAU_LEFT, CASTELJAU_RIGHT, Segment, arc_ifs, chaos_points, iterate_polygon, parse_segments, read_segments,
    write_segments,
};
