//! The library's front door: the single-edge-notched tension plate of
//! validation/fracture (W = 0.1 m, free length 0.2 m between clamped grips,
//! edge notch a = W/2, spacing W/30, m = 3.015, E = 30 GPa, G₀ = 200 J/m²,
//! bond-based, plane stress), built in Rust instead of TOML, run with the
//! event-driven quasi-static driver, and its peak load printed. It is the
//! scene `validation/fracture/scenes/sent_bond_based_event_n30_m3.toml`.
//!
//! `cargo run --release --example library`

use dhpd::scene::{BoundarySpec, BoxSpec, ComponentsSpec, CrackSpec, Dimension, FractureSpec};
use dhpd::scene::{MaterialSpec, ModelSpec, QuasiStaticSpec, RegionSpec, SceneSpec};

fn main() -> Result<(), dhpd::Error> {
    let (width, length) = (0.1, 0.2);
    let h = width / 30.0;
    let grip = 4.0 * h; // whole spacings, at least a horizon deep
    let (top, bottom) = (0.5 * length + grip, -0.5 * length - grip);
    let slab = |y0: f64, y1: f64| BoxSpec::new([0.0, y0], [width, y1]);
    let guard = 0.5 * length - 0.1 * width;

    let scene = SceneSpec::new(ModelSpec::new(Dimension::PlaneStress))
        .named("library_sent")
        .with_horizon_factor(3.015)
        .with_material("plate", MaterialSpec::new(3e10).fracture_energy(200.0))
        .with_region(RegionSpec::new("plate", h, slab(bottom, top)))
        .with_crack(CrackSpec::segment([0.0, 0.0], [0.5 * width, 0.0]))
        .with_boundary(BoundarySpec::displacement(
            "bottom",
            slab(bottom, -0.5 * length),
            ComponentsSpec::new().x(0.0).y(0.0),
        ))
        .with_boundary(BoundarySpec::displacement(
            "top",
            slab(0.5 * length, top),
            ComponentsSpec::new().x(0.0).y(1e-4),
        ))
        .with_fracture(
            FractureSpec::default()
                .no_fail(slab(bottom, -guard))
                .no_fail(slab(guard, top)),
        )
        .with_quasi_static(QuasiStaticSpec::new(1.0))
        .build()?;

    let solution = dhpd::run(&scene, &mut ())?;
    let solution = solution
        .into_quasi_static()
        .expect("a scene with [quasi_static] runs the quasi-static driver");
    let top = 1; // the second support
    let peak = solution.peak(top).expect("at least one state");
    println!(
        "{}: {} states, {} bonds broken; peak load {:.6e} N/m at grip displacement {:.6e} m (state {})",
        scene.name,
        solution.records.len(),
        solution.records.last().map_or(0, |r| r.broken_total),
        peak.reactions[top][1],
        peak.displacement,
        peak.step,
    );
    Ok(())
}
