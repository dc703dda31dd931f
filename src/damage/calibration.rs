//! Energy-consistent critical values: what `fracture_energy = G₀` means.
//!
//! The papers' critical values (000 Eq. 12, 001 Eq. 40; [`super`]) make the bonds
//! that cross a unit area of a straight cut in a continuum hold `G₀` at their
//! critical value (the **continuum** calibration). A discrete body dissipates more
//! than that per unit area of crack growth: bonds off the crack line break too
//! (the crack is a band about a spacing wide), and releasing a bond at fixed
//! displacement releases more than its own energy, since its neighbours relax
//! (validation/fracture/README.md, Sec. 2). The ratio
//!
//! ```text
//! D = (energy dissipated per unit area of steady crack growth) / G₀
//! ```
//!
//! is a property of the lattice: of `m = δ/Δx`, the partial-volume rule, the
//! dimension and the criterion. It does not depend on E or G₀: the model is
//! linear between events, so scaling every critical value by `k` scales every
//! event load by `k` and leaves the sequence of breaks unchanged, and the energy
//! scales by `k²`. Neither does it depend on the spacing at fixed `m` (the strip
//! below scales with it). Hence the **dissipation** calibration (the default):
//!
//! ```text
//! s₀ = s₀(continuum) / sqrt(D(m_i))        (bond-based, per owner i, m_i = δ_i/Δx_i)
//! ε^d_max, or the energy criterion's value, / sqrt(D(m_i, ν))   (shear model, mode I)
//! ```
//!
//! makes steady growth dissipate `G₀` per unit area on every owner's lattice.
//!
//! **Lattice trapping and the peak calibration.** Steady growth on a lattice is a
//! saw-tooth: the crack passes one spacing in a cycle of events whose critical
//! loads differ, and the dissipated energy is their energy mean, while the peak
//! load of a specimen is their largest. The strip measures the ratio
//!
//! ```text
//! r = (largest critical grip displacement of a cycle) / (the energy-equivalent one)
//! ```
//!
//! (`validation::fracture::trapping_ratio`). Like `D` it depends on the lattice
//! alone, and at fixed `m` the peak load of a sharp crack tends, as `δ/a → 0`, to
//! `r ×` the LEFM load of the dissipated energy (validation/fracture/README.md).
//! No single scale of the critical values makes both the dissipated energy and the
//! peak load agree with `G₀` (their ratio is `r²`, fixed by the lattice); the
//! **peak** calibration (`fracture.calibration = "peak"`) chooses the peak load:
//!
//! ```text
//! s₀ = s₀(continuum) / (r(m_i) sqrt(D(m_i)))
//! ```
//!
//! so that the largest energy release rate steady growth needs is `G₀`; growth
//! then dissipates `G₀ / r²` per unit area.
//!
//! **How `D` is measured** (`examples/fracture_calibration.rs`, regenerates the
//! tables): a strip of 120 × 30 spacings between clamped grips, split from an
//! edge pre-crack of 20 spacings by the event strategy with the continuum values.
//! Every event releases `Δ (R_critical − R_broken) / 2` at fixed grip
//! displacement `Δ`; that energy is booked at the midpoints of the bonds the
//! event broke, and `D` is the energy booked between `notch + 3δ` and
//! `length − H`, over `G₀` times that length (the profile is flat there: steady
//! growth). Measured as well (validation/fracture/README.md): the crack at 30° and
//! 45° to the grid, a taller strip, other E, G₀ and spacing.
//!
//! With overlap partial volumes (the default) the factor is interpolated linearly
//! between the tabulated `m`; without correction or with the ramp, whose bond
//! sets jump with `m`, it applies at the tabulated `m` only. In 3D the strip is
//! 48 × 12 × 14 spacings (`Strip::new_3d`; `D` booked only for bonds whose
//! midpoints lie 1.5 horizons or more inside both faces: the bulk's lattice, not
//! the faces' skin) and the bond-based model is measured at `m = 3.015` with
//! overlap volumes (only there). Elsewhere (1D, the shear model in 3D, points of
//! a Gmsh mesh: an irregular cloud, not measured) the continuum value is used and
//! the run says so.

use crate::scene::{
    Dimension, EnergyCounting, ShearCriterion, ShearFormulation, SurfaceCorrection,
    VolumeCorrection,
};

/// What the strip measures of one lattice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatticeFactors {
    /// `D`: energy dissipated per unit area of steady growth over `G₀`.
    pub dissipation: f64,
    /// `r`: the largest critical load of a cycle of steady growth over the
    /// energy-equivalent load.
    pub trapping: f64,
}

