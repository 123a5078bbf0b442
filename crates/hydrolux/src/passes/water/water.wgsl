// The water surface: a camera-centred clipmap of square rings (geometry
// clipmaps, Losasso & Hoppe 2004) whose vertices sit on a world-fixed grid (no
// swimming) and morph onto the next coarser ring's grid before its edge
// (CDLOD-style, no cracks or popping). Shading: Fresnel (seed 000 §2.1.2;
// selectable formula), local reflections of the scene by projective texturing
// (§3.1.3, §4.4) over the environment-mapped sky (§3.1.2), refraction through
// the water body's absorption and single scattering (§3.3, §4.3; or seed
// 002's simple water colour), a sun glint from a Gaussian slope distribution
// whose variance comes from the filtered slope moments plus the unresolved
// Cox–Munk remainder (Bruneton, Neyret & Holzschuch 2010), and the foam
// that white water leaves (simulation/whitewater; seed 003 §4.4).
// The rings are drawn twice: depth only (`fs_depth`), then shaded with depth
// test Equal, so each pixel runs the expensive shading once however thin the
// distant triangles get (grazing views make them sub-pixel).
// Displacement fades to zero across the outermost displaced ring, where waves
// are below a pixel; beyond it a flat far field (`far_vertex`) reaches the horizon.
// RING_HALF (grid cells from the centre to a ring's edge) and DISPLACED_RINGS
// are prepended by the pass.
#import constants, frame, optics, sea_brdf, sky_model, sky_bindings, pbr, surface, medium, fog, projective, shadow_space, shadow_lookup, caustics_lookup, heightfield_trace, traced, traced_hits, water_traced, water_foam

// Inputs of the water pass (group 2), rebuilt with the render targets. Seen
// from the air: the scene above the water mirrored (reflection) and the
// scene below it (refraction). Seen from inside the water: the scene below
// mirrored (total internal reflection) and the scene above (through
// Snell's window).
@group(2) @binding(0) var reflection_tex: texture_2d<f32>;
@group(2) @binding(1) var refraction_tex: texture_2d<f32>;
@group(2) @binding(2) var refraction_depth: texture_2d<f32>;
@group(2) @binding(3) var clamp_sampler: sampler;
@group(2) @binding(4) var reflection_under_tex: texture_2d<f32>;
@group(2) @binding(5) var refraction_over_tex: texture_2d<f32>;
@group(2) @binding(6) var refraction_over_depth: texture_2d<f32>;

// Ray tracing (`water.method = "raytrace"`, passes/raytrace; seed 003
// §3.3.1): the reflected and refracted rays traced exactly against the
// ground and the water surface as heightfields, instead of looked up in the
// projective textures. Specialised like RIPPLES: 0 projective, 1 traced.
override RAYTRACE: u32 = 0u;
@group(3) @binding(0) var<uniform> traced: TracedParams;
@group(3) @binding(1) var<storage, read> hf_heights: array<f32>;
@group(3) @binding(2) var<storage, read> hf_bounds: array<vec2<f32>>;
@group(3) @binding(3) var<storage, read> traced_objects: array<TracedObject>;
@group(3) @binding(4) var<storage, read> ground_light: array<f32>;
@group(3) @binding(5) var<storage, read> traced_meshes: array<vec4<f32>>;

struct VsOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) grid_pos: vec2<f32>,
}

@vertex
fn vs_main(@location(0) cell: vec2<i32>, @builtin(instance_index) level: u32) -> VsOut {
    // The far field is this entry point's instance FAR_LEVEL rather than its
    // own: one pipeline per medium shades rings and far field alike, and the
    // water's fragment shader, by far the largest, is compiled half as often.
    if (level == FAR_LEVEL) {
        return far_vertex(cell);
    }
    let spacing = frame.surface.base_spacing * exp2(f32(level));
    let cam = frame.view.position.xz;
    // Snap to twice the spacing so this ring's even vertices are the next ring's vertices.
    let centre = round(cam / (2.0 * spacing)) * 2.0 * spacing;
    var g = centre + vec2<f32>(cell) * spacing;
    let half_extent = RING_HALF * spacing;
    let d = max(abs(g.x - cam.x), abs(g.y - cam.y));
    // The camera is at most one spacing from the centre, so every edge vertex
    // is past morph_end: the ring's border matches the coarser ring exactly.
    let morph_end = half_extent - 1.5 * spacing;
    let morph_start = morph_end - 0.3 * half_extent;
    let k = clamp((d - morph_start) / (morph_end - morph_start), 0.0, 1.0);
    let odd = vec2<f32>(cell & vec2<i32>(1));
    g -= odd * spacing * k;
    let s = surface_sample_footprint(g, spacing * (1.0 + k));
    var fade = 1.0;
    if (level + 1u == DISPLACED_RINGS) {
        let from_centre = max(abs(g.x - centre.x), abs(g.y - centre.y));
        fade = 1.0 - smoothstep(0.5 * half_extent, half_extent, from_centre);
    }
    let world = vec3<f32>(g.x + s.disp.x * fade, s.disp.y * fade, g.y + s.disp.z * fade);
    return vs_out(world, g);
}

