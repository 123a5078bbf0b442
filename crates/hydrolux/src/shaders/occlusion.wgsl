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

// Lambert's sum over a clipped polygon's edges as its corners come (no
// array of corners: lavapipe spills dynamically indexed locals to memory).
struct LambertSum {
    sum: f32,
    count: u32,
    first: vec3<f32>,
    last: vec3<f32>,
}

fn lambert_add(acc: ptr<function, LambertSum>, x: vec3<f32>, p: vec3<f32>, n: vec3<f32>) {
    if ((*acc).count == 0u) {
        (*acc).first = x;
    } else {
        (*acc).sum += lambert_edge((*acc).last, x, p, n);
    }
    (*acc).last = x;
    (*acc).count += 1u;
}

// One edge a → b of Sutherland–Hodgman against the plane n·(x − p) = 0:
// a if it is above, and where the edge crosses.
fn clip_edge(acc: ptr<function, LambertSum>, a: vec3<f32>, b: vec3<f32>, p: vec3<f32>, n: vec3<f32>) {
    let da = dot(n, a - p);
    let db = dot(n, b - p);
    if (da >= 0.0) {
        lambert_add(acc, a, p, n);
    }
    if ((da >= 0.0) != (db >= 0.0)) {
        lambert_add(acc, a + (b - a) * (da / (da - db)), p, n);
    }
}

// A quad's form factor, clipped to the hemisphere above n at p (twin:
// occlusion::polygon_form_factor).
fn quad_form_factor(q0: vec3<f32>, q1: vec3<f32>, q2: vec3<f32>, q3: vec3<f32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    var acc = LambertSum(0.0, 0u, vec3<f32>(0.0), vec3<f32>(0.0));
    clip_edge(&acc, q0, q1, p, n);
    clip_edge(&acc, q1, q2, p, n);
    clip_edge(&acc, q2, q3, p, n);
    clip_edge(&acc, q3, q0, p, n);
    if (acc.count < 3u) {
        return 0.0;
    }
    return abs(acc.sum + lambert_edge(acc.last, acc.first, p, n)) / (2.0 * PI);
}

// The face of ±a of a box (half-axes a, b, c) turned towards p, if p is
// not on its plane (a point on a face would see that face as its whole
// sky).
fn box_faces(centre: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let side = select(-1.0, 1.0, dot(a, p - centre) > 0.0);
    let face = centre + a * side;
    if (dot(normalize(a), p - face) * side <= 1e-3) {
        return 0.0;
    }
    return quad_form_factor(face - b - c, face + b - c, face + b + c, face - b + c, p, n);
}

// A box's form factor: its faces turned towards p — at most one of each
// opposite pair (twin: occlusion::box_form_factor).
fn box_form_factor(o: Occluder, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let x = o.axis_x.xyz;
    let y = o.axis_y.xyz;
    let z = o.axis_z.xyz;
    let total = box_faces(o.centre.xyz, x, y, z, p, n) + box_faces(o.centre.xyz, y, z, x, p, n)
        + box_faces(o.centre.xyz, z, x, y, p, n);
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
        // Bounded by its enclosing sphere's: skip what cannot hide 0.2% of
        // the sky, or lies wholly below the horizon.
        let to_centre = o.centre.xyz - p;
        let reach = select(o.axis_x.w, length(o.axis_x.xyz + o.axis_y.xyz + o.axis_z.xyz), o.centre.w > 0.5);
        let d2 = dot(to_centre, to_centre);
        if (reach * reach < 0.002 * d2 || dot(n, to_centre) < -reach) {
            continue;
        }
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
