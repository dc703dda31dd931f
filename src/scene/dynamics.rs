//! Explicit dynamics: `[dynamics]` (Verlet or dynamic relaxation, run length,
//! time step, damping, tolerances) and `[[initial_conditions]]`; densities,
//! prescribed velocities and the time functions of supports and loads are
//! checked here too (stored with their material, support and load).
//!
//! Every key here applies to the explicit driver only and is refused, with the
//! key named, in a scene without `[dynamics]`; within `[dynamics]`, keys of
//! Verlet are refused for dynamic relaxation and the other way round.

use super::boundary::{time_function, TimeFunction};
use super::fields::{aabb, components, positive, Aabb};
use super::spec::{
    DynamicsMethod, DynamicsSpec, ForceKernel, GaussianSpec, HorizonMode, ModelKind, SceneSpec,
};
use crate::error::{num, InputError};

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

/// Validated `[dynamics]`.
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
}

/// Largest number of explicit steps a scene may ask for.
pub const MAX_STEPS: usize = 100_000_000;

/// What the dynamics sections give the scene: `[dynamics]`, the initial
/// conditions, and the time function of each support and each load (stored
/// with them).
pub(super) struct Explicit {
    pub(super) dynamics: Dynamics,
    pub(super) initial_conditions: Vec<InitialCondition>,
    pub(super) boundary_time: Vec<TimeFunction>,
    pub(super) load_time: Vec<TimeFunction>,
}

/// Validates the explicit-dynamics parts of `spec`; `None` when the scene has
/// no `[dynamics]` (then every dynamics-only key is refused).
pub(super) fn validate(spec: &SceneSpec, d: usize) -> Result<Option<Explicit>, InputError> {
    let Some(dy) = &spec.dynamics else {
        static_scene(spec)?;
        return Ok(None);
    };
    if spec.quasi_static.is_some() {
        return Err(InputError::new(
            "dynamics",
            "a scene runs one driver: remove [dynamics] or [quasi_static]",
        ));
    }
    let relaxation = dy.method == DynamicsMethod::Relaxation;
    method_keys(spec, dy, relaxation)?;
    let length = run_length(dy, relaxation)?;
    let dynamics = numbers(spec, dy, length)?;
    densities(spec, relaxation)?;
    let (boundary_time, load_time) = time_functions(spec)?;
    let initial_conditions = initial_conditions(spec, d)?;
    Ok(Some(Explicit {
        dynamics,
        initial_conditions,
        boundary_time,
        load_time,
    }))
}

/// Refuses the keys of explicit dynamics in a scene without `[dynamics]`.
fn static_scene(spec: &SceneSpec) -> Result<(), InputError> {
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
    Ok(())
}

/// Refuses the keys of Verlet in a relaxation and the other way round.
fn method_keys(spec: &SceneSpec, dy: &DynamicsSpec, relaxation: bool) -> Result<(), InputError> {
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
    Ok(())
}

/// `steps` or `end_time`.
fn run_length(dy: &DynamicsSpec, relaxation: bool) -> Result<RunLength, InputError> {
    Ok(match (dy.steps, dy.end_time) {
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
    })
}

/// The numbers of `[dynamics]`, defaults filled in, with the run length.
fn numbers(spec: &SceneSpec, dy: &DynamicsSpec, length: RunLength) -> Result<Dynamics, InputError> {
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
    Ok(Dynamics {
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
    })
}

/// Verlet needs every material's density (stored with the material);
/// relaxation uses a fictitious mass and refuses one.
fn densities(spec: &SceneSpec, relaxation: bool) -> Result<(), InputError> {
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
            (Some(rho), false) => positive(&f, rho)?,
            (None, true) => {}
        }
    }
    Ok(())
}

/// The time function of each support and each load.
fn time_functions(spec: &SceneSpec) -> Result<(Vec<TimeFunction>, Vec<TimeFunction>), InputError> {
    let boundary_time = spec
        .boundary
        .iter()
        .enumerate()
        .map(|(k, b)| time_function(&format!("boundary[{k}].time_function"), &b.time_function))
        .collect::<Result<_, _>>()?;
    let load_time = spec
        .loads
        .iter()
        .enumerate()
        .map(|(k, l)| time_function(&format!("loads[{k}].time_function"), &l.time_function))
        .collect::<Result<_, _>>()?;
    Ok((boundary_time, load_time))
}

/// `[[initial_conditions]]`.
fn initial_conditions(spec: &SceneSpec, d: usize) -> Result<Vec<InitialCondition>, InputError> {
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
    Ok(initial)
}

/// A Gaussian pulse of a `d`-dimensional scene.
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

#[cfg(test)]
mod tests {
    use crate::scene::boundary::TimeFunction;

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
