//! The two halves of a Cholesky solve `P K Pᵀ = L Lᵀ`, and the forward half
//! for a sparse right-hand side along the elimination tree.
//!
//! `K⁻¹ b = Pᵀ L⁻ᵀ L⁻¹ P b`. For a right-hand side `v` with a few non-zero
//! entries, `L⁻¹ P v` is non-zero only on the columns of `L` whose
//! elimination-tree nodes are ancestors of `v`'s entries (Gilbert's reach: a
//! column `j` of `L` updates only rows of its pattern, all of them ancestors of
//! `j`). On faer's supernodal factor the tree is that of the supernodes (the
//! parent of a supernode holds the first row of its pattern); on the
//! simplicial factor every column is its own node. A nested-dissection order
//! makes these paths the separators above a point: a few thousand of the
//! `n` unknowns, so [`Llt::forward_sparse`] costs a small fraction of a solve.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place as dense_lower_solve;
use faer::sparse::linalg::cholesky::simplicial::SymbolicSimplicialCholesky;
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_lower_triangular_transpose_in_place,
};
use faer::sparse::SparseColMatRef;
use faer::{Accum, Conj, Mat, MatMut, MatRef, Par};

/// `L⁻¹ P v` for a sparse `v`: the values on the columns of the nodes it
/// reaches, node by node in ascending order (permuted numbering).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PathColumn {
    /// Nodes reached, ascending.
    nodes: Vec<usize>,
    /// First (permuted) row of each node.
    starts: Vec<usize>,
    /// Offsets of each node's values in `values` (one more than `nodes`).
    offsets: Vec<usize>,
    values: Vec<f64>,
}

impl PathColumn {
    /// Number of stored values.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    fn segments(&self) -> impl Iterator<Item = (usize, usize, &[f64])> {
        (0..self.nodes.len()).map(|k| {
            (
                self.nodes[k],
                self.starts[k],
                &self.values[self.offsets[k]..self.offsets[k + 1]],
            )
        })
    }

    /// `selfᵀ c` for a dense `c` in the permuted numbering.
    pub fn dot_dense(&self, c: &[f64]) -> f64 {
        self.segments()
            .map(|(_, start, v)| v.iter().zip(&c[start..]).map(|(a, b)| a * b).sum::<f64>())
            .sum()
    }

    /// `c += a self`.
    pub fn add_to(&self, a: f64, c: &mut [f64]) {
        for (_, start, v) in self.segments() {
            c[start..start + v.len()]
                .iter_mut()
                .zip(v)
                .for_each(|(ci, vi)| *ci += a * vi);
        }
    }

    /// `selfᵀ other`: only the nodes both reach (their common ancestors) count.
    pub fn dot(&self, other: &PathColumn) -> f64 {
        let (mut i, mut j, mut sum) = (0, 0, 0.0);
        while i < self.nodes.len() && j < other.nodes.len() {
            match self.nodes[i].cmp(&other.nodes[j]) {
                std::cmp::Ordering::Less => i += 1,
                std::cmp::Ordering::Greater => j += 1,
                std::cmp::Ordering::Equal => {
                    let a = &self.values[self.offsets[i]..self.offsets[i + 1]];
                    let b = &other.values[other.offsets[j]..other.offsets[j + 1]];
                    sum += a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
                    i += 1;
                    j += 1;
                }
            }
        }
        sum
    }
}

/// A double-precision factor `P K Pᵀ = L Lᵀ`: faer's symbolic part and values.
#[derive(Clone, Copy)]
pub struct Llt<'a> {
    symbolic: &'a SymbolicCholesky<usize>,
    factor: &'a [f64],
}

impl<'a> Llt<'a> {
    /// The factor with this symbolic part and these values.
    pub fn new(symbolic: &'a SymbolicCholesky<usize>, factor: &'a [f64]) -> Self {
        Self { symbolic, factor }
    }

    /// Number of stored entries of `L`.
    pub fn nnz(&self) -> usize {
        self.factor.len()
    }

