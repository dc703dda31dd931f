//! External forces: tractions on the outermost point layer of a face and body forces.
//!
//! A traction on a mesh's boundary group acts on the group's facets: each
//! facet's area (length × thickness in 2D) times `t` goes to the point of the
//! one cell the facet bounds, so the total force is `t` times the group's area.
//!
//! A traction `t` on the face with outward normal `n` (axis `a`, sign `s`) acts on
//! the points whose coordinate `s·x_a` lies within half their spacing of the
//! largest one among the selected points; each gets `t × V_i / h_i` (its share of
//! the face area, `V_i/h_i` with `h_i` its spacing), so the total force is `t`
//! times the face area covered by that layer. That share tiles the face only on
//! a grid: the layer of a mesh or point file has cells of any shape (a structured
//! triangle mesh of a 0.1 m square gets 1.414 × the force), so a face whose layer
//! holds a point of `meshes` or `point_files` is refused, naming `group` (the
//! mesh's boundary facets, exact). A body force `b` gives `b V_i`.

use crate::discretization::{groups, Discretization};
use crate::error::InputError;
use crate::geometry::grid::Source;
use crate::scene::{Load, LoadTarget, Selection};

/// The total force each load applies (for the summary).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AppliedLoad {
    /// Load name.
    pub name: String,
    /// Number of loaded points.
    pub points: usize,
    /// Sum of the point forces in N.
    pub total_force: [f64; 3],
}

/// The external forces of a scene's loads.
#[derive(Debug, Clone, PartialEq)]
pub struct ExternalForces {
    /// The force on every point, every load at its full value.
    pub total: Vec<[f64; 3]>,
    /// Each load's force on each point it loads (explicit dynamics scales each
    /// by its time function).
    pub per_load: Vec<Vec<(usize, [f64; 3])>>,
    /// The total force of each load, for the summary.
    pub applied: Vec<AppliedLoad>,
}

/// Builds the external force of every load on every point.
pub fn external_forces(
    disc: &Discretization,
    loads: &[Load],
) -> Result<ExternalForces, InputError> {
    let mut f = vec![[0.0; 3]; disc.points.len()];
    let mut applied = Vec::with_capacity(loads.len());
    let mut per_load = Vec::with_capacity(loads.len());
    for (k, load) in loads.iter().enumerate() {
        let (own, count) = load_forces(disc, k, load, &mut f)?;
        let total = own.total;
        if total.iter().any(|v| !v.is_finite()) {
            return Err(InputError::new(
                format!("loads[{k}].value"),
                format!(
                    "the total force of \"{}\" is not finite ({total:?} N): rescale the units",
                    load.name
                ),
            ));
        }
        applied.push(AppliedLoad {
            name: load.name.clone(),
            points: count,
            total_force: total,
        });
        per_load.push(
            own.forces
                .into_iter()
                .enumerate()
                .filter(|(_, v)| v.iter().any(|&c| c != 0.0))
                .collect(),
        );
    }
    Ok(ExternalForces {
        total: f,
        per_load,
        applied,
    })
}

/// The forces of load `k` as they are added.
struct Own {
    k: usize,
    d: usize,
    /// This load's own force on every point (a point may take several facets).
    forces: Vec<[f64; 3]>,
    /// Their sum.
    total: [f64; 3],
}

impl Own {
    /// Adds `value × scale` to point `i`, in `f` (all loads) and here;
    /// refuses a point force `f` cannot hold.
    fn add(
        &mut self,
        f: &mut [[f64; 3]],
        i: usize,
        value: &[f64; 3],
        scale: f64,
    ) -> Result<(), InputError> {
        for c in 0..self.d {
            let fc = value[c] * scale;
            f[i][c] += fc;
            self.forces[i][c] += fc;
            self.total[c] += fc;
        }
        finite(self.k, &f[i], i)
    }
}

