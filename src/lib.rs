//! # dhpd: implicit dual-horizon peridynamics
//!
//! dhpd solves peridynamic problems by assembling the linearised tangent
//! stiffness and factorising it (sparse Cholesky or LU, or a two-level
//! iterative solver), instead of running thousands of explicit steps; it also
//! runs quasi-static fracture under prescribed displacement and explicit
//! dynamics. Horizons may vary from point to point: each bond is owned by the
//! point whose horizon holds it and carries its owner's parameters
//! (dual-horizon PD, Ren, Zhuang & Rabczuk), so a model can be fine where it
//! matters and coarse elsewhere without ghost forces.
//!
//! **The front door.** Describe a [`scene::Scene`] (read a TOML or JSON file
//! with [`scene::load`], or build one in code from [`scene::SceneSpec`] and its
//! sections), then [`run`] it: the driver the scene asks for runs (a static
//! solve; quasi-static fracture with `[quasi_static]`; explicit dynamics or
//! dynamic relaxation with `[dynamics]`), watched by an [`Observer`] (its
//! notes, progress, records and snapshots), and returns a [`Solution`]
//! ([`results`] holds the types it is made of). [`output::Results`] writes it
//! to disk as the command line does.
//!
//! ```
//! use dhpd::scene::{BoundarySpec, BoxSpec, ComponentsSpec, Dimension, MaterialSpec};
//! use dhpd::scene::{ModelSpec, RegionSpec, SceneSpec};
//!
//! // A 1D bar, 1 m long, held at the left end and stretched by 1e-4 m.
//! let scene = SceneSpec::new(ModelSpec::new(Dimension::One))
//!     .with_material("steel", MaterialSpec::new(2.0e11))
//!     .with_region(RegionSpec::new("steel", 0.01, BoxSpec::new([0.0], [1.0])))
//!     .with_boundary(BoundarySpec::displacement(
//!         "left",
//!         BoxSpec::new([0.0], [0.03]),
//!         ComponentsSpec::new().x(0.0),
//!     ))
//!     .with_boundary(BoundarySpec::displacement(
//!         "right",
//!         BoxSpec::new([0.97], [1.0]),
//!         ComponentsSpec::new().x(1e-4),
//!     ))
//!     .build()?;
//! let solution = dhpd::run(&scene, &mut ())?.into_static().expect("a static scene");
//! assert!(solution.residual < 1e-10);
//! # Ok::<(), dhpd::Error>(())
//! ```
//!
//! **Inside**, data flows one way; each layer uses only those before it and
//! the ground floor (`error`, `vector`, `memory`, `csr`, `notes`):
//!
//! ```text
//! scene ─► geometry ─► discretization ─► model ─► assembly ─► solve ─► drivers ─► output
//!  (typed,   (grids, files,  (points, bonds,  (bond     (pattern,    (sees     (setup, static,  (VTU,
//!  validated) meshes, cracks) one transpose)  kernels)  K, loads)    matrices) fracture, explicit) CSV, JSON)
//! ```
//!
//! The internals are crate-private; the `fixtures` feature opens them (and the
//! validation cases) to the crate's own tests, examples and studies. It is not
//! a stable API.

/// Declares internal modules: crate-private, public (and hidden from the
/// documentation) with the `fixtures` feature.
macro_rules! internal {
    ($($name:ident),* $(,)?) => {$(
        #[cfg(feature = "fixtures")]
        #[doc(hidden)]
        pub mod $name;
        #[cfg(not(feature = "fixtures"))]
        pub(crate) mod $name;
    )*};
}

pub mod default_scene;
pub mod error;
pub mod output;
pub mod results;
pub mod scene;

internal!(
    assembly,
    csr,
    damage,
    discretization,
    drivers,
    geometry,
    memory,
    model,
    notes,
    processes,
    reference,
    solve,
    vector
);

#[cfg(feature = "fixtures")]
#[doc(hidden)]
pub mod validation;

/// MPI runs through PETSc (the `mpi` feature): hold a [`mpi::Petsc`] (PETSc
/// and MPI initialised for its life) and scenes with `solver.method =
/// "petsc"` solve on every process of the run (`mpirun -np N`). Each process
/// discretises the whole body and assembles its own columns of `K` (and its
/// ghost points'); PETSc distributes the linear solve; every process receives
/// the whole solution. [`mpi::share_path`] and [`mpi::on_every_process`] let
/// the processes write one results directory together
/// ([`output::Results::in_pieces`]).
#[cfg(feature = "mpi")]
pub mod mpi {
    pub use crate::solve::petsc::{on_every_process, share_path, Petsc, PetscReport};
}

pub use drivers::{check, run, Observer, Progress, Snapshot, Solution};
pub use error::{Error, InputError, NumericalError};
pub use notes::Notes;