/// `(m, D, r)` of the bond-based model, 2D, overlap partial volumes (the default),
/// with the surface correction (the default; `cargo run --release --example
/// fracture_calibration -- table`).
const BOND_BASED_2D_OVERLAP: &[(f64, f64, f64)] = &[
    (2.015, 1.4995, 1.1450),
    (2.515, 1.4469, 1.0888),
    (3.015, 1.2355, 1.0620),
    (3.515, 1.2297, 1.0714),
    (4.015, 1.1484, 1.0540),
    (4.515, 1.0955, 1.0648),
    (5.015, 1.0896, 1.0501),
];

/// The same without the surface correction (`surface_correction = "none"`).
const BOND_BASED_2D_OVERLAP_UNCORRECTED: &[(f64, f64, f64)] = &[
    (2.015, 1.5002, 1.1444),
    (2.515, 1.2855, 1.1107),
    (3.015, 1.2358, 1.0613),
    (3.515, 1.2300, 1.0744),
    (4.015, 1.1486, 1.0557),
    (4.515, 1.0957, 1.0653),
    (5.015, 1.0897, 1.0539),
];

/// `(m, D, r)` of the bond-based model, 3D, overlap partial volumes, surface
/// correction, at these `m` only (`cargo run --release --example
/// fracture_calibration -- 3d 3.015`: 14,784 points, 135,216 bonds broken;
/// validation/fracture/README.md Sec. 7).
const BOND_BASED_3D_OVERLAP: &[(f64, f64, f64)] = &[(3.015, 1.0964, 1.0192)];

/// The same without the surface correction (133,760 bonds broken).
const BOND_BASED_3D_OVERLAP_UNCORRECTED: &[(f64, f64, f64)] = &[(3.015, 1.0968, 1.0250)];

/// `(m, D, r)` of the bond-based model, 2D, no partial-volume correction (at these
/// `m` only: without partial volumes the bond set jumps between them), surface
/// correction.
const BOND_BASED_2D_NONE: &[(f64, f64, f64)] = &[(3.015, 1.2753, 1.0695), (4.015, 1.0629, 1.0448)];

/// The same without the surface correction.
const BOND_BASED_2D_NONE_UNCORRECTED: &[(f64, f64, f64)] =
    &[(3.015, 1.2756, 1.0684), (4.015, 1.0631, 1.0477)];

/// `(m, D, r)` of the bond-based model, 2D, 000 Eq. A.1 ramp (at these `m` only),
/// surface correction.
const BOND_BASED_2D_RAMP: &[(f64, f64, f64)] = &[(3.015, 1.0880, 1.0852), (4.015, 0.9710, 1.0501)];

/// The same without the surface correction.
const BOND_BASED_2D_RAMP_UNCORRECTED: &[(f64, f64, f64)] =
    &[(3.015, 1.0694, 1.0841), (4.015, 0.9711, 1.0524)];

/// `(m, D, r)` of the shear model in mode I, 2D, overlap partial volumes, ν = 1/3,
/// energy criterion, pair counting, energy formulation (the default; at these
/// `m` only; `cargo run --release --example fracture_calibration -- modes 3.015`).
const SHEAR_2D_ENERGY: &[(f64, f64, f64)] = &[(3.015, 1.6825, 1.0334)];

/// The same for the deviatoric criterion of 001 Eq. 37.
const SHEAR_2D_DEVIATORIC: &[(f64, f64, f64)] = &[(3.015, 1.8776, 1.0661)];

/// The energy criterion with the paper's force (`model.formulation = "paper"`).
const SHEAR_2D_ENERGY_PAPER: &[(f64, f64, f64)] = &[(3.015, 1.7732, 1.0433)];

/// The deviatoric criterion with the paper's force.
const SHEAR_2D_DEVIATORIC_PAPER: &[(f64, f64, f64)] = &[(3.015, 2.0081, 1.0689)];

/// The Poisson ratio of the shear model's measurements.
const SHEAR_POISSON_RATIO: f64 = 1.0 / 3.0;

/// Why a point keeps its continuum critical value under the dissipation calibration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Uncalibrated {
    /// `m` outside the measured range.
    HorizonFactor,
    /// No table for the dimension (1D; the shear model in 3D; the bond-based
    /// model in 3D other than with overlap volumes at a measured `m`).
    Dimension,
    /// A point of a Gmsh mesh: an irregular cloud.
    Irregular,
    /// The shear model's factor is measured at one Poisson ratio.
    PoissonRatio,
}

