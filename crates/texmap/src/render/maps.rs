//! Texture reads of the fragment stage: a [`MapRead`] is one texture of a draw resolved once
//! (image, sampler with the overrides, uv transform as one affine map, uv set), read a quad
//! at a time or a batch of quads at a time (staged across the quads by
//! [`sample_quads_lanes`], so their dependent chains overlap); [`super::reads::QuadReads`]
//! holds what a quad read.

use std::mem::MaybeUninit;

use glam::{Mat2, Vec2, Vec4};

use super::varyings::Slot;
use crate::pipeline::{Quad, BATCH};
use crate::shading::TextureSlot;
use crate::texture::{
    quad_mip_choice, sample_quad_lanes, sample_quad_lanes_at, sample_quads_lanes, Filter,
    MinFilter, MipChoice, QuadCoords, Sampler, SharedQuads, StagedQuads, Texture2D, VirtualTexture,
    QUADS_STAGED,
};

/// A batch of quads' reads between [`MapRead::begin`] and [`MapRead::end`].
pub(super) struct MapStaged {
    batch: BatchCoords,
    staged: Option<StagedQuads>,
}

/// At most [`BATCH`] quads' coordinates and masks, as a batch's reads take them
/// ([`MapRead::batch`]): each written once, the array not zeroed first (the zeroing was a
/// 768-byte `memset` a batch, 0.5 % of the trilinear plane's instructions; without it the
/// frame takes 0.99× the time, measured frame by frame in one process).
pub(super) struct BatchCoords {
    coords: [MaybeUninit<QuadCoords>; BATCH],
    masks: [u8; BATCH],
    n: usize,
}

impl BatchCoords {
    /// No quads yet ([`MapRead::batch`] fills it in place: built and returned by value, the
    /// 800-byte batch was copied once more).
    #[inline(always)]
    fn new() -> Self {
        BatchCoords {
            coords: [const { MaybeUninit::uninit() }; BATCH],
            masks: [0; BATCH],
            n: 0,
        }
    }

    /// The quads' coordinates.
    #[inline]
    fn coords(&self) -> &[QuadCoords] {
        // SAFETY: `MapRead::batch` wrote the first `n` (at most `BATCH`), and
        // `MaybeUninit<QuadCoords>` has `QuadCoords`' layout.
        unsafe { std::slice::from_raw_parts(self.coords.as_ptr().cast(), self.n) }
    }

    /// The quads' masks.
    #[inline]
    fn masks(&self) -> &[u8] {
        &self.masks[..self.n]
    }
}

crate::cpu::dispatch! {
    /// [`batch_coords_in`] at the CPU's level (called once a batch by [`MapRead::batch`],
    /// which the batch's own x86-64-v3 copy does not inline: at the baseline level the loop
    /// was 36 instructions a quad).
    fn batch_coords(read: &MapRead, quads: &[Quad], b: &mut BatchCoords) => batch_coords_in,
        batch_coords_v3
}

/// The coordinates and masks of `quads` read by `read`, written to `b`.
///
/// # Panics
/// If `quads` is longer than [`BATCH`].
#[inline(always)]
fn batch_coords_in(read: &MapRead, quads: &[Quad], b: &mut BatchCoords) {
    assert!(quads.len() <= BATCH);
    for ((c, m), q) in b.coords.iter_mut().zip(&mut b.masks).zip(quads) {
        c.write(read.coords(q));
        *m = q.mask;
    }
    b.n = quads.len();
}

// A batch of the rasterizer fits one staged read.
const _: () = assert!(BATCH <= QUADS_STAGED);

/// A texture the fragment stage reads: image, sampler (command-line overrides applied), the
/// slot's uv transform and scales folded into one affine map (computed once per draw, not per
/// quad), its uv set, and the map's scale (normal scale, occlusion strength).
#[derive(Clone, Copy)]
pub(super) struct MapRead<'a> {
    pub tex: &'a Texture2D,
    /// A virtual texture read through its page table instead of `tex`.
    pub virt: Option<&'a VirtualTexture>,
    pub sampler: Sampler,
    /// `uv' = linear·uv + offset` = `transform.apply(uv) · uv_scale · scene scale`.
    pub linear: Mat2,
    pub offset: Vec2,
    /// The raw uv set read.
    pub uv: Slot<2>,
    pub scale: f32,
}

