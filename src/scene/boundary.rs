//! Supports and loads: `[[boundary]]` (prescribed displacements; in explicit
//! dynamics also velocities) and `[[loads]]` (tractions, body forces), each
//! selecting its points by a box or a mesh's physical group, each scaled in
//! explicit dynamics by its own function of time.

use super::body::MeshFile;
use super::fields::{aabb, components, coords, name, positive, Aabb};
use super::spec::{BoundarySpec, LoadKind, LoadSpec, TimeFunctionKind, TimeFunctionSpec};
use crate::error::{num, InputError};

/// Which points a boundary condition or a load selects.
#[derive(Debug, Clone, PartialEq)]
pub enum Selection {
    /// The points inside a box.
    Box(Aabb),
    /// The points of a mesh's physical group (its cells, or the cells touching
    /// a lower-dimensional group).
    Group(String),
}

/// Prescribed displacement (explicit dynamics: or velocity) on a set of points.
#[derive(Debug, Clone, PartialEq)]
pub struct Prescribed {
    /// Name for the reaction report.
    pub name: String,
    /// Selected points.
    pub selection: Selection,
    /// Prescribed value per component (`None` = free).
    pub values: [Option<f64>; 3],
    /// What the values prescribe (explicit dynamics: a displacement or a velocity).
    pub motion: Motion,
    /// The values are multiplied by this function of time (explicit dynamics).
    pub time: TimeFunction,
}

/// Where a load acts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LoadTarget {
    /// Outermost point layer facing `axis` in direction `sign` (±1).
    Face { axis: usize, sign: f64 },
    /// Every selected point, in proportion to its volume.
    Volume,
    /// The boundary facets of a mesh group (dimension d − 1): each facet's
    /// traction × area goes to the cell it bounds.
    Facets,
}

/// A validated load.
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    /// Name for the summary.
    pub name: String,
    /// Face or volume.
    pub target: LoadTarget,
    /// Restricting selection (None = whole body).
    pub selection: Option<Selection>,
    /// Traction (Pa) or force density (N/m³).
    pub value: [f64; 3],
    /// The load is multiplied by this function of time (explicit dynamics).
    pub time: TimeFunction,
}

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

/// `[[boundary]]` entry `k` (its name unique among the first `k`, `earlier`);
/// its time function is validated with the dynamics (a static scene has none).
pub(super) fn boundary(
    k: usize,
    b: &BoundarySpec,
    earlier: &[BoundarySpec],
    d: usize,
    meshes: &[MeshFile],
) -> Result<Prescribed, InputError> {
    let f = format!("boundary[{k}]");
    name(&format!("{f}.name"), &b.name)?;
    if earlier.iter().any(|o| o.name == b.name) {
        return Err(InputError::new(
            format!("{f}.name"),
            format!("\"{}\" is used twice", b.name),
        ));
    }
    let values = match (&b.displacement, &b.velocity) {
        (Some(c), None) => components(&format!("{f}.displacement"), c, d)?,
        (None, Some(c)) => components(&format!("{f}.velocity"), c, d)?,
        (Some(_), Some(_)) => {
            return Err(InputError::new(
                format!("{f}.velocity"),
                "give either displacement or velocity, not both",
            ))
        }
        (None, None) => {
            return Err(InputError::new(
                format!("{f}.displacement"),
                "missing: give the prescribed displacement components \
                 (or, in explicit dynamics, velocity)",
            ))
        }
    };
    let selection = match (&b.bounds, &b.group) {
        (Some(bounds), None) => Selection::Box(aabb(&format!("{f}.box"), bounds, d)?),
        (None, Some(group)) => {
            mesh_group(&format!("{f}.group"), group, &meshes)?;
            Selection::Group(group.clone())
        }
        (Some(_), Some(_)) => {
            return Err(InputError::new(
                format!("{f}.group"),
                "give either box or group, not both",
            ))
        }
        (None, None) => {
            return Err(InputError::new(
                format!("{f}.box"),
                "missing: select the points with a box (or a mesh's physical group)",
            ))
        }
    };
    Ok(Prescribed {
        name: b.name.clone(),
        selection,
        values,
        motion: if b.velocity.is_some() {
            Motion::Velocity
        } else {
            Motion::Displacement
        },
        time: TimeFunction::Constant,
    })
}

