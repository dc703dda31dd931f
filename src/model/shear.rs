//! Shear-deformation dual-horizon PD (Ren, Zhuang & Rabczuk, seed 001;
//! formulation Sec. 4), 2D (plane stress, plane strain) and 3D.
//!
//! Per owner `i`, over its intact bonds, with `ω_j = 1/|ξ_j|²` (the influence
//! function 001 recommends after its Eq. 22) and
//! `w_j = ω_j V_j ν_ij`:
//!
//! ```text
//! m_i = Σ w_j |ξ_j|²,   K_i = Σ w_j ξ_j ⊗ ξ_j                      (shape tensor)
//! F_i = (Σ w_j (ξ_j + η_j) ⊗ ξ_j) K_i⁻¹ = R_i P_i                   (001 Eq. 10-12, SVD)
//! ξ_r = R ξ,  η_r = ξ + η − ξ_r,  θ_i = (d/m_i) Σ w_j η_r·ξ_r       (001 Eq. 15)
//! η^d = η_r − (θ_i/d) ξ_r,  f_ij = (d ω_j/m_i)(κ θ_i ξ_r + 2μ η^d)  (001 Eq. 27-28)
//! force on i: + f_ij V_i V_j ν_ij,   on j: − f_ij V_i V_j ν_ij
//! ```
//!
//! `κ` is the bulk modulus of the setting (3D `E/(3(1−2ν))`, plane strain
//! `E/(2(1+ν)(1−2ν))`, plane stress `E/(2(1−ν))`), `μ = E/(2(1+ν))`. The rotation
//! is the proper rotation of the SVD `F = U Σ Vᵀ`, `R = U Vᵀ`, with the column of
//! `U` of the smallest singular value flipped when `det(U Vᵀ) < 0`.
//!
//! **Linearisation** about the reference configuration (formulation Sec. 4):
//! with `b_k = w_k K⁻¹ ξ_k`, `a_k = (d/m) w_k ξ_k`, `G = Σ η_k ⊗ b_k`,
//! `W = (G − Gᵀ)/2` and `θ = Σ a_k·η_k`,
//!
//! ```text
//! f_ij ≈ (d ω_j/m) [ (κ − 2μ/d) θ ξ_j + 2μ (η_j − W ξ_j) ] = Σ_k A_jk η_k
//! A_jk = (d ω_j/m) [ (κ − 2μ/d) ξ_j ⊗ a_k + 2μ δ_jk I − μ ((b_k·ξ_j) I − b_k ⊗ ξ_j) ]
//! ```
//!
//! and `∂f_ij/∂u_k = A_jk`, `∂f_ij/∂u_i = −Σ_k A_jk`. Each owner couples every
//! pair of `{i} ∪ H_i`, so the stiffness links neighbours of neighbours
//! ([`Coupling::Family`]) and is not symmetric in general.
//!
//! **Energy formulation** (`model.formulation = "energy"`, the default; issue
//! 33). The paper's force is not the derivative of an energy: its tangent is
//! not symmetric, and at a free surface, where the truncated shape tensor is
//! anisotropic (`K_i ≠ (m_i/d) I`), it transmits `(1 + α)` times Hooke's stress
//! (validation/bimaterial_bar/shear_surface). The energy formulation derives
//! every bond force from the strain energy of the owner's cell,
//!
//! ```text
//! E = Σ_i V_i W_i,   W_i = ½ λ (tr G)² + μ G_s : G_s + (α_i/2) Σ_j w_j |r_j|²,
//! G_i = Σ_j η_j ⊗ b_j (b_j = w_j K_i⁻¹ ξ_j),   r_j = η_j − G_i ξ_j,   α_i = 2 d μ / m_i,
//! ```
//!
//! `λ = κ − 2μ/d`, `G_s = (G + Gᵀ)/2`: Hooke's energy of the family's displacement
//! gradient (exact for every affine field, whatever the family) plus the paper's
//! own penalty on the non-affine part. The force of bond `j` on the owner is
//! `V_i ∂W_i/∂η_j = V_i [σ b_j + α (w_j r_j − C b_j)]`, `σ = λ tr G I + 2μ G_s`,
//! `C = Σ_k w_k r_k ⊗ ξ_k` (zero: `Σ_k w_k η_k ⊗ ξ_k = G K`). Where the family is
//! full, `K = (m/d) I`, `b_j = (d/m) w_j ξ_j` and this is exactly 001 Eq. 27-28
//! linearised (formulation Sec. 4): `(dω/m)[(κ − 2μ/d) θ ξ + 2μ (η − W ξ)]` with
//! `θ = tr G`, `W = (G − Gᵀ)/2`. Anywhere, the flux `Σ_j f_j ⊗ ξ_j / V_i` is σ
//! (the penalty's flux vanishes), so a homogeneous strain gives Hooke's stress
//! at surface points too. The tangent (`∂f_m/∂η_k = V_i A_mk`)
//!
//! ```text
//! A_mk = λ b_m ⊗ b_k + μ [(b_m·b_k) I + b_k ⊗ b_m]
//!      + α [w_m δ_mk − w_m (b_k·ξ_m) − w_k (b_m·ξ_k) + b_m·K b_k] I
//! ```
//!
//! satisfies `A_mk = A_kmᵀ`: `K` is symmetric positive semi-definite (Cholesky,
//! CG). Finite deformation (explicit dynamics, the nonlinear force): the
//! Saint Venant-Kirchhoff energy of `F = I + G` with the same penalty on
//! `r_j = y_j − F ξ_j`: `σ b_j` becomes `P b_j`, `P = F S`, `S = λ tr E I + 2μ E`,
//! `E = (FᵀF − I)/2`; objective (a rotation `Q` gives `F = Q`, `E = 0`, `r = 0`)
//! and equal to the linearised force to first order. The damage criteria use
//! the same kinematics (θ = tr G, rotation from `F`), as `dilatation = "gradient"`.
//!
//! **Grips** (energy formulation). A point whose every component is prescribed
//! is part of a rigid grip: it stores no energy (its moduli are set to zero,
//! so its recovered stress is zero), and a bond from a free owner into the grip,
//! of which only the part `t` lies in the free body
//! ([`super::surface::grip_fractions`]), weighs `t w` and sees `η/t`: under a
//! field linear up to the grip's face its owner's gradient is exact, as a clamp
//! on that face requires (without this a bar between grips is softer by about
//! 0.28 δ of length per grip; validation/surfaces).
//!
//! //! **Paper's force, gradient dilatation** (`model.formulation = "paper"`, `model.dilatation = "gradient"`): the
//! weighted dilatation `θ = (d/m) Σ w η_r·ξ_r` equals `tr ε` under a homogeneous
//! strain only when `K_i = (m_i/d) I`, i.e. for a full, symmetric family. At a free
//! surface it does not, which softens or stiffens the rim. The corrected form
//! `θ = Σ w η_r·(R K⁻¹ ξ)` (linearised: `θ = Σ b_k·η_k = tr G`) is identical in
//! the interior and exact for homogeneous deformation everywhere; in `A_jk` it
//! replaces `a_k` by `b_k`.
//!
//! **Stress** (001 Eq. 32, with the sign of formulation Sec. 4):
//! `σ_i = (m_i/d) Σ_j f_ij ⊗ ξ_r V_j ν_ij K_i⁻¹`; under a homogeneous strain with a
//! full horizon it returns Hooke's law exactly.

