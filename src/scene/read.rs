//! Reading scene files: TOML or JSON text into a [`SceneSpec`], and the
//! input files a scene names (regular files only, bounded in size, UTF-8).

use super::spec::SceneSpec;
use super::Scene;
use crate::error::{Error, InputError};
use std::path::Path;

/// Parses scene text; `json` selects JSON instead of TOML.
pub fn parse_spec(text: &str, json: bool) -> Result<SceneSpec, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if json {
        check_json(text)?;
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

/// Refuses what a JSON parser would otherwise resolve silently: a key given
/// twice in one object (serde keeps the last) and text after the scene's
/// value (two scenes pasted into one file would run the first). TOML refuses
/// both itself.
fn check_json(text: &str) -> Result<(), InputError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize::<_, UniqueKeys>(&mut *de).map_err(|e| {
        let field = path_or_root(&e.path().to_string());
        InputError::new(field, format!("{} (JSON)", e.inner()))
    })?;
    de.end().map_err(|e| {
        InputError::new(
            "scene",
            format!("text after the scene's JSON value: {e}; a file holds one scene"),
        )
    })
}

/// Any JSON value whose objects each name a key once ([`check_json`]).
struct UniqueKeys;

impl<'de> serde::Deserialize<'de> for UniqueKeys {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(UniqueKeysVisitor)
    }
}

struct UniqueKeysVisitor;

impl<'de> serde::de::Visitor<'de> for UniqueKeysVisitor {
    type Value = UniqueKeys;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_bool<E>(self, _: bool) -> Result<UniqueKeys, E> {
        Ok(UniqueKeys)
    }

    fn visit_i64<E>(self, _: i64) -> Result<UniqueKeys, E> {
        Ok(UniqueKeys)
    }

    fn visit_u64<E>(self, _: u64) -> Result<UniqueKeys, E> {
        Ok(UniqueKeys)
    }

    fn visit_f64<E>(self, _: f64) -> Result<UniqueKeys, E> {
        Ok(UniqueKeys)
    }

    fn visit_str<E>(self, _: &str) -> Result<UniqueKeys, E> {
        Ok(UniqueKeys)
    }

    fn visit_unit<E>(self) -> Result<UniqueKeys, E> {
        Ok(UniqueKeys)
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut a: A) -> Result<UniqueKeys, A::Error> {
        while a.next_element::<UniqueKeys>()?.is_some() {}
        Ok(UniqueKeys)
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut a: A) -> Result<UniqueKeys, A::Error> {
        let mut seen = std::collections::HashSet::new();
        while let Some(key) = a.next_key::<String>()? {
            if !seen.insert(key.clone()) {
                return Err(serde::de::Error::custom(format!(
                    "the key {key:?} is given twice in one object (give each key once)"
                )));
            }
            a.next_value::<UniqueKeys>()?;
        }
        Ok(UniqueKeys)
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

/// Largest scene file read, in bytes.
const MAX_SCENE_BYTES: u64 = 16 << 20;

/// Largest point file read, in bytes.
pub const MAX_POINT_FILE_BYTES: u64 = 4 << 30;

/// Reads an input file's bytes: regular files only (a pipe or a device would
/// hang or never end), at most `max_bytes`. `field` names the input in errors.
pub fn read_input_file(path: &Path, field: &str, max_bytes: u64) -> Result<Vec<u8>, Error> {
    use std::io::Read;
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        return Err(InputError::new(
            field,
            format!(
                "{} is not a regular file (a directory, pipe or device); give a file",
                path.display()
            ),
        )
        .into());
    }
    if meta.len() > max_bytes {
        return Err(InputError::new(
            field,
            format!(
                "{} has {} bytes; at most {max_bytes} are read",
                path.display(),
                meta.len()
            ),
        )
        .into());
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(max_bytes + 1).read_to_end(&mut bytes))
        .map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > max_bytes {
        return Err(InputError::new(
            field,
            format!(
                "{} grew beyond {max_bytes} bytes while read",
                path.display()
            ),
        )
        .into());
    }
    Ok(bytes)
}

/// Reads a text input file ([`read_input_file`]) as UTF-8 (UTF-16 is recognised
/// and named; the parsers skip a leading byte-order mark).
pub fn read_text_file(path: &Path, field: &str, max_bytes: u64) -> Result<String, Error> {
    let bytes = read_input_file(path, field, max_bytes)?;
    let utf16 = bytes.starts_with(&[0xFF, 0xFE])
        || bytes.starts_with(&[0xFE, 0xFF])
        || (bytes.len() >= 4 && (bytes[1] == 0 && bytes[3] == 0 || bytes[0] == 0 && bytes[2] == 0));
    match std::str::from_utf8(&bytes) {
        Ok(text) => Ok(text.to_string()),
        Err(_) if utf16 => Err(InputError::new(
            field,
            format!(
                "{} looks like UTF-16 text (byte-order mark or zero bytes between characters); \
                 save it as UTF-8",
                path.display()
            ),
        )
        .into()),
        Err(e) => Err(InputError::new(
            field,
            format!(
                "{} is not valid UTF-8 (first invalid byte at offset {}); save it as UTF-8 text",
                path.display(),
                e.valid_up_to()
            ),
        )
        .into()),
    }
}

/// Reads, parses and validates a scene file (`.json` is read as JSON, anything else as TOML).
pub fn load(path: &Path) -> Result<Scene, Error> {
    let text = read_text_file(path, "scene", MAX_SCENE_BYTES)?;
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