impl<'a> MapRead<'a> {
    /// `slot` read through `sampler` from uv set `uv`, its coordinates also multiplied by
    /// `uv_scale`; `scale` is the map's own (normal scale, strength, bump height).
    pub fn new(
        slot: &'a TextureSlot,
        sampler: Sampler,
        uv: Slot<2>,
        uv_scale: f32,
        scale: f32,
    ) -> Self {
        let s = slot.uv_scale * uv_scale;
        MapRead {
            tex: &slot.texture,
            virt: slot.virtual_texture.as_deref(),
            sampler,
            linear: slot.transform.matrix() * s,
            offset: slot.transform.offset * s,
            uv,
            scale,
        }
    }

    /// The quad's four reads. The transform is affine, so applying it per pixel to the raw,
    /// interpolated uv (and its linear part to the derivatives) equals applying it per vertex.
    pub fn quad(&self, quad: &Quad) -> [Vec4; 4] {
        self.read_lanes(&self.coords(quad), quad.mask)
    }

    /// One quad's reads at `c`, from the image or through the virtual texture's pages.
    #[inline]
    fn read_lanes(&self, c: &QuadCoords, mask: u8) -> [Vec4; 4] {
        if let Some(vt) = self.virt {
            let mut out = [[Vec4::ZERO; 4]];
            vt.sample_quads_lanes(&self.sampler, std::slice::from_ref(c), &[mask], &mut out);
            return out[0];
        }
        sample_quad_lanes(
            self.tex,
            &self.sampler,
            (c.u, c.v),
            c.duv_dx,
            c.duv_dy,
            mask,
        )
    }

    /// [`MapRead::quad`] for several quads (`out[i]` for `quads[i]`), the reads staged by
    /// [`sample_quads_lanes`].
    #[inline]
    pub fn quads(&self, quads: &[Quad], out: &mut [[Vec4; 4]]) {
        for (quads, out) in quads.chunks(BATCH).zip(out.chunks_mut(BATCH)) {
            let mut b = BatchCoords::new();
            self.batch(quads, &mut b);
            let (coords, masks) = (b.coords(), b.masks());
            match self.virt {
                Some(vt) => vt.sample_quads_lanes(&self.sampler, coords, masks, out),
                None => sample_quads_lanes(self.tex, &self.sampler, coords, masks, out),
            }
        }
    }

    /// The coordinates and masks of `quads`, written to `b` ([`batch_coords`]).
    ///
    /// # Panics
    /// If `quads` is longer than [`BATCH`].
    #[inline(always)]
    fn batch(&self, quads: &[Quad], b: &mut BatchCoords) {
        batch_coords(self, quads, b);
    }

    /// Whether [`MapRead::begin`] can request texels ahead of the reads: an image (not a
    /// virtual texture) minified on level 0 only (the OpenGL filters `nearest` and `linear`),
    /// where neighbouring pixels' texels lie far apart. Other reads stay in cache and gain
    /// nothing from the two stages.
    #[inline]
    pub fn prefetches(&self) -> bool {
        self.virt.is_none()
            && matches!(
                self.sampler.filter,
                Filter::Gl {
                    min: MinFilter::Nearest | MinFilter::Linear,
                    ..
                }
            )
    }

    /// The first stage of [`MapRead::quads`] of at most [`BATCH`] quads: their coordinates,
    /// levels, and the far texels requested from memory ([`StagedQuads`]); the caller can do
    /// other work (the lighting) before [`MapRead::end`] reads.
    ///
    /// # Panics
    /// If `quads` is longer than [`BATCH`].
    #[inline]
    pub fn begin(&self, quads: &[Quad]) -> MapStaged {
        let mut st = MapStaged {
            batch: BatchCoords::new(),
            staged: None,
        };
        self.batch(quads, &mut st.batch);
        if self.virt.is_none() {
            let b = &st.batch;
            st.staged = Some(StagedQuads::begin(
                self.tex,
                &self.sampler,
                b.coords(),
                b.masks(),
            ));
        }
        st
    }

