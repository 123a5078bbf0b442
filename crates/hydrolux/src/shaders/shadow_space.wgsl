// The sun's shadow map, bent by refraction. Below the mean surface, sunlight
// travels along the refracted direction; a point x at depth d is moved along
// back up the refracted beam to its entry point e = x − t·d/cos θw, then down
// the unrefracted beam to the same depth: e − l·d/l.y. An orthographic
// projection along the sun then maps it to the texel of its entry point. Exact for a flat surface (Snell); twin of
// hydrolux_core::projective::shadow_space.
#import frame

fn shadow_space(world: vec3<f32>) -> vec3<f32> {
    let d = select(0.0, max(-world.y, 0.0), has_water());
    let t = frame.light.sun_travel;
    let l = frame.light.sun_dir;
    let entry = world - t * (d / max(frame.light.sun_travel_cos, 1e-3));
    return entry - l * (d / max(l.y, 1e-3));
}
