//! Damage: when a bond breaks (formulation Sec. 5), kept apart from the force
//! kernels. One implementation of each criterion, for every driver that breaks
//! bonds. Bonds never heal; every bond carries its owner's critical value.
//!
//! **Bond-based** (000 Eq. 12, 003 Eq. 36): bond `i→j` breaks when its stretch
//! reaches `s₀(δ_i)`. The critical stretch follows from the fracture energy `G₀`,
//! the energy per unit crack area of every pair of bonds that crosses it, each
//! pair storing `c s² |ξ| / 2` per unit volume² (`c = 2 C_i`, the pair's
//! micromodulus; formulation Sec. 3):
//!
//! ```text
//! 1D:  G₀ = c s₀² δ³ / 6        s₀ = sqrt(6 G₀ / (c δ³))
//! 2D:  G₀ = c s₀² δ⁴ / 4        s₀ = sqrt(4 G₀ / (c δ⁴))        (per unit thickness)
//! 3D:  G₀ = π c s₀² δ⁵ / 10     s₀ = sqrt(10 G₀ / (π c δ⁵))
//! ```
//!
//! With the micromoduli of formulation Sec. 3 these are the tabulated
//! `sqrt(3G₀/(Eδ))`, `sqrt(4πG₀/(9Eδ))` (plane stress), `sqrt(5πG₀/(12Eδ))`
//! (plane strain) and `sqrt(5G₀/(6Eδ))` (3D) (checked in the tests); written
//! through `c` they stay right for a micromodulus matched to another ν
//! (`model.allow_any_poisson`).
//!
//! **Shear model** (001 Eq. 37): bond `i→j` breaks when `|ε^d| ≥ ε^d_max(δ_i)`,
//! `ε^d = η^d/|ξ|`, and `θ_i ≥ 0` or `θ_j ≥ 0` (at least one end in tension).
//! The bond energy at the critical strain is `(dμ/m) (ε^d_max)²` (001 Eq. 38),
//! `m = πδ²` (2D, per unit thickness) or `4πδ³/3` (3D), and the crossing
//! integral of 001 Eq. 39 gives, counting **one** bond per pair as the paper does,
//!
//! ```text
//! 3D:  ε^d_max = (4/3) sqrt(G₀ / (μ δ))          (001 Eq. 40)
//! 2D:  ε^d_max = sqrt(3π G₀ / (4 μ δ))
//! ```
//!
//! Both bonds `i→j` and `j→i` of a pair carry that energy in the model (each
//! owner's family stores its own), so breaking a pair releases twice as much:
//! counting **both** divides `ε^d_max` by √2. dhpd's default is the pair count
//! (`fracture.shear_energy = "pair"`), the one consistent with the energy the
//! model stores, as the bond-based rule is; `"one_bond"` is the paper's.
//!
//! **Shear model, energy criterion** (`fracture.shear_criterion = "energy"`, the
//! default). The deviatoric rule counts only the deviatoric part of a bond's energy;
//! in mode I the dilatation takes about half of the opening strain, so the bonds
//! across a crack are stretched about twice as far as bond-based bonds before they
//! break (validation/fracture/README.md). The energy density of owner `i` in the
//! variational form of the model (formulation Sec. 4) is
//! `W_i = K θ_i²/2 + (d μ/m_i) Σ_j (ε^d_ij)² V_j`; with `ω = 1/|ξ|²` the weights
//! `V_j/m_i` sum to one, so bond `i→j` carries the share
//!
//! ```text
//! e_ij = V_j (K θ_i²/2 + d μ (ε^d_ij)²) / m_i   = V_j q_ij / m_i
//! ```
//!
//! and breaks when `q_ij = K θ_i²/2 + d μ (ε^d_ij)² ≥ q_c` (with the tension check
//! of 001 Eq. 37). The crossing integral of a straight cut (pairs counted twice,
//! as above), `G₀ = 2 (q_c/m) ∫ crossing V V`, with `∫ = 2δ³/3` per unit length
//! (2D, per unit thickness, `m = πδ²`) or `πδ⁴/4` per unit area (3D,
//! `m = 4πδ³/3`), gives
//!
//! ```text
//! 2D:  q_c = 3π G₀ / (4 δ)          3D:  q_c = 8 G₀ / (3 δ)
//! ```
//!
//! which is `d μ (ε^d_max)²` with the pair-counted `ε^d_max` above: the two rules
//! agree where `θ_i = 0` and the energy rule breaks earlier where the bond's owner
//! dilates. The ratio `sqrt(q_ij / q_c)` is positively homogeneous of degree one in
//! the displacements, as the event strategy needs.
//!
//! **Calibration** ([`calibration`]): with `fracture.calibration = "dissipation"`
//! (the default) every critical value from `G₀` above is divided by `sqrt(D)`, the
//! measured excess dissipation of the owner's lattice; with `"peak"` by `r sqrt(D)`,
//! `r` the lattice's trapping ratio (the peak load of a sharp crack then tends to
//! the LEFM load of `G₀`).
//!
//! Damage of a point (formulation Sec. 5): `φ_i = 1 − Σ_intact V_j ν_ij / Σ_all V_j ν_ij`
//! over the bonds it owns.

