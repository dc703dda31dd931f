//! The scene file as written by the user (TOML or JSON), deserialised with serde.
//!
//! Every section rejects unknown keys. Defaults are documented on each field;
//! [`crate::scene::Scene::try_from_spec`] validates these raw values into a typed scene.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Root of a scene file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// Free-text name used in reports (default: the file stem).
    pub name: Option<String>,
    /// Model and dimension (required).
    pub model: ModelSpec,
    /// Horizon and bond settings.
    #[serde(default)]
    pub discretization: DiscretizationSpec,
    /// Named materials (at least one).
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialSpec>,
    /// Regular grids filling boxes, each with its own spacing and material.
    #[serde(default)]
    pub regions: Vec<RegionSpec>,
    /// Point clouds read from text files.
    #[serde(default)]
    pub point_files: Vec<PointFileSpec>,
    /// Gmsh meshes (MSH 4.1): one point per element.
    #[serde(default)]
    pub meshes: Vec<MeshSpec>,
    /// Circular (2D) or spherical (3D) holes: points inside are removed.
    #[serde(default)]
    pub holes: Vec<HoleSpec>,
    /// Pre-cracks that no bond may cross.
    #[serde(default)]
    pub cracks: Vec<CrackSpec>,
    /// Prescribed displacements on point sets.
    #[serde(default)]
    pub boundary: Vec<BoundarySpec>,
    /// Tractions and body forces.
    #[serde(default)]
    pub loads: Vec<LoadSpec>,
    /// Linear solver choice.
    #[serde(default)]
    pub solver: SolverSpec,
    /// What to write.
    #[serde(default)]
    pub output: OutputSpec,
    /// Bond breakage settings shared by every driver that breaks bonds.
    pub fracture: Option<FractureSpec>,
    /// Quasi-static load stepping with bond breakage (its presence selects the
    /// quasi-static driver).
    pub quasi_static: Option<QuasiStaticSpec>,
    /// Explicit dynamics or dynamic relaxation (its presence selects the
    /// explicit driver).
    pub dynamics: Option<DynamicsSpec>,
    /// Explicit dynamics: initial displacement and velocity, per box or as a
    /// Gaussian pulse; later entries add to earlier ones.
    #[serde(default)]
    pub initial_conditions: Vec<InitialConditionSpec>,
}

/// `[model]`
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// `"bond_based"` (default) or `"shear"`.
    #[serde(default)]
    pub kind: ModelKind,
    /// `"1d"`, `"plane_stress"`, `"plane_strain"` or `"3d"` (required).
    pub dimension: Dimension,
    /// 2D only: out-of-plane thickness in m (default 1).
    pub thickness: Option<f64>,
    /// 1D only: cross-section area in m² (default 1).
    pub area: Option<f64>,
    /// `"dual"` (default): every point keeps its own horizon (DH-PD);
    /// `"constant"`: every point takes the largest horizon of the body (baseline);
    /// `"traditional"` (explicit dynamics, bond-based): every point keeps its own
    /// horizon but feels only the bonds in it, with twice their force (the
    /// variable-horizon PD with ghost forces the papers compare against).
    #[serde(default)]
    pub horizons: HorizonMode,
    /// Shear model only: `"weighted"` (001 Eq. 15, default) or `"gradient"`
    /// (θ from the shape-tensor gradient, exact for homogeneous deformation at
    /// free surfaces too; it does not remove the stiffening of the force along
    /// a free surface: validation/bimaterial_bar/README.md).
    pub dilatation: Option<Dilatation>,
    /// Shear model only: `"energy"` (default: the force derived from a strain
    /// energy, equal to the paper's where the family is full, symmetric
    /// tangent) or `"paper"` (001 Eq. 27-28 as published).
    pub formulation: Option<ShearFormulation>,
    /// Bond-based only: accept a Poisson ratio the model cannot represent
    /// (the micromodulus then matches the bulk modulus). Default false.
    #[serde(default)]
    pub allow_any_poisson: bool,
}

/// Peridynamic model.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// Bond-based DH-PD (formulation Sec. 3).
    #[default]
    BondBased,
    /// Shear-deformation DH-PD of Ren, Zhuang & Rabczuk (formulation Sec. 4): any ν, 2D or 3D.
    Shear,
}

