//! Building a scene in code: constructors for the sections of a
//! [`SceneSpec`] with the same defaults as the TOML, and
//! [`SceneSpec::build`], which validates the result exactly as a file is
//! validated (every check of [`Scene::try_from_spec`] applies).

use super::spec::*;
use super::Scene;
use crate::error::InputError;
use std::path::Path;

impl SceneSpec {
    /// A scene with this model and nothing else: add materials, bodies,
    /// supports and loads with the `with_*` methods.
    pub fn new(model: ModelSpec) -> Self {
        SceneSpec {
            name: None,
            model,
            discretization: DiscretizationSpec::default(),
            materials: Default::default(),
            regions: Vec::new(),
            point_files: Vec::new(),
            meshes: Vec::new(),
            holes: Vec::new(),
            cracks: Vec::new(),
            boundary: Vec::new(),
            loads: Vec::new(),
            solver: SolverSpec::default(),
            output: OutputSpec::default(),
            fracture: None,
            quasi_static: None,
            dynamics: None,
            initial_conditions: Vec::new(),
        }
    }

    /// Names the scene (used in reports; default `"scene"`).
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = Some(name.into());
        self
    }

    /// Sets the horizon as a multiple of the local spacing (default 3.015).
    pub fn with_horizon_factor(mut self, factor: f64) -> Self {
        self.discretization.horizon_factor = factor;
        self
    }

    /// Adds (or replaces) the material `name`.
    pub fn with_material(mut self, name: impl Into<String>, material: MaterialSpec) -> Self {
        self.materials.insert(name.into(), material);
        self
    }

    /// Adds a box filled with a regular grid.
    pub fn with_region(mut self, region: RegionSpec) -> Self {
        self.regions.push(region);
        self
    }

    /// Adds a circular (2D) or spherical (3D) hole.
    pub fn with_hole(mut self, center: impl Into<Vec<f64>>, radius: f64) -> Self {
        self.holes.push(HoleSpec {
            center: center.into(),
            radius,
            axis: None,
        });
        self
    }

    /// Adds a 3D through hole: a cylinder of `radius` about the line through
    /// `center` along `axis`.
    pub fn with_through_hole(
        mut self,
        center: impl Into<Vec<f64>>,
        axis: impl Into<Vec<f64>>,
        radius: f64,
    ) -> Self {
        self.holes.push(HoleSpec {
            center: center.into(),
            radius,
            axis: Some(axis.into()),
        });
        self
    }

    /// Adds a pre-crack that no bond may cross.
    pub fn with_crack(mut self, crack: CrackSpec) -> Self {
        self.cracks.push(crack);
        self
    }

    /// Adds a support (prescribed displacement or velocity).
    pub fn with_boundary(mut self, boundary: BoundarySpec) -> Self {
        self.boundary.push(boundary);
        self
    }

    /// Adds a traction or body force.
    pub fn with_load(mut self, load: LoadSpec) -> Self {
        self.loads.push(load);
        self
    }

    /// Sets the `[solver]` section.
    pub fn with_solver(mut self, solver: SolverSpec) -> Self {
        self.solver = solver;
        self
    }

    /// Sets the `[output]` section.
    pub fn with_output(mut self, output: OutputSpec) -> Self {
        self.output = output;
        self
    }

    /// Sets the `[fracture]` section.
    pub fn with_fracture(mut self, fracture: FractureSpec) -> Self {
        self.fracture = Some(fracture);
        self
    }

    /// Selects the quasi-static fracture driver.
    pub fn with_quasi_static(mut self, quasi_static: QuasiStaticSpec) -> Self {
        self.quasi_static = Some(quasi_static);
        self
    }

    /// Validates the scene as a scene file is validated (relative paths are
    /// read from the working directory).
    pub fn build(self) -> Result<Scene, InputError> {
        Scene::try_from_spec(self, Path::new("."), "scene")
    }
}

impl ModelSpec {
    /// The bond-based model in this dimension, dual horizons, thickness and
    /// area 1.
    pub fn new(dimension: Dimension) -> Self {
        ModelSpec {
            kind: ModelKind::default(),
            dimension,
            thickness: None,
            area: None,
            horizons: HorizonMode::default(),
            dilatation: None,
            formulation: None,
            allow_any_poisson: false,
        }
    }

