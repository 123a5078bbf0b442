// Per-frame constants shared by every render pass (group 0), one named
// struct per concern. Layout twins: the `Frame*` structs in src/uniforms.rs
// and the technique folders; a test checks every field's offset by name
// against naga's layout of these structs. The modes' numbers (`VIEW_*`,
// `FRESNEL_*`…) are generated from the scene's enums (src/modes.rs).

#import modes

// The camera.
struct FrameView {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    position: vec3<f32>,
    // Simulation time (s), reduced modulo the ocean's repeat period.
    time: f32,
    // Viewport in pixels, and its reciprocal.
    size: vec2<f32>,
    inv_size: vec2<f32>,
}

// Sun and sky, pre-exposed.
struct FrameLight {
    // Unit direction towards the sun, and the cos of its angular radius.
    sun_dir: vec3<f32>,
    cos_sun_radius: f32,
    // Sun illuminance on a plane facing it, and 1 / the disk's solid angle.
    sun_illuminance: vec3<f32>,
    inv_sun_solid_angle: f32,
    // Sky irradiance on a horizontal plane, and the exposure scale.
    sky_ambient: vec3<f32>,
    exposure: f32,
    // Direction refracted sunlight travels under a flat surface, and its cos
    // to the vertical.
    sun_travel: vec3<f32>,
    sun_travel_cos: f32,
    // Sun irradiance just under the surface facing the refracted beam, and
    // the floor's depth (m; 0: none).
    sun_underwater: vec3<f32>,
    floor_depth: f32,
    // Sky irradiance just under the surface (horizontal), and the floor's
    // mean albedo.
    sky_underwater: vec3<f32>,
    floor_albedo: f32,
    // The sky's and the grey world's irradiance on any normal in the air:
    // nine spherical-harmonic coefficients (rgb; lighting.wgsl
    // `sky_irradiance`; twin: hydrolux-core irradiance).
    sky_light: array<vec4<f32>, 9>,
}

// The water body and how its surface is shaded.
struct FrameWater {
    // Diffuse reflectance of the water body (simple optics).
    body_color: vec3<f32>,
    ior: f32,
    // Absorption σa (m⁻¹) and the Henyey–Greenstein g of the medium.
    absorption: vec3<f32>,
    phase_g: f32,
    // Scattering σs (m⁻¹), and the exponent of the power Fresnel mode.
    scattering: vec3<f32>,
    fresnel_power: f32,
    // Height of the plane reflections are looked up at (m).
    reflection_height: f32,
    // Depth of the plane refractions are looked up at (plane mode, m).
    refraction_depth: f32,
    // Clamp of the refraction offset (m).
    refraction_max: f32,
    // Attenuation k of the simple water colour (m⁻¹).
    simple_attenuation: f32,
    // 1 when the scene has a water body (`water.model` is not "none").
    has_water: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// What the surface's geometry and textures do not resolve.
struct FrameSurface {
    // Sub-texel slope variance along x and z.
    unresolved_variance: vec2<f32>,
    // Mesh spacing of the finest ring (m), and the number of rings.
    base_spacing: f32,
    rings: f32,
}

// Local reflection and refraction textures (seed 000 §3.1.3, §4.4).
struct FrameProjective {
    // Reflection texture: widened camera × mirror about y = 0.
    reflection_view_proj: mat4x4<f32>,
    // Refraction texture: widened camera, and its inverse.
    refraction_view_proj: mat4x4<f32>,
    inv_refraction_view_proj: mat4x4<f32>,
    // Reflection texels per radian of view angle (for the roughness blur).
    reflection_texels_per_radian: f32,
    // 1 when the scene has geometry (0: the refraction texture is empty).
    has_geometry: u32,
    _pad0: u32,
    _pad1: u32,
}

// The sun's shadow map (in refraction-bent shadow space).
struct FrameShadow {
    // World → clip, applied after shadow_space().
    view_proj: mat4x4<f32>,
    // 1 when the shadow map is in use this frame.
    enabled: u32,
    // Its size (texels per side).
    size: u32,
    _pad0: u32,
    _pad1: u32,
}

// Floor caustics in layers (passes/caustics).
struct FrameCaustics {
    // Patch the maps tile (m); x = 0 when caustics are off.
    patch_size: vec2<f32>,
    // The floor depth the layers reach (m).
    floor_depth: f32,
    // 1 / the map's value under flat water.
    inv_flat_value: f32,
    // Layers in use (the texture may hold more, see capabilities.rs).
    layers: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// Light scattered in the water and the fog (passes/godrays).
struct FrameVolume {
    // Distance from the eye (m) within which god rays replace the uniform
    // sun in-scattering (0: no god rays this frame).
    godray_distance: f32,
    // 1 when the god-ray pass marches the sun's light in the fog this frame.
    fog_marched: u32,
    // How far (m) along refracted paths seen from above the water shaders
    // march god rays (0: not this frame).
    shafts_from_above: f32,
    _pad0: f32,
}

// Fog in the air (`[air]`).
struct FrameFog {
    // Scattering σ (m⁻¹) and Henyey–Greenstein g.
    scattering: f32,
    g: f32,
    // How far from the eye it reaches (m), and the fraction of the sky lighting it.
    distance: f32,
    sky_fraction: f32,
    // The clear air's extinction at sea level (m⁻¹, per channel: Rayleigh,
    // aerosols and ozone of the sky's atmosphere), for aerial perspective.
    air_extinction: vec3<f32>,
    _pad0: f32,
}

// Refractive objects' light (passes/water_object).
struct FrameObjects {
    // Their light view (world → clip, orthographic along the sun).
    light_view_proj: mat4x4<f32>,
    // 1 when they bend the sunlight (their caustic map is in use).
    enabled: u32,
    // Depth tolerance of a receiver in that view.
    depth_tolerance: f32,
    _pad0: f32,
    _pad1: f32,
}

// An ambient occluder (hydrolux_core::occlusion::Occluder::packed).
struct Occluder {
    // Centre (m); w the shape: 0 a sphere, 1 a box.
    centre: vec4<f32>,
    // A box's half-axes (m); a sphere's radius in axis_x.w.
    axis_x: vec4<f32>,
    axis_y: vec4<f32>,
    axis_z: vec4<f32>,
}

// The scene's ambient occluders where they are now (shaders/occlusion.wgsl).
struct FrameOcclusion {
    count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    occluders: array<Occluder, 32>,
}

// Choices made by the scene.
struct FrameModes {
    // 0 exact, 1 Schlick, 2 Jensen–Goliáš, 3 power.
    fresnel: u32,
    // 0 ACES, 1 clamp.
    tonemap: u32,
    // VIEW_* below.
    debug_view: u32,
    // 0 physical, 1 simple.
    optics: u32,
    // 0 depth, 1 plane.
    refraction_lookup: u32,
    // The caller's target (the tone map's output), when the frame is drawn
    // at another size (render.quality); 0 when it is the frame's own size.
    output_width: u32,
    output_height: u32,
    _pad2: u32,
}

struct Frame {
    view: FrameView,
    light: FrameLight,
    water: FrameWater,
    surface: FrameSurface,
    projective: FrameProjective,
    shadow: FrameShadow,
    caustics: FrameCaustics,
    volume: FrameVolume,
    fog: FrameFog,
    objects: FrameObjects,
    occlusion: FrameOcclusion,
    modes: FrameModes,
}

fn has_water() -> bool {
    return frame.water.has_water == 1u;
}


@group(0) @binding(0) var<uniform> frame: Frame;

fn exposure() -> f32 {
    return frame.light.exposure;
}