    /// The reads [`MapRead::begin`] staged: `out[i]` for its `quads[i]`.
    #[inline]
    pub fn end(&self, st: &MapStaged, out: &mut [[Vec4; 4]]) {
        let (coords, masks) = (st.batch.coords(), st.batch.masks());
        match (self.virt, &st.staged) {
            (Some(vt), _) => vt.sample_quads_lanes(&self.sampler, coords, masks, out),
            (None, Some(staged)) => staged.end(self.tex, &self.sampler, coords, masks, out),
            (None, None) => sample_quads_lanes(self.tex, &self.sampler, coords, masks, out),
        }
    }

    /// Whether `other` is read at this map's coordinates through its sampler, from an image
    /// of its size under an OpenGL filter: the two can be read together
    /// ([`MapRead::quads_shared`]).
    pub fn shares_coords(&self, other: &MapRead) -> bool {
        let size = |m: &MapRead| (m.tex.width(), m.tex.height(), m.tex.levels().len());
        matches!(self.sampler.filter, Filter::Gl { .. })
            && self.same_coords(other)
            && size(self) == size(other)
    }

    /// Whether `other` reads what this map reads: the same image, at the same coordinates,
    /// through the same sampler (two maps in one image, as glTF's occlusion and
    /// metallic-roughness maps often are).
    pub fn reads_same(&self, other: &MapRead) -> bool {
        std::ptr::eq(self.tex, other.tex) && self.same_coords(other)
    }

    /// Whether `other` is read at this map's coordinates through its sampler (neither a
    /// virtual texture).
    fn same_coords(&self, other: &MapRead) -> bool {
        self.virt.is_none()
            && other.virt.is_none()
            && self.sampler == other.sampler
            && self.uv == other.uv
            && self.linear == other.linear
            && self.offset == other.offset
    }

    /// [`MapRead::quads`] of the maps whose images `reads` holds (made with this one's
    /// sampler, read at its coordinates: each [`MapRead::shares_coords`] with it): `put(t, i,
    /// texels)` gets image `t`'s reads of `quads[i]` (the same values), the texel addresses
    /// and weights computed once for all.
    pub fn quads_shared(
        &self,
        reads: &SharedQuads,
        quads: &[Quad],
        put: impl FnMut(usize, usize, [Vec4; 4]),
    ) {
        let mut b = BatchCoords::new();
        self.batch(quads, &mut b);
        reads.sample(b.coords(), b.masks(), put);
    }

    /// The quad's transformed uvs (one lane per pixel) and their screen derivatives.
    #[inline]
    fn coords(&self, quad: &Quad) -> QuadCoords {
        let (m, offset) = (self.linear, self.offset);
        let [u, v] = self.uv.lanes(quad);
        let (dx, dy) = (self.uv.ddx(quad), self.uv.ddy(quad));
        QuadCoords {
            u: u * m.x_axis.x + v * m.y_axis.x + offset.x,
            v: u * m.x_axis.y + v * m.y_axis.y + offset.y,
            duv_dx: m * Vec2::from_array(dx),
            duv_dy: m * Vec2::from_array(dy),
        }
    }

    /// The quad's reads at raw (untransformed) uvs `u`, `v` of the pixels in `mask`, each with
    /// the pixel's own footprint (the derivatives of the quad's uv set): parallax mapping's
    /// height reads along the view ray.
    pub fn read_raw(&self, quad: &Quad, u: Vec4, v: Vec4, mask: u8) -> [Vec4; 4] {
        let m = self.linear;
        let c = self.coords(quad);
        let c = QuadCoords {
            u: u * m.x_axis.x + v * m.y_axis.x + self.offset.x,
            v: u * m.x_axis.y + v * m.y_axis.y + self.offset.y,
            ..c
        };
        self.read_lanes(&c, mask)
    }

    /// A reader of this map at raw uvs with `quad`'s footprint, its level chosen once
    /// ([`MapRead::read_raw`] per call chooses it again): the parallax search's reads.
    pub fn raw_reader(&self, quad: &Quad) -> RawReader<'_, 'a> {
        let coords = self.coords(quad);
        let choice = match self.virt {
            Some(_) => None,
            None => quad_mip_choice(self.tex, &self.sampler, coords.duv_dx, coords.duv_dy),
        };
        RawReader {
            map: self,
            coords,
            choice,
        }
    }