    /// `c = L⁻¹ P b`.
    pub fn forward(&self, b: &[f64]) -> Vec<f64> {
        let (symbolic, factor) = (self.symbolic, self.factor);
        let mut c = match symbolic.perm() {
            Some(perm) => perm.arrays().0.iter().map(|&i| b[i]).collect(),
            None => b.to_vec(),
        };
        let par = faer::get_global_parallelism();
        let n = c.len();
        let rhs = MatMut::from_column_major_slice_mut(&mut c, n, 1);
        match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(sym) => {
                solve_lower_triangular_in_place(simplicial(sym, factor), Conj::No, rhs, par)
            }
            SymbolicCholeskyRaw::Supernodal(sym) => {
                let mut mem = MemBuffer::new(sym.solve_in_place_scratch::<f64>(1, par));
                SupernodalLltRef::new(sym, factor).l_solve_with_conj(
                    Conj::No,
                    rhs,
                    par,
                    MemStack::new(&mut mem),
                );
            }
        }
        c
    }

    /// `x = Pᵀ L⁻ᵀ c`.
    pub fn backward(&self, mut c: Vec<f64>) -> Vec<f64> {
        let (symbolic, factor) = (self.symbolic, self.factor);
        let par = faer::get_global_parallelism();
        let n = c.len();
        let rhs = MatMut::from_column_major_slice_mut(&mut c, n, 1);
        match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(sym) => solve_lower_triangular_transpose_in_place(
                simplicial(sym, factor),
                Conj::No,
                rhs,
                par,
            ),
            SymbolicCholeskyRaw::Supernodal(sym) => {
                let l = SupernodalLltRef::new(sym, factor);
                match Subtrees::new(sym) {
                    Some(tree) => tree.backward(l, &mut c),
                    None => {
                        let mut mem = MemBuffer::new(sym.solve_in_place_scratch::<f64>(1, par));
                        l.l_transpose_solve_with_conj(
                            Conj::No,
                            MatMut::from_column_major_slice_mut(&mut c, n, 1),
                            par,
                            MemStack::new(&mut mem),
                        );
                    }
                }
            }
        }
        match symbolic.perm() {
            Some(perm) => perm.arrays().1.iter().map(|&k| c[k]).collect(),
            None => c,
        }
    }

    /// `L⁻¹ P v` for `v` given by its non-zero `entries` (original numbering),
    /// eliminating only the nodes on the paths from those entries to the root.
    pub fn forward_sparse(&self, entries: &[(usize, f64)]) -> PathColumn {
        let (symbolic, factor) = (self.symbolic, self.factor);
        let n = symbolic.nrows();
        let mut work = vec![0.0; n];
        let tree = Tree::new(symbolic, factor);
        let mut seen = vec![false; tree.len()];
        let mut reached = Vec::new();
        for &(i, v) in entries {
            let row = match symbolic.perm() {
                Some(perm) => perm.arrays().1[i],
                None => i,
            };
            work[row] += v;
            let mut node = Some(tree.node_of(row));
            while let Some(s) = node.filter(|&s| !seen[s]) {
                seen[s] = true;
                reached.push(s);
                node = tree.parent(s);
            }
        }
        // A parent's number exceeds its children's: ascending is an elimination order.
        reached.sort_unstable();
        let mut column = PathColumn {
            offsets: vec![0],
            ..Default::default()
        };
        for &s in &reached {
            let (start, size) = tree.eliminate(s, &mut work);
            column.nodes.push(s);
            column.starts.push(start);
            column.values.extend_from_slice(&work[start..start + size]);
            column.offsets.push(column.values.len());
        }
        column
    }
}

fn simplicial<'a>(
    sym: &'a SymbolicSimplicialCholesky<usize>,
    factor: &'a [f64],
) -> SparseColMatRef<'a, usize, f64> {
    SparseColMatRef::new(sym.factor(), factor)
}

/// The elimination tree of a factor's nodes.
enum Tree<'a> {
    /// Every column a node; faer stores each column's diagonal first.
    Simplicial(SparseColMatRef<'a, usize, f64>),
    Supernodal(
        &'a SymbolicSupernodalCholesky<usize>,
        SupernodalLltRef<'a, usize, f64>,
    ),
}

