//! Points from Gmsh meshes (`[[meshes]]`, MSH 4.1 read by [`super::gmsh`]).
//!
//! Each cell (element of the scene's dimension) becomes one point at its
//! centroid, with its area × thickness (2D) or volume (3D) as the point's
//! volume, the equivalent spacing `measure^(1/d)` and the horizon
//! `horizon_factor × spacing` (seed 000 builds its irregular discretisations
//! this way from Abaqus meshes). A cell takes the material of the mapped
//! physical group it belongs to (`meshes[k].groups`), else the mesh's
//! `material`.
//!
//! Physical groups become point sets for boundary conditions and loads
//! ([`MeshGroup`]): a group of the scene's dimension selects its cells; a
//! lower-dimensional one (boundary curves or faces, points) selects the cells
//! that have a node on it, and its facets (dimension d − 1) carry tractions:
//! facet area (length × thickness in 2D) times the traction, on the one cell
//! the facet bounds.

use super::gmsh;
use super::grid::{RawPoint, Source};
use crate::error::{Error, InputError};
use crate::scene::MeshFile;

/// A boundary facet of a mesh group: the cells it bounds and its area.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Facet {
    /// A cell the facet bounds.
    pub cell: u32,
    /// How many cells share the facet (1 on the body's boundary, 2 inside, 0
    /// when it bounds no cell of the mesh).
    pub cells: u8,
    /// Area (3D) or length × thickness (2D).
    pub area: f64,
}

/// A named physical group of a mesh, by cell index.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshGroup {
    /// Group name (unnamed groups are not kept).
    pub name: String,
    /// Index of the mesh in the scene.
    pub mesh: u32,
    /// Dimension of the group's elements.
    pub dim: usize,
    /// The cells it selects, sorted.
    pub cells: Vec<u32>,
    /// Its elements of dimension d − 1.
    pub facets: Vec<Facet>,
}

/// The points and named groups of one mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedMesh {
    /// One point per cell, in cell order.
    pub points: Vec<RawPoint>,
    /// Named physical groups.
    pub groups: Vec<MeshGroup>,
}

/// Largest mesh file read, in bytes.
const MAX_MESH_FILE_BYTES: u64 = 4 << 30;

/// Reads `meshes[index]` into points of dimension `d` (2 or 3).
pub fn import(
    file: &MeshFile,
    index: usize,
    d: usize,
    thickness: f64,
) -> Result<ImportedMesh, Error> {
    let field = format!("{}.path", file.field);
    let bytes = crate::scene::read_input_file(&file.path, &field, MAX_MESH_FILE_BYTES)?;
    let mesh = gmsh::read_msh(&bytes, d)
        .map_err(|e| InputError::new(&field, format!("{}: {e}", file.path.display())))?;
    drop(bytes);
    for (group, _) in &file.groups {
        if !mesh.groups.iter().any(|g| g.dim == d && &g.name == group) {
            return Err(InputError::new(
                format!("{}.groups.{group}", file.field),
                format!(
                    "{} has no {d}D physical group \"{group}\"; {d}D groups: {}",
                    file.path.display(),
                    names(&mesh, d)
                ),
            )
            .into());
        }
    }
    let points = (0..mesh.cells.measure.len())
        .map(|c| cell_point(&mesh, file, index, c, d, thickness))
        .collect::<Result<Vec<_>, _>>()?;
    let node_cells = node_cells(&mesh);
    let groups = mesh
        .groups
        .iter()
        .filter(|g| !g.name.is_empty())
        .map(|g| MeshGroup {
            name: g.name.clone(),
            mesh: index as u32,
            dim: g.dim,
            cells: if g.dim == d {
                g.cells.iter().map(|&c| c as u32).collect()
            } else {
                touching(&node_cells, &g.nodes)
            },
            facets: g
                .facets
                .iter()
                .map(|f| facet(&mesh, &node_cells, f, d, thickness))
                .collect(),
        })
        .collect();
    Ok(ImportedMesh { points, groups })
}