    /// A height map's screen derivatives `(∂h/∂x, ∂h/∂y)` per pixel, times `scale`: the red
    /// channel read at uv, one pixel footprint further along x (uv + ∂uv/∂x) and along y,
    /// each with the pixel's own footprint (three quad reads).
    pub fn height_slopes(&self, quad: &Quad) -> [Vec2; 4] {
        let c = self.coords(quad);
        let (dx, dy) = (c.duv_dx, c.duv_dy);
        let read = |u: Vec4, v: Vec4| {
            let c = QuadCoords {
                u,
                v,
                duv_dx: dx,
                duv_dy: dy,
            };
            self.read_lanes(&c, quad.mask)
        };
        let h = read(c.u, c.v);
        let hx = read(c.u + dx.x, c.v + dx.y);
        let hy = read(c.u + dy.x, c.v + dy.y);
        std::array::from_fn(|j| Vec2::new(hx[j].x - h[j].x, hy[j].x - h[j].x) * self.scale)
    }
}

/// The maps among `maps` read together with the first one present that
/// [`MapRead::shares_coords`] with itself: bit `k` for `maps[k]`, none (0) unless two are.
pub(super) fn shared_group(maps: &[Option<&MapRead>]) -> u8 {
    let mut first: Option<&MapRead> = None;
    let mut bits = 0u8;
    for (k, m) in maps.iter().enumerate() {
        let Some(m) = m else {
            continue;
        };
        let joins = match first {
            Some(f) => f.shares_coords(m),
            None => m.shares_coords(m),
        };
        if joins {
            first = first.or(Some(m));
            bits |= 1 << k;
        }
    }
    if bits.count_ones() >= 2 {
        bits
    } else {
        0
    }
}

/// The maps of a draw read together ([`shared_group`]) and the images they read, each image
/// once (two maps in one image take the same values): worked out once a draw.
pub(super) struct SharedReads<'a> {
    /// Bit `k` for the `k`-th candidate read together.
    pub maps: u8,
    /// The candidate whose coordinates and sampler the reads take (the first of them).
    pub first: usize,
    /// The maps (bits over the candidates) each image read feeds…
    pub feeds: [u8; 5],
    /// …and the reads of the distinct images, in the order of their first map, checked and
    /// their levels looked up (through the first map's sampler).
    pub reads: SharedQuads<'a>,
}

impl<'a> SharedReads<'a> {
    /// The shared reads of a draw's `candidates`; `None` unless two or more are read
    /// together.
    pub(super) fn new(candidates: &[Option<&MapRead<'a>>; 5]) -> Option<Self> {
        let maps = shared_group(candidates);
        let first = (0..5).find(|&k| maps & (1 << k) != 0)?;
        let leader = candidates[first]?;
        let (mut images, mut feeds, mut count) = ([leader.tex; 5], [0u8; 5], 0);
        for (k, m) in candidates.iter().enumerate() {
            let Some(m) = m.filter(|_| maps & (1 << k) != 0) else {
                continue;
            };
            let known = images[..count].iter().position(|&t| std::ptr::eq(t, m.tex));
            let t = known.unwrap_or_else(|| {
                images[count] = m.tex;
                count += 1;
                count - 1
            });
            feeds[t] |= 1 << k;
        }
        Some(SharedReads {
            maps,
            first,
            feeds,
            reads: SharedQuads::new(&images[..count], &leader.sampler),
        })
    }
}

/// [`MapRead::raw_reader`]: one quad's footprint and level choice, read at any raw uvs.
pub(super) struct RawReader<'r, 'a> {
    map: &'r MapRead<'a>,
    coords: QuadCoords,
    choice: Option<MipChoice>,
}

impl RawReader<'_, '_> {
    /// The reads at raw (untransformed) uvs `u`, `v` of the pixels in `mask`: as
    /// [`MapRead::read_raw`], the same values.
    #[inline]
    pub fn read(&self, u: Vec4, v: Vec4, mask: u8) -> [Vec4; 4] {
        let m = self.map.linear;
        let c = QuadCoords {
            u: u * m.x_axis.x + v * m.y_axis.x + self.map.offset.x,
            v: u * m.x_axis.y + v * m.y_axis.y + self.map.offset.y,
            ..self.coords
        };
        match self.choice {
            Some(choice) => {
                sample_quad_lanes_at(self.map.tex, &self.map.sampler, (c.u, c.v), choice, mask)
            }
            None => self.map.read_lanes(&c, mask),
        }
    }
}