impl<'a> Tree<'a> {
    fn new(symbolic: &'a SymbolicCholesky<usize>, factor: &'a [f64]) -> Self {
        match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(sym) => Tree::Simplicial(simplicial(sym, factor)),
            SymbolicCholeskyRaw::Supernodal(sym) => {
                Tree::Supernodal(sym, SupernodalLltRef::new(sym, factor))
            }
        }
    }

    fn len(&self) -> usize {
        match self {
            Tree::Simplicial(l) => l.ncols(),
            Tree::Supernodal(sym, _) => sym.n_supernodes(),
        }
    }

    /// The node holding (permuted) row `row`.
    fn node_of(&self, row: usize) -> usize {
        match self {
            Tree::Simplicial(_) => row,
            Tree::Supernodal(sym, _) => sym.supernode_begin().partition_point(|&b| b <= row) - 1,
        }
    }

    fn parent(&self, s: usize) -> Option<usize> {
        match self {
            Tree::Simplicial(l) => l.row_idx_of_col_raw(s)[1..].iter().copied().min(),
            Tree::Supernodal(_, l) => {
                let first = l.supernode(s).pattern().iter().copied().min()?;
                Some(self.node_of(first))
            }
        }
    }

    /// Solves node `s`'s diagonal block in `work` and subtracts its
    /// contribution from the rows below; returns the node's first row and width.
    fn eliminate(&self, s: usize, work: &mut [f64]) -> (usize, usize) {
        match self {
            Tree::Simplicial(l) => {
                let (rows, values) = (l.row_idx_of_col_raw(s), l.val_of_col(s));
                work[s] /= values[0];
                let xs = work[s];
                for (&i, &v) in rows[1..].iter().zip(&values[1..]) {
                    work[i] -= v * xs;
                }
                (s, 1)
            }
            Tree::Supernodal(_, l) => {
                let node = l.supernode(s);
                let (start, pattern) = (node.start(), node.pattern());
                let size = node.val().ncols();
                let (top, below) = node.val().split_at_row(size);
                let x = &mut work[start..start + size];
                dense_lower_solve(
                    top,
                    MatMut::from_column_major_slice_mut(x, size, 1),
                    Par::Seq,
                );
                let mut update = Mat::<f64>::zeros(pattern.len(), 1);
                matmul(
                    update.as_mut(),
                    Accum::Replace,
                    below,
                    MatRef::from_column_major_slice(x, size, 1),
                    1.0,
                    Par::Seq,
                );
                for (k, &i) in pattern.iter().enumerate() {
                    work[i] -= update[(k, 0)];
                }
                (start, size)
            }
        }
    }
}

/// Subtrees of the supernodal elimination tree large enough to run on their
/// own thread in the backward half-solve.
const PARALLEL_SUBTREE_VALUES: usize = 1 << 16;

/// The supernodal elimination tree in postorder: every subtree is the
/// contiguous range of supernodes `first[s] ..= s`.
struct Subtrees {
    children: Vec<Vec<usize>>,
    roots: Vec<usize>,
    first: Vec<usize>,
    /// Offsets of the supernodes' values (`col_ptr_for_val`).
    values: Vec<usize>,
}

/// `x`, shared by the threads of the backward half-solve: each writes only the
/// rows of its own supernodes and reads only rows of their ancestors, which
/// are final before any descendant starts.
#[derive(Clone, Copy)]
struct SharedRows(*mut f64, usize);
// SAFETY: the threads write disjoint rows (above) and read rows nobody writes any more.
unsafe impl Send for SharedRows {}
unsafe impl Sync for SharedRows {}

impl Subtrees {
    /// The tree of `sym`; `None` when its supernodes are not in postorder
    /// (then faer's sequential half-solve serves).
    fn new(sym: &SymbolicSupernodalCholesky<usize>) -> Option<Self> {
        let ns = sym.n_supernodes();
        let begin = sym.supernode_begin();
        let node_of = |row: usize| begin.partition_point(|&b| b <= row) - 1;
        let rows = sym.col_ptr_for_row_idx();
        let (mut children, mut roots) = (vec![Vec::new(); ns], Vec::new());
        let mut first: Vec<usize> = (0..ns).collect();
        let mut size = vec![1usize; ns];
        for s in 0..ns {
            match sym.row_idx()[rows[s]..rows[s + 1]].iter().min() {
                Some(&row) => {
                    let p = node_of(row);
                    children[p].push(s);
                    first[p] = first[p].min(first[s]);
                    size[p] += size[s];
                }
                None => roots.push(s),
            }
        }
        let postorder = (0..ns).all(|s| s + 1 - first[s] == size[s]);
        postorder.then(|| Self {
            children,
            roots,
            first,
            values: sym.col_ptr_for_val().to_vec(),
        })
    }

    /// `x ← L⁻ᵀ x`, independent subtrees in parallel.
    fn backward(&self, l: SupernodalLltRef<'_, usize, f64>, x: &mut [f64]) {
        use rayon::prelude::*;
        let shared = SharedRows(x.as_mut_ptr(), x.len());
        self.roots
            .par_iter()
            .for_each(|&r| self.descend(l, r, shared));
    }

    fn descend(&self, l: SupernodalLltRef<'_, usize, f64>, mut s: usize, x: SharedRows) {
        use rayon::prelude::*;
        loop {
            Self::solve_node(l, s, x);
            let small = self.values[s + 1] - self.values[self.first[s]] < PARALLEL_SUBTREE_VALUES;
            match self.children[s].as_slice() {
                [] => return,
                _ if small => {
                    (self.first[s]..s)
                        .rev()
                        .for_each(|t| Self::solve_node(l, t, x));
                    return;
                }
                [only] => s = *only,
                several => {
                    several.par_iter().for_each(|&c| self.descend(l, c, x));
                    return;
                }
            }
        }
    }

