//! Loading scenes: TOML text → table → `--set` overrides → key and type checks
//! against the schema (the default scene) → typed [`Scene`] → range checks.
//! Every failure is one line naming the bad value and what is allowed.

use super::{BUILTIN_SCENES, Scene, WaterModel};
use std::path::Path;
use toml::{Table, Value};

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SceneError {
    #[error("unknown scene `{name}`: built-in scenes are {list}; or give a path to a .toml file")]
    UnknownScene { name: String, list: String },
    #[error("cannot read scene file {path}: {reason}")]
    Io { path: String, reason: String },
    #[error("{origin}:{line}:{column}: TOML syntax error: {message}")]
    Syntax { origin: String, line: usize, column: usize, message: String },
    #[error("{origin}: unknown key `{key}`{suggestion}")]
    UnknownKey { origin: String, key: String, suggestion: String },
    #[error("{origin}: `{key}` must be {expected}, got {got}")]
    WrongType { origin: String, key: String, expected: String, got: String },
    #[error("`{key}` = {value} is out of range: {allowed}")]
    OutOfRange { key: String, value: String, allowed: String },
    #[error("bad --set `{text}`: {reason}")]
    BadOverride { text: String, reason: String },
}

fn type_name(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "a string",
        Value::Integer(_) => "an integer",
        Value::Float(_) => "a number",
        Value::Boolean(_) => "true or false",
        Value::Datetime(_) => "a date",
        Value::Array(_) => "an array",
        Value::Table(_) => "a table",
    }
}

fn show(v: &Value) -> String {
    let s = v.to_string();
    if s.len() > 40 { format!("{}…", &s[..40]) } else { s }
}

fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            cur.push((prev[j] + usize::from(ca != *cb)).min(prev[j + 1] + 1).min(cur[j] + 1));
        }
        prev = cur;
    }
    prev[b.len()]
}

fn all_keys(table: &Table, prefix: &str, out: &mut Vec<String>) {
    for (k, v) in table {
        let path = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
        if let Value::Table(t) = v {
            all_keys(t, &path, out);
        }
        out.push(path);
    }
}

fn suggestion(key: &str, schema: &Table) -> String {
    let mut keys = Vec::new();
    all_keys(schema, "", &mut keys);
    let last = key.rsplit('.').next().unwrap_or(key);
    let best = keys
        .iter()
        .map(|k| {
            let k_last = k.rsplit('.').next().unwrap_or(k);
            (levenshtein(key, k).min(levenshtein(last, k_last) + 1), k)
        })
        .min();
    match best {
        Some((d, k)) if d <= 3.max(key.len() / 3) => format!("; did you mean `{k}`?"),
        _ => {
            let sections: Vec<&String> = schema.keys().collect();
            format!(
                " (sections are {})",
                sections.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
            )
        }
    }
}

/// Check every key of `user` exists in `schema` with a compatible type;
/// integers given where numbers are expected become floats.
fn check_against_schema(
    user: &mut Table,
    schema: &Table,
    prefix: &str,
    origin: &str,
    root: &Table,
) -> Result<(), SceneError> {
    for (k, v) in user.iter_mut() {
        let path = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
        if path == "objects" {
            check_objects(v, origin)?;
            continue;
        }
        let Some(expected) = schema.get(k) else {
            return Err(SceneError::UnknownKey {
                origin: origin.into(),
                key: path.clone(),
                suggestion: suggestion(&path, root),
            });
        };
        check_value(v, expected, &path, origin, root)?;
    }
    Ok(())
}

