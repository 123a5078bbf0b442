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
    // Reflection texture: widened camera × mirror about y = 0.
    refl_view_proj: mat4x4<f32>,
    // Refraction texture: widened camera, and its inverse.
    refr_view_proj: mat4x4<f32>,
    inv_refr_view_proj: mat4x4<f32>,
    // Sun's orthographic shadow map (world → clip, applied after shadow_space()).
    shadow_view_proj: mat4x4<f32>,
    // rgb absorption σa (m⁻¹); w Henyey–Greenstein g.
    absorption: vec4<f32>,
    // rgb scattering σs (m⁻¹); w exponent q of the power Fresnel mode.
    scattering: vec4<f32>,
    // x reflection plane height, y refraction plane depth, z clamp of dv (m),
    // w attenuation k of the simple water colour (m⁻¹).
    water_params: vec4<f32>,
    // x reflection texture texels per radian (for the roughness blur).
    reflection_params: vec4<f32>,
    // xyz direction refracted sunlight travels under a flat surface; w its cos to the vertical.
    sun_travel: vec4<f32>,
    // rgb sun irradiance just under the surface facing the refracted beam, pre-exposed.
    sun_underwater: vec4<f32>,
    // rgb sky irradiance just under the surface (horizontal), pre-exposed;
    // w 1 when the scene has geometry (0: the refraction texture is empty).
    sky_underwater: vec4<f32>,
    // x optics (0 physical, 1 simple), y refraction lookup (0 depth, 1 plane),
    // z shadow map in use (0/1), w shadow map size (texels).
    modes2: vec4<u32>,
    // Floor caustics: xy patch (m; x = 0 when off), z the floor depth the map
    // is for, w 1 / (the flat-water value of the map).
    caustic_params: vec4<f32>,
    // x distance from the eye (m) within which god rays replace the uniform
    // sun in-scattering (0: no god rays this frame); y 1 when the scene has a
    // water body; z 1 when the god-ray pass marches the sun's light in the
    // fog (shadowed) this frame; w how far (m) along refracted paths seen from
    // above the water shaders march god rays (0: not this frame).
    volume: vec4<f32>,
    // Fog in the air: x scattering σ (m⁻¹), y Henyey–Greenstein g, z how far
    // from the eye it reaches (m), w the fraction of the sky lighting it.
    fog: vec4<f32>,
    // Refractive objects' light view (world → clip, orthographic along the sun).
    object_light_view_proj: mat4x4<f32>,
    // x 1 when refractive objects bend the sunlight (their caustic map is
    // in use); y the depth tolerance of a receiver in that view.
    object_params: vec4<f32>,
}

fn has_water() -> bool {
    return frame.volume.y > 0.5;
}

const VIEW_FINAL: u32 = 0u;
const VIEW_REFLECTION: u32 = 1u;
const VIEW_REFRACTION: u32 = 2u;
const VIEW_DEPTH: u32 = 3u;
const VIEW_NORMALS: u32 = 4u;
const VIEW_SHADOW: u32 = 5u;
const VIEW_MEDIUM: u32 = 6u;
const VIEW_CAUSTICS: u32 = 7u;

@group(0) @binding(0) var<uniform> frame: Frame;

fn exposure() -> f32 {
    return frame.sky_ambient.w;
}
