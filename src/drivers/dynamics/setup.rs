//! What the explicit driver adds to the common setup: which components are
//! free, the prescribed ones with their set and time function, the loads with
//! theirs, the force field of the scene's model and kernel, the stable time
//! step (module docs of [`super`]) and the fictitious masses of dynamic
//! relaxation.

use super::kernels::{FamilyKernel, ForceField, PairKernel, TangentKernel, WithStress};
use crate::assembly::dofs::{DofMap, PRESCRIBED};
use crate::damage::Criterion;
use crate::discretization::Discretization;
use crate::error::Error;
use crate::model::bond_based::BondBased;
use crate::model::AnyModel;
use crate::notes::Notes;
use crate::scene::{ForceKernel, HorizonMode, ModelKind, Scene, TimeFunction};

/// A prescribed component: point, component, set, value.
#[derive(Debug, Clone, Copy)]
pub(super) struct Constrained {
    pub(super) point: u32,
    pub(super) component: u8,
    pub(super) set: u16,
    pub(super) value: f64,
}

/// The external forces of each load, with its time function.
pub(super) struct Loads {
    per_load: Vec<(Vec<(usize, [f64; 3])>, TimeFunction)>,
}

impl Loads {
    /// Adds every load's forces at time `t` into `out`.
    pub(super) fn add_into(&self, t: f64, out: &mut [[f64; 3]]) {
        for (forces, g) in &self.per_load {
            let s = g.value(t);
            for &(i, f) in forces {
                for c in 0..3 {
                    out[i][c] += s * f[c];
                }
            }
        }
    }

    /// `Σ f_ext(t) · du` over the loaded points.
    pub(super) fn power(&self, t: f64, du: &[[f64; 3]]) -> f64 {
        let mut w = 0.0;
        for (forces, g) in &self.per_load {
            let s = g.value(t);
            for &(i, f) in forces {
                w += s * (f[0] * du[i][0] + f[1] * du[i][1] + f[2] * du[i][2]);
            }
        }
        w
    }
}

/// The degrees of freedom of an explicit run.
pub(super) struct Explicit {
    /// Which components of each point are free.
    pub(super) free: Vec<[bool; 3]>,
    /// Each prescribed component once, in the set that owns it.
    pub(super) constrained: Vec<Constrained>,
    /// The loads, each with its time function.
    pub(super) loads: Loads,
    /// The points whose histories are recorded.
    pub(super) probes: Vec<usize>,
    /// Number of constrained sets.
    pub(super) sets: usize,
}

impl Explicit {
    /// The free and prescribed components of `dofs` (each prescribed component
    /// once, in the set that owns it: `ConstrainedSet`), the loads of
    /// `load_forces` with the scene's time functions, the `probes`.
    pub(super) fn new(
        scene: &Scene,
        disc: &Discretization,
        dofs: &DofMap,
        load_forces: Vec<Vec<(usize, [f64; 3])>>,
        probes: Vec<usize>,
    ) -> Self {
        let (n, d) = (disc.points.len(), disc.d);
        let mut constrained = Vec::new();
        for (k, set) in dofs.sets.iter().enumerate() {
            for &(point, component) in &set.owned {
                if let Some(value) = scene.boundaries[k].values[component as usize] {
                    constrained.push(Constrained {
                        point,
                        component,
                        set: k as u16,
                        value,
                    });
                }
            }
        }
        let per_load = load_forces
            .into_iter()
            .zip(&scene.loads)
            .map(|(forces, load)| (forces, load.time.clone()))
            .collect();
        Explicit {
            free: (0..n)
                .map(|i| std::array::from_fn(|c| c < d && dofs.free_index[3 * i + c] != PRESCRIBED))
                .collect(),
            constrained,
            loads: Loads { per_load },
            probes,
            sets: dofs.sets.len(),
        }
    }
}

