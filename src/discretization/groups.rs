//! Point sets: what a boundary condition or a load selects, by box or by a
//! mesh's physical group ([`crate::geometry::mesh_file`]).

use super::Discretization;
use crate::error::InputError;
use crate::geometry::grid::{RawPoint, Source};
use crate::geometry::mesh_file::MeshGroup;
use crate::scene::Selection;
use std::collections::HashMap;

/// A physical group of an imported mesh, by final point index.
#[derive(Debug, Clone, PartialEq)]
pub struct PointGroup {
    /// Group name.
    pub name: String,
    /// Dimension of its elements.
    pub dim: usize,
    /// Selected points, sorted (cells removed by a hole or as isolated are absent).
    pub points: Vec<u32>,
    /// Facets (dimension d − 1): the point of the cell each bounds (`None` when
    /// that cell's point was removed), how many cells share it, and its area.
    pub facets: Vec<(Option<u32>, u8, f64)>,
}

/// Maps the mesh groups' cells to the final points.
pub fn resolve(mesh_groups: &[MeshGroup], raw: &[RawPoint]) -> Vec<PointGroup> {
    if mesh_groups.is_empty() {
        return Vec::new();
    }
    let index: HashMap<(u32, u32), u32> = raw
        .iter()
        .enumerate()
        .filter_map(|(i, p)| match p.source {
            Source::Mesh { mesh, cell, .. } => Some(((mesh, cell), i as u32)),
            _ => None,
        })
        .collect();
    mesh_groups
        .iter()
        .map(|g| PointGroup {
            name: g.name.clone(),
            dim: g.dim,
            points: {
                let mut p: Vec<u32> = g
                    .cells
                    .iter()
                    .filter_map(|&c| index.get(&(g.mesh, c)).copied())
                    .collect();
                p.sort_unstable();
                p
            },
            facets: g
                .facets
                .iter()
                .map(|f| (index.get(&(g.mesh, f.cell)).copied(), f.cells, f.area))
                .collect(),
        })
        .collect()
}

/// The points `selection` selects, sorted; `field` names the selection in errors.
pub fn select(
    disc: &Discretization,
    selection: &Selection,
    field: &str,
) -> Result<Vec<usize>, InputError> {
    match selection {
        Selection::Box(b) => Ok((0..disc.points.len())
            .filter(|&i| b.contains(&disc.points.x[i]))
            .collect()),
        Selection::Group(name) => {
            let mut points: Vec<usize> = named(disc, name, field)?
                .flat_map(|g| g.points.iter().map(|&p| p as usize))
                .collect();
            points.sort_unstable();
            points.dedup();
            Ok(points)
        }
    }
}

/// `(point, area)` of every facet of the groups called `name` (dimension
/// d − 1): each must bound exactly one cell whose point is in the body.
pub fn facets(
    disc: &Discretization,
    name: &str,
    field: &str,
) -> Result<Vec<(usize, f64)>, InputError> {
    let d = disc.d;
    let mut out = Vec::new();
    for g in named(disc, name, field)?.filter(|g| g.dim + 1 == d) {
        for (k, &(point, cells, area)) in g.facets.iter().enumerate() {
            let problem = match (point, cells) {
                (_, 0) => "bounds no cell of the mesh",
                (_, 2..) => {
                    "lies inside the body (two cells share it); a traction acts on the boundary"
                }
                (None, _) => "bounds a cell whose point was removed (by a hole or as isolated)",
                (Some(p), 1) => {
                    out.push((p as usize, area));
                    continue;
                }
            };
            return Err(InputError::new(
                field,
                format!("facet {k} of group \"{name}\" {problem}"),
            ));
        }
    }
    if out.is_empty() {
        return Err(InputError::new(
            field,
            format!(
                "group \"{name}\" has no {}D elements (boundary {}) for a traction; use a body \
                 force on a {d}D group instead",
                d - 1,
                if d == 2 { "segments" } else { "faces" }
            ),
        ));
    }
    Ok(out)
}

/// The groups called `name`, or an error listing the named groups.
fn named<'a>(
    disc: &'a Discretization,
    name: &'a str,
    field: &str,
) -> Result<impl Iterator<Item = &'a PointGroup>, InputError> {
    if !disc.groups.iter().any(|g| g.name == name) {
        let mut known: Vec<&str> = disc.groups.iter().map(|g| g.name.as_str()).collect();
        known.sort_unstable();
        known.dedup();
        return Err(InputError::new(
            field,
            format!(
                "no physical group \"{name}\" in the meshes; named groups: {}",
                crate::error::echo_list(known)
            ),
        ));
    }
    Ok(disc.groups.iter().filter(move |g| g.name == name))
}
