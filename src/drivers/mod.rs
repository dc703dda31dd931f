//! Drivers: from a validated scene to a solution.

pub mod static_solve;
