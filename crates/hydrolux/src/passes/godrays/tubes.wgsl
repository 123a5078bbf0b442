// God rays, step 1 (lines method): one thread per photon of a regular grid
// over the square of surface around the viewer traces its beam tube: refract
// at the displaced surface, carry the flux its cell lets through, end at the
// floor or where no point of it can be within the drawn distance. Twin:
// hydrolux_core::godrays::beam_tubes.
#import constants, frame, medium, tube, godrays_common, optics, surface, photon

@group(2) @binding(0) var<uniform> params: GodRayParams;
@group(2) @binding(1) var<storage, read_write> tubes: array<Tube>;

@compute @workgroup_size(8, 8, 1)
fn build(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = params.photons;
    if (id.x >= n || id.y >= n) {
        return;
    }
    let half = params.region_half;
    let origin = params.region_centre + ((vec2<f32>(id.xy) + 0.5) / f32(n) - 0.5) * 2.0 * half;
    let photon = refracted_photon(origin);
    var tube: Tube;
    tube.start = vec4<f32>(photon.pos, 0.0);
    tube.dir = vec4<f32>(photon.dir, 0.0);
    tube.tint = vec4<f32>(1.0);
    if (photon.weight > 0.0) {
        let length = max((photon.pos.y + params.end_depth) / -photon.dir.y, 0.0);
        // Cull tubes that never come within the drawn distance of the eye.
        let eye = frame.view.position;
        let along = clamp(dot(eye - photon.pos, photon.dir), 0.0, length);
        let gap = distance(photon.pos + photon.dir * along, eye);
        let spacing = 2.0 * half / f32(n);
        if (gap < params.distance + params.ribbon_half_width) {
            tube.start.w = length;
            tube.dir.w = photon.weight * spacing * spacing;
        }
    }
    tubes[id.y * n + id.x] = tube;
}
