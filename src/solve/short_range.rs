//! The short-range preconditioner of the iterative route
//! (`solver.method = "iterative"`, and the automatic choice when no factor of
//! `K` fits in memory).
//!
//! A direct factor of `K` fills like the bonds reach: with δ = 3Δx a 3D point
//! is coupled to 122 others, and the nested-dissection factor of a cube of
//! 50,653 points holds 1.0e9 entries. The iterative route never factorises `K`.
//! It runs CG on `K` (GMRES for the shear model's non-symmetric tangent),
//! preconditioned by the Cholesky factor of `K_s`, the bond-based stiffness of
//! the same points with short horizons
//!
//! ```text
//! δ_s,i = min(δ_i, REACH Δx_i),    C_s,i = C(δ_s,i)   (formulation Sec. 3)
//! ```
//!
//! from the same materials, pre-cracks and partial-volume rule, so that `K_s`
//! carries the same bulk stiffness with the pattern of a local stencil (on a
//! grid with REACH = 1.5: 8 neighbours in 2D and 18 in 3D, plus the bonds the
//! partial-volume rule reaches), whose factor fills far less.
//!
//! **Why the iteration count does not grow with the number of points** at a
//! fixed ratio m = δ/Δx: for a displacement wave of wavelength λ, both
//! `uᵀ K u` and `uᵀ K_s u` are `Δx^(d−2)` times a bounded function of `Δx/λ`,
//! and both tend to the same elastic energy (up to the Poisson ratio, which
//! `K_s` does not represent) as `Δx/λ → 0`. Their ratio is therefore bounded
//! above and below by constants that depend on m, the materials and the shape,
//! not on N, and so are `κ(K_s⁻¹ K)` and the CG iteration count (∝ √κ).
//! Measured in `validation/solver/README.md`. The ratio is not bounded
//! uniformly in the Poisson ratio: near incompressibility the shear model's
//! bulk stiffness dominates and the iteration count grows.

use crate::discretization::Discretization;
use crate::error::Error;
use crate::model::bond_based::BondBased;
use crate::scene::Scene;

/// Horizon of the short-range stiffness, in local spacings.
pub const REACH: f64 = 1.5;

/// The short-range discretisation and its bond-based model.
pub struct ShortRange {
    /// The same points with horizons `min(δ_i, REACH Δx_i)` and their bonds.
    pub disc: Discretization,
    /// Bond-based micromoduli of the short horizons.
    pub model: BondBased,
}

impl ShortRange {
    /// Builds the short-range stiffness's points and bonds for `disc`.
    pub fn new(disc: &Discretization, scene: &Scene) -> Result<Self, Error> {
        let horizon = disc
            .points
            .horizon
            .iter()
            .zip(&disc.points.spacing)
            .map(|(&delta, &dx)| delta.min(REACH * dx))
            .collect();
        let disc = disc.with_horizons(horizon, scene)?;
        let model = BondBased::new(&disc, scene.dimension, &scene.materials, scene.thickness);
        Ok(Self { disc, model })
    }
}
