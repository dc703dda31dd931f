//! The bodies of a scene: grid regions (`[[regions]]`), point clouds
//! (`[[point_files]]`), Gmsh meshes (`[[meshes]]`), holes and pre-cracks.
//! Each region's box must be a whole number of spacings, regions may touch but
//! not overlap, a horizon must stay below the body's size and its bond
//! stiffness within the floating-point range.

use super::fields::{
    aabb, check_horizon_factor, coords, length_in_range, positive, Aabb, MAX_HORIZON_FACTOR,
    MAX_POINTS,
};
use super::material::{bond_stiffness_in_range, Material};
use super::spec::{CrackSpec, MeshSpec, PointFileSpec, RegionSpec, SceneSpec};
use crate::error::{approx, echo_list, num, InputError};
use crate::vector::{cross, norm};
use std::path::{Path, PathBuf};

/// How a region's horizons are set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HorizonRule {
    /// `δ = factor × spacing`.
    Factor(f64),
    /// A fixed radius in m.
    Radius(f64),
}

/// A validated grid region.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// Index into [`super::Scene::materials`].
    pub material: usize,
    /// Grid spacing.
    pub spacing: f64,
    /// Box filled with points (axes beyond `d` are unbounded).
    pub bounds: Aabb,
    /// Horizon rule.
    pub horizon: HorizonRule,
}

/// A validated point file reference.
#[derive(Debug, Clone, PartialEq)]
pub struct PointFile {
    /// Resolved path.
    pub path: PathBuf,
    /// Name of the field in the scene, for error messages (`point_files[0]`).
    pub field: String,
    /// Default material for rows without one.
    pub material: Option<usize>,
    /// Horizon factor for rows without a horizon.
    pub horizon_factor: f64,
}

/// A validated Gmsh mesh reference (`[[meshes]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshFile {
    /// Resolved path.
    pub path: PathBuf,
    /// Name of the field in the scene, for error messages (`meshes[0]`).
    pub field: String,
    /// Material of the cells in no mapped group.
    pub material: Option<usize>,
    /// `(physical group name, material)` pairs.
    pub groups: Vec<(String, usize)>,
    /// Horizon factor times each cell's equivalent spacing.
    pub horizon_factor: f64,
}

/// A hole: points whose centre is strictly inside are removed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hole {
    /// Centre.
    pub center: [f64; 3],
    /// Radius.
    pub radius: f64,
    /// Unit axis of a 3D through hole (a cylinder); `None`: a disc (2D) or ball (3D).
    pub axis: Option<[f64; 3]>,
}

impl Hole {
    /// Whether `x` lies strictly inside the hole.
    pub fn contains(&self, x: &[f64; 3]) -> bool {
        let r: [f64; 3] = std::array::from_fn(|a| x[a] - self.center[a]);
        let along = self
            .axis
            .map_or(0.0, |n| (0..3).map(|a| r[a] * n[a]).sum::<f64>());
        let radial2 = (0..3).map(|a| r[a] * r[a]).sum::<f64>() - along * along;
        radial2 < self.radius * self.radius
    }
}

/// A pre-crack no bond may cross.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Crack {
    /// 2D segment.
    Segment { from: [f64; 3], to: [f64; 3] },
    /// 3D parallelogram.
    Parallelogram {
        origin: [f64; 3],
        edge1: [f64; 3],
        edge2: [f64; 3],
    },
}

/// The validated bodies of a scene.
pub(super) struct Bodies {
    pub(super) regions: Vec<Region>,
    pub(super) point_files: Vec<PointFile>,
    pub(super) meshes: Vec<MeshFile>,
    pub(super) holes: Vec<Hole>,
    pub(super) cracks: Vec<Crack>,
}

