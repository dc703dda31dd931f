//! Bodies of different sources that cover the same space (issue 17).
//!
//! Regions, point files and meshes each bring their own points; where two of
//! them cover the same space the material is counted twice (a mesh of a square
//! and a region of the same square give 200 points and twice the stiffness).
//! Overlapping regions are refused by their boxes when the scene is validated;
//! here every point is tested against the bodies of the other sources:
//!
//! - **inside a region's box**: a point of another source lying strictly inside
//!   `regions[k].box` (by more than `10⁻⁶ h_k`) lies in one of its cells, since
//!   the cells tile the box exactly;
//! - **inside an unstructured point's cell**: the cell of a mesh or point-file
//!   point `q` of spacing `s_q` (`(V_q / thickness)^{1/d}`) contains the ball of
//!   radius `r_q = 0.3 s_q` about `q` for cells of reasonable shape: the centroid
//!   of a right isosceles triangle lies `0.333 s` from its nearest edge, that of
//!   an equilateral triangle `0.439 s`, that of a regular tetrahedron `0.417 s`, a
//!   square's or cube's centre `0.5 s`. A mesh or point-file point of another
//!   body within `r_q` of `q` therefore lies in `q`'s cell. Bodies that only touch
//!   are not refused: a point of the other side is at least its own and `q`'s
//!   distance to the common boundary away. Region points are not tested against
//!   these balls: a point file's rows have a volume but no cell shape (a heavy
//!   point beside a plate is legitimate input), and a mesh that covers a region
//!   has its centroids inside the region's box.
//!
//! A full overlap of unstructured bodies puts a fraction of about `π 0.3² ≈ 0.28`
//! (2D) of the foreign points within `r_q` of a centroid, so any overlap of more
//! than a few cells is found; the region test finds every point inside a box.

use crate::error::InputError;
use crate::geometry::grid::{RawPoint, Source};
use crate::scene::Region;
use crate::vector::{norm, sub};
use std::collections::HashMap;

/// Fraction of its equivalent spacing within which an unstructured point's cell
/// surely contains a foreign point (see the module docs).
const CELL_BALL: f64 = 0.3;

/// The body a source belongs to: kind (0 region, 1 point file, 2 mesh) and index.
fn body(source: Source) -> (u8, u32) {
    match source {
        Source::Region(k) => (0, k),
        Source::File { file, .. } => (1, file),
        Source::Mesh { mesh, .. } => (2, mesh),
    }
}

/// The body's field name (`regions[0].box`, `point_files[1]`, `meshes[0]`).
fn body_field(source: Source) -> String {
    match source {
        Source::Region(k) => format!("regions[{k}].box"),
        Source::File { file, .. } => format!("point_files[{file}]"),
        Source::Mesh { mesh, .. } => format!("meshes[{mesh}]"),
    }
}

fn refuse(p: &RawPoint, what: &str) -> InputError {
    InputError::new(
        body_field(p.source),
        format!(
            "{} at {:?} lies {what}: the two bodies cover the same space and would count its \
             material twice; bodies of regions, point files and meshes must not overlap (they \
             may touch)",
            p.source, p.x
        ),
    )
}

/// Refuses a point of one source that lies inside the body of another.
pub fn reject_overlaps(raw: &[RawPoint], regions: &[Region], d: usize) -> Result<(), InputError> {
    for (k, region) in regions.iter().enumerate() {
        let margin = 1e-6 * region.spacing;
        let inside = |x: &[f64; 3]| {
            (0..d).all(|a| {
                x[a] > region.bounds.min[a] + margin && x[a] < region.bounds.max[a] - margin
            })
        };
        if let Some(p) = raw
            .iter()
            .find(|p| body(p.source) != (0, k as u32) && inside(&p.x))
        {
            return Err(refuse(p, &format!("inside regions[{k}].box")));
        }
    }
    let loose: Vec<(&RawPoint, f64)> = raw
        .iter()
        .filter(|p| !matches!(p.source, Source::Region(_)))
        .map(|p| (p, CELL_BALL * p.spacing))
        .collect();
    let Some(cell) = loose
        .iter()
        .map(|&(_, r)| r)
        .filter(|r| r.is_finite() && *r > 0.0)
        .reduce(f64::max)
    else {
        return Ok(());
    };
    let key = |x: &[f64; 3]| x.map(|v| (v / cell).floor() as i64);
    let mut buckets: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (n, (p, _)) in loose.iter().enumerate() {
        buckets.entry(key(&p.x)).or_default().push(n);
    }
    for &(p, _) in &loose {
        let c = key(&p.x);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let Some(list) = buckets.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                        continue;
                    };
                    for &n in list {
                        let (q, r) = loose[n];
                        if body(q.source) != body(p.source) && norm(&sub(&p.x, &q.x)) < r {
                            return Err(refuse(
                                p,
                                &format!("in the cell of {} (x = {:?})", q.source, q.x),
                            ));
                        }
                    }
                }
            }
        }
    }
    Ok(())
}
