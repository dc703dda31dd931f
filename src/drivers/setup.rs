//! One setup for every driver: the points and bonds of a scene, its degrees
//! of freedom and constrained sets, the external forces of its loads, the
//! points its outputs read (probes, profiles) and the time each took. The
//! static, quasi-static and dynamics drivers all start from a [`Setup`];
//! a scene that seeks a static equilibrium is checked to have one (held
//! against every rigid motion) before any numerics.

use crate::assembly::dofs::DofMap;
use crate::assembly::loads::{external_forces, AppliedLoad};
use crate::assembly::rigid_modes;
use crate::discretization::share::Distribution;
use crate::discretization::{self, Discretization};
use crate::error::{Error, InputError, NumericalError};
use crate::notes::Notes;
use crate::processes::Processes;
use crate::scene::{DynamicsMethod, Scene};
use crate::vector::{dot, norm, sub};
use serde::Serialize;
use std::time::Instant;

/// Refuses a load all of whose force falls on prescribed displacement
/// components: it would do nothing (its force goes straight into a reaction).
/// Every process holds every point and the whole map, so all agree.
fn check_loads_act(
    scene: &Scene,
    dofs: &DofMap,
    per_load: &[Vec<(usize, [f64; 3])>],
) -> Result<(), InputError> {
    use crate::assembly::dofs::PRESCRIBED;
    for (k, forces) in per_load.iter().enumerate() {
        let acts = forces.iter().any(|(i, f)| {
            (0..dofs.d).any(|c| f[c] != 0.0 && dofs.free_index[3 * i + c] != PRESCRIBED)
        });
        if !forces.is_empty() && !acts {
            return Err(InputError::new(
                format!("loads[{k}]"),
                format!(
                    "\"{}\" acts only on prescribed displacement components (every point it \
                     loads is held by a [[boundary]] in the loaded directions), so it would do \
                     nothing; move the load or the boundary box, or remove the load",
                    scene.loads[k].name
                ),
            ));
        }
    }
    Ok(())
}

/// Wall time per phase in seconds.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Timings {
    /// Point generation (grids, files, holes).
    pub discretization: f64,
    /// Neighbour search and bond construction.
    pub neighbour_search: f64,
    /// Sparsity pattern.
    pub pattern: f64,
    /// Stiffness values, loads and right-hand side.
    pub assembly: f64,
    /// Symbolic factorisation (ordering).
    pub symbolic_factorization: f64,
    /// Numeric factorisation.
    pub numeric_factorization: f64,
    /// Triangular solves, residual and reactions.
    pub solve: f64,
}

/// A scene made ready for a driver.
pub struct Setup {
    /// Points and bonds.
    pub disc: Discretization,
    /// Degrees of freedom and constrained sets.
    pub dofs: DofMap,
    /// External force on every point, every load at its full value.
    pub f_ext: Vec<[f64; 3]>,
    /// Each load's force on the points it loads (explicit dynamics scales each
    /// by its time function).
    pub load_forces: Vec<Vec<(usize, [f64; 3])>>,
    /// The total force of each load.
    pub loads: Vec<AppliedLoad>,
    /// The points the outputs read.
    pub plan: Plan,
    /// Time spent so far.
    pub timings: Timings,
    /// The processes the body is discretised over, when there are several
    /// (`discretization::share`); the explicit driver exchanges its
    /// ghost points' displacements through them.
    pub processes: Option<Box<dyn Processes>>,
}

impl Setup {
    /// Discretises `scene` (points, then bonds), selects the constrained and
    /// loaded points, checks that a body seeking a static equilibrium (static,
    /// quasi-static, dynamic relaxation) is held against every rigid motion,
    /// and resolves the output points: every check that does not need the
    /// stiffness matrix. Notes (overlapping sets, removed points) go to `notes`.
    pub fn new(scene: &Scene, notes: &mut Notes) -> Result<Self, Error> {
        let mut timings = Timings::default();
        let t = Instant::now();
        let raw = discretization::generate_points(scene)?;
        timings.discretization = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let shared = distributed(scene);
        let processes = shared.as_deref();
        let free_components = |body: &Discretization| -> Result<Vec<usize>, Error> {
            let dofs = DofMap::new(body, &scene.boundaries)?;
            Ok((0..body.points.len()).map(|i| dofs.free_count(i)).collect())
        };
        let distribution = processes.map(|processes| Distribution {
            processes,
            free_components: &free_components,
        });
        let disc = discretization::discretize(scene, raw, notes, distribution.as_ref())?;
        timings.neighbour_search = t.elapsed().as_secs_f64();
        let dofs = DofMap::new(&disc, &scene.boundaries)?;
        dofs.overlap_notes().into_iter().for_each(|n| notes.push(n));
        let forces = external_forces(&disc, &scene.loads)?;
        let explicit = scene.dynamics.as_ref().map(|d| d.method);
        if explicit.is_none() && dofs.n_free() == 0 {
            return Err(NumericalError::NothingToSolve.into());
        }
        check_loads_act(scene, &dofs, &forces.per_load)?;
        if explicit.is_none_or(|m| m == DynamicsMethod::Relaxation) {
            // A static equilibrium (relaxation seeks one too) needs a held body.
            rigid_modes::check(&disc, &dofs, processes)?;
        }
        let plan = Plan::new(scene, &disc)?;
        Ok(Setup {
            disc,
            dofs,
            f_ext: forces.total,
            load_forces: forces.per_load,
            loads: forces.applied,
            plan,
            timings,
            processes: shared,
        })
    }
}