use crate::discretization::Discretization;
use crate::geometry::grid::Source;
use crate::model::Model;
use crate::scene::{
    Calibration, Dimension, EnergyCounting, FractureParameter, ModelKind, Scene, ShearCriterion,
};
use calibration::{LatticeFactors, Uncalibrated};

pub mod calibration;
use rayon::prelude::*;
use std::f64::consts::PI;

/// A bond breakage criterion with every owner's critical value.
#[derive(Debug, Clone)]
pub struct Criterion {
    /// Critical value of each owner's bonds (∞: they never break).
    critical: Vec<f64>,
    /// Points inside a no-fail zone: a bond with either end here never breaks.
    protected: Vec<bool>,
    /// The shear model's tension check (`θ_i ≥ 0 or θ_j ≥ 0`).
    tension_check: bool,
    /// Shear model, energy criterion: `(K/2, d μ)` of every owner.
    energy_moduli: Option<Vec<(f64, f64)>>,
}

/// Critical stretch of a bond-based owner from `G₀` and the pair micromodulus
/// `c` per unit thickness (2D) or area (1D) (module docs).
pub fn critical_stretch(d: usize, pair_micromodulus: f64, horizon: f64, g0: f64) -> f64 {
    let (c, h) = (pair_micromodulus, horizon);
    match d {
        1 => (6.0 * g0 / (c * h.powi(3))).sqrt(),
        2 => (4.0 * g0 / (c * h.powi(4))).sqrt(),
        _ => (10.0 * g0 / (PI * c * h.powi(5))).sqrt(),
    }
}

/// Critical deviatoric bond strain of a shear-model owner (module docs).
pub fn critical_deviatoric_strain(
    d: usize,
    shear_modulus: f64,
    horizon: f64,
    g0: f64,
    counting: EnergyCounting,
) -> f64 {
    let one_bond = if d == 2 {
        (3.0 * PI * g0 / (4.0 * shear_modulus * horizon)).sqrt()
    } else {
        4.0 / 3.0 * (g0 / (shear_modulus * horizon)).sqrt()
    };
    match counting {
        EnergyCounting::OneBond => one_bond,
        EnergyCounting::Pair => one_bond / std::f64::consts::SQRT_2,
    }
}

/// Which calibration each group of owners received (`summary.json`).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct CalibrationReport {
    /// `fracture.calibration`.
    pub calibration: Calibration,
    /// Owners with a fracture energy, grouped by material, horizon factor and factor.
    pub groups: Vec<CalibratedGroup>,
}

/// Owners of one material and horizon factor with the same calibration.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CalibratedGroup {
    /// Material name.
    pub material: String,
    /// `m = δ/Δx`.
    pub horizon_factor: f64,
    /// The dissipation factor `D` applied (critical value / sqrt(D)); `None`: the continuum value.
    pub dissipation_factor: Option<f64>,
    /// The trapping ratio `r` applied as well (`calibration = "peak"`: critical
    /// value / (r sqrt(D))).
    pub trapping_ratio: Option<f64>,
    /// Why no factor applies under the dissipation calibration.
    pub continuum_because: Option<&'static str>,
    /// Number of owners.
    pub points: usize,
}