/// Which force law the shear model uses (`src/model/shear.rs`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ShearFormulation {
    /// Derived from a strain energy: Hooke's law of the family's displacement
    /// gradient plus the paper's penalty on the non-affine part. Default.
    #[default]
    Energy,
    /// 001 Eq. 27-28 as published (not symmetric).
    Paper,
}

/// How the shear model computes an owner's dilatation θ.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Dilatation {
    /// `θ = (d/m) Σ w η_r·ξ_r` (001 Eq. 15).
    #[default]
    Weighted,
    /// `θ = Σ w η_r·(R K⁻¹ ξ)`: exact θ at free surfaces.
    Gradient,
}

/// Spatial setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum Dimension {
    /// Bar, per cross-section area.
    #[serde(rename = "1d")]
    One,
    /// 2D plane stress, with a thickness.
    #[serde(rename = "plane_stress")]
    PlaneStress,
    /// 2D plane strain, with a thickness.
    #[serde(rename = "plane_strain")]
    PlaneStrain,
    /// Three dimensions.
    #[serde(rename = "3d")]
    Three,
}

impl Dimension {
    /// Number of spatial dimensions `d`.
    pub fn d(self) -> usize {
        match self {
            Dimension::One => 1,
            Dimension::PlaneStress | Dimension::PlaneStrain => 2,
            Dimension::Three => 3,
        }
    }
}

/// How horizons are assigned.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HorizonMode {
    /// Each point keeps its own horizon (dual-horizon PD).
    #[default]
    Dual,
    /// Every point takes the largest horizon in the body (constant-horizon baseline).
    Constant,
    /// Each point keeps its own horizon and feels only the bonds in it, each with
    /// twice its dual-horizon force: no reaction from the points whose horizons
    /// hold it (traditional variable-horizon PD, with ghost forces). Explicit
    /// dynamics with the bond-based model only.
    Traditional,
}

/// What to do with points left without any bond.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IsolatedPolicy {
    /// Stop with an error naming the first such point (default).
    #[default]
    Error,
    /// Remove them and print a warning.
    Remove,
}

/// Partial-volume (horizon rim) rule, formulation Sec. 6.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VolumeCorrection {
    /// Exact overlap of the horizon (radius δ_i) with the neighbour's equivalent
    /// segment, disc or ball (000 Eq. A.2/A.3); bonds reach to `δ_i + r_j`. Default.
    #[default]
    Overlap,
    /// 000 Eq. A.1 as printed: ramp from 1 at `δ_i − Δ_j/2` to 1/2 at `δ_i`, no bond beyond `δ_i`.
    Ramp,
    /// Full volume for every neighbour within `δ_i`.
    None,
}

/// Surface correction of the bond-based model (`src/model/surface.rs`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceCorrection {
    /// Each owner's bonds scaled so that its stiffness tensor under homogeneous
    /// strain equals that of a full family, and bonds into grips see a clamp
    /// on the grip's face. Default.
    #[default]
    Energy,
    /// No correction: the bonds of a family cut by a surface keep their stiffness.
    None,
}

/// `[discretization]`
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DiscretizationSpec {
    /// Horizon as a multiple of the local spacing (default 3.015).
    #[serde(default = "default_horizon_factor")]
    pub horizon_factor: f64,
    /// Partial-volume rule near the horizon's rim: `"overlap"` (default),
    /// `"ramp"` (000 Eq. A.1 as printed) or `"none"`.
    #[serde(default)]
    pub volume_correction: VolumeCorrection,
    /// `"error"` (default) or `"remove"`.
    #[serde(default)]
    pub isolated_points: IsolatedPolicy,
    /// Bond-based model: `"energy"` (default) or `"none"`.
    pub surface_correction: Option<SurfaceCorrection>,
}

impl Default for DiscretizationSpec {
    fn default() -> Self {
        Self {
            horizon_factor: default_horizon_factor(),
            volume_correction: VolumeCorrection::Overlap,
            isolated_points: IsolatedPolicy::Error,
            surface_correction: None,
        }
    }
}

