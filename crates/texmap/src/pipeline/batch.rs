//! A batch of covered quads: the rasterizer's unit of shading. Up to [`BATCH`] depth-tested
//! quads of one draw wait here, are shaded in one [`super::FragmentShader::shade_batch`]
//! call and written to the tile's colour and depth.
//!
//! With one sample a pixel, a batch holds the quads of consecutive primitives of a draw (a
//! mesh's small triangles cover a few quads each in a tile: batches of one primitive were
//! 11 quads on average for the DamagedHelmet, and each batch runs the shader's whole code
//! once). Its quads cover no pixel twice: a quad whose pixels one waiting quad of an
//! earlier primitive covers flushes the batch before its depth test ([`Batch::waits_on`]),
//! so every depth test and every write sees what quad-by-quad drawing would. (One
//! primitive's quads are disjoint: the waiting quads are marked on a map of the tile only
//! when the next primitive begins, so a batch of one primitive's quads costs no marks.)

use glam::Vec4;

use super::bin::TileRect;
use super::framebuffer::{over, TileColors};
use super::interpolate::Planes;
use super::raster::{RasterContext, TileStats};
use super::{Prim, Quad, MAX_VARYINGS};

/// Quads shaded in one call: up to this many covered quads of one draw, so the
/// shader's per-quad chains (level of detail, texel addresses, loads) of neighbouring quads
/// sit close enough in the instruction stream to overlap. The most quads one
/// [`super::FragmentShader::shade_batch`] call receives, so
/// shaders size their scratch arrays by it.
pub const BATCH: usize = 16;

/// A quad waiting in a [`Batch`]: its tile position, the samples that passed the depth test
/// per pixel (with one sample a pixel unset: the quad's mask says it), and the pixels'
/// depths. (44 bytes: copied into the batch for every quad.)
#[derive(Clone, Copy, Default)]
pub(super) struct Pending {
    pub(super) lx: u32,
    pub(super) ly: u32,
    pub(super) pass: [u32; 4],
    pub(super) zp: [f32; 4],
    /// Whether the depths are written (the draw writes depth, and a later primitive of the
    /// tile may read it).
    pub(super) write_depth: bool,
}

/// Quad positions in a tile.
const TILE_QUADS: usize = (super::bin::TILE as usize / 2) * (super::bin::TILE as usize / 2);

/// Covered quads of one draw, depth-tested, waiting to be shaded and written. No two cover
/// the same pixel, so testing all before writing any gives what quad-by-quad would.
pub(super) struct Batch {
    len: usize,
    /// The draw of the waiting quads.
    call: u32,
    quads: [Quad; BATCH],
    pending: [Pending; BATCH],
    colors: [[Vec4; 4]; BATCH],
    kept: [u8; BATCH],
    /// The pixels (bit `j` pixel `j`) of the first `marked` waiting quads, by quad position
    /// in the tile: those of earlier primitives than the one being walked.
    waiting: [u8; TILE_QUADS],
    marked: usize,
    /// The last draw whose quads the shader did not shade into the tile
    /// ([`FragmentShader::shade_into_tile`], whose answer depends on the draw alone): not
    /// asked again for its batches in this tile.
    not_into_tile: Option<u32>,
}

impl Batch {
    pub(super) fn new() -> Self {
        Batch {
            len: 0,
            call: 0,
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
            waiting: [0; TILE_QUADS],
            marked: 0,
            not_into_tile: None,
        }
    }

    /// The draw of the waiting quads, if any wait.
    #[inline(always)]
    pub(super) fn call(&self) -> Option<u32> {
        (self.len > 0).then_some(self.call)
    }

    /// The quads of a primitive of draw `call` come next (a batch of another draw's quads
    /// has been flushed): the waiting quads, an earlier primitive's, are marked on the
    /// tile's map ([`Batch::waits_on`] reads it).
    #[inline(always)]
    pub(super) fn begin_prim(&mut self, call: u32) {
        debug_assert!(self.len == 0 || self.call == call);
        self.call = call;
        for (p, q) in self.pending[self.marked..self.len]
            .iter()
            .zip(&self.quads[self.marked..self.len])
        {
            self.waiting[quad_index(p.lx as usize, p.ly as usize)] |= q.mask;
        }
        self.marked = self.len;
    }

    /// Whether a waiting quad of an earlier primitive covers one of the pixels `mask` of the
    /// quad at tile position `(lx, ly)` (even): that quad's depth test and write must wait
    /// for a flush.
    #[inline(always)]
    pub(super) fn waits_on(&self, lx: usize, ly: usize, mask: u8) -> bool {
        self.marked > 0 && self.waiting[quad_index(lx, ly)] & mask != 0
    }

