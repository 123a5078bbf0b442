// The liquid's surface mesh from the camera, depth only: where the white
// water's draw (white_water_draw.wgsl) finds the liquid in front of it.
#import geometry_common

@vertex
fn vs_depth(v: VsIn) -> @builtin(position) vec4<f32> {
    return view.view_proj * object.model * vec4<f32>(v.position, 1.0);
}
