//! Drivers: from a validated scene to a solution.

pub mod dynamics;
pub mod quasi_static;
pub mod static_solve;
