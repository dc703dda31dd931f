//! Validation of the explicit-dynamics parts of a scene: `[dynamics]`,
//! `[[initial_conditions]]`, densities, prescribed velocities and time functions.
//!
//! Every key here applies to the explicit driver only and is refused, with the
//! key named, in a scene without `[dynamics]`; within `[dynamics]`, keys of
//! Verlet are refused for dynamic relaxation and the other way round.

use super::spec::*;
use super::validate::{aabb, components, positive, Aabb};
use crate::error::{num, InputError};

/// A validated function of time `g(t)`.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeFunction {
    /// `g = 1`.
    Constant,
    /// `g = min(t/duration, 1)`.
    Ramp(f64),
    /// Piecewise linear through `(t, g)` pairs with increasing `t`; constant outside.
    Table(Vec<(f64, f64)>),
}

impl TimeFunction {
    /// `g(t)`.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Constant => 1.0,
            TimeFunction::Ramp(d) => (t / d).clamp(0.0, 1.0),
            TimeFunction::Table(pts) => {
                let k = pts.partition_point(|p| p.0 <= t);
                if k == 0 {
                    pts[0].1
                } else if k == pts.len() {
                    pts[k - 1].1
                } else {
                    let ((t0, g0), (t1, g1)) = (pts[k - 1], pts[k]);
                    g0 + (g1 - g0) * (t - t0) / (t1 - t0)
                }
            }
        }
    }

    /// `∫₀ᵗ g(s) ds` (a prescribed velocity's displacement); `g` before the
    /// first table time is the first value.
    pub fn integral(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Constant => t,
            TimeFunction::Ramp(d) => {
                if t <= *d {
                    0.5 * t * t / d
                } else {
                    t - 0.5 * d
                }
            }
            TimeFunction::Table(pts) => {
                let mut sum = 0.0;
                let mut prev = (0.0, self.value(0.0));
                let mut knots: Vec<(f64, f64)> = pts
                    .iter()
                    .copied()
                    .filter(|p| p.0 > 0.0 && p.0 < t)
                    .collect();
                knots.push((t, self.value(t)));
                for (tk, gk) in knots {
                    sum += 0.5 * (prev.1 + gk) * (tk - prev.0);
                    prev = (tk, gk);
                }
                sum
            }
        }
    }
}

/// What a `[[boundary]]` prescribes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// `u = value · g(t)`.
    Displacement,
    /// `v = value · g(t)`, `u = value · ∫g`.
    Velocity,
}

/// A validated Gaussian pulse.
#[derive(Debug, Clone, PartialEq)]
pub struct Gaussian {
    /// Centre (only the first `axes` components count).
    pub center: [f64; 3],
    /// Number of axes the distance is measured along.
    pub axes: usize,
    /// Width.
    pub width: f64,
    /// Amplitude vector.
    pub amplitude: [f64; 3],
}

impl Gaussian {
    /// The pulse's displacement at `x`. The distance is divided by the width
    /// before it is squared: a width of 1e-200 m (whose square underflows to 0)
    /// gives the amplitude at the centre and 0 elsewhere, not 0/0.
    pub fn at(&self, x: &[f64; 3]) -> [f64; 3] {
        let r2: f64 = (0..self.axes)
            .map(|a| ((x[a] - self.center[a]) / self.width).powi(2))
            .sum();
        let g = (-r2).exp();
        self.amplitude.map(|a| a * g)
    }
}

/// A validated `[[initial_conditions]]` entry.
#[derive(Debug, Clone, PartialEq)]
pub struct InitialCondition {
    /// Selected points (None: all).
    pub bounds: Option<Aabb>,
    /// Displacement components added.
    pub displacement: [Option<f64>; 3],
    /// Velocity components added.
    pub velocity: [Option<f64>; 3],
    /// Pulse added.
    pub gaussian: Option<Gaussian>,
}

/// How long a run lasts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunLength {
    /// A number of steps.
    Steps(usize),
    /// A simulated time (Verlet).
    Time(f64),
}

