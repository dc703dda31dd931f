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

use super::spec::Dimension;
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
