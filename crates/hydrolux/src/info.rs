//! What the offline checks know of a technique (or of shared code that
//! builds shaders): its name, shaders and uniform layouts. A leaf, so that
//! shared vocabulary (mip chains, the medium copy) can declare its own.

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
}
