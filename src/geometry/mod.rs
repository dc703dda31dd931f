//! Geometry: point generators (regular grids, point files, Gmsh meshes) and
//! pre-crack intersection tests.
//!
//! Coordinates are always `[f64; 3]`; axes beyond the scene's dimension are zero.

pub mod gmsh;
pub mod grid;
pub mod mesh_file;
pub mod point_file;

use crate::scene::Crack;
use crate::vector::{cross, dot, norm, sub};

/// Relative tolerance of the crossing test at the crack's own edges.
const EDGE_TOLERANCE: f64 = 1e-9;

/// Whether the segment `p`-`q` crosses the crack.
///
/// A point on the crack's line (2D) or plane (3D), to within a relative 1e-9 of
/// the bond's length, counts as lying on its positive side: left of the
/// direction `from → to` (2D), along `edge1 × edge2` (3D). A bond that ends on
/// the crack is thus cut exactly as if the crack passed an infinitesimal
/// distance to the other side of its end point, so the bonds (and the answer)
/// do not jump when a crack is drawn through a row of points instead of 1e-8 m
/// beside it; a bond lying in the crack is not cut.
/// The crack itself is closed: a segment through its end point (2D) or across
/// its edge (3D), to within a relative 1e-9, crosses it, so that mirror-image
/// bonds through a crack tip are treated alike whatever the round-off.
pub fn crosses(crack: &Crack, p: &[f64; 3], q: &[f64; 3]) -> bool {
    match crack {
        Crack::Segment { from, to } => {
            let orient = |a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]| {
                (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
            };
            let (o1, o2) = (orient(from, to, p), orient(from, to, q));
            let (o3, o4) = (orient(p, q, from), orient(p, q, to));
            let tol = EDGE_TOLERANCE * norm(&sub(q, p)) * norm(&sub(to, from));
            let on_line = |o: f64| o.abs() <= tol;
            let left = |o: f64| o > -tol;
            left(o1) != left(o2) && (o3 * o4 < 0.0 || on_line(o3) || on_line(o4))
        }
        Crack::Parallelogram {
            origin,
            edge1,
            edge2,
        } => {
            let n = cross(edge1, edge2);
            let (sp, sq) = (dot(&n, &sub(p, origin)), dot(&n, &sub(q, origin)));
            let tol = EDGE_TOLERANCE * norm(&n) * norm(&sub(q, p));
            if (sp > -tol) == (sq > -tol) {
                return false;
            }
            let t = sp / (sp - sq);
            let hit = [
                p[0] + t * (q[0] - p[0]),
                p[1] + t * (q[1] - p[1]),
                p[2] + t * (q[2] - p[2]),
            ];
            let r = sub(&hit, origin);
            let (g11, g12, g22) = (dot(edge1, edge1), dot(edge1, edge2), dot(edge2, edge2));
            let (r1, r2) = (dot(edge1, &r), dot(edge2, &r));
            let det = g11 * g22 - g12 * g12;
            let alpha = (g22 * r1 - g12 * r2) / det;
            let beta = (g11 * r2 - g12 * r1) / det;
            let closed = -EDGE_TOLERANCE..=1.0 + EDGE_TOLERANCE;
            closed.contains(&alpha) && closed.contains(&beta)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_crossing_is_strict() {
        let c = Crack::Segment {
            from: [0.0, 0.0, 0.0],
            to: [1.0, 0.0, 0.0],
        };
        assert!(crosses(&c, &[0.5, -0.1, 0.0], &[0.5, 0.1, 0.0]));
        assert!(!crosses(&c, &[1.5, -0.1, 0.0], &[1.5, 0.1, 0.0]));
        // An end on the crack counts as left of from → to (+y): cut towards -y only,
        // as by the crack 1e-12 m below; a bond along the crack is not cut.
        assert!(!crosses(&c, &[0.5, 0.0, 0.0], &[0.5, 0.1, 0.0]));
        assert!(crosses(&c, &[0.5, 0.0, 0.0], &[0.5, -0.1, 0.0]));
        assert!(!crosses(&c, &[0.2, 0.0, 0.0], &[0.4, 0.0, 0.0]));
        let below = Crack::Segment {
            from: [0.0, -1e-12, 0.0],
            to: [1.0, -1e-12, 0.0],
        };
        for q in [[0.5, 0.1, 0.0], [0.5, -0.1, 0.0], [0.6, -0.05, 0.0]] {
            let p = [0.5, 0.0, 0.0];
            assert_eq!(crosses(&c, &p, &q), crosses(&below, &p, &q), "{q:?}");
        }
        // Through the tip, from either side and with round-off either way: cut.
        for eps in [0.0, 1e-17, -1e-17] {
            assert!(crosses(&c, &[0.9, -0.1 + eps, 0.0], &[1.1, 0.1, 0.0]));
            assert!(crosses(&c, &[0.9, 0.1 + eps, 0.0], &[1.1, -0.1, 0.0]));
        }
    }

    #[test]
    fn parallelogram_crossing() {
        let c = Crack::Parallelogram {
            origin: [0.0; 3],
            edge1: [1.0, 0.0, 0.0],
            edge2: [0.0, 1.0, 0.0],
        };
        assert!(crosses(&c, &[0.5, 0.5, -0.1], &[0.5, 0.5, 0.1]));
        assert!(!crosses(&c, &[1.5, 0.5, -0.1], &[1.5, 0.5, 0.1]));
        assert!(!crosses(&c, &[0.5, 0.5, 0.1], &[0.5, 0.5, 0.2]));
        // An end in the plane counts as on the side of edge1 × edge2 (+z).
        assert!(crosses(&c, &[0.5, 0.5, 0.0], &[0.5, 0.5, -0.1]));
        assert!(!crosses(&c, &[0.5, 0.5, 0.0], &[0.5, 0.5, 0.1]));
    }
}
