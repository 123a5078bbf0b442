// Opaque scene geometry (objects, terrain, floor): physically based
// materials (shaders/pbr.wgsl) with a base colour, a texture or a
// procedural tile/checker pattern, lit by the sun (shadow-mapped) and the
// sky. Below the mean water level the light is the light field under the
// surface (seed 000 §3.3): refracted, attenuated by e^(−σk·d) on its way
// down, on a Lambertian surface of the base colour (the specular part there
// would reflect the water's own radiance field, which is not modelled). Drawn for several views — main, reflection
// (mirrored, clipped to y ≥ 0), refraction (clipped to y ≤ 0) — and into the
// sun's shadow map (`vs_shadow`).
#import constants, frame, lighting, pbr, medium, fog, shadow_space, shadow_lookup, caustics_lookup, object_caustics, geometry_common

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
}

@vertex
fn vs_main(v: VsIn) -> VsOut {
    let world = (object.model * vec4<f32>(v.position, 1.0)).xyz;
    var out: VsOut;
    out.clip = view.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = object.normal_matrix * v.normal;
    out.uv = v.uv * object.uv_scale;
    return out;
}

// Procedural pattern on the plane facing the dominant normal axis.
fn pattern_mix(world: vec3<f32>, n: vec3<f32>) -> f32 {
    let q = pattern_plane(world, n) / object.tile_size;
    return pattern_coverage(q, fwidth(q), object.pattern);
}

// Seen from inside the water: what fs_main gives, attenuated and
// in-scattered along the way to the eye (seed 000 eq. 3.7–3.8).
@fragment
fn fs_underwater(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let c = shade(in, front);
    if (frame.modes.debug_view == VIEW_NORMALS || frame.modes.debug_view >= VIEW_RIPPLES) {
        return c;
    }
    return vec4<f32>(through_water(frame.view.position, in.world, c.rgb), 1.0);
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    return shade(in, front);
}

// The refraction view (clipped to y ≤ 0, drawn only with water): the light
// field under the surface alone. A software rasteriser runs both sides of a
// branch, so the air's shading is left out of this entry point entirely.
@fragment
fn fs_below(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    return shade_surface(in, front, false);
}

// The main view through air: through the fog, if any.
@fragment
fn fs_air(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let c = shade(in, front);
    if (frame.modes.debug_view == VIEW_NORMALS || frame.modes.debug_view >= VIEW_RIPPLES) {
        return c;
    }
    return vec4<f32>(through_air(frame.view.position, in.world, c.rgb), 1.0);
}

// The surface's own radiance: material, sun (shadow-mapped), sky, and below
// the mean water level the light field under the surface.
fn shade(in: VsOut, front: bool) -> vec4<f32> {
    return shade_surface(in, front, true);
}

// As `shade`; without `in_air` (a constant at each call) only the light
// under the surface.
fn shade_surface(in: VsOut, front: bool, in_air: bool) -> vec4<f32> {
    if (dot(view.clip_plane.xyz, in.world) + view.clip_plane.w < 0.0) {
        discard;
    }
    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    if (frame.modes.debug_view == VIEW_NORMALS) {
        return vec4<f32>(n * 0.5 + 0.5, 1.0);
    }
    if (frame.modes.debug_view >= VIEW_RIPPLES) {
        return vec4<f32>(vec3<f32>(0.12 + 0.1 * n.y), 1.0);
    }
    var albedo = object.albedo * textureSample(albedo_tex, albedo_sampler, in.uv).rgb;
    albedo = mix(albedo, object.pattern_color, pattern_mix(in.world, n));
    let visibility = sun_visibility(in.world, n);
    if (!in_air || (in.world.y < 0.0 && has_water())) {
        let irradiance = underwater_irradiance(-in.world.y, n, visibility * caustic_factor(in.world));
        return vec4<f32>(albedo / PI * irradiance, 1.0);
    }
    // The sun, plus what refractive objects bend onto this point.
    let material = Material(albedo, object.roughness, object.metalness, object.specular);
    let v = normalize(view.eye - in.world);
    return vec4<f32>(air_surface_radiance(material, in.world, n, v, visibility + object_caustic(in.world), object.occluder), 1.0);
}