fn default_horizon_factor() -> f64 {
    3.015
}

fn default_true() -> bool {
    true
}

/// `[materials.NAME]`
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Young's modulus E in Pa (required, > 0).
    pub youngs_modulus: f64,
    /// Poisson ratio ν. Bond-based: defaults to the value the model implies
    /// (1/3 plane stress, 1/4 otherwise; none in 1D).
    pub poisson_ratio: Option<f64>,
    /// Fracture energy G₀ in J/m² (fracture runs only); the critical value of
    /// each bond follows from it and the owner's horizon.
    pub fracture_energy: Option<f64>,
    /// Bond-based: critical stretch s₀, instead of `fracture_energy`.
    pub critical_stretch: Option<f64>,
    /// Shear model: critical deviatoric bond strain ε^d_max, instead of `fracture_energy`.
    pub critical_deviatoric_strain: Option<f64>,
    /// Mass density ρ in kg/m³ (explicit dynamics only; required there).
    pub density: Option<f64>,
}

/// An axis-aligned box; 1D, 2D or 3D coordinates.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// Lower corner.
    pub min: Vec<f64>,
    /// Upper corner.
    pub max: Vec<f64>,
}

/// `[[regions]]`: a box filled with a regular grid.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// Name of a material in `[materials]`.
    pub material: String,
    /// Grid spacing in m; every box edge must be a whole number of spacings.
    pub spacing: f64,
    /// The box to fill (points at cell centres).
    #[serde(rename = "box")]
    pub bounds: BoxSpec,
    /// Explicit horizon radius in m (overrides the factor).
    pub horizon: Option<f64>,
    /// Horizon factor for this region (default: `discretization.horizon_factor`).
    pub horizon_factor: Option<f64>,
}

/// `[[point_files]]`: rows `x y [z] volume [horizon] [material]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PointFileSpec {
    /// Path, relative to the scene file.
    pub path: String,
    /// Material for rows without a material column.
    pub material: Option<String>,
    /// Horizon factor for rows without a horizon column, times the point's
    /// equivalent spacing (volume^(1/d)); default `discretization.horizon_factor`.
    pub horizon_factor: Option<f64>,
}

/// `[[meshes]]`: a Gmsh MSH 4.1 file (ASCII or binary); every element of the
/// scene's dimension becomes a point at its centroid with its area × thickness
/// (2D) or volume (3D).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// Path, relative to the scene file.
    pub path: String,
    /// Material of the cells in no group of `groups`.
    pub material: Option<String>,
    /// Physical group (of the scene's dimension) → material, for its cells.
    #[serde(default)]
    pub groups: BTreeMap<String, String>,
    /// Horizon factor times the cell's equivalent spacing (measure^(1/d));
    /// default `discretization.horizon_factor`.
    pub horizon_factor: Option<f64>,
}

/// `[[holes]]`
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HoleSpec {
    /// Centre.
    pub center: Vec<f64>,
    /// Radius in m (> 0).
    pub radius: f64,
    /// 3D only: the direction of a through hole (a cylinder of `radius` about
    /// the line through `center`); left out, a 3D hole is a sphere.
    pub axis: Option<Vec<f64>>,
}

/// `[[cracks]]`: a segment `from`-`to` (2D) or a parallelogram
/// `origin`, `origin + edge1`, `origin + edge2` (3D).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CrackSpec {
    /// 2D: start of the segment.
    pub from: Option<Vec<f64>>,
    /// 2D: end of the segment.
    pub to: Option<Vec<f64>>,
    /// 3D: a corner of the crack face.
    pub origin: Option<Vec<f64>>,
    /// 3D: first edge vector.
    pub edge1: Option<Vec<f64>>,
    /// 3D: second edge vector.
    pub edge2: Option<Vec<f64>>,
}

/// Per-component values; an omitted component is free.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ComponentsSpec {
    /// x component.
    pub x: Option<f64>,
    /// y component.
    pub y: Option<f64>,
    /// z component.
    pub z: Option<f64>,
}

