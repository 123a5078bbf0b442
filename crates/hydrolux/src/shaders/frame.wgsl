// Per-frame constants shared by every render pass (group 0).
// Layout twin: `FrameUniforms` in src/uniforms.rs (size checked against naga).


struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    // xyz camera position; w simulation time (s, reduced mod the repeat period).
    camera_pos: vec4<f32>,
    // xyz unit direction towards the sun; w cos of its angular radius.
    sun_dir: vec4<f32>,
    // rgb sun illuminance on a plane facing it, pre-exposed; w 1/solid angle of the disk.
    sun_illuminance: vec4<f32>,
    // rgb sky irradiance on a horizontal plane, pre-exposed; w exposure scale.
    sky_ambient: vec4<f32>,
    // rgb diffuse reflectance of the water body; w index of refraction.
    water_body: vec4<f32>,
    // x Fresnel mode (0 exact, 1 Schlick); y surface model (0 fft, 1 sines, 2 flat);
    // z tone map (0 ACES, 1 clamp); w debug view.
    modes: vec4<u32>,
    // width, height, 1/width, 1/height.
    viewport: vec4<f32>,
    // x, y unresolved (sub-texel) slope variance along x and z; z mesh spacing of
    // the finest ring (m); w number of rings.
    surface_detail: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;

fn exposure() -> f32 {
    return frame.sky_ambient.w;
}
