//! Regular grids: points at the cell centres of a box, one cell per spacing.

use crate::scene::{HorizonRule, Region};

/// A generated point before neighbour search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RawPoint {
    /// Position.
    pub x: [f64; 3],
    /// Volume (area × thickness in 2D, length × area in 1D).
    pub volume: f64,
    /// Local spacing (cell size).
    pub spacing: f64,
    /// Horizon radius.
    pub horizon: f64,
    /// Material index.
    pub material: u32,
    /// Where the point comes from, for error messages.
    pub source: Source,
}

/// The scene item that produced a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// `regions[k]`.
    Region(u32),
    /// `point_files[k]`, 1-based line.
    File { file: u32, line: u32 },
    /// `meshes[k]`: cell index (into the mesh's cells) and Gmsh element tag.
    Mesh { mesh: u32, cell: u32, element: u64 },
}

impl std::fmt::Display for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Source::Region(k) => write!(f, "regions[{k}]"),
            Source::File { file, line } => write!(f, "point_files[{file}] (line {line})"),
            Source::Mesh { mesh, element, .. } => write!(f, "meshes[{mesh}] (element {element})"),
        }
    }
}

/// Fills `region` with points at cell centres; `d` is the dimension and
/// `thickness` the 2D thickness or 1D area.
/// `index` is the region's position in the scene.
pub fn fill(region: &Region, index: usize, d: usize, thickness: f64) -> Vec<RawPoint> {
    let h = region.spacing;
    let mut counts = [1usize; 3];
    for (a, count) in counts.iter_mut().enumerate().take(d) {
        *count = ((region.bounds.max[a] - region.bounds.min[a]) / h).round() as usize;
    }
    let volume = h.powi(d as i32) * if d < 3 { thickness } else { 1.0 };
    let horizon = match region.horizon {
        HorizonRule::Factor(m) => m * h,
        HorizonRule::Radius(r) => r,
    };
    let mut points = Vec::with_capacity(counts.iter().product());
    for k in 0..counts[2] {
        for j in 0..counts[1] {
            for i in 0..counts[0] {
                let mut x = [0.0; 3];
                for (a, idx) in [i, j, k].into_iter().enumerate().take(d) {
                    x[a] = region.bounds.min[a] + (idx as f64 + 0.5) * h;
                }
                points.push(RawPoint {
                    x,
                    volume,
                    spacing: h,
                    horizon,
                    material: region.material as u32,
                    source: Source::Region(index as u32),
                });
            }
        }
    }
    points
}
