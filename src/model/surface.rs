//! Surface correction of the bond-based model (`discretization.surface_correction`).
//!
//! **Why.** Under a homogeneous strain `ε` the bonds of owner `i` store
//! (formulation Sec. 3, linearised)
//!
//! ```text
//! W_i(ε) = ½ Σ_b C_i V_i V_j ν_b |ξ_b| (e_b·ε e_b)² = ½ C_i V_i Σ_b κ_b (e_b ⊗ e_b ⊗ e_b ⊗ e_b) :: (ε ⊗ ε),
//! κ_b = V_j ν_b |ξ_b|,
//! ```
//!
//! so the owner's stiffness is the fourth moment `M_i = Σ_b κ_b e_b⊗e_b⊗e_b⊗e_b` of
//! its family. Where the family is full, `M_i` is the bulk's and DH-PD is exact
//! (each owner carries the energy of its own cell: 000 Eq. 11 is calibrated so).
//! Where a free surface, a hole or a pre-crack cuts the horizon, `M_i` misses the
//! bonds beyond it and the point is too soft: 3D bodies with 8 points through
//! their thickness lose 13-31 % of their stiffness (issue 33).
//!
//! **What.** Each bond of owner `i` is scaled by a factor `g_b > 0` chosen so that
//! the owner's corrected moments equal those of its full family,
//! `Σ_b g_b κ_b q(e_b) = M̄_i`, while staying as close to 1 as possible in the sense
//!
//! ```text
//! minimise Σ_b κ_b (g_b ln g_b − g_b + 1)   subject to   Σ_b g_b κ_b q(e_b) = M̄_i,
//! ```
//!
//! with `q(e)` the monomials of degree 4 of `e` with even exponents (`e_x⁴` in 1D;
//! `e_x⁴, e_x²e_y², e_y⁴` in 2D; the six `e_a⁴, e_a²e_b²` in 3D). The solution is
//! `g_b = exp(λ_i·q(e_b))`, with `λ_i` the minimiser of the convex dual
//! `Φ(λ) = Σ_b κ_b exp(λ·q(e_b)) − λ·M̄_i` (Newton's method with backtracking;
//! 1, 3 or 6 unknowns per owner), so every factor is positive and the factor
//! varies smoothly with the bond's direction. The monomials with an odd
//! exponent vanish for every family symmetric about the lattice planes (flat
//! faces, edges and corners of grid bodies); they are left out because at an
//! edge or a corner no positive factors can make them vanish (the family lies
//! in one quadrant), while the even moments are always reachable.
//!
//! **Properties.** The factor belongs to the bond's owner, like every other bond
//! parameter in DH-PD; each bond still adds the symmetric `g k e ⊗ e` to `K`, so `K`
//! stays symmetric positive semi-definite, rigid motions give no force, and a
//! bond keeps its direction. An owner whose moments equal the target to 1e-10
//! (a full family) keeps `g = 1` exactly: its bonds, and the columns of `K` of
//! points all of whose bonds belong to such owners, are bitwise as without the
//! correction. The factors are computed once from the reference configuration
//! and frozen: breaking a bond during fracture or dynamics removes it with its
//! factor and recomputes nothing.
//!
//! **Targets.** A grid point (a region) is matched to the family it would have in
//! the infinite lattice of its own spacing and horizon under the same
//! partial-volume rule (the discrete bulk: interior points are untouched). An
//! imported point (point file, mesh) has no lattice: it is matched to the
//! continuum moments of its horizon ball, `∫_{|ξ|<δ} |ξ| q(e) dV`, so every
//! imported point is corrected, interior ones included (this also removes the
//! anisotropy of an irregular cloud's families).

use crate::discretization::partial_volume::PartialVolume;
use crate::discretization::Discretization;
use crate::geometry::grid::Source;
use crate::scene::VolumeCorrection;
use crate::vector::{norm, sub};
use std::collections::HashMap;
use std::f64::consts::PI;

/// Relative mismatch of an owner's moments below which its family counts as full.
const FULL: f64 = 1e-10;

/// Largest mismatch of a matched owner's moments, relative to the largest
/// target moment: 100 times the round-off of a sum of a few hundred terms.
const MATCHED: f64 = 1e-11;

/// Newton iterations per owner (the dual converges in 4-12 on every family seen).
const MAX_NEWTON: usize = 80;

/// The even degree-4 monomials of a direction in `d` dimensions (module docs).
fn monomials(d: usize, e: &[f64; 3]) -> ([f64; 6], usize) {
    let [x, y, z] = e.map(|v| v * v);
    match d {
        1 => ([x * x, 0.0, 0.0, 0.0, 0.0, 0.0], 1),
        2 => ([x * x, x * y, y * y, 0.0, 0.0, 0.0], 3),
        _ => ([x * x, y * y, z * z, x * y, x * z, y * z], 6),
    }
}

