//! Partial-volume factors `ν_ij` at the rim of a horizon (formulation Sec. 6;
//! 000 App. A).
//!
//! A neighbour `j` is represented by its equivalent segment (1D, half-length
//! `r_j = Δ_j/2`), disc (2D, `r_j = Δ_j/√π`, same area as its cell) or ball
//! (3D, `r_j = Δ_j (3/4π)^{1/3}`, same volume). With the default rule,
//! `Overlap`, `ν_ij` is the fraction of that shape inside the horizon ball of
//! radius `δ_i` (000 Eq. A.2 in 2D, A.3 in 3D, the exact interval overlap in
//! 1D), so a neighbour whose centre lies just outside `δ_i` still counts, up
//! to `δ_i + r_j`.
//!
//! Why this default: for a 2D grid with `δ = 3.015Δ` the discrete bond sum of
//! the interior stiffness, `Σ_j ν_j V_j cos⁴θ |ξ|`, relative to its continuum
//! value `πδ³/4`, is 1.0095 with `Overlap`, 0.861 with the printed ramp of
//! Eq. A.1 (`Ramp`: 1 up to `δ − Δ/2`, falling to 1/2 at `δ`, none beyond)
//! and 1.037 with no correction (`None`): the printed ramp makes a plate 14 %
//! too soft (see `validation/bimaterial_bar/README.md`). In 1D at `3.015Δ` the
//! rules `Overlap` and `Ramp` coincide and are exact.

use crate::scene::VolumeCorrection;
use std::f64::consts::PI;

/// The partial-volume rule in a given dimension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartialVolume {
    /// Rule.
    pub rule: VolumeCorrection,
    /// Dimension.
    pub d: usize,
}

impl PartialVolume {
    /// Equivalent radius of a point of spacing `spacing`.
    pub fn equivalent_radius(&self, spacing: f64) -> f64 {
        match (self.rule, self.d) {
            (VolumeCorrection::Ramp, _) | (_, 1) => 0.5 * spacing,
            (_, 2) => spacing / PI.sqrt(),
            _ => spacing * (3.0 / (4.0 * PI)).cbrt(),
        }
    }

    /// How far beyond `δ_i` a neighbour of spacing `spacing` can still be bonded.
    pub fn reach(&self, spacing: f64) -> f64 {
        match self.rule {
            VolumeCorrection::Overlap => self.equivalent_radius(spacing),
            VolumeCorrection::Ramp | VolumeCorrection::None => 0.0,
        }
    }

    /// `ν_ij` for a neighbour at `distance` with spacing `spacing`, horizon `horizon`.
    pub fn factor(&self, distance: f64, horizon: f64, spacing: f64) -> f64 {
        let r = self.equivalent_radius(spacing);
        match self.rule {
            VolumeCorrection::None => f64::from(distance <= horizon),
            VolumeCorrection::Ramp => {
                if distance <= horizon - r {
                    1.0
                } else if distance <= horizon {
                    (horizon + r - distance) / (2.0 * r)
                } else {
                    0.0
                }
            }
            // In units of r: the overlaps' products of four lengths would leave
            // double precision at spacings far from 1 m (1e-82 m: 1e-328).
            VolumeCorrection::Overlap => match self.d {
                1 => ((horizon + r - distance) / (2.0 * r)).clamp(0.0, 1.0),
                2 => disc_overlap(horizon / r, 1.0, distance / r) / PI,
                _ => ball_overlap(horizon / r, 1.0, distance / r) / (4.0 / 3.0 * PI),
            },
        }
    }
}

/// Area of the intersection of discs of radii `big` and `small` whose centres are `dist` apart (000 Eq. A.2).
pub fn disc_overlap(big: f64, small: f64, dist: f64) -> f64 {
    if dist >= big + small {
        return 0.0;
    }
    if dist <= (big - small).abs() {
        return PI * big.min(small).powi(2);
    }
    let a = small
        * small
        * ((dist * dist + small * small - big * big) / (2.0 * dist * small))
            .clamp(-1.0, 1.0)
            .acos();
    let b = big
        * big
        * ((dist * dist + big * big - small * small) / (2.0 * dist * big))
            .clamp(-1.0, 1.0)
            .acos();
    let c = 0.5
        * ((-dist + small + big)
            * (dist + small - big)
            * (dist - small + big)
            * (dist + small + big))
            .max(0.0)
            .sqrt();
    a + b - c
}

/// Volume of the intersection of balls of radii `big` and `small` whose centres are `dist` apart (000 Eq. A.3).
pub fn ball_overlap(big: f64, small: f64, dist: f64) -> f64 {
    if dist >= big + small {
        return 0.0;
    }
    if dist <= (big - small).abs() {
        return 4.0 / 3.0 * PI * big.min(small).powi(3);
    }
    PI * (big + small - dist).powi(2)
        * (dist * dist + 2.0 * dist * small - 3.0 * small * small
            + 2.0 * dist * big
            + 6.0 * small * big
            - 3.0 * big * big)
        / (12.0 * dist)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disc_overlap_limits_and_half() {
        assert_eq!(disc_overlap(3.0, 0.5, 4.0), 0.0);
        assert!((disc_overlap(3.0, 0.5, 1.0) - PI * 0.25).abs() < 1e-15);
        // Two equal discs at distance r: lens area (2π/3 − √3/2) r².
        let lens = (2.0 * PI / 3.0 - 3f64.sqrt() / 2.0) * 4.0;
        assert!((disc_overlap(2.0, 2.0, 2.0) - lens).abs() < 1e-12);
    }

    #[test]
    fn ball_overlap_limits_and_equal_balls() {
        assert_eq!(ball_overlap(3.0, 0.5, 4.0), 0.0);
        assert!((ball_overlap(3.0, 0.5, 1.0) - 4.0 / 3.0 * PI * 0.125).abs() < 1e-15);
        // Two unit balls at distance 1: lens volume 5π/12.
        assert!((ball_overlap(1.0, 1.0, 1.0) - 5.0 * PI / 12.0).abs() < 1e-12);
    }

    #[test]
    fn overlap_rule_is_continuous_and_bounded() {
        for d in 1..=3 {
            let pv = PartialVolume {
                rule: VolumeCorrection::Overlap,
                d,
            };
            let mut last = 1.0;
            for k in 0..=400 {
                let dist = 2.0 + k as f64 * 0.005;
                let f = pv.factor(dist, 3.0, 1.0);
                assert!((0.0..=1.0).contains(&f) && f <= last + 1e-12);
                last = f;
            }
            assert_eq!(pv.factor(3.0 + pv.reach(1.0) + 1e-9, 3.0, 1.0), 0.0);
        }
    }
}