/// `[[objects]]`: an array of tables, each checked against a default object.
fn check_objects(v: &mut Value, origin: &str) -> Result<(), SceneError> {
    let schema =
        toml::Table::try_from(super::ObjectDesc::default()).expect("an object always serialises");
    let Value::Array(items) = v else {
        return Err(SceneError::WrongType {
            origin: origin.into(),
            key: "objects".into(),
            expected: "an array of tables ([[objects]] sections)".into(),
            got: format!("{} {}", type_name(v), show(v)),
        });
    };
    for (i, item) in items.iter_mut().enumerate() {
        let path = format!("objects[{i}]");
        let Value::Table(t) = item else {
            return Err(SceneError::WrongType {
                origin: origin.into(),
                key: path,
                expected: "a table".into(),
                got: type_name(item).into(),
            });
        };
        for (k, v) in t.iter_mut() {
            let key = format!("{path}.{k}");
            let Some(expected) = schema.get(k) else {
                let mut keys = Vec::new();
                all_keys(&schema, "", &mut keys);
                let near = keys.iter().min_by_key(|c| levenshtein(k, c));
                let suggestion = match near {
                    Some(c) if levenshtein(k, c) <= 3 => format!("; did you mean `{path}.{c}`?"),
                    _ => format!(
                        " (object keys are {})",
                        schema.keys().cloned().collect::<Vec<_>>().join(", ")
                    ),
                };
                return Err(SceneError::UnknownKey { origin: origin.into(), key, suggestion });
            };
            check_value(v, expected, &key, origin, &schema)?;
        }
    }
    Ok(())
}

fn check_value(
    v: &mut Value,
    expected: &Value,
    path: &str,
    origin: &str,
    root: &Table,
) -> Result<(), SceneError> {
    let wrong = |v: &Value, what: String| SceneError::WrongType {
        origin: origin.into(),
        key: path.into(),
        expected: what,
        got: format!("{} {}", type_name(v), show(v)),
    };
    match (expected, &mut *v) {
        (Value::Table(s), Value::Table(u)) => check_against_schema(u, s, path, origin, root),
        (Value::Float(_), Value::Integer(i)) => {
            *v = Value::Float(*i as f64);
            Ok(())
        }
        (Value::Array(e), Value::Array(a)) => {
            if a.len() != e.len() {
                return Err(wrong(v, format!("an array of {} numbers", e.len())));
            }
            for item in a.iter_mut() {
                if let Value::Integer(i) = item {
                    *item = Value::Float(*i as f64);
                }
                if !matches!(item, Value::Float(_)) {
                    let shown = Value::Array(a.clone());
                    return Err(wrong(&shown, format!("an array of {} numbers", e.len())));
                }
            }
            Ok(())
        }
        (Value::Integer(_), Value::Integer(i)) if *i < 0 => {
            Err(wrong(v, "a whole number ≥ 0".into()))
        }
        (e, u) if std::mem::discriminant(e) == std::mem::discriminant(u) => Ok(()),
        (e, u) => Err(wrong(u, type_name(e).to_string())),
    }
}

/// Parse `section.key=value` (value is TOML; a bare word or path is a string).
pub fn parse_override(text: &str) -> Result<(Vec<String>, Value), SceneError> {
    let bad = |reason: &str| SceneError::BadOverride { text: text.into(), reason: reason.into() };
    let (key, raw) = text.split_once('=').ok_or_else(|| bad("expected section.key=value"))?;
    let path: Vec<String> = key.trim().split('.').map(str::to_string).collect();
    if path.iter().any(|p| p.is_empty()) {
        return Err(bad("the key must look like section.key"));
    }
    let raw = raw.trim();
    let value = match format!("v = {raw}").parse::<Table>() {
        Ok(mut t) => t.remove("v").ok_or_else(|| bad("no value"))?,
        // Bare words (names, file paths) are strings.
        Err(_)
            if !raw.is_empty()
                && raw
                    .chars()
                    .all(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | '.' | '/')) =>
        {
            Value::String(raw.to_string())
        }
        Err(_) => {
            return Err(bad(&format!(
                "`{raw}` is not a TOML value (quote strings, arrays look like [1, 2, 3])"
            )));
        }
    };
    Ok((path, value))
}