/// `[[boundary]]`: prescribed displacement (or, in explicit dynamics,
/// velocity) on the points inside a box.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    /// Name used for the reaction force in the summary.
    pub name: String,
    /// Points inside this box (inclusive) are constrained (this or `group`).
    #[serde(rename = "box")]
    pub bounds: Option<BoxSpec>,
    /// The points of a mesh's physical group (this or `box`).
    pub group: Option<String>,
    /// Prescribed components in m (this or `velocity`).
    pub displacement: Option<ComponentsSpec>,
    /// Explicit dynamics: prescribed velocity components in m/s (this or `displacement`).
    pub velocity: Option<ComponentsSpec>,
    /// Explicit dynamics: the prescribed values are multiplied by this function
    /// of time (default constant 1).
    pub time_function: Option<TimeFunctionSpec>,
}

/// A function of time `g(t)` that scales a prescribed value or a load.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TimeFunctionSpec {
    /// `"constant"` (g = 1), `"ramp"` (g = t/duration, then 1) or `"table"`
    /// (piecewise linear through `times`/`values`, constant outside).
    pub kind: TimeFunctionKind,
    /// `ramp`: time to reach 1, in s.
    pub duration: Option<f64>,
    /// `table`: increasing times in s.
    pub times: Option<Vec<f64>>,
    /// `table`: values at `times`.
    pub values: Option<Vec<f64>>,
}

/// Kind of time function.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TimeFunctionKind {
    /// `g(t) = 1`.
    Constant,
    /// `g(t) = min(t / duration, 1)`.
    Ramp,
    /// Piecewise linear.
    Table,
}

/// `[[initial_conditions]]`: initial displacement and velocity (explicit dynamics).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InitialConditionSpec {
    /// Points inside this box (default: the whole body).
    #[serde(rename = "box")]
    pub bounds: Option<BoxSpec>,
    /// Initial displacement components in m.
    pub displacement: Option<ComponentsSpec>,
    /// Initial velocity components in m/s.
    pub velocity: Option<ComponentsSpec>,
    /// A Gaussian displacement pulse.
    pub gaussian: Option<GaussianSpec>,
}

/// `u(x, 0) = amplitude · exp(−|x − center|² / width²)`, with the distance over
/// the axes listed in `center` (give fewer components for a plane pulse: `[0.5]`
/// in 2D is a pulse across x only).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GaussianSpec {
    /// Centre (1 to d components: the axes the distance is measured along).
    pub center: Vec<f64>,
    /// Width in m (> 0).
    pub width: f64,
    /// Displacement vector at the centre, one entry per dimension.
    pub amplitude: Vec<f64>,
}

/// Explicit time integrator.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DynamicsMethod {
    /// Velocity Verlet (default).
    #[default]
    Verlet,
    /// Adaptive dynamic relaxation (Kilic & Madenci 2010) for the static answer.
    Relaxation,
}

/// Which forces the explicit driver integrates.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ForceKernel {
    /// The bond kernels with the current bond direction / polar rotation (default).
    #[default]
    Nonlinear,
    /// `F = −K u` with the assembled tangent of the implicit solver.
    Linearised,
}

/// `[dynamics]`: explicit dynamics (its presence selects the explicit driver).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsSpec {
    /// `"verlet"` (default) or `"relaxation"`.
    #[serde(default)]
    pub method: DynamicsMethod,
    /// `"nonlinear"` (default) or `"linearised"`.
    #[serde(default)]
    pub kernel: ForceKernel,
    /// Number of steps (this or `end_time`; relaxation: the largest number of steps).
    pub steps: Option<usize>,
    /// Verlet: simulated time in s (this or `steps`).
    pub end_time: Option<f64>,
    /// Verlet: time step in s (default: `safety_factor` × the stable step).
    pub time_step: Option<f64>,
    /// Verlet: fraction of the stable time step (default 0.8).
    pub safety_factor: Option<f64>,
    /// Verlet: accept a `time_step` above the stable one (default false).
    #[serde(default)]
    pub force_time_step: bool,
    /// Verlet: mass-proportional damping coefficient α in 1/s (001 Eq. 42; default 0).
    pub damping: Option<f64>,
    /// Relaxation: stop when the out-of-balance force is this fraction of the
    /// applied (or reaction) force (default 1e-8).
    pub tolerance: Option<f64>,
    /// Write probes and the energy history every this many steps (default 1).
    pub record_every: Option<usize>,
    /// Verlet: largest energy-balance error accepted, relative to the largest
    /// energy of the run (default 0.2; `inf` turns the check off).
    pub balance_tolerance: Option<f64>,
}

