// The caustic layers as receivers read them (group 0, bindings 6 and 7):
// layer k holds the caustics on the plane at depth (k + 1)/K × the floor
// depth. A receiver reads the two layers around its depth, each where its
// flat-refracted sunbeam meets that layer (the maps tile the plane), and
// interpolates; above the first layer towards the unfocused value. Returns
// the factor by which the caustics change the sunlight of flat water: 1
// where the surface neither focuses nor spreads it.
#import frame

@group(0) @binding(6) var caustic_map: texture_2d_array<f32>;
@group(0) @binding(7) var caustic_sampler: sampler;

fn caustic_layer(world: vec3<f32>, layer: i32) -> f32 {
    let layers = f32(frame.caustics.layers);
    let layer_depth = frame.caustics.floor_depth * f32(layer + 1) / layers;
    let travel = frame.light.sun_travel;
    let on_layer = world + travel * ((layer_depth + world.y) / max(frame.light.sun_travel_cos, 1e-3));
    let uv = on_layer.xz / frame.caustics.patch_size + 0.5;
    return textureSampleLevel(caustic_map, caustic_sampler, uv, layer, 0.0).r * frame.caustics.inv_flat_value;
}

fn caustic_factor(world: vec3<f32>) -> f32 {
    if (frame.caustics.patch_size.x <= 0.0) {
        return 1.0;
    }
    let layers = i32(frame.caustics.layers);
    // Continuous layer coordinate: layer k at k + 1, the surface at 0.
    let f = clamp(max(-world.y, 0.0) / frame.caustics.floor_depth * f32(layers), 0.0, f32(layers));
    let upper = i32(floor(f)) - 1;
    let a = f - floor(f);
    var above = 1.0;
    if (upper >= 0) {
        above = caustic_layer(world, upper);
    }
    if (upper + 1 >= layers || a == 0.0) {
        return above;
    }
    return mix(above, caustic_layer(world, upper + 1), a);
}
