//! Ken Perlin's improved noise (SIGGRAPH 2002), exactly as his Java reference implementation:
//! the same permutation table, the fade curve 6t⁵ − 15t⁴ + 10t³, and the twelve gradient
//! directions (plus four repeats) picked by the low four bits of the hash. Also its analytic
//! gradient, fBm and turbulence, and Perlin's bias and gain functions.
//!
//! Everything is `f64`, as in the reference, so values agree with it to the last bits.

use glam::DVec3;

/// Ken Perlin's permutation of 0..=255, as published.
const PERMUTATION: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

#[inline(always)]
fn p(i: usize) -> usize {
    PERMUTATION[i & 255] as usize
}

/// [`PERMUTATION`] twice over (the reference's `p[512]`): the hashes of [`noise3f`] and
/// [`noise3f_x4`] index it below 512 without a mask.
const PERMUTATION_2: [u8; 512] = {
    let mut out = [0u8; 512];
    let mut i = 0;
    while i < 512 {
        out[i] = PERMUTATION[i & 255];
        i += 1;
    }
    out
};

/// `p(i)` for `i < 512`, one load.
///
/// # Safety
/// `i < 512`.
#[inline(always)]
unsafe fn p2(i: usize) -> usize {
    // SAFETY: the caller's bound.
    usize::from(unsafe { *PERMUTATION_2.get_unchecked(i) })
}

/// 6t⁵ − 15t⁴ + 10t³.
#[inline(always)]
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// d/dt of [`fade`]: 30t⁴ − 60t³ + 30t².
#[inline(always)]
fn fade_derivative(t: f64) -> f64 {
    30.0 * t * t * (t * (t - 2.0) + 1.0)
}

/// The gradient vector the hash picks (the reference's `grad` as a vector).
#[inline(always)]
fn gradient(hash: usize) -> DVec3 {
    let h = hash & 15;
    let (mut g, su, sv) = (
        DVec3::ZERO,
        if h & 1 == 0 { 1.0 } else { -1.0 },
        if h & 2 == 0 { 1.0 } else { -1.0 },
    );
    // u = x if h < 8 else y; v = y if h < 4, x if h is 12 or 14, else z.
    if h < 8 {
        g.x += su;
    } else {
        g.y += su;
    }
    if h < 4 {
        g.y += sv;
    } else if h == 12 || h == 14 {
        g.x += sv;
    } else {
        g.z += sv;
    }
    g
}

/// Lattice floor and fraction, wrapped to the table's period of 256 like the reference.
#[inline(always)]
fn cell(v: f64) -> (usize, f64) {
    let f = v.floor();
    ((f as i64 & 255) as usize, v - f)
}

/// The eight corner hashes of the cell containing `(x, y, z)` and the position inside it.
#[inline(always)]
fn corners(x: f64, y: f64, z: f64) -> ([usize; 8], DVec3) {
    let (xi, fx) = cell(x);
    let (yi, fy) = cell(y);
    let (zi, fz) = cell(z);
    let a = p(xi) + yi;
    let (aa, ab) = (p(a) + zi, p(a + 1) + zi);
    let b = p(xi + 1) + yi;
    let (ba, bb) = (p(b) + zi, p(b + 1) + zi);
    // Order: (x, y, z) bits = (0,0,0), (1,0,0), (0,1,0), (1,1,0), then z + 1.
    (
        [
            p(aa),
            p(ba),
            p(ab),
            p(bb),
            p(aa + 1),
            p(ba + 1),
            p(ab + 1),
            p(bb + 1),
        ],
        DVec3::new(fx, fy, fz),
    )
}