/// Kind of load.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadKind {
    /// Traction in Pa on a face, applied to the outermost point layer.
    Traction,
    /// Force per volume in N/m³.
    BodyForce,
}

/// `[[loads]]`
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Name used in the summary.
    pub name: String,
    /// `"traction"` or `"body_force"`.
    pub kind: LoadKind,
    /// Traction: the face's outward normal, one of `-x +x -y +y -z +z`
    /// (or `group`).
    pub face: Option<String>,
    /// Restrict to the points in this box (body force: default whole body).
    #[serde(rename = "box")]
    pub bounds: Option<BoxSpec>,
    /// A mesh's physical group: a traction acts on its boundary facets (a group
    /// of dimension d − 1), a body force on its cells (dimension d).
    pub group: Option<String>,
    /// Traction vector (Pa) or body force density (N/m³), one entry per dimension.
    pub value: Vec<f64>,
    /// Explicit dynamics: the load is multiplied by this function of time
    /// (default constant 1).
    pub time_function: Option<TimeFunctionSpec>,
}

/// Linear solver route (`solver.method`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverMethod {
    /// Sparse Cholesky (symmetric positive definite); the default for the
    /// bond-based model.
    #[default]
    Cholesky,
    /// Sparse LU of `K` (small problems only: up to 20,000 free unknowns).
    Lu,
    /// GMRES on `K`, preconditioned by the Cholesky factor of a symmetric
    /// surrogate (the bond-based stiffness on the bond pattern, or
    /// `(K + Kᵀ)/2`); the default for the shear model.
    Gmres,
    /// CG on `K` (GMRES for a non-symmetric `K`) preconditioned by a two-level
    /// cycle (Chebyshev smoothing, a coarse space of the rigid motions of small
    /// point aggregates): no factor of `K` is stored, memory linear in the points.
    Iterative,
    /// PETSc on every process of an MPI run (`mpirun -np N dhpd run`): CG
    /// (GMRES for a non-symmetric `K`) with algebraic multigrid (GAMG) given
    /// the rigid motions; static solves only, and only in a build with the
    /// `mpi` feature.
    Petsc,
}

/// What PETSc solves with on the `petsc` route (`solver.petsc_solver`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PetscSolver {
    /// CG (GMRES for a non-symmetric `K`) preconditioned by algebraic
    /// multigrid (GAMG) with the rigid motions as its near-null space.
    #[default]
    Gamg,
    /// MUMPS's distributed sparse LU (PETSc's external package), applied
    /// once: a direct solve on many processes.
    Mumps,
}

/// The fill-reducing ordering of the Cholesky factor (`solver.ordering`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Ordering {
    /// Both analysed; the one whose factorisation needs fewer operations kept
    /// (nested dissection alone above 5e7 stored entries of `K`).
    #[default]
    Auto,
    /// faer's approximate minimum degree.
    Amd,
    /// Geometric nested dissection on the points.
    NestedDissection,
}

/// The precision of the Cholesky factor (`solver.precision`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// Single precision for large factors (from 1e8 entries, where it halves
    /// the factorisation time) or when only that fits in memory; double
    /// otherwise.
    #[default]
    Auto,
    /// Double precision.
    Double,
    /// Single-precision factor; double-precision accuracy recovered by CG
    /// (Cholesky route) or GMRES (shear model) preconditioned by it.
    Mixed,
}

