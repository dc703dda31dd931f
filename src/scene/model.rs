//! `[model]` and `[discretization]`: which peridynamic model, in which
//! setting, with which horizons; how the horizons' rims and isolated points
//! are treated.

use super::fields::positive;
use super::material::{self, Material};
use super::spec::{
    Dilatation, Dimension, HorizonMode, IsolatedPolicy, ModelKind, ModelSpec, SceneSpec,
    ShearFormulation, SurfaceCorrection, VolumeCorrection,
};
use crate::error::InputError;

/// The validated `[model]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    /// Bond-based or shear-deformation DH-PD.
    pub kind: ModelKind,
    /// Spatial setting.
    pub dimension: Dimension,
    /// 2D thickness, 1D area, 1 in 3D: the factor from per-unit quantities to volumes.
    pub thickness: f64,
    /// Dual, constant or traditional horizons.
    pub horizons: HorizonMode,
    /// Shear model: how an owner's dilatation is computed (weighted unless
    /// `model.dilatation = "gradient"`).
    pub dilatation: Dilatation,
    /// Shear model: the energy-derived force (default) or the paper's.
    pub formulation: ShearFormulation,
}

impl Model {
    /// Spatial dimension `d`.
    pub fn d(&self) -> usize {
        self.dimension.d()
    }

    /// Whether the shear model takes θ from the shape-tensor gradient.
    pub fn gradient_dilatation(&self) -> bool {
        self.dilatation == Dilatation::Gradient
    }

    /// Whether the shear model uses its energy-derived force (symmetric tangent).
    pub fn energy_shear(&self) -> bool {
        self.kind == ModelKind::Shear && self.formulation == ShearFormulation::Energy
    }
}

/// The validated `[discretization]` (horizon factors are resolved into each
/// region, point file and mesh).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscretizationSettings {
    /// Partial-volume rule.
    pub volume_correction: VolumeCorrection,
    /// What to do with points left without any bond.
    pub isolated_points: IsolatedPolicy,
    /// Bond-based model: the surface correction of its bonds.
    pub surface_correction: SurfaceCorrection,
}

/// `[model]`, up to the checks that need the other sections ([`late_checks`]).
pub(super) fn validate(m: &ModelSpec) -> Result<Model, InputError> {
    Ok(Model {
        kind: m.kind,
        dimension: m.dimension,
        thickness: thickness(m)?,
        horizons: m.horizons,
        dilatation: m.dilatation.unwrap_or_default(),
        formulation: m.formulation.unwrap_or_default(),
    })
}

/// The 2D thickness or 1D area (each positive; 3D takes neither).
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

/// What the model allows of the rest of the scene: the gradient dilatation
/// and the formulation are the shear model's, which needs 2D or 3D; the
/// bond-based model represents only its implied Poisson ratio (unless
/// `model.allow_any_poisson`).
pub(super) fn late_checks(
    spec: &SceneSpec,
    model: &Model,
    materials: &[Material],
) -> Result<(), InputError> {
    if spec.model.dilatation.is_some() && model.kind != ModelKind::Shear {
        return Err(InputError::new(
            "model.dilatation",
            "applies to the shear model only (model.kind = \"shear\")",
        ));
    }
    if spec.model.formulation.is_some() && model.kind != ModelKind::Shear {
        return Err(InputError::new(
            "model.formulation",
            "applies to the shear model only (model.kind = \"shear\"); the bond-based model's \
             surfaces are chosen by discretization.surface_correction",
        ));
    }
    if spec.model.dilatation.is_some() && model.energy_shear() {
        return Err(InputError::new(
            "model.dilatation",
            "applies to the paper's force only (model.formulation = \"paper\"); the energy \
             formulation's dilatation is the trace of its displacement gradient, exact at \
             free surfaces",
        ));
    }
    if spec.discretization.surface_correction.is_some() && model.kind == ModelKind::Shear {
        return Err(InputError::new(
            "discretization.surface_correction",
            "applies to the bond-based model only; the shear model's surfaces are chosen by \
             model.formulation (\"energy\", the default, is exact under homogeneous \
             deformation at free surfaces; \"paper\" is 001's force)",
        ));
    }
    if model.kind == ModelKind::Shear && model.d() == 1 {
        return Err(InputError::new(
            "model.kind",
            "the shear model is defined in 2D and 3D; use \"bond_based\" for a 1D bar",
        ));
    }
    if model.kind == ModelKind::BondBased {
        for (m, spec_m) in materials.iter().zip(spec.materials.values()) {
            material::check_bond_based(
                model.dimension,
                m,
                spec_m.poisson_ratio.is_some(),
                spec.model.allow_any_poisson,
            )
            .map_err(|msg| InputError::new(format!("materials.{}.poisson_ratio", m.name), msg))?;
        }
    }
    Ok(())
}
