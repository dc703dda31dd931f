//! Discretisation: points with per-point volume, spacing, horizon and material,
//! and their bonds.
//!
//! Bonds (formulation Sec. 1): `i → j` exists when `j` lies in the horizon of
//! `i` (with a positive partial-volume factor) and the segment crosses no pre-crack. Its owner is `i`. Bonds are stored per owner in
//! CSR form (`offsets`, `neighbour`), with the partial-volume factor `ν_ij`
//! (formulation Sec. 6) and an intact flag per bond. The dual horizon
//! `H'_i = { j : i ∈ H_j }` is implied and never stored here.
//!
//! Imported points (point files, meshes) are checked like grid regions: a
//! spacing within [`crate::scene::MIN_LENGTH`, `crate::scene::MAX_LENGTH`],
//! coordinates within ±`MAX_LENGTH`, a bond stiffness in the floating-point
//! range. Points at the same position, or closer than 1e-9 of a spacing, are
//! refused, naming both sources.
//!
//! The partial-volume rule is chosen per scene ([`partial_volume`]); the
//! default counts the exact overlap of each neighbour's equivalent disc or ball
//! with the horizon, so bonds reach up to `δ_i + r_j`.

pub mod groups;
mod neighbours;
mod overlap;
pub mod partial_volume;
pub mod share;

use crate::error::{Error, InputError, NumericalError};
use crate::geometry::grid::{self, RawPoint, Source};
use crate::geometry::mesh_file::{self, MeshGroup};
use crate::geometry::point_file;
use crate::notes::Notes;
use crate::processes::{agreed, Processes};
use crate::scene::VolumeCorrection;
use crate::scene::{HorizonMode, IsolatedPolicy, Scene};
use groups::PointGroup;
use share::{Distribution, Share};
use std::ops::Range;

/// Per-point data, structure of arrays.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Points {
    /// Reference positions (unused axes are zero).
    pub x: Vec<[f64; 3]>,
    /// Volumes (including thickness in 2D, area in 1D).
    pub volume: Vec<f64>,
    /// Local spacing (cell size, or volume^(1/d) for imported points).
    pub spacing: Vec<f64>,
    /// Horizon radius δ_i.
    pub horizon: Vec<f64>,
    /// Material index into the scene's materials.
    pub material: Vec<u32>,
    /// The scene item each point comes from (a region, a point-file line, a mesh cell).
    pub source: Vec<Source>,
}

impl Points {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there is no point.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    fn from_raw(raw: &[RawPoint]) -> Self {
        Points {
            x: raw.iter().map(|p| p.x).collect(),
            volume: raw.iter().map(|p| p.volume).collect(),
            spacing: raw.iter().map(|p| p.spacing).collect(),
            horizon: raw.iter().map(|p| p.horizon).collect(),
            material: raw.iter().map(|p| p.material).collect(),
            source: raw.iter().map(|p| p.source).collect(),
        }
    }
}

/// Bonds grouped by owner (CSR).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bonds {
    /// `offsets[i]..offsets[i+1]` are the bonds owned by point `i`.
    pub offsets: Vec<usize>,
    /// Neighbour `j` of each bond.
    pub neighbour: Vec<u32>,
    /// Partial-volume factor `ν_ij` of each bond.
    pub volume_factor: Vec<f64>,
    /// Intact flag (bonds never heal).
    pub intact: Vec<bool>,
    /// `in_offsets[q]..in_offsets[q+1]` index `in_bonds` for point `q`: the
    /// transpose of the CSR, built once ([`Bonds::incoming`]).
    pub in_offsets: Vec<usize>,
    /// `(owner, bond)` of every bond whose neighbour is `q`, by owner.
    pub in_bonds: Vec<(u32, u32)>,
}

impl Bonds {
    /// The bond indices owned by `i`.
    #[inline]
    pub fn owned_by(&self, i: usize) -> Range<usize> {
        self.offsets[i]..self.offsets[i + 1]
    }

    /// The `(owner, bond)` pairs of the bonds ending at `q` (its dual horizon),
    /// by owner; intact or not.
    #[inline]
    pub fn incoming(&self, q: usize) -> &[(u32, u32)] {
        &self.in_bonds[self.in_offsets[q]..self.in_offsets[q + 1]]
    }