/// `[solver]`
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// `"cholesky"`, `"lu"`, `"gmres"` or `"iterative"`; default: Cholesky for
    /// the bond-based model, GMRES preconditioned by the Cholesky factor of the
    /// bond-based stiffness for the shear model (its tangent is 0.2-0.7 %
    /// asymmetric). Either default switches to `"iterative"` (Krylov on `K`
    /// preconditioned by a two-level cycle, no factor of `K`) when no factor
    /// fits in memory or a factor would cost more than 2e4 operations per
    /// entry of `K` (outside fracture runs).
    pub method: Option<SolverMethod>,
    /// Largest sparse factor to attempt, in GiB (default and upper bound: 90 % of
    /// the memory available when the factorisation starts). A larger factor is
    /// refused right after the symbolic analysis, with the size it would need.
    pub memory_limit_gib: Option<f64>,
    /// Fracture runs: a re-solve after bonds broke iterates with the previous
    /// factor as preconditioner; past this many iterations the matrix is
    /// factorised afresh (default: chosen from the measured cost of a
    /// factorisation and of one iteration).
    pub refactor_iterations: Option<usize>,
    /// Fill-reducing ordering of the Cholesky factor: `"auto"` (default: AMD and
    /// nested dissection both analysed, the smaller factor kept), `"amd"` or
    /// `"nested_dissection"`.
    pub ordering: Option<Ordering>,
    /// Precision of the Cholesky factor: `"auto"` (default: double, single when
    /// only that fits in memory), `"double"` or `"mixed"` (single-precision
    /// factor, full accuracy recovered by CG or GMRES preconditioned by it).
    pub precision: Option<Precision>,
    /// With `method = "petsc"`: `"gamg"` (default: CG or GMRES with algebraic
    /// multigrid) or `"mumps"` (MUMPS's distributed sparse LU).
    pub petsc_solver: Option<PetscSolver>,
}

/// `[output]`
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Write `points.vtu` (default true).
    #[serde(default = "default_true")]
    pub vtu: bool,
    /// Write `points.csv` (default true).
    #[serde(default = "default_true")]
    pub points_csv: bool,
    /// Recover the stress at every point (shear model, 001 Eq. 32) and add it to
    /// `points.csv` and `points.vtu` (default false).
    #[serde(default)]
    pub stress: bool,
    /// Write `K.mtx` and `f.mtx` (reduced system, Matrix Market) (default false).
    #[serde(default)]
    pub matrix_market: bool,
    /// Line profiles, each written to `profile_NAME.csv`.
    #[serde(default)]
    pub profiles: Vec<ProfileSpec>,
    /// Point probes, written together to `probes.csv`.
    #[serde(default)]
    pub probes: Vec<ProbeSpec>,
    /// Fracture and dynamics runs: write a VTU file of the state every this many
    /// steps (listed in `series.pvd`); default: the final state only.
    pub every: Option<usize>,
    /// Fracture and dynamics runs: write a VTU file at these steps too.
    #[serde(default)]
    pub steps: Vec<usize>,
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            vtu: true,
            points_csv: true,
            stress: false,
            matrix_market: false,
            profiles: Vec::new(),
            probes: Vec::new(),
            every: None,
            steps: Vec::new(),
        }
    }
}

/// `[[output.profiles]]`: the points within half their spacing of a segment.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileSpec {
    /// File name part: letters, digits, `_` and `-`.
    pub name: String,
    /// Start of the segment.
    pub from: Vec<f64>,
    /// End of the segment.
    pub to: Vec<f64>,
}

/// `[[output.probes]]`: the point nearest to a location.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    /// Name in `probes.csv`.
    pub name: String,
    /// Location.
    pub at: Vec<f64>,
}

/// `[fracture]`: bond breakage settings shared by the drivers that break bonds.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FractureSpec {
    /// Shear model: how `fracture_energy` becomes ε^d_max. `"pair"` (default)
    /// counts the energy of both bonds of a pair (001 Eq. 40 divided by √2),
    /// `"one_bond"` is 001 Eq. 40 as printed.
    #[serde(default)]
    pub shear_energy: EnergyCounting,
    /// How `fracture_energy` becomes a critical value: `"dissipation"` (default)
    /// makes steady crack growth on the scene's own lattice dissipate G₀ per unit
    /// crack area; `"peak"` makes the peak load of a sharp crack tend to the LEFM
    /// load of G₀ (growth then dissipates G₀/r², r the lattice's trapping ratio);
    /// `"continuum"` is the papers' formula (the crossing bonds of a continuum
    /// hold G₀). See `damage::calibration`.
    #[serde(default)]
    pub calibration: Calibration,
    /// Shear model: which bond quantity reaches its critical value. `"energy"`
    /// (default): the bond's energy density, deviatoric plus its share of the
    /// volumetric part; `"deviatoric"`: the deviatoric bond strain of 001 Eq. 37.
    /// Both keep the tension check of 001 Eq. 37.
    #[serde(default)]
    pub shear_criterion: ShearCriterion,
    /// Boxes in which no bond breaks (a bond with either end inside is kept).
    #[serde(default)]
    pub no_fail: Vec<NoFailSpec>,
}