/// Default `dynamics.balance_tolerance`: above every run the validation
/// measured (Verlet's O(Δt²) error: 9e-3 at 0.8 of the stable step; bonds
/// breaking: 4.3e-2; the traditional variable-horizon baseline's ghost forces:
/// up to 0.13, validation/dynamics/README.md), far below what a broken scheme
/// gives (an unstable damping: 4.5e8).
pub const DEFAULT_BALANCE_TOLERANCE: f64 = 0.2;

/// Validated `[dynamics]` with everything the explicit driver needs.
#[derive(Debug, Clone, PartialEq)]
pub struct Dynamics {
    /// Verlet or relaxation.
    pub method: DynamicsMethod,
    /// Nonlinear kernels or the assembled tangent.
    pub kernel: ForceKernel,
    /// Run length (relaxation: largest number of steps).
    pub length: RunLength,
    /// Given time step.
    pub time_step: Option<f64>,
    /// Fraction of the stable step.
    pub safety_factor: f64,
    /// Accept a time step above the stable one.
    pub force_time_step: bool,
    /// Mass-proportional damping α (1/s).
    pub damping: f64,
    /// Relaxation's convergence tolerance.
    pub tolerance: f64,
    /// Probe and energy cadence.
    pub record_every: usize,
    /// Verlet: largest relative energy-balance error before the run fails.
    pub balance_tolerance: f64,
    /// Density of each material (Verlet; empty for relaxation).
    pub density: Vec<f64>,
    /// What each boundary prescribes.
    pub motion: Vec<Motion>,
    /// Each boundary's time function.
    pub boundary_time: Vec<TimeFunction>,
    /// Each load's time function.
    pub load_time: Vec<TimeFunction>,
    /// Initial conditions.
    pub initial: Vec<InitialCondition>,
}

fn time_function(field: &str, t: &Option<TimeFunctionSpec>) -> Result<TimeFunction, InputError> {
    let Some(t) = t else {
        return Ok(TimeFunction::Constant);
    };
    let unexpected = |key: &str, present: bool, kind: &str| {
        if present {
            Err(InputError::new(
                format!("{field}.{key}"),
                format!("does not apply to kind \"{kind}\""),
            ))
        } else {
            Ok(())
        }
    };
    match t.kind {
        TimeFunctionKind::Constant => {
            unexpected("duration", t.duration.is_some(), "constant")?;
            unexpected("times", t.times.is_some(), "constant")?;
            unexpected("values", t.values.is_some(), "constant")?;
            Ok(TimeFunction::Constant)
        }
        TimeFunctionKind::Ramp => {
            unexpected("times", t.times.is_some(), "ramp")?;
            unexpected("values", t.values.is_some(), "ramp")?;
            let d = t.duration.ok_or_else(|| {
                InputError::new(
                    format!("{field}.duration"),
                    "a ramp needs its duration in s",
                )
            })?;
            positive(&format!("{field}.duration"), d)?;
            Ok(TimeFunction::Ramp(d))
        }
        TimeFunctionKind::Table => {
            unexpected("duration", t.duration.is_some(), "table")?;
            let (Some(times), Some(values)) = (&t.times, &t.values) else {
                return Err(InputError::new(
                    field,
                    "a table needs `times` and `values` of the same length",
                ));
            };
            if times.is_empty() || times.len() != values.len() {
                return Err(InputError::new(
                    format!("{field}.values"),
                    format!(
                        "{} values for {} times: give one value per time, at least one",
                        values.len(),
                        times.len()
                    ),
                ));
            }
            for (k, (&tk, &gk)) in times.iter().zip(values).enumerate() {
                if !tk.is_finite() || tk < 0.0 || (k > 0 && tk <= times[k - 1]) {
                    return Err(InputError::new(
                        format!("{field}.times[{k}]"),
                        format!(
                            "{}: times must be finite, ≥ 0 and strictly increasing",
                            num(tk)
                        ),
                    ));
                }
                if !gk.is_finite() {
                    return Err(InputError::new(
                        format!("{field}.values[{k}]"),
                        format!("{} is not a finite number", num(gk)),
                    ));
                }
            }
            Ok(TimeFunction::Table(
                times.iter().copied().zip(values.iter().copied()).collect(),
            ))
        }
    }
}