impl CalibrationReport {
    /// One line per group that keeps the continuum value under the dissipation
    /// or peak calibration (for the run's notes).
    pub fn notes(&self) -> Vec<String> {
        let name = match self.calibration {
            Calibration::Dissipation => "dissipation",
            Calibration::Peak => "peak",
            Calibration::Continuum => "continuum",
        };
        self.groups
            .iter()
            .filter_map(|g| {
                g.continuum_because.map(|why| {
                    format!(
                        "fracture.calibration = \"{name}\": {} points of material \"{}\" \
                         (m = {:.3}) keep the continuum critical value: {why}",
                        g.points, g.material, g.horizon_factor
                    )
                })
            })
            .collect()
    }

    fn add(&mut self, material: &str, m: f64, applied: &Applied) {
        let (dissipation_factor, trapping_ratio, continuum_because) = match *applied {
            Ok(None) => (None, None, None),
            Ok(Some((d, r))) => (Some(d), r, None),
            Err(why) => (None, None, Some(why.explain())),
        };
        let same = |g: &&mut CalibratedGroup| {
            g.material == material
                && (g.horizon_factor - m).abs() <= 1e-9 * m
                && g.dissipation_factor == dissipation_factor
                && g.trapping_ratio == trapping_ratio
                && g.continuum_because == continuum_because
        };
        match self.groups.iter_mut().find(same) {
            Some(g) => g.points += 1,
            None => self.groups.push(CalibratedGroup {
                material: material.to_string(),
                horizon_factor: m,
                dissipation_factor,
                trapping_ratio,
                continuum_because,
                points: 1,
            }),
        }
    }
}

/// The papers' critical value of owner `i` for fracture energy `g0` (module docs).
fn continuum_critical_value(scene: &Scene, disc: &Discretization, i: usize, g0: f64) -> f64 {
    let p = &disc.points;
    let material = &scene.materials[p.material[i] as usize];
    let horizon = p.horizon[i];
    match scene.model.kind {
        ModelKind::BondBased => {
            // C per volume² including thickness/area; per unit thickness × t.
            let per_unit = if scene.model.dimension == Dimension::Three {
                1.0
            } else {
                scene.model.thickness
            };
            let c = 2.0
                * material.micromodulus(scene.model.dimension, horizon, scene.model.thickness)
                * per_unit;
            critical_stretch(disc.d, c, horizon, g0)
        }
        ModelKind::Shear => {
            let (_, mu) = material.moduli(scene.model.dimension);
            critical_deviatoric_strain(disc.d, mu, horizon, g0, scene.fracture.shear_energy)
        }
    }
}

/// What a calibration applied to an owner: `(D, r)` (`r` under the peak
/// calibration only), nothing (continuum), or why the continuum value is kept.
type Applied = Result<Option<(f64, Option<f64>)>, Uncalibrated>;

/// The lattice factors of owner `i` with horizon factor `m` ([`calibration`]).
fn lattice_factors(
    scene: &Scene,
    disc: &Discretization,
    i: usize,
    m: f64,
) -> Result<LatticeFactors, Uncalibrated> {
    if matches!(disc.points.source[i], Source::Mesh { .. }) {
        return Err(Uncalibrated::Irregular);
    }
    match scene.model.kind {
        ModelKind::BondBased => calibration::bond_based_factors(
            scene.model.dimension,
            scene.discretization.volume_correction,
            scene.discretization.surface_correction,
            m,
        ),
        ModelKind::Shear => calibration::shear_factors(
            scene.model.dimension,
            scene.discretization.volume_correction,
            scene.model.formulation,
            scene.fracture.shear_criterion,
            scene.fracture.shear_energy,
            scene.materials[disc.points.material[i] as usize].poisson_ratio,
            m,
        ),
    }
}

impl Criterion {
    /// Every owner's critical value from its material and horizon, and the no-fail zones.
    #[cfg(feature = "fixtures")]
    pub fn new(scene: &Scene, disc: &Discretization) -> Self {
        Self::with_report(scene, disc).0
    }

