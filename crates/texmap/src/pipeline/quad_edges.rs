//! A quad's four pixel-centre edge tests at once, for one sample a pixel.
//!
//! The rasterizer's edge functions are exact `i64` (`setup.rs`): a pixel is inside when all
//! three are `≥ 0`, that is when the bitwise or of the three has its sign bit clear. Here the
//! four pixels' values of each edge sit in two SSE2 registers (pixels 0, 1 and 2, 3), stepped
//! by one add per register, and the covered pixels come from the or's sign bits: about a
//! dozen instructions a quad where the scalar loop took some forty (callgrind, the
//! 199,200-triangle sphere, whose small triangles make most quads edge quads). The values and
//! the mask are the scalar test's, bit for bit; other targets run that test.

/// The three edge functions at a quad's four pixel centres: pixel `j` at
/// `(x + (j & 1), y + (j >> 1))`.
#[derive(Clone, Copy)]
pub(super) struct QuadEdges {
    #[cfg(target_arch = "x86_64")]
    lanes: [[std::arch::x86_64::__m128i; 2]; 3],
    #[cfg(not(target_arch = "x86_64"))]
    lanes: [[i64; 4]; 3],
}

impl QuadEdges {
    /// The values at the quad whose top-left pixel has edge values `e`, for edges changing by
    /// `dx` a pixel to the right and `dy` a pixel down.
    #[inline(always)]
    pub(super) fn new(e: [i64; 3], dx: [i64; 3], dy: [i64; 3]) -> Self {
        let px = |k: usize| [e[k], e[k] + dx[k], e[k] + dy[k], e[k] + dx[k] + dy[k]];
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::_mm_set_epi64x;
            let pair = |p: [i64; 4]| {
                // SAFETY: SSE2 is part of x86_64. Lane 0 (the low one) is the first pixel.
                unsafe { [_mm_set_epi64x(p[1], p[0]), _mm_set_epi64x(p[3], p[2])] }
            };
            QuadEdges {
                lanes: [pair(px(0)), pair(px(1)), pair(px(2))],
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        QuadEdges {
            lanes: [px(0), px(1), px(2)],
        }
    }

    /// Moves the quad: edge `k` changes by `d[k]` at every pixel.
    #[inline(always)]
    pub(super) fn step(&mut self, d: &QuadStep) {
        #[cfg(target_arch = "x86_64")]
        for (l, d) in self.lanes.iter_mut().zip(&d.0) {
            use std::arch::x86_64::_mm_add_epi64;
            // SAFETY: SSE2 is part of x86_64.
            unsafe {
                l[0] = _mm_add_epi64(l[0], *d);
                l[1] = _mm_add_epi64(l[1], *d);
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        for (l, d) in self.lanes.iter_mut().zip(d.0) {
            for x in l.iter_mut() {
                *x += d;
            }
        }
    }

    /// Bit `j` set: pixel `j`'s centre is inside all three edges.
    #[inline(always)]
    pub(super) fn covered(&self) -> u8 {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_castsi128_pd, _mm_movemask_pd, _mm_or_si128};
            let [a, b, c] = self.lanes;
            // SAFETY: SSE2 is part of x86_64.
            let outside = unsafe {
                let top = _mm_or_si128(_mm_or_si128(a[0], b[0]), c[0]);
                let bottom = _mm_or_si128(_mm_or_si128(a[1], b[1]), c[1]);
                _mm_movemask_pd(_mm_castsi128_pd(top))
                    | _mm_movemask_pd(_mm_castsi128_pd(bottom)) << 2
            };
            !(outside as u8) & 0b1111
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let [a, b, c] = self.lanes;
            (0..4).fold(0u8, |m, j| m | u8::from((a[j] | b[j] | c[j]) >= 0) << j)
        }
    }
}

/// A step of [`QuadEdges`]: each edge's change, ready to add.
#[derive(Clone, Copy)]
pub(super) struct QuadStep(
    #[cfg(target_arch = "x86_64")] [std::arch::x86_64::__m128i; 3],
    #[cfg(not(target_arch = "x86_64"))] [i64; 3],
);

impl QuadStep {
    /// Edge `k` changing by `d[k]`.
    #[inline(always)]
    pub(super) fn new(d: [i64; 3]) -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::_mm_set1_epi64x;
            // SAFETY: SSE2 is part of x86_64.
            QuadStep(d.map(|d| unsafe { _mm_set1_epi64x(d) }))
        }
        #[cfg(not(target_arch = "x86_64"))]
        QuadStep(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scalar rule: pixel j inside when all three values at it are ≥ 0.
    fn scalar(e: [i64; 3], dx: [i64; 3], dy: [i64; 3]) -> u8 {
        (0..4).fold(0u8, |m, j| {
            let (ox, oy) = ((j & 1) as i64, (j >> 1) as i64);
            let v: [i64; 3] = std::array::from_fn(|k| e[k] + ox * dx[k] + oy * dy[k]);
            m | u8::from(v.iter().all(|&x| x >= 0)) << j
        })
    }

    #[test]
    fn matches_the_scalar_test_while_stepping() {
        // A small linear congruential generator: edge values around zero and far from it,
        // steps of both signs (the guard band keeps |E| below 2^53).
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = |range: i64| {
            s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            ((s >> 11) as i64 % (2 * range + 1)) - range
        };
        for _ in 0..2000 {
            let range = [4, 300, 1 << 40][(next(1) + 1) as usize];
            let e: [i64; 3] = std::array::from_fn(|_| next(range));
            let dx: [i64; 3] = std::array::from_fn(|_| next(range / 2 + 1));
            let dy: [i64; 3] = std::array::from_fn(|_| next(range / 2 + 1));
            let mut q = QuadEdges::new(e, dx, dy);
            let step = QuadStep::new(dx.map(|d| 2 * d));
            let mut cur = e;
            for _ in 0..5 {
                assert_eq!(q.covered(), scalar(cur, dx, dy), "{cur:?} {dx:?} {dy:?}");
                q.step(&step);
                for k in 0..3 {
                    cur[k] += 2 * dx[k];
                }
            }
        }
        // Zero is inside, −1 outside.
        assert_eq!(QuadEdges::new([0; 3], [0; 3], [0; 3]).covered(), 0b1111);
        assert_eq!(QuadEdges::new([0, 0, -1], [0; 3], [0; 3]).covered(), 0);
    }
}