fn vs_out(world: vec3<f32>, grid_pos: vec2<f32>) -> VsOut {
    var out: VsOut;
    out.clip = frame.view.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.grid_pos = grid_pos;
    return out;
}

// The flat far field: a coarse square ring (cells to ±FAR_HALF, hole inside
// ±FAR_HALF/2) stretched radially so its inner edge is the outermost
// displaced ring's edge (same snapped centre) and its outer edge FAR_SCALE
// times further out. Both edges lie at y = 0, so the seam is closed. Drawn
// by `vs_main` as its instance FAR_LEVEL.
fn far_vertex(cell: vec2<i32>) -> VsOut {
    let last = frame.surface.base_spacing * exp2(f32(DISPLACED_RINGS - 1u));
    let centre = round(frame.view.position.xz / (2.0 * last)) * 2.0 * last;
    let c = vec2<f32>(cell);
    let edge = max(abs(c.x), abs(c.y));
    let t = (edge - 0.5 * FAR_HALF) / (0.5 * FAR_HALF);
    let inner = RING_HALF * last;
    let radius = mix(inner, inner * FAR_SCALE, t * t);
    let g = centre + c / edge * radius;
    return vs_out(vec3<f32>(g.x, 0.0, g.y), g);
}

// Closes the water into a volume for the per-pixel medium test (seed 000
// §4.2): four walls from the far field's square outer edge down to
// VOLUME_DEPTH, and a floor, facing outwards (counter-clockwise seen from
// outside, like the surface seen from above). Draw 30 vertices.
@vertex
fn vs_box(@builtin(vertex_index) i: u32) -> VsOut {
    let last = frame.surface.base_spacing * exp2(f32(DISPLACED_RINGS - 1u));
    let centre = round(frame.view.position.xz / (2.0 * last)) * 2.0 * last;
    let r = RING_HALF * last * FAR_SCALE;
    let half = vec3<f32>(r, 0.5 * VOLUME_DEPTH, r);
    let mid = vec3<f32>(centre.x, -0.5 * VOLUME_DEPTH, centre.y);
    var normals = array<vec3<f32>, 5>(
        vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(-1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0, 0.0, -1.0), vec3<f32>(0.0, -1.0, 0.0));
    var corners = array<vec2<f32>, 6>(vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0));
    let n = normals[i / 6u];
    // u × v = n, so the corners run counter-clockwise around n.
    var u = vec3<f32>(0.0, 1.0, 0.0);
    if (abs(n.y) > 0.5) {
        u = vec3<f32>(1.0, 0.0, 0.0);
    }
    let v = cross(n, u);
    let c = corners[i % 6u];
    let world = mid + half * (n + c.x * u + c.y * v);
    return vs_out(world, world.xz);
}

// Takes the same inputs as fs_main so both pipelines keep the same vertex
// outputs and compute bit-identical positions.
@fragment
fn fs_depth(in: VsOut) {
    _ = in.world;
}

// What a refraction texture shows at `uv`: its world position (w = 1), or
// w = 0 where nothing was drawn.
fn refraction_world(depth_tex: texture_2d<f32>, uv: vec2<f32>) -> vec4<f32> {
    let dims = vec2<f32>(textureDimensions(depth_tex));
    let texel = vec2<i32>(clamp(uv * dims, vec2<f32>(0.0), dims - 1.0));
    let d = textureLoad(depth_tex, texel, 0).r;
    if (d <= 0.0) {
        return vec4<f32>(0.0);
    }
    let ndc = vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    let w = frame.projective.inv_refraction_view_proj * vec4<f32>(ndc, d, 1.0);
    return vec4<f32>(w.xyz / w.w, 1.0);
}

