//! Degrees of freedom: `d` per point, numbered point by point; prescribed ones
//! are eliminated and the rest numbered consecutively (so a point's free
//! degrees of freedom are adjacent columns of `K`).

use crate::discretization::{groups, Discretization};
use crate::error::{num, InputError};
use crate::scene::{Prescribed, Selection};

/// Marker for a prescribed degree of freedom in [`DofMap::free_index`].
pub const PRESCRIBED: u32 = u32::MAX;

/// A named set of constrained points, for reaction forces.
///
/// Sets may overlap (a point may be selected by several boundary boxes when
/// their values agree). Each prescribed component of a point belongs to the
/// **first** set, in scene order, that prescribes it: that set's reaction
/// counts it and no later set does. The reactions of all sets therefore sum to
/// the total force of the supports, each support force counted once; a set
/// nested in an earlier one that prescribes the same components reports zero.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstrainedSet {
    /// Name from the scene.
    pub name: String,
    /// Points in the set.
    pub points: Vec<usize>,
    /// The `(point, component)` pairs this set prescribes first (it owns their reaction).
    pub owned: Vec<(u32, u8)>,
    /// `(earlier set, components)`: prescribed components of this set that an
    /// earlier set already prescribes (and whose reaction it counts).
    pub shared_with: Vec<(usize, usize)>,
}

/// The mapping between point components and free unknowns.
#[derive(Debug, Clone, PartialEq)]
pub struct DofMap {
    /// Spatial dimension.
    pub d: usize,
    /// `free_index[3 i + c]`: index among the free unknowns, or `PRESCRIBED`.
    pub free_index: Vec<u32>,
    /// Prescribed displacements per point (zero for free components).
    pub prescribed: Vec<[f64; 3]>,
    /// `(point, component)` of each free unknown.
    pub free_dofs: Vec<(u32, u8)>,
    /// The constrained sets, in scene order.
    pub sets: Vec<ConstrainedSet>,
}

impl DofMap {
    /// Selects the points of each prescribed set and numbers the free unknowns.
    /// Errors on a set that selects no point and on conflicting values.
    pub fn new(disc: &Discretization, boundaries: &[Prescribed]) -> Result<Self, InputError> {
        let (points, d) = (&disc.points, disc.d);
        let n = points.len();
        let mut value: Vec<[Option<(f64, usize)>; 3]> = vec![[None; 3]; n];
        let mut sets = Vec::with_capacity(boundaries.len());
        for (k, bc) in boundaries.iter().enumerate() {
            let field = match bc.selection {
                Selection::Box(_) => format!("boundary[{k}].box"),
                Selection::Group(_) => format!("boundary[{k}].group"),
            };
            let selected = groups::select(disc, &bc.selection, &field)?;
            if selected.is_empty() {
                return Err(InputError::new(field, format!(
                    "selects no point (\"{}\"); enlarge the box so that it holds at least one point layer", bc.name)));
            }
            let mut shared = vec![0usize; k];
            for &i in &selected {
                for c in 0..d {
                    if let Some(v) = bc.values[c] {
                        match value[i][c] {
                            Some((old, other)) if old != v => {
                                return Err(InputError::new(format!("boundary[{k}].displacement"), format!(
                                    "point {i} at {:?} is also in boundary[{other}] with a different value \
                                     for component {c} ({} vs {}); a degree of freedom takes one value", points.x[i], num(old), num(v))));
                            }
                            Some((_, other)) => shared[other] += 1,
                            None => value[i][c] = Some((v, k)),
                        }
                    }
                }
            }
            sets.push(ConstrainedSet {
                name: bc.name.clone(),
                points: selected,
                owned: Vec::new(),
                shared_with: shared
                    .into_iter()
                    .enumerate()
                    .filter(|&(_, n)| n > 0)
                    .collect(),
            });
        }
        let mut free_index = vec![PRESCRIBED; 3 * n];
        let mut prescribed = vec![[0.0; 3]; n];
        let mut free_dofs = Vec::new();
        for i in 0..n {
            for c in 0..d {
                match value[i][c] {
                    Some((v, k)) => {
                        prescribed[i][c] = v;
                        sets[k].owned.push((i as u32, c as u8));
                    }
                    None => {
                        free_index[3 * i + c] = free_dofs.len() as u32;
                        free_dofs.push((i as u32, c as u8));
                    }
                }
            }
        }
        Ok(Self {
            d,
            free_index,
            prescribed,
            free_dofs,
            sets,
        })
    }

    /// One note per pair of overlapping sets: which components' reactions a
    /// later set leaves to an earlier one ([`ConstrainedSet`]).
    pub fn overlap_notes(&self) -> Vec<String> {
        let mut notes = Vec::new();
        for set in &self.sets {
            for &(earlier, n) in &set.shared_with {
                notes.push(format!(
                    "note: boundary \"{}\" prescribes {n} component(s) that boundary \"{}\" \
                     (earlier in the scene) already prescribes; their reaction is counted in \"{}\" only",
                    set.name, self.sets[earlier].name, self.sets[earlier].name
                ));
            }
        }
        notes
    }

    /// Number of free unknowns.
    pub fn n_free(&self) -> usize {
        self.free_dofs.len()
    }

    /// Number of free components of point `i`.
    #[inline]
    pub fn free_count(&self, i: usize) -> usize {
        (0..self.d)
            .filter(|&c| self.free_index[3 * i + c] != PRESCRIBED)
            .count()
    }

    /// The full displacement field from the free unknowns `x`.
    pub fn expand(&self, x: &[f64]) -> Vec<[f64; 3]> {
        let mut u = self.prescribed.clone();
        for (k, &(i, c)) in self.free_dofs.iter().enumerate() {
            u[i as usize][c as usize] = x[k];
        }
        u
    }
}
