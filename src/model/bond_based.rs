//! Bond-based dual-horizon PD (formulation Sec. 3; 000 Eq. 11-12; 003 Eq. 35).
//!
//! Bond `i → j` (owner `i`) carries the owner's micromodulus `C_i = C(δ_i)`:
//!
//! ```text
//! f_ij = C_i s n,   s = (|ξ+η| − |ξ|)/|ξ|,   n = (ξ+η)/|ξ+η|
//! force on i: + f_ij V_i V_j ν_ij      force on j: − f_ij V_i V_j ν_ij
//! ```
//!
//! | setting | `C(δ)` per unit thickness/area | implied ν |
//! |---|---|---|
//! | 3D | `3E / (π δ⁴ (1−2ν))` | 1/4 |
//! | plane stress | `3E / (π δ³ (1−ν))` | 1/3 |
//! | plane strain | `3E / (π δ³ (1+ν)(1−2ν))` | 1/4 |
//! | 1D | `E / δ²` | – |
//!
//! These are half the constant-horizon micromodulus because each pair is carried
//! by two bonds. Volumes here include the thickness (2D) or the area (1D), so the
//! tabulated value is divided by it.
//!
//! Linearised about the reference configuration, `s ≈ e·η/|ξ|` and `n ≈ e`, so each
//! bond contributes `k = C_i V_i V_j ν_ij / |ξ| · e ⊗ e` with `+k` on blocks
//! (i,i), (j,j) and `−k` on (i,j), (j,i): `K` is symmetric.

use super::{Block, Column, Coupling, Model};
use crate::discretization::Discretization;
use crate::geometry::{dot, norm, sub};
use crate::scene::{Dimension, Material};
use std::f64::consts::PI;

/// The only Poisson ratio bond-based PD represents in this setting (0 in 1D, where it does not apply).
pub fn implied_poisson_ratio(dim: Dimension) -> f64 {
    match dim {
        Dimension::One => 0.0,
        Dimension::PlaneStress => 1.0 / 3.0,
        Dimension::PlaneStrain | Dimension::Three => 0.25,
    }
}

