//! Bond-based dual-horizon PD (formulation Sec. 3; 000 Eq. 15-16).
//!
//! Bond `i → j` (owner `i`) carries the owner's micromodulus `C_i = C(δ_i)`
//! (000 Eq. 11, 003 Eq. 35; tabulated in [`crate::scene::material`]) and the
//! weight `w_ij = C_i V_i V_j ν_ij` ([`BondBased::bond_weight`]):
//!
//! ```text
//! f_ij = C_i s n,   s = (|ξ+η| − |ξ|)/|ξ|,   n = (ξ+η)/|ξ+η|
//! force on i: + f_ij V_i V_j ν_ij      force on j: − f_ij V_i V_j ν_ij
//! ```
//!
//! Linearised about the reference configuration, `s ≈ e·η/|ξ|` and `n ≈ e`, so each
//! bond contributes `k = C_i V_i V_j ν_ij / |ξ| · e ⊗ e` with `+k` on blocks
//! (i,i), (j,j) and `−k` on (i,j), (j,i): `K` is symmetric.
//!
//! With the surface correction (`discretization.surface_correction = "energy"`,
//! the default; [`super::surface`]) every weight is multiplied by its owner's
//! positive factor `g_ij`, 1 where the family is full: `w_ij = C_i V_i V_j ν_ij g_ij`.
//!
//! **Stress** (`output.stress`). The stress of owner `i` is the derivative of
//! its bonds' energy per unit volume with respect to a homogeneous strain,
//! `W_i(ε) = ½ Σ_b w_b |ξ_b| (e_b·ε e_b)²` ([`super::surface`]), which is the
//! flux of its own bonds' forces (the virial of the bonds it owns):
//!
//! ```text
//! σ_i = (1/V_i) ∂W_i/∂ε = (1/V_i) Σ_{b owned by i, intact} F_b ⊗ ξ_b,
//! F_b = w_b s_b e_b (linearised: s_b = e_b·η_b/|ξ_b|).
//! ```
//!
//! It is symmetric. Under a homogeneous strain it depends only on the owner's
//! even fourth moments, so with the surface correction every point, surface,
//! edge and corner points included, gives the full family's stress: the
//! lattice's (Hooke's law with the model's Poisson ratio, times the lattice's
//! own bias of +1-2 %) for grid points and Hooke's law exactly for imported
//! points (matched to the continuum ball). Without the correction a surface
//! point reports its truncated family's smaller stress, as its stiffness is
//! smaller. Bonds into a grip (factor `1/t`) carry the force of the continued
//! bond and count with their whole `ξ`; points held by a grip report zero (they
//! belong to the rigid grip, as in the shear model's energy formulation).

use super::{Block, Column, Coupling, Model};
use crate::discretization::Discretization;
use crate::scene::{Dimension, Material, Scene, SurfaceCorrection, VolumeCorrection};
use crate::vector::{dot, norm, sub};

/// The bond-based model with each point's micromodulus.
#[derive(Debug, Clone)]
pub struct BondBased {
    /// `C_i` of each owner.
    pub micromodulus: Vec<f64>,
    /// The surface factor `g_ij` of each bond ([`super::surface`]); empty: 1.
    pub surface_factor: Vec<f64>,
    /// Owners whose moments the surface correction could not match (kept at 1).
    pub unmatched_owners: usize,
    /// Whether the pre-crack faces were corrected as surfaces, because the
    /// uncracked bonds could not be searched ([`super::surface`], "Pre-cracks").
    pub crack_faces_corrected: bool,
    /// Points held by a grip (their stress is zero; module docs); empty: none.
    pub held: Vec<bool>,
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
            .map(|i| materials[p.material[i] as usize].micromodulus(dim, p.horizon[i], thickness))
            .collect();
        Self {
            micromodulus,
            surface_factor: Vec::new(),
            unmatched_owners: 0,
            crack_faces_corrected: false,
            held: Vec::new(),
        }
    }

    /// The same model with the surface correction of [`super::surface`]
    /// (`has_cracks`: the scene has pre-cracks, whose faces stay uncorrected).
    pub fn with_surface_correction(
        mut self,
        disc: &Discretization,
        rule: VolumeCorrection,
        thickness: f64,
        has_cracks: bool,
    ) -> Self {
        let (factors, unmatched) = match has_cracks {
            false => super::surface::factors(disc, rule, thickness),
            true => match super::surface::factors_before_cracks(disc, rule, thickness) {
                Some(before) => before,
                None => {
                    self.crack_faces_corrected = true;
                    super::surface::factors(disc, rule, thickness)
                }
            },
        };
        self.surface_factor = factors;
        self.unmatched_owners = unmatched;
        self
    }

    /// The weight `w_ij = C_i V_i V_j ν_ij` of bond `b` owned by `i` (module docs).
    #[inline]
    pub fn bond_weight(&self, disc: &Discretization, i: usize, b: usize) -> f64 {
        let p = &disc.points;
        let j = disc.bonds.neighbour[b] as usize;
        let w = self.micromodulus[i] * p.volume[i] * p.volume[j] * disc.bonds.volume_factor[b];
        match self.surface_factor.get(b) {
            Some(g) => w * g,
            None => w,
        }
    }

    /// The model of `scene` on `disc`.
    pub fn of(scene: &Scene, disc: &Discretization) -> Self {
        let model = Self::new(
            disc,
            scene.model.dimension,
            &scene.materials,
            scene.model.thickness,
        );
        match scene.discretization.surface_correction {
            SurfaceCorrection::Energy => {
                let mut model = model.with_surface_correction(
                    disc,
                    scene.discretization.volume_correction,
                    scene.model.thickness,
                    !scene.cracks.is_empty(),
                );
                let held = super::surface::grip_points(disc, &scene.boundaries);
                let fractions = super::surface::grip_fractions(disc, &held);
                model
                    .surface_factor
                    .iter_mut()
                    .zip(fractions)
                    .for_each(|(g, t)| *g /= t);
                model.held = held;
                model
            }
            SurfaceCorrection::None => model,
        }
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
        let scale = self.bond_weight(disc, i, b) / len;
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
            let weight = self.bond_weight(disc, i, b);
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
        let k = self.bond_weight(disc, i, b) / len;
        Some((k, xi.map(|v| v / len)))
    }

    fn stress(&self, disc: &Discretization, owner: usize, u: &[[f64; 3]]) -> Option<Block> {
        let mut sigma = [[0.0; 3]; 3];
        if self.held.get(owner) == Some(&true) {
            return Some(sigma);
        }
        let p = &disc.points;
        let bonds = &disc.bonds;
        for b in bonds.owned_by(owner).filter(|&b| bonds.intact[b]) {
            let j = bonds.neighbour[b] as usize;
            let xi = sub(&p.x[j], &p.x[owner]);
            let eta = sub(&u[j], &u[owner]);
            let len = norm(&xi);
            let e = xi.map(|v| v / len);
            // F ⊗ ξ / V_i = (w s / V_i) |ξ| e ⊗ e, with w / V_i = C_i V_j ν g.
            let scale = self.bond_weight(disc, owner, b) / p.volume[owner] * dot(&e, &eta);
            for r in 0..3 {
                for c in r..3 {
                    sigma[r][c] += scale * e[r] * e[c];
                }
            }
        }
        for r in 1..3 {
            for c in 0..r {
                sigma[r][c] = sigma[c][r];
            }
        }
        Some(sigma)
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
