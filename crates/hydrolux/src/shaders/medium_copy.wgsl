// The main view's stencil (each pixel's medium) copied into a colour
// texture, for backends that cannot sample it next to the depth (wgpu's
// GL, see targets.rs, MediumCopy). No texture is read: the pipeline's
// stencil test passes only the water pixels, and they write STENCIL_WATER.
#import fullscreen, modes

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_ndc(i), 0.0, 1.0);
}

@fragment
fn fs_main() -> @location(0) vec4<u32> {
    return vec4<u32>(STENCIL_WATER, 0u, 0u, 0u);
}