/// Set `path` to `value` in `table`, creating sections as needed.
pub fn apply_override(table: &mut Table, path: &[String], value: Value) {
    let (last, sections) = path.split_last().expect("override paths are never empty");
    let mut t = table;
    for s in sections {
        let entry = t.entry(s.clone()).or_insert_with(|| Value::Table(Table::new()));
        if !entry.is_table() {
            *entry = Value::Table(Table::new());
        }
        t = entry.as_table_mut().expect("just made a table");
    }
    t.insert(last.clone(), value);
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

impl Scene {
    /// Parse TOML text (named `origin` in errors) and apply `overrides`.
    pub fn from_toml(text: &str, origin: &str, overrides: &[String]) -> Result<Scene, SceneError> {
        let mut user: Table = text.parse().map_err(|e: toml::de::Error| {
            let (line, column) = e.span().map_or((1, 1), |s| line_col(text, s.start));
            SceneError::Syntax {
                origin: origin.into(),
                line,
                column,
                message: e.message().trim().to_string(),
            }
        })?;
        let schema = Scene::default().to_table();
        check_against_schema(&mut user, &schema, "", origin, &schema)?;
        // Coefficients given without a named medium mean a custom medium.
        if let Some(Value::Table(w)) = user.get_mut("water")
            && (w.contains_key("absorption") || w.contains_key("scattering"))
            && !w.contains_key("medium")
        {
            w.insert("medium".into(), Value::String("custom".into()));
        }
        for o in overrides {
            let (path, value) = parse_override(o)?;
            let mut one = Table::new();
            apply_override(&mut one, &path, value);
            check_against_schema(&mut one, &schema, "", "--set", &schema)?;
            let (path_again, value) = flatten_single(&one, &path);
            apply_override(&mut user, &path_again, value);
        }
        let scene: Scene =
            Value::Table(user.clone()).try_into().map_err(|e: toml::de::Error| {
                // After the checks above only enum names can fail: find the key.
                let msg = e.message().trim().to_string();
                let key = find_string_key(&user, "", &msg).unwrap_or_else(|| "scene".into());
                SceneError::WrongType {
                    origin: origin.into(),
                    key,
                    expected: "one of the listed names".into(),
                    got: msg,
                }
            })?;
        scene.validate()?;
        Ok(scene)
    }

    /// Load a built-in scene by name or a `.toml` file by path.
    pub fn load(spec: &str, overrides: &[String]) -> Result<Scene, SceneError> {
        if let Some(b) = BUILTIN_SCENES.iter().find(|b| b.name == spec) {
            return Scene::from_toml(b.toml, &format!("built-in scene `{spec}`"), overrides);
        }
        let looks_like_path = spec.ends_with(".toml") || spec.contains('/') || spec.contains('\\');
        if !looks_like_path {
            let list = BUILTIN_SCENES.iter().map(|b| b.name).collect::<Vec<_>>().join(", ");
            return Err(SceneError::UnknownScene { name: spec.into(), list });
        }
        let text = std::fs::read_to_string(Path::new(spec))
            .map_err(|e| SceneError::Io { path: spec.into(), reason: e.to_string() })?;
        let mut scene = Scene::from_toml(&text, spec, overrides)?;
        scene.base_dir = Path::new(spec).parent().map(Path::to_path_buf).unwrap_or_default();
        Ok(scene)
    }

    /// Range checks: each section's own (next to its defaults in
    /// scene/mod.rs), then those that span sections. Device-dependent limits
    /// (N against buffer sizes) are checked by the renderer, which knows the
    /// device.
    pub fn validate(&self) -> Result<(), SceneError> {
        self.camera.validate()?;
        self.sun.validate()?;
        self.sky.validate()?;
        self.ocean.validate()?;
        self.water.validate()?;
        self.sines.validate()?;
        self.render.validate()?;
        self.floor.validate()?;
        self.caustics.validate()?;
        self.air.validate()?;
        self.godrays.validate()?;
        if self.water.model == WaterModel::Sines && !(1..=64).contains(&self.sines.count) {
            return Err(SceneError::OutOfRange {
                key: "sines.count".into(),
                value: self.sines.count.to_string(),
                allowed: "must be 1 to 64".into(),
            });
        }
        if let Some(i) = self
            .objects
            .iter()
            .position(|o| o.material.ior > 0.0)
            .filter(|_| self.water.model != super::WaterModel::None)
        {
            return Err(SceneError::OutOfRange {
                key: format!("objects[{i}].material.ior"),
                value: self.objects[i].material.ior.to_string(),
                allowed:
                    "refractive objects need water.model = \"none\" (they are lit through air)"
                        .into(),
            });
        }
        if self.objects.len() > 1024 {
            return Err(SceneError::OutOfRange {
                key: "objects".into(),
                value: self.objects.len().to_string(),
                allowed: "at most 1024 objects".into(),
            });
        }
        for (i, o) in self.objects.iter().enumerate() {
            for (j, c) in o.scale.iter().enumerate() {
                range(&format!("objects[{i}].scale[{j}]"), *c, c.abs() > 1e-6, "must be non-zero")?;
            }
            for (j, c) in o.position.iter().chain(&o.rotation_deg).enumerate() {
                range(
                    &format!("objects[{i}].{}", if j < 3 { "position" } else { "rotation_deg" }),
                    *c,
                    true,
                    "must be finite",
                )?;
            }
            validate_material(&format!("objects[{i}].material"), &o.material)?;
        }
        Ok(())
    }
}

/// `v` is finite and `ok`, else an error naming `key` and what is allowed.
pub(super) fn range(key: &str, v: f32, ok: bool, allowed: &str) -> Result<(), SceneError> {
    if ok && v.is_finite() {
        Ok(())
    } else {
        Err(SceneError::OutOfRange {
            key: key.into(),
            value: v.to_string(),
            allowed: allowed.into(),
        })
    }
}

pub(super) fn validate_material(key: &str, m: &super::MaterialDesc) -> Result<(), SceneError> {
    for (name, v) in [("albedo", m.albedo), ("pattern_color", m.pattern_color)] {
        for (i, c) in v.iter().enumerate() {
            if !(0.0..=1.0).contains(c) {
                return Err(SceneError::OutOfRange {
                    key: format!("{key}.{name}[{i}]"),
                    value: c.to_string(),
                    allowed: "must be in [0, 1]".into(),
                });
            }
        }
    }
    if !(m.tile_size > 0.0 && m.tile_size.is_finite()) {
        return Err(SceneError::OutOfRange {
            key: format!("{key}.tile_size"),
            value: m.tile_size.to_string(),
            allowed: "must be > 0 m".into(),
        });
    }
    if !(m.ior == 0.0 || (1.0..=3.0).contains(&m.ior)) {
        return Err(SceneError::OutOfRange {
            key: format!("{key}.ior"),
            value: m.ior.to_string(),
            allowed: "must be 0 (opaque) or 1 to 3 (refractive)".into(),
        });
    }
    if !(m.uv_scale.is_finite() && m.uv_scale != 0.0) {
        return Err(SceneError::OutOfRange {
            key: format!("{key}.uv_scale"),
            value: m.uv_scale.to_string(),
            allowed: "must be finite and non-zero".into(),
        });
    }
    Ok(())
}

fn flatten_single(t: &Table, path: &[String]) -> (Vec<String>, Value) {
    let mut v = Value::Table(t.clone());
    for p in path {
        v = v.as_table().and_then(|t| t.get(p)).cloned().unwrap_or(Value::Table(Table::new()));
    }
    (path.to_vec(), v)
}

fn find_string_key(t: &Table, prefix: &str, message: &str) -> Option<String> {
    for (k, v) in t {
        let path = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
        match v {
            Value::String(s) if message.contains(&format!("`{s}`")) => return Some(path),
            Value::Table(inner) => {
                if let Some(p) = find_string_key(inner, &path, message) {
                    return Some(p);
                }
            }
            _ => {}
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtins_load_and_validate() {
        for b in BUILTIN_SCENES {
            let s = Scene::load(b.name, &[]).unwrap_or_else(|e| panic!("{}: {e}", b.name));
            assert!(!s.description.is_empty(), "{} has no description", b.name);
        }
    }

    #[test]
    fn overrides_take_toml_values_and_bare_words() {
        let s = Scene::load(
            "ocean",
            &[
                "ocean.wind_speed=14".into(),
                "ocean.spectrum=phillips".into(),
                "camera.position=[1, 20, 3]".into(),
            ],
        )
        .unwrap();
        assert_eq!(s.ocean.wind_speed, 14.0);
        assert_eq!(s.ocean.spectrum, super::super::Spectrum::Phillips);
        assert_eq!(s.camera.position, [1.0, 20.0, 3.0]);
    }

    #[test]
    fn errors_are_one_clear_line() {
        let cases: &[(&str, &[&str], &str)] = &[
            ("nowhere", &[], "unknown scene `nowhere`: built-in scenes are ocean"),
            ("ocean", &["ocean.wind_sped=3"], "did you mean `ocean.wind_speed`?"),
            ("ocean", &["ocean.wind_speed=-3"], "`ocean.wind_speed` = -3 is out of range"),
            ("ocean", &["ocean.resolution=300"], "power of two from 64 to 1024"),
            (
                "ocean",
                &["ocean.wind_speed=fast"],
                "`ocean.wind_speed` must be a number, got a string \"fast\"",
            ),
            ("ocean", &["ocean.spectrum=foo"], "ocean.spectrum"),
            ("ocean", &["camera.fov_y_deg=180"], "must be in (0, 180)"),
            ("ocean", &["camera.position=[1, 2]"], "an array of 3 numbers"),
            ("ocean", &["nonsense"], "expected section.key=value"),
            ("ocean", &["ocean.seed=-1"], "a whole number ≥ 0"),
        ];
        for (scene, sets, want) in cases {
            let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
            let e = Scene::load(scene, &sets).unwrap_err().to_string();
            assert!(e.contains(want), "{scene} {sets:?}: `{e}` lacks `{want}`");
            assert!(!e.contains('\n'), "multi-line error: {e}");
        }
    }

    #[test]
    fn objects_are_checked_and_media_resolve() {
        let text = "[[objects]]\nprimitive = \"sphere\"\nposition = [0, 1, 2]\n[objects.material]\nalbedo = [0.9, 0.1, 0.1]\n";
        let s = Scene::from_toml(text, "x.toml", &[]).unwrap();
        assert_eq!(s.objects.len(), 1);
        assert_eq!(s.objects[0].primitive, super::super::Primitive::Sphere);
        assert_eq!(s.objects[0].material.albedo, [0.9, 0.1, 0.1]);
        let e = Scene::from_toml("[[objects]]\npositon = [0, 1, 2]\n", "x.toml", &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`objects[0].positon`") && e.contains("did you mean `objects[0].position`"),
            "{e}"
        );
        let e = Scene::from_toml("[[objects]]\nscale = [1, 0, 1]\n", "x.toml", &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("objects[0].scale[1]"), "{e}");
        let e = Scene::from_toml("[water]\nmedium = \"swamp\"\n", "x.toml", &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("water.medium") && e.contains("clear_ocean") && e.contains("turbid_harbor"),
            "{e}"
        );
        // Coefficients alone make a custom medium.
        let s =
            Scene::from_toml("[water]\nabsorption = [0.5, 0.1, 0.05]\n", "x.toml", &[]).unwrap();
        assert_eq!(s.water.medium, super::super::MediumName::Custom);
        assert_eq!(s.medium().absorption, glam::Vec3::new(0.5, 0.1, 0.05));
        let s = Scene::from_toml("[water]\nmedium = \"pure\"\n", "x.toml", &[]).unwrap();
        assert_eq!(s.medium().absorption, glam::Vec3::from(crate::medium::PURE_WATER_ABSORPTION));
    }

    #[test]
    fn syntax_errors_name_line_and_column() {
        let e =
            Scene::from_toml("[ocean]\nwind_speed = = 3\n", "x.toml", &[]).unwrap_err().to_string();
        assert!(e.starts_with("x.toml:2:"), "{e}");
        assert!(!e.contains('\n'));
    }

    #[test]
    fn a_file_with_one_section_gets_defaults_for_the_rest() {
        let s = Scene::from_toml("[sun]\nelevation_deg = 10\n", "x.toml", &[]).unwrap();
        assert_eq!(s.sun.elevation_deg, 10.0);
        assert_eq!(s.ocean, super::super::OceanDesc::default());
    }
}
