//! Small vector helpers on `[f64; 3]` (ground floor: every layer uses them,
//! they use nothing). Axes beyond a scene's dimension are zero.

/// `a - b`.
#[inline]
pub fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a · b`.
#[inline]
pub fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `|a|`.
#[inline]
pub fn norm(a: &[f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// `|a|` without overflow or underflow of the squares (`hypot`), for the
/// reported forces: a reaction of 1e-295 N keeps its magnitude (`norm` gives 0).
#[inline]
pub fn magnitude(a: &[f64; 3]) -> f64 {
    a[0].hypot(a[1]).hypot(a[2])
}

/// `a × b`.
#[inline]
pub fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
