//! # dhpd: implicit dual-horizon peridynamics
//!
//! dhpd solves static peridynamic problems by assembling the linearised tangent
//! stiffness and factorising it (faer sparse Cholesky or LU), instead of running
//! thousands of explicit steps. Horizons may vary from point to point: each bond
//! is owned by the point whose horizon holds it and carries its owner's
//! parameters (dual-horizon PD, Ren, Zhuang & Rabczuk), so a model can be fine
//! where it matters and coarse elsewhere without ghost forces.
//!
//! Data flows one way:
//!
//! ```text
//! scene file ─► scene::Scene (typed, validated)
//!            ─► discretization::Discretization (points, bonds)
//!            ─► model (bond kernels: force and tangent)
//!            ─► assembly (pattern once, values in parallel) ─► solve::pipeline (faer)
//!            ─► drivers::static_solve | drivers::quasi_static (+ damage) | drivers::dynamics
//!            ─► output (VTU and .pvd series, CSV, JSON, Matrix Market)
//! ```
//!
//! A scene with a `[quasi_static]` section and a fracture parameter per
//! material runs [`drivers::quasi_static::run`]: the prescribed displacements
//! are scaled by a load factor and bonds break by the criteria of [`damage`].
//! A scene with `[dynamics]` runs [`drivers::dynamics::run`]: explicit velocity
//! Verlet (or dynamic relaxation) on the same kernels, breaking bonds by the
//! same criteria.
//!
//! ```
//! let scene = dhpd::scene::parse_spec(r#"
//!     [model]
//!     dimension = "1d"
//!     [materials.steel]
//!     youngs_modulus = 1.0
//!     [[regions]]
//!     material = "steel"
//!     spacing = 0.01
//!     box = { min = [0.0], max = [1.0] }
//!     [[boundary]]
//!     name = "left"
//!     box = { min = [0.0], max = [0.03] }
//!     displacement = { x = 0.0 }
//!     [[boundary]]
//!     name = "right"
//!     box = { min = [0.97], max = [1.0] }
//!     displacement = { x = 1e-4 }
//! "#, false).unwrap();
//! let scene = dhpd::scene::Scene::try_from_spec(scene, std::path::Path::new("."), "bar").unwrap();
//! let solution = dhpd::drivers::static_solve::solve(&scene).unwrap();
//! assert!(solution.residual < 1e-10);
//! ```

pub mod assembly;
pub mod csr;
pub mod damage;
pub mod default_scene;
pub mod discretization;
pub mod drivers;
pub mod error;
pub mod geometry;
pub mod memory;
pub mod model;
pub mod notes;
pub mod output;
pub mod reference;
pub mod scene;
pub mod solve;
pub mod validation;
pub mod vector;

pub use drivers::dynamics::{DynamicsSolution, Outcome as DynamicsOutcome};
pub use drivers::quasi_static::QuasiStaticSolution;
pub use drivers::static_solve::StaticSolution;
pub use drivers::{check, run, Observer, Progress, Snapshot, Solution};
pub use error::{Error, InputError, NumericalError};
pub use notes::Notes;
pub use solve::pipeline::Route;
