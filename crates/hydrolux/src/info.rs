//! What is known of a technique or a simulation (or of shared code that
//! builds shaders) without a device: its name, shaders and uniform layouts
//! (for the offline checks), and the dumps it offers (for `hydrolux render
//! --dump` and its help, collected by `registry::dump_kinds`). A leaf, so
//! that shared vocabulary (mip chains, the medium copy) can declare its own.

use hydrolux_core::scene::Scene;

/// One technique's offline description (read by the offline checks, the
/// registry's tests, and by `hydrolux info` for the names).
pub(crate) struct TechniqueInfo {
    pub name: &'static str,
    /// (label, composed WGSL) of every shader it builds.
    #[cfg_attr(not(test), allow(dead_code))]
    pub shaders: fn() -> Vec<(String, String)>,
    /// Its uniform structs and the shader each is checked against.
    #[cfg_attr(not(test), allow(dead_code))]
    pub uniforms: fn() -> Vec<crate::uniforms::Layout>,
    /// The internal buffers it can dump (its `dump` hook reads them).
    pub dumps: &'static [DumpKind],
}

/// What a dump holds, for the file formats that can hold it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DumpShape {
    /// Rows × columns of cells with channels (`.npy` or `.exr`).
    Grid,
    /// A list of records, one per row, that may be empty (`.npy` only).
    List,
    /// A document (`.json`).
    Json,
}

/// One dump an owner offers.
#[derive(Debug)]
pub struct DumpKind {
    /// As `--dump NAME=FILE` spells it.
    pub name: &'static str,
    pub shape: DumpShape,
    /// Why a scene has nothing to dump (`None`: it has), known before any
    /// frame: the line a user reads.
    pub missing: fn(&Scene) -> Option<&'static str>,
}

/// A dump read back: floats (rows × columns × channels, row-major) with a
/// line saying what they are, or a document.
#[derive(Clone, Debug, PartialEq)]
pub enum DumpData {
    Floats { columns: usize, rows: usize, channels: usize, data: Vec<f32>, note: Option<String> },
    Json(String),
}