/// The moments `Σ κ q(e)` of an infinite lattice of spacing `h` about one of
/// its points, with horizon `delta` under the partial-volume `rule`
/// (`κ = V_j ν |ξ|`, `V_j = h^d · thickness`).
fn lattice_moments(d: usize, h: f64, delta: f64, rule: PartialVolume, thickness: f64) -> [f64; 6] {
    let reach = delta + rule.reach(h);
    let n = (reach / h).ceil() as i64;
    let volume = h.powi(d as i32) * if d < 3 { thickness } else { 1.0 };
    let span = |a: usize| if a < d { -n..=n } else { 0..=0 };
    let mut m = [0.0; 6];
    for k in span(2) {
        for j in span(1) {
            for i in span(0) {
                if (i, j, k) == (0, 0, 0) {
                    continue;
                }
                let xi = [i as f64 * h, j as f64 * h, k as f64 * h];
                let len = norm(&xi);
                let nu = rule.factor(len, delta, h);
                if nu <= 0.0 {
                    continue;
                }
                let (q, _) = monomials(d, &xi.map(|v| v / len));
                for (a, qa) in q.iter().enumerate() {
                    m[a] += volume * nu * len * qa;
                }
            }
        }
    }
    m
}

/// The continuum moments `∫_{|ξ|<δ} |ξ| q(e) dV` of a horizon ball (`dV`
/// includes the thickness in 2D): `∫ r^d dr` times the angular integrals of
/// `e_x⁴` and `e_x²e_y²` (1D: 2, 2D: 3π/4 and π/4, 3D: 4π/5 and 4π/15).
fn ball_moments(d: usize, delta: f64, thickness: f64) -> [f64; 6] {
    let radial = delta.powi(d as i32 + 1) / (d as f64 + 1.0);
    match d {
        1 => [2.0 * radial * thickness, 0.0, 0.0, 0.0, 0.0, 0.0],
        2 => {
            let (a, b) = (
                0.75 * PI * radial * thickness,
                0.25 * PI * radial * thickness,
            );
            [a, b, a, 0.0, 0.0, 0.0]
        }
        _ => {
            let (a, b) = (0.8 * PI * radial, 4.0 / 15.0 * PI * radial);
            [a, a, a, b, b, b]
        }
    }
}

/// The surface factor of every bond (1 where the owner's family is full), and
/// how many owners could not be matched (kept at 1; their families do not
/// reach the moments of a full one, e.g. a body one point thick).
///
/// On a body discretised over several processes, only the owners whose
/// families this process holds (`disc.share`) are computed; the others keep 1.
pub fn factors(disc: &Discretization, rule: VolumeCorrection, thickness: f64) -> (Vec<f64>, usize) {
    use rayon::prelude::*;
    let d = disc.d;
    let pv = PartialVolume { rule, d };
    let p = &disc.points;
    // One lattice target per distinct (spacing, horizon) of the grid points.
    let mut lattices: HashMap<(u64, u64), [f64; 6]> = HashMap::new();
    for i in 0..p.len() {
        if matches!(p.source[i], Source::Region(_)) {
            lattices
                .entry((p.spacing[i].to_bits(), p.horizon[i].to_bits()))
                .or_insert_with(|| lattice_moments(d, p.spacing[i], p.horizon[i], pv, thickness));
        }
    }
    let owners: Vec<(Vec<f64>, bool)> = (0..p.len())
        .into_par_iter()
        .map(|i| {
            let bonds = disc.bonds.owned_by(i);
            if disc.share.as_ref().is_some_and(|s| !s.holds(i)) || bonds.is_empty() {
                return (vec![1.0; bonds.len()], true);
            }
            let target = match p.source[i] {
                Source::Region(_) => lattices[&(p.spacing[i].to_bits(), p.horizon[i].to_bits())],
                _ => ball_moments(d, p.horizon[i], thickness),
            };
            owner_factors(disc, i, &target)
        })
        .collect();
    let failed = owners.iter().filter(|(_, ok)| !ok).count();
    (owners.into_iter().flat_map(|(g, _)| g).collect(), failed)
}

