// The caustic that refractive objects cast (group 0, binding 8; made by
// passes/water_object): in the objects' light view, rgb is the sunlight that
// came through them landing there, as irradiance on a plane facing the sun
// relative to the sun's; a is the depth, in that view, of the surface it
// landed on. A receiver at that depth gets the rgb × its cos to the sun.
// Needs `frame` and `caustics_lookup` (its sampler).
#import frame, caustics_lookup

@group(0) @binding(8) var object_caustic_map: texture_2d<f32>;

// `world` in the objects' light view: (uv, depth), and whether it lies in
// that view (and the view is made).
fn object_light_at(world: vec3<f32>) -> vec4<f32> {
    let clip = frame.objects.light_view_proj * vec4<f32>(world, 1.0);
    let uv = vec2<f32>(0.5 + 0.5 * clip.x, 0.5 - 0.5 * clip.y);
    let inside = frame.objects.enabled != 0u && all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0));
    return vec4<f32>(uv, clip.z, select(0.0, 1.0, inside));
}

fn object_caustic(world: vec3<f32>) -> vec3<f32> {
    let at = object_light_at(world);
    if (at.w == 0.0) {
        return vec3<f32>(0.0);
    }
    let m = textureSampleLevel(object_caustic_map, caustic_sampler, at.xy, 0.0);
    if (abs(at.z - m.a) > frame.objects.depth_tolerance) {
        return vec3<f32>(0.0);
    }
    return m.rgb;
}

// Whether the sun reaches `world` past the opaque scene alone (1) or not
// (0), as the refractive things' light view sees it (its map's a: the
// opaque scene's depth there). For what lies among the clear things — the
// liquid's white water in a glass or under the liquid's surface — which
// the shadow map counts as shadowing; 0 outside that view. (The clear
// faces' own reflection, a few per cent a face, is not taken off.)
fn sun_past_opaque(world: vec3<f32>) -> f32 {
    let at = object_light_at(world);
    if (at.w == 0.0) {
        return 0.0;
    }
    let size = vec2<i32>(textureDimensions(object_caustic_map));
    let texel = min(vec2<i32>(at.xy * vec2<f32>(size)), size - 1);
    let opaque = textureLoad(object_caustic_map, texel, 0).a;
    // A fifth of the landing's tolerance (a few mm): a thin wall still
    // shades what lies just behind it.
    return select(0.0, 1.0, at.z <= opaque + 0.2 * frame.objects.depth_tolerance);
}