/// Poisson ratio from which the shear model counts as nearly incompressible:
/// the weighted dilatation's boundary error, multiplied by λ, dominates
/// (validation/stability: L2(u) error 1.2× the ν = 0.3 value at ν = 0.49, 1.7×
/// at 0.4999, and spurious boundary stresses of several times the peak
/// stress), and the two-level preconditioner weakens (its bound grows with
/// λ/μ: 473 CG iterations at ν = 0.4999 against 23 at ν = 0.3).
pub const NEAR_INCOMPRESSIBLE: f64 = 0.49;

use super::{Block, Column, Coupling, Model};
use crate::discretization::Discretization;
use crate::error::NumericalError;
use crate::scene::{Dimension, Material, Scene};
use crate::vector::{dot, sub};

type Mat3 = [[f64; 3]; 3];

/// What an owner's kernels need, computed once per set of intact bonds.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Owner {
    /// Weighted volume `m_i`.
    m: f64,
    /// Inverse shape tensor `K_i⁻¹` (leading d × d block).
    k_inv: Mat3,
    /// `Σ_k a_k`.
    a_sum: [f64; 3],
    /// `Σ_k b_k`.
    b_sum: [f64; 3],
    /// Shape tensor `K_i` (energy formulation: the penalty's `b·K b` terms).
    k: Mat3,
    /// `Σ_k w_k ξ_k`.
    x_sum: [f64; 3],
    /// Bulk modulus κ.
    kappa: f64,
    /// Shear modulus μ.
    mu: f64,
}

impl Owner {
    /// The data of an owner without intact bonds: every kernel loop over its
    /// intact bonds is empty, so it contributes nothing.
    fn failed(kappa: f64, mu: f64) -> Self {
        Owner {
            m: 0.0,
            k_inv: [[0.0; 3]; 3],
            a_sum: [0.0; 3],
            b_sum: [0.0; 3],
            k: [[0.0; 3]; 3],
            x_sum: [0.0; 3],
            kappa,
            mu,
        }
    }
}

/// The shear-deformation model with each owner's cached family data.
#[derive(Debug, Clone)]
pub struct Shear {
    d: usize,
    owners: Vec<Owner>,
    gradient_dilatation: bool,
    /// The energy formulation (module docs); `false`: the paper's force.
    energy: bool,
    /// Energy formulation: the free part `t` of each bond next to a grip
    /// (module docs, "Grips"); empty: 1 for every bond.
    grip: Vec<f64>,
}

