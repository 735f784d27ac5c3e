//! A batch of covered quads: the rasterizer's unit of shading. Up to [`BATCH`] depth-tested
//! quads of one primitive wait here, are shaded in one
//! [`super::FragmentShader::shade_batch`] call and written to the tile's colour and depth.

use glam::Vec4;

use super::bin::TileRect;
use super::framebuffer::over;
use super::interpolate::Planes;
use super::raster::{RasterContext, TileStats};
use super::{Prim, Quad, MAX_VARYINGS};

/// Quads shaded in one call: up to this many covered quads of one primitive, so the
/// shader's per-quad chains (level of detail, texel addresses, loads) of neighbouring quads
/// sit close enough in the instruction stream to overlap. The most quads one
/// [`super::FragmentShader::shade_batch`] call receives, so
/// shaders size their scratch arrays by it.
pub const BATCH: usize = 16;

/// A quad waiting in a [`Batch`]: its tile position, the samples that passed the depth test
/// per pixel (with one sample a pixel unset: the quad's mask says it), and the pixels'
/// depths.
#[derive(Clone, Copy, Default)]
pub(super) struct Pending {
    pub(super) lx: usize,
    pub(super) ly: usize,
    pub(super) pass: [u32; 4],
    pub(super) zp: [f32; 4],
}

/// Covered quads of one primitive, depth-tested, waiting to be shaded and written. They are
/// disjoint, so testing all before writing any gives what quad-by-quad would.
pub(super) struct Batch {
    len: usize,
    quads: [Quad; BATCH],
    pending: [Pending; BATCH],
    colors: [[Vec4; 4]; BATCH],
    kept: [u8; BATCH],
}

impl Batch {
    pub(super) fn new() -> Self {
        Batch {
            len: 0,
            quads: std::array::from_fn(|_| Quad {
                x: 0,
                y: 0,
                mask: 0,
                front_facing: true,
                varyings: [Vec4::ZERO; MAX_VARYINGS],
            }),
            pending: [Pending::default(); BATCH],
            colors: [[Vec4::ZERO; 4]; BATCH],
            kept: [0; BATCH],
        }
    }

    /// Queues quad `p` of `prim` (`qmask` its pixels to shade), its varyings from `planes`;
    /// true when the batch is full and must be flushed.
    #[inline(always)]
    pub(super) fn push(
        &mut self,
        prim: &Prim,
        qmask: u8,
        p: Pending,
        rect: TileRect,
        planes: &Planes,
    ) -> bool {
        let n = self.len;
        let quad = &mut self.quads[n];
        quad.x = rect.x0 + p.lx as u32;
        quad.y = rect.y0 + p.ly as u32;
        quad.mask = qmask;
        quad.front_facing = prim.front_facing;
        planes.quad(p.lx as f32, p.ly as f32, &mut quad.varyings);
        self.pending[n] = p;
        self.len += 1;
        self.len == BATCH
    }

    /// Shades the waiting quads of draw `call` and writes their colours and, with
    /// `write_depth` (the draw writes depth and a later primitive of the tile may read it),
    /// their depths.
    pub(super) fn flush<const S: usize>(
        &mut self,
        ctx: &RasterContext,
        call: u32,
        zoff: &[f32; S],
        (color, depth, write_depth): (&mut [Vec4], &mut [f32], bool),
        stats: &mut TileStats,
    ) {
        let n = std::mem::take(&mut self.len);
        if n == 0 {
            return;
        }
        let state = ctx.calls[call as usize].state;
        ctx.shader.shade_batch(
            call,
            &self.quads[..n],
            &mut self.colors[..n],
            &mut self.kept[..n],
        );
        let writes = (color, depth, write_depth, state.blend);
        let shaded = write_batch::<S>(self, n, zoff, writes);
        stats.pixels_shaded += shaded;
        stats.texture_samples += shaded * u64::from(state.texture_reads);
    }
}

crate::cpu::dispatch! {
    /// [`write_batch_in`] at the CPU's level (a function of its own: inlined into the
    /// raster's loop, its registers spilled there).
    fn write_batch<const S: usize>(
        batch: &Batch,
        n: usize,
        zoff: &[f32; S],
        writes: (&mut [Vec4], &mut [f32], bool, bool),
    ) -> u64 => write_batch_in, write_batch_v3
}

/// Writes the first `n` shaded quads of `batch` into the tile's colours (blended with
/// `blend`) and, with `write_depth`, depths; returns the pixels shaded.
#[inline(always)]
fn write_batch_in<const S: usize>(
    batch: &Batch,
    n: usize,
    zoff: &[f32; S],
    (color, depth, write_depth, blend): (&mut [Vec4], &mut [f32], bool, bool),
) -> u64 {
    let tile = super::bin::TILE as usize;
    let mut shaded = 0;
    for ((quad, p), (colors, &kept)) in batch.quads[..n]
        .iter()
        .zip(&batch.pending[..n])
        .zip(batch.colors[..n].iter().zip(&batch.kept[..n]))
    {
        shaded += u64::from(quad.mask.count_ones());
        let kept = kept & quad.mask;
        if S == 1 && kept == 0b1111 && !blend {
            // The common quad: all four pixels written, one sample each, without a test
            // per pixel.
            let i = p.ly * tile + p.lx;
            let c = &mut color[i..i + tile + 2];
            c[..2].copy_from_slice(&colors[..2]);
            c[tile..].copy_from_slice(&colors[2..]);
            if write_depth {
                let d = &mut depth[i..i + tile + 2];
                d[..2].copy_from_slice(&p.zp[..2]);
                d[tile..].copy_from_slice(&p.zp[2..]);
            }
            continue;
        }
        for j in 0..4 {
            if kept & (1 << j) == 0 {
                continue;
            }
            let (x, y) = (p.lx + (j & 1), p.ly + (j >> 1));
            let base = (y * tile + x) * S;
            for s in 0..S {
                if S == 1 || p.pass[j] & (1 << s) != 0 {
                    over(&mut color[base + s], colors[j], blend);
                    if write_depth {
                        depth[base + s] = p.zp[j] + zoff[s];
                    }
                }
            }
        }
    }
    shaded
}