/// Improved noise at `(x, y, z)`: in about [−1, 1], zero at every lattice point.
///
/// ```
/// let n = texmap::texture::procedural::perlin::noise3(3.14, 42.0, 7.0);
/// assert!((n - 0.13691995878400012).abs() < 1e-12);
/// ```
#[must_use]
pub fn noise3(x: f64, y: f64, z: f64) -> f64 {
    let (h, f) = corners(x, y, z);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let g = |i: usize, x: f64, y: f64, z: f64| grad(h[i], x, y, z);
    let lerp = |t: f64, a: f64, b: f64| a + t * (b - a);
    let (x, y, z) = (f.x, f.y, f.z);
    lerp(
        w,
        lerp(
            v,
            lerp(u, g(0, x, y, z), g(1, x - 1.0, y, z)),
            lerp(u, g(2, x, y - 1.0, z), g(3, x - 1.0, y - 1.0, z)),
        ),
        lerp(
            v,
            lerp(u, g(4, x, y, z - 1.0), g(5, x - 1.0, y, z - 1.0)),
            lerp(
                u,
                g(6, x, y - 1.0, z - 1.0),
                g(7, x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    )
}

/// The reference's `grad`: the dot product of the hashed gradient with `(x, y, z)`.
#[inline(always)]
fn grad(hash: usize, x: f64, y: f64, z: f64) -> f64 {
    let h = hash & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// Noise and its analytic gradient (∂n/∂x, ∂n/∂y, ∂n/∂z).
#[must_use]
pub fn noise3_with_gradient(x: f64, y: f64, z: f64) -> (f64, DVec3) {
    let (h, f) = corners(x, y, z);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let (du, dv, dw) = (
        fade_derivative(f.x),
        fade_derivative(f.y),
        fade_derivative(f.z),
    );
    let mut values = [0.0; 8];
    let mut grads = [DVec3::ZERO; 8];
    for (i, &hash) in h.iter().enumerate() {
        let offset = DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64);
        grads[i] = gradient(hash);
        values[i] = grads[i].dot(f - offset);
    }
    let lerp = |t: f64, a: f64, b: f64| a + t * (b - a);
    // Trilinear blend of the corner values with the faded weights, as the reference nests it.
    let x00 = lerp(u, values[0], values[1]);
    let x10 = lerp(u, values[2], values[3]);
    let x01 = lerp(u, values[4], values[5]);
    let x11 = lerp(u, values[6], values[7]);
    let y0 = lerp(v, x00, x10);
    let y1 = lerp(v, x01, x11);
    let n = lerp(w, y0, y1);
    // Gradient: blended corner gradients plus the fade derivatives times the value differences.
    let gl = |t: f64, a: DVec3, b: DVec3| a + (b - a) * t;
    let g00 = gl(u, grads[0], grads[1]);
    let g10 = gl(u, grads[2], grads[3]);
    let g01 = gl(u, grads[4], grads[5]);
    let g11 = gl(u, grads[6], grads[7]);
    let g = gl(w, gl(v, g00, g10), gl(v, g01, g11));
    let dx = du
        * lerp(
            w,
            lerp(v, values[1] - values[0], values[3] - values[2]),
            lerp(v, values[5] - values[4], values[7] - values[6]),
        );
    let dy = dv * lerp(w, x10 - x00, x11 - x01);
    let dz = dw * (y1 - y0);
    (n, g + DVec3::new(dx, dy, dz))
}

/// Fractional Brownian motion: Σ gainⁱ·noise(lacunarityⁱ·p) over `octaves` (fractional
/// octaves fade the last one in, so the octave count can follow a footprint smoothly).
#[must_use]
pub fn fbm(p: DVec3, octaves: f64, lacunarity: f64, gain: f64) -> f64 {
    sum_octaves(p, octaves, lacunarity, gain, |v| v)
}

/// Turbulence: Σ gainⁱ·|noise(lacunarityⁱ·p)|, Perlin's sum of absolute values.
#[must_use]
pub fn turbulence(p: DVec3, octaves: f64, lacunarity: f64, gain: f64) -> f64 {
    sum_octaves(p, octaves, lacunarity, gain, f64::abs)
}

fn sum_octaves(
    p: DVec3,
    octaves: f64,
    lacunarity: f64,
    gain: f64,
    shape: impl Fn(f64) -> f64,
) -> f64 {
    let octaves = octaves.clamp(0.0, 32.0);
    let whole = octaves.floor() as u32;
    let (mut sum, mut amp, mut freq) = (0.0, 1.0, 1.0);
    for _ in 0..whole {
        let q = p * freq;
        sum += amp * shape(noise3(q.x, q.y, q.z));
        amp *= gain;
        freq *= lacunarity;
    }
    let partial = octaves - whole as f64;
    if partial > 0.0 {
        let q = p * freq;
        sum += partial * amp * shape(noise3(q.x, q.y, q.z));
    }
    sum
}

/// [`fbm`] and its analytic gradient, with the same octaves (the last, fractional one faded in
/// the same way), so a bump from the pattern follows the footprint as its colour does.
#[must_use]
pub fn fbm_with_gradient(p: DVec3, octaves: f64, lacunarity: f64, gain: f64) -> (f64, DVec3) {
    sum_octaves_with_gradient(p, octaves, lacunarity, gain, false)
}

/// [`turbulence`] and its gradient (where an octave's noise is exactly zero, the kink of |n|,
/// that octave's gradient is taken as zero).
#[must_use]
pub fn turbulence_with_gradient(
    p: DVec3,
    octaves: f64,
    lacunarity: f64,
    gain: f64,
) -> (f64, DVec3) {
    sum_octaves_with_gradient(p, octaves, lacunarity, gain, true)
}

fn sum_octaves_with_gradient(
    p: DVec3,
    octaves: f64,
    lacunarity: f64,
    gain: f64,
    absolute: bool,
) -> (f64, DVec3) {
    let octaves = octaves.clamp(0.0, 32.0);
    let whole = octaves.floor() as u32;
    let partial = octaves - whole as f64;
    let (mut sum, mut grad) = (0.0, DVec3::ZERO);
    let (mut amp, mut freq) = (1.0, 1.0);
    for i in 0..=whole {
        let weight = if i < whole { amp } else { partial * amp };
        if weight == 0.0 {
            break;
        }
        let q = p * freq;
        let (mut n, mut g) = noise3_with_gradient(q.x, q.y, q.z);
        if absolute {
            // d|n| = sign(n)·dn; at n = 0 the kink's gradient is taken as zero.
            let s = if n > 0.0 {
                1.0
            } else if n < 0.0 {
                -1.0
            } else {
                0.0
            };
            n = n.abs();
            g *= s;
        }
        sum += weight * n;
        // The chain rule through q = freq·p.
        grad += g * (weight * freq);
        amp *= gain;
        freq *= lacunarity;
    }
    (sum, grad)
}

/// Perlin's bias: `t^(ln b / ln ½)` — bias(b, ½) = b; b = ½ is the identity.
#[must_use]
pub fn bias(b: f64, t: f64) -> f64 {
    if t <= 0.0 {
        return 0.0;
    }
    t.powf(b.ln() / 0.5f64.ln())
}

/// Perlin's gain: an S-curve (g > ½) or its inverse (g < ½) built from two biases.
#[must_use]
pub fn gain(g: f64, t: f64) -> f64 {
    if t < 0.5 {
        bias(1.0 - g, 2.0 * t) / 2.0
    } else {
        1.0 - bias(1.0 - g, 2.0 - 2.0 * t) / 2.0
    }
}

/// [`gradient`]'s sixteen vectors.
const GRADIENTS_F32: [[f32; 3]; 16] = [
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [-1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [-1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, -1.0, 1.0],
    [0.0, 1.0, -1.0],
    [0.0, -1.0, -1.0],
    [1.0, 1.0, 0.0],
    [0.0, -1.0, 1.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, -1.0],
];

/// [`GRADIENTS_F32`] padded to four components: one 16-byte load per hash, four lanes'
/// gradients transposed into x, y and z lanes ([`noise3f_x4`]).
const GRADIENTS_F32X4: [[f32; 4]; 16] = {
    let mut out = [[0.0f32; 4]; 16];
    let mut i = 0;
    while i < 16 {
        let [x, y, z] = GRADIENTS_F32[i];
        out[i] = [x, y, z, 0.0];
        i += 1;
    }
    out
};

/// The gradient a corner's hash `h < 512` picks, `GRADIENTS_F32X4[p(h) & 15]`: one load
/// instead of the lookup, the mask and the second load (the same values).
const GRADIENT_OF_HASH: [[f32; 4]; 512] = {
    let mut out = [[0.0f32; 4]; 512];
    let mut i = 0;
    while i < 512 {
        out[i] = GRADIENTS_F32X4[(PERMUTATION[i & 255] & 15) as usize];
        i += 1;
    }
    out
};

/// [`GRADIENT_OF_HASH`]`[h]`.
///
/// # Safety
/// `h < 512`.
#[inline(always)]
unsafe fn gradient_of_hash(h: usize) -> &'static [f32; 4] {
    // SAFETY: the caller's bound.
    unsafe { GRADIENT_OF_HASH.get_unchecked(h) }
}

/// [`noise3`] in `f32`, for volume work that evaluates noise millions of times a frame
/// (hypertexture): the same lattice, hashes and gradients, so it agrees with [`noise3`] to
/// `f32` rounding (about 1e-6) for coordinates below 2¹⁶.
#[must_use]
#[inline]
pub fn noise3f(x: f32, y: f32, z: f32) -> f32 {
    let cellf = |v: f32| {
        let f = v.floor();
        ((f as i32 & 255) as usize, v - f)
    };
    let (xi, x) = cellf(x);
    let (yi, y) = cellf(y);
    let (zi, z) = cellf(z);
    // SAFETY (the `p2` and `gradient_of_hash` calls): xi, yi, zi ≤ 255 and a table entry
    // ≤ 255, so `a`, `b`, `aa`, `ab`, `ba`, `bb` ≤ 510 and every index (each + 1 at most)
    // is below 512.
    let a = p(xi) + yi;
    let (aa, ab) = unsafe { (p2(a) + zi, p2(a + 1) + zi) };
    let b = unsafe { p2(xi + 1) } + yi;
    let (ba, bb) = unsafe { (p2(b) + zi, p2(b + 1) + zi) };
    let fadef = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v, w) = (fadef(x), fadef(y), fadef(z));
    // The reference's twelve directions (and four repeats) as a table: a branch per hash
    // bit mispredicts half the time on random hashes. `hash` is a corner's `aa`… (+ 1).
    let g = |hash: usize, x: f32, y: f32, z: f32| {
        let [gx, gy, gz, _] = *unsafe { gradient_of_hash(hash) };
        gx * x + gy * y + gz * z
    };
    let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
    lerp(
        w,
        lerp(
            v,
            lerp(u, g(aa, x, y, z), g(ba, x - 1.0, y, z)),
            lerp(u, g(ab, x, y - 1.0, z), g(bb, x - 1.0, y - 1.0, z)),
        ),
        lerp(
            v,
            lerp(u, g(aa + 1, x, y, z - 1.0), g(ba + 1, x - 1.0, y, z - 1.0)),
            lerp(
                u,
                g(ab + 1, x, y - 1.0, z - 1.0),
                g(bb + 1, x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    )
}

/// [`noise3f`] at four points at once (lane `i` is the point `(x[i], y[i], z[i])`): the
/// hashes per lane, the fade curves, gradient products and blends in `Vec4` lanes in
/// `noise3f`'s order of operations, so each lane has exactly `noise3f`'s bits.
#[must_use]
#[inline]
pub fn noise3f_x4(x: glam::Vec4, y: glam::Vec4, z: glam::Vec4) -> glam::Vec4 {
    let (fx, fy, fz) = (x.floor(), y.floor(), z.floor());
    let mut g = [[glam::Vec4::ZERO; 3]; 8];
    corner_gradients_x4(fx, fy, fz, &mut g);
    blend_x4(x - fx, y - fy, z - fz, &g)
}

/// The lattice cells of the last four points [`noise3f_x4_cached`] took and their corners'
/// gradients: a pure function of the cells, so reusing it for points in the same cells
/// gives the same bits.
#[derive(Clone, Copy, Debug)]
pub struct CellsX4 {
    /// The four lanes' cells (the points' floors; NaN: none yet).
    floors: [glam::Vec4; 3],
    /// Per corner (`noise3f`'s order), the four lanes' gradients' x, y and z in lanes.
    gradients: [[glam::Vec4; 3]; 8],
}

impl CellsX4 {
    /// No cells yet.
    pub const EMPTY: CellsX4 = CellsX4 {
        floors: [glam::Vec4::NAN; 3],
        gradients: [[glam::Vec4::ZERO; 3]; 8],
    };
}

/// [`noise3f_x4`] taking the corners' gradients from `cells` when the four points lie in
/// the cells it holds (each lane the same one as before), else hashing and storing them:
/// the same bits as [`noise3f_x4`]. Points that move little between calls (a ray's steps,
/// a normal's central differences) skip the 56 table reads of the hashes and the
/// gradients' transposes.
#[must_use]
#[inline]
pub fn noise3f_x4_cached(
    x: glam::Vec4,
    y: glam::Vec4,
    z: glam::Vec4,
    cells: &mut CellsX4,
) -> glam::Vec4 {
    let (fx, fy, fz) = (x.floor(), y.floor(), z.floor());
    let [cx, cy, cz] = cells.floors;
    // NaN (no cells yet, or a NaN point) is never equal: hashed afresh.
    if !(fx.cmpeq(cx) & fy.cmpeq(cy) & fz.cmpeq(cz)).all() {
        corner_gradients_x4(fx, fy, fz, &mut cells.gradients);
        cells.floors = [fx, fy, fz];
    }
    blend_x4(x - fx, y - fy, z - fz, &cells.gradients)
}

/// The gradients of the eight corners of the cells whose lowest corners are the four
/// lanes' `(fx, fy, fz)` (whole numbers), into `out`: per corner, in [`noise3f`]'s order
/// (aa, ba, ab, bb, then +1), the lanes' x, y and z components in lanes.
#[inline(always)]
fn corner_gradients_x4(
    fx: glam::Vec4,
    fy: glam::Vec4,
    fz: glam::Vec4,
    out: &mut [[glam::Vec4; 3]; 8],
) {
    use glam::Vec4;
    // The lattice cells' low bytes, as `noise3f`'s saturating `as i32`; without its checks
    // when every lane is in `i32`'s range (NaN is not).
    let lim = Vec4::splat(2_147_483_648.0);
    let in_range = (fx.abs().cmplt(lim) & fy.abs().cmplt(lim) & fz.abs().cmplt(lim)).all();
    let cells = |f: Vec4| -> [usize; 4] {
        if in_range {
            // SAFETY: |f| < 2³¹ and f is whole (checked above): it is an `i32`.
            f.to_array()
                .map(|v| (unsafe { v.to_int_unchecked::<i32>() } & 255) as usize)
        } else {
            f.to_array().map(|v| (v as i32 & 255) as usize)
        }
    };
    let (xs, ys, zs) = (cells(fx), cells(fy), cells(fz));
    // Per lane: the eight corners' hashes, in `noise3f`'s order (aa, ba, ab, bb, then +1).
    let mut hashes = [[0usize; 4]; 8];
    for l in 0..4 {
        let (xi, yi, zi) = (xs[l], ys[l], zs[l]);
        // SAFETY: as `noise3f`'s (cells masked to 255): every index is below 512.
        let a = p(xi) + yi;
        let (aa, ab) = unsafe { (p2(a) + zi, p2(a + 1) + zi) };
        let b = unsafe { p2(xi + 1) } + yi;
        let (ba, bb) = unsafe { (p2(b) + zi, p2(b + 1) + zi) };
        for (k, h) in [aa, ba, ab, bb, aa + 1, ba + 1, ab + 1, bb + 1]
            .into_iter()
            .enumerate()
        {
            hashes[k][l] = h;
        }
    }
    for (o, h) in out.iter_mut().zip(&hashes) {
        // The four lanes' gradients as a matrix's columns; its transpose's columns are
        // their x, y and z components in lanes (the same table values).
        // SAFETY: a corner's hash is below 512 (above).
        let row = |l: usize| Vec4::from_array(*unsafe { gradient_of_hash(h[l]) });
        let c = glam::Mat4::from_cols(row(0), row(1), row(2), row(3)).transpose();
        *o = [c.x_axis, c.y_axis, c.z_axis];
    }
}

/// The noise of four lanes at `(x, y, z)` inside their cells (the fractions) whose corners'
/// gradients are `g` ([`corner_gradients_x4`]): `noise3f`'s fades, products and blends.
#[inline(always)]
fn blend_x4(x: glam::Vec4, y: glam::Vec4, z: glam::Vec4, g: &[[glam::Vec4; 3]; 8]) -> glam::Vec4 {
    use glam::Vec4;
    let fadef = |t: Vec4| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v, w) = (fadef(x), fadef(y), fadef(z));
    let g = |k: usize, x: Vec4, y: Vec4, z: Vec4| {
        let [gx, gy, gz] = g[k];
        gx * x + gy * y + gz * z
    };
    let lerp = |t: Vec4, a: Vec4, b: Vec4| a + t * (b - a);
    let (x1, y1, z1) = (x - 1.0, y - 1.0, z - 1.0);
    lerp(
        w,
        lerp(
            v,
            lerp(u, g(0, x, y, z), g(1, x1, y, z)),
            lerp(u, g(2, x, y1, z), g(3, x1, y1, z)),
        ),
        lerp(
            v,
            lerp(u, g(4, x, y, z1), g(5, x1, y, z1)),
            lerp(u, g(6, x, y1, z1), g(7, x1, y1, z1)),
        ),
    )
}

/// A bound on `|noise3f|` (and `|noise3|`): improved noise stays within about ±1.04; callers
/// that skip work where noise cannot reach a level use this, with room to spare.
pub const NOISE_BOUND: f32 = 1.1;

/// [`fbm`] (`absolute` false) or [`turbulence`] (true) in `f32` over [`noise3f`], with the
/// same fractional last octave.
#[must_use]
#[inline]
pub fn octaves3f(p: glam::Vec3, octaves: f32, lacunarity: f32, gain: f32, absolute: bool) -> f32 {
    let octaves = octaves.clamp(0.0, 32.0);
    let whole = octaves.floor() as u32;
    let (mut sum, mut amp, mut freq) = (0.0f32, 1.0f32, 1.0f32);
    for i in 0..=whole {
        let weight = if i < whole {
            amp
        } else {
            (octaves - whole as f32) * amp
        };
        if weight == 0.0 {
            break;
        }
        let q = p * freq;
        let n = noise3f(q.x, q.y, q.z);
        sum += weight * if absolute { n.abs() } else { n };
        amp *= gain;
        freq *= lacunarity;
    }
    sum
}

/// The number of octaves an fBm of base frequency 1 can take before its finest one is
/// smaller than the footprint `width` (in the same units as the noise domain): octaves at
/// or above the Nyquist limit only alias, so they are left out (the last fades out over one
/// octave). `lacunarity` > 1.
#[must_use]
pub fn octaves_for_width(width: f64, max_octaves: f64, lacunarity: f64) -> f64 {
    if !(width > 0.0) {
        return max_octaves;
    }
    // Octave i has features of size 1/lacunarityⁱ; keep those at least two footprints wide.
    let n = (-(2.0 * width).log2() / lacunarity.log2()).max(0.0);
    n.min(max_octaves)
}

#[cfg(test)]
mod tests;