impl Setup {
    /// The bonds of the whole body (on a body discretised over several
    /// processes, summed over them: a collective call).
    pub fn bond_count(&self) -> usize {
        super::shares::total_bonds(&self.disc)
    }
}

/// The processes a scene on the `petsc` route is discretised over, when the
/// run has several ([`crate::discretization::share`]); `None` otherwise: one
/// process, other routes, a build without the `mpi` feature.
fn distributed(scene: &Scene) -> Option<Box<dyn Processes>> {
    #[cfg(feature = "mpi")]
    if scene.solver.method == crate::scene::SolverMethod::Petsc {
        return crate::solve::petsc::Processes::of_run().map(|p| Box::new(p) as Box<dyn Processes>);
    }
    let _ = scene;
    None
}

/// The points each requested profile and probe reads, resolved before solving.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Plan {
    /// Per profile: `(name, [(arc length, point)])` sorted by arc length.
    pub profiles: Vec<(String, Vec<(f64, usize)>)>,
    /// Per probe: `(name, nearest point)`.
    pub probes: Vec<(String, usize)>,
}

impl Plan {
    /// Selects the profile and probe points; a profile, a `fracture.no_fail`
    /// box or an `initial_conditions` box that selects no point is an input error.
    pub fn new(scene: &Scene, disc: &Discretization) -> Result<Self, InputError> {
        let profiles = profile_points(scene, disc)?;
        let probes = probe_points(scene, disc)?;
        // A no-fail box that holds no point protects nothing, as a boundary or
        // load box that selects nothing does nothing: both are input errors.
        for (k, b) in scene.fracture.no_fail.iter().enumerate() {
            if !disc.points.x.iter().any(|p| b.contains(p)) {
                return Err(InputError::new(
                    format!("fracture.no_fail[{k}].box"),
                    "selects no point; give a box that holds the points whose bonds must not \
                     break",
                ));
            }
        }
        // The same for an initial-condition box: it would start nothing moving.
        for (k, ic) in scene.initial_conditions.iter().enumerate() {
            if let Some(b) = &ic.bounds {
                if !disc.points.x.iter().any(|p| b.contains(p)) {
                    return Err(InputError::new(
                        format!("initial_conditions[{k}].box"),
                        "selects no point; give a box that holds the points it sets (or leave \
                         the box out to set every point)",
                    ));
                }
            }
        }
        Ok(Plan { profiles, probes })
    }
}

/// The points within half their spacing of each profile's segment, by arc length.
fn profile_points(
    scene: &Scene,
    disc: &Discretization,
) -> Result<Vec<(String, Vec<(f64, usize)>)>, InputError> {
    let x = &disc.points.x;
    let mut profiles = Vec::new();
    for (k, p) in scene.output.profiles.iter().enumerate() {
        let dir = sub(&p.to, &p.from);
        let len = norm(&dir);
        let mut pts: Vec<(f64, usize)> = (0..x.len())
            .filter_map(|i| {
                let rel = sub(&x[i], &p.from);
                let s = dot(&rel, &dir) / len;
                let off = sub(&rel, &std::array::from_fn(|a| s * dir[a] / len));
                let tol = 0.5 * disc.points.spacing[i] * (1.0 + 1e-9);
                (s >= -tol && s <= len + tol && norm(&off) <= tol).then_some((s, i))
            })
            .collect();
        if pts.is_empty() {
            return Err(InputError::new(
                format!("output.profiles[{k}]"),
                format!(
                    "profile \"{}\" passes within half a spacing of no point",
                    p.name
                ),
            ));
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        profiles.push((p.name.clone(), pts));
    }
    Ok(profiles)
}

/// The point nearest each probe, within its spacing.
fn probe_points(scene: &Scene, disc: &Discretization) -> Result<Vec<(String, usize)>, InputError> {
    let x = &disc.points.x;
    let mut probes = Vec::new();
    for (k, p) in scene.output.probes.iter().enumerate() {
        let nearest = (0..x.len())
            .min_by(|&a, &b| norm(&sub(&x[a], &p.at)).total_cmp(&norm(&sub(&x[b], &p.at))))
            .unwrap_or(0);
        // A location inside the body is within half a cell diagonal of a point.
        let distance = norm(&sub(&x[nearest], &p.at));
        let spacing = disc.points.spacing[nearest];
        if !(distance <= spacing) {
            return Err(InputError::new(
                format!("output.probes[{k}].at"),
                format!(
                    "probe \"{}\" is {distance:.4e} m from the nearest point ({:?}), more than \
                         that point's spacing {spacing:e} m: the location is outside the body \
                         (or in a hole); move it onto the body",
                    p.name,
                    &x[nearest][..disc.d]
                ),
            ));
        }
        probes.push((p.name.clone(), nearest));
    }
    Ok(probes)
}