    /// Builds the transpose of the bond CSR for `n` points ([`Bonds::incoming`]).
    fn with_transpose(mut self, n: usize) -> Self {
        let mut in_offsets = vec![0usize; n + 1];
        for &j in &self.neighbour {
            in_offsets[j as usize + 1] += 1;
        }
        for q in 0..n {
            in_offsets[q + 1] += in_offsets[q];
        }
        let mut fill = in_offsets.clone();
        let mut in_bonds = vec![(0u32, 0u32); self.len()];
        for o in 0..n {
            for b in self.owned_by(o) {
                let j = self.neighbour[b] as usize;
                in_bonds[fill[j]] = (o as u32, b as u32);
                fill[j] += 1;
            }
        }
        self.in_offsets = in_offsets;
        self.in_bonds = in_bonds;
        self
    }

    /// Total number of bonds.
    pub fn len(&self) -> usize {
        self.neighbour.len()
    }

    /// Whether there is no bond.
    pub fn is_empty(&self) -> bool {
        self.neighbour.is_empty()
    }

    /// Number of intact bonds that touch each point, as owner or as neighbour.
    pub fn touch_counts(&self, n: usize) -> Vec<u32> {
        let mut count = vec![0u32; n];
        for i in 0..n {
            for b in self.owned_by(i) {
                if self.intact[b] {
                    count[i] += 1;
                    count[self.neighbour[b] as usize] += 1;
                }
            }
        }
        count
    }
}

/// Points and bonds of a body.
#[derive(Debug, Clone, PartialEq)]
pub struct Discretization {
    /// Spatial dimension d.
    pub d: usize,
    /// Points.
    pub points: Points,
    /// Bonds.
    pub bonds: Bonds,
    /// Number of isolated points removed (policy `remove`).
    pub removed_isolated: usize,
    /// Named point sets from the physical groups of imported meshes.
    pub groups: Vec<PointGroup>,
    /// This process's share when the body is discretised over several
    /// processes (`discretization::share`): only the families of
    /// `share.searched` are here. `None`: one process.
    pub share: Option<Share>,
}

impl Discretization {
    /// This process's share when it holds only some of the bonds (a body
    /// discretised over several processes, not a fracture scene's, whose
    /// processes each hold every bond).
    pub fn partial_share(&self) -> Option<&Share> {
        self.share.as_ref().filter(|s| !s.every_bond)
    }

    /// The same points with the bonds they would have without pre-cracks (the
    /// reference of the surface correction, `model::surface`), searched with the
    /// same partial-volume `rule` and over the same share.
    pub fn without_cracks(&self, rule: VolumeCorrection) -> Result<Discretization, Error> {
        let searched = self.share.as_ref().map(|s| &s.searched[..]);
        let bonds = neighbours::find_bonds(&self.points, self.d, &[], rule, None, searched)?;
        Ok(Discretization {
            d: self.d,
            points: self.points.clone(),
            bonds,
            removed_isolated: self.removed_isolated,
            groups: Vec::new(),
            share: self.share.clone(),
        })
    }

    /// Whether this process answers for point `i` (its force, reaction,
    /// stress, bonds): every point, unless it holds only some of the bonds
    /// ([`Discretization::partial_share`]), then its own.
    pub fn reports(&self, i: usize) -> bool {
        self.partial_share().is_none_or(|s| s.owns(i))
    }
}

/// The points of a scene before bonds are found, with the named groups of its meshes.
#[derive(Debug, Clone, PartialEq)]
pub struct RawBody {
    /// Points of every region, point file and mesh, holes removed.
    pub points: Vec<RawPoint>,
    /// Physical groups of the meshes, by cell.
    pub mesh_groups: Vec<MeshGroup>,
}

/// Builds the points of a scene (grids, point files, holes, horizon mode) and
/// their bonds, notes dropped: for the crate's tests and studies (the drivers
/// start from their setup).
#[cfg(feature = "fixtures")]
pub fn build(scene: &Scene) -> Result<Discretization, Error> {
    discretize(scene, generate_points(scene)?, &mut Notes::default(), None)
}

