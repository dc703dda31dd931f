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
//! **Pre-cracks.** A pre-crack (`[[cracks]]`) is treated as the bonds it cuts
//! broken before the first step: the factors are those of the body without it,
//! so its faces are left as soft as the faces of a crack grown by breakage.
//! This keeps a pre-crack and a grown crack of the same shape identical, and
//! the fracture calibration (`damage::calibration`, measured on grown cracks)
//! valid at the pre-crack's tip; with corrected pre-crack faces the
//! dissipation-calibrated SENT peak rose from +3.8 % to +6.8 % of LEFM. The
//! price is the surface error along the pre-crack faces (a stiffness deficit of
//! order `δ` over the crack's length), as along any crack.
//!
//! **Grips.** A point whose every component is prescribed (held by a grip or a
//! clamp) does not deform: the bonds from a free point into a grip are
//! stretched only over the part `t` of their length that lies in the free
//! body, so the material next to a grip is too soft (a bar between two grips
//! behaves as if each grip began 0.28 δ further out, about 3 % of a bar 48
//! spacings long). The continuum picture of a grip of held cells is a clamp
//! on the face of those cells; under a field that is linear up to that face,
//! a crossing bond carries the force it would carry in a continued body if its
//! factor is `1/t` (its energy is then the free part `t` of the continued
//! bond's). So every bond between a held and a free point is multiplied by
//! `1/t`, `t = s/(s + a)` with `s` and `a` the depths of its ends below the
//! boundary between the held and the free points ([`grip_fractions`]; exact
//! for a flat grip along the lattice, `1 ≤ 1/t ≤ 7` at `m = 3`). Points with
//! only some components prescribed (rollers), and held points bonded to no
//! other held point (point supports, [`grip_points`]), are left as they are.
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

/// The moments `Σ κ q(e)` of an infinite lattice of unit spacing about one of
/// its points, with horizon `delta` (in spacings) under the partial-volume
/// `rule` (`κ = V_j ν |ξ|` in units of the point's `V h`: `V_j = 1`). Every
/// moment of this module is in units of its owner's `V_i h_i`, so that none
/// leaves double precision at any spacing the scene accepts.
fn lattice_moments(d: usize, delta: f64, rule: PartialVolume) -> [f64; 6] {
    let h = 1.0;
    let reach = delta + rule.reach(h);
    let n = (reach / h).ceil() as i64;
    let volume = 1.0;
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
/// `e_x⁴` and `e_x²e_y²` (1D: 2, 2D: 3π/4 and π/4, 3D: 4π/5 and 4π/15). In
/// units of `V h` (`delta` in spacings `h`; `thickness` is `h^d t / V`, the
/// thickness over the point's volume in those units).
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
    // One lattice target per distinct horizon in spacings of the grid points.
    let mut lattices: HashMap<u64, [f64; 6]> = HashMap::new();
    for i in 0..p.len() {
        if matches!(p.source[i], Source::Region(_)) {
            let m = p.horizon[i] / p.spacing[i];
            lattices
                .entry(m.to_bits())
                .or_insert_with(|| lattice_moments(d, m, pv));
        }
    }
    let owners: Vec<(Vec<f64>, bool)> = (0..p.len())
        .into_par_iter()
        .map(|i| {
            let bonds = disc.bonds.owned_by(i);
            if disc.share.as_ref().is_some_and(|s| !s.holds(i)) || bonds.is_empty() {
                return (vec![1.0; bonds.len()], true);
            }
            let h = p.spacing[i];
            let target = match p.source[i] {
                Source::Region(_) => lattices[&(p.horizon[i] / h).to_bits()],
                _ => {
                    let slab = if d < 3 { thickness } else { 1.0 };
                    let cell = (0..d).fold(slab / p.volume[i], |c, _| c * h);
                    ball_moments(d, p.horizon[i] / h, cell)
                }
            };
            owner_factors(disc, i, &target)
        })
        .collect();
    let failed = owners.iter().filter(|(_, ok)| !ok).count();
    (owners.into_iter().flat_map(|(g, _)| g).collect(), failed)
}

