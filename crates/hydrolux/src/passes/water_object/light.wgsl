// Refractive objects seen from the light (seed 004 §3.1): their front faces
// and back faces nearest the sun (where the light enters the first thing on
// its way and where it leaves it), each as outward normal × that thing's
// index of refraction (a glass's, the liquid's) and depth in the objects'
// orthographic light view (a view slot whose matrix is
// frame.objects.light_view_proj).
#import constants, frame, geometry_common

struct LightOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
}

@vertex
fn vs_light(v: VsIn) -> LightOut {
    let world = (object.model * vec4<f32>(v.position, 1.0)).xyz;
    var out: LightOut;
    out.clip = view.view_proj * vec4<f32>(world, 1.0);
    out.normal = object.normal_matrix * v.normal;
    return out;
}

@fragment
fn fs_light(in: LightOut) -> @location(0) vec4<u32> {
    // Stored as the floats' bits (an Rgba32Uint target renders everywhere);
    // the normal's length is the index of refraction (object.ior ≥ 1 for
    // everything drawn here).
    return bitcast<vec4<u32>>(vec4<f32>(normalize(in.normal) * max(object.ior, 1.0), in.clip.z));
}
