//! The axes and the digits of written coordinates, shared by every writer:
//! files are Y-up (OBJ's, glTF's and Blender's importer's convention), a
//! model is Z-up unless its coordinates came from a mesh file.

use super::number::push_f64;

/// Which model axis is "up" in the file. OBJ is Y-up by convention (Blender's
/// importer turns file Y into its Z), so a model whose z is up is written
/// with model z as file y (`(x, y, z)` → `(x, z, −y)`, a rotation); 2D
/// curves stay in the xy plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Up {
    /// The format's convention (the default): Y-up in OBJ, OFF and PLY (what
    /// Blender's OBJ importer turns upright, and MeshLab and trimesh show), Z-up
    /// in STL and 3MF (slicers build along z; Blender's STL importer keeps the
    /// file's axes).
    #[default]
    Auto,
    /// Model z becomes the file's y.
    Y,
    /// The model's axes as they are.
    Z,
}

impl Up {
    /// This choice, or `convention` for [`Up::Auto`].
    pub fn or(self, convention: Up) -> Up {
        if self == Up::Auto { convention } else { self }
    }
}

/// How the coordinates a writer is given reach its file: the up axis the
/// file gets, whether the coordinates are already Y-up (a mesh file's
/// axes, [`crate::Model::y_up`]) and their significant digits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Coordinates {
    /// The file's up axis.
    pub up: Up,
    /// The coordinates given are already Y-up: written as they are for
    /// [`Up::Y`], turned back for [`Up::Z`].
    pub y_up_input: bool,
    /// Significant digits, 1 to 15 (`None`: the shortest text that reads
    /// back to the same `f64`).
    pub precision: Option<u32>,
}

/// A rotation about x on the way to the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Turn {
    None,
    /// Model z becomes the file's y: `(x, y, z) ↦ (x, z, −y)`.
    ZToY,
    /// A Y-up shape written Z-up: `(x, y, z) ↦ (x, −z, y)`.
    YToZ,
}

impl Turn {
    #[inline]
    pub(crate) fn apply(self, v: [f64; 3]) -> [f64; 3] {
        match self {
            Turn::None => v,
            Turn::ZToY => [v[0], v[2], -v[1]],
            Turn::YToZ => [v[0], -v[2], v[1]],
        }
    }
}

impl Coordinates {
    /// The same, with `digits` significant digits (1 to 15; `None`, or 16
    /// and more: the shortest round trip).
    pub fn with_precision(mut self, digits: Option<u32>) -> Coordinates {
        self.precision = digits.filter(|&d| d < 16).map(|d| d.max(1));
        self
    }

    /// The turn for vertices of `dim` coordinates (2D curves stay in the xy plane).
    pub(crate) fn turn(&self, dim: usize) -> Turn {
        match (dim == 3, self.y_up_input, self.up.or(Up::Y)) {
            (true, false, Up::Y) => Turn::ZToY,
            (true, true, Up::Z) => Turn::YToZ,
            _ => Turn::None,
        }
    }

    /// Appends the coordinates of `p` (a vertex or a normal) turned by
    /// `turn`, separated by spaces: three numbers, the third 0 for a 2D vertex.
    #[inline]
    pub(crate) fn push(&self, line: &mut Vec<u8>, ryu: &mut ryu::Buffer, turn: Turn, p: &[f64]) {
        let v = [p[0], p.get(1).copied().unwrap_or(0.0), p.get(2).copied().unwrap_or(0.0)];
        for (k, x) in turn.apply(v).into_iter().enumerate() {
            if k > 0 {
                line.push(b' ');
            }
            push_f64(line, ryu, x, self.precision);
        }
    }
}
