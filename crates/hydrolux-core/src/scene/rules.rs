//! The scene's error type and the range rules every section's `validate()`
//! uses: one line naming the bad value and what is allowed.

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
    #[error("{setting} has no effect {reason}")]
    NoEffect { setting: String, reason: String },
}

/// Objects a scene may have.
pub const MAX_OBJECTS: usize = 1024;

/// Positions in a scene (camera, objects) lie within this many metres of
/// the origin on each axis: beyond, single-precision rendering loses the
/// centimetres a water surface needs.
pub const WORLD_EXTENT_M: f32 = 100_000.0;

/// Every component of `v` finite and within ±`max`, else an error naming
/// `key` and what is allowed.
pub(super) fn vec3_range(
    key: &str,
    v: [f32; 3],
    max: f32,
    allowed: &str,
) -> Result<(), SceneError> {
    if v.iter().all(|c| c.is_finite() && c.abs() <= max) {
        Ok(())
    } else {
        Err(SceneError::OutOfRange {
            key: key.into(),
            value: format!("{v:?}"),
            allowed: allowed.into(),
        })
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
