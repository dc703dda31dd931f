//! Scenes: parsing (TOML or JSON) and validation into a typed [`Scene`].
//!
//! No numerics happen here. Every check names the offending field with a dotted
//! path (`regions[1].spacing`) and says what would be valid. Checks that need the
//! points (a boundary box that selects nothing, a traction face with no point)
//! are done by [`crate::discretization`] right after the points exist and before
//! any bond is built.

mod dynamics;
mod spec;
mod validate;

pub use dynamics::{
    Dynamics, Gaussian, InitialCondition, Motion, RunLength, TimeFunction,
    MAX_STEPS as MAX_DYNAMICS_STEPS,
};
pub use spec::*;
pub use validate::{
    Aabb, Crack, FractureParameter, FractureSettings, Hole, HorizonRule, Load, LoadTarget,
    Material, OutputSettings, PointFile, Prescribed, Probe, Profile, QuasiStatic, Region, Scene,
    MAX_HORIZON_FACTOR,
};

use crate::error::{Error, InputError};
use std::path::Path;

/// The scene of `cargo run` without arguments: the 2D bimaterial strip
/// (validation/bimaterial_bar), coarse enough to run in a second.
pub const DEFAULT_SCENE: &str = include_str!("../../validation/bimaterial_bar/strip_2d.toml");

/// Parses scene text; `json` selects JSON instead of TOML.
pub fn parse_spec(text: &str, json: bool) -> Result<SceneSpec, InputError> {
    if json {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            let field = path_or_root(&e.path().to_string());
            InputError::new(field, format!("{} (JSON)", e.inner()))
        })
    } else {
        let de = toml::de::Deserializer::parse(text).map_err(|e| toml_error(text, &e))?;
        serde_path_to_error::deserialize(de).map_err(|e| {
            let field = path_or_root(&e.path().to_string());
            InputError::new(field, toml_error(text, e.inner()).message)
        })
    }
}

fn path_or_root(path: &str) -> String {
    if path.trim().is_empty() || path == "." || path == "?" {
        "scene".to_string()
    } else {
        path.to_string()
    }
}

fn toml_error(text: &str, e: &toml::de::Error) -> InputError {
    let location = e
        .span()
        .map(|span| {
            let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
            format!(" (line {line})")
        })
        .unwrap_or_default();
    InputError::new("scene", format!("{}{location}", e.message().trim_end()))
}

/// Reads, parses and validates a scene file (`.json` is read as JSON, anything else as TOML).
pub fn load(path: &Path) -> Result<Scene, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let json = path
        .extension()
        .is_some_and(|ext| ext.eq_ignore_ascii_case("json"));
    let spec = parse_spec(&text, json)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let default_name = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    Ok(Scene::try_from_spec(
        spec,
        base,
        default_name.as_deref().unwrap_or("scene"),
    )?)
}