    /// Queues quad `p` of `prim` (`qmask` its pixels to shade), its varyings from `planes`;
    /// true when the batch is full and must be flushed. A batch's quads are one draw's
    /// ([`Batch::call`]) and cover no pixel twice ([`Batch::waits_on`]).
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
        debug_assert!(self.call == prim.call);
        debug_assert!(!self.waits_on(p.lx as usize, p.ly as usize, qmask));
        let quad = &mut self.quads[n];
        quad.x = rect.x0 + p.lx;
        quad.y = rect.y0 + p.ly;
        quad.mask = qmask;
        quad.front_facing = prim.front_facing;
        planes.quad(p.lx as f32, p.ly as f32, &mut quad.varyings);
        self.pending[n] = p;
        self.len += 1;
        self.len == BATCH
    }

    /// Shades the waiting quads and writes their colours and, those that write depth
    /// ([`Pending::write_depth`]), their depths (each sample's offset `zoff` from the pixel's
    /// depth, with more than one sample a pixel: those batches hold one primitive's quads).
    pub(super) fn flush<const S: usize>(
        &mut self,
        ctx: &RasterContext,
        zoff: &[f32; S],
        (color, depth): (&mut [Vec4], &mut [f32]),
        stats: &mut TileStats,
    ) {
        let n = std::mem::take(&mut self.len);
        if n == 0 {
            return;
        }
        for p in &self.pending[..std::mem::take(&mut self.marked)] {
            self.waiting[quad_index(p.lx as usize, p.ly as usize)] = 0;
        }
        let call = self.call;
        let state = ctx.calls[call as usize].state;
        if S == 1 && !state.blend && self.not_into_tile != Some(call) {
            if let Some(shaded) = self.shade_into_tile(ctx, n, color, depth) {
                stats.pixels_shaded += shaded;
                stats.texture_samples += shaded * u64::from(state.texture_reads);
                return;
            }
            self.not_into_tile = Some(call);
        }
        ctx.shader.shade_batch(
            call,
            &self.quads[..n],
            &mut self.colors[..n],
            &mut self.kept[..n],
        );
        let writes = (color, depth, state.blend);
        let shaded = write_batch::<S>(self, n, zoff, writes);
        stats.pixels_shaded += shaded;
        stats.texture_samples += shaded * u64::from(state.texture_reads);
    }

    /// One-sample quads (the first `n`) shaded straight into the tile's colours where the
    /// shader does that for their draw ([`FragmentShader::shade_into_tile`]), then the
    /// depths of those that write them; the pixels shaded, or `None`, and nothing written,
    /// where it does not.
    fn shade_into_tile(
        &mut self,
        ctx: &RasterContext,
        n: usize,
        color: &mut [Vec4],
        depth: &mut [f32],
    ) -> Option<u64> {
        let (q, p) = (&self.quads[0], &self.pending[0]);
        let mut tile = TileColors::new(color, q.x - p.lx, q.y - p.ly);
        let quads = &self.quads[..n];
        if !ctx
            .shader
            .shade_into_tile(self.call, quads, &mut self.colors[..n], &mut tile)
        {
            return None;
        }
        let w = super::bin::TILE as usize;
        let mut shaded = 0;
        for (quad, p) in quads.iter().zip(&self.pending[..n]) {
            shaded += u64::from(quad.mask.count_ones());
            if !p.write_depth {
                continue;
            }
            let i = p.ly as usize * w + p.lx as usize;
            let d = &mut depth[i..i + w + 2];
            if quad.mask == 0b1111 {
                d[..2].copy_from_slice(&p.zp[..2]);
                d[w..].copy_from_slice(&p.zp[2..]);
                continue;
            }
            for j in 0..4 {
                if quad.mask & (1 << j) != 0 {
                    d[(j >> 1) * w + (j & 1)] = p.zp[j];
                }
            }
        }
        Some(shaded)
    }
}

crate::cpu::dispatch! {
    /// [`write_batch_in`] at the CPU's level (a function of its own: inlined into the
    /// raster's loop, its registers spilled there).
    fn write_batch<const S: usize>(
        batch: &Batch,
        n: usize,
        zoff: &[f32; S],
        writes: (&mut [Vec4], &mut [f32], bool),
    ) -> u64 => write_batch_in, write_batch_v3
}

/// Writes the first `n` shaded quads of `batch` into the tile's colours (blended with
/// `blend`) and the depths of those that write them; returns the pixels shaded.
#[inline(always)]
fn write_batch_in<const S: usize>(
    batch: &Batch,
    n: usize,
    zoff: &[f32; S],
    (color, depth, blend): (&mut [Vec4], &mut [f32], bool),
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
            let i = p.ly as usize * tile + p.lx as usize;
            let c = &mut color[i..i + tile + 2];
            c[..2].copy_from_slice(&colors[..2]);
            c[tile..].copy_from_slice(&colors[2..]);
            if p.write_depth {
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
            let (x, y) = (p.lx as usize + (j & 1), p.ly as usize + (j >> 1));
            let base = (y * tile + x) * S;
            for s in 0..S {
                if S == 1 || p.pass[j] & (1 << s) != 0 {
                    over(&mut color[base + s], colors[j], blend);
                    if p.write_depth {
                        // One sample: the pixel's depth, as the whole quad's writes it.
                        depth[base + s] = if S == 1 { p.zp[j] } else { p.zp[j] + zoff[s] };
                    }
                }
            }
        }
    }
    shaded
}

/// The index in [`Batch::waiting`] of the quad at tile position `(lx, ly)` (even).
#[inline(always)]
fn quad_index(lx: usize, ly: usize) -> usize {
    (ly / 2) * (super::bin::TILE as usize / 2) + lx / 2
}