/// Generates the raw points of the scene, holes removed, horizons set.
pub fn generate_points(scene: &Scene) -> Result<RawBody, Error> {
    let d = scene.d();
    let mut raw: Vec<RawPoint> = Vec::new();
    let mut mesh_groups = Vec::new();
    for (k, region) in scene.regions.iter().enumerate() {
        raw.extend(grid::fill(region, k, d, scene.model.thickness));
    }
    for (k, file) in scene.point_files.iter().enumerate() {
        let text = crate::scene::read_text_file(
            &file.path,
            &format!("{}.path", file.field),
            crate::scene::read::MAX_POINT_FILE_BYTES,
        )?;
        raw.extend(point_file::parse(
            &text,
            file,
            k,
            d,
            scene.model.thickness,
            &scene.materials,
        )?);
    }
    for (k, file) in scene.meshes.iter().enumerate() {
        let mesh = mesh_file::import(file, k, d, scene.model.thickness)?;
        raw.extend(mesh.points);
        mesh_groups.extend(mesh.groups);
    }
    raw.retain(|p| !scene.holes.iter().any(|h| h.contains(&p.x)));
    if raw.is_empty() {
        return Err(InputError::new("holes", "the holes remove every point of the body").into());
    }
    // A region the holes empty would vanish without a word (its material and
    // spacing with it): almost always a misplaced box or hole.
    let mut kept = vec![false; scene.regions.len()];
    for p in &raw {
        if let Source::Region(k) = p.source {
            kept[k as usize] = true;
        }
    }
    if let Some(k) = kept.iter().position(|&kept| !kept) {
        return Err(InputError::new(
            format!("regions[{k}]"),
            "every point of this region lies inside a hole ([[holes]]); remove the region, or \
             move its box or the hole",
        )
        .into());
    }
    check_scales(&raw, scene)?;
    reject_duplicates(&raw)?;
    overlap::reject_overlaps(&raw, &scene.regions, d)?;
    if scene.model.horizons == HorizonMode::Constant {
        let largest = raw.iter().map(|p| p.horizon).fold(0.0, f64::max);
        raw.iter_mut().for_each(|p| p.horizon = largest);
    }
    Ok(RawBody {
        points: raw,
        mesh_groups,
    })
}

/// Refuses an imported point (point file, mesh) whose spacing or coordinates
/// lie outside the lengths double precision holds for the bond computations
/// ([`crate::scene::fields::length_in_range`]) or whose bond stiffness is out of range
/// (regions are checked with the scene).
fn check_scales(raw: &[RawPoint], scene: &Scene) -> Result<(), InputError> {
    for p in raw {
        if matches!(p.source, Source::Region(_)) {
            continue;
        }
        let field = p.source.to_string();
        crate::scene::fields::length_in_range(&field, "spacing", p.spacing)?;
        for &x in &p.x[..scene.d()] {
            crate::scene::fields::length_in_range(&field, "coordinate", x)?;
        }
        crate::scene::material::bond_stiffness_in_range(
            &field,
            &field,
            scene.model.dimension,
            &scene.materials[p.material as usize],
            p.spacing,
            p.horizon,
            p.volume,
            scene.model.thickness,
        )?;
    }
    Ok(())
}

/// The error for a point whose model quantities (`what`, of value `value`)
/// are not finite or underflow although its inputs passed their checks: a
/// scale at which a model's intermediate quantities (the shear model's
/// `1/(|ξ|² m)`) leave double precision. Names the point's source
/// (`regions[k].spacing`, a point-file line, a mesh element).
pub fn beyond_double_precision(
    disc: &Discretization,
    point: usize,
    what: &str,
    value: f64,
) -> InputError {
    let p = &disc.points;
    let field = match p.source[point] {
        Source::Region(k) => format!("regions[{k}].spacing"),
        other => other.to_string(),
    };
    InputError::new(
        field,
        format!(
            "{what} of point {point} (x = {:?}) is {value:.3e}, outside the floating-point \
             range: at its spacing ({} m) the model's quantities (e.g. the shear model's \
             1/(|ξ|² m)) leave double precision; rescale the units (e.g. mm or µm, or km, \
             instead of m)",
            p.x[point],
            crate::error::num(p.spacing[point])
        ),
    )
}

/// Rejects points at identical positions, naming where both come from.
fn reject_duplicates(raw: &[RawPoint]) -> Result<(), InputError> {
    let mut order: Vec<usize> = (0..raw.len()).collect();
    order.sort_unstable_by_key(|&i| raw[i].x.map(f64::to_bits));
    for w in order.windows(2) {
        if raw[w[0]].x == raw[w[1]].x {
            let (a, b) = (w[0].min(w[1]), w[0].max(w[1]));
            return Err(InputError::new(
                raw[b].source.to_string(),
                format!(
                    "a point at {:?} duplicates one from {}; each position may hold one point",
                    raw[b].x, raw[a].source
                ),
            ));
        }
    }
    Ok(())
}