/// Validates the bodies of `spec`; `thickness` is the model's, `base`
/// resolves relative paths.
pub(super) fn validate(
    spec: &SceneSpec,
    materials: &[Material],
    thickness: f64,
    base: &Path,
) -> Result<Bodies, InputError> {
    let d = spec.model.dimension.d();
    let regions = regions(spec, materials, thickness)?;
    let horizon_factor = spec.discretization.horizon_factor;
    let point_files = spec
        .point_files
        .iter()
        .enumerate()
        .map(|(k, p)| point_file(k, p, materials, horizon_factor, base))
        .collect::<Result<Vec<_>, _>>()?;
    let meshes = spec
        .meshes
        .iter()
        .enumerate()
        .map(|(k, m)| mesh(k, m, d, materials, horizon_factor, base))
        .collect::<Result<Vec<_>, _>>()?;
    if regions.is_empty() && point_files.is_empty() && meshes.is_empty() {
        return Err(InputError::new(
            "regions",
            "the scene has no points: add [[regions]], [[point_files]] or [[meshes]]",
        ));
    }
    let mut holes = Vec::new();
    for (k, h) in spec.holes.iter().enumerate() {
        let f = format!("holes[{k}]");
        if d == 1 {
            return Err(InputError::new(f, "holes need 2D or 3D"));
        }
        positive(&format!("{f}.radius"), h.radius)?;
        let axis = match (&h.axis, d) {
            (None, _) => None,
            (Some(_), 2) => {
                return Err(InputError::new(
                    format!("{f}.axis"),
                    "a 2D hole is a disc; axis is for 3D through holes",
                ))
            }
            (Some(a), _) => {
                let a = coords(&format!("{f}.axis"), a, d)?;
                let len = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                if !(len > 0.0 && len.is_finite()) {
                    return Err(InputError::new(
                        format!("{f}.axis"),
                        "must be a non-zero direction, e.g. [0, 0, 1]",
                    ));
                }
                Some(a.map(|v| v / len))
            }
        };
        holes.push(Hole {
            center: coords(&format!("{f}.center"), &h.center, d)?,
            radius: h.radius,
            axis,
        });
    }
    let cracks = spec
        .cracks
        .iter()
        .enumerate()
        .map(|(k, c)| crack(&format!("cracks[{k}]"), c, d))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Bodies {
        regions,
        point_files,
        meshes,
        holes,
        cracks,
    })
}

/// The index of material `name`, or an error listing the materials.
pub(super) fn material_index(
    materials: &[Material],
    field: &str,
    name: &str,
) -> Result<usize, InputError> {
    materials
        .iter()
        .position(|m| m.name == name)
        .ok_or_else(|| {
            let known: Vec<_> = materials.iter().map(|m| m.name.as_str()).collect();
            InputError::new(
                field,
                format!("unknown material \"{name}\"; defined: {}", echo_list(known)),
            )
        })
}

/// The regions, each checked, then checked together: no horizon as wide as
/// the body, no overlap.
fn regions(
    spec: &SceneSpec,
    materials: &[Material],
    thickness: f64,
) -> Result<Vec<Region>, InputError> {
    let mut regions = Vec::new();
    let mut total_points = 0.0f64;
    for (k, r) in spec.regions.iter().enumerate() {
        regions.push(region(k, r, spec, materials, thickness, &mut total_points)?);
    }
    let d = spec.model.dimension.d();
    check_extent(&regions, d)?;
    for i in 0..regions.len() {
        for j in 0..i {
            if overlap(&regions[i].bounds, &regions[j].bounds, d) {
                return Err(InputError::new(
                    format!("regions[{i}].box"),
                    format!("overlaps regions[{j}].box; regions must not overlap (they may touch)"),
                ));
            }
        }
    }
    Ok(regions)
}

/// Region `k`; `total_points` counts the grid points of the regions so far.
fn region(
    k: usize,
    r: &RegionSpec,
    spec: &SceneSpec,
    materials: &[Material],
    thickness: f64,
    total_points: &mut f64,
) -> Result<Region, InputError> {
    let dimension = spec.model.dimension;
    let d = dimension.d();
    let f = format!("regions[{k}]");
    let material = material_index(materials, &format!("{f}.material"), &r.material)?;
    positive(&format!("{f}.spacing"), r.spacing)?;
    length_in_range(&format!("{f}.spacing"), "spacing", r.spacing)?;
    let bounds = aabb(&format!("{f}.box"), &r.bounds, d)?;
    for x in bounds.min[..d].iter().chain(&bounds.max[..d]) {
        length_in_range(&format!("{f}.box"), "coordinate", *x)?;
    }
    *total_points += cell_count(&f, &bounds, r.spacing, d)?;
    if *total_points > MAX_POINTS as f64 {
        return Err(InputError::new(format!("{f}.spacing"), format!(
            "the regions would hold {total_points:.3e} points; at most {MAX_POINTS} are supported \
             (a direct solver needs far less than that to run out of memory): use a coarser spacing")));
    }
    let horizon = horizon_rule(&f, r, spec.discretization.horizon_factor)?;
    // Each input is finite and positive, but their products must be too.
    let volume = r.spacing.powi(d as i32) * if d < 3 { thickness } else { 1.0 };
    let radius = match horizon {
        HorizonRule::Factor(m) => m * r.spacing,
        HorizonRule::Radius(h) => h,
    };
    if !(volume.is_finite() && volume > 0.0 && (radius + 2.0 * r.spacing).is_finite()) {
        return Err(InputError::new(
            format!("{f}.spacing"),
            format!(
                "spacing {} gives a point volume {volume:e} and a horizon {radius:e}: \
                 outside the floating-point range; rescale the units",
                num(r.spacing)
            ),
        ));
    }
    bond_stiffness_in_range(
        &f,
        &format!("{f}.spacing"),
        dimension,
        &materials[material],
        r.spacing,
        radius,
        volume,
        thickness,
    )?;
    Ok(Region {
        material,
        spacing: r.spacing,
        bounds,
        horizon,
    })
}