/// The force field of the scene's model and `[dynamics]` kernel (calibration
/// notes of a breaking run go to `notes`).
pub(super) fn kernel(
    scene: &Scene,
    disc: Discretization,
    notes: &mut Notes,
) -> Result<Box<dyn ForceField>, Error> {
    let dy = scene.dynamics.as_ref().expect("a dynamics scene");
    let criterion = scene
        .materials
        .iter()
        .any(|m| m.fracture.is_some())
        .then(|| {
            let (criterion, report) = Criterion::with_report(scene, &disc);
            report
                .notes()
                .iter()
                .for_each(|n| notes.push(format!("note: {n}")));
            criterion
        });
    let model = AnyModel::new(scene, &disc)?;
    model.warnings().into_iter().for_each(|w| notes.push(w));
    let limit = scene.solver.memory_limit_bytes;
    let stress = scene.output.stress;
    let with_stress = |field: Box<dyn ForceField>, model| -> Box<dyn ForceField> {
        match stress {
            true => Box::new(WithStress { field, model }),
            false => field,
        }
    };
    Ok(match (model, dy.kernel) {
        (AnyModel::BondBased(model), ForceKernel::Nonlinear) => {
            let traditional = scene.model.horizons == HorizonMode::Traditional;
            let field = Box::new(PairKernel::new(disc, &model, criterion, traditional));
            with_stress(field, AnyModel::BondBased(model))
        }
        (model, ForceKernel::Linearised) => {
            let field = Box::new(TangentKernel::new(disc, &model, limit)?);
            with_stress(field, model)
        }
        (AnyModel::Shear(model), ForceKernel::Nonlinear) => {
            Box::new(FamilyKernel::new(disc, model, false, criterion))
        }
    })
}

/// What ran: the kernel's name and its vector path.
pub(super) fn kernel_description(scene: &Scene, field: &dyn ForceField) -> String {
    let dy = scene.dynamics.as_ref().expect("a dynamics scene");
    let name = match (scene.model.kind, dy.kernel, scene.model.horizons) {
        (_, ForceKernel::Linearised, _) => "assembled tangent (linearised)",
        (ModelKind::BondBased, _, HorizonMode::Traditional) => {
            "bond-based pairs, traditional horizons"
        }
        (ModelKind::BondBased, _, _) => "bond-based pairs (nonlinear)",
        (ModelKind::Shear, _, _) => "shear families (nonlinear, polar rotation)",
    };
    match field.simd() {
        Some(simd) => format!("{name}, {simd:?} vector path"),
        None => name.to_string(),
    }
}

/// Gershgorin row sums `Σ_c |K_rc|` of the scene's tangent, per point and component (not assembled).
pub(super) fn tangent_row_sums(
    scene: &Scene,
    disc: &Discretization,
) -> Result<Vec<[f64; 3]>, Error> {
    let model = AnyModel::new(scene, disc)?;
    Ok(crate::assembly::stiffness::row_abs_sums(&model, disc))
}

/// The largest stable time step of every point (module docs of [`super`]).
pub(super) fn stable_time_steps(
    scene: &Scene,
    disc: &Discretization,
    mass: &[f64],
) -> Result<Vec<f64>, Error> {
    let n = disc.points.len();
    if scene.model.kind == ModelKind::BondBased {
        let model = BondBased::of(scene, disc);
        let traditional = scene.model.horizons == HorizonMode::Traditional;
        let (p, bonds) = (&disc.points, &disc.bonds);
        let mut k = vec![0.0; n];
        for i in 0..n {
            for b in bonds.owned_by(i) {
                let j = bonds.neighbour[b] as usize;
                let len = crate::vector::norm(&crate::vector::sub(&p.x[j], &p.x[i]));
                let w = model.bond_weight(disc, i, b) / len;
                if traditional {
                    k[i] += 2.0 * w;
                } else {
                    k[i] += w;
                    k[j] += w;
                }
            }
        }
        Ok((0..n)
            .map(|i| (2.0 * mass[i] / k[i]).sqrt())
            .collect::<Vec<_>>())
    } else {
        let rows = tangent_row_sums(scene, disc)?;
        Ok((0..n)
            .map(|i| {
                (0..disc.d)
                    .map(|c| 2.0 * (mass[i] / rows[i][c]).sqrt())
                    .fold(f64::INFINITY, f64::min)
            })
            .collect())
    }
}
