//! Shared helpers for the integration tests: scene builders and dense views.
#![allow(dead_code)]

use dhpd::assembly::dofs::DofMap;
use dhpd::assembly::pattern::Pattern;
use dhpd::assembly::stiffness::Stiffness;
use dhpd::discretization::{self, Discretization};
use dhpd::model::Model;
use dhpd::scene::{parse_spec, Scene};
use std::path::Path;

/// Parses and validates a TOML scene.
pub fn scene(text: &str) -> Scene {
    Scene::try_from_spec(
        parse_spec(text, false).expect("test scene parses"),
        Path::new("."),
        "test",
    )
    .expect("test scene is valid")
}

/// A small body in each setting, optionally with a second region of twice the
/// spacing (a horizon jump) and a second material.
pub fn small_body(dimension: &str, jump: bool, extra_model: &str) -> Scene {
    let (d, h) = match dimension {
        "1d" => (1, 0.1),
        "3d" => (3, 0.25),
        _ => (2, 0.1),
    };
    let lo = |x: f64| match d {
        1 => format!("[{x}]"),
        2 => format!("[{x}, 0.0]"),
        _ => format!("[{x}, 0.0, 0.0]"),
    };
    let hi = |x: f64| match d {
        1 => format!("[{x}]"),
        2 => format!("[{x}, 0.8]"),
        _ => format!("[{x}, 1.0, 1.0]"),
    };
    // The shear model takes any Poisson ratio (and needs one); bond-based uses its own.
    let shear = extra_model.contains("shear");
    let (nu_a, nu_b) = if shear {
        ("poisson_ratio = 0.3\n", "poisson_ratio = 0.2\n")
    } else {
        ("", "")
    };
    let mut text = format!(
        "[model]\ndimension = \"{dimension}\"\n{extra_model}\n\
         [materials.a]\nyoungs_modulus = 2.0e9\n{nu_a}[materials.b]\nyoungs_modulus = 5.0e9\n{nu_b}\
         [[regions]]\nmaterial = \"a\"\nspacing = {h}\nbox = {{ min = {}, max = {} }}\n",
        lo(0.0),
        hi(if d == 3 { 1.0 } else { 0.8 })
    );
    if jump {
        let x0 = if d == 3 { 1.0 } else { 0.8 };
        text += &format!(
            "[[regions]]\nmaterial = \"b\"\nspacing = {}\nbox = {{ min = {}, max = {} }}\n",
            2.0 * h,
            lo(x0),
            hi(x0 + 8.0 * h)
        );
    }
    scene(&text)
}

/// Discretisation of a scene.
pub fn disc(scene: &Scene) -> Discretization {
    discretization::build(scene).expect("discretisation succeeds")
}

/// The dense stiffness on all degrees of freedom (no constraint), `n d × n d`.
pub fn dense_stiffness<M: Model>(model: &M, disc: &Discretization) -> Vec<Vec<f64>> {
    let dofs = DofMap::new(&disc, &[]).unwrap();
    let pattern = Pattern::new(disc, &dofs, model.coupling(), None).unwrap();
    let k = Stiffness::assemble(model, disc, &dofs, &pattern);
    let n = dofs.n_free();
    let mut dense = vec![vec![0.0; n]; n];
    for col in 0..n {
        for p in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
            dense[pattern.row_idx[p]][col] = k.values[p];
        }
    }
    dense
}

/// Deterministic pseudo-random numbers in [-1, 1) (xorshift), so tests need no extra crate.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E3779B97F4A7C15) | 1)
    }
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// Largest absolute entry of a list of vectors (first `d` components).
pub fn max_abs(v: &[[f64; 3]], d: usize) -> f64 {
    v.iter()
        .flat_map(|x| x[..d].iter())
        .fold(0.0f64, |m, x| m.max(x.abs()))
}

/// A 0.2 m × 0.1 m plane-stress plate (200 points, left edge clamped, right edge
/// pulled by a traction): the base of `tests/bad_scenes.rs` and a seed of
/// `tests/fuzz_parsers.rs`.
pub const PLATE_SCENE: &str = r#"# 0.2 m x 0.1 m plate, spacing 0.01 m (200 points)
name = "bad_scenes_base"

[model]
dimension = "plane_stress"
thickness = 0.01

[discretization]
horizon_factor = 3.015

[materials.soft]
youngs_modulus = 1.0e9
poisson_ratio = 0.3333333333333333

[[regions]]
material = "soft"
spacing = 0.01
box = { min = [0.0, 0.0], max = [0.2, 0.1] }

[[boundary]]
name = "left"
box = { min = [0.0, 0.0], max = [0.01, 0.1] }
displacement = { x = 0.0, y = 0.0 }

[[loads]]
name = "pull"
kind = "traction"
face = "+x"
box = { min = [0.19, 0.0], max = [0.2, 0.1] }
value = [1.0e6, 0.0]

[[output.profiles]]
name = "centerline"
from = [0.0, 0.05]
to = [0.2, 0.05]
"#;