/// Checks that `group` names a physical group a mesh can provide: with no mesh
/// in the scene it cannot (the name itself is checked when the meshes are read).
fn mesh_group(field: &str, group: &str, meshes: &[MeshFile]) -> Result<(), InputError> {
    if meshes.is_empty() {
        return Err(InputError::new(
            field,
            format!("\"{group}\": physical groups come from [[meshes]], and the scene has none; select with `box`"),
        ));
    }
    if group.is_empty() {
        return Err(InputError::new(field, "empty group name"));
    }
    Ok(())
}

/// `[[loads]]` entry `field`; its time function is validated with the dynamics.
pub(super) fn load(
    field: &str,
    l: &LoadSpec,
    d: usize,
    meshes: &[MeshFile],
) -> Result<Load, InputError> {
    name(&format!("{field}.name"), &l.name)?;
    let v = coords(&format!("{field}.value"), &l.value, d)?;
    let selection = match (&l.bounds, &l.group) {
        (Some(b), None) => Some(Selection::Box(aabb(&format!("{field}.box"), b, d)?)),
        (None, Some(group)) => {
            mesh_group(&format!("{field}.group"), group, meshes)?;
            Some(Selection::Group(group.clone()))
        }
        (Some(_), Some(_)) => {
            return Err(InputError::new(
                format!("{field}.group"),
                "give either box or group, not both",
            ))
        }
        (None, None) => None,
    };
    let target = match (l.kind, l.face.as_deref()) {
        (LoadKind::Traction, None) if l.group.is_some() => LoadTarget::Facets,
        (LoadKind::Traction, Some(_)) if l.group.is_some() => {
            return Err(InputError::new(
                format!("{field}.face"),
                "a traction on a group acts on the group's boundary facets: remove `face`",
            ))
        }
        (LoadKind::Traction, Some(face)) => {
            let axes = ["x", "y", "z"];
            let parsed = face
                .strip_prefix('+')
                .map(|a| (a, 1.0))
                .or_else(|| face.strip_prefix('-').map(|a| (a, -1.0)));
            match parsed
                .and_then(|(a, s)| axes[..d].iter().position(|x| *x == a).map(|axis| (axis, s)))
            {
                Some((axis, sign)) => LoadTarget::Face { axis, sign },
                None => {
                    let valid: Vec<String> = axes[..d]
                        .iter()
                        .flat_map(|a| [format!("-{a}"), format!("+{a}")])
                        .collect();
                    return Err(InputError::new(
                        format!("{field}.face"),
                        format!("\"{face}\" is not one of {}", valid.join(", ")),
                    ));
                }
            }
        }
        (LoadKind::Traction, None) => return Err(InputError::new(
            format!("{field}.face"),
            "a traction needs a face (one of -x, +x, -y, +y, -z, +z) or a mesh's boundary group",
        )),
        (LoadKind::BodyForce, None) => LoadTarget::Volume,
        (LoadKind::BodyForce, Some(_)) => {
            return Err(InputError::new(
                format!("{field}.face"),
                "a body force acts on a volume; remove `face` (use `box` to restrict it)",
            ))
        }
    };
    Ok(Load {
        name: l.name.clone(),
        target,
        selection,
        value: v,
        time: TimeFunction::Constant,
    })
}

/// A validated time function (none given: constant 1).
pub(super) fn time_function(
    field: &str,
    t: &Option<TimeFunctionSpec>,
) -> Result<TimeFunction, InputError> {
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