fn gaussian(field: &str, g: &GaussianSpec, d: usize) -> Result<Gaussian, InputError> {
    if g.center.is_empty() || g.center.len() > d {
        return Err(InputError::new(
            format!("{field}.center"),
            format!(
                "{} components; give 1 to {d} (the axes the distance is measured along)",
                g.center.len()
            ),
        ));
    }
    let mut center = [0.0; 3];
    for (a, &c) in g.center.iter().enumerate() {
        if !c.is_finite() {
            return Err(InputError::new(
                format!("{field}.center[{a}]"),
                format!("{} is not a finite number", num(c)),
            ));
        }
        center[a] = c;
    }
    positive(&format!("{field}.width"), g.width)?;
    if g.amplitude.len() != d {
        return Err(InputError::new(
            format!("{field}.amplitude"),
            format!("{} components; give {d}", g.amplitude.len()),
        ));
    }
    let mut amplitude = [0.0; 3];
    for (a, &v) in g.amplitude.iter().enumerate() {
        if !v.is_finite() {
            return Err(InputError::new(
                format!("{field}.amplitude[{a}]"),
                format!("{} is not a finite number", num(v)),
            ));
        }
        amplitude[a] = v;
    }
    Ok(Gaussian {
        center,
        axes: g.center.len(),
        width: g.width,
        amplitude,
    })
}