    /// Selects the model (`BondBased` or `Shear`).
    pub fn kind(mut self, kind: ModelKind) -> Self {
        self.kind = kind;
        self
    }
}

impl MaterialSpec {
    /// A material with Young's modulus `youngs_modulus` (Pa) and nothing else
    /// (bond-based: the Poisson ratio the model implies).
    pub fn new(youngs_modulus: f64) -> Self {
        MaterialSpec {
            youngs_modulus,
            poisson_ratio: None,
            fracture_energy: None,
            critical_stretch: None,
            critical_deviatoric_strain: None,
            density: None,
        }
    }

    /// Sets the Poisson ratio ν.
    pub fn poisson_ratio(mut self, nu: f64) -> Self {
        self.poisson_ratio = Some(nu);
        self
    }

    /// Sets the fracture energy G₀ (J/m²).
    pub fn fracture_energy(mut self, g0: f64) -> Self {
        self.fracture_energy = Some(g0);
        self
    }

    /// Sets the mass density ρ (kg/m³).
    pub fn density(mut self, rho: f64) -> Self {
        self.density = Some(rho);
        self
    }
}

impl BoxSpec {
    /// The box with corners `min` and `max`.
    pub fn new(min: impl Into<Vec<f64>>, max: impl Into<Vec<f64>>) -> Self {
        BoxSpec {
            min: min.into(),
            max: max.into(),
        }
    }
}

impl RegionSpec {
    /// The box `bounds` filled with a grid of spacing `spacing` of `material`.
    pub fn new(material: impl Into<String>, spacing: f64, bounds: BoxSpec) -> Self {
        RegionSpec {
            material: material.into(),
            spacing,
            bounds,
            horizon: None,
            horizon_factor: None,
        }
    }
}

impl CrackSpec {
    /// A 2D crack along the segment `from`-`to`.
    pub fn segment(from: impl Into<Vec<f64>>, to: impl Into<Vec<f64>>) -> Self {
        CrackSpec {
            from: Some(from.into()),
            to: Some(to.into()),
            origin: None,
            edge1: None,
            edge2: None,
        }
    }

    /// A 3D crack: the parallelogram `origin`, `origin + edge1`, `origin + edge2`.
    pub fn parallelogram(
        origin: impl Into<Vec<f64>>,
        edge1: impl Into<Vec<f64>>,
        edge2: impl Into<Vec<f64>>,
    ) -> Self {
        CrackSpec {
            from: None,
            to: None,
            origin: Some(origin.into()),
            edge1: Some(edge1.into()),
            edge2: Some(edge2.into()),
        }
    }
}

impl ComponentsSpec {
    /// No component prescribed.
    pub fn new() -> Self {
        Self::default()
    }

    /// Prescribes the x component.
    pub fn x(mut self, value: f64) -> Self {
        self.x = Some(value);
        self
    }

    /// Prescribes the y component.
    pub fn y(mut self, value: f64) -> Self {
        self.y = Some(value);
        self
    }

    /// Prescribes the z component.
    pub fn z(mut self, value: f64) -> Self {
        self.z = Some(value);
        self
    }
}

impl BoundarySpec {
    /// Prescribed displacement `components` on the points inside `bounds`.
    pub fn displacement(
        name: impl Into<String>,
        bounds: BoxSpec,
        components: ComponentsSpec,
    ) -> Self {
        BoundarySpec {
            name: name.into(),
            bounds: Some(bounds),
            group: None,
            displacement: Some(components),
            velocity: None,
            time_function: None,
        }
    }
}

impl FractureSpec {
    /// Bonds whose both ends lie inside `bounds` never break (e.g. grips).
    pub fn no_fail(mut self, bounds: BoxSpec) -> Self {
        self.no_fail.push(NoFailSpec { bounds });
        self
    }
}

impl QuasiStaticSpec {
    /// The event-driven strategy up to `max_load_factor` times the prescribed
    /// displacements.
    pub fn new(max_load_factor: f64) -> Self {
        QuasiStaticSpec {
            strategy: Strategy::default(),
            max_load_factor,
            steps: None,
            max_broken_per_step: None,
            min_step_fraction: None,
            tolerance: None,
            max_resolves: None,
            max_events: None,
            stop_after_peak: None,
        }
    }
}
