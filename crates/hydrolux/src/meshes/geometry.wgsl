// Opaque scene geometry (objects, terrain, floor): Lambertian materials with
// an albedo, a texture or a procedural tile/checker pattern, lit by the sun
// (shadow-mapped) and the sky. Below the mean water level the light is the
// light field under the surface (seed 000 §3.3): refracted, attenuated by
// e^(−σk·d) on its way down. Drawn for several views — main, reflection
// (mirrored, clipped to y ≥ 0), refraction (clipped to y ≤ 0) — and into the
// sun's shadow map (`vs_shadow`).
#import constants, frame, medium, fog, shadow_space, shadow_lookup, caustics_lookup, object_caustics, geometry_common

const GROUND_ALBEDO: f32 = 0.15;

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
    let a = abs(n);
    var p = world.xz;
    if (a.x > a.y && a.x > a.z) {
        p = world.zy;
    } else if (a.z > a.y) {
        p = world.xy;
    }
    let q = p / object.tile_size;
    // Where a pixel covers a good part of a tile, fade to the pattern's mean
    // coverage instead of aliasing into moiré.
    let w = max(fwidth(q), vec2<f32>(1e-4));
    let far = smoothstep(0.15, 0.5, max(w.x, w.y));
    if (object.pattern == 1u) {
        // Grout lines 6% of a tile wide (3% each side), anti-aliased by the
        // pixel footprint; they cover 1 − 0.94² ≈ 11.6% of the area.
        let f = abs(fract(q) - 0.5);
        let line = smoothstep(vec2<f32>(0.47) - w, vec2<f32>(0.47) + w, f);
        return mix(max(line.x, line.y), 0.1164, far);
    }
    if (object.pattern == 2u) {
        let c = floor(q);
        return mix(f32((i32(c.x) + i32(c.y)) & 1), 0.5, far);
    }
    return 0.0;
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

// The main view through air: through the fog, if any.
@fragment
fn fs_air(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let c = shade(in, front);
    if (frame.modes.debug_view == VIEW_NORMALS || frame.modes.debug_view >= VIEW_RIPPLES) {
        return c;
    }
    return vec4<f32>(through_fog(frame.view.position, in.world, c.rgb), 1.0);
}

// The surface's own radiance: material, sun (shadow-mapped), sky, and below
// the mean water level the light field under the surface.
fn shade(in: VsOut, front: bool) -> vec4<f32> {
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
    var irradiance: vec3<f32>;
    if (in.world.y < 0.0 && has_water()) {
        irradiance = underwater_irradiance(-in.world.y, n, visibility * caustic_factor(in.world));
    } else {
        // Sun, sky from above, and light bounced off the ground and water
        // below (a grey world of albedo GROUND_ALBEDO), so the undersides
        // that reflections show are not black.
        let l = frame.light.sun_dir;
        let e_down = frame.light.sky_ambient + frame.light.sun_illuminance * max(l.y, 0.0);
        // The sun, plus what refractive objects bend onto this point.
        irradiance = frame.light.sun_illuminance * max(dot(n, l), 0.0) * (visibility + object_caustic(in.world))
            + frame.light.sky_ambient * (0.5 + 0.5 * n.y)
            + GROUND_ALBEDO * e_down * (0.5 - 0.5 * n.y);
    }
    return vec4<f32>(albedo / PI * irradiance, 1.0);
}