impl Uncalibrated {
    /// The reason, for the run's notes.
    pub fn explain(self) -> &'static str {
        match self {
            Uncalibrated::HorizonFactor => "the horizon factor is outside the measured range",
            Uncalibrated::Dimension => {
                "the dissipation factor is measured in 2D, and in 3D only for the bond-based \
                 model with overlap partial volumes at m = 3.015"
            }
            Uncalibrated::Irregular => {
                "points of a Gmsh mesh form an irregular cloud, whose factor is not measured"
            }
            Uncalibrated::PoissonRatio => {
                "the shear model's dissipation factor is measured at poisson_ratio = 1/3 only"
            }
        }
    }
}

/// The lattice factors of a bond-based owner with horizon factor `m` on a
/// regular lattice, or why there are none.
pub fn bond_based_factors(
    dimension: Dimension,
    rule: VolumeCorrection,
    surfaces: SurfaceCorrection,
    m: f64,
) -> Result<LatticeFactors, Uncalibrated> {
    let corrected = surfaces == SurfaceCorrection::Energy;
    let pick = |with, without| if corrected { with } else { without };
    match (dimension, rule) {
        (Dimension::Three, VolumeCorrection::Overlap) => node(
            pick(BOND_BASED_3D_OVERLAP, BOND_BASED_3D_OVERLAP_UNCORRECTED),
            m,
        )
        .ok_or(Uncalibrated::Dimension),
        (Dimension::PlaneStress | Dimension::PlaneStrain, rule) => match rule {
            VolumeCorrection::Overlap => interpolate(
                pick(BOND_BASED_2D_OVERLAP, BOND_BASED_2D_OVERLAP_UNCORRECTED),
                m,
            ),
            VolumeCorrection::None => {
                node(pick(BOND_BASED_2D_NONE, BOND_BASED_2D_NONE_UNCORRECTED), m)
            }
            VolumeCorrection::Ramp => {
                node(pick(BOND_BASED_2D_RAMP, BOND_BASED_2D_RAMP_UNCORRECTED), m)
            }
        }
        .ok_or(Uncalibrated::HorizonFactor),
        _ => Err(Uncalibrated::Dimension),
    }
}

/// The mode-I lattice factors of a shear-model owner with horizon factor `m`
/// and Poisson ratio `nu`, for the pair count of `G₀` (the paper's one-bond count
/// stores twice the energy at the same strain: `2 D`, the same `r`).
pub fn shear_factors(
    dimension: Dimension,
    rule: VolumeCorrection,
    formulation: ShearFormulation,
    criterion: ShearCriterion,
    counting: EnergyCounting,
    nu: f64,
    m: f64,
) -> Result<LatticeFactors, Uncalibrated> {
    if !matches!(dimension, Dimension::PlaneStress | Dimension::PlaneStrain) {
        return Err(Uncalibrated::Dimension);
    }
    if rule != VolumeCorrection::Overlap {
        return Err(Uncalibrated::HorizonFactor);
    }
    if (nu - SHEAR_POISSON_RATIO).abs() > 1e-9 {
        return Err(Uncalibrated::PoissonRatio);
    }
    let table = match (formulation, criterion) {
        (ShearFormulation::Energy, ShearCriterion::Energy) => SHEAR_2D_ENERGY,
        (ShearFormulation::Energy, ShearCriterion::Deviatoric) => SHEAR_2D_DEVIATORIC,
        (ShearFormulation::Paper, ShearCriterion::Energy) => SHEAR_2D_ENERGY_PAPER,
        (ShearFormulation::Paper, ShearCriterion::Deviatoric) => SHEAR_2D_DEVIATORIC_PAPER,
    };
    let pair = node(table, m).ok_or(Uncalibrated::HorizonFactor)?;
    Ok(match counting {
        EnergyCounting::Pair => pair,
        EnergyCounting::OneBond => LatticeFactors {
            dissipation: 2.0 * pair.dissipation,
            ..pair
        },
    })
}

/// The tabulated factors at `m` (to a relative 1e-9), without interpolation.
fn node(table: &[(f64, f64, f64)], m: f64) -> Option<LatticeFactors> {
    table
        .iter()
        .find(|&&(x, _, _)| (x - m).abs() <= 1e-9 * x)
        .map(|&(_, dissipation, trapping)| LatticeFactors {
            dissipation,
            trapping,
        })
}