    /// [`Criterion::new`], and which calibration every owner with a fracture energy received.
    pub fn with_report(scene: &Scene, disc: &Discretization) -> (Self, CalibrationReport) {
        let p = &disc.points;
        let calibration = scene.fracture.calibration;
        let mut report = CalibrationReport {
            calibration,
            groups: Vec::new(),
        };
        let energy_moduli = (scene.model.kind == ModelKind::Shear
            && scene.fracture.shear_criterion == ShearCriterion::Energy)
            .then(|| {
                (0..p.len())
                    .map(|i| {
                        let material = &scene.materials[p.material[i] as usize];
                        let (kappa, mu) = material.moduli(scene.model.dimension);
                        (0.5 * kappa, disc.d as f64 * mu)
                    })
                    .collect::<Vec<_>>()
            });
        let critical = (0..p.len())
            .map(|i| {
                let material = &scene.materials[p.material[i] as usize];
                // The energy criterion's critical value from ε^d_max: sqrt(d μ) ε^d_max.
                let scale = energy_moduli.as_ref().map_or(1.0, |e| e[i].1.sqrt());
                scale
                    * match material.fracture {
                        None => f64::INFINITY,
                        Some(FractureParameter::CriticalStretch(s0)) => s0,
                        Some(FractureParameter::CriticalDeviatoricStrain(e)) => e,
                        Some(FractureParameter::Energy(g0)) => {
                            let continuum = continuum_critical_value(scene, disc, i, g0);
                            let m = p.horizon[i] / p.spacing[i];
                            let applied: Applied = match calibration {
                                Calibration::Continuum => Ok(None),
                                Calibration::Dissipation => lattice_factors(scene, disc, i, m)
                                    .map(|f| Some((f.dissipation, None))),
                                Calibration::Peak => lattice_factors(scene, disc, i, m)
                                    .map(|f| Some((f.dissipation, Some(f.trapping)))),
                            };
                            report.add(&material.name, m, &applied);
                            match applied {
                                Ok(Some((d, r))) => continuum / (r.unwrap_or(1.0) * d.sqrt()),
                                _ => continuum,
                            }
                        }
                    }
            })
            .collect();
        let protected =
            p.x.iter()
                .map(|x| scene.fracture.no_fail.iter().any(|b| b.contains(x)))
                .collect();
        let criterion = Criterion {
            critical,
            protected,
            tension_check: scene.model.kind == ModelKind::Shear,
            energy_moduli,
        };
        (criterion, report)
    }

    /// The critical value of owner `i`'s bonds.
    #[cfg(feature = "fixtures")]
    pub fn critical(&self, i: usize) -> f64 {
        self.critical[i]
    }

    /// The value at which bond `owner → neighbour` breaks: its owner's critical
    /// value, or ∞ when it may not break (no fracture parameter, or either end
    /// in a no-fail zone). The shear model's tension check comes on top.
    pub fn limit(&self, owner: usize, neighbour: usize) -> f64 {
        if self.protected[owner] || self.protected[neighbour] {
            f64::INFINITY
        } else {
            self.critical[owner]
        }
    }

    /// Writes, for every bond, `value / critical value` for displacements `u`
    /// (0 for a broken bond, a bond that may not break, a compressed bond-based
    /// bond, or a shear bond with both ends in compression). A bond breaks when
    /// its ratio reaches 1. The ratio is positively homogeneous of degree one in
    /// `u` when `linear`: doubling `u` doubles it.
    pub fn ratios<M: Model>(
        &self,
        model: &M,
        disc: &Discretization,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [f64],
    ) {
        let bonds = &disc.bonds;
        let n = disc.points.len();
        let dilatation: Vec<Option<f64>> = crate::csr::split_at_offsets(out, &bonds.offsets)
            .into_par_iter()
            .enumerate()
            .map(|(i, strains)| model.bond_strains(disc, i, u, linear, strains))
            .collect();
        debug_assert_eq!(dilatation.len(), n);
        crate::csr::split_at_offsets(out, &bonds.offsets)
            .into_par_iter()
            .enumerate()
            .for_each(|(i, ratios)| {
                let first = bonds.offsets[i];
                for b in bonds.owned_by(i) {
                    let j = bonds.neighbour[b] as usize;
                    let slot = &mut ratios[b - first];
                    let critical = self.limit(i, j);
                    let eligible = bonds.intact[b]
                        && critical.is_finite()
                        && (!self.tension_check
                            || dilatation[i].is_some_and(|t| t >= 0.0)
                            || dilatation[j].is_some_and(|t| t >= 0.0));
                    let value = match (&self.energy_moduli, dilatation[i]) {
                        (Some(e), Some(theta)) => {
                            let (half_kappa, d_mu) = e[i];
                            (half_kappa * theta * theta + d_mu * *slot * *slot).sqrt()
                        }
                        _ => *slot,
                    };
                    *slot = if eligible {
                        (value / critical).max(0.0)
                    } else {
                        0.0
                    };
                }
            });
    }
}