// Where the refracted ray t_dir from surface point p finds its colour in a
// refraction texture (seed 000 §4.4, seed 002 eq. 1): xy the texture
// coordinates, z the path length to what it shows (1e5: nothing). `below`:
// the texture holds the scene under the water (and may use the plane
// lookup); otherwise the scene above it. Never let what lies on the eye's
// side of the surface leak in: the texture must show something beyond p on
// the ray's side, or we fall back to p's own texel.
fn refraction_lookup(depth_tex: texture_2d<f32>, p: vec3<f32>, t_dir: vec3<f32>, below: bool) -> vec3<f32> {
    let own_uv = clip_to_uv(frame.projective.refraction_view_proj * vec4<f32>(p, 1.0));
    var uv: vec2<f32>;
    if (below && frame.modes.refraction_lookup == REFRACTION_PLANE) {
        uv = clip_to_uv(frame.projective.refraction_view_proj * vec4<f32>(refraction_point_plane(p, t_dir, frame.water.refraction_depth, 1000.0), 1.0));
    } else {
        // Seed 002 eq. 1: W = U + dv·R, dv = the distance to what lies behind p, clamped.
        let behind = refraction_world(depth_tex, own_uv);
        var dv = frame.water.refraction_max;
        if (behind.w > 0.0) {
            dv = min(distance(behind.xyz, p), dv);
        }
        uv = clip_to_uv(frame.projective.refraction_view_proj * vec4<f32>(p + t_dir * dv, 1.0));
    }
    var hit = refraction_world(depth_tex, uv);
    let cam = frame.view.position;
    let wrong_side = select((hit.y < p.y - 0.05), (hit.y > p.y + 0.05), below);
    if (hit.w > 0.0 && (distance(hit.xyz, cam) < distance(p, cam) || wrong_side)) {
        uv = own_uv;
        hit = refraction_world(depth_tex, uv);
    }
    var s = 1e5;
    if (hit.w > 0.0) {
        s = distance(hit.xyz, p);
    }
    return vec3<f32>(clamp(uv, vec2<f32>(0.0), vec2<f32>(1.0)), s);
}

// The light that comes up through the surface at p along the refracted ray
// t_dir: what the refraction texture shows where that ray ends, attenuated
// on the way, plus the water's in-scattering.
fn transmitted(p: vec3<f32>, t_dir: vec3<f32>, e_down: vec3<f32>) -> vec3<f32> {
    let ior = frame.water.ior;
    if (frame.projective.has_geometry == 0u) {
        // Nothing under the water (open ocean): bottomless.
        if (frame.modes.optics == OPTICS_SIMPLE) {
            return frame.water.body_color * e_down / PI;
        }
        return path_in_scatter(t_dir, 1e5) / (ior * ior);
    }
    let found = refraction_lookup(refraction_depth, p, t_dir, true);
    let seen = textureSampleLevel(refraction_tex, clamp_sampler, found.xy, 0.0).rgb;
    let s = found.z;
    if (frame.modes.optics == OPTICS_SIMPLE) {
        // Seed 002 eq. 5–6: blend towards the water colour by e^(−d·k).
        let c_water = frame.water.body_color * e_down / PI;
        let a = exp(-s * frame.water.simple_attenuation);
        return c_water + a * (seen - c_water);
    }
    // In-medium radiance leaves through the surface divided by n² (the solid angle widens).
    return (seen * transmittance(s) + path_in_scatter_with_shafts(p, t_dir, s)) / (ior * ior);
}

