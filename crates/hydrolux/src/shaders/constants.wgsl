// Mathematical constants and small helpers shared by all shaders.
const PI: f32 = 3.14159265358979;
const TAU: f32 = 6.28318530717959;

// Interleaved gradient noise (Jimenez 2014) in [0, 1) from a pixel position:
// per-pixel offsets of marched samples, turning banding into fine noise.
fn interleaved_gradient_noise(p: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(p, vec2<f32>(0.06711056, 0.00583715))));
}
