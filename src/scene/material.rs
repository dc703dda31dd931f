//! Materials and their elastic constants: the one place the scene's validation
//! and the models read them from.
//!
//! **Bond-based micromodulus** (formulation Sec. 3; 000 Eq. 11, 003 Eq. 35):
//! bond `i → j` carries its owner's `C_i = C(δ_i)`,
//!
//! | setting | `C(δ)` per unit thickness/area | implied ν |
//! |---|---|---|
//! | 3D | `3E / (π δ⁴ (1−2ν))` | 1/4 |
//! | plane stress | `3E / (π δ³ (1−ν))` | 1/3 |
//! | plane strain | `3E / (π δ³ (1+ν)(1−2ν))` | 1/4 |
//! | 1D | `E / δ²` | – |
//!
//! These are half the constant-horizon micromodulus because each pair is carried
//! by two bonds. Volumes include the thickness (2D) or the area (1D), so
//! [`Material::micromodulus`] divides the tabulated value by it. Bond-based PD
//! represents only the implied ν ([`bond_based_poisson_ratio`]); another ν is
//! refused unless `model.allow_any_poisson` (the micromodulus then matches the
//! bulk modulus).
//!
//! **Shear model moduli** (formulation Sec. 4): `μ = E/(2(1+ν))` and the bulk
//! modulus `κ` of the setting: 3D `E/(3(1−2ν))`, plane strain `E/(2(1+ν)(1−2ν))`,
//! plane stress `E/(2(1−ν))` ([`Material::moduli`]).

use super::fields::{self, positive};
use super::spec::{Dimension, MaterialSpec, ModelKind, SceneSpec};
use crate::error::{num, InputError};
use std::f64::consts::PI;

/// A validated material.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Name from the scene.
    pub name: String,
    /// Young's modulus in Pa.
    pub youngs_modulus: f64,
    /// Poisson ratio (the model's implied value when not given).
    pub poisson_ratio: f64,
    /// How bonds of this material break (None: they never do).
    pub fracture: Option<FractureParameter>,
    /// Mass density ρ in kg/m³ (explicit dynamics with Verlet only).
    pub density: Option<f64>,
}

/// A material's fracture parameter, as the scene gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FractureParameter {
    /// Fracture energy G₀ (J/m²); the critical value follows from the owner's horizon.
    Energy(f64),
    /// Critical stretch s₀ (bond-based).
    CriticalStretch(f64),
    /// Critical deviatoric bond strain ε^d_max (shear model).
    CriticalDeviatoricStrain(f64),
}

/// The only Poisson ratio bond-based PD represents in this setting (0 in 1D,
/// where it does not apply).
pub fn bond_based_poisson_ratio(dim: Dimension) -> f64 {
    match dim {
        Dimension::One => 0.0,
        Dimension::PlaneStress => 1.0 / 3.0,
        Dimension::PlaneStrain | Dimension::Three => 0.25,
    }
}

impl Material {
    /// Micromodulus `C(δ)` of an owner of this material with horizon `horizon`
    /// (per volume² including thickness/area; module docs).
    pub fn micromodulus(&self, dim: Dimension, horizon: f64, thickness: f64) -> f64 {
        let (e, nu, d) = (self.youngs_modulus, self.poisson_ratio, horizon);
        match dim {
            Dimension::One => e / (d * d) / thickness,
            Dimension::PlaneStress => 3.0 * e / (PI * d.powi(3) * (1.0 - nu)) / thickness,
            Dimension::PlaneStrain => {
                3.0 * e / (PI * d.powi(3) * (1.0 + nu) * (1.0 - 2.0 * nu)) / thickness
            }
            Dimension::Three => 3.0 * e / (PI * d.powi(4) * (1.0 - 2.0 * nu)),
        }
    }

    /// Bulk and shear moduli `(κ, μ)` in a setting (module docs).
    pub fn moduli(&self, dim: Dimension) -> (f64, f64) {
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        let mu = e / (2.0 * (1.0 + nu));
        let kappa = match dim {
            Dimension::PlaneStress => e / (2.0 * (1.0 - nu)),
            Dimension::PlaneStrain => e / (2.0 * (1.0 + nu) * (1.0 - 2.0 * nu)),
            Dimension::Three | Dimension::One => e / (3.0 * (1.0 - 2.0 * nu)),
        };
        (kappa, mu)
    }
}

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

/// Checks that the bond-based model can represent `material`; `given` tells
/// whether the scene stated ν, `allow_any` is the user's explicit opt-in.
pub(super) fn check_bond_based(
    dim: Dimension,
    material: &Material,
    given: bool,
    allow_any: bool,
) -> Result<(), String> {
    let implied = bond_based_poisson_ratio(dim);
    if dim == Dimension::One {
        return if given {
            Err("a 1D bar has no Poisson ratio; remove it".into())
        } else {
            Ok(())
        };
    }
    if !given || allow_any || (material.poisson_ratio - implied).abs() <= 1e-6 {
        return Ok(());
    }
    Err(format!(
        "bond-based PD in this setting represents only ν = {implied:.6}, not {}; use that value, \
         omit poisson_ratio, or set model.allow_any_poisson = true to match the bulk modulus instead",
        material.poisson_ratio
    ))
}

/// `[materials.NAME]`: at least one, each with a positive E, a stable ν (the
/// shear model needs one; bond-based takes its implied value) and at most one
/// fracture parameter matching the model, in a run that breaks bonds.
pub(super) fn validate(spec: &SceneSpec) -> Result<Vec<Material>, InputError> {
    if spec.materials.is_empty() {
        return Err(InputError::new(
            "materials",
            "no material defined: add [materials.NAME] with youngs_modulus",
        ));
    }
    let implied = bond_based_poisson_ratio(spec.model.dimension);
    spec.materials
        .iter()
        .map(|(name, m)| {
            let f = format!("materials.{name}");
            // The name goes into points.csv and messages: no comma, quote or newline.
            fields::name(&f, name)?;
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
