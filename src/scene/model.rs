//! `[model]` and `[discretization]`: which peridynamic model, in which
//! setting, with which horizons; how the horizons' rims and isolated points
//! are treated.

use super::fields::positive;
use super::material::{self, Material};
use super::output::OutputSettings;
use super::spec::{
    Dilatation, Dimension, HorizonMode, IsolatedPolicy, ModelKind, ModelSpec, SceneSpec,
    VolumeCorrection,
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
}

/// The validated `[discretization]` (horizon factors are resolved into each
/// region, point file and mesh).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscretizationSettings {
    /// Partial-volume rule.
    pub volume_correction: VolumeCorrection,
    /// What to do with points left without any bond.
    pub isolated_points: IsolatedPolicy,
}

/// `[model]`, up to the checks that need the other sections ([`late_checks`]).
pub(super) fn validate(m: &ModelSpec) -> Result<Model, InputError> {
    Ok(Model {
        kind: m.kind,
        dimension: m.dimension,
        thickness: thickness(m)?,
        horizons: m.horizons,
        dilatation: m.dilatation.unwrap_or_default(),
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

/// What the model allows of the rest of the scene: stress recovery and the
/// gradient dilatation are the shear model's, which needs 2D or 3D; the
/// bond-based model represents only its implied Poisson ratio (unless
/// `model.allow_any_poisson`).
pub(super) fn late_checks(
    spec: &SceneSpec,
    model: &Model,
    materials: &[Material],
    output: &OutputSettings,
) -> Result<(), InputError> {
    if output.stress && model.kind != ModelKind::Shear {
        return Err(InputError::new(
            "output.stress",
            "stress recovery is defined for the shear model (model.kind = \"shear\")",
        ));
    }
    if spec.model.dilatation.is_some() && model.kind != ModelKind::Shear {
        return Err(InputError::new(
            "model.dilatation",
            "applies to the shear model only (model.kind = \"shear\")",
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
