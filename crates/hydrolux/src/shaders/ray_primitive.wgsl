// Rays against the primitives bodies and traced objects are made of,
// centred at the origin in their own frame: code PRIMITIVE_SPHERE (radius
// size.x), PRIMITIVE_BOX (half-sizes size) or anything else a cylinder
// along y (radius size.x, half-height size.y). Twin: hydrolux-core
// bodies::body_column (the same intervals). Also their signed distance,
// and the rotation into and out of a body's frame.

#import modes

// Where the ray o + t·d (d need not be unit) is inside the primitive:
// (t_in, t_out), with t_in > t_out when it misses.
fn ray_primitive(code: u32, size: vec3<f32>, o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let miss = vec2<f32>(1.0, -1.0);
    var t = vec2<f32>(-1e30, 1e30);
    if (code == PRIMITIVE_SPHERE) {
        let a = dot(d, d);
        let b = dot(o, d);
        let disc = b * b - a * (dot(o, o) - size.x * size.x);
        if (disc < 0.0 || a <= 0.0) {
            return miss;
        }
        return vec2<f32>((-b - sqrt(disc)) / a, (-b + sqrt(disc)) / a);
    }
    if (code == PRIMITIVE_BOX) {
        for (var k = 0; k < 3; k++) {
            if (abs(d[k]) < 1e-6) {
                if (abs(o[k]) > size[k]) {
                    return miss;
                }
            } else {
                let ta = (-size[k] - o[k]) / d[k];
                let tb = (size[k] - o[k]) / d[k];
                t = vec2<f32>(max(t.x, min(ta, tb)), min(t.y, max(ta, tb)));
            }
        }
        return t;
    }
    let a = d.x * d.x + d.z * d.z;
    let b = o.x * d.x + o.z * d.z;
    let c = o.x * o.x + o.z * o.z - size.x * size.x;
    if (a < 1e-8) {
        if (c > 0.0) {
            return miss;
        }
    } else {
        let disc = b * b - a * c;
        if (disc < 0.0) {
            return miss;
        }
        t = vec2<f32>((-b - sqrt(disc)) / a, (-b + sqrt(disc)) / a);
    }
    if (abs(d.y) < 1e-6) {
        if (abs(o.y) > size.y) {
            return miss;
        }
    } else {
        let ta = (-size.y - o.y) / d.y;
        let tb = (size.y - o.y) / d.y;
        t = vec2<f32>(max(t.x, min(ta, tb)), min(t.y, max(ta, tb)));
    }
    return t;
}

// The outward normal of the primitive at its surface point p.
fn primitive_normal(code: u32, size: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    if (code == PRIMITIVE_SPHERE) {
        return normalize(p);
    }
    if (code == PRIMITIVE_BOX) {
        let q = abs(p) / size;
        if (q.x >= q.y && q.x >= q.z) {
            return vec3<f32>(sign(p.x), 0.0, 0.0);
        }
        if (q.y >= q.z) {
            return vec3<f32>(0.0, sign(p.y), 0.0);
        }
        return vec3<f32>(0.0, 0.0, sign(p.z));
    }
    if (abs(p.y) / size.y >= length(p.xz) / size.x) {
        return vec3<f32>(0.0, sign(p.y), 0.0);
    }
    return normalize(vec3<f32>(p.x, 0.0, p.z));
}

// v rotated by the unit quaternion q (x, y, z, w).
fn quat_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

// Signed distance (m) from the primitive's surface to p in its own frame
// (Shape::signed_distance).
fn shape_distance(code: u32, size: vec3<f32>, p: vec3<f32>) -> f32 {
    if (code == PRIMITIVE_SPHERE) {
        return length(p) - size.x;
    }
    if (code == PRIMITIVE_BOX) {
        let q = abs(p) - size;
        return length(max(q, vec3<f32>(0.0))) + min(max(q.x, max(q.y, q.z)), 0.0);
    }
    let q = vec2<f32>(length(p.xz) - size.x, abs(p.y) - size.y);
    return length(max(q, vec2<f32>(0.0))) + min(max(q.x, q.y), 0.0);
}
