// The geometry into the sun's shadow map, in refraction-bent shadow space
// (shaders/shadow_space.wgsl). Composed without the shadow map's bindings:
// it is the attachment being written.
#import constants, frame, shadow_space, geometry_common

@vertex
fn vs_shadow(v: VsIn) -> @builtin(position) vec4<f32> {
    let world = (object.model * vec4<f32>(v.position, 1.0)).xyz;
    return view.view_proj * vec4<f32>(shadow_space(world), 1.0);
}

