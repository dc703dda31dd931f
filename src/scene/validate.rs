//! Validation of a [`SceneSpec`] into a typed [`Scene`].

use super::material::{self, FractureParameter, Material};
use super::solver::{Precision, SolverSettings};
use super::spec::*;
use crate::error::{approx, echo_list, num, InputError};
use std::path::{Path, PathBuf};

/// The largest number of grid points a scene may generate.
pub const MAX_POINTS: usize = 50_000_000;

/// An axis-aligned box in 3D coordinates; axes beyond the scene's dimension are unbounded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: [f64; 3],
    /// Upper corner.
    pub max: [f64; 3],
}

impl Aabb {
    /// Whether `x` lies inside, boundary included (with a relative tolerance of 1e-9 of the box size).
    pub fn contains(&self, x: &[f64; 3]) -> bool {
        (0..3).all(|a| {
            let tol = if self.max[a].is_finite() {
                1e-9 * (self.max[a] - self.min[a]).abs().max(f64::MIN_POSITIVE)
            } else {
                0.0
            };
            x[a] >= self.min[a] - tol && x[a] <= self.max[a] + tol
        })
    }
}

/// Bond breakage settings shared by the drivers that break bonds.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FractureSettings {
    /// Shear model: energy counting of `fracture_energy`.
    pub shear_energy: EnergyCounting,
    /// How `fracture_energy` becomes a critical value.
    pub calibration: Calibration,
    /// Shear model: the breakage criterion.
    pub shear_criterion: ShearCriterion,
    /// Boxes where no bond breaks.
    pub no_fail: Vec<Aabb>,
}

/// Validated quasi-static settings (formulation Sec. 5, sequentially linear breakage).
#[derive(Debug, Clone, PartialEq)]
pub struct QuasiStatic {
    /// Breakage strategy.
    pub strategy: Strategy,
    /// Largest load factor.
    pub max_load_factor: f64,
    /// Uniform steps up to `max_load_factor` (`all`, `most_critical`).
    pub steps: usize,
    /// Halve a step that breaks more than this many bonds.
    pub max_broken_per_step: Option<usize>,
    /// Smallest step when halving, as a fraction of the uniform step.
    pub min_step_fraction: f64,
    /// Relative tolerance on the largest ratio for bonds that break together.
    pub tolerance: f64,
    /// Re-solves allowed within one step.
    pub max_resolves: usize,
    /// Events allowed (`event`).
    pub max_events: usize,
    /// End once every reaction is below this fraction of its peak.
    pub stop_after_peak: Option<f64>,
}

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
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// Grid spacing.
    pub spacing: f64,
    /// Box filled with points (axes beyond `d` are unbounded).
    pub bounds: Aabb,
    /// Horizon rule.
    pub horizon: HorizonRule,
}

/// Smallest load step of the stepped fracture strategies, relative to
/// `max_load_factor` (bounds `quasi_static.min_step_fraction` from below).
pub const MIN_STEP_RELATIVE: f64 = 1e-12;

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

/// Which points a boundary condition or a load selects.
#[derive(Debug, Clone, PartialEq)]
pub enum Selection {
    /// The points inside a box.
    Box(Aabb),
    /// The points of a mesh's physical group (its cells, or the cells touching
    /// a lower-dimensional group).
    Group(String),
}

/// A hole: points whose centre is strictly inside are removed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hole {
    /// Centre.
    pub center: [f64; 3],
    /// Radius.
    pub radius: f64,
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

/// Prescribed displacement on a set of points.
#[derive(Debug, Clone, PartialEq)]
pub struct Prescribed {
    /// Name for the reaction report.
    pub name: String,
    /// Selected points.
    pub selection: Selection,
    /// Prescribed value per component (`None` = free).
    pub values: [Option<f64>; 3],
}

/// Where a load acts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LoadTarget {
    /// Outermost point layer facing `axis` in direction `sign` (±1).
    Face { axis: usize, sign: f64 },
    /// Every selected point, in proportion to its volume.
    Volume,
    /// The boundary facets of a mesh group (dimension d − 1): each facet's
    /// traction × area goes to the cell it bounds.
    Facets,
}

/// A validated load.
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    /// Name for the summary.
    pub name: String,
    /// Face or volume.
    pub target: LoadTarget,
    /// Restricting selection (None = whole body).
    pub selection: Option<Selection>,
    /// Traction (Pa) or force density (N/m³).
    pub value: [f64; 3],
}

/// A validated line profile.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// Name (safe as a file name).
    pub name: String,
    /// Start.
    pub from: [f64; 3],
    /// End.
    pub to: [f64; 3],
}

/// A validated probe.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// Name.
    pub name: String,
    /// Location.
    pub at: [f64; 3],
}

