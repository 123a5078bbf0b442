// Mathematical constants shared by all shaders.
const PI: f32 = 3.14159265358979;
const TAU: f32 = 6.28318530717959;