/// The number of grid points of a region `f` (its box a whole number of
/// spacings along every axis).
fn cell_count(f: &str, bounds: &Aabb, spacing: f64, d: usize) -> Result<f64, InputError> {
    let mut count = 1.0f64;
    for a in 0..d {
        let cells = (bounds.max[a] - bounds.min[a]) / spacing;
        if cells < 0.5 {
            return Err(InputError::new(
                format!("{f}.box"),
                format!("extent {} along axis {a} is smaller than one spacing ({}): the region would hold no point",
                    num(bounds.max[a] - bounds.min[a]), num(spacing)),
            ));
        }
        count *= cells.round();
        if (cells - cells.round()).abs() > 1e-6 * cells.max(1.0) {
            return Err(InputError::new(
                format!("{f}.box"),
                format!(
                    "extent {} along axis {a} is not a whole number of spacings ({} × {}); \
                         adjust the box or the spacing",
                    num(bounds.max[a] - bounds.min[a]),
                    approx(cells),
                    num(spacing)
                ),
            ));
        }
    }
    Ok(count)
}

/// How region `f` sets its horizons: a radius, its own factor, or the
/// scene's `horizon_factor`.
fn horizon_rule(f: &str, r: &RegionSpec, horizon_factor: f64) -> Result<HorizonRule, InputError> {
    Ok(match (r.horizon, r.horizon_factor) {
        (Some(_), Some(_)) => {
            return Err(InputError::new(
                format!("{f}.horizon"),
                "give either horizon or horizon_factor, not both",
            ))
        }
        (Some(h), None) => {
            positive(&format!("{f}.horizon"), h)?;
            if h <= r.spacing {
                return Err(InputError::new(format!("{f}.horizon"), format!(
                    "horizon {} is not larger than the spacing {}: no point would have a neighbour; \
                     use a horizon of about 3 spacings", num(h), num(r.spacing))));
            }
            if h > MAX_HORIZON_FACTOR * r.spacing {
                return Err(InputError::new(format!("{f}.horizon"), format!(
                    "horizon {} is {} spacings ({}): implausibly large (above {MAX_HORIZON_FACTOR}); \
                     typical horizons are 2 to 5 spacings", num(h), approx(h / r.spacing), num(r.spacing))));
            }
            HorizonRule::Radius(h)
        }
        (None, Some(m)) => {
            check_horizon_factor(&format!("{f}.horizon_factor"), m)?;
            HorizonRule::Factor(m)
        }
        (None, None) => HorizonRule::Factor(horizon_factor),
    })
}