/// Linear interpolation in a table sorted by its first column; `None` outside it.
/// The ends are widened by a relative 1e-9 so that `m` computed as `δ/Δx`
/// matches a tabulated value.
fn interpolate(table: &[(f64, f64, f64)], m: f64) -> Option<LatticeFactors> {
    let (first, last) = (table.first()?, table.last()?);
    if m < first.0 * (1.0 - 1e-9) || m > last.0 * (1.0 + 1e-9) {
        return None;
    }
    let m = m.clamp(first.0, last.0);
    let k = table
        .partition_point(|&(x, _, _)| x < m)
        .clamp(1, table.len().max(2) - 1);
    if table.len() == 1 {
        return node(table, first.0);
    }
    let ((x0, d0, r0), (x1, d1, r1)) = (table[k - 1], table[k]);
    let t = (m - x0) / (x1 - x0);
    Some(LatticeFactors {
        dissipation: d0 + (d1 - d0) * t,
        trapping: r0 + (r1 - r0) * t,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(f: Option<LatticeFactors>) -> Option<f64> {
        f.map(|f| f.dissipation)
    }

    #[test]
    fn interpolation_hits_the_nodes_and_refuses_outside() {
        let t = [(2.0, 1.5, 1.2), (3.0, 1.2, 1.1), (4.0, 1.1, 1.0)];
        assert_eq!(d(interpolate(&t, 2.0)), Some(1.5));
        assert_eq!(d(interpolate(&t, 4.0)), Some(1.1));
        assert!((d(interpolate(&t, 2.5)).unwrap() - 1.35).abs() < 1e-15);
        assert!((interpolate(&t, 2.5).unwrap().trapping - 1.15).abs() < 1e-15);
        assert!((d(interpolate(&t, 3.5)).unwrap() - 1.15).abs() < 1e-15);
        assert_eq!(interpolate(&t, 1.9), None);
        assert_eq!(interpolate(&t, 4.1), None);
        assert_eq!(interpolate(&[], 3.0), None);
    }

    #[test]
    fn nodes_only_tables_refuse_between_their_nodes() {
        let t = [(3.015, 1.3, 1.06), (4.015, 1.1, 1.05)];
        assert_eq!(d(node(&t, 3.015)), Some(1.3));
        assert_eq!(d(node(&t, 0.1 * 40.15)), Some(1.1));
        assert_eq!(node(&t, 3.5), None);
    }

    /// 3D: the bond-based model at the measured `m` with overlap volumes, and
    /// nothing else (the reason names the dimension).
    #[test]
    fn three_dimensions_at_the_measured_horizon_factor_only() {
        let three =
            |rule, m| bond_based_factors(Dimension::Three, rule, SurfaceCorrection::Energy, m);
        assert_eq!(
            three(VolumeCorrection::Overlap, 3.015).unwrap().dissipation,
            1.0964
        );
        assert_eq!(
            bond_based_factors(
                Dimension::Three,
                VolumeCorrection::Overlap,
                SurfaceCorrection::None,
                3.015
            )
            .unwrap()
            .dissipation,
            1.0968
        );
        for (rule, m) in [
            (VolumeCorrection::Overlap, 3.5),
            (VolumeCorrection::None, 3.015),
            (VolumeCorrection::Ramp, 3.015),
        ] {
            assert_eq!(three(rule, m), Err(Uncalibrated::Dimension));
        }
        assert_eq!(
            bond_based_factors(
                Dimension::One,
                VolumeCorrection::Overlap,
                SurfaceCorrection::Energy,
                3.015
            ),
            Err(Uncalibrated::Dimension)
        );
    }

    #[test]
    fn every_table_is_sorted() {
        for t in [
            BOND_BASED_2D_OVERLAP,
            BOND_BASED_2D_OVERLAP_UNCORRECTED,
            BOND_BASED_3D_OVERLAP,
            BOND_BASED_3D_OVERLAP_UNCORRECTED,
            BOND_BASED_2D_NONE,
            BOND_BASED_2D_NONE_UNCORRECTED,
            BOND_BASED_2D_RAMP,
            BOND_BASED_2D_RAMP_UNCORRECTED,
            SHEAR_2D_ENERGY,
            SHEAR_2D_DEVIATORIC,
            SHEAR_2D_ENERGY_PAPER,
            SHEAR_2D_DEVIATORIC_PAPER,
        ] {
            assert!(t.windows(2).all(|w| w[0].0 < w[1].0));
            assert!(t
                .iter()
                .all(|&(_, d, r)| d.is_finite() && d > 0.0 && r.is_finite() && r >= 1.0));
        }
    }
}