/// [`factors`] of the body before its pre-cracks, for the bonds of `disc`: a
/// pre-crack is a set of bonds broken before the first step, and the factors
/// are frozen before any break (module docs, "Pre-cracks"). `None` when the
/// uncracked bonds could not be searched (memory): the caller then corrects the
/// pre-crack faces as surfaces and says so.
pub fn factors_before_cracks(
    disc: &Discretization,
    rule: VolumeCorrection,
    thickness: f64,
) -> Option<(Vec<f64>, usize)> {
    let whole = disc.without_cracks(rule).ok()?;
    let (g, unmatched) = factors(&whole, rule, thickness);
    let (cut, all) = (&disc.bonds, &whole.bonds);
    let mut mapped = Vec::with_capacity(cut.neighbour.len());
    for i in 0..disc.points.len() {
        let family = all.owned_by(i);
        // The cracked family is the uncracked one with some bonds left out, in
        // the same order: walk both; search the whole family if that fails.
        let mut k = family.start;
        for b in cut.owned_by(i) {
            let j = cut.neighbour[b];
            while k < family.end && all.neighbour[k] != j {
                k += 1;
            }
            if k == family.end {
                k = family.clone().find(|&c| all.neighbour[c] == j)?;
            }
            mapped.push(g[k]);
            k += 1;
        }
    }
    Some((mapped, unmatched))
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
        // In units of the owner's V h (module docs of `lattice_moments`).
        kappa.push(p.volume[j] / p.volume[i] * disc.bonds.volume_factor[b] * (len / p.spacing[i]));
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
            let ball = ball_moments(d, 12.0, 1.0);
            let lat = lattice_moments(d, 12.0, pv);
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

/// The points of grips: every component prescribed by `boundaries`, bonded
/// to another such point, and prescribed the same displacement as every held
/// point they are bonded to (a rigid block). A held point with no held
/// neighbour is a point support (a pin), and held points with different
/// values side by side prescribe a deforming field (layers that carry an
/// exact solution): neither is a grip with a face, and both are left as they
/// are (the correction is exact for fields that vanish on a rigid grip's face).
pub fn grip_points(disc: &Discretization, boundaries: &[crate::scene::Prescribed]) -> Vec<bool> {
    let d = disc.d;
    let n = disc.points.len();
    let mut value: Vec<[Option<f64>; 3]> = vec![[None; 3]; n];
    for bc in boundaries {
        // An unknown group is reported by the degrees of freedom; skip it here.
        let Ok(points) = crate::discretization::groups::select(disc, &bc.selection, "") else {
            continue;
        };
        for i in points {
            for c in 0..d {
                if value[i][c].is_none() {
                    value[i][c] = bc.values[c];
                }
            }
        }
    }
    let held: Vec<bool> = value
        .iter()
        .map(|v| v[..d].iter().all(Option::is_some))
        .collect();
    let bonds = &disc.bonds;
    (0..n)
        .map(|i| {
            if !held[i] {
                return false;
            }
            let neighbours = bonds
                .owned_by(i)
                .map(|b| bonds.neighbour[b] as usize)
                .chain(bonds.incoming(i).iter().map(|&(o, _)| o as usize))
                .filter(|&j| held[j]);
            let mut any = false;
            for j in neighbours {
                if value[j][..d] != value[i][..d] {
                    return false;
                }
                any = true;
            }
            any
        })
        .collect()
}

/// The part `t` of every bond that lies on the free side of the boundary
/// between held and free points: `t = s/(s + a)` for a bond between a held
/// and a free point (`s`, `a`: the depths of its free and held ends, each the
/// distance to the nearest point of the other side less that point's half
/// spacing; exact for a flat boundary along the lattice), 1 for every other
/// bond. Module docs, "Grips".
pub fn grip_fractions(disc: &Discretization, held: &[bool]) -> Vec<f64> {
    let p = &disc.points;
    let bonds = &disc.bonds;
    let n = p.len();
    let mut depth = vec![f64::INFINITY; n];
    for i in 0..n {
        for b in bonds.owned_by(i) {
            let j = bonds.neighbour[b] as usize;
            if held[i] != held[j] {
                let r = norm(&sub(&p.x[j], &p.x[i]));
                depth[i] = depth[i].min(r - 0.5 * p.spacing[j]);
                depth[j] = depth[j].min(r - 0.5 * p.spacing[i]);
            }
        }
    }
    let mut t = vec![1.0; bonds.len()];
    for i in 0..n {
        for b in bonds.owned_by(i) {
            let j = bonds.neighbour[b] as usize;
            if held[i] != held[j] {
                let (s, a) = if held[i] {
                    (depth[j], depth[i])
                } else {
                    (depth[i], depth[j])
                };
                if s > 0.0 && a > 0.0 {
                    t[b] = s / (s + a);
                }
            }
        }
    }
    t
}
