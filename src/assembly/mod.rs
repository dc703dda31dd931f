//! Assembly: degrees of freedom and constraints, loads, the sparsity pattern
//! (built once) and the stiffness values (filled in parallel, column by column),
//! plus matrix-free internal forces from the same kernels.
//!
//! Constraints are eliminated: `K` is assembled on the free degrees of freedom
//! only, and the prescribed values enter the right-hand side through the
//! linearised internal force, `b = f_ext,free + F_int(u_prescribed)_free`
//! (since `F_int = −K u` for the linearised model).

pub mod dofs;
pub mod forces;
pub mod loads;
pub mod pattern;
pub mod rigid_modes;
pub mod stiffness;

/// Splits `data` into consecutive mutable chunks at `offsets` (length n + 1, starting at 0).
pub(crate) fn split_at_offsets<'a, T>(
    mut data: &'a mut [T],
    offsets: &[usize],
) -> Vec<&'a mut [T]> {
    let mut chunks = Vec::with_capacity(offsets.len().saturating_sub(1));
    for w in offsets.windows(2) {
        let (head, tail) = data.split_at_mut(w[1] - w[0]);
        chunks.push(head);
        data = tail;
    }
    chunks
}
