//! Bond breakage: `[fracture]` (how fracture energies become critical values,
//! the shear model's criterion, no-fail zones; shared by every driver that
//! breaks bonds) and `[quasi_static]` (the load stepping of a fracture run
//! under prescribed displacement, formulation Sec. 5).

use super::boundary::{Load, Prescribed};
use super::fields::{aabb, positive, Aabb};
use super::material::Material;
use super::spec::{
    Calibration, EnergyCounting, QuasiStaticSpec, SceneSpec, ShearCriterion, Strategy,
};
use crate::error::{num, InputError};

/// Bond breakage settings shared by the drivers that break bonds.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FractureSettings {
    /// Shear model: energy counting of `fracture_energy`.
    pub shear_energy: EnergyCounting,
    /// How `fracture_energy` becomes a critical value.
    pub calibration: Calibration,
    /// Shear model: the breakage criterion.
    pub shear_criterion: ShearCriterion,
    /// Boxes where no bond breaks.
    pub no_fail: Vec<Aabb>,
}

/// Validated quasi-static settings (formulation Sec. 5, sequentially linear breakage).
#[derive(Debug, Clone, PartialEq)]
pub struct QuasiStatic {
    /// Breakage strategy.
    pub strategy: Strategy,
    /// Largest load factor.
    pub max_load_factor: f64,
    /// Uniform steps up to `max_load_factor` (`all`, `most_critical`).
    pub steps: usize,
    /// Halve a step that breaks more than this many bonds.
    pub max_broken_per_step: Option<usize>,
    /// Smallest step when halving, as a fraction of the uniform step.
    pub min_step_fraction: f64,
    /// Relative tolerance on the largest ratio for bonds that break together.
    pub tolerance: f64,
    /// Re-solves allowed within one step.
    pub max_resolves: usize,
    /// Events allowed (`event`).
    pub max_events: usize,
    /// End once every reaction is below this fraction of its peak.
    pub stop_after_peak: Option<f64>,
}

/// Smallest load step of the stepped fracture strategies, relative to
/// `max_load_factor` (bounds `quasi_static.min_step_fraction` from below).
pub const MIN_STEP_RELATIVE: f64 = 1e-12;

/// Validates `[fracture]` and `[quasi_static]`: a fracture run needs a material
/// that breaks and a non-zero load to scale.
pub(super) fn validate(
    spec: &SceneSpec,
    materials: &[Material],
    boundaries: &[Prescribed],
    loads: &[Load],
    d: usize,
) -> Result<(FractureSettings, Option<QuasiStatic>), InputError> {
    let fracture = fracture_settings(spec, d)?;
    let Some(q) = &spec.quasi_static else {
        if spec.fracture.is_some() && !materials.iter().any(|m| m.fracture.is_some()) {
            return Err(InputError::new(
                "fracture",
                "bond breakage settings need a run that breaks bonds: add a [quasi_static] \
                 or [dynamics] section and a fracture parameter",
            ));
        }
        return Ok((fracture, None));
    };
    if !materials.iter().any(|m| m.fracture.is_some()) {
        return Err(InputError::new(
            "quasi_static",
            "no material has a fracture parameter, so no bond could break: give \
             fracture_energy (or the critical value) for at least one material",
        ));
    }
    let loaded = boundaries
        .iter()
        .any(|b| b.values.iter().flatten().any(|&v| v != 0.0))
        || loads.iter().any(|l| l.value.iter().any(|&v| v != 0.0));
    if !loaded {
        return Err(InputError::new(
            "quasi_static",
            "every prescribed displacement and load is zero: scaling them by a load factor \
             does nothing; prescribe a non-zero displacement (or load)",
        ));
    }
    positive("quasi_static.max_load_factor", q.max_load_factor)?;
    strategy_keys(q)?;
    Ok((fracture, Some(quasi_static(q)?)))
}

/// `[fracture]` of a `d`-dimensional scene.
fn fracture_settings(spec: &SceneSpec, d: usize) -> Result<FractureSettings, InputError> {
    let mut fracture = FractureSettings::default();
    if let Some(f) = &spec.fracture {
        fracture.shear_energy = f.shear_energy;
        fracture.calibration = f.calibration;
        fracture.shear_criterion = f.shear_criterion;
        for (k, b) in f.no_fail.iter().enumerate() {
            fracture
                .no_fail
                .push(aabb(&format!("fracture.no_fail[{k}].box"), &b.bounds, d)?);
        }
    }
    Ok(fracture)
}

