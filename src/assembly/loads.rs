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
    let (points, d) = (&disc.points, disc.d);
    let n = points.len();
    let mut f = vec![[0.0; 3]; n];
    let mut applied = Vec::with_capacity(loads.len());
    let mut per_load = Vec::with_capacity(loads.len());
    for (k, load) in loads.iter().enumerate() {
        // This load's own forces (a point may take several facets).
        let mut own = vec![[0.0; 3]; n];
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
        let mut total = [0.0; 3];
        let mut count = 0;
        match load.target {
            LoadTarget::Facets => {
                let Some(Selection::Group(name)) = &load.selection else {
                    return Err(InputError::new(field, "a facet traction needs a group"));
                };
                let facets = groups::facets(disc, name, &field)?;
                let mut loaded = vec![false; n];
                for (i, area) in facets {
                    for c in 0..d {
                        let fc = load.value[c] * area;
                        f[i][c] += fc;
                        own[i][c] += fc;
                        total[c] += fc;
                    }
                    finite(k, &f[i], i)?;
                    count += usize::from(!loaded[i]);
                    loaded[i] = true;
                }
            }
            LoadTarget::Volume => {
                for &i in &selected {
                    for c in 0..d {
                        let fc = load.value[c] * points.volume[i];
                        f[i][c] += fc;
                        own[i][c] += fc;
                        total[c] += fc;
                    }
                    finite(k, &f[i], i)?;
                }
                count = selected.len();
            }
            LoadTarget::Face { axis, sign } => {
                let outer = selected
                    .iter()
                    .map(|&i| sign * points.x[i][axis])
                    .fold(f64::NEG_INFINITY, f64::max);
                let layer = selected
                    .iter()
                    .copied()
                    .filter(|&i| sign * points.x[i][axis] >= outer - 0.5 * points.spacing[i]);
                for i in layer {
                    if !matches!(points.source[i], Source::Region(_)) {
                        return Err(InputError::new(
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
                        ));
                    }
                    let share = points.volume[i] / points.spacing[i];
                    for c in 0..d {
                        let fc = load.value[c] * share;
                        f[i][c] += fc;
                        own[i][c] += fc;
                        total[c] += fc;
                    }
                    finite(k, &f[i], i)?;
                    count += 1;
                }
            }
        }
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
            own.into_iter()
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
