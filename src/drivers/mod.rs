//! Drivers: from a validated scene to a solution.

pub mod quasi_static;
pub mod static_solve;