/// How the fracture energy of the shear model is counted (formulation Sec. 5).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EnergyCounting {
    /// Both bonds `i→j` and `j→i` of a pair store energy: ε^d_max of 001 Eq. 40 / √2.
    #[default]
    Pair,
    /// One bond per pair, as 001 Eq. 39-40 count it.
    OneBond,
}

/// The shear model's bond breakage criterion (`damage` module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ShearCriterion {
    /// `K θ_i²/2 + d μ (ε^d)²` reaches its critical value.
    #[default]
    Energy,
    /// `|ε^d|` reaches `ε^d_max` (001 Eq. 37).
    Deviatoric,
}

/// How a fracture energy becomes each owner's critical value (`damage::calibration`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Calibration {
    /// The continuum formula divided by `sqrt(D)`, `D` the measured dissipation
    /// factor of the owner's lattice: crack growth dissipates G₀ per unit area.
    #[default]
    Dissipation,
    /// The continuum formula of the papers (000 Eq. 12, 001 Eq. 40).
    Continuum,
    /// The continuum formula divided by `r sqrt(D)`, `r` the measured lattice
    /// trapping ratio: the peak load of a sharp crack tends to the LEFM load of
    /// G₀ as δ/a → 0; growth dissipates G₀/r² per unit area.
    Peak,
}

/// `[[fracture.no_fail]]`: a box where bonds never break.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct NoFailSpec {
    /// The box (inclusive).
    #[serde(rename = "box")]
    pub bounds: BoxSpec,
}

/// How the quasi-static driver breaks bonds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Strategy {
    /// From one solve, the exact load factor at which the next bond reaches its
    /// critical value; scale to it, break it, re-solve (default).
    #[default]
    Event,
    /// At each load step, break every bond over its critical value, re-solve.
    All,
    /// At each load step, break the bonds within `tolerance` of the largest
    /// ratio (value / critical value), re-solve.
    MostCritical,
}

/// `[quasi_static]`: load stepping under the scene's loads scaled by a load factor.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct QuasiStaticSpec {
    /// `"event"` (default), `"all"` or `"most_critical"`.
    #[serde(default)]
    pub strategy: Strategy,
    /// Largest load factor (the scene's prescribed values and loads are reached
    /// at 1). Required.
    pub max_load_factor: f64,
    /// `all` / `most_critical`: number of uniform load steps up to `max_load_factor` (default 100).
    pub steps: Option<usize>,
    /// `all` / `most_critical`: halve a step that breaks more than this many bonds
    /// (adaptive stepping; default: no halving).
    pub max_broken_per_step: Option<usize>,
    /// `all` / `most_critical`: smallest step when halving, as a fraction of the
    /// uniform step (default 1/1024).
    pub min_step_fraction: Option<f64>,
    /// `event` / `most_critical`: bonds whose ratio (value / critical value) is
    /// within this relative tolerance of the largest break together (default
    /// 1e-6: ties up to round-off, e.g. bonds mirrored by a symmetry).
    pub tolerance: Option<f64>,
    /// `all` / `most_critical`: largest number of re-solves within one step (default 10,000).
    pub max_resolves: Option<usize>,
    /// `event`: largest number of events (default 1,000,000).
    pub max_events: Option<usize>,
    /// End the run once every reaction has fallen below this fraction of its
    /// peak (e.g. 0.5 to study the peak load only); default: run to the
    /// maximal load factor or to separation.
    pub stop_after_peak: Option<f64>,
}