/// Validates the dynamics parts of `spec`; `None` when the scene has no
/// `[dynamics]` (then every dynamics-only key is refused).
pub(super) fn validate(spec: &SceneSpec, d: usize) -> Result<Option<Dynamics>, InputError> {
    let Some(dy) = &spec.dynamics else {
        let only = "applies to explicit dynamics only (add a [dynamics] section)";
        if let Some((name, _)) = spec.materials.iter().find(|(_, m)| m.density.is_some()) {
            return Err(InputError::new(format!("materials.{name}.density"), only));
        }
        if !spec.initial_conditions.is_empty() {
            return Err(InputError::new("initial_conditions", only));
        }
        for (k, b) in spec.boundary.iter().enumerate() {
            if b.velocity.is_some() {
                return Err(InputError::new(format!("boundary[{k}].velocity"), only));
            }
            if b.time_function.is_some() {
                return Err(InputError::new(
                    format!("boundary[{k}].time_function"),
                    only,
                ));
            }
        }
        for (k, l) in spec.loads.iter().enumerate() {
            if l.time_function.is_some() {
                return Err(InputError::new(format!("loads[{k}].time_function"), only));
            }
        }
        if spec.model.horizons == HorizonMode::Traditional {
            return Err(InputError::new(
                "model.horizons",
                "\"traditional\" (forces from a point's own horizon only, with ghost forces) \
                 is a baseline for explicit dynamics; its tangent is not symmetric and the \
                 implicit solvers do not take it: use \"dual\" or \"constant\"",
            ));
        }
        return Ok(None);
    };
    if spec.quasi_static.is_some() {
        return Err(InputError::new(
            "dynamics",
            "a scene runs one driver: remove [dynamics] or [quasi_static]",
        ));
    }
    let relaxation = dy.method == DynamicsMethod::Relaxation;
    let (method_name, other) = if relaxation {
        ("relaxation", "\"verlet\"")
    } else {
        ("verlet", "\"relaxation\"")
    };
    let only_for = |key: &str, present: bool, verlet_key: bool| {
        if present && verlet_key == relaxation {
            Err(InputError::new(
                key,
                format!("applies to method {other} only (method is \"{method_name}\")"),
            ))
        } else {
            Ok(())
        }
    };
    only_for("dynamics.end_time", dy.end_time.is_some(), true)?;
    only_for("dynamics.time_step", dy.time_step.is_some(), true)?;
    only_for("dynamics.safety_factor", dy.safety_factor.is_some(), true)?;
    only_for("dynamics.force_time_step", dy.force_time_step, true)?;
    only_for("dynamics.damping", dy.damping.is_some(), true)?;
    only_for(
        "dynamics.balance_tolerance",
        dy.balance_tolerance.is_some(),
        true,
    )?;
    only_for("dynamics.tolerance", dy.tolerance.is_some(), false)?;
    only_for(
        "initial_conditions",
        !spec.initial_conditions.is_empty(),
        true,
    )?;
    for (k, b) in spec.boundary.iter().enumerate() {
        only_for(
            &format!("boundary[{k}].velocity"),
            b.velocity.is_some(),
            true,
        )?;
        only_for(
            &format!("boundary[{k}].time_function"),
            b.time_function.is_some(),
            true,
        )?;
    }
    for (k, l) in spec.loads.iter().enumerate() {
        only_for(
            &format!("loads[{k}].time_function"),
            l.time_function.is_some(),
            true,
        )?;
    }

    let length = match (dy.steps, dy.end_time) {
        (Some(_), Some(_)) => {
            return Err(InputError::new(
                "dynamics.end_time",
                "give either steps or end_time, not both",
            ))
        }
        (Some(n), None) => {
            if n == 0 || n > MAX_STEPS {
                return Err(InputError::new(
                    "dynamics.steps",
                    format!("{n} is outside 1..={MAX_STEPS}"),
                ));
            }
            RunLength::Steps(n)
        }
        (None, Some(t)) => {
            positive("dynamics.end_time", t)?;
            RunLength::Time(t)
        }
        (None, None) => {
            return Err(InputError::new(
                "dynamics",
                if relaxation {
                    "give steps: the largest number of relaxation steps"
                } else {
                    "give the run's length: steps or end_time"
                },
            ))
        }
    };
    if let Some(t) = dy.time_step {
        positive("dynamics.time_step", t)?;
    }
    if dy.force_time_step && dy.time_step.is_none() {
        return Err(InputError::new(
            "dynamics.force_time_step",
            "forces a given time_step; give dynamics.time_step too",
        ));
    }
    let safety_factor = dy.safety_factor.unwrap_or(0.8);
    if !(safety_factor > 0.0 && safety_factor <= 1.0) {
        return Err(InputError::new(
            "dynamics.safety_factor",
            format!("{} is outside (0, 1]", num(safety_factor)),
        ));
    }
    if dy.safety_factor.is_some() && dy.time_step.is_some() {
        return Err(InputError::new(
            "dynamics.safety_factor",
            "scales the stable time step; it does not apply to a given time_step",
        ));
    }
    let damping = dy.damping.unwrap_or(0.0);
    if !(damping.is_finite() && damping >= 0.0) {
        return Err(InputError::new(
            "dynamics.damping",
            format!("{} is not a finite number ≥ 0 (1/s)", num(damping)),
        ));
    }
    let tolerance = dy.tolerance.unwrap_or(1e-8);
    if !(tolerance > 0.0 && tolerance < 1.0) {
        return Err(InputError::new(
            "dynamics.tolerance",
            format!("{} is outside (0, 1)", num(tolerance)),
        ));
    }
    let balance_tolerance = dy.balance_tolerance.unwrap_or(DEFAULT_BALANCE_TOLERANCE);
    if !(balance_tolerance > 0.0) {
        return Err(InputError::new(
            "dynamics.balance_tolerance",
            format!(
                "{} is not a positive number (a fraction of the largest \
                 energy; default {DEFAULT_BALANCE_TOLERANCE}, inf turns the check off)",
                num(balance_tolerance)
            ),
        ));
    }
    let record_every = dy.record_every.unwrap_or(1);
    if record_every == 0 {
        return Err(InputError::new(
            "dynamics.record_every",
            "0 steps; give a positive number of steps",
        ));
    }
    if dy.kernel == ForceKernel::Linearised && spec.model.horizons == HorizonMode::Traditional {
        return Err(InputError::new(
            "dynamics.kernel",
            "the assembled tangent is dual-horizon; \"traditional\" horizons need the nonlinear kernel",
        ));
    }
    if spec.model.horizons == HorizonMode::Traditional && spec.model.kind != ModelKind::BondBased {
        return Err(InputError::new(
            "model.horizons",
            "\"traditional\" is defined for the bond-based model only",
        ));
    }

    let mut density = Vec::new();
    for (name, m) in &spec.materials {
        let f = format!("materials.{name}.density");
        match (m.density, relaxation) {
            (Some(_), true) => {
                return Err(InputError::new(
                    f,
                    "dynamic relaxation uses a fictitious mass; remove the density",
                ))
            }
            (None, false) => {
                return Err(InputError::new(
                    f,
                    "explicit dynamics needs every material's density in kg/m³",
                ))
            }
            (Some(rho), false) => {
                positive(&f, rho)?;
                density.push(rho);
            }
            (None, true) => {}
        }
    }

    let mut motion = Vec::new();
    let mut boundary_time = Vec::new();
    for (k, b) in spec.boundary.iter().enumerate() {
        motion.push(if b.velocity.is_some() {
            Motion::Velocity
        } else {
            Motion::Displacement
        });
        boundary_time.push(time_function(
            &format!("boundary[{k}].time_function"),
            &b.time_function,
        )?);
    }
    let mut load_time = Vec::new();
    for (k, l) in spec.loads.iter().enumerate() {
        load_time.push(time_function(
            &format!("loads[{k}].time_function"),
            &l.time_function,
        )?);
    }
    let mut initial = Vec::new();
    for (k, ic) in spec.initial_conditions.iter().enumerate() {
        let f = format!("initial_conditions[{k}]");
        let bounds = ic
            .bounds
            .as_ref()
            .map(|b| aabb(&format!("{f}.box"), b, d))
            .transpose()?;
        let displacement = match &ic.displacement {
            Some(c) => components(&format!("{f}.displacement"), c, d)?,
            None => [None; 3],
        };
        let velocity = match &ic.velocity {
            Some(c) => components(&format!("{f}.velocity"), c, d)?,
            None => [None; 3],
        };
        let gaussian = ic
            .gaussian
            .as_ref()
            .map(|g| gaussian(&format!("{f}.gaussian"), g, d))
            .transpose()?;
        if displacement.iter().all(Option::is_none)
            && velocity.iter().all(Option::is_none)
            && gaussian.is_none()
        {
            return Err(InputError::new(
                f,
                "sets nothing: give displacement, velocity or gaussian",
            ));
        }
        if gaussian.is_some() && bounds.is_some() {
            return Err(InputError::new(
                format!("{f}.box"),
                "a Gaussian pulse covers the whole body; remove the box",
            ));
        }
        initial.push(InitialCondition {
            bounds,
            displacement,
            velocity,
            gaussian,
        });
    }
    Ok(Some(Dynamics {
        method: dy.method,
        kernel: dy.kernel,
        length,
        time_step: dy.time_step,
        safety_factor,
        force_time_step: dy.force_time_step,
        damping,
        tolerance,
        record_every,
        balance_tolerance,
        density,
        motion,
        boundary_time,
        load_time,
        initial,
    }))
}

/// Largest number of explicit steps a scene may ask for.
pub const MAX_STEPS: usize = 100_000_000;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_functions_and_their_integrals() {
        let ramp = TimeFunction::Ramp(2.0);
        assert_eq!(ramp.value(1.0), 0.5);
        assert_eq!(ramp.integral(1.0), 0.25);
        assert_eq!(ramp.integral(3.0), 2.0);
        let table = TimeFunction::Table(vec![(0.0, 0.0), (1.0, 2.0), (3.0, 2.0)]);
        assert_eq!(table.value(0.5), 1.0);
        assert_eq!(table.value(5.0), 2.0);
        assert!((table.integral(2.0) - 3.0).abs() < 1e-15);
        assert!((table.integral(4.0) - 7.0).abs() < 1e-15);
        assert_eq!(TimeFunction::Constant.integral(2.5), 2.5);
    }
}