/// The factors of owner `i`'s bonds for the moments `target` (module docs);
/// `false` when the dual did not converge (the factors are then all 1).
fn owner_factors(disc: &Discretization, i: usize, target: &[f64; 6]) -> (Vec<f64>, bool) {
    let d = disc.d;
    let p = &disc.points;
    let bonds = disc.bonds.owned_by(i);
    let mut kappa = Vec::with_capacity(bonds.len());
    let mut q = Vec::with_capacity(bonds.len());
    let mut k = 0;
    for b in bonds.clone() {
        let j = disc.bonds.neighbour[b] as usize;
        let xi = sub(&p.x[j], &p.x[i]);
        let len = norm(&xi);
        let (qb, kk) = monomials(d, &xi.map(|v| v / len));
        k = kk;
        kappa.push(p.volume[j] * disc.bonds.volume_factor[b] * len);
        q.push(qb);
    }
    // Scale so that the target's largest moment is 1 (λ is then of order 1).
    let scale = target[..k].iter().fold(0.0f64, |m, &t| m.max(t.abs()));
    let moments = |g: &dyn Fn(usize) -> f64| {
        let mut m = [0.0; 6];
        for (b, qb) in q.iter().enumerate() {
            let w = kappa[b] * g(b) / scale;
            for a in 0..k {
                m[a] += w * qb[a];
            }
        }
        m
    };
    let t: Vec<f64> = target[..k].iter().map(|v| v / scale).collect();
    let m0 = moments(&|_| 1.0);
    if (0..k).all(|a| (m0[a] - t[a]).abs() <= FULL) {
        return (vec![1.0; q.len()], true);
    }
    let exponent = |lambda: &[f64; 6], b: usize| (0..k).map(|a| lambda[a] * q[b][a]).sum::<f64>();
    let dual = |lambda: &[f64; 6]| {
        let sum: f64 = (0..q.len())
            .map(|b| kappa[b] / scale * exponent(lambda, b).exp())
            .sum();
        sum - (0..k).map(|a| lambda[a] * t[a]).sum::<f64>()
    };
    let mut lambda = [0.0; 6];
    for _ in 0..MAX_NEWTON {
        let g: Vec<f64> = (0..q.len()).map(|b| exponent(&lambda, b).exp()).collect();
        let m = moments(&|b| g[b]);
        let grad: Vec<f64> = (0..k).map(|a| m[a] - t[a]).collect();
        if grad.iter().all(|v| v.abs() <= MATCHED) {
            return (g, true);
        }
        let mut hessian = nalgebra::DMatrix::<f64>::zeros(k, k);
        for (b, qb) in q.iter().enumerate() {
            let w = kappa[b] * g[b] / scale;
            for r in 0..k {
                for c in 0..k {
                    hessian[(r, c)] += w * qb[r] * qb[c];
                }
            }
        }
        let Some(step) = hessian.cholesky().map(|ch| {
            ch.solve(&nalgebra::DVector::from_iterator(
                k,
                grad.iter().map(|v| -v),
            ))
        }) else {
            break;
        };
        let slope: f64 = (0..k).map(|a| grad[a] * step[a]).sum();
        let here = dual(&lambda);
        let mut tau = 1.0;
        let next = loop {
            let trial: [f64; 6] =
                std::array::from_fn(|a| lambda[a] + if a < k { tau * step[a] } else { 0.0 });
            // Near the minimum the decrease falls below the round-off of Φ:
            // the Newton step is then taken whole (it converges quadratically).
            let negligible = -slope <= 1e-12 * here.abs();
            if negligible || dual(&trial) <= here + 1e-4 * tau * slope || tau < 1e-12 {
                break trial;
            }
            tau *= 0.5;
        };
        lambda = next;
    }
    (vec![1.0; q.len()], false)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lattice moments converge to the continuum ball's as the horizon grows
    /// in spacings (the overlap rule), and the ball's are isotropic: in 2D
    /// `e_x⁴ : e_x²e_y² = 3 : 1`, in 3D too.
    #[test]
    fn lattice_tends_to_the_ball() {
        for d in [1, 2, 3] {
            let pv = PartialVolume {
                rule: VolumeCorrection::Overlap,
                d,
            };
            let ball = ball_moments(d, 1.0, 1.0);
            let lat = lattice_moments(d, 1.0 / 12.0, 1.0, pv, 1.0);
            assert!(
                (lat[0] / ball[0] - 1.0).abs() < 5e-3,
                "d = {d}: {:?} vs {:?}",
                lat,
                ball
            );
            let cross = if d == 3 { 3 } else { 1 };
            if d > 1 {
                assert!((ball[0] / ball[cross] - 3.0).abs() < 1e-12);
                assert!(
                    (lat[cross] / ball[cross] - 1.0).abs() < 1e-2,
                    "d = {d}: {lat:?} vs {ball:?}"
                );
            }
        }
    }
}
