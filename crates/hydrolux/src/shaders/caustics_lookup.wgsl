// The floor caustic map as receivers read it (group 0, bindings 6 and 7):
// follow the flat-refracted sunbeam from the receiver down to the floor
// plane the map was made for and read the map there (it tiles the plane).
// Returns the factor by which the caustics change the sunlight of flat
// water: 1 where the surface neither focuses nor spreads it.

@group(0) @binding(6) var caustic_map: texture_2d<f32>;
@group(0) @binding(7) var caustic_sampler: sampler;

fn caustic_factor(world: vec3<f32>) -> f32 {
    let extent = frame.caustic_params.xy;
    if (extent.x <= 0.0) {
        return 1.0;
    }
    let floor_depth = frame.caustic_params.z;
    let depth = max(-world.y, 0.0);
    let travel = frame.sun_travel.xyz;
    let on_floor = world + travel * ((floor_depth - depth) / max(frame.sun_travel.w, 1e-3));
    let uv = on_floor.xz / extent + 0.5;
    return textureSampleLevel(caustic_map, caustic_sampler, uv, 0.0).r * frame.caustic_params.w;
}
