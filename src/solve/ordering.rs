//! Fill-reducing orderings for the sparse Cholesky factor.
//!
//! faer orders with approximate minimum degree (AMD). On peridynamic stiffness
//! matrices, whose graph is a geometric neighbourhood graph (points bonded
//! within a horizon), a **geometric nested dissection** produces less fill:
//! split the points at the median of the longer side of their bounding box;
//! the separator is the set of points of the far half bonded (coupled in the
//! pattern) to the near half; order the near half, then the rest of the far
//! half, recursively, then the separator. The two halves no longer couple once
//! the separator is eliminated last, so their factors fill independently and
//! the dense fill is confined to the separators, of size `O(n^((d−1)/d))`
//! (George 1973; Lipton, Rose & Tarjan 1979). Both degrees of freedom of a
//! point stay together; leaves of at most [`LEAF`] points keep their natural
//! order (which, for grids, is already banded).
//!
//! The ordering works on any point set (holes, pre-cracks, refined regions,
//! imported clouds); `solver.ordering = "auto"` analyses both orderings and
//! keeps the one whose factor is cheaper, since the sizes are known from the
//! symbolic analysis before any value is assembled.

use crate::assembly::dofs::{DofMap, PRESCRIBED};
use crate::assembly::pattern::Pattern;

/// Points per leaf of the dissection.
const LEAF: usize = 64;

/// A nested-dissection order and the size of its root separator.
pub struct Dissection {
    /// `order[k]` is the free unknown eliminated `k`-th.
    pub order: Vec<usize>,
    /// Free unknowns of the root separator, eliminated last. Every one of its
    /// points is coupled to the near half, so when that half is connected the
    /// separator's block of the factor is dense: the factorisation needs at
    /// least `s³/3` multiply-adds ([`Dissection::root_flops`]).
    pub root_separator: usize,
}

impl Dissection {
    /// The dense root separator's share of the factorisation flops, `Σ_{k≤s} k²`.
    pub fn root_flops(&self) -> f64 {
        let s = self.root_separator as f64;
        s * (s + 1.0) * (2.0 * s + 1.0) / 6.0
    }
}

/// The nested-dissection order of the free unknowns.
pub fn nested_dissection(x: &[[f64; 3]], dofs: &DofMap, pattern: &Pattern) -> Dissection {
    let n = x.len();
    let mut points: Vec<u32> = (0..n as u32)
        .filter(|&i| dofs.free_count(i as usize) > 0)
        .collect();
    let mut side = vec![0u8; n];
    let mut order = Vec::with_capacity(points.len());
    let root = dissect(&mut points, x, dofs.d, pattern, &mut side, &mut order);
    let root_separator = order[order.len() - root..]
        .iter()
        .map(|&i| dofs.free_count(i as usize))
        .sum();
    let mut dof_order = Vec::with_capacity(dofs.n_free());
    for &i in &order {
        for c in 0..dofs.d {
            let k = dofs.free_index[3 * i as usize + c];
            if k != PRESCRIBED {
                dof_order.push(k as usize);
            }
        }
    }
    Dissection {
        order: dof_order,
        root_separator,
    }
}

/// Orders `set` into `out` (module docs) and returns the number of points of
/// its separator (0 for a leaf). `side` is zero on entry and exit.
fn dissect(
    set: &mut [u32],
    x: &[[f64; 3]],
    d: usize,
    pattern: &Pattern,
    side: &mut [u8],
    out: &mut Vec<u32>,
) -> usize {
    if set.len() <= LEAF {
        set.sort_unstable();
        out.extend_from_slice(set);
        return 0;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for &p in set.iter() {
        for a in 0..d {
            lo[a] = lo[a].min(x[p as usize][a]);
            hi[a] = hi[a].max(x[p as usize][a]);
        }
    }
    let axis = (0..d)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0);
    if hi[axis] <= lo[axis] {
        set.sort_unstable();
        out.extend_from_slice(set);
        return 0;
    }
    // Cut at the median, moved to the nearest gap between distinct coordinates
    // so that a grid column is never split (it would widen the separator).
    set.sort_unstable_by(|&p, &q| x[p as usize][axis].total_cmp(&x[q as usize][axis]));
    let coord = |k: usize| x[set[k] as usize][axis];
    let half = set.len() / 2;
    let gap = |k: usize| k > 0 && k < set.len() && coord(k - 1) < coord(k);
    let mid = (0..half)
        .flat_map(|o| [half - o, half + o])
        .find(|&k| gap(k))
        .unwrap_or(half);
    let (near, far) = set.split_at_mut(mid);
    near.iter().for_each(|&p| side[p as usize] = 1);
    // The far points coupled to the near half form the separator: move them to
    // the end of `far`.
    let mut split = far.len();
    let mut k = 0;
    while k < split {
        let p = far[k] as usize;
        if pattern.rows(p).iter().any(|&q| side[q as usize] == 1) {
            split -= 1;
            far.swap(k, split);
        } else {
            k += 1;
        }
    }
    near.iter().for_each(|&p| side[p as usize] = 0);
    let (rest, separator) = far.split_at_mut(split);
    dissect(near, x, d, pattern, side, out);
    dissect(rest, x, d, pattern, side, out);
    separator.sort_unstable();
    out.extend_from_slice(separator);
    separator.len()
}