/// The point of cell `c`: at its centroid, with its measure (times the
/// thickness in 2D), the material of its groups or the file's.
fn cell_point(
    mesh: &gmsh::Mesh,
    file: &MeshFile,
    index: usize,
    c: usize,
    d: usize,
    thickness: f64,
) -> Result<RawPoint, InputError> {
    let cells = &mesh.cells;
    let at = |msg: String| InputError::new(&file.field, format!("{}: {msg}", file.path.display()));
    let mut material = None;
    for &g in &cells.groups[c] {
        let name = &mesh.groups[g].name;
        if let Some(&(_, m)) = file.groups.iter().find(|(group, _)| group == name) {
            if material.is_some_and(|old| old != m) {
                return Err(at(format!(
                    "element {} is in two groups mapped to different materials",
                    cells.element_tag[c]
                )));
            }
            material = Some(m);
        }
    }
    let material = material.or(file.material).ok_or_else(|| {
        at(format!(
            "element {} is in no group of `groups` and `material` is not given",
            cells.element_tag[c]
        ))
    })?;
    let measure = cells.measure[c];
    let spacing = measure.powf(1.0 / d as f64);
    let volume = measure * if d == 2 { thickness } else { 1.0 };
    if !(volume.is_finite() && volume > 0.0 && spacing > 0.0) {
        return Err(at(format!(
            "element {} has a measure {measure:e} outside the floating-point range of volumes",
            cells.element_tag[c]
        )));
    }
    Ok(RawPoint {
        x: cells.centroid[c],
        volume,
        spacing,
        horizon: file.horizon_factor * spacing,
        material: material as u32,
        source: Source::Mesh {
            mesh: index as u32,
            cell: c as u32,
            element: cells.element_tag[c],
        },
    })
}

/// The names of the mesh's named groups of dimension `dim`.
fn names(mesh: &gmsh::Mesh, dim: usize) -> String {
    crate::error::echo_list(
        mesh.groups
            .iter()
            .filter(|g| !g.name.is_empty() && g.dim == dim)
            .map(|g| g.name.as_str()),
    )
}

/// The cells of each node (CSR: offsets, cells).
fn node_cells(mesh: &gmsh::Mesh) -> (Vec<usize>, Vec<u32>) {
    let mut offsets = vec![0usize; mesh.nodes.len() + 1];
    for nodes in &mesh.cells.nodes {
        nodes.iter().for_each(|&n| offsets[n + 1] += 1);
    }
    for k in 0..mesh.nodes.len() {
        offsets[k + 1] += offsets[k];
    }
    let mut fill = offsets.clone();
    let mut cells = vec![0u32; offsets[mesh.nodes.len()]];
    for (c, nodes) in mesh.cells.nodes.iter().enumerate() {
        for &n in nodes {
            cells[fill[n]] = c as u32;
            fill[n] += 1;
        }
    }
    (offsets, cells)
}

/// The cells that have a node among `nodes`, sorted.
fn touching((offsets, cells): &(Vec<usize>, Vec<u32>), nodes: &[usize]) -> Vec<u32> {
    let mut out: Vec<u32> = nodes
        .iter()
        .flat_map(|&n| cells[offsets[n]..offsets[n + 1]].iter().copied())
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// A facet's bounding cells (those holding all its corner nodes) and area.
fn facet(
    mesh: &gmsh::Mesh,
    adjacency: &(Vec<usize>, Vec<u32>),
    nodes: &[usize],
    d: usize,
    thickness: f64,
) -> Facet {
    let (offsets, cells) = adjacency;
    // Corner nodes: a segment's two ends; a triangle's three or a quadrangle's
    // four corners (higher-order facets list their corners first).
    let corners = match (d, nodes.len()) {
        (2, _) => &nodes[..nodes.len().min(2)],
        (_, 3) | (_, 6) => &nodes[..3],
        _ => &nodes[..nodes.len().min(4)],
    };
    let x = |k: usize| mesh.nodes[corners[k]];
    let area = match corners.len() {
        2 => crate::vector::norm(&crate::vector::sub(&x(1), &x(0))) * thickness,
        3 => triangle(&x(0), &x(1), &x(2)),
        4 => triangle(&x(0), &x(1), &x(2)) + triangle(&x(0), &x(2), &x(3)),
        _ => 0.0,
    };
    let first = corners[0];
    let bounded: Vec<u32> = cells[offsets[first]..offsets[first + 1]]
        .iter()
        .copied()
        .filter(|&c| {
            corners
                .iter()
                .all(|n| mesh.cells.nodes[c as usize].contains(n))
        })
        .collect();
    Facet {
        cell: bounded.first().copied().unwrap_or(u32::MAX),
        cells: bounded.len().min(u8::MAX as usize) as u8,
        area,
    }
}

fn triangle(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    let (u, v) = (crate::vector::sub(b, a), crate::vector::sub(c, a));
    0.5 * crate::vector::norm(&crate::vector::cross(&u, &v))
}
