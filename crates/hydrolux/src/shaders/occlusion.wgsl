// Ambient occlusion by the scene's primitives (issue #32 item 1): what the
// occluders in frame.occlusion leave of the sky's light at a point — the
// product of 1 − F over them, F each one's form factor in closed form (a
// sphere: exact above, below and straddling the horizon; a box: Lambert's
// formula over its faces turned towards the point, clipped to its
// horizon). Twin: hydrolux-core occlusion (the reasons for analytic
// occluders are there).
#import constants, frame

// A sphere of radius r whose centre is at `to_centre` (twin:
// occlusion::sphere_form_factor).
fn sphere_form_factor(to_centre: vec3<f32>, r: f32, n: vec3<f32>) -> f32 {
    let d = length(to_centre);
    if (d <= r) {
        return 1.0;
    }
    let nl = dot(n, to_centre / d);
    let h2 = (d / r) * (d / r);
    let k2 = 1.0 - h2 * nl * nl;
    if (k2 <= 0.0) {
        return max(nl, 0.0) / h2;
    }
    let res = nl * acos(clamp(-nl * sqrt((h2 - 1.0) / max(1.0 - nl * nl, 1e-9)), -1.0, 1.0)) - sqrt(k2 * (h2 - 1.0));
    return clamp((res / h2 + atan(sqrt(k2 / (h2 - 1.0)))) / PI, 0.0, 1.0);
}

// One edge's term of Lambert's formula.
fn lambert_edge(a: vec3<f32>, b: vec3<f32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let u = normalize(a - p);
    let v = normalize(b - p);
    let c = cross(u, v);
    let len = length(c);
    return select(0.0, acos(clamp(dot(u, v), -1.0, 1.0)) * dot(n, c / max(len, 1e-12)), len > 1e-9);
}

// A quad's form factor, clipped to the hemisphere above n at p
// (Sutherland–Hodgman: at most five corners; twin:
// occlusion::polygon_form_factor).
fn quad_form_factor(q: array<vec3<f32>, 4>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    var clipped: array<vec3<f32>, 5>;
    var count = 0u;
    for (var i = 0u; i < 4u; i++) {
        let a = q[i];
        let b = q[(i + 1u) % 4u];
        let da = dot(n, a - p);
        let db = dot(n, b - p);
        if (da >= 0.0) {
            clipped[count] = a;
            count++;
        }
        if ((da >= 0.0) != (db >= 0.0) && count < 5u) {
            clipped[count] = a + (b - a) * (da / (da - db));
            count++;
        }
    }
    if (count < 3u) {
        return 0.0;
    }
    var sum = 0.0;
    for (var i = 0u; i < count; i++) {
        sum += lambert_edge(clipped[i], clipped[(i + 1u) % count], p, n);
    }
    return abs(sum) / (2.0 * PI);
}

// A box's form factor: its faces turned towards p (twin:
// occlusion::box_form_factor).
fn box_form_factor(o: Occluder, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let axes = array<vec3<f32>, 3>(o.axis_x.xyz, o.axis_y.xyz, o.axis_z.xyz);
    var total = 0.0;
    for (var k = 0u; k < 3u; k++) {
        let a = axes[k];
        let b = axes[(k + 1u) % 3u];
        let c = axes[(k + 2u) % 3u];
        for (var s = 0u; s < 2u; s++) {
            let side = select(-1.0, 1.0, s == 1u);
            let face = o.centre.xyz + a * side;
            // Turned towards p, which is not on its plane (a point on a
            // face would see that face as its whole sky).
            if (dot(normalize(a), p - face) * side > 1e-3) {
                total += quad_form_factor(array<vec3<f32>, 4>(face - b - c, face + b - c, face + b + c, face - b + c), p, n);
            }
        }
    }
    return min(total, 1.0);
}

// What the occluders but occluder `own` (the surface's own, or
// 0xffffffff) leave of the sky's light at p, normal n (twin:
// occlusion::sky_visibility).
fn sky_visibility(p: vec3<f32>, n: vec3<f32>, own: u32) -> f32 {
    var v = 1.0;
    for (var i = 0u; i < min(frame.occlusion.count, 32u); i++) {
        if (i == own) {
            continue;
        }
        let o = frame.occlusion.occluders[i];
        var f: f32;
        if (o.centre.w < 0.5) {
            f = sphere_form_factor(o.centre.xyz - p, o.axis_x.w, n);
        } else {
            f = box_form_factor(o, p, n);
        }
        v *= 1.0 - f;
    }
    return v;
}