/// Adds the forces of load `k` into `f`; returns them with the number of
/// loaded points.
fn load_forces(
    disc: &Discretization,
    k: usize,
    load: &Load,
    f: &mut [[f64; 3]],
) -> Result<(Own, usize), InputError> {
    let (points, n) = (&disc.points, disc.points.len());
    let field = match load.selection {
        Some(Selection::Group(_)) => format!("loads[{k}].group"),
        _ => format!("loads[{k}].box"),
    };
    let selected = match &load.selection {
        Some(selection) => groups::select(disc, selection, &field)?,
        None => (0..n).collect(),
    };
    if selected.is_empty() {
        return Err(InputError::new(
            field,
            format!("selects no point (\"{}\")", load.name),
        ));
    }
    let mut own = Own {
        k,
        d: disc.d,
        forces: vec![[0.0; 3]; n],
        total: [0.0; 3],
    };
    let count = match load.target {
        LoadTarget::Facets => {
            let Some(Selection::Group(name)) = &load.selection else {
                return Err(InputError::new(field, "a facet traction needs a group"));
            };
            let mut loaded = vec![false; n];
            let mut count = 0;
            for (i, area) in groups::facets(disc, name, &field)? {
                own.add(f, i, &load.value, area)?;
                count += usize::from(!loaded[i]);
                loaded[i] = true;
            }
            count
        }
        LoadTarget::Volume => {
            for &i in &selected {
                own.add(f, i, &load.value, points.volume[i])?;
            }
            selected.len()
        }
        LoadTarget::Face { axis, sign } => {
            let mut count = 0;
            for i in face_layer(disc, &selected, axis, sign) {
                check_region_point(disc, k, load, i)?;
                own.add(f, i, &load.value, points.volume[i] / points.spacing[i])?;
                count += 1;
            }
            count
        }
    };
    Ok((own, count))
}

/// The points of `selected` whose coordinate `sign · x[axis]` lies within
/// half their spacing of the largest (the outermost layer of a face).
fn face_layer<'a>(
    disc: &'a Discretization,
    selected: &'a [usize],
    axis: usize,
    sign: f64,
) -> impl Iterator<Item = usize> + 'a {
    let points = &disc.points;
    let outer = selected
        .iter()
        .map(|&i| sign * points.x[i][axis])
        .fold(f64::NEG_INFINITY, f64::max);
    selected
        .iter()
        .copied()
        .filter(move |&i| sign * points.x[i][axis] >= outer - 0.5 * points.spacing[i])
}

/// Refuses a `face` traction on a point of a mesh or point file (module docs).
fn check_region_point(
    disc: &Discretization,
    k: usize,
    load: &Load,
    i: usize,
) -> Result<(), InputError> {
    let points = &disc.points;
    if matches!(points.source[i], Source::Region(_)) {
        return Ok(());
    }
    Err(InputError::new(
        format!("loads[{k}].face"),
        format!(
            "\"{}\" would load point {i} (x = {:?}) of {}: `face` shares \
             the traction by grid spacing, exact only on the points of \
             `regions` (an unstructured point set's layer does not tile the \
             face); load a mesh through its boundary group with `group` \
             instead of `face` (the facets' area, exact), or restrict `box` \
             to region points",
            load.name, points.x[i], points.source[i]
        ),
    ))
}

/// Largest point force accepted, in N: products with the stiffness and sums over
/// bonds need headroom below the largest double (1.8e308).
const MAX_POINT_FORCE: f64 = 1e250;

/// Refuses a point force that is not finite or leaves no headroom.
fn finite(k: usize, force: &[f64; 3], point: usize) -> Result<(), InputError> {
    if force.iter().all(|v| v.abs() <= MAX_POINT_FORCE) {
        Ok(())
    } else {
        Err(InputError::new(
            format!("loads[{k}].value"),
            format!(
                "gives point {point} a force of {force:?} N (the value times its volume or face \
                 share): not finite or above {MAX_POINT_FORCE:e} N, outside the range the \
                 solution can be computed in; rescale the units"
            ),
        ))
    }
}
