//! Checks every section uses: numbers, names, coordinates, boxes and
//! components, each naming the offending field with a dotted path
//! (`regions[1].spacing`) and saying what would be valid; the limits of the
//! lengths, horizons and stiffnesses double precision holds.

use super::spec::{BoxSpec, ComponentsSpec};
use crate::error::{num, InputError};

/// The largest number of grid points a scene may generate.
pub const MAX_POINTS: usize = 50_000_000;

/// An axis-aligned box in 3D coordinates; axes beyond the scene's dimension are unbounded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: [f64; 3],
    /// Upper corner.
    pub max: [f64; 3],
}

impl Aabb {
    /// Whether `x` lies inside, boundary included (with a relative tolerance of 1e-9 of the box size).
    pub fn contains(&self, x: &[f64; 3]) -> bool {
        (0..3).all(|a| {
            let tol = if self.max[a].is_finite() {
                1e-9 * (self.max[a] - self.min[a]).abs().max(f64::MIN_POSITIVE)
            } else {
                0.0
            };
            x[a] >= self.min[a] - tol && x[a] <= self.max[a] + tol
        })
    }
}

/// Largest horizon, in spacings, a scene may give (factor or radius).
pub const MAX_HORIZON_FACTOR: f64 = 20.0;

/// Smallest spacing of a body (m): bond lengths are computed from squared
/// coordinate differences, which stay normal doubles (above 2.2e-308) down to
/// about 1.5e-154 m; the margin covers the sums of three squares.
pub const MIN_LENGTH: f64 = 1e-150;

/// Largest spacing and coordinate magnitude of a body (m): squared lengths
/// stay finite (below 1.8e308) up to about 1.3e154 m.
pub const MAX_LENGTH: f64 = 1e150;

/// Refuses a spacing outside [[`MIN_LENGTH`], [`MAX_LENGTH`]] or a coordinate
/// beyond ±[`MAX_LENGTH`]: `what` is "spacing" or "coordinate".
pub fn length_in_range(field: &str, what: &str, v: f64) -> Result<(), InputError> {
    let spacing = what == "spacing";
    if (spacing && v.abs() < MIN_LENGTH) || v.abs() > MAX_LENGTH {
        return Err(InputError::new(
            field,
            format!(
                "{what} {v:?} m is outside [{}, {MAX_LENGTH:e}] m, the range in which squared \
                 lengths (bond lengths, neighbour distances) are normal double-precision \
                 numbers; rescale the units (e.g. µm or km instead of m)",
                if spacing {
                    format!("{MIN_LENGTH:e}")
                } else {
                    format!("{:e}", -MAX_LENGTH)
                }
            ),
        ));
    }
    Ok(())
}

/// Refuses a number that is not finite and positive.
pub(super) fn positive(field: &str, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(InputError::new(
            field,
            format!("{} is not a finite positive number", num(v)),
        ))
    }
}

/// Refuses a horizon factor that gives no neighbour or an implausibly large horizon.
pub(super) fn check_horizon_factor(field: &str, m: f64) -> Result<(), InputError> {
    if !m.is_finite() || m <= 1.0 {
        return Err(InputError::new(field, format!(
            "{} would make the horizon no larger than the spacing (no neighbours); use a value above 1, typically 3.015", num(m))));
    }
    if m > MAX_HORIZON_FACTOR {
        return Err(InputError::new(
            field,
            format!("{} is implausibly large (above {MAX_HORIZON_FACTOR} spacings); typical values are 2 to 5", num(m)),
        ));
    }
    Ok(())
}

/// A file-name-safe version of a default scene name.
pub(super) fn sanitize(n: &str) -> String {
    let s: String = n
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        "scene".into()
    } else {
        s
    }
}

/// Refuses a name that is empty or has characters other than letters, digits, `_` and `-`.
pub(super) fn name(field: &str, n: &str) -> Result<(), InputError> {
    if n.is_empty()
        || !n
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return Err(InputError::new(
            field,
            format!("\"{n}\" must be non-empty and use only letters, digits, '_' and '-'"),
        ));
    }
    Ok(())
}

/// Pads a coordinate list of length `d` to 3D with zeros.
pub(super) fn coords(field: &str, v: &[f64], d: usize) -> Result<[f64; 3], InputError> {
    if v.len() != d {
        return Err(InputError::new(
            field,
            format!("has {} coordinate(s); this {d}D scene needs {d}", v.len()),
        ));
    }
    if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
        return Err(InputError::new(
            field,
            format!("{} is not a finite number", num(*bad)),
        ));
    }
    let mut x = [0.0; 3];
    x[..d].copy_from_slice(v);
    Ok(x)
}

/// A box with `min ≤ max` on every axis of the scene (others unbounded).
pub(super) fn aabb(field: &str, b: &BoxSpec, d: usize) -> Result<Aabb, InputError> {
    let min = coords(&format!("{field}.min"), &b.min, d)?;
    let max = coords(&format!("{field}.max"), &b.max, d)?;
    let mut bounds = Aabb {
        min: [f64::NEG_INFINITY; 3],
        max: [f64::INFINITY; 3],
    };
    for a in 0..d {
        if max[a] < min[a] {
            return Err(InputError::new(
                field,
                format!(
                    "max[{a}] = {} is below min[{a}] = {}",
                    num(max[a]),
                    num(min[a])
                ),
            ));
        }
        bounds.min[a] = min[a];
        bounds.max[a] = max[a];
    }
    Ok(bounds)
}

/// Per-component values, at least one given and each of an axis of the scene.
pub(super) fn components(
    field: &str,
    c: &ComponentsSpec,
    d: usize,
) -> Result<[Option<f64>; 3], InputError> {
    let values = [c.x, c.y, c.z];
    for (a, axis) in ["x", "y", "z"].iter().enumerate() {
        match values[a] {
            Some(_) if a >= d => {
                return Err(InputError::new(
                    format!("{field}.{axis}"),
                    format!("a {d}D scene has no {axis} component"),
                ))
            }
            Some(v) if !v.is_finite() => {
                return Err(InputError::new(
                    format!("{field}.{axis}"),
                    format!("{} is not finite", num(v)),
                ))
            }
            _ => {}
        }
    }
    if values.iter().all(Option::is_none) {
        return Err(InputError::new(
            field,
            "prescribes no component; give at least one of x, y, z",
        ));
    }
    Ok(values)
}
