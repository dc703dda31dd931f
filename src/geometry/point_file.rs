//! Point clouds from text files, one point per line (like Peridigm's text
//! discretisation):
//!
//! ```text
//! # comment lines start with '#'
//! x y [z] volume [horizon] [material]
//! ```
//!
//! Columns are separated by commas and/or white space. A file has `d + 1`
//! columns (positions and volume), `d + 2` (plus the horizon radius) or `d + 3`
//! (plus a material name from the scene). The volume includes the thickness
//! (2D) or the area (1D). Without a horizon column a point's horizon is
//! `horizon_factor × (volume / thickness)^(1/d)`. A leading UTF-8 byte-order
//! mark is skipped, as in scenes and meshes.

use super::grid::{RawPoint, Source};
use crate::error::{approx, echo, echo_list, num, InputError};
use crate::scene::{Material, PointFile};

/// Parses point-file text. `field` names the file in errors (`point_files[0]`).
pub fn parse(
    text: &str,
    file: &PointFile,
    index: usize,
    d: usize,
    thickness: f64,
    materials: &[Material],
) -> Result<Vec<RawPoint>, InputError> {
    // A UTF-8 byte-order mark is not part of the first row (as for scenes).
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut points = Vec::new();
    let mut width = None;
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let at = |msg: String| {
            InputError::new(
                format!("{} ({}, line {})", file.field, file.path.display(), n + 1),
                msg,
            )
        };
        let cols: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .collect();
        if cols.len() < d + 1 || cols.len() > d + 3 {
            return Err(at(format!(
                "{} columns; a {d}D point file has {} (x.. volume), {} (+ horizon) or {} (+ material)",
                cols.len(), d + 1, d + 2, d + 3)));
        }
        if let Some(w) = width {
            if w != cols.len() {
                return Err(at(format!(
                    "{} columns where earlier lines have {w}; every row needs the same columns",
                    cols.len()
                )));
            }
        }
        width = Some(cols.len());
        let number = |k: usize, what: &str| -> Result<f64, InputError> {
            let v: f64 = cols[k]
                .parse()
                .map_err(|_| at(format!("{what} \"{}\" is not a number", echo(cols[k]))))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(at(format!(
                    "{what} is {}; only finite numbers are valid",
                    num(v)
                )))
            }
        };
        let mut x = [0.0; 3];
        for (a, name) in ["x", "y", "z"].iter().enumerate().take(d) {
            x[a] = number(a, name)?;
        }
        let volume = number(d, "volume")?;
        if volume <= 0.0 {
            return Err(at(format!("volume {} must be positive", num(volume))));
        }
        let spacing = (volume / if d < 3 { thickness } else { 1.0 }).powf(1.0 / d as f64);
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(at(format!(
                "volume {} gives an equivalent spacing (volume / thickness)^(1/{d}) = {} \
                 outside the floating-point range",
                num(volume),
                num(spacing)
            )));
        }
        let horizon = if cols.len() >= d + 2 {
            let h = number(d + 1, "horizon")?;
            if h <= 0.0 {
                return Err(at(format!("horizon {} must be positive", num(h))));
            }
            h
        } else {
            file.horizon_factor * spacing
        };
        if !horizon.is_finite() {
            return Err(at(format!(
                "the horizon ({} × spacing {}) overflows",
                num(file.horizon_factor),
                num(spacing)
            )));
        }
        let factor = crate::scene::fields::MAX_HORIZON_FACTOR;
        if horizon > factor * spacing {
            return Err(at(format!(
                "horizon {} is {} times the point's equivalent spacing {} \
                 ((volume / thickness)^(1/{d})): implausibly large (above {factor}); typical \
                 horizons are 2 to 5 spacings",
                num(horizon),
                approx(horizon / spacing),
                num(spacing)
            )));
        }
        let material = if cols.len() == d + 3 {
            let name = cols[d + 2];
            materials
                .iter()
                .position(|m| m.name == name)
                .ok_or_else(|| {
                    let known: Vec<_> = materials.iter().map(|m| m.name.as_str()).collect();
                    at(format!(
                        "unknown material \"{name}\"; defined: {}",
                        echo_list(known)
                    ))
                })?
        } else {
            file.material.ok_or_else(|| {
                at("no material column and no `material` in the scene for this file".into())
            })?
        };
        points.push(RawPoint {
            x,
            volume,
            spacing,
            horizon,
            material: material as u32,
            source: Source::File {
                file: index as u32,
                line: n as u32 + 1,
            },
        });
    }
    if points.is_empty() {
        return Err(InputError::new(
            format!("{}.path", file.field),
            format!("{} contains no point", file.path.display()),
        ));
    }
    Ok(points)
}