// path_in_scatter, but with god rays seen from above (frame.volume.shafts_from_above > 0):
// over the first frame.volume.shafts_from_above metres of the refracted path the sun's
// part is marched through the caustic layers and the shadow map (the
// focused, shadowed light), beyond it the uniform closed form. Flat water
// gives the same either way.
fn path_in_scatter_with_shafts(p: vec3<f32>, t_dir: vec3<f32>, s: f32) -> vec3<f32> {
    let reach = min(frame.volume.shafts_from_above, s);
    if (reach <= 0.0) {
        return path_in_scatter(t_dir, s);
    }
    let ds = reach / f32(SHAFT_STEPS);
    let jitter = interleaved_gradient_noise(p.xz * 37.0);
    // Each step: the closed form of its segment (exact for flat water)
    // times the focusing and visibility sampled in it.
    var shafts = vec3<f32>(0.0);
    for (var i = 0u; i < SHAFT_STEPS; i++) {
        let d0 = f32(i) * ds;
        let q = p + t_dir * (d0 + jitter * ds);
        shafts += caustic_factor(q) * sun_visibility_point(q) * sun_in_scatter(0.0, t_dir, d0, d0 + ds);
    }
    return shafts + sun_in_scatter(0.0, t_dir, reach, s) + sky_in_scatter(0.0, t_dir, s);
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let p = in.grid_pos;
    let s = surface_sample_grad(p, dpdx(p), dpdy(p));
    let to_eye = frame.view.position - in.world;
    let dist = length(to_eye);
    let v = to_eye / dist;
    // The rasterised triangle's own normal faces the viewer whenever the
    // triangle is visible (up to folds).
    var n_geo = normalize(cross(dpdy(in.world), dpdx(in.world)));
    if (dot(n_geo, v) < 0.0) {
        n_geo = -n_geo;
    }
    var n = surface_normal(s);
    // Behind a crest the filtered texture normal can face away from a pixel the
    // mesh shows: those pixels would sparkle with grazing (total) Fresnel
    // reflection. Lean on the geometric normal there instead. Only where the
    // normal faces away more than flat water would: towards the horizon
    // every normal is grazing (n·v ≈ v_y), and leaning there put the coarse
    // rings' facets in place of the filtered normal, as dark dots on the
    // horizon (issue #26 item 7).
    let nv = dot(n, v);
    let grazing = clamp(v.y, 1e-3, 0.1);
    if (nv < grazing) {
        n = normalize(mix(n_geo, n, clamp(nv / grazing, 0.0, 1.0)));
    }
    let nv2 = dot(n, v);
    if (nv2 < 0.02) {
        n = normalize(n + (0.02 - nv2) * v);
    }
    if (frame.modes.debug_view == VIEW_NORMALS) {
        return vec4<f32>(n * 0.5 + 0.5, 1.0);
    }
    if (frame.modes.debug_view == VIEW_RIPPLES) {
        return ripple_view(p, n);
    }
    // Derivatives in uniform control flow (WGSL's rule), shared by the foam's
    // cover and its shade.
    let p_dx = dpdx(p);
    let p_dy = dpdy(p);
    let foam = foam_look(p, p_dx, p_dy);
    if (frame.modes.debug_view == VIEW_FOAM) {
        return foam_view(foam_opacity(foam), n);
    }
    let ior = frame.water.ior;
    let q = frame.water.fresnel_power;
    // The pixel's facets (sea_brdf): slopes about the mean normal's, with the
    // variance resolved by the filtered moments plus the unresolved rest.
    // Where they are far below a pixel this is the far sea's BRDF; close up
    // the variance vanishes and it is the mirror of the normal.
    let mean_slope = -n.xz / max(n.y, 1e-3);
    let variance = s.slope_variance + frame.surface.unresolved_variance;
    let sigma = sqrt(variance.x + variance.y);
    // Fresnel over the visible facets, and the mean direction they mirror.
    let sea = sea_reflection(v, mean_slope, variance, frame.modes.fresnel, q, ior);
    let f = sea.fresnel;
    if (frame.modes.debug_view == VIEW_FRESNEL) {
        return vec4<f32>(f, 1.0, 0.0, 1.0);
    }

    // Sky reflection over the pixel's slopes: the sky cube filtered for the
    // GGX lobe of the same mean square slope (α² = σx² + σy², as for
    // Beckmann's; perceptual roughness √α), the lobe opaque surfaces use.
    var r = sea.direction;
    r.y = abs(r.y);
    let lod = specular_cube_lod(sqrt(sigma));
    let sky_reflected = textureSampleLevel(sky_cube, sky_sampler, r, lod).rgb * exposure();
    // Traced water looks nothing up in the reflection texture (a traced
    // frame does not draw it): it traces its reflection below.
    var reflected = sky_reflected;
    if (RAYTRACE == 0u) {
        // Local reflection (seed 000 §3.1.3): the mirrored scene where the
        // reflected ray meets a plane above the surface; the sky where it has none.
        let ruv = clamp(reflection_uv(frame.projective.reflection_view_proj, in.world, r, frame.water.reflection_height, 2000.0), vec2<f32>(0.001), vec2<f32>(0.999));
        // Sub-pixel roughness spreads reflected rays (the resolved waves already
        // move the lookup). Mips blur isotropically where real roughness smears
        // reflections mostly vertically, so a box of half a σ of the unresolved
        // slopes: distant reflections soften without vanishing.
        let unresolved = sqrt(frame.surface.unresolved_variance.x + frame.surface.unresolved_variance.y);
        let local_lod = log2(max(0.5 * unresolved * frame.projective.reflection_texels_per_radian, 1.0));
        let local = textureSampleLevel(reflection_tex, clamp_sampler, ruv, local_lod);
        // The texture is cleared to transparent black, so it is premultiplied by
        // coverage at every mip level.
        reflected = local.rgb + (1.0 - local.a) * sky_reflected;
    }

    // Sun glint, shadowed by the scene.
    let l = frame.light.sun_dir;
    var glint = vec3<f32>(0.0);
    if (l.y > 0.0) {
        glint = frame.light.sun_illuminance * sea_glitter(v, l, mean_slope, variance, frame.modes.fresnel, q, ior);
        glint *= sun_visibility(in.world, vec3<f32>(0.0, 1.0, 0.0));
    }

    let e_down = frame.light.sky_ambient + frame.light.sun_illuminance * max(l.y, 0.0);
    let t_dir = refract(-v, n, 1.0 / ior);
    var through: vec3<f32>;
    if (RAYTRACE == 1u) {
        // Where the refracted ray meets the ground, and how wide a pixel is
        // there (derivatives here, in uniform control flow).
        let pixel_angle = length(fwidth(in.world)) / max(dist, 1e-3);
        reflected = traced_reflection(in.world, n, r, sky_reflected, e_down, pixel_angle);
        let seen = traced_scene(in.world, t_dir, trace_ground(in.world, t_dir), dist, pixel_angle);
        through = traced_transmitted(in.world, t_dir, e_down, seen);
    } else {
        through = transmitted(in.world, t_dir, e_down);
    }
    // The bubble cloud under fresh foam hides what lies deeper and sends up
    // the light it scatters.
    let cloud = bubble_cloud_at(p);
    if (cloud > 0.0) {
        let e_water = frame.light.sun_underwater + frame.light.sky_underwater;
        through = through * (1.0 - BUBBLE_CLOUD_REFLECTANCE * cloud) + bubble_cloud_radiance(cloud, e_water) / (ior * ior);
    }
    var color = f * reflected + (1.0 - f) * through + glint;

    // Foam: a raft of bubbles (albedo 0.8) over the water and its glint.
    // Its top is the wave's surface tilted by the foam's own lumps, so the
    // sun lights a sheet's clumps and edges and leaves their lee and the
    // wave's back in shade, and the sky lights it by the share of the dome
    // the top sees (foam_radiance): foam takes the sky's own light, warm
    // under a low sun, as a white card would. Thin film and hollows are
    // darker (light goes on into the water there) and let the water show
    // (foam_opacity).
    let foam_alpha = foam_opacity(foam);
    if (foam_alpha > 0.0) {
        let top = normalize(n - vec3<f32>(foam.slope.x, 0.0, foam.slope.y));
        let sun = frame.light.sun_illuminance * sun_visibility(in.world, vec3<f32>(0.0, 1.0, 0.0));
        let foam_color = foam_radiance(top, foam.thickness, l, sun, frame.light.sky_ambient);
        color = mix(color, foam_color, foam_alpha);
    }

    // Aerial perspective: distant water melts into the horizon's haze.
    color = through_air(frame.view.position, in.world, color);
    // Alpha 0: the surface's look changes by itself, so the anti-aliasing
    // trusts its history less (TAA_RESPONSIVE_WEIGHT).
    return vec4<f32>(min(color, vec3<f32>(60000.0)), 0.0);
}

