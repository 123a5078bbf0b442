// Random numbers without state: a 32-bit integer hash (PCG's output
// permutation) and a uniform number in [0, 1) from a step, an index and a
// salt; the same as hydrolux-core's `whitewater::{hash_u32, random}`, so
// the CPU twins draw the same numbers.

fn hash_u32(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn random(step: u32, index: u32, salt: u32) -> f32 {
    let h = hash_u32(index ^ hash_u32((step * 0x9E3779B9u) ^ hash_u32(salt)));
    return f32(h >> 8u) / 16777216.0;
}