/// Local damage of every point, `φ_i = 1 − Σ_intact V_j ν_ij / Σ_all V_j ν_ij` over
/// the bonds it owns (0 for a point that owns no bond).
pub fn damage(disc: &Discretization) -> Vec<f64> {
    (0..disc.points.len())
        .into_par_iter()
        .map(|i| point_damage(disc, i))
        .collect()
}

/// Local damage `φ_i` of one point (see [`damage`]).
pub fn point_damage(disc: &Discretization, i: usize) -> f64 {
    let p = &disc.points;
    let bonds = &disc.bonds;
    let (mut intact, mut all) = (0.0, 0.0);
    for b in bonds.owned_by(i) {
        let w = p.volume[bonds.neighbour[b] as usize] * bonds.volume_factor[b];
        all += w;
        if bonds.intact[b] {
            intact += w;
        }
    }
    if all > 0.0 {
        1.0 - intact / all
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Material;

    fn material(e: f64, nu: f64) -> Material {
        Material {
            name: "m".into(),
            youngs_modulus: e,
            poisson_ratio: nu,
            fracture: None,
            density: None,
        }
    }

    /// Through the micromoduli of formulation Sec. 3, the energy balance gives
    /// the closed forms tabulated in formulation Sec. 3 (003 Eq. 36).
    #[test]
    fn critical_stretch_matches_the_tabulated_closed_forms() {
        let (e, g0, delta, t): (f64, f64, f64, f64) = (3.0e10, 200.0, 0.004, 0.01);
        let cases = [
            (Dimension::One, 1, (3.0 * g0 / (e * delta)).sqrt()),
            (
                Dimension::PlaneStress,
                2,
                (4.0 * PI * g0 / (9.0 * e * delta)).sqrt(),
            ),
            (
                Dimension::PlaneStrain,
                2,
                (5.0 * PI * g0 / (12.0 * e * delta)).sqrt(),
            ),
            (Dimension::Three, 3, (5.0 * g0 / (6.0 * e * delta)).sqrt()),
        ];
        for (dim, d, expected) in cases {
            let m = material(e, crate::scene::material::bond_based_poisson_ratio(dim));
            let per_unit = if d == 3 { 1.0 } else { t };
            let c = 2.0 * m.micromodulus(dim, delta, t) * per_unit;
            let s0 = critical_stretch(d, c, delta, g0);
            assert!(
                (s0 / expected - 1.0).abs() < 1e-14,
                "{dim:?}: {s0} vs {expected}"
            );
        }
    }

    /// 001 Eq. 40 in 3D; the 2D form from the same integral; the pair count is
    /// smaller by √2.
    #[test]
    fn critical_deviatoric_strain_forms() {
        let (mu, delta, g0): (f64, f64, f64) = (1.125e10, 0.015, 200.0);
        let eq40 = 4.0 / 3.0 * (g0 / (mu * delta)).sqrt();
        let one = critical_deviatoric_strain(3, mu, delta, g0, EnergyCounting::OneBond);
        assert!((one / eq40 - 1.0).abs() < 1e-15);
        let pair = critical_deviatoric_strain(3, mu, delta, g0, EnergyCounting::Pair);
        assert!((pair * 2f64.sqrt() / one - 1.0).abs() < 1e-15);
        // 2D: G₀ = (2δ³/3)(2μ/(πδ²)) ε² for one bond per pair.
        let e2 = critical_deviatoric_strain(2, mu, delta, g0, EnergyCounting::OneBond);
        let g_back = 2.0 * delta.powi(3) / 3.0 * 2.0 * mu / (PI * delta * delta) * e2 * e2;
        assert!((g_back / g0 - 1.0).abs() < 1e-14);
    }
}
