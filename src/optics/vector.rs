//! Three-vector arithmetic on `[f64; 3]`, defined once for the analyzer's
//! geometry (the heatmap views' cameras and shading, the placement's
//! footprints, a solo camera's pose). The analyzer does without glam (the
//! capture's vector crate), so these few are its own.

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// `v` scaled to unit length (a zero vector stays zero).
pub(crate) fn normalize(v: [f64; 3]) -> [f64; 3] {
    let length = dot(v, v).sqrt().max(1e-300);
    v.map(|c| c / length)
}