/// Refuses the keys of `[quasi_static]` that its strategy does not use.
fn strategy_keys(q: &QuasiStaticSpec) -> Result<(), InputError> {
    let stepped = q.strategy != Strategy::Event;
    let only = |key: &str, present: bool, applies: bool, to: &str| {
        if present && !applies {
            Err(InputError::new(
                format!("quasi_static.{key}"),
                format!(
                    "applies to strategy {to} only (strategy is {:?})",
                    q.strategy
                ),
            ))
        } else {
            Ok(())
        }
    };
    let stepped_names = "\"all\" or \"most_critical\"";
    only("steps", q.steps.is_some(), stepped, stepped_names)?;
    only(
        "max_broken_per_step",
        q.max_broken_per_step.is_some(),
        stepped,
        stepped_names,
    )?;
    only(
        "min_step_fraction",
        q.min_step_fraction.is_some(),
        stepped,
        stepped_names,
    )?;
    only(
        "max_resolves",
        q.max_resolves.is_some(),
        stepped,
        stepped_names,
    )?;
    only("max_events", q.max_events.is_some(), !stepped, "\"event\"")?;
    only(
        "tolerance",
        q.tolerance.is_some(),
        q.strategy != Strategy::All,
        "\"event\" or \"most_critical\"",
    )?;
    Ok(())
}

/// The numbers of `[quasi_static]`, defaults filled in.
fn quasi_static(q: &QuasiStaticSpec) -> Result<QuasiStatic, InputError> {
    let count = |key: &str, v: Option<usize>, default: usize, max: usize| match v {
        Some(n) if n == 0 || n > max => Err(InputError::new(
            format!("quasi_static.{key}"),
            format!("{n} is outside 1..={max}"),
        )),
        Some(n) => Ok(n),
        None => Ok(default),
    };
    let steps = count("steps", q.steps, 100, 10_000_000)?;
    let max_resolves = count("max_resolves", q.max_resolves, 10_000, 100_000_000)?;
    let max_events = count("max_events", q.max_events, 1_000_000, 1_000_000_000)?;
    if let Some(n) = q.max_broken_per_step {
        count("max_broken_per_step", Some(n), n, usize::MAX)?;
    }
    let min_step_fraction = q.min_step_fraction.unwrap_or(1.0 / 1024.0);
    // The smallest step, min_step_fraction × max_load_factor / steps, must still
    // change λ in double precision (an ulp of λ ≤ max_load_factor is 2.2e-16 of
    // it): at least MIN_STEP_RELATIVE of max_load_factor, with room to spare.
    let lowest = MIN_STEP_RELATIVE * steps as f64;
    if !(min_step_fraction >= lowest && min_step_fraction <= 1.0) {
        return Err(InputError::new(
            "quasi_static.min_step_fraction",
            format!(
                "{} is outside [{lowest:e}, 1]: the smallest step \
                 (min_step_fraction × max_load_factor / steps) must be at least \
                 {MIN_STEP_RELATIVE:e} of max_load_factor, or it no longer changes the load \
                 factor in double precision and the run never ends",
                num(min_step_fraction)
            ),
        ));
    }
    if let Some(f) = q.stop_after_peak {
        if !(f > 0.0 && f < 1.0) {
            return Err(InputError::new(
                "quasi_static.stop_after_peak",
                format!("{} is outside (0, 1): give the fraction of the peak reaction below which the run ends", num(f)),
            ));
        }
    }
    let tolerance = q.tolerance.unwrap_or(1e-6);
    if !(0.0..1.0).contains(&tolerance) {
        return Err(InputError::new(
            "quasi_static.tolerance",
            format!("{} is outside [0, 1)", num(tolerance)),
        ));
    }
    Ok(QuasiStatic {
        strategy: q.strategy,
        max_load_factor: q.max_load_factor,
        steps,
        max_broken_per_step: q.max_broken_per_step,
        min_step_fraction,
        tolerance,
        max_resolves,
        max_events,
        stop_after_peak: q.stop_after_peak,
    })
}
