//! Batches of quads read together: [`sample_quads_lanes`] (one texture), its two stages
//! ([`StagedQuads`]: levels and far texels requested first, reads after other work), and
//! [`sample_quads_lanes_shared`] (a material's maps at one set of coordinates). The quads'
//! levels are chosen first, then read, so independent chains of dependent operations overlap.

use glam::{Vec2, Vec4};

use super::super::{Filter, LodRule, MagFilter, MinFilter, MipChoice, Sampler, Texture2D};
use super::{anisotropic, ewa_probes, fixed16, gl_read, sample_quad_lanes};

/// One quad's coordinates for [`sample_quads_lanes`]: pixel `j`'s `(u, v)` in lane `j`, and the
/// derivatives the quad shares.
#[derive(Clone, Copy, Debug, Default)]
pub struct QuadCoords {
    pub u: Vec4,
    pub v: Vec4,
    pub duv_dx: Vec2,
    pub duv_dy: Vec2,
}

/// [`sample_quad_lanes`] for several quads (`out[i]` for `coords[i]` and `masks[i]`), in
/// stages: every quad's level of detail first, then the reads, so the quads' independent
/// chains of dependent operations overlap instead of running one after another.
///
/// # Panics
/// If `masks` or `out` is shorter than `coords`.
#[inline]
pub fn sample_quads_lanes(
    texture: &Texture2D,
    sampler: &Sampler,
    coords: &[QuadCoords],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) {
    if let Filter::Gl { mag, min } = sampler.filter {
        if let Some(choice) = MipChoice::fixed(texture.levels().len(), mag, min) {
            if level_quads_at(texture, sampler, choice, min, coords, masks, out) {
                return;
            }
        }
    }
    sample_quads_at(texture, sampler, coords, masks, out);
}

crate::cpu::dispatch! {
    /// [`sample_quads_lanes`] at the CPU's level ([`crate::cpu`]).
    fn sample_quads_at(
        texture: &Texture2D,
        sampler: &Sampler,
        coords: &[QuadCoords],
        masks: &[u8],
        out: &mut [[Vec4; 4]],
    ) => sample_quads_in, sample_quads_v3
}

/// [`sample_quads_lanes`]'s body, compiled twice.
#[inline(always)]
fn sample_quads_in(
    texture: &Texture2D,
    sampler: &Sampler,
    coords: &[QuadCoords],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) {
    assert!(masks.len() >= coords.len() && out.len() >= coords.len());
    let Filter::Gl { mag, min } = sampler.filter else {
        // Anisotropic and `ewa` quads on the storage the fixed-point probes serve: planned
        // four at a time, then read (`staged_plans`, inlined here so that it is compiled at
        // this copy's level too); other textures and filters read as `sample_quad_lanes`
        // reads.
        let served = fixed16::serves(texture, sampler);
        if let (Filter::Anisotropic { max_aniso, lod }, true) = (sampler.filter, served) {
            let aniso = anisotropic::Aniso { max_aniso, lod };
            let planner = AnisotropicPlans(aniso, anisotropic::probe_sets());
            staged_plans(texture, sampler, &planner, (coords, masks, out));
            return;
        }
        if let (Filter::Ewa { max_eccentricity }, true) = (sampler.filter, served) {
            let planner = EwaPlans(max_eccentricity, ewa_probes::probe_sets());
            staged_plans(texture, sampler, &planner, (coords, masks, out));
            return;
        }
        for ((c, &m), o) in coords.iter().zip(masks).zip(out.iter_mut()) {
            *o = sample_quad_lanes(texture, sampler, (c.u, c.v), c.duv_dx, c.duv_dy, m);
        }
        return;
    };
    // Trilinear on the fixed-point storage: each quad's level and weights straight from its
    // λ (`fixed16/trilinear.rs`), no level choices made (where that path does not run, the
    // chunk is read as any other).
    let trilinear = (mag, min) == (MagFilter::Linear, MinFilter::LinearMipmapLinear)
        && fixed16::serves(texture, sampler);
    for ((coords, masks), out) in coords
        .chunks(CHUNK)
        .zip(masks.chunks(CHUNK))
        .zip(out.chunks_mut(CHUNK))
    {
        if trilinear {
            let lods = adjusted_lods::<CHUNK>(texture, sampler, coords);
            if fixed16::read_trilinear(texture, sampler, coords, &lods, masks, out) {
                continue;
            }
        }
        // A rasterizer's batch (most calls) chooses into a smaller array.
        if coords.len() <= QUADS_STAGED {
            let choices = gl_begin::<QUADS_STAGED>(texture, sampler, coords, masks, mag, min);
            gl_end(texture, sampler, coords, masks, &choices, out);
        } else {
            let choices = gl_begin::<CHUNK>(texture, sampler, coords, masks, mag, min);
            gl_end(texture, sampler, coords, masks, &choices, out);
        }
    }
}

