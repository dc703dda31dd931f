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
//! **Surface correction** (optional, `model.dilatation = "gradient"`): the
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
                owner_data(disc, i, kappa, mu).ok_or(NumericalError::SingularShapeTensor {
                    point: i,
                    position: disc.points.x[i],
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            d,
            owners,
            gradient_dilatation,
        })
    }

    /// The model of `scene` on `disc` ([`Shear::new`]).
    pub fn of(scene: &Scene, disc: &Discretization) -> Result<Self, NumericalError> {
        Self::new(
            disc,
            scene.model.dimension,
            &scene.materials,
            scene.model.gradient_dilatation(),
        )
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
        self.family_forces(disc, owner, u, linear, out);
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
            self.owners[i] = match owner_data(disc, i, kappa, mu) {
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
fn owner_data(disc: &Discretization, i: usize, kappa: f64, mu: f64) -> Option<Owner> {
    let d = disc.d;
    let p = &disc.points;
    let bonds = &disc.bonds;
    let (mut m, mut k, mut xw) = (0.0, [[0.0; 3]; 3], [0.0; 3]);
    for b in bonds.owned_by(i).filter(|&b| bonds.intact[b]) {
        let j = bonds.neighbour[b] as usize;
        let xi = sub(&p.x[j], &p.x[i]);
        let w = p.volume[j] * bonds.volume_factor[b] / dot(&xi, &xi);
        m += w * dot(&xi, &xi);
        for r in 0..3 {
            xw[r] += w * xi[r];
            for c in 0..3 {
                k[r][c] += w * xi[r] * xi[c];
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
