// The interactive water's texel (of its kicks and its heights' texture; row
// = z) holding world point p, or −1 outside its domain: cells of `cell` m,
// `n` a side, the window's first world cell `window_origin`; between walls
// the domain cell, in open water the world cell modulo n (the texture
// tiles the plane). Twin: hydrolux_core::waves::ripples::texel_of.
fn ripple_texel(p: vec2<f32>, cell: f32, n: i32, window_origin: vec2<i32>, walls: bool) -> i32 {
    let c = vec2<i32>(floor(p / cell));
    let d = c - window_origin;
    if (any(d < vec2<i32>(0)) || any(d >= vec2<i32>(n))) {
        return -1;
    }
    var t = d;
    if (!walls) {
        t = ((c % n) + n) % n;
    }
    return t.y * n + t.x;
}