/// A filter whose quads' reads follow a plan made from their derivatives, for
/// [`staged_plans`]. (Methods, always inlined, rather than closures: a closure is compiled
/// on its own, at the baseline level, even when the batch that calls it runs at x86-64-v3.)
trait Plans {
    type Plan: Copy;
    /// A placeholder, for arrays of plans.
    const NONE: Self::Plan;
    /// The plans of up to four quads (plan `k` for `coords[k]`).
    fn plan4(&self, tex: &Texture2D, s: &Sampler, coords: &[QuadCoords]) -> [Self::Plan; 4];
    /// The first level a quad's probes read, for its prefetch (`None`: nothing asked for).
    fn first_level(&self, plan: &Self::Plan) -> Option<usize>;
    /// Quad `c`'s reads as `plan` says, by the batch's `reader`.
    fn read(
        &self,
        reader: &mut fixed16::ProbeReader,
        tex: &Texture2D,
        s: &Sampler,
        c: &QuadCoords,
        plan: &Self::Plan,
        mask: u8,
    ) -> [Vec4; 4];
}

/// Anisotropic filtering's plans, as its filter asks, and its probes.
struct AnisotropicPlans(anisotropic::Aniso, &'static fixed16::ProbeSets);

impl Plans for AnisotropicPlans {
    type Plan = anisotropic::QuadPlan;
    const NONE: Self::Plan = anisotropic::QuadPlan::NONE;
    #[inline(always)]
    fn plan4(&self, tex: &Texture2D, s: &Sampler, coords: &[QuadCoords]) -> [Self::Plan; 4] {
        anisotropic::quad_plans4(tex, s, coords, self.0)
    }
    #[inline(always)]
    fn first_level(&self, plan: &Self::Plan) -> Option<usize> {
        Some(plan.choice().level)
    }
    #[inline(always)]
    fn read(
        &self,
        reader: &mut fixed16::ProbeReader,
        _: &Texture2D,
        s: &Sampler,
        c: &QuadCoords,
        plan: &Self::Plan,
        mask: u8,
    ) -> [Vec4; 4] {
        anisotropic::read_quad_with(reader, s, (c.u, c.v), plan, self.1, mask)
    }
}

/// `ewa`'s plans, at most this eccentricity, and its probes.
struct EwaPlans(f32, &'static fixed16::ProbeSets);

impl Plans for EwaPlans {
    type Plan = ewa_probes::Plan;
    const NONE: Self::Plan = ewa_probes::Plan::Bilinear;
    #[inline(always)]
    fn plan4(&self, tex: &Texture2D, s: &Sampler, coords: &[QuadCoords]) -> [Self::Plan; 4] {
        ewa_probes::quad_plans4(tex, s, coords, self.0)
    }
    #[inline(always)]
    fn first_level(&self, plan: &Self::Plan) -> Option<usize> {
        match plan {
            ewa_probes::Plan::Probes { choice, .. } => Some(choice.level),
            _ => None,
        }
    }
    #[inline(always)]
    fn read(
        &self,
        reader: &mut fixed16::ProbeReader,
        tex: &Texture2D,
        s: &Sampler,
        c: &QuadCoords,
        plan: &Self::Plan,
        mask: u8,
    ) -> [Vec4; 4] {
        let duv = (c.duv_dx, c.duv_dy);
        ewa_probes::read_quad_with(reader, tex, s, (c.u, c.v), duv, plan, self.1, mask, self.0)
    }
}

/// Quads whose reads follow a plan made from their derivatives (anisotropic filtering,
/// `ewa`): each chunk's plans first, four quads at a time, then the texels of each quad's
/// first level asked for where that level is large, then each quad read by one
/// [`fixed16::ProbeReader`] for the whole batch (the storage checked once, each level
/// looked up once while consecutive quads read it). Every quad's plan waits on square
/// roots, divisions and a logarithm; made before any read, they no longer wait one after
/// another between reads. Where the fixed-point path does not serve the texture, each quad
/// is read as [`sample_quad_lanes`] reads it.
#[inline(always)]
fn staged_plans<P: Plans>(
    texture: &Texture2D,
    sampler: &Sampler,
    planner: &P,
    (coords, masks, out): (&[QuadCoords], &[u8], &mut [[Vec4; 4]]),
) {
    let Some(mut reader) = fixed16::ProbeReader::new(texture, sampler) else {
        for ((c, &m), o) in coords.iter().zip(masks).zip(out.iter_mut()) {
            *o = sample_quad_lanes(texture, sampler, (c.u, c.v), c.duv_dx, c.duv_dy, m);
        }
        return;
    };
    let mut plans = [P::NONE; CHUNK];
    for ((coords, masks), out) in coords
        .chunks(CHUNK)
        .zip(masks.chunks(CHUNK))
        .zip(out.chunks_mut(CHUNK))
    {
        for (plans, coords) in plans.chunks_mut(4).zip(coords.chunks(4)) {
            plans.copy_from_slice(&planner.plan4(texture, sampler, coords)[..plans.len()]);
        }
        // Each quad's texels on its first level asked for before the chunk's reads, where
        // that level is larger than an L1 cache (`ProbeReader::prefetch`).
        for ((c, &m), plan) in coords.iter().zip(masks).zip(&plans) {
            if let Some(level) = planner.first_level(plan) {
                reader.prefetch(sampler, level, (c.u, c.v), m);
            }
        }
        for (((c, &m), o), plan) in coords.iter().zip(masks).zip(out).zip(&plans) {
            *o = planner.read(&mut reader, texture, sampler, c, plan, m);
        }
    }
}

crate::cpu::dispatch! {
    /// [`level_quads`] at the CPU's level ([`crate::cpu`]): its own function, so that the
    /// general batch's code stays as it was compiled without it.
    fn level_quads_at(
        texture: &Texture2D,
        sampler: &Sampler,
        choice: MipChoice,
        min: MinFilter,
        coords: &[QuadCoords],
        masks: &[u8],
        out: &mut [[Vec4; 4]],
    ) -> bool => level_quads, level_quads_v3
}

/// [`sample_quads_lanes`] when every quad reads one level (`choice`, fixed by the filter
/// pair `min` and its magnification): each quad's texel indices computed once, for its
/// prefetch (bilinear taps, as [`gl_begin`] asks for them) and its read. `false`, and nothing read, when the
/// fixed-point path does not serve this texture or sampler.
#[inline(always)]
fn level_quads(
    texture: &Texture2D,
    sampler: &Sampler,
    choice: MipChoice,
    min: MinFilter,
    coords: &[QuadCoords],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) -> bool {
    for ((coords, masks), out) in coords
        .chunks(CHUNK)
        .zip(masks.chunks(CHUNK))
        .zip(out.chunks_mut(CHUNK))
    {
        // Bilinear taps minified on level 0 are asked for first; nearest ones are not: a
        // nearest quad's four loads are issued close together anyway, and the prefetch's
        // level of detail and addresses cost more than it saved (DESIGN.md's log).
        let far = if min == MinFilter::Linear {
            far_quads(texture, sampler, coords)
        } else {
            0
        };
        // The first chunk answers for all: the texture and sampler decide.
        if !fixed16::read_level_quads(texture, sampler, choice, coords, masks, far, out) {
            return false;
        }
    }
    true
}

/// The first stage of an OpenGL-filtered batch (at most `N` quads): the level
/// choices, and, minified on level 0, the far quads' texels requested from memory
/// (fixed16/prefetch.rs).
#[inline(always)]
fn gl_begin<const N: usize>(
    texture: &Texture2D,
    sampler: &Sampler,
    coords: &[QuadCoords],
    masks: &[u8],
    mag: MagFilter,
    min: MinFilter,
) -> [MipChoice; N] {
    let (choices, far) = gl_choices::<N>(texture, sampler, coords, mag, min);
    if far != 0 && matches!(min, MinFilter::Nearest | MinFilter::Linear) {
        fixed16::prefetch_quads(texture, sampler, coords, &choices, masks, far);
    }
    choices
}

/// The second stage: the reads on the levels [`gl_begin`] chose.
#[inline(always)]
fn gl_end<const N: usize>(
    texture: &Texture2D,
    sampler: &Sampler,
    coords: &[QuadCoords],
    masks: &[u8],
    choices: &[MipChoice; N],
    out: &mut [[Vec4; 4]],
) {
    if !fixed16::read_quads(texture, sampler, coords, choices, masks, out) {
        for (((c, &m), o), &choice) in coords.iter().zip(masks).zip(out.iter_mut()).zip(choices) {
            *o = gl_read(texture, sampler, (c.u, c.v), choice, m);
        }
    }
}

/// [`sample_quads_lanes`] of a batch of at most [`QUADS_STAGED`] quads in two calls, so that
/// other work can run between them while the texels come from memory: [`StagedQuads::begin`]
/// chooses the levels and requests the far texels, [`StagedQuads::end`] reads (the same
/// values).
#[derive(Clone, Copy)]
pub struct StagedQuads {
    /// The level choices, for OpenGL filters.
    choices: Option<[MipChoice; QUADS_STAGED]>,
    /// The one level every quad reads, when the filter pair fixes it ([`MipChoice::fixed`]).
    fixed: Option<MipChoice>,
}

/// The most quads one [`StagedQuads`] holds: the rasterizer's batch (a smaller value to copy
/// than the 16 a longer batch chooses at a time).
pub const QUADS_STAGED: usize = 16;

impl StagedQuads {
    /// The first stage for `coords` and `masks` (at most [`QUADS_STAGED`] quads).
    ///
    /// # Panics
    /// If `masks` is shorter than `coords`, or `coords` longer than [`QUADS_STAGED`].
    #[inline]
    #[must_use]
    pub fn begin(
        texture: &Texture2D,
        sampler: &Sampler,
        coords: &[QuadCoords],
        masks: &[u8],
    ) -> Self {
        assert!(masks.len() >= coords.len() && coords.len() <= QUADS_STAGED);
        let (choices, fixed) = match sampler.filter {
            Filter::Gl { mag, min } => (
                Some(gl_begin(texture, sampler, coords, masks, mag, min)),
                MipChoice::fixed(texture.levels().len(), mag, min),
            ),
            _ => (None, None),
        };
        StagedQuads { choices, fixed }
    }

    /// The reads: [`sample_quads_lanes`] of the same arguments [`StagedQuads::begin`] had.
    ///
    /// # Panics
    /// If `masks` or `out` is shorter than `coords`.
    #[inline]
    pub fn end(
        &self,
        texture: &Texture2D,
        sampler: &Sampler,
        coords: &[QuadCoords],
        masks: &[u8],
        out: &mut [[Vec4; 4]],
    ) {
        staged_end(self, texture, sampler, coords, masks, out);
    }
}

crate::cpu::dispatch! {
    /// [`StagedQuads::end`] at the CPU's level ([`crate::cpu`]).
    fn staged_end(
        staged: &StagedQuads,
        texture: &Texture2D,
        sampler: &Sampler,
        coords: &[QuadCoords],
        masks: &[u8],
        out: &mut [[Vec4; 4]],
    ) => staged_end_in, staged_end_v3
}

/// [`StagedQuads::end`]'s body, compiled twice.
#[inline(always)]
fn staged_end_in(
    staged: &StagedQuads,
    texture: &Texture2D,
    sampler: &Sampler,
    coords: &[QuadCoords],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) {
    assert!(masks.len() >= coords.len() && out.len() >= coords.len());
    // One level for every quad: read as `level_quads` reads (the far texels were asked for
    // in the first stage).
    if let Some(choice) = staged.fixed {
        if fixed16::read_level_quads(texture, sampler, choice, coords, masks, 0, out) {
            return;
        }
    }
    match &staged.choices {
        Some(choices) => gl_end(texture, sampler, coords, masks, choices, out),
        None => sample_quads_in(texture, sampler, coords, masks, out),
    }
}

/// The quads [`sample_quads_lanes`] and [`sample_quads_lanes_shared`] choose levels for at a
/// time.
const CHUNK: usize = 16;
const _: () = assert!(CHUNK <= fixed16::LEVEL_QUADS && CHUNK.is_multiple_of(4));
const _: () = assert!(QUADS_STAGED <= fixed16::LEVEL_QUADS);

/// λ above which a quad's neighbouring pixels read texels more than two apart, so that on
/// level 0 their texels leave the cache lines already read (fixed16/prefetch.rs).
pub(super) const FAR_LOD: f32 = 1.0;

/// 4^[`FAR_LOD`]: [`far_quads`]' limit for a sampler without a bias (as `exp2` it was a
/// libm call a batch, 0.7 % of the bilinear plane's `perf` samples).
pub(super) const FAR_LIMIT: f32 = 4.0;

/// The OpenGL level choices of up to `N` (≤ 32) quads: λ four quads at a time (one per
/// lane), then each quad's levels; and a mask of the quads whose λ is over [`FAR_LOD`] (bit
/// `i` for quad `i`). (Inlined: as a call it cost the one-map read 2% more.)
#[inline(always)]
fn gl_choices<const N: usize>(
    texture: &Texture2D,
    sampler: &Sampler,
    coords: &[QuadCoords],
    mag: MagFilter,
    min: MinFilter,
) -> ([MipChoice; N], u32) {
    let size = Vec2::new(texture.width() as f32, texture.height() as f32);
    let level_count = texture.levels().len();
    // A filter pair whose choice λ cannot change: λ only for the prefetch's mask, and only
    // where it prefetches.
    let fixed = MipChoice::fixed(level_count, mag, min);
    if fixed.is_some() && !matches!(min, MinFilter::Nearest | MinFilter::Linear) {
        return ([fixed.unwrap_or(MipChoice::LEVEL0); N], 0);
    }
    let mut choices = [MipChoice::LEVEL0; N];
    let mut far = 0;
    for (k, (choices, coords)) in choices.chunks_mut(4).zip(coords.chunks(4)).enumerate() {
        let lod = lod4(size, sampler, coords);
        for (i, choice) in choices.iter_mut().enumerate().take(coords.len()) {
            let lod = sampler.adjust_lod(lod[i]);
            *choice = fixed.unwrap_or_else(|| MipChoice::gl(lod, level_count, mag, min));
            far |= u32::from(lod > FAR_LOD) << (4 * k + i);
        }
    }
    (choices, far)
}

/// λ of up to `N` quads (a multiple of 4, at least `coords.len()`) after the sampler's bias
/// and clamps: [`gl_choices`]' λ, four quads at a time, the same values (lanes past
/// `coords` hold λ of zero derivatives).
#[inline(always)]
fn adjusted_lods<const N: usize>(
    texture: &Texture2D,
    sampler: &Sampler,
    coords: &[QuadCoords],
) -> [f32; N] {
    let size = Vec2::new(texture.width() as f32, texture.height() as f32);
    let mut lods = [0.0; N];
    for (lods, coords) in lods.chunks_mut(4).zip(coords.chunks(4)) {
        let lod = sampler.adjust_lod4(lod4(size, sampler, coords));
        lods.copy_from_slice(&lod.to_array()[..lods.len()]);
    }
    lods
}

/// λ of up to four quads on a texture of `size`, one per lane (before the sampler's bias and
/// clamps; lanes past `coords` read zero derivatives).
#[inline(always)]
fn lod4(size: Vec2, sampler: &Sampler, coords: &[QuadCoords]) -> Vec4 {
    // Each quad's four derivatives in texels as one vector, then the four transposed into
    // lanes (the same products: it was sixteen scalar loads, products and inserts, each
    // load behind its own bounds test).
    let scale = Vec4::new(size.x, size.y, size.x, size.y);
    let quad = |i: usize| {
        coords.get(i).map_or(Vec4::ZERO, |c| {
            Vec4::new(c.duv_dx.x, c.duv_dx.y, c.duv_dy.x, c.duv_dy.y) * scale
        })
    };
    let t = glam::Mat4::from_cols(quad(0), quad(1), quad(2), quad(3)).transpose();
    sampler
        .lod_rule
        .lod4(t.x_axis, t.y_axis, t.z_axis, t.w_axis)
}

/// The mask of `coords`' quads (at most 32; bit `i` for quad `i`) whose λ is over
/// [`FAR_LOD`], after the sampler's bias and clamp: the decision of [`gl_choices`]' second
/// value, without the logarithm (λ = ½·log2 of the squared length the lod rule takes, so
/// λ + bias > FAR_LOD where that length exceeds 4^(FAR_LOD − bias)). Only prefetches follow
/// from it.
#[inline(always)]
pub(super) fn far_quads(texture: &Texture2D, sampler: &Sampler, coords: &[QuadCoords]) -> u32 {
    // The clamp's range decides alone when it lies on one side of FAR_LOD.
    if !(sampler.max_lod > FAR_LOD) {
        return 0;
    }
    if sampler.min_lod > FAR_LOD {
        return u32::MAX >> (32 - coords.len().clamp(1, 32));
    }
    let limit = if sampler.lod_bias == 0.0 {
        FAR_LIMIT
    } else {
        (2.0 * (FAR_LOD - sampler.lod_bias)).exp2()
    };
    let size = Vec2::new(texture.width() as f32, texture.height() as f32);
    let mut far = 0;
    for (i, c) in coords.iter().enumerate().take(32) {
        let (dx, dy) = (c.duv_dx * size, c.duv_dy * size);
        let (lx, ly) = (dx.length_squared(), dy.length_squared());
        let arg = match sampler.lod_rule {
            LodRule::GlMax => lx.max(ly),
            LodRule::RootSumSquares => lx + ly,
        };
        far |= u32::from(arg > limit) << i;
    }
    far
}

/// [`sample_quads_lanes`] of several textures read at the same coordinates through one
/// sampler (a material's maps on one uv set): `put(t, i, texels)` gets texture `t`'s read of
/// quad `i`, the same values as `sample_quads_lanes` of each texture. On textures of one size
/// under an OpenGL filter, each quad's levels are chosen once and the default storage's
/// bilinear taps (addresses and weights) computed once for all of them
/// (`fixed16::read_quad_shared`). [`SharedQuads`] made once for many calls.
///
/// # Panics
/// If `masks` is shorter than `coords`.
pub fn sample_quads_lanes_shared(
    textures: &[&Texture2D],
    sampler: &Sampler,
    coords: &[QuadCoords],
    masks: &[u8],
    put: impl FnMut(usize, usize, [Vec4; 4]),
) {
    SharedQuads::new(textures, sampler).sample(coords, masks, put);
}

/// Textures read together at the same coordinates through one sampler
/// ([`sample_quads_lanes_shared`]), checked and their levels looked up once (a draw makes one
/// for all its quads).
pub struct SharedQuads<'a> {
    textures: Vec<&'a Texture2D>,
    sampler: Sampler,
    /// The OpenGL filter of textures of one size (the shared reads), else `None`.
    gl: Option<(MagFilter, MinFilter)>,
    /// Each group of at most `MAX_SHARED` textures, when the fixed-point reads serve it.
    groups: Vec<Option<fixed16::Shared<'a>>>,
}

impl<'a> SharedQuads<'a> {
    /// `textures` read through `sampler`.
    pub fn new(textures: &[&'a Texture2D], sampler: &Sampler) -> Self {
        let one_size = textures.windows(2).all(|w| {
            (w[0].width(), w[0].height(), w[0].levels().len())
                == (w[1].width(), w[1].height(), w[1].levels().len())
        });
        let gl = match sampler.filter {
            Filter::Gl { mag, min } if one_size && !textures.is_empty() => Some((mag, min)),
            _ => None,
        };
        let groups = match gl {
            Some(_) => textures
                .chunks(fixed16::MAX_SHARED)
                .map(|group| fixed16::Shared::new(group, sampler))
                .collect(),
            None => Vec::new(),
        };
        SharedQuads {
            textures: textures.to_vec(),
            sampler: *sampler,
            gl,
            groups,
        }
    }

    /// The reads of every texture at `coords` (pixels in `masks`): `put(t, i, texels)` for
    /// texture `t` and quad `i`, as [`sample_quads_lanes_shared`].
    ///
    /// # Panics
    /// If `masks` is shorter than `coords`.
    pub fn sample(
        &self,
        coords: &[QuadCoords],
        masks: &[u8],
        mut put: impl FnMut(usize, usize, [Vec4; 4]),
    ) {
        assert!(masks.len() >= coords.len());
        let (textures, sampler) = (&self.textures[..], &self.sampler);
        let (Some((mag, min)), Some(first)) = (self.gl, textures.first()) else {
            let mut out = [[Vec4::ZERO; 4]; CHUNK];
            for (t, texture) in textures.iter().enumerate() {
                let chunks = coords.chunks(CHUNK).zip(masks.chunks(CHUNK));
                for (start, (coords, masks)) in chunks.enumerate() {
                    sample_quads_lanes(texture, sampler, coords, masks, &mut out);
                    for (k, o) in out.iter().take(coords.len()).enumerate() {
                        put(t, start * CHUNK + k, *o);
                    }
                }
            }
            return;
        };
        let mut quad = [[Vec4::ZERO; 4]; fixed16::MAX_SHARED];
        // Two quads' reads (each pair's textures written before they are handed out).
        let mut pair = [[[Vec4::ZERO; 4]; fixed16::MAX_SHARED]; 2];
        for (start, (coords, masks)) in coords.chunks(CHUNK).zip(masks.chunks(CHUNK)).enumerate() {
            let (choices, _) = gl_choices::<CHUNK>(first, sampler, coords, mag, min);
            // The chunk's first texels asked for at once, so their misses overlap.
            #[cfg(target_arch = "x86_64")]
            if let Some(Some(shared)) = self.groups.first() {
                for (c, &choice) in coords.iter().zip(&choices) {
                    fixed16::prefetch_shared(shared, sampler, choice, c.u, c.v);
                }
            }
            let groups = textures.chunks(fixed16::MAX_SHARED).zip(&self.groups);
            for (group, (textures, shared)) in groups.enumerate() {
                let mut k = 0;
                while k < coords.len() {
                    // Two neighbours on the same levels at once, where the CPU has the lanes.
                    if let (Some(shared), true) = (shared.as_ref(), k + 1 < coords.len()) {
                        let both = [choices[k], choices[k + 1]];
                        let (c, m) = ([&coords[k], &coords[k + 1]], [masks[k], masks[k + 1]]);
                        if fixed16::read_pair_shared(shared, sampler, both, c, m, &mut pair) {
                            for (j, quad) in pair.iter().enumerate() {
                                for (t, q) in quad.iter().take(textures.len()).enumerate() {
                                    let t = group * fixed16::MAX_SHARED + t;
                                    put(t, start * CHUNK + k + j, *q);
                                }
                            }
                            k += 2;
                            continue;
                        }
                    }
                    let (c, m, choice) = (&coords[k], masks[k], choices[k]);
                    let quad = &mut quad[..textures.len()];
                    let read = shared.as_ref().is_some_and(|shared| {
                        fixed16::read_quad_shared(shared, sampler, choice, c.u, c.v, m, quad)
                    });
                    if !read {
                        for (q, texture) in quad.iter_mut().zip(textures) {
                            *q = gl_read(texture, sampler, (c.u, c.v), choice, m);
                        }
                    }
                    for (t, q) in quad.iter().enumerate() {
                        put(group * fixed16::MAX_SHARED + t, start * CHUNK + k, *q);
                    }
                    k += 1;
                }
            }
        }
    }
}
