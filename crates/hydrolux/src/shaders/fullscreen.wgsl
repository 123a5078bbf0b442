// A triangle covering the screen, from the vertex index alone (draw 3 vertices).

fn fullscreen_ndc(i: u32) -> vec2<f32> {
    return vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0 - 1.0;
}