impl Shear {
    /// Computes every owner's weighted volume and inverse shape tensor. An owner
    /// whose intact bonds do not span the space is an error naming the point.
    /// On a body discretised over several processes, only the owners whose
    /// families this process holds (`disc.share`); the others contribute nothing.
    /// `gradient_dilatation` selects `θ = tr(K⁻¹ Σ w ξ ⊗ η_r)` (the surface
    /// correction, module docs) instead of the paper's weighted sum.
    pub fn new(
        disc: &Discretization,
        dim: Dimension,
        materials: &[Material],
        gradient_dilatation: bool,
        energy: bool,
    ) -> Result<Self, NumericalError> {
        use rayon::prelude::*;
        let d = disc.d;
        let owners = (0..disc.points.len())
            .into_par_iter()
            .map(|i| {
                let (kappa, mu) = materials[disc.points.material[i] as usize].moduli(dim);
                if disc.share.as_ref().is_some_and(|s| !s.holds(i)) {
                    return Ok(Owner::failed(kappa, mu));
                }
                owner_data(disc, i, kappa, mu, &[]).ok_or(NumericalError::SingularShapeTensor {
                    point: i,
                    position: disc.points.x[i],
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            d,
            owners,
            // The energy formulation's dilatation is tr G, the gradient form.
            gradient_dilatation: gradient_dilatation || energy,
            energy,
            grip: Vec::new(),
        })
    }

    /// The model of `scene` on `disc` ([`Shear::new`]).
    pub fn of(scene: &Scene, disc: &Discretization) -> Result<Self, NumericalError> {
        let model = Self::new(
            disc,
            scene.model.dimension,
            &scene.materials,
            scene.model.gradient_dilatation(),
            scene.model.energy_shear(),
        )?;
        Ok(if model.energy {
            model.with_grips(disc, &super::surface::grip_points(disc, &scene.boundaries))
        } else {
            model
        })
    }

    /// The energy formulation next to grips (module docs, "Grips"): the bonds
    /// between `held` and free points weigh `t w` and see `η/t` (`t`: their free
    /// part, [`super::surface::grip_fractions`]), and a held owner stores no
    /// energy (it belongs to the rigid grip; its recovered stress is zero).
    pub fn with_grips(mut self, disc: &Discretization, held: &[bool]) -> Self {
        let grip = super::surface::grip_fractions(disc, held);
        let affected: Vec<usize> = (0..disc.points.len())
            .filter(|&i| disc.bonds.owned_by(i).any(|b| grip[b] != 1.0))
            .collect();
        self.grip = grip;
        for &i in &affected {
            let (kappa, mu) = (self.owners[i].kappa, self.owners[i].mu);
            if let Some(o) = owner_data(disc, i, kappa, mu, &self.grip) {
                self.owners[i] = o;
            }
        }
        for (o, _) in self.owners.iter_mut().zip(held).filter(|(_, &h)| h) {
            o.kappa = 0.0;
            o.mu = 0.0;
        }
        self
    }

    /// Stress at `owner` for displacements `u` (001 Eq. 32); `linear` selects the
    /// linearised bond forces.
    pub fn stress_at(
        &self,
        disc: &Discretization,
        owner: usize,
        u: &[[f64; 3]],
        linear: bool,
    ) -> Mat3 {
        if self.energy {
            return self.energy_cauchy(disc, owner, u, linear);
        }
        let o = &self.owners[owner];
        let bonds = disc.bonds.owned_by(owner);
        let mut forces = vec![[0.0; 3]; bonds.len()];
        let k = self.family_forces(disc, owner, u, linear, &mut forces);
        let rotation = if k.linear { identity() } else { k.rotation };
        let p = &disc.points;
        let mut acc = [[0.0; 3]; 3];
        for (slot, b) in bonds.enumerate() {
            if !disc.bonds.intact[b] {
                continue;
            }
            let j = disc.bonds.neighbour[b] as usize;
            let xi = sub(&p.x[j], &p.x[owner]);
            let xr = mat_vec(&rotation, &xi);
            // forces[slot] holds f_ij V_i V_j ν_ij: divide V_i out, keep V_j ν_ij.
            let f: [f64; 3] = std::array::from_fn(|a| forces[slot][a] / p.volume[owner]);
            for r in 0..3 {
                for c in 0..3 {
                    acc[r][c] += f[r] * xr[c];
                }
            }
        }
        let mut sigma = [[0.0; 3]; 3];
        for r in 0..self.d {
            for c in 0..self.d {
                sigma[r][c] = o.m / self.d as f64
                    * (0..self.d).map(|k| acc[r][k] * o.k_inv[k][c]).sum::<f64>();
            }
        }
        sigma
    }

    /// The owner's rotation (the polar rotation `R`, or `I + W` linearised) and
    /// dilatation `θ` for displacements `u`.
    fn kinematics(
        &self,
        disc: &Discretization,
        i: usize,
        u: &[[f64; 3]],
        linear: bool,
    ) -> Kinematics {
        let o = &self.owners[i];
        let d = self.d;
        let df = d as f64;
        let p = &disc.points;
        let bonds = &disc.bonds;
        let intact = bonds.owned_by(i).filter(|&b| bonds.intact[b]);
        if linear {
            let mut g = [[0.0; 3]; 3];
            let mut theta = 0.0;
            for b in intact {
                let (j, xi) = bond_vector(disc, i, b);
                let eta = sub(&u[j], &u[i]);
                let w = p.volume[j] * bonds.volume_factor[b] / dot(&xi, &xi);
                let bk = mat_vec(&o.k_inv, &xi);
                for r in 0..3 {
                    for c in 0..3 {
                        g[r][c] += eta[r] * w * bk[c];
                    }
                }
                theta += if self.gradient_dilatation {
                    w * dot(&bk, &eta)
                } else {
                    df / o.m * w * dot(&xi, &eta)
                };
            }
            let skew = std::array::from_fn(|r| std::array::from_fn(|c| 0.5 * (g[r][c] - g[c][r])));
            return Kinematics {
                linear: true,
                rotation: skew,
                theta,
            };
        }
        let mut f = [[0.0; 3]; 3];
        for b in intact.clone() {
            let (j, xi) = bond_vector(disc, i, b);
            let eta = sub(&u[j], &u[i]);
            let w = p.volume[j] * bonds.volume_factor[b] / dot(&xi, &xi);
            for r in 0..d {
                for c in 0..d {
                    f[r][c] += w * (xi[r] + eta[r]) * xi[c];
                }
            }
        }
        let rotation = proper_rotation(&mat_mul(&f, &o.k_inv), d);
        let mut k = Kinematics {
            linear: false,
            rotation,
            theta: 0.0,
        };
        for b in intact {
            let (j, xi) = bond_vector(disc, i, b);
            let eta = sub(&u[j], &u[i]);
            let w = p.volume[j] * bonds.volume_factor[b] / dot(&xi, &xi);
            let (xr, er) = k.rotated(&xi, &eta);
            k.theta += if self.gradient_dilatation {
                w * dot(&er, &mat_vec(&rotation, &mat_vec(&o.k_inv, &xi)))
            } else {
                df / o.m * w * dot(&er, &xr)
            };
        }
        k
    }

    /// Writes the force each bond of `owner` puts on it into `out` (001 Eq. 27-28);
    /// returns the owner's kinematics.
    fn family_forces(
        &self,
        disc: &Discretization,
        i: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [[f64; 3]],
    ) -> Kinematics {
        let o = &self.owners[i];
        let df = self.d as f64;
        let p = &disc.points;
        let bonds = &disc.bonds;
        let first = bonds.offsets[i];
        let k = self.kinematics(disc, i, u, linear);
        for b in bonds.owned_by(i) {
            if !bonds.intact[b] {
                out[b - first] = [0.0; 3];
                continue;
            }
            let (j, xi) = bond_vector(disc, i, b);
            let eta = sub(&u[j], &u[i]);
            let (xr, er) = k.rotated(&xi, &eta);
            let scale =
                df / (dot(&xi, &xi) * o.m) * p.volume[i] * p.volume[j] * bonds.volume_factor[b];
            out[b - first] = std::array::from_fn(|a| {
                let deviatoric = er[a] - k.theta / df * xr[a];
                scale * (o.kappa * k.theta * xr[a] + 2.0 * o.mu * deviatoric)
            });
        }
        k
    }

    /// The deviatoric bond strain `|ε^d| = |η^d|/|ξ|` of every bond of `owner`
    /// into `out` (0 for broken bonds, formulation Sec. 5); returns the owner's
    /// dilatation θ.
    pub fn deviatoric_strains(
        &self,
        disc: &Discretization,
        i: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [f64],
    ) -> f64 {
        let df = self.d as f64;
        let bonds = &disc.bonds;
        let first = bonds.offsets[i];
        let k = self.kinematics(disc, i, u, linear);
        for b in bonds.owned_by(i) {
            out[b - first] = if bonds.intact[b] {
                let (j, xi) = bond_vector(disc, i, b);
                let (xr, er) = k.rotated(&xi, &sub(&u[j], &u[i]));
                let deviatoric: [f64; 3] = std::array::from_fn(|a| er[a] - k.theta / df * xr[a]);
                (dot(&deviatoric, &deviatoric) / dot(&xi, &xi)).sqrt()
            } else {
                0.0
            };
        }
        k.theta
    }
}

/// The energy formulation (module docs): what one owner's kernels share.
impl Shear {
    /// `(j, ξ, w, b)` of every intact bond of owner `i`: the neighbour, the
    /// reference bond, `w = V_j ν/|ξ|²` and `b = w K⁻¹ ξ`.
    fn energy_bonds(&self, disc: &Discretization, i: usize) -> Vec<EnergyBond> {
        let o = &self.owners[i];
        let p = &disc.points;
        let bonds = &disc.bonds;
        bonds
            .owned_by(i)
            .filter(|&b| bonds.intact[b])
            .map(|b| {
                let (j, xi) = bond_vector(disc, i, b);
                let t = self.grip.get(b).copied().unwrap_or(1.0);
                let w = t * p.volume[j] * bonds.volume_factor[b] / dot(&xi, &xi);
                EnergyBond {
                    j,
                    xi,
                    w,
                    b: mat_vec(&o.k_inv, &xi).map(|v| w * v),
                    scale: 1.0 / t,
                }
            })
            .collect()
    }

    /// The owner's displacement gradient `G = Σ η_k ⊗ b_k` (exact for every
    /// affine field, whatever the family).
    fn energy_gradient(bonds: &[EnergyBond], i: usize, u: &[[f64; 3]]) -> Mat3 {
        let mut g = [[0.0; 3]; 3];
        for EnergyBond { j, b, scale, .. } in bonds {
            let eta = sub(&u[*j], &u[i]).map(|v| scale * v);
            for r in 0..3 {
                for c in 0..3 {
                    g[r][c] += eta[r] * b[c];
                }
            }
        }
        g
    }

    /// The owner's stress measure conjugate to `G`: Hooke's law of `G`
    /// (`linear`) or the first Piola-Kirchhoff stress `P = F S` of the
    /// Saint Venant-Kirchhoff energy, `F = I + G`, `S = λ tr E I + 2μ E`,
    /// `E = (FᵀF − I)/2`; `λ = κ − 2μ/d`. Leading `d × d` block.
    fn energy_stress(&self, i: usize, g: &Mat3, linear: bool) -> Mat3 {
        let o = &self.owners[i];
        let d = self.d;
        let lambda = o.kappa - 2.0 * o.mu / d as f64;
        let mut out = [[0.0; 3]; 3];
        if linear {
            let tr: f64 = (0..d).map(|a| g[a][a]).sum();
            for r in 0..d {
                for c in 0..d {
                    out[r][c] = o.mu * (g[r][c] + g[c][r]) + if r == c { lambda * tr } else { 0.0 };
                }
            }
            return out;
        }
        let f: Mat3 = std::array::from_fn(|r| {
            std::array::from_fn(|c| {
                if r < d && c < d {
                    g[r][c] + f64::from(r == c)
                } else {
                    0.0
                }
            })
        });
        let mut e = [[0.0; 3]; 3];
        for r in 0..d {
            for c in 0..d {
                e[r][c] =
                    0.5 * ((0..d).map(|k| f[k][r] * f[k][c]).sum::<f64>() - f64::from(r == c));
            }
        }
        let tr: f64 = (0..d).map(|a| e[a][a]).sum();
        let mut stress = [[0.0; 3]; 3];
        for r in 0..d {
            for c in 0..d {
                stress[r][c] = 2.0 * o.mu * e[r][c] + if r == c { lambda * tr } else { 0.0 };
            }
        }
        for r in 0..d {
            for c in 0..d {
                out[r][c] = (0..d).map(|k| f[r][k] * stress[k][c]).sum();
            }
        }
        out
    }

    /// The penalty's modulus `α_i = 2 d μ / m_i` (module docs).
    fn alpha(&self, i: usize) -> f64 {
        let o = &self.owners[i];
        2.0 * self.d as f64 * o.mu / o.m
    }

    /// The force of every bond of owner `i` on the owner,
    /// `V_i ∂W_i/∂η_j = V_i [P b_j + α (w_j r_j − C b_j)]`, `r_j = η_j − G ξ_j`,
    /// `C = Σ_k w_k r_k ⊗ ξ_k` (module docs), into `out` (0 for broken bonds).
    fn energy_forces(
        &self,
        disc: &Discretization,
        i: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [[f64; 3]],
    ) {
        let bonds = &disc.bonds;
        let first = bonds.offsets[i];
        let family = self.energy_bonds(disc, i);
        let g = Self::energy_gradient(&family, i, u);
        let stress = self.energy_stress(i, &g, linear);
        let residual = |e: &EnergyBond| -> [f64; 3] {
            let eta = sub(&u[e.j], &u[i]).map(|v| e.scale * v);
            std::array::from_fn(|r| eta[r] - (0..3).map(|c| g[r][c] * e.xi[c]).sum::<f64>())
        };
        let mut c = [[0.0; 3]; 3];
        for e in &family {
            let (r, xi, w) = (residual(e), &e.xi, e.w);
            for a in 0..3 {
                for b in 0..3 {
                    c[a][b] += w * r[a] * xi[b];
                }
            }
        }
        let alpha = self.alpha(i);
        let volume = disc.points.volume[i];
        let mut next = family.iter();
        for b in bonds.owned_by(i) {
            out[b - first] = if bonds.intact[b] {
                let e = next.next().expect("one entry per intact bond");
                let r = residual(e);
                let pb = mat_vec(&stress, &e.b);
                let cb = mat_vec(&c, &e.b);
                std::array::from_fn(|a| e.scale * volume * (pb[a] + alpha * (e.w * r[a] - cb[a])))
            } else {
                [0.0; 3]
            };
        }
    }

    /// Recovered stress of the energy formulation: Hooke's law of `G`
    /// (`linear`), or the Cauchy stress `F S Fᵀ / det F`. It is the owner's
    /// own stress: `Σ_j (force of bond j) ⊗ ξ_j / V_i = P` for any family (the
    /// penalty's flux `Σ w r ⊗ ξ − C Σ b ⊗ ξ` vanishes).
    fn energy_cauchy(&self, disc: &Discretization, i: usize, u: &[[f64; 3]], linear: bool) -> Mat3 {
        let family = self.energy_bonds(disc, i);
        let g = Self::energy_gradient(&family, i, u);
        let p = self.energy_stress(i, &g, linear);
        if linear {
            return p;
        }
        let d = self.d;
        let f: Mat3 = std::array::from_fn(|r| {
            std::array::from_fn(|c| {
                if r < d && c < d {
                    g[r][c] + f64::from(r == c)
                } else {
                    f64::from(r == c)
                }
            })
        });
        let det = to_matrix(&f).determinant();
        let mut sigma = [[0.0; 3]; 3];
        for r in 0..d {
            for c in 0..d {
                sigma[r][c] = (0..d).map(|k| p[r][k] * f[c][k]).sum::<f64>() / det;
            }
        }
        sigma
    }

    /// Blocks `K[row][column]` of owner `i` for the energy formulation:
    /// with `β, χ, Kβ, δ` of the column (a neighbour `k`: `b_k`, `w_k ξ_k`,
    /// `K b_k`, `w_k` on row `k` only; the owner: `−Σ b`, `−Σ w ξ`, `−K Σ b`,
    /// `−w_m` on every row `m`), row `m` gets `V_i A_m` and the owner row
    /// `−V_i Σ_m A_m`, where
    /// `A_m = λ b_m ⊗ β + μ [(b_m·β) I + β ⊗ b_m] + α [δ − w_m (β·ξ_m) − b_m·χ + b_m·Kβ] I`.
    fn energy_tangent_column(
        &self,
        disc: &Discretization,
        i: usize,
        column: Column,
        add: &mut dyn FnMut(usize, &Block),
    ) {
        let o = &self.owners[i];
        let d = self.d;
        let bonds = &disc.bonds;
        let p = &disc.points;
        let scale_of = |b: usize| 1.0 / self.grip.get(b).copied().unwrap_or(1.0);
        let (beta, chi, k_beta, own) = match column {
            Column::Neighbour(k) => {
                if !bonds.intact[k] {
                    return;
                }
                let (_, xi) = bond_vector(disc, i, k);
                let w = p.volume[bonds.neighbour[k] as usize] * bonds.volume_factor[k]
                    / (dot(&xi, &xi) * scale_of(k));
                let bk = mat_vec(&o.k_inv, &xi).map(|v| w * v);
                (bk, xi.map(|v| w * v), mat_vec(&o.k, &bk), Some((k, w)))
            }
            Column::Owner => (
                o.b_sum.map(|v| -v),
                o.x_sum.map(|v| -v),
                mat_vec(&o.k, &o.b_sum).map(|v| -v),
                None,
            ),
        };
        let lambda = o.kappa - 2.0 * o.mu / d as f64;
        let alpha = self.alpha(i);
        let volume = p.volume[i];
        let mut owner_block = [[0.0; 3]; 3];
        for b in bonds.owned_by(i) {
            if !bonds.intact[b] {
                continue;
            }
            let (j, xi) = bond_vector(disc, i, b);
            let sm = scale_of(b);
            let w = p.volume[j] * bonds.volume_factor[b] / (dot(&xi, &xi) * sm);
            let bm = mat_vec(&o.k_inv, &xi).map(|v| w * v);
            // The actual block is the effective one (η_eff = s η) times s_m s_k;
            // the owner column's sums carry s_k already (Σ s b = K⁻¹ Σ w ξ).
            let (delta, rows) = match own {
                Some((k, wk)) => (if k == b { wk } else { 0.0 }, sm * scale_of(k)),
                None => (-sm * w, sm),
            };
            let penalty =
                alpha * (delta - w * dot(&beta, &xi) - dot(&bm, &chi) + dot(&bm, &k_beta));
            let bb = dot(&bm, &beta);
            let mut block: Block = [[0.0; 3]; 3];
            for r in 0..d {
                for c in 0..d {
                    let diagonal = if r == c { o.mu * bb + penalty } else { 0.0 };
                    let a = rows * (lambda * bm[r] * beta[c] + o.mu * beta[r] * bm[c] + diagonal);
                    block[r][c] = volume * a;
                    owner_block[r][c] -= volume * a;
                }
            }
            add(j, &block);
        }
        add(i, &owner_block);
    }
}

/// One intact bond of an energy-formulation owner: the neighbour `j`, the
/// reference bond `ξ`, its weight `w = t V_j ν/|ξ|²`, `b = w K⁻¹ ξ`, and the
/// scale `1/t` of its relative displacement (`t`: the bond's free part, 1 away
/// from grips).
struct EnergyBond {
    j: usize,
    xi: [f64; 3],
    w: f64,
    b: [f64; 3],
    scale: f64,
}

/// An owner's rotation and dilatation.
#[derive(Debug, Clone, Copy)]
struct Kinematics {
    /// Whether `rotation` holds the infinitesimal rotation `W` (linearised kernel)
    /// rather than the polar rotation `R`.
    linear: bool,
    rotation: Mat3,
    theta: f64,
}

impl Kinematics {
    /// `(ξ_r, η_r)` of a bond: `(ξ, η − W ξ)` linearised, `(R ξ, ξ + η − R ξ)` otherwise.
    fn rotated(&self, xi: &[f64; 3], eta: &[f64; 3]) -> ([f64; 3], [f64; 3]) {
        let r = mat_vec(&self.rotation, xi);
        if self.linear {
            (*xi, std::array::from_fn(|a| eta[a] - r[a]))
        } else {
            (r, std::array::from_fn(|a| xi[a] + eta[a] - r[a]))
        }
    }
}

/// Neighbour and reference bond vector `ξ` of bond `b` owned by `i`.
#[inline]
fn bond_vector(disc: &Discretization, i: usize, b: usize) -> (usize, [f64; 3]) {
    let j = disc.bonds.neighbour[b] as usize;
    (j, sub(&disc.points.x[j], &disc.points.x[i]))
}

impl Model for Shear {
    fn coupling(&self) -> Coupling {
        Coupling::Family
    }

    fn owner_forces(
        &self,
        disc: &Discretization,
        owner: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [[f64; 3]],
    ) {
        if self.energy {
            self.energy_forces(disc, owner, u, linear, out);
        } else {
            self.family_forces(disc, owner, u, linear, out);
        }
    }

    fn bond_strains(
        &self,
        disc: &Discretization,
        owner: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [f64],
    ) -> Option<f64> {
        Some(self.deviatoric_strains(disc, owner, u, linear, out))
    }

    /// Recomputes `m`, `K⁻¹` and the column sums of each owner from its intact
    /// bonds. An owner whose intact bonds no longer span the space gets zero data
    /// (formulation Sec. 4: it is treated as fully failed) and is returned.
    fn refresh_owners(&mut self, disc: &Discretization, owners: &[usize]) -> Vec<usize> {
        let mut singular = Vec::new();
        for &i in owners {
            let (kappa, mu) = (self.owners[i].kappa, self.owners[i].mu);
            let any_intact = disc.bonds.owned_by(i).any(|b| disc.bonds.intact[b]);
            self.owners[i] = match owner_data(disc, i, kappa, mu, &self.grip) {
                Some(o) => o,
                None => {
                    if any_intact {
                        singular.push(i);
                    }
                    Owner::failed(kappa, mu)
                }
            };
        }
        singular
    }

    fn stress(&self, disc: &Discretization, owner: usize, u: &[[f64; 3]]) -> Option<Block> {
        Some(self.stress_at(disc, owner, u, true))
    }

    fn tangent_column(
        &self,
        disc: &Discretization,
        i: usize,
        column: Column,
        add: &mut dyn FnMut(usize, &Block),
    ) {
        if self.energy {
            return self.energy_tangent_column(disc, i, column, add);
        }
        let o = &self.owners[i];
        let d = self.d;
        let df = d as f64;
        let p = &disc.points;
        let bonds = &disc.bonds;
        // The column's "a" and "b" vectors: a_k, b_k for a neighbour, minus their sums for the owner.
        let (ak, bk, own_k, sign) = match column {
            Column::Neighbour(k) => {
                if !bonds.intact[k] {
                    return;
                }
                let j = bonds.neighbour[k] as usize;
                let xi = sub(&p.x[j], &p.x[i]);
                let w = p.volume[j] * bonds.volume_factor[k] / dot(&xi, &xi);
                let b = mat_vec(&o.k_inv, &xi);
                let a = if self.gradient_dilatation {
                    b.map(|x| w * x)
                } else {
                    xi.map(|x| df / o.m * w * x)
                };
                (a, b.map(|x| w * x), Some(k), 1.0)
            }
            Column::Owner => (
                if self.gradient_dilatation {
                    o.b_sum
                } else {
                    o.a_sum
                },
                o.b_sum,
                None,
                -1.0,
            ),
        };
        let mut owner_block = [[0.0; 3]; 3];
        for b in bonds.owned_by(i) {
            if !bonds.intact[b] {
                continue;
            }
            let j = bonds.neighbour[b] as usize;
            let xi = sub(&p.x[j], &p.x[i]);
            let len2 = dot(&xi, &xi);
            let pre = df / (len2 * o.m);
            let bx = dot(&bk, &xi);
            let diagonal = match own_k {
                Some(k) => f64::from(k == b),
                None => 1.0,
            };
            // A_jk (neighbour column) or Σ_k A_jk (owner column), then the sign of ∂/∂u.
            // K = −∂F/∂u: the owner feels +f V_i V_j ν, the neighbour −f V_i V_j ν.
            let weight = sign * pre * p.volume[i] * p.volume[j] * bonds.volume_factor[b];
            let mut to_neighbour: Block = [[0.0; 3]; 3];
            for r in 0..d {
                for c in 0..d {
                    let delta = f64::from(r == c);
                    let a = (o.kappa - 2.0 * o.mu / df) * xi[r] * ak[c]
                        + 2.0 * o.mu * diagonal * delta
                        - o.mu * (bx * delta - bk[r] * xi[c]);
                    to_neighbour[r][c] = weight * a;
                    owner_block[r][c] -= weight * a;
                }
            }
            add(j, &to_neighbour);
        }
        add(i, &owner_block);
    }
}

/// Weighted volume, inverse shape tensor and the column sums of owner `i`;
/// `None` when the intact bonds do not span the space.
///
/// `grip`: the free part `t` of each bond (energy formulation, module docs
/// "Grips"; empty: 1): `m` and `K` weigh a bond by `t w`, `Σ w ξ` by `w`.
fn owner_data(disc: &Discretization, i: usize, kappa: f64, mu: f64, grip: &[f64]) -> Option<Owner> {
    let d = disc.d;
    let p = &disc.points;
    let bonds = &disc.bonds;
    let (mut m, mut k, mut xw) = (0.0, [[0.0; 3]; 3], [0.0; 3]);
    for b in bonds.owned_by(i).filter(|&b| bonds.intact[b]) {
        let j = bonds.neighbour[b] as usize;
        let xi = sub(&p.x[j], &p.x[i]);
        let w = p.volume[j] * bonds.volume_factor[b] / dot(&xi, &xi);
        let wt = w * grip.get(b).copied().unwrap_or(1.0);
        m += wt * dot(&xi, &xi);
        for r in 0..3 {
            xw[r] += w * xi[r];
            for c in 0..3 {
                k[r][c] += wt * xi[r] * xi[c];
            }
        }
    }
    let k_inv = invert(&k, d)?;
    let df = d as f64;
    Some(Owner {
        m,
        k_inv,
        a_sum: xw.map(|x| df / m * x),
        b_sum: mat_vec(&k_inv, &xw),
        k,
        x_sum: xw,
        kappa,
        mu,
    })
}

/// Inverse of the leading d × d block (zeros elsewhere); `None` if it is singular
/// relative to its size (the determinant of the block divided by its largest
/// diagonal entry below 1e-10). The block is scaled to a unit diagonal first,
/// so its determinant neither under- nor overflows at any length scale (a
/// spacing of 1e-80 m gives entries of 1e-160 and a determinant of 1e-320).
fn invert(k: &Mat3, d: usize) -> Option<Mat3> {
    let scale = (0..d).map(|a| k[a][a]).fold(0.0, f64::max);
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let unit: Mat3 = std::array::from_fn(|r| std::array::from_fn(|c| k[r][c] / scale));
    let mut inv = [[0.0; 3]; 3];
    if d == 2 {
        let m = nalgebra::Matrix2::new(unit[0][0], unit[0][1], unit[1][0], unit[1][1]);
        if m.determinant() <= 1e-10 {
            return None;
        }
        let m = m.try_inverse()?;
        for r in 0..2 {
            for c in 0..2 {
                inv[r][c] = m[(r, c)] / scale;
            }
        }
    } else {
        let m = to_matrix(&unit);
        if m.determinant() <= 1e-10 {
            return None;
        }
        inv = from_matrix(&m.try_inverse()?).map(|row| row.map(|v| v / scale));
    }
    Some(inv)
}

fn to_matrix(m: &Mat3) -> nalgebra::Matrix3<f64> {
    nalgebra::Matrix3::from_fn(|r, c| m[r][c])
}

fn from_matrix(m: &nalgebra::Matrix3<f64>) -> Mat3 {
    std::array::from_fn(|r| std::array::from_fn(|c| m[(r, c)]))
}

fn identity() -> Mat3 {
    from_matrix(&nalgebra::Matrix3::identity())
}

fn mat_vec(m: &Mat3, v: &[f64; 3]) -> [f64; 3] {
    (to_matrix(m) * nalgebra::Vector3::from(*v)).into()
}

fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    from_matrix(&(to_matrix(a) * to_matrix(b)))
}

/// The rotation of the polar decomposition `F = R P` by SVD, made proper.
fn proper_rotation(f: &Mat3, d: usize) -> Mat3 {
    let mut r = identity();
    if d == 2 {
        let m = nalgebra::Matrix2::new(f[0][0], f[0][1], f[1][0], f[1][1]);
        let svd = m.svd(true, true);
        let (mut u, vt) = (svd.u.expect("u computed"), svd.v_t.expect("v computed"));
        if (u * vt).determinant() < 0.0 {
            let smallest = if svd.singular_values[0] < svd.singular_values[1] {
                0
            } else {
                1
            };
            u.column_mut(smallest).neg_mut();
        }
        let rot = u * vt;
        for a in 0..2 {
            for b in 0..2 {
                r[a][b] = rot[(a, b)];
            }
        }
    } else {
        let m = nalgebra::Matrix3::from_fn(|a, b| f[a][b]);
        let svd = m.svd(true, true);
        let (mut u, vt) = (svd.u.expect("u computed"), svd.v_t.expect("v computed"));
        if (u * vt).determinant() < 0.0 {
            let smallest = svd.singular_values.imin();
            u.column_mut(smallest).neg_mut();
        }
        let rot = u * vt;
        for a in 0..3 {
            for b in 0..3 {
                r[a][b] = rot[(a, b)];
            }
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proper_rotation_of_a_rotation_and_a_reflection() {
        let (s, c) = (0.3f64.sin(), 0.3f64.cos());
        let rot = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        let stretched = mat_mul(&rot, &[[1.2, 0.1, 0.0], [0.1, 0.9, 0.0], [0.0, 0.0, 1.0]]);
        for d in [2, 3] {
            let r = proper_rotation(&stretched, d);
            for a in 0..d {
                assert!((0..d).all(|b| (r[a][b] - rot[a][b]).abs() < 1e-12));
            }
        }
        // A reflection gives a proper rotation (det +1), never the reflection.
        let reflect = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let r = proper_rotation(&reflect, 2);
        assert!((r[0][0] * r[1][1] - r[0][1] * r[1][0] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn inverse() {
        let k = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 1.0]];
        let inv = invert(&k, 3).unwrap();
        let id = mat_mul(&k, &inv);
        for a in 0..3 {
            for b in 0..3 {
                assert!((id[a][b] - f64::from(a == b)).abs() < 1e-14);
            }
        }
        assert!(invert(&[[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0; 3]], 2).is_none());
    }
}
