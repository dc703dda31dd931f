//! What a run produces: the [`crate::Solution`] of each driver and the data it
//! is made of (points and bonds, supports and their reactions, loads, records,
//! solver reports, timings).

pub use crate::assembly::dofs::{ConstrainedSet, DofMap};
pub use crate::assembly::loads::AppliedLoad;
pub use crate::damage::{CalibratedGroup, CalibrationReport};
pub use crate::discretization::groups::PointGroup;
pub use crate::discretization::{Bonds, Discretization, Points};
pub use crate::drivers::dynamics::{
    DynamicsSolution, DynamicsTimings, Outcome as DynamicsOutcome, Record,
};
pub use crate::drivers::quasi_static::{
    Outcome as FractureOutcome, QuasiStaticSolution, ResolveRecord, StateKind, StepRecord,
};
pub use crate::drivers::setup::{Plan, Setup, Timings};
pub use crate::drivers::static_solve::{Counts, StaticSolution};
pub use crate::drivers::system::Reaction;
pub use crate::geometry::grid::Source;
pub use crate::model::Block;
pub use crate::solve::cholesky::PivotStats;
pub use crate::solve::gmres::GmresReport;
pub use crate::solve::pipeline::{Route, SolveReport};
pub use crate::solve::route::OrderingReport;