/// Refuses a region whose horizon is not smaller than the body: it would
/// bond every point to every other.
fn check_extent(regions: &[Region], d: usize) -> Result<(), InputError> {
    if let Some(first) = regions.first() {
        // A horizon as wide as the body bonds every point to every other.
        let (mut lo, mut hi) = (first.bounds.min, first.bounds.max);
        for r in regions {
            for a in 0..d {
                lo[a] = lo[a].min(r.bounds.min[a]);
                hi[a] = hi[a].max(r.bounds.max[a]);
            }
        }
        let extent = (0..d).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
        for (k, r) in regions.iter().enumerate() {
            let (radius, field) = match r.horizon {
                HorizonRule::Factor(m) => (m * r.spacing, "horizon_factor"),
                HorizonRule::Radius(h) => (h, "horizon"),
            };
            if radius >= extent {
                return Err(InputError::new(
                    format!("regions[{k}].{field}"),
                    format!(
                        "gives a horizon of {} m, not smaller than the body ({} m \
                         across its regions): every point would bond to every other; use a \
                         finer spacing or a smaller horizon",
                        num(radius),
                        num(extent)
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// `[[point_files]]` entry `k`.
fn point_file(
    k: usize,
    p: &PointFileSpec,
    materials: &[Material],
    horizon_factor: f64,
    base: &Path,
) -> Result<PointFile, InputError> {
    let f = format!("point_files[{k}]");
    if p.path.trim().is_empty() {
        return Err(InputError::new(format!("{f}.path"), "empty path"));
    }
    let material = p
        .material
        .as_deref()
        .map(|m| material_index(materials, &format!("{f}.material"), m))
        .transpose()?;
    let factor = p.horizon_factor.unwrap_or(horizon_factor);
    check_horizon_factor(&format!("{f}.horizon_factor"), factor)?;
    Ok(PointFile {
        path: base.join(&p.path),
        field: f,
        material,
        horizon_factor: factor,
    })
}

/// `[[meshes]]` entry `k` of a `d`-dimensional scene.
fn mesh(
    k: usize,
    m: &MeshSpec,
    d: usize,
    materials: &[Material],
    horizon_factor: f64,
    base: &Path,
) -> Result<MeshFile, InputError> {
    let f = format!("meshes[{k}]");
    if m.path.trim().is_empty() {
        return Err(InputError::new(format!("{f}.path"), "empty path"));
    }
    if d == 1 {
        return Err(InputError::new(
            f,
            "meshes need 2D or 3D (triangles, quadrangles, tetrahedra, hexahedra)",
        ));
    }
    let material = m
        .material
        .as_deref()
        .map(|name| material_index(materials, &format!("{f}.material"), name))
        .transpose()?;
    let groups = m
        .groups
        .iter()
        .map(|(group, name)| {
            Ok((
                group.clone(),
                material_index(materials, &format!("{f}.groups.{group}"), name)?,
            ))
        })
        .collect::<Result<Vec<_>, InputError>>()?;
    if material.is_none() && groups.is_empty() {
        return Err(InputError::new(
            format!("{f}.material"),
            "missing: give the cells' material, or `groups` mapping physical groups to materials",
        ));
    }
    let factor = m.horizon_factor.unwrap_or(horizon_factor);
    check_horizon_factor(&format!("{f}.horizon_factor"), factor)?;
    Ok(MeshFile {
        path: base.join(&m.path),
        field: f,
        material,
        groups,
        horizon_factor: factor,
    })
}

/// Whether two boxes share more than a face (relative 1e-9 of the larger).
fn overlap(a: &Aabb, b: &Aabb, d: usize) -> bool {
    (0..d).all(|k| {
        let lo = a.min[k].max(b.min[k]);
        let hi = a.max[k].min(b.max[k]);
        hi - lo > 1e-9 * (a.max[k] - a.min[k]).max(b.max[k] - b.min[k])
    })
}

/// A pre-crack: a segment in 2D, a parallelogram in 3D.
fn crack(field: &str, c: &CrackSpec, d: usize) -> Result<Crack, InputError> {
    match (d, c) {
        (
            2,
            CrackSpec {
                from: Some(a),
                to: Some(b),
                origin: None,
                edge1: None,
                edge2: None,
            },
        ) => {
            let (from, to) = (
                coords(&format!("{field}.from"), a, 2)?,
                coords(&format!("{field}.to"), b, 2)?,
            );
            if from == to {
                return Err(InputError::new(field, "the segment has zero length"));
            }
            Ok(Crack::Segment { from, to })
        }
        (
            3,
            CrackSpec {
                from: None,
                to: None,
                origin: Some(o),
                edge1: Some(e1),
                edge2: Some(e2),
            },
        ) => {
            let (origin, edge1, edge2) = (
                coords(&format!("{field}.origin"), o, 3)?,
                coords(&format!("{field}.edge1"), e1, 3)?,
                coords(&format!("{field}.edge2"), e2, 3)?,
            );
            let n = cross(&edge1, &edge2);
            if norm(&n) == 0.0 {
                return Err(InputError::new(
                    field,
                    "edge1 and edge2 are parallel: the crack face has no area",
                ));
            }
            Ok(Crack::Parallelogram {
                origin,
                edge1,
                edge2,
            })
        }
        (2, _) => Err(InputError::new(
            field,
            "a 2D crack is a segment: give exactly `from` and `to`",
        )),
        (3, _) => Err(InputError::new(
            field,
            "a 3D crack is a parallelogram: give exactly `origin`, `edge1` and `edge2`",
        )),
        _ => Err(InputError::new(field, "pre-cracks need 2D or 3D")),
    }
}