// The surface seen from inside the water (seed 000 §2.1.2, §3.3; seed 003
// Fig. 17): Fresnel from water to air, so rays within the critical angle
// (48.6°) leave through Snell's window and show the sky and what stands
// above the water, bent; beyond it the surface is a mirror (total internal
// reflection) showing the scene below or the water's own colour. Everything
// then travels to the eye through the water.
@fragment
fn fs_below(in: VsOut) -> @location(0) vec4<f32> {
    let g = in.grid_pos;
    let s = surface_sample_grad(g, dpdx(g), dpdy(g));
    let eye = frame.view.position;
    let v = normalize(eye - in.world);
    // The normal on the water's side, facing the viewer.
    var n = -surface_normal(s);
    let nv = dot(n, v);
    if (nv < 0.02) {
        n = normalize(n + (0.02 - nv) * v);
    }
    if (frame.modes.debug_view == VIEW_NORMALS) {
        return vec4<f32>(n * 0.5 + 0.5, 1.0);
    }
    if (frame.modes.debug_view == VIEW_RIPPLES) {
        return ripple_view(g, -n);
    }
    let foam = foam_look(g, dpdx(g), dpdy(g));
    if (frame.modes.debug_view == VIEW_FOAM) {
        return foam_view(foam_opacity(foam), n);
    }
    let ior = frame.water.ior;
    // How wide a pixel is per metre along its ray (traced hits' patterns).
    let pixel_angle = length(fwidth(in.world)) / max(distance(eye, in.world), 1e-3);
    let cos_v = max(dot(n, v), 1e-3);
    let f = fresnel(frame.modes.fresnel, frame.water.fresnel_power, cos_v, ior, 1.0);
    if (frame.modes.debug_view == VIEW_FRESNEL) {
        return vec4<f32>(f, 1.0, 0.0, 1.0);
    }
    let depth = max(-in.world.y, 0.0);

    // Reflected back down: the mirrored scene under the water where the ray
    // meets a plane `reflection_height` below, attenuated over that path;
    // endless water where the texture is empty.
    let r = reflect(-v, n);
    let deep = view_in_scatter(depth, r, 1e5);
    var reflected: vec3<f32>;
    if (RAYTRACE == 1u) {
        // Traced down to the ground, through the water on the way.
        // (n faces the viewer: into the water.)
        let o = in.world + n * 0.02;
        let seen = traced_scene(o, r, trace_ground(o, r), distance(eye, in.world), pixel_angle);
        reflected = deep;
        if (seen.w < NO_ROOT) {
            reflected = seen.rgb * transmittance(seen.w) + view_in_scatter(depth, r, seen.w);
        }
    } else {
        let h = frame.water.reflection_height;
        let t_r = clamp((-h - in.world.y) / min(r.y, -1e-3), 0.0, 200.0);
        let unresolved = sqrt(frame.surface.unresolved_variance.x + frame.surface.unresolved_variance.y);
        let lod = log2(max(0.5 * unresolved * frame.projective.reflection_texels_per_radian, 1.0));
        let ruv = clamp(reflection_uv(frame.projective.reflection_view_proj, in.world, r, -h, 200.0), vec2<f32>(0.001), vec2<f32>(0.999));
        let local = textureSampleLevel(reflection_under_tex, clamp_sampler, ruv, lod);
        reflected = local.rgb * transmittance(t_r) + local.a * view_in_scatter(depth, r, t_r) + (1.0 - local.a) * deep;
    }

    // Out through Snell's window: the scene above the water, or the sky; the
    // radiance gains n² entering the denser medium.
    var through = vec3<f32>(0.0);
    if (f < 1.0) {
        let t_dir = refract(-v, n, ior);
        var sky_l = textureSampleLevel(sky_cube, sky_sampler, t_dir, 0.0).rgb * exposure();
        if (RAYTRACE == 1u) {
            // Traced up to the land above the water, or the sky.
            let o = in.world - n * 0.02;
            let seen = traced_scene(o, t_dir, trace_ground(o, t_dir), distance(eye, in.world), pixel_angle);
            var above = sky_l;
            if (seen.w < NO_ROOT) {
                above = through_fog(in.world, o + t_dir * seen.w, seen.rgb);
            }
            through = above * ior * ior;
        } else {
            let found = refraction_lookup(refraction_over_depth, in.world, t_dir, false);
            let above = textureSampleLevel(refraction_over_tex, clamp_sampler, found.xy, 0.0);
            through = (above.rgb + (1.0 - above.a) * sky_l) * ior * ior;
        }
    }
    var l = f * reflected + (1.0 - f) * through;
    // Foam seen from below: a dark, ragged layer. What comes through it is
    // what its bubbles do not scatter back up, by its thickness: a film
    // passes most of the light behind it, a thick sheet only the dim glow
    // diffused through it (a tenth of the sky's).
    let through_foam = mix(l * foam_transmittance(foam.thickness), FOAM_BELOW * frame.light.sky_underwater / PI, foam.thickness);
    l = mix(l, through_foam, foam.cover);
    return vec4<f32>(min(through_water(eye, in.world, l), vec3<f32>(60000.0)), 0.0);
}