/// Checks that the bond-based model can represent `material`; `given` tells whether
/// the scene stated ν, `allow_any` is the user's explicit opt-in.
pub fn check_material(
    dim: Dimension,
    material: &Material,
    given: bool,
    allow_any: bool,
) -> Result<(), String> {
    let implied = implied_poisson_ratio(dim);
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

/// Micromodulus `C(δ)` of an owner (per volume² including thickness/area), formulation Sec. 3.
pub fn micromodulus(dim: Dimension, material: &Material, horizon: f64, thickness: f64) -> f64 {
    let (e, nu, d) = (material.youngs_modulus, material.poisson_ratio, horizon);
    match dim {
        Dimension::One => e / (d * d) / thickness,
        Dimension::PlaneStress => 3.0 * e / (PI * d.powi(3) * (1.0 - nu)) / thickness,
        Dimension::PlaneStrain => {
            3.0 * e / (PI * d.powi(3) * (1.0 + nu) * (1.0 - 2.0 * nu)) / thickness
        }
        Dimension::Three => 3.0 * e / (PI * d.powi(4) * (1.0 - 2.0 * nu)),
    }
}

/// The bond-based model with each point's micromodulus.
#[derive(Debug, Clone)]
pub struct BondBased {
    /// `C_i` of each owner.
    pub micromodulus: Vec<f64>,
}

impl BondBased {
    /// Computes every owner's micromodulus from its material and horizon.
    pub fn new(
        disc: &Discretization,
        dim: Dimension,
        materials: &[Material],
        thickness: f64,
    ) -> Self {
        let p = &disc.points;
        let micromodulus = (0..p.len())
            .map(|i| {
                micromodulus(
                    dim,
                    &materials[p.material[i] as usize],
                    p.horizon[i],
                    thickness,
                )
            })
            .collect();
        Self { micromodulus }
    }

    /// Linearised stiffness block `k` of bond `b` owned by `i`.
    #[inline]
    fn bond_block(&self, disc: &Discretization, i: usize, b: usize) -> Block {
        let p = &disc.points;
        let j = disc.bonds.neighbour[b] as usize;
        let xi = sub(&p.x[j], &p.x[i]);
        let len = norm(&xi);
        // `k e ⊗ e` with the unit vector: `ξ ⊗ ξ / |ξ|³` would under- or
        // overflow at spacings far from 1 m (|ξ|³ = 1e-450 at 1e-150 m).
        let e = xi.map(|v| v / len);
        let scale =
            self.micromodulus[i] * p.volume[i] * p.volume[j] * disc.bonds.volume_factor[b] / len;
        std::array::from_fn(|r| std::array::from_fn(|c| scale * e[r] * e[c]))
    }
}

impl Model for BondBased {
    fn coupling(&self) -> Coupling {
        Coupling::Star
    }

    fn owner_forces(
        &self,
        disc: &Discretization,
        i: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [[f64; 3]],
    ) {
        let p = &disc.points;
        let bonds = &disc.bonds;
        let first = bonds.offsets[i];
        for b in bonds.owned_by(i) {
            let slot = &mut out[b - first];
            if !bonds.intact[b] {
                *slot = [0.0; 3];
                continue;
            }
            let j = bonds.neighbour[b] as usize;
            let xi = sub(&p.x[j], &p.x[i]);
            let eta = sub(&u[j], &u[i]);
            let len = norm(&xi);
            let weight = self.micromodulus[i] * p.volume[i] * p.volume[j] * bonds.volume_factor[b];
            *slot = if linear {
                let s = dot(&xi, &eta) / (len * len);
                std::array::from_fn(|a| weight * s * xi[a] / len)
            } else {
                let y = [xi[0] + eta[0], xi[1] + eta[1], xi[2] + eta[2]];
                let ylen = norm(&y);
                let s = (ylen - len) / len;
                std::array::from_fn(|a| weight * s * y[a] / ylen)
            };
        }
    }

    fn bond_strains(
        &self,
        disc: &Discretization,
        i: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [f64],
    ) -> Option<f64> {
        let p = &disc.points;
        let bonds = &disc.bonds;
        let first = bonds.offsets[i];
        for b in bonds.owned_by(i) {
            out[b - first] = if bonds.intact[b] {
                let j = bonds.neighbour[b] as usize;
                let xi = sub(&p.x[j], &p.x[i]);
                let eta = sub(&u[j], &u[i]);
                let len = norm(&xi);
                if linear {
                    dot(&xi, &eta) / (len * len)
                } else {
                    let y: [f64; 3] = std::array::from_fn(|a| xi[a] + eta[a]);
                    (norm(&y) - len) / len
                }
            } else {
                0.0
            };
        }
        None
    }

    fn bond_stiffness(&self, disc: &Discretization, i: usize, b: usize) -> Option<(f64, [f64; 3])> {
        let p = &disc.points;
        let j = disc.bonds.neighbour[b] as usize;
        let xi = sub(&p.x[j], &p.x[i]);
        let len = norm(&xi);
        let k =
            self.micromodulus[i] * p.volume[i] * p.volume[j] * disc.bonds.volume_factor[b] / len;
        Some((k, xi.map(|v| v / len)))
    }

    fn tangent_column(
        &self,
        disc: &Discretization,
        owner: usize,
        column: Column,
        add: &mut dyn FnMut(usize, &Block),
    ) {
        let neg =
            |k: &Block| -> Block { std::array::from_fn(|r| std::array::from_fn(|c| -k[r][c])) };
        match column {
            Column::Owner => {
                let mut diag = [[0.0; 3]; 3];
                for b in disc.bonds.owned_by(owner) {
                    if !disc.bonds.intact[b] {
                        continue;
                    }
                    let k = self.bond_block(disc, owner, b);
                    for r in 0..3 {
                        for c in 0..3 {
                            diag[r][c] += k[r][c];
                        }
                    }
                    add(disc.bonds.neighbour[b] as usize, &neg(&k));
                }
                add(owner, &diag);
            }
            Column::Neighbour(b) => {
                if disc.bonds.intact[b] {
                    let k = self.bond_block(disc, owner, b);
                    add(owner, &neg(&k));
                    add(disc.bonds.neighbour[b] as usize, &k);
                }
            }
        }
    }
}