    /// `x_s ← L_ssᵀ⁻¹ (x_s − L_bsᵀ x_b)` for supernode `s` (`b`: its pattern).
    fn solve_node(l: SupernodalLltRef<'_, usize, f64>, s: usize, x: SharedRows) {
        use faer::reborrow::ReborrowMut;
        let node = l.supernode(s);
        let (start, pattern) = (node.start(), node.pattern());
        let size = node.val().ncols();
        let (top, below) = node.val().split_at_row(size);
        // SAFETY: rows of the pattern belong to ancestors (final); the node's
        // own rows are written by this call only (see `SharedRows`).
        let gathered: Vec<f64> = pattern.iter().map(|&i| unsafe { *x.0.add(i) }).collect();
        debug_assert!(start + size <= x.1);
        let own = unsafe { std::slice::from_raw_parts_mut(x.0.add(start), size) };
        let mut own = MatMut::from_column_major_slice_mut(own, size, 1);
        matmul(
            own.rb_mut(),
            Accum::Add,
            below.transpose(),
            MatRef::from_column_major_slice(&gathered, pattern.len(), 1),
            -1.0,
            Par::Seq,
        );
        faer::linalg::triangular_solve::solve_upper_triangular_in_place(
            top.transpose(),
            own,
            Par::Seq,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::cholesky::{analyse_forced, laplacian};
    use faer::sparse::linalg::SupernodalThreshold;
    use faer::sparse::SymbolicSparseColMatRef;

    /// On both of faer's factor layouts: the two halves compose to the full
    /// solve (the supernodal backward half through subtrees on their own
    /// threads), and the sparse forward solve equals the dense one on every
    /// row (zero off its path), with the path a small part of the unknowns.
    #[test]
    fn halves_and_sparse_forward_match_the_full_solve() {
        // The supernodal grid is large enough for subtrees on their own threads.
        for (threshold, m) in [
            (SupernodalThreshold::FORCE_SIMPLICIAL, 30),
            (SupernodalThreshold::FORCE_SUPERNODAL, 160),
        ] {
            let n = m * m;
            let (col_ptr, row_idx, values) = laplacian(m, 0, 4.5);
            let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
            let mut chol = analyse_forced(sym, threshold);
            chol.factorize(SparseColMatRef::new(sym, &values)).unwrap();
            let llt = chol.double_factor().unwrap();
            if let SymbolicCholeskyRaw::Supernodal(sym) = llt.symbolic.raw() {
                let tree = Subtrees::new(sym).expect("faer numbers supernodes in postorder");
                let top = tree.roots[0];
                assert!(
                    tree.values[top + 1] - tree.values[tree.first[top]]
                        > 8 * PARALLEL_SUBTREE_VALUES
                );
            }
            let b: Vec<f64> = (0..n).map(|k| (0.3 * k as f64).cos()).collect();
            let mut full = b.clone();
            chol.solve_in_place(&mut full);
            let halves = llt.backward(llt.forward(&b));
            for (a, e) in halves.iter().zip(&full) {
                assert!((a - e).abs() < 1e-13 * e.abs().max(1.0), "{a} vs {e}");
            }
            let entries = [(m * m / 2 + 3, 1.0), (m * m / 2 + 4, -0.5), (7, 2.0)];
            let mut v = vec![0.0; n];
            entries.iter().for_each(|&(i, x)| v[i] += x);
            let dense = llt.forward(&v);
            let sparse = llt.forward_sparse(&entries);
            let mut scattered = vec![0.0; n];
            sparse.add_to(1.0, &mut scattered);
            for (a, e) in scattered.iter().zip(&dense) {
                assert!((a - e).abs() < 1e-14, "{a} vs {e}");
            }
            assert!(sparse.len() < n / 2, "path of {} of {n}", sparse.len());
            // Dot products: sparse·dense, sparse·sparse.
            let other = llt.forward_sparse(&[(n - 1, 1.0)]);
            let mut o = vec![0.0; n];
            other.add_to(1.0, &mut o);
            let exact: f64 = dense.iter().zip(&o).map(|(a, b)| a * b).sum();
            assert!((sparse.dot(&other) - exact).abs() < 1e-14 * exact.abs().max(1.0));
            assert!((sparse.dot_dense(&o) - exact).abs() < 1e-14 * exact.abs().max(1.0));
        }
    }
}
