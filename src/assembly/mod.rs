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
