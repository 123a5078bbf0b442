//! Loading scenes: TOML text → table → `--set` overrides → key and type checks
//! against the schema (the default scene) → typed [`Scene`] → range checks.
//! Every failure is one line naming the bad value and what is allowed.

use super::material::validate_material;
use super::rules::{range, vec3_range};
use super::{
    BUILTIN_SCENES, MAX_LIQUID_BODIES, MAX_OBJECTS, Scene, SceneError, WORLD_EXTENT_M, WaterModel,
};
use std::path::Path;
use toml::{Table, Value};

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

/// A value for a message: at most 40 characters (cut at a character, not
/// inside one: found by fuzzing).
fn show(v: &Value) -> String {
    let s = v.to_string();
    if s.chars().count() > 40 {
        format!("{}…", s.chars().take(40).collect::<String>())
    } else {
        s
    }
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
        if let Some(schema) = array_schema(&path) {
            check_array_of_tables(v, origin, &path, &schema)?;
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

/// Keys whose value is a list of names of any length (every other array
/// is a fixed number of numbers, as its default has).
const STRING_LISTS: [&str; 1] = ["fluid.open"];

/// The schema of one entry of a top-level array of tables, by its name.
fn array_schema(name: &str) -> Option<Table> {
    let table = |t: Result<Table, _>| t.expect("a default entry serialises");
    match name {
        "objects" => {
            // `path` is optional (absent from the default): its own table.
            let mut t = table(Table::try_from(super::ObjectDesc::default()));
            let path = table(Table::try_from(crate::path::PathDesc::default()));
            t.insert("path".into(), Value::Table(path));
            Some(t)
        }
        "drops" => Some(table(Table::try_from(super::DropDesc::default()))),
        "emitters" => Some(table(Table::try_from(super::EmitterDesc::default()))),
        "fluid.sources" => Some(table(Table::try_from(super::FluidSource::default()))),
        _ => None,
    }
}

/// `[[objects]]`, `[[drops]]`, `[[emitters]]`, `[[fluid.sources]]`: an array of tables, each
/// checked against a default entry (`schema`).
fn check_array_of_tables(
    v: &mut Value,
    origin: &str,
    name: &str,
    schema: &Table,
) -> Result<(), SceneError> {
    let Value::Array(items) = v else {
        return Err(SceneError::WrongType {
            origin: origin.into(),
            key: name.into(),
            expected: format!("an array of tables ([[{name}]] sections)"),
            got: format!("{} {}", type_name(v), show(v)),
        });
    };
    let what = name.trim_end_matches('s');
    for (i, item) in items.iter_mut().enumerate() {
        let path = format!("{name}[{i}]");
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
                all_keys(schema, "", &mut keys);
                let near = keys.iter().min_by_key(|c| levenshtein(k, c));
                let suggestion = match near {
                    Some(c) if levenshtein(k, c) <= 3 => format!("; did you mean `{path}.{c}`?"),
                    _ => format!(
                        " ({what} keys are {})",
                        schema.keys().cloned().collect::<Vec<_>>().join(", ")
                    ),
                };
                return Err(SceneError::UnknownKey { origin: origin.into(), key, suggestion });
            };
            check_value(v, expected, &key, origin, schema)?;
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
        (Value::Array(_), Value::Array(a)) if STRING_LISTS.contains(&path) => {
            if a.iter().all(|item| matches!(item, Value::String(_))) {
                Ok(())
            } else {
                Err(wrong(v, "an array of strings".into()))
            }
        }
        // An empty default: a list of any length, of numbers or of
        // [x, y, z] points (`objects.path.times`, `.points`).
        (Value::Array(e), Value::Array(a)) if e.is_empty() => {
            let number = |item: &mut Value| {
                if let Value::Integer(i) = item {
                    *item = Value::Float(*i as f64);
                }
                matches!(item, Value::Float(_))
            };
            let ok = a.iter_mut().all(|item| match item {
                Value::Array(p) => p.len() == 3 && p.iter_mut().all(number),
                other => number(other),
            });
            if ok {
                Ok(())
            } else {
                Err(wrong(v, "a list of numbers or of [x, y, z] points".into()))
            }
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

/// Coefficients given together with a named medium.
fn contradiction(origin: &str, coefficient: &str, medium: &Value) -> SceneError {
    SceneError::WrongType {
        origin: origin.into(),
        key: format!("water.{coefficient}"),
        expected: "given only with water.medium = \"custom\" (or without water.medium, which then means custom)".into(),
        got: format!("water.medium = {medium}"),
    }
}

/// Whether `raw` is written as a number (sign, digits, point, exponent).
fn looks_numeric(raw: &str) -> bool {
    let body = raw.trim_start_matches(['+', '-']);
    body.starts_with(|c: char| c.is_ascii_digit())
        && body
            .chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-' | '_'))
}

/// At most 40 characters of `s`, for messages.
fn shorten(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        format!("{}… ({} characters)", s.chars().take(40).collect::<String>(), s.chars().count())
    }
}

/// Parse `section.key=value` (value is TOML; a bare word or path is a string).
pub fn parse_override(text: &str) -> Result<(Vec<String>, Value), SceneError> {
    let bad = |reason: &str| SceneError::BadOverride { text: shorten(text), reason: reason.into() };
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
                && !looks_numeric(raw)
                && raw
                    .chars()
                    .all(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | '.' | '/')) =>
        {
            Value::String(raw.to_string())
        }
        // Digits that TOML cannot hold: not a string, a number out of range.
        Err(_) if looks_numeric(raw) => {
            return Err(bad(&format!(
                "`{}` is a number TOML cannot hold: integers are at most 9223372036854775807, floats at most about 1.8e308",
                shorten(raw)
            )));
        }
        Err(_) => {
            return Err(bad(&format!(
                "`{}` is not a TOML value (quote strings, arrays look like [1, 2, 3])",
                shorten(raw)
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

/// The dotted key assigned on `line` (1-based) of a TOML text: the last
/// `[section]` above it and the name before `=`.
fn key_at_line(text: &str, line: usize) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let here = lines.get(line.checked_sub(1)?)?;
    let name = here.split_once('=')?.0.trim();
    let section = lines[..line - 1].iter().rev().find_map(|l| {
        let l = l.trim();
        (l.starts_with('[') && !l.starts_with("[["))
            .then(|| l.trim_matches(|c| c == '[' || c == ']').to_string())
    });
    Some(match section {
        Some(s) => format!("{s}.{name}"),
        None => name.to_string(),
    })
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
        let scene = Scene::from_toml_live(text, origin, overrides)?;
        scene.check_effective()?;
        Ok(scene)
    }

    /// [`Scene::from_toml`] without refusing settings that have no effect
    /// (the viewer's editor, where a switch is flipped live: it warns with
    /// [`Scene::check_effective`] instead).
    pub fn from_toml_live(
        text: &str,
        origin: &str,
        overrides: &[String],
    ) -> Result<Scene, SceneError> {
        // Stop at the object limit before parsing them all.
        let headers =
            text.lines().enumerate().filter(|(_, l)| l.trim_start().starts_with("[[objects]]"));
        if let Some((line, _)) = headers.clone().nth(MAX_OBJECTS) {
            return Err(SceneError::OutOfRange {
                key: "objects".into(),
                value: format!(
                    "{}+ (line {} starts object {})",
                    MAX_OBJECTS + 1,
                    line + 1,
                    MAX_OBJECTS + 1
                ),
                allowed: format!("at most {MAX_OBJECTS} objects"),
            });
        }
        let mut user: Table = text.parse().map_err(|e: toml::de::Error| {
            let (line, column) = e.span().map_or((1, 1), |s| line_col(text, s.start));
            let mut message = e.message().trim().to_string();
            if message.contains("too large") || message.contains("overflow") {
                let key = key_at_line(text, line).map(|k| format!("`{k}`: ")).unwrap_or_default();
                message = format!(
                    "{key}{message} (TOML integers are at most 9223372036854775807, floats at most about 1.8e308)"
                );
            }
            SceneError::Syntax { origin: origin.into(), line, column, message }
        })?;
        let schema = Scene::default().to_table();
        check_against_schema(&mut user, &schema, "", origin, &schema)?;
        // Coefficients mean a custom medium, in the file and in --set alike:
        // given without `medium` they make it "custom" (a --set overriding the
        // file's named medium); given with a named medium they contradict it.
        let coefficients = |keys: &mut dyn Iterator<Item = &str>| {
            keys.filter(|k| *k == "absorption" || *k == "scattering").map(str::to_string).next()
        };
        if let Some(Value::Table(w)) = user.get_mut("water")
            && let Some(coefficient) = coefficients(&mut w.keys().map(String::as_str))
        {
            match w.get("medium") {
                None => {
                    w.insert("medium".into(), Value::String("custom".into()));
                }
                Some(Value::String(m)) if m == "custom" => {}
                Some(m) => return Err(contradiction(origin, &coefficient, m)),
            }
        }
        let (mut set_coefficient, mut set_medium) = (None, None);
        let mut set_keys = Vec::new();
        for o in overrides {
            let (path, value) = parse_override(o)?;
            set_keys.push(path.join("."));
            if path.len() == 2 && path[0] == "water" {
                match path[1].as_str() {
                    "absorption" | "scattering" => set_coefficient = Some(path[1].clone()),
                    "medium" => set_medium = Some(value.clone()),
                    _ => {}
                }
            }
            let mut one = Table::new();
            apply_override(&mut one, &path, value);
            check_against_schema(&mut one, &schema, "", "--set", &schema)?;
            let (path_again, value) = flatten_single(&one, &path);
            apply_override(&mut user, &path_again, value);
        }
        if let Some(coefficient) = set_coefficient {
            match set_medium {
                Some(Value::String(m)) if m == "custom" => {}
                Some(m) => return Err(contradiction("--set", &coefficient, &m)),
                None => {
                    let path = ["water".to_string(), "medium".to_string()];
                    apply_override(&mut user, &path, Value::String("custom".into()));
                }
            }
        }
        // `mesh = ""` would read as "no mesh": say so instead.
        if let Some(Value::Array(objects)) = user.get("objects") {
            for (i, o) in objects.iter().enumerate() {
                if let Some(Value::String(m)) = o.get("mesh")
                    && m.trim().is_empty()
                {
                    return Err(SceneError::OutOfRange {
                        key: format!("objects[{i}].mesh"),
                        value: format!("{m:?}"),
                        allowed: "must name a file (.obj, .gltf, .glb) or builtin:bunny; leave the key out to use `primitive`".into(),
                    });
                }
            }
        }
        let scene: Scene =
            Value::Table(user.clone()).try_into().map_err(|e: toml::de::Error| {
                // After the checks above only enum names and integer ranges
                // can fail: find the key the message quotes.
                let msg = e.message().trim().to_string();
                let value = Value::Table(user.clone());
                let key = find_quoted_key(&value, "", &msg).unwrap_or_else(|| "scene".into());
                let got = msg.split(", expected").next().unwrap_or(&msg);
                let got = got.trim_start_matches("invalid value: ");
                let got = match got.split_once('`') {
                    Some((kind, rest)) => {
                        let quoted = rest.trim_end_matches('`');
                        if kind.contains("variant") {
                            format!("{quoted:?}")
                        } else {
                            quoted.to_string()
                        }
                    }
                    None => got.to_string(),
                };
                // A key --set gave is --set's error, not the scene's.
                let from_set =
                    set_keys.iter().any(|k| key == *k || key.starts_with(&format!("{k}.")));
                // An integer beyond its type: the key's own rule, where it
                // has one, says what is allowed (not the type's range).
                if msg.contains("integer")
                    && let Some(allowed) = rule_of(&user, &key)
                {
                    return if from_set {
                        SceneError::BadOverride {
                            text: format!("{key}={got}"),
                            reason: format!("out of range: {allowed}"),
                        }
                    } else {
                        SceneError::OutOfRange { key, value: got, allowed }
                    };
                }
                SceneError::WrongType {
                    origin: if from_set { "--set".into() } else { origin.into() },
                    key,
                    expected: expected_from(&msg),
                    got,
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
        let text = crate::files::read_text_bounded(Path::new(spec), crate::files::limits::SCENE)
            .map_err(|reason| SceneError::Io { path: spec.into(), reason })?;
        let mut scene = Scene::from_toml(&text, spec, overrides)?;
        scene.base_dir = Path::new(spec).parent().map(Path::to_path_buf).unwrap_or_default();
        Ok(scene)
    }

    /// Range checks: each section's own (next to its defaults in
    /// scene/mod.rs), then those that span sections. Device-dependent limits
    /// (N against buffer sizes) are checked by the renderer, which knows the
    /// device.
    pub fn validate(&self) -> Result<(), SceneError> {
        if !(self.start_time.is_finite()
            && (0.0..=super::MAX_START_TIME_S).contains(&self.start_time))
        {
            return Err(SceneError::OutOfRange {
                key: "start_time".into(),
                value: self.start_time.to_string(),
                allowed: format!("must be 0 to {} s", super::MAX_START_TIME_S),
            });
        }
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
        self.validate_ripples()?;
        self.whitewater.validate()?;
        self.fluid.validate()?;
        if self.water.model == WaterModel::Sines && !(1..=64).contains(&self.sines.count) {
            return Err(SceneError::OutOfRange {
                key: "sines.count".into(),
                value: self.sines.count.to_string(),
                allowed: "must be 1 to 64".into(),
            });
        }
        // A view of what the scene does not have would draw something else.
        use super::{Choice, DebugView};
        let missing = match self.render.view {
            DebugView::Error if self.water.model == WaterModel::None && !self.fluid.enabled() => {
                Some(
                    "it compares the water's methods or the liquid's surfaces, and the scene has neither (water.model = \"none\", no [[fluid.sources]])",
                )
            }
            DebugView::Fresnel if self.water.model == WaterModel::None => {
                Some("it is a view of the water, and the scene has none (water.model = \"none\")")
            }
            DebugView::Ripples if !self.has_interactive_water() => Some(
                "it shows the interactive water, and the scene has none (it needs water.dynamic = true, with water)",
            ),
            DebugView::Foam if !(self.has_whitewater() && self.whitewater.foam) => Some(
                "it shows the foam, and the scene has none (it needs whitewater.foam = true and water that moves)",
            ),
            DebugView::Fluid if !self.fluid.enabled() => Some(
                "it shows the volumetric liquid, and the scene has none (it needs [[fluid.sources]])",
            ),
            _ => None,
        };
        if let Some(why) = missing {
            return Err(SceneError::OutOfRange {
                key: "render.view".into(),
                value: format!("\"{}\"", self.render.view.name()),
                allowed: format!("{why}; choose another view"),
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
        if self.objects.len() > MAX_OBJECTS {
            return Err(SceneError::OutOfRange {
                key: "objects".into(),
                value: self.objects.len().to_string(),
                allowed: format!("at most {MAX_OBJECTS} objects"),
            });
        }
        for (i, o) in self.objects.iter().enumerate() {
            let within = format!("must be finite, each coordinate within ±{WORLD_EXTENT_M} m");
            vec3_range(&format!("objects[{i}].position"), o.position, WORLD_EXTENT_M, &within)?;
            let scale_ok = o.scale.iter().all(|c| (1e-6..=WORLD_EXTENT_M).contains(&c.abs()));
            if !scale_ok {
                return Err(SceneError::OutOfRange {
                    key: format!("objects[{i}].scale"),
                    value: format!("{:?}", o.scale),
                    allowed: format!(
                        "each factor must be finite and non-zero, its size from 1e-6 to {WORLD_EXTENT_M}"
                    ),
                });
            }
            vec3_range(
                &format!("objects[{i}].rotation_deg"),
                o.rotation_deg,
                1e6,
                "must be angles within ±1000000 degrees",
            )?;
            validate_material(&format!("objects[{i}].material"), &o.material)?;
            range(
                &format!("objects[{i}].density"),
                o.density,
                (1.0..=100_000.0).contains(&o.density),
                "must be 1 to 100000 kg/m³ (water: 1000)",
            )?;
            vec3_range(
                &format!("objects[{i}].velocity"),
                o.velocity,
                1000.0,
                "must be finite, each component within ±1000 m/s",
            )?;
            if let Some(path) = &o.path {
                let key = format!("objects[{i}].path");
                if o.dynamic || o.velocity.iter().any(|&v| v != 0.0) {
                    return Err(SceneError::OutOfRange {
                        key,
                        value: "a path with dynamic or a velocity".into(),
                        allowed:
                            "a path moves a kinematic object: leave dynamic false and velocity zero"
                                .into(),
                    });
                }
                if let Err((value, allowed)) = path.build() {
                    return Err(SceneError::OutOfRange { key, value, allowed });
                }
            }
            let moving = o.moving();
            if moving && crate::coupling::Shape::of(o).is_none() {
                return Err(SceneError::OutOfRange {
                    key: format!("objects[{i}].dynamic"),
                    value: if o.dynamic { "true".into() } else { format!("velocity {:?}", o.velocity) },
                    allowed: "moving objects are sphere (equal scale), box or cylinder (equal x and z scale) primitives".into(),
                });
            }
        }
        let in_liquid = self.objects.iter().filter(|o| self.in_liquid(o)).count();
        if in_liquid > MAX_LIQUID_BODIES {
            return Err(SceneError::OutOfRange {
                key: "objects".into(),
                value: format!("{in_liquid} moving objects in fluid.min..fluid.max"),
                allowed: format!(
                    "at most {MAX_LIQUID_BODIES} moving objects start in the liquid's domain"
                ),
            });
        }
        Ok(())
    }
}

impl Scene {
    /// Settings that would have no effect in the scene as given are refused
    /// in one line naming both keys: the interactive water's sections
    /// without `water.dynamic`, and `water.dynamic` without water.
    pub fn check_effective(&self) -> Result<(), SceneError> {
        if !self.water.dynamic {
            let given = [
                ("[ripples]", self.ripples != super::RipplesDesc::default()),
                ("[[drops]]", !self.drops.is_empty()),
                ("[[emitters]]", !self.emitters.is_empty()),
            ];
            if let Some((section, _)) = given.iter().find(|(_, g)| *g) {
                return Err(SceneError::NoEffect {
                    setting: format!("`{section}`"),
                    reason: format!(
                        "without `water.dynamic = true` (the interactive water it sets up): set water.dynamic = true, or leave {section} out"
                    ),
                });
            }
        } else if self.water.model == WaterModel::None {
            return Err(SceneError::NoEffect {
                setting: "`water.dynamic = true`".into(),
                reason: "with `water.model = \"none\"` (there is no water to move): choose a water.model, or leave water.dynamic out".into(),
            });
        }
        Ok(())
    }
}

/// What the range check of `key` (a dotted path of plain tables) allows,
/// found by giving the key 0 and validating: `None` where 0 passes or
/// another key fails.
fn rule_of(user: &Table, key: &str) -> Option<String> {
    let path: Vec<String> = key.split('.').map(str::to_string).collect();
    if path.iter().any(|p| p.contains('[')) {
        return None;
    }
    let mut probe = user.clone();
    apply_override(&mut probe, &path, Value::Integer(0));
    let scene: Scene = Value::Table(probe).try_into().ok()?;
    match scene.validate() {
        Err(SceneError::OutOfRange { key: k, allowed, .. }) if k == key => Some(allowed),
        _ => None,
    }
}

fn flatten_single(t: &Table, path: &[String]) -> (Vec<String>, Value) {
    let mut v = Value::Table(t.clone());
    for p in path {
        v = v.as_table().and_then(|t| t.get(p)).cloned().unwrap_or(Value::Table(Table::new()));
    }
    (path.to_vec(), v)
}

/// The key whose string or integer value a deserializer message quotes
/// (`` unknown variant `torus` ``, `` integer `4294967296` ``), searching
/// sections and arrays of tables (`objects[2].primitive`).
fn find_quoted_key(v: &Value, path: &str, message: &str) -> Option<String> {
    match v {
        Value::String(s) if message.contains(&format!("`{s}`")) => Some(path.to_string()),
        Value::Integer(n) if message.contains(&format!("integer `{n}`")) => Some(path.to_string()),
        Value::Table(t) => t.iter().find_map(|(k, v)| {
            let p = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
            find_quoted_key(v, &p, message)
        }),
        Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, v)| find_quoted_key(v, &format!("{path}[{i}]"), message)),
        _ => None,
    }
}

/// What a deserializer message says was expected, in the scene's words.
fn expected_from(message: &str) -> String {
    let expected = message.rsplit("expected ").next().unwrap_or(message).trim();
    match expected {
        "u32" => "a whole number from 0 to 4294967295".into(),
        "u64" => "a whole number from 0 to 9223372036854775807".into(),
        "i32" => "a whole number from -2147483648 to 2147483647".into(),
        e if e.starts_with("one of") || e.starts_with('`') => e.to_string(),
        _ => "one of the listed names".into(),
    }
}

#[cfg(test)]
#[path = "load_tests.rs"]
mod tests;
