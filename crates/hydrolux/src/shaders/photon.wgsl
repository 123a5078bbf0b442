// A photon of sunlight refracted into the water at the displaced surface
// (seed 000 §4.5). Twin: hydrolux_core::caustics::refracted_photon. Needs
// `frame`, `optics` and `surface`.
#import frame, optics, surface

struct Photon {
    // Where it enters the water.
    pos: vec3<f32>,
    // Unit direction of travel.
    dir: vec3<f32>,
    // Fraction of the sun's irradiance × area it carries per unit of
    // undisplaced surface area; 0 for none (back-facing cell, no downward ray).
    weight: f32,
}

fn refracted_photon(origin: vec2<f32>) -> Photon {
    var p: Photon;
    p.weight = 0.0;
    let s = surface_sample_footprint(origin, 0.0);
    let tx = vec3<f32>(1.0 + s.dxx, s.slope.x, s.dxz);
    let tz = vec3<f32>(s.dxz, s.slope.y, 1.0 + s.dzz);
    // Unnormalised normal: its length is the displaced cell's area scale,
    // so its dot with the light is the area the cell shows the sun.
    let area_normal = cross(tz, tx);
    let l = frame.light.sun_dir;
    let shown = dot(area_normal, l);
    if (shown <= 0.0) {
        return p;
    }
    let nrm = normalize(area_normal);
    let ior = frame.water.ior;
    let dir = refract(-l, nrm, 1.0 / ior);
    if (dir.y > -1e-4) {
        return p;
    }
    p.pos = vec3<f32>(origin.x + s.disp.x, s.disp.y, origin.y + s.disp.z);
    p.dir = dir;
    // Foam on the surface scatters most of the light back up.
    p.weight = shown * (1.0 - fresnel_exact(dot(nrm, l), 1.0, ior)) * foam_transmittance(foam_cover_at(origin));
    return p;
}
