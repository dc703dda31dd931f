//! Scenes: parsing (TOML or JSON) and validation into a typed [`Scene`],
//! nested as the file is: one validator per section, called in the order of
//! the sections a check depends on.
//!
//! No numerics happen here. Every check names the offending field with a dotted
//! path (`regions[1].spacing`) and says what would be valid. Checks that need the
//! points (a boundary box that selects nothing, a traction face with no point)
//! are done by the discretisation right after the points exist and before
//! any bond is built.
//!
//! Sections, each a file with its typed form and its validator: `model`
//! (`[model]`, `[discretization]`), `material` (`[materials]` and their
//! elastic constants: the micromodulus, the bulk and shear moduli, read by the
//! models too), `body` (regions, point files, meshes, holes, cracks),
//! `boundary` (supports and loads), `output`, `solver` (the solver's
//! vocabulary), `fracture` (`[fracture]`, `[quasi_static]`), `dynamics`
//! (`[dynamics]`, initial conditions); `fields` holds the checks they share,
//! `read` the parsing, `builder` the constructors of the sections in code.

internal!(body, boundary, dynamics, fields, fracture, material, model, output, read, solver);
mod builder;
mod spec;

pub use body::{Crack, Hole, HorizonRule, MeshFile, PointFile, Region};
pub use boundary::{Load, LoadTarget, Motion, Prescribed, Selection, TimeFunction};
pub use dynamics::{Dynamics, Gaussian, InitialCondition, RunLength};
pub use fields::Aabb;
pub use fracture::{FractureSettings, QuasiStatic};
pub use material::{FractureParameter, Material};
pub use model::{DiscretizationSettings, Model};
pub use output::{OutputSettings, Probe, Profile};
pub use read::{load, parse_spec, read_input_file, read_text_file};
pub use solver::SolverSettings;
pub use spec::*;

use crate::error::InputError;
use std::path::Path;

/// A validated scene, nested as the file: everything the numerics need,
/// nothing they do not.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Name used in reports and as the default output directory.
    pub name: String,
    /// `[model]`.
    pub model: Model,
    /// `[discretization]`.
    pub discretization: DiscretizationSettings,
    /// `[materials]`, indexed by regions and points.
    pub materials: Vec<Material>,
    /// `[[regions]]`.
    pub regions: Vec<Region>,
    /// `[[point_files]]`.
    pub point_files: Vec<PointFile>,
    /// `[[meshes]]`.
    pub meshes: Vec<MeshFile>,
    /// `[[holes]]`.
    pub holes: Vec<Hole>,
    /// `[[cracks]]`.
    pub cracks: Vec<Crack>,
    /// `[[boundary]]`: prescribed displacements (or velocities).
    pub boundaries: Vec<Prescribed>,
    /// `[[loads]]`.
    pub loads: Vec<Load>,
    /// `[solver]`.
    pub solver: SolverSettings,
    /// `[output]`.
    pub output: OutputSettings,
    /// `[fracture]` (used by the drivers that break bonds).
    pub fracture: FractureSettings,
    /// `[quasi_static]`: a fracture run (None: another driver).
    pub quasi_static: Option<QuasiStatic>,
    /// `[dynamics]`: an explicit run (None: another driver).
    pub dynamics: Option<Dynamics>,
    /// `[[initial_conditions]]` (explicit runs).
    pub initial_conditions: Vec<InitialCondition>,
}

impl Scene {
    /// Spatial dimension `d`.
    pub fn d(&self) -> usize {
        self.model.d()
    }

    /// Validates a raw spec. `base` resolves relative point-file paths;
    /// `default_name` is used when the scene has no `name`.
    pub fn try_from_spec(
        spec: SceneSpec,
        base: &Path,
        default_name: &str,
    ) -> Result<Scene, InputError> {
        let d = spec.model.dimension.d();
        let model = model::validate(&spec.model)?;
        fields::check_horizon_factor(
            "discretization.horizon_factor",
            spec.discretization.horizon_factor,
        )?;
        let materials = material::validate(&spec)?;
        let bodies = body::validate(&spec, &materials, model.thickness, base)?;
        let mut boundaries = (spec.boundary.iter().enumerate())
            .map(|(k, b)| boundary::boundary(k, b, &spec.boundary[..k], d, &bodies.meshes))
            .collect::<Result<Vec<_>, _>>()?;
        let mut loads = (spec.loads.iter().enumerate())
            .map(|(k, l)| boundary::load(&format!("loads[{k}]"), l, d, &bodies.meshes))
            .collect::<Result<Vec<_>, _>>()?;
        let output = output::validate(&spec.output, d)?;
        let explicit = dynamics::validate(&spec, d)?;
        let (fracture, quasi_static) =
            fracture::validate(&spec, &materials, &boundaries, &loads, d)?;
        let dynamics = explicit.as_ref().map(|e| &e.dynamics);
        driver_keys(&spec, &materials, &output, quasi_static.is_some(), dynamics)?;
        let run = solver::RunKind {
            dynamics: dynamics.map(|d| d.method),
            fracture: quasi_static.is_some(),
        };
        let symmetric = spec.model.kind == ModelKind::BondBased
            || spec.model.formulation.unwrap_or_default() == ShearFormulation::Energy;
        let solver = solver::validate(&spec.solver, symmetric, run)?;
        let name = match &spec.name {
            Some(n) => {
                fields::name("name", n)?;
                n.clone()
            }
            None => fields::sanitize(default_name),
        };
        model::late_checks(&spec, &model, &materials)?;
        let (dynamics, initial_conditions) = match explicit {
            Some(e) => {
                // Each support's and load's time function goes with it.
                let times = boundaries.iter_mut().zip(e.boundary_time);
                times.for_each(|(b, t)| b.time = t);
                loads
                    .iter_mut()
                    .zip(e.load_time)
                    .for_each(|(l, t)| l.time = t);
                (Some(e.dynamics), e.initial_conditions)
            }
            None => (None, Vec::new()),
        };
        Ok(Scene {
            name,
            model,
            discretization: DiscretizationSettings {
                volume_correction: spec.discretization.volume_correction,
                isolated_points: spec.discretization.isolated_points,
                surface_correction: spec.discretization.surface_correction.unwrap_or_default(),
            },
            materials,
            regions: bodies.regions,
            point_files: bodies.point_files,
            meshes: bodies.meshes,
            holes: bodies.holes,
            cracks: bodies.cracks,
            boundaries,
            loads,
            solver,
            output,
            fracture,
            quasi_static,
            dynamics,
            initial_conditions,
        })
    }
}

/// The keys that apply to one driver only: a relaxation or a linearised run
/// breaks no bond; the series and the refactorisation threshold need a run
/// that steps; mixed precision needs a static solve.
fn driver_keys(
    spec: &SceneSpec,
    materials: &[Material],
    output: &OutputSettings,
    fracture_run: bool,
    dynamics: Option<&Dynamics>,
) -> Result<(), InputError> {
    if let Some(dy) = dynamics {
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
    } else if !fracture_run {
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
    if spec.solver.precision == Some(Precision::Mixed) && (fracture_run || dynamics.is_some()) {
        return Err(InputError::new(
            "solver.precision",
            "\"mixed\" applies to static solves (fracture runs update the factor exactly, \
             which needs double precision; explicit runs factorise nothing)",
        ));
    }
    Ok(())
}