/// What to write.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputSettings {
    /// `points.vtu`.
    pub vtu: bool,
    /// `points.csv`.
    pub points_csv: bool,
    /// Stress recovery.
    pub stress: bool,
    /// `K.mtx`, `f.mtx`.
    pub matrix_market: bool,
    /// Profiles.
    pub profiles: Vec<Profile>,
    /// Probes.
    pub probes: Vec<Probe>,
    /// Fracture runs: a VTU file every this many steps.
    pub every: Option<usize>,
    /// Fracture runs: a VTU file at these steps.
    pub steps: Vec<usize>,
}

/// A validated scene: everything the numerics need, nothing they do not.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Name used in reports.
    pub name: String,
    /// Model.
    pub model: ModelKind,
    /// Spatial setting.
    pub dimension: Dimension,
    /// 2D thickness, 1D area, 1 in 3D: the factor from per-unit quantities to volumes.
    pub thickness: f64,
    /// Dual or constant horizons.
    pub horizons: HorizonMode,
    /// Partial-volume rule.
    pub volume_correction: VolumeCorrection,
    /// Shear model: dilatation from the shape-tensor gradient (exact θ at free surfaces).
    pub gradient_dilatation: bool,
    /// Isolated-point policy.
    pub isolated_points: IsolatedPolicy,
    /// Materials, indexed by regions and points.
    pub materials: Vec<Material>,
    /// Grid regions.
    pub regions: Vec<Region>,
    /// Point files.
    pub point_files: Vec<PointFile>,
    /// Gmsh meshes.
    pub meshes: Vec<MeshFile>,
    /// Holes.
    pub holes: Vec<Hole>,
    /// Pre-cracks.
    pub cracks: Vec<Crack>,
    /// Prescribed displacements.
    pub boundaries: Vec<Prescribed>,
    /// Loads.
    pub loads: Vec<Load>,
    /// The `[solver]` section.
    pub solver: SolverSettings,
    /// Output settings.
    pub output: OutputSettings,
    /// Bond breakage settings (used by fracture runs only).
    pub fracture: FractureSettings,
    /// Quasi-static fracture run (None: a static solve).
    pub quasi_static: Option<QuasiStatic>,
    /// Explicit dynamics settings (selects the explicit driver).
    pub dynamics: Option<super::dynamics::Dynamics>,
}

impl Scene {
    /// Spatial dimension `d`.
    pub fn d(&self) -> usize {
        self.dimension.d()
    }

