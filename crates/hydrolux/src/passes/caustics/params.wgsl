// The caustic maps' parameters, read by the photon splatting (caustics.wgsl)
// and the beam projection (beam.wgsl). Layout twin: CausticUniforms (mod.rs).

struct CausticParams {
    // Photons per side, map cells per side (M), beam grid cells per side,
    // layers (layer k lies at depth (k + 1)/layers × the floor depth).
    photons: u32,
    cells: u32,
    beam_cells: u32,
    layers: u32,
    // Patch size (m), floor depth (m), fixed-point scale.
    patch_size: vec2<f32>,
    floor_depth: f32,
    fixed_point_scale: f32,
}