/// Builds bonds for given points, applying the isolated-point policy (a
/// warning in `notes` for the points it removes). With a `distribution`,
/// this process searches only the families of its share ([`share`]), and
/// every decision that needs the whole body (isolated points) is made together.
pub fn discretize(
    scene: &Scene,
    body: RawBody,
    notes: &mut Notes,
    distribution: Option<&Distribution>,
) -> Result<Discretization, Error> {
    let processes = distribution.map(|s| s.processes);
    let d = scene.d();
    let RawBody {
        points: mut raw,
        mesh_groups,
    } = body;
    let mut removed_isolated = 0;
    let rule = scene.discretization.volume_correction;
    loop {
        let points = Points::from_raw(&raw);
        let share = distribution
            .map(|s| {
                let bodiless = Discretization {
                    d,
                    points: points.clone(),
                    bonds: Bonds::default(),
                    removed_isolated,
                    groups: groups::resolve(&mesh_groups, &raw),
                    share: None,
                };
                let free = (s.free_components)(&bodiless)?;
                let largest = points.spacing.iter().copied().fold(0.0, f64::max);
                let reach = partial_volume::PartialVolume { rule, d }.reach(largest);
                let depth = Share::depth(scene);
                Share::new(s.processes, &points, &free, d, depth, reach)
            })
            .transpose();
        let share = agreed(processes, share)?;
        let bonds = neighbours::find_bonds(
            &points,
            d,
            &scene.cracks,
            rule,
            scene.solver.memory_limit_bytes,
            share.as_ref().map(|s| &s.searched[..]),
        );
        let bonds = agreed(processes, bonds)?;
        let partial = share.as_ref().filter(|s| !s.every_bond);
        let isolated = isolated_points(&bonds, points.len(), partial, processes);
        if isolated.is_empty() {
            return Ok(Discretization {
                d,
                groups: groups::resolve(&mesh_groups, &raw),
                bonds: bonds.with_transpose(points.len()),
                points,
                removed_isolated,
                share,
            });
        }
        match scene.discretization.isolated_points {
            IsolatedPolicy::Error => {
                return Err(NumericalError::IsolatedPoints {
                    count: isolated.len(),
                    first: isolated[0],
                    position: points.x[isolated[0]],
                }
                .into())
            }
            IsolatedPolicy::Remove => {
                notes.push(format!(
                    "warning: removing {} point(s) without any bond (first at {:?})",
                    isolated.len(),
                    points.x[isolated[0]]
                ));
                removed_isolated += isolated.len();
                let mut keep = vec![true; raw.len()];
                isolated.iter().for_each(|&i| keep[i] = false);
                let mut k = 0;
                raw.retain(|_| {
                    k += 1;
                    keep[k - 1]
                });
                if raw.is_empty() {
                    return Err(InputError::new(
                        "discretization.isolated_points",
                        "every point is isolated",
                    )
                    .into());
                }
            }
        }
    }
}

/// The points no bond touches, in increasing order. With a `share` of the
/// bonds, each process decides for its own points (whose touching bonds it
/// all holds) and the processes add up their answers (a collective call).
fn isolated_points(
    bonds: &Bonds,
    n: usize,
    share: Option<&Share>,
    processes: Option<&dyn Processes>,
) -> Vec<usize> {
    let touches = bonds.touch_counts(n);
    let mine = |i: usize| touches[i] == 0 && share.is_none_or(|s| s.owns(i));
    let Some(processes) = processes.filter(|_| share.is_some()) else {
        return (0..n).filter(|&i| mine(i)).collect();
    };
    let mut count = [(0..n).filter(|&i| mine(i)).count() as f64];
    processes.sum(&mut count);
    if count[0] == 0.0 {
        return Vec::new();
    }
    let mut flags: Vec<f64> = (0..n).map(|i| f64::from(u8::from(mine(i)))).collect();
    processes.sum(&mut flags);
    (0..n).filter(|&i| flags[i] > 0.0).collect()
}