    /// Validates a raw spec. `base` resolves relative point-file paths;
    /// `default_name` is used when the scene has no `name`.
    pub fn try_from_spec(
        spec: SceneSpec,
        base: &Path,
        default_name: &str,
    ) -> Result<Scene, InputError> {
        let dimension = spec.model.dimension;
        let d = dimension.d();
        let thickness = thickness(&spec.model)?;
        let horizon_factor = spec.discretization.horizon_factor;
        check_horizon_factor("discretization.horizon_factor", horizon_factor)?;
        let materials = materials(&spec)?;
        let material_index = |field: &str, name: &str| {
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
        };

        let mut regions = Vec::new();
        let mut total_points = 0.0f64;
        for (k, r) in spec.regions.iter().enumerate() {
            let f = format!("regions[{k}]");
            let material = material_index(&format!("{f}.material"), &r.material)?;
            positive(&format!("{f}.spacing"), r.spacing)?;
            length_in_range(&format!("{f}.spacing"), "spacing", r.spacing)?;
            let bounds = aabb(&format!("{f}.box"), &r.bounds, d)?;
            for x in bounds.min[..d].iter().chain(&bounds.max[..d]) {
                length_in_range(&format!("{f}.box"), "coordinate", *x)?;
            }
            let mut count = 1.0f64;
            for a in 0..d {
                let cells = (bounds.max[a] - bounds.min[a]) / r.spacing;
                if cells < 0.5 {
                    return Err(InputError::new(
                        format!("{f}.box"),
                        format!("extent {} along axis {a} is smaller than one spacing ({}): the region would hold no point",
                            num(bounds.max[a] - bounds.min[a]), num(r.spacing)),
                    ));
                }
                count *= cells.round();
                if (cells - cells.round()).abs() > 1e-6 * cells.max(1.0) {
                    return Err(InputError::new(
                        format!("{f}.box"),
                        format!("extent {} along axis {a} is not a whole number of spacings ({} × {}); \
                                 adjust the box or the spacing", num(bounds.max[a] - bounds.min[a]), approx(cells), num(r.spacing)),
                    ));
                }
            }
            total_points += count;
            if total_points > MAX_POINTS as f64 {
                return Err(InputError::new(format!("{f}.spacing"), format!(
                    "the regions would hold {total_points:.3e} points; at most {MAX_POINTS} are supported \
                     (a direct solver needs far less than that to run out of memory): use a coarser spacing")));
            }
            let horizon = match (r.horizon, r.horizon_factor) {
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
            };
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
            regions.push(Region {
                material,
                spacing: r.spacing,
                bounds,
                horizon,
            });
        }
        if let Some(first) = regions.first() {
            // A horizon as wide as the body bonds every point to every other.
            let (mut lo, mut hi) = (first.bounds.min, first.bounds.max);
            for r in &regions {
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
        for i in 0..regions.len() {
            for j in 0..i {
                if overlap(&regions[i].bounds, &regions[j].bounds, d) {
                    return Err(InputError::new(
                        format!("regions[{i}].box"),
                        format!(
                            "overlaps regions[{j}].box; regions must not overlap (they may touch)"
                        ),
                    ));
                }
            }
        }

        let mut point_files = Vec::new();
        for (k, p) in spec.point_files.iter().enumerate() {
            let f = format!("point_files[{k}]");
            if p.path.trim().is_empty() {
                return Err(InputError::new(format!("{f}.path"), "empty path"));
            }
            let material = p
                .material
                .as_deref()
                .map(|m| material_index(&format!("{f}.material"), m))
                .transpose()?;
            let factor = p.horizon_factor.unwrap_or(horizon_factor);
            check_horizon_factor(&format!("{f}.horizon_factor"), factor)?;
            point_files.push(PointFile {
                path: base.join(&p.path),
                field: f,
                material,
                horizon_factor: factor,
            });
        }
        let mut meshes = Vec::new();
        for (k, m) in spec.meshes.iter().enumerate() {
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
                .map(|name| material_index(&format!("{f}.material"), name))
                .transpose()?;
            let groups = m
                .groups
                .iter()
                .map(|(group, name)| {
                    Ok((
                        group.clone(),
                        material_index(&format!("{f}.groups.{group}"), name)?,
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
            meshes.push(MeshFile {
                path: base.join(&m.path),
                field: f,
                material,
                groups,
                horizon_factor: factor,
            });
        }
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
            holes.push(Hole {
                center: coords(&format!("{f}.center"), &h.center, d)?,
                radius: h.radius,
            });
        }

        let mut cracks = Vec::new();
        for (k, c) in spec.cracks.iter().enumerate() {
            cracks.push(crack(&format!("cracks[{k}]"), c, d)?);
        }

        let mut boundaries = Vec::new();
        for (k, b) in spec.boundary.iter().enumerate() {
            let f = format!("boundary[{k}]");
            name(&format!("{f}.name"), &b.name)?;
            if spec.boundary[..k].iter().any(|o| o.name == b.name) {
                return Err(InputError::new(
                    format!("{f}.name"),
                    format!("\"{}\" is used twice", b.name),
                ));
            }
            let values = match (&b.displacement, &b.velocity) {
                (Some(c), None) => components(&format!("{f}.displacement"), c, d)?,
                (None, Some(c)) => components(&format!("{f}.velocity"), c, d)?,
                (Some(_), Some(_)) => {
                    return Err(InputError::new(
                        format!("{f}.velocity"),
                        "give either displacement or velocity, not both",
                    ))
                }
                (None, None) => {
                    return Err(InputError::new(
                        format!("{f}.displacement"),
                        "missing: give the prescribed displacement components \
                         (or, in explicit dynamics, velocity)",
                    ))
                }
            };
            let selection = match (&b.bounds, &b.group) {
                (Some(bounds), None) => Selection::Box(aabb(&format!("{f}.box"), bounds, d)?),
                (None, Some(group)) => {
                    mesh_group(&format!("{f}.group"), group, &meshes)?;
                    Selection::Group(group.clone())
                }
                (Some(_), Some(_)) => {
                    return Err(InputError::new(
                        format!("{f}.group"),
                        "give either box or group, not both",
                    ))
                }
                (None, None) => {
                    return Err(InputError::new(
                        format!("{f}.box"),
                        "missing: select the points with a box (or a mesh's physical group)",
                    ))
                }
            };
            boundaries.push(Prescribed {
                name: b.name.clone(),
                selection,
                values,
            });
        }

        let mut loads = Vec::new();
        for (k, l) in spec.loads.iter().enumerate() {
            loads.push(load(&format!("loads[{k}]"), l, d, &meshes)?);
        }

        let output = output(&spec.output, d)?;
        let dynamics = super::dynamics::validate(&spec, d)?;
        let (fracture, quasi_static) = fracture_runs(&spec, &materials, &boundaries, &loads, d)?;
        if let Some(dy) = &dynamics {
            let breaks = materials.iter().any(|m| m.fracture.is_some());
            if breaks && dy.method == DynamicsMethod::Relaxation {
                return Err(InputError::new(
                    "dynamics.method",
                    "dynamic relaxation finds a static answer and breaks no bond: remove the \
                     fracture parameters, or use [quasi_static] for fracture under load",
                ));
            }
            if breaks && dy.kernel == ForceKernel::Linearised {
                return Err(InputError::new(
                    "dynamics.kernel",
                    "bond breakage needs the nonlinear kernel (the assembled tangent is frozen)",
                ));
            }
            if spec.solver.refactor_iterations.is_some() {
                return Err(InputError::new(
                    "solver.refactor_iterations",
                    "applies to quasi-static fracture runs only",
                ));
            }
        } else if quasi_static.is_none() {
            for (key, present) in [
                ("output.every", output.every.is_some()),
                ("output.steps", !output.steps.is_empty()),
            ] {
                if present {
                    return Err(InputError::new(
                        key,
                        "applies to fracture and dynamics runs only (add a [quasi_static] \
                         or [dynamics] section)",
                    ));
                }
            }
            if spec.solver.refactor_iterations.is_some() {
                return Err(InputError::new(
                    "solver.refactor_iterations",
                    "applies to fracture runs only (add a [quasi_static] section)",
                ));
            }
        }
        if spec.solver.precision == Some(Precision::Mixed)
            && (quasi_static.is_some() || dynamics.is_some())
        {
            return Err(InputError::new(
                "solver.precision",
                "\"mixed\" applies to static solves (fracture runs update the factor exactly, \
                 which needs double precision; explicit runs factorise nothing)",
            ));
        }
        let solver = super::solver::validate(&spec.solver, spec.model.kind)?;
        let scene_name = match &spec.name {
            Some(n) => {
                name("name", n)?;
                n.clone()
            }
            None => sanitize(default_name),
        };

        let scene = Scene {
            name: scene_name,
            model: spec.model.kind,
            dimension,
            thickness,
            horizons: spec.model.horizons,
            volume_correction: spec.discretization.volume_correction,
            gradient_dilatation: spec.model.dilatation == Some(Dilatation::Gradient),
            isolated_points: spec.discretization.isolated_points,
            materials,
            regions,
            point_files,
            meshes,
            holes,
            cracks,
            boundaries,
            loads,
            solver,
            output,
            fracture,
            quasi_static,
            dynamics,
        };
        if scene.output.stress && scene.model != ModelKind::Shear {
            return Err(InputError::new(
                "output.stress",
                "stress recovery is defined for the shear model (model.kind = \"shear\")",
            ));
        }
        if spec.model.dilatation.is_some() && scene.model != ModelKind::Shear {
            return Err(InputError::new(
                "model.dilatation",
                "applies to the shear model only (model.kind = \"shear\")",
            ));
        }
        if scene.model == ModelKind::Shear && d == 1 {
            return Err(InputError::new(
                "model.kind",
                "the shear model is defined in 2D and 3D; use \"bond_based\" for a 1D bar",
            ));
        }
        if scene.model == ModelKind::BondBased {
            for (m, spec_m) in scene.materials.iter().zip(spec.materials.values()) {
                material::check_bond_based(
                    dimension,
                    m,
                    spec_m.poisson_ratio.is_some(),
                    spec.model.allow_any_poisson,
                )
                .map_err(|msg| {
                    InputError::new(format!("materials.{}.poisson_ratio", m.name), msg)
                })?;
            }
        }
        Ok(scene)
    }
}

fn thickness(m: &ModelSpec) -> Result<f64, InputError> {
    match (m.dimension, m.thickness, m.area) {
        (Dimension::One, None, a) => a.map_or(Ok(1.0), |a| positive("model.area", a).map(|_| a)),
        (Dimension::One, Some(_), _) => Err(InputError::new(
            "model.thickness",
            "a 1D bar has an area, not a thickness; use model.area",
        )),
        (Dimension::PlaneStress | Dimension::PlaneStrain, t, None) => {
            t.map_or(Ok(1.0), |t| positive("model.thickness", t).map(|_| t))
        }
        (Dimension::PlaneStress | Dimension::PlaneStrain, _, Some(_)) => Err(InputError::new(
            "model.area",
            "2D uses model.thickness, not an area",
        )),
        (Dimension::Three, None, None) => Ok(1.0),
        (Dimension::Three, _, _) => Err(InputError::new(
            "model.thickness",
            "3D takes neither a thickness nor an area",
        )),
    }
}

fn materials(spec: &SceneSpec) -> Result<Vec<Material>, InputError> {
    if spec.materials.is_empty() {
        return Err(InputError::new(
            "materials",
            "no material defined: add [materials.NAME] with youngs_modulus",
        ));
    }
    let implied = material::bond_based_poisson_ratio(spec.model.dimension);
    spec.materials
        .iter()
        .map(|(name, m)| {
            let f = format!("materials.{name}");
            // The name goes into points.csv and messages: no comma, quote or newline.
            self::name(&f, name)?;
            positive(&format!("{f}.youngs_modulus"), m.youngs_modulus)?;
            if let Some(nu) = m.poisson_ratio {
                let plane_stress = spec.model.dimension == Dimension::PlaneStress;
                if !nu.is_finite() || nu <= -1.0 || nu > 0.5 || (nu == 0.5 && !plane_stress) {
                    let range = if plane_stress {
                        "(-1, 0.5]"
                    } else {
                        "(-1, 0.5)"
                    };
                    return Err(InputError::new(
                        format!("{f}.poisson_ratio"),
                        format!(
                            "{} is outside {range}, the range of a stable isotropic material here",
                            num(nu)
                        ),
                    ));
                }
            } else if spec.model.kind == ModelKind::Shear {
                return Err(InputError::new(
                    format!("{f}.poisson_ratio"),
                    "the shear model needs a Poisson ratio for every material",
                ));
            }
            Ok(Material {
                name: name.clone(),
                youngs_modulus: m.youngs_modulus,
                poisson_ratio: m.poisson_ratio.unwrap_or(implied),
                fracture: fracture_parameter(&f, m, spec)?,
                density: m.density,
            })
        })
        .collect()
}

/// The fracture parameter of a material: at most one, positive, matching the
/// model, and only in a run that breaks bonds.
fn fracture_parameter(
    field: &str,
    m: &MaterialSpec,
    spec: &SceneSpec,
) -> Result<Option<FractureParameter>, InputError> {
    let given: Vec<(&str, f64)> = [
        ("fracture_energy", m.fracture_energy),
        ("critical_stretch", m.critical_stretch),
        ("critical_deviatoric_strain", m.critical_deviatoric_strain),
    ]
    .into_iter()
    .filter_map(|(k, v)| v.map(|v| (k, v)))
    .collect();
    let Some(&(key, value)) = given.first() else {
        return Ok(None);
    };
    let f = format!("{field}.{key}");
    if given.len() > 1 {
        return Err(InputError::new(
            format!("{field}.{}", given[1].0),
            format!(
                "give one fracture parameter per material, not both {key} and {}",
                given[1].0
            ),
        ));
    }
    if spec.quasi_static.is_none() && spec.dynamics.is_none() {
        return Err(InputError::new(
            f,
            "fracture parameters apply to runs that break bonds: add a [quasi_static] or \
             [dynamics] section, or remove the parameter for a static solve",
        ));
    }
    positive(&f, value)?;
    let parameter = match (key, spec.model.kind) {
        ("fracture_energy", _) => FractureParameter::Energy(value),
        ("critical_stretch", ModelKind::BondBased) => FractureParameter::CriticalStretch(value),
        ("critical_deviatoric_strain", ModelKind::Shear) => {
            FractureParameter::CriticalDeviatoricStrain(value)
        }
        ("critical_stretch", _) => {
            return Err(InputError::new(
                f,
                "the shear model breaks bonds on their deviatoric strain: give \
                 critical_deviatoric_strain or fracture_energy",
            ))
        }
        _ => {
            return Err(InputError::new(
                f,
                "the bond-based model breaks bonds on their stretch: give critical_stretch \
                 or fracture_energy",
            ))
        }
    };
    Ok(Some(parameter))
}

/// The `[fracture]` and `[quasi_static]` sections.
fn fracture_runs(
    spec: &SceneSpec,
    materials: &[Material],
    boundaries: &[Prescribed],
    loads: &[Load],
    d: usize,
) -> Result<(FractureSettings, Option<QuasiStatic>), InputError> {
    let mut fracture = FractureSettings::default();
    if let Some(f) = &spec.fracture {
        fracture.shear_energy = f.shear_energy;
        fracture.calibration = f.calibration;
        fracture.shear_criterion = f.shear_criterion;
        for (k, b) in f.no_fail.iter().enumerate() {
            fracture
                .no_fail
                .push(aabb(&format!("fracture.no_fail[{k}].box"), &b.bounds, d)?);
        }
    }
    let Some(q) = &spec.quasi_static else {
        if spec.fracture.is_some() && !materials.iter().any(|m| m.fracture.is_some()) {
            return Err(InputError::new(
                "fracture",
                "bond breakage settings need a run that breaks bonds: add a [quasi_static] \
                 or [dynamics] section and a fracture parameter",
            ));
        }
        return Ok((fracture, None));
    };
    if !materials.iter().any(|m| m.fracture.is_some()) {
        return Err(InputError::new(
            "quasi_static",
            "no material has a fracture parameter, so no bond could break: give \
             fracture_energy (or the critical value) for at least one material",
        ));
    }
    let loaded = boundaries
        .iter()
        .any(|b| b.values.iter().flatten().any(|&v| v != 0.0))
        || loads.iter().any(|l| l.value.iter().any(|&v| v != 0.0));
    if !loaded {
        return Err(InputError::new(
            "quasi_static",
            "every prescribed displacement and load is zero: scaling them by a load factor \
             does nothing; prescribe a non-zero displacement (or load)",
        ));
    }
    positive("quasi_static.max_load_factor", q.max_load_factor)?;
    let stepped = q.strategy != Strategy::Event;
    let only = |key: &str, present: bool, applies: bool, to: &str| {
        if present && !applies {
            Err(InputError::new(
                format!("quasi_static.{key}"),
                format!(
                    "applies to strategy {to} only (strategy is {:?})",
                    q.strategy
                ),
            ))
        } else {
            Ok(())
        }
    };
    let stepped_names = "\"all\" or \"most_critical\"";
    only("steps", q.steps.is_some(), stepped, stepped_names)?;
    only(
        "max_broken_per_step",
        q.max_broken_per_step.is_some(),
        stepped,
        stepped_names,
    )?;
    only(
        "min_step_fraction",
        q.min_step_fraction.is_some(),
        stepped,
        stepped_names,
    )?;
    only(
        "max_resolves",
        q.max_resolves.is_some(),
        stepped,
        stepped_names,
    )?;
    only("max_events", q.max_events.is_some(), !stepped, "\"event\"")?;
    only(
        "tolerance",
        q.tolerance.is_some(),
        q.strategy != Strategy::All,
        "\"event\" or \"most_critical\"",
    )?;
    let count = |key: &str, v: Option<usize>, default: usize, max: usize| match v {
        Some(n) if n == 0 || n > max => Err(InputError::new(
            format!("quasi_static.{key}"),
            format!("{n} is outside 1..={max}"),
        )),
        Some(n) => Ok(n),
        None => Ok(default),
    };
    let steps = count("steps", q.steps, 100, 10_000_000)?;
    let max_resolves = count("max_resolves", q.max_resolves, 10_000, 100_000_000)?;
    let max_events = count("max_events", q.max_events, 1_000_000, 1_000_000_000)?;
    if let Some(n) = q.max_broken_per_step {
        count("max_broken_per_step", Some(n), n, usize::MAX)?;
    }
    let min_step_fraction = q.min_step_fraction.unwrap_or(1.0 / 1024.0);
    // The smallest step, min_step_fraction × max_load_factor / steps, must still
    // change λ in double precision (an ulp of λ ≤ max_load_factor is 2.2e-16 of
    // it): at least MIN_STEP_RELATIVE of max_load_factor, with room to spare.
    let lowest = MIN_STEP_RELATIVE * steps as f64;
    if !(min_step_fraction >= lowest && min_step_fraction <= 1.0) {
        return Err(InputError::new(
            "quasi_static.min_step_fraction",
            format!(
                "{} is outside [{lowest:e}, 1]: the smallest step \
                 (min_step_fraction × max_load_factor / steps) must be at least \
                 {MIN_STEP_RELATIVE:e} of max_load_factor, or it no longer changes the load \
                 factor in double precision and the run never ends",
                num(min_step_fraction)
            ),
        ));
    }
    if let Some(f) = q.stop_after_peak {
        if !(f > 0.0 && f < 1.0) {
            return Err(InputError::new(
                "quasi_static.stop_after_peak",
                format!("{} is outside (0, 1): give the fraction of the peak reaction below which the run ends", num(f)),
            ));
        }
    }
    let tolerance = q.tolerance.unwrap_or(1e-6);
    if !(0.0..1.0).contains(&tolerance) {
        return Err(InputError::new(
            "quasi_static.tolerance",
            format!("{} is outside [0, 1)", num(tolerance)),
        ));
    }
    Ok((
        fracture,
        Some(QuasiStatic {
            strategy: q.strategy,
            max_load_factor: q.max_load_factor,
            steps,
            max_broken_per_step: q.max_broken_per_step,
            min_step_fraction,
            tolerance,
            max_resolves,
            max_events,
            stop_after_peak: q.stop_after_peak,
        }),
    ))
}

/// Largest horizon, in spacings, a scene may give (factor or radius).
pub const MAX_HORIZON_FACTOR: f64 = 20.0;

/// Smallest spacing of a body (m): bond lengths are computed from squared
/// coordinate differences, which stay normal doubles (above 2.2e-308) down to
/// about 1.5e-154 m; the margin covers the sums of three squares.
pub const MIN_LENGTH: f64 = 1e-150;

/// Largest spacing and coordinate magnitude of a body (m): squared lengths
/// stay finite (below 1.8e308) up to about 1.3e154 m.
pub const MAX_LENGTH: f64 = 1e150;

/// Refuses a point whose bond stiffness `C(δ) V² / Δx` is not a normal
/// floating-point number, naming `materials.NAME.youngs_modulus` when the
/// modulus is to blame (the same bond with E = 1 Pa is in range) and
/// `spacing_field` otherwise; `source` names the region, point-file line or
/// mesh element.
#[allow(clippy::too_many_arguments)]
pub fn bond_stiffness_in_range(
    source: &str,
    spacing_field: &str,
    dimension: Dimension,
    material: &Material,
    spacing: f64,
    horizon: f64,
    volume: f64,
    thickness: f64,
) -> Result<(), InputError> {
    let stiffness =
        |m: &Material| m.micromodulus(dimension, horizon, thickness) * volume * volume / spacing;
    let k = stiffness(material);
    if k.is_normal() {
        return Ok(());
    }
    let unit = Material {
        youngs_modulus: 1.0,
        ..material.clone()
    };
    let field = if stiffness(&unit).is_normal() {
        format!("materials.{}.youngs_modulus", material.name)
    } else {
        spacing_field.to_string()
    };
    Err(InputError::new(
        field,
        format!(
            "with E = {} Pa, the spacing {} m and the horizon {} m of {source}, a bond's \
             stiffness C V²/Δx would be {k:.3e}: outside the floating-point range; rescale \
             the units (e.g. MPa and mm)",
            num(material.youngs_modulus),
            num(spacing),
            num(horizon)
        ),
    ))
}

/// Refuses a spacing outside [[`MIN_LENGTH`], [`MAX_LENGTH`]] or a coordinate
/// beyond ±[`MAX_LENGTH`]: `what` is "spacing" or "coordinate".
pub fn length_in_range(field: &str, what: &str, v: f64) -> Result<(), InputError> {
    let spacing = what == "spacing";
    if (spacing && v.abs() < MIN_LENGTH) || v.abs() > MAX_LENGTH {
        return Err(InputError::new(
            field,
            format!(
                "{what} {v:?} m is outside [{}, {MAX_LENGTH:e}] m, the range in which squared \
                 lengths (bond lengths, neighbour distances) are normal double-precision \
                 numbers; rescale the units (e.g. µm or km instead of m)",
                if spacing {
                    format!("{MIN_LENGTH:e}")
                } else {
                    format!("{:e}", -MAX_LENGTH)
                }
            ),
        ));
    }
    Ok(())
}

pub(super) fn positive(field: &str, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(InputError::new(
            field,
            format!("{} is not a finite positive number", num(v)),
        ))
    }
}

fn check_horizon_factor(field: &str, m: f64) -> Result<(), InputError> {
    if !m.is_finite() || m <= 1.0 {
        return Err(InputError::new(field, format!(
            "{} would make the horizon no larger than the spacing (no neighbours); use a value above 1, typically 3.015", num(m))));
    }
    if m > MAX_HORIZON_FACTOR {
        return Err(InputError::new(
            field,
            format!("{} is implausibly large (above {MAX_HORIZON_FACTOR} spacings); typical values are 2 to 5", num(m)),
        ));
    }
    Ok(())
}

/// A file-name-safe version of a default scene name.
fn sanitize(n: &str) -> String {
    let s: String = n
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        "scene".into()
    } else {
        s
    }
}

fn name(field: &str, n: &str) -> Result<(), InputError> {
    if n.is_empty()
        || !n
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return Err(InputError::new(
            field,
            format!("\"{n}\" must be non-empty and use only letters, digits, '_' and '-'"),
        ));
    }
    Ok(())
}

/// Pads a coordinate list of length `d` to 3D with zeros.
fn coords(field: &str, v: &[f64], d: usize) -> Result<[f64; 3], InputError> {
    if v.len() != d {
        return Err(InputError::new(
            field,
            format!("has {} coordinate(s); this {d}D scene needs {d}", v.len()),
        ));
    }
    if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
        return Err(InputError::new(
            field,
            format!("{} is not a finite number", num(*bad)),
        ));
    }
    let mut x = [0.0; 3];
    x[..d].copy_from_slice(v);
    Ok(x)
}

pub(super) fn aabb(field: &str, b: &BoxSpec, d: usize) -> Result<Aabb, InputError> {
    let min = coords(&format!("{field}.min"), &b.min, d)?;
    let max = coords(&format!("{field}.max"), &b.max, d)?;
    let mut bounds = Aabb {
        min: [f64::NEG_INFINITY; 3],
        max: [f64::INFINITY; 3],
    };
    for a in 0..d {
        if max[a] < min[a] {
            return Err(InputError::new(
                field,
                format!(
                    "max[{a}] = {} is below min[{a}] = {}",
                    num(max[a]),
                    num(min[a])
                ),
            ));
        }
        bounds.min[a] = min[a];
        bounds.max[a] = max[a];
    }
    Ok(bounds)
}

fn overlap(a: &Aabb, b: &Aabb, d: usize) -> bool {
    (0..d).all(|k| {
        let lo = a.min[k].max(b.min[k]);
        let hi = a.max[k].min(b.max[k]);
        hi - lo > 1e-9 * (a.max[k] - a.min[k]).max(b.max[k] - b.min[k])
    })
}

pub(super) fn components(
    field: &str,
    c: &ComponentsSpec,
    d: usize,
) -> Result<[Option<f64>; 3], InputError> {
    let values = [c.x, c.y, c.z];
    for (a, axis) in ["x", "y", "z"].iter().enumerate() {
        match values[a] {
            Some(_) if a >= d => {
                return Err(InputError::new(
                    format!("{field}.{axis}"),
                    format!("a {d}D scene has no {axis} component"),
                ))
            }
            Some(v) if !v.is_finite() => {
                return Err(InputError::new(
                    format!("{field}.{axis}"),
                    format!("{} is not finite", num(v)),
                ))
            }
            _ => {}
        }
    }
    if values.iter().all(Option::is_none) {
        return Err(InputError::new(
            field,
            "prescribes no component; give at least one of x, y, z",
        ));
    }
    Ok(values)
}

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
            let n = crate::vector::cross(&edge1, &edge2);
            if crate::vector::norm(&n) == 0.0 {
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

/// Checks that `group` names a physical group a mesh can provide: with no mesh
/// in the scene it cannot (the name itself is checked when the meshes are read).
fn mesh_group(field: &str, group: &str, meshes: &[MeshFile]) -> Result<(), InputError> {
    if meshes.is_empty() {
        return Err(InputError::new(
            field,
            format!("\"{group}\": physical groups come from [[meshes]], and the scene has none; select with `box`"),
        ));
    }
    if group.is_empty() {
        return Err(InputError::new(field, "empty group name"));
    }
    Ok(())
}

fn load(field: &str, l: &LoadSpec, d: usize, meshes: &[MeshFile]) -> Result<Load, InputError> {
    name(&format!("{field}.name"), &l.name)?;
    let v = coords(&format!("{field}.value"), &l.value, d)?;
    let selection = match (&l.bounds, &l.group) {
        (Some(b), None) => Some(Selection::Box(aabb(&format!("{field}.box"), b, d)?)),
        (None, Some(group)) => {
            mesh_group(&format!("{field}.group"), group, meshes)?;
            Some(Selection::Group(group.clone()))
        }
        (Some(_), Some(_)) => {
            return Err(InputError::new(
                format!("{field}.group"),
                "give either box or group, not both",
            ))
        }
        (None, None) => None,
    };
    let target = match (l.kind, l.face.as_deref()) {
        (LoadKind::Traction, None) if l.group.is_some() => LoadTarget::Facets,
        (LoadKind::Traction, Some(_)) if l.group.is_some() => {
            return Err(InputError::new(
                format!("{field}.face"),
                "a traction on a group acts on the group's boundary facets: remove `face`",
            ))
        }
        (LoadKind::Traction, Some(face)) => {
            let axes = ["x", "y", "z"];
            let parsed = face
                .strip_prefix('+')
                .map(|a| (a, 1.0))
                .or_else(|| face.strip_prefix('-').map(|a| (a, -1.0)));
            match parsed
                .and_then(|(a, s)| axes[..d].iter().position(|x| *x == a).map(|axis| (axis, s)))
            {
                Some((axis, sign)) => LoadTarget::Face { axis, sign },
                None => {
                    let valid: Vec<String> = axes[..d]
                        .iter()
                        .flat_map(|a| [format!("-{a}"), format!("+{a}")])
                        .collect();
                    return Err(InputError::new(
                        format!("{field}.face"),
                        format!("\"{face}\" is not one of {}", valid.join(", ")),
                    ));
                }
            }
        }
        (LoadKind::Traction, None) => return Err(InputError::new(
            format!("{field}.face"),
            "a traction needs a face (one of -x, +x, -y, +y, -z, +z) or a mesh's boundary group",
        )),
        (LoadKind::BodyForce, None) => LoadTarget::Volume,
        (LoadKind::BodyForce, Some(_)) => {
            return Err(InputError::new(
                format!("{field}.face"),
                "a body force acts on a volume; remove `face` (use `box` to restrict it)",
            ))
        }
    };
    Ok(Load {
        name: l.name.clone(),
        target,
        selection,
        value: v,
    })
}

fn output(o: &OutputSpec, d: usize) -> Result<OutputSettings, InputError> {
    let mut profiles = Vec::new();
    for (k, p) in o.profiles.iter().enumerate() {
        let f = format!("output.profiles[{k}]");
        name(&format!("{f}.name"), &p.name)?;
        if o.profiles[..k].iter().any(|q| q.name == p.name) {
            return Err(InputError::new(
                format!("{f}.name"),
                format!("\"{}\" is used twice", p.name),
            ));
        }
        let (from, to) = (
            coords(&format!("{f}.from"), &p.from, d)?,
            coords(&format!("{f}.to"), &p.to, d)?,
        );
        if from == to {
            return Err(InputError::new(f, "from and to coincide"));
        }
        profiles.push(Profile {
            name: p.name.clone(),
            from,
            to,
        });
    }
    let mut probes = Vec::new();
    for (k, p) in o.probes.iter().enumerate() {
        let f = format!("output.probes[{k}]");
        name(&format!("{f}.name"), &p.name)?;
        if o.probes[..k].iter().any(|q| q.name == p.name) {
            return Err(InputError::new(
                format!("{f}.name"),
                format!(
                    "\"{}\" is used twice (each probe is a column of probes.csv)",
                    p.name
                ),
            ));
        }
        probes.push(Probe {
            name: p.name.clone(),
            at: coords(&format!("{f}.at"), &p.at, d)?,
        });
    }
    if o.every == Some(0) {
        return Err(InputError::new(
            "output.every",
            "0 steps; give a positive number of steps",
        ));
    }
    Ok(OutputSettings {
        every: o.every,
        steps: o.steps.clone(),
        vtu: o.vtu,
        points_csv: o.points_csv,
        stress: o.stress,
        matrix_market: o.matrix_market,
        profiles,
        probes,
    })
}
