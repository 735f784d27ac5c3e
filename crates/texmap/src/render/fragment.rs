//! The scene's fragment shader: a quad's colour from its draw's [`DrawInfo`].
//!
//! Two paths, chosen per draw:
//! - **plain** (an opaque Phong draw with at most a base-colour texture, no maps, vertex
//!   colour or procedural colour): the four pixels are lit in lanes ([`phong_quad`], every
//!   kind of light) and coloured with no per-pixel branch; a batch's
//!   lighting comes first, then every texture read (staged across the quads), then the
//!   colours;
//! - **general**: the batch's texture reads map by map ([`read_batch`]), then each pixel's
//!   colour, its [`Surface`] built from the maps and lit by [`illuminate`] — or, for a map-free
//!   Phong draw, lit in lanes too (with or without the environment's terms).
//!
//! Both end in [`combine`] (alpha mode, premultiplied output) or its opaque special case.

use glam::{Vec3, Vec4};

use super::behind::SceneBehind;
use super::draw::{DrawInfo, LightingPath};
use super::layers::{apply_outline, fold_layers, surface_colors};
use super::maps::{MapRead, SharedReads};
use super::parallax::{self, SelfShadow};
use super::projectors::Projectors;
use super::reads::{QuadReads, Read};
use super::varyings::Factors;
use crate::pipeline::{FragmentShader, Quad, TileColors, BATCH};
use crate::shading::lanes::{phong_quad, QuadFactors};
use crate::shading::{combine, phong, Lighting, ShadingModel, Surface, Viewer};

pub(super) struct SceneShader<'a> {
    pub draws: &'a [DrawInfo<'a>],
    pub lighting: Lighting<'a>,
    pub viewer: Viewer,
    /// The frame's slide projectors, when it has any (`projectors.rs`).
    pub projectors: Option<&'a Projectors<'a>>,
    /// The opaque scene behind transmitting surfaces, when the frame has any (`behind.rs`).
    pub behind: Option<&'a SceneBehind>,
}

impl FragmentShader for SceneShader<'_> {
    fn shade_batch(&self, draw: u32, quads: &[Quad], out: &mut [[Vec4; 4]], kept: &mut [u8]) {
        shade_batch(self, draw, quads, out, kept);
    }

    fn shade_into_tile(
        &self,
        draw: u32,
        quads: &[Quad],
        scratch: &mut [[Vec4; 4]],
        tile: &mut TileColors,
    ) -> bool {
        // Plain textured draws whose factors do not vary over a side (unlit, or lit once):
        // they keep every pixel of a quad's mask.
        let d = &self.draws[draw as usize];
        let fused = self.is_plain(d) && d.texture.is_some() && constant_factors(d).is_some();
        if fused {
            into_tile(d, quads, scratch, tile);
        }
        fused
    }

    fn shade(&self, draw: u32, quad: &Quad, out: &mut [Vec4; 4]) -> u8 {
        let d = &self.draws[draw as usize];
        if self.is_plain(d) {
            let texels = d.texture.as_ref().map(|t| t.quad(quad));
            plain_colors(d, &self.plain_factors(d, quad), texels.as_ref(), out);
            return quad.mask;
        }
        let mut reads = [QuadReads::default()];
        let moved = &d.parallax_quad(quad, self.viewer);
        read_batch(d, std::slice::from_ref(moved), &mut reads);
        let ss = self.self_shadow(d, quad, moved);
        self.shade_read(d, moved, &reads[0], out, ss.as_ref())
    }
}

/// The batch's colours (`FragmentShader::shade_batch`): plain draws' and the others' in
/// functions of their own ([`batch`]'s two instances), each compiled twice, for the CPU's
/// level ([`crate::cpu`]). (One function held both, and every plain batch allocated and
/// probed the general path's 41 KB of scratch: ten stack pages, 1.6 % of the trilinear
/// plane's `perf` samples.)
fn shade_batch(
    shader: &SceneShader,
    draw: u32,
    quads: &[Quad],
    out: &mut [[Vec4; 4]],
    kept: &mut [u8],
) {
    if shader.is_plain(&shader.draws[draw as usize]) {
        batch::<true>(shader, draw, quads, out, kept);
    } else {
        batch::<false>(shader, draw, quads, out, kept);
    }
}

crate::cpu::dispatch! {
    /// [`batch_in`] at the CPU's level.
    fn batch<const PLAIN: bool>(
        shader: &SceneShader,
        draw: u32,
        quads: &[Quad],
        out: &mut [[Vec4; 4]],
        kept: &mut [u8],
    ) => batch_in, batch_v3
}

/// The colours of a batch of a plain draw ([`SceneShader::plain_batch_at`]) or, not
/// `PLAIN`, of any other ([`SceneShader::general_batch_at`]).
#[inline(always)]
fn batch_in<const PLAIN: bool>(
    shader: &SceneShader,
    draw: u32,
    quads: &[Quad],
    out: &mut [[Vec4; 4]],
    kept: &mut [u8],
) {
    if PLAIN {
        shader.plain_batch_at(draw, quads, out, kept);
    } else {
        shader.general_batch_at(draw, quads, out, kept);
    }
}

impl SceneShader<'_> {
    /// [`batch_in`]'s work for a plain draw, as a method of the shader whose draws it reads.
    #[inline(always)]
    fn plain_batch_at(&self, draw: u32, quads: &[Quad], out: &mut [[Vec4; 4]], kept: &mut [u8]) {
        let d = &self.draws[draw as usize];
        match d.texture.as_ref() {
            // Plain textured quads: the lighting of every quad, then every texture read
            // (staged across quads), then the colours.
            Some(t) => {
                for ((quads, out), kept) in quads
                    .chunks(BATCH)
                    .zip(out.chunks_mut(BATCH))
                    .zip(kept.chunks_mut(BATCH))
                {
                    // Factors the same for every quad of a side need no array of them, and
                    // no lighting waits for staged reads.
                    if let Some(sides) = constant_factors(d) {
                        t.quads(quads, out);
                        texels_colors(d, quads, out, kept, |_, quad| side(d, sides, quad));
                        continue;
                    }
                    // Texels far apart are asked for first (minified on level 0): the
                    // lighting runs while they come.
                    let staged = t.prefetches().then(|| t.begin(quads));
                    let mut factors = [QuadFactors::ZERO; BATCH];
                    for (f, quad) in factors.iter_mut().zip(quads) {
                        *f = self.plain_factors(d, quad);
                    }
                    match &staged {
                        Some(staged) => t.end(staged, out),
                        None => t.quads(quads, out),
                    }
                    texels_colors(d, quads, out, kept, |i, _| &factors[i]);
                }
            }
            None => {
                for ((quad, o), k) in quads.iter().zip(out.iter_mut()).zip(kept.iter_mut()) {
                    *k = self.shade(draw, quad, o);
                }
            }
        }
    }

    /// [`batch_in`]'s work for any other draw.
    #[inline(always)]
    fn general_batch_at(&self, draw: u32, quads: &[Quad], out: &mut [[Vec4; 4]], kept: &mut [u8]) {
        let d = &self.draws[draw as usize];
        // Every texture read of the batch first, map by map, then each quad's colours.
        let mut reads = [QuadReads::default(); BATCH];
        // Parallax self-shadowing asked for only by draws whose map casts it (most
        // have none): one test a batch, not a call a quad.
        let self_shadows = d.parallax.as_ref().is_some_and(|p| p.shadows);
        // Plain metallic-roughness quads (`DrawInfo::mr_quads`, as `shade_read` takes
        // them) two at a time in eight lanes, where the CPU has AVX2.
        let pairs = cfg!(target_arch = "x86_64")
            && crate::cpu::level() == crate::cpu::Level::V3
            && d.mr_quads()
            && !self_shadows;
        // Parallax's moved copies of a batch (only for draws with parallax).
        let mut moved = quads
            .first()
            .filter(|_| d.parallax.is_some())
            .map(|q| [*q; BATCH]);
        for ((quads, out), kept) in quads
            .chunks(BATCH)
            .zip(out.chunks_mut(BATCH))
            .zip(kept.chunks_mut(BATCH))
        {
            // Parallax moves the uvs before any map is read.
            let shifted = parallax::shifted(d, quads, self.viewer, moved.as_mut());
            read_batch(d, shifted, &mut reads[..shifted.len()]);
            if pairs {
                // SAFETY: the CPU has x86-64-v3 (`pairs` asked `cpu::level`).
                #[cfg(target_arch = "x86_64")]
                unsafe {
                    self.shade_mr_batch(d, shifted, &reads, out, kept);
                }
                continue;
            }
            for ((((quad, o), k), r), orig) in shifted
                .iter()
                .zip(out.iter_mut())
                .zip(kept.iter_mut())
                .zip(&reads)
                .zip(quads)
            {
                let ss = self_shadows
                    .then(|| self.self_shadow(d, orig, quad))
                    .flatten();
                *k = self.shade_read(d, quad, r, o, ss.as_ref());
            }
        }
    }
}

impl SceneShader<'_> {
    /// Parallax self-shadowing of a quad lit per pixel (`quad` as rasterized, `moved` its
    /// parallax-moved copy).
    #[inline]
    fn self_shadow(&self, d: &DrawInfo, quad: &Quad, moved: &Quad) -> Option<SelfShadow> {
        (d.path == LightingPath::PerPixel)
            .then(|| d.parallax_self_shadow(quad, moved, self.lighting.lights))
            .flatten()
    }

    /// What the frame's projectors add at surface `s` of a quad of draw `d` (nothing when
    /// the draw takes no projector light).
    #[inline]
    pub(super) fn projected(&self, d: &DrawInfo, quad: &Quad, s: &Surface) -> (Vec3, Vec3) {
        match (self.projectors, d.layout.position) {
            (Some(p), Some(pos)) if d.projectors => {
                p.terms(d, s, pos.ddx3(quad), pos.ddy3(quad), self.viewer)
            }
            _ => (Vec3::ZERO, Vec3::ZERO),
        }
    }

    /// The surface projectors light at pixel `j` of a Gouraud or flat quad: the material's
    /// own parameters at the interpolated position, with the interpolated normal (Gouraud)
    /// or the face's, from the position's derivatives (flat), on the viewer's side for
    /// double-sided back faces.
    fn interpolated_surface(&self, d: &DrawInfo, quad: &Quad, j: usize, back: bool) -> Surface {
        let Some(pos) = d.layout.position else {
            return d.surface;
        };
        let position = pos.pixel3(quad, j);
        let normal = match d.layout.normal {
            Some(n) => {
                let n = n.pixel3(quad, j).normalize_or_zero();
                if back {
                    -n
                } else {
                    n
                }
            }
            None => {
                let n = pos.ddx3(quad).cross(pos.ddy3(quad)).normalize_or_zero();
                let facing = n.dot(self.viewer.towards(position)) >= 0.0;
                // The face's own side, or the viewer's for double-sided materials.
                if facing == (quad.front_facing || back) {
                    n
                } else {
                    -n
                }
            }
        };
        Surface {
            position,
            normal,
            ..d.surface
        }
    }

    /// Whether draw `d` takes the plain path.
    #[inline]
    fn is_plain(&self, d: &DrawInfo) -> bool {
        d.plain
    }

    /// The draw's own surface lit at the quad's four pixels in lanes (map-free Phong);
    /// double-sided back faces are lit from their side.
    #[inline(always)]
    fn phong_lanes(&self, d: &DrawInfo, quad: &Quad) -> QuadFactors {
        self.phong_lanes_with(d, quad, &self.lighting)
    }

    /// [`SceneShader::phong_lanes`] under `lighting` (the environment's draws leave the
    /// uniform ambient out).
    #[inline(always)]
    pub(super) fn phong_lanes_with(
        &self,
        d: &DrawInfo,
        quad: &Quad,
        lighting: &Lighting,
    ) -> QuadFactors {
        let Some(normal) = d.layout.normal else {
            return QuadFactors::UNLIT;
        };
        let mut n = normal.lanes(quad);
        if d.material.double_sided && !quad.front_facing {
            n = n.map(|l| -l);
        }
        let position = d.layout.position.map(|p| p.lanes(quad));
        phong_quad(&d.surface, n, position, lighting, self.viewer)
    }

    /// The factors D and S of a plain draw's quad, one vector per pixel (fourth lanes 0).
    #[inline(always)]
    fn plain_factors(&self, d: &DrawInfo, quad: &Quad) -> QuadFactors {
        if let Some(sides) = constant_factors(d) {
            return *side(d, sides, quad);
        }
        match d.path {
            LightingPath::Unlit => QuadFactors::UNLIT,
            LightingPath::PerPixel => self.phong_lanes(d, quad),
            LightingPath::Interpolated => match interpolated_factors(d, quad) {
                Some(f) => QuadFactors::from_lanes(f.d.lanes(quad), f.s.lanes(quad)),
                None => QuadFactors::UNLIT,
            },
        }
    }

    /// The general path's colours of one quad of draw `d`, its texture reads made.
    fn shade_read(
        &self,
        d: &DrawInfo,
        quad: &Quad,
        reads: &QuadReads,
        out: &mut [Vec4; 4],
        self_shadow: Option<&SelfShadow>,
    ) -> u8 {
        if let Some(e) = d.env.as_ref().filter(|_| d.path == LightingPath::PerPixel) {
            let kept = self.shade_env(d, e, quad, reads, out, self_shadow);
            if let Some((weights, color)) = d.outline(quad, self.viewer) {
                apply_outline(out, weights, color);
            }
            return kept;
        }
        if d.mr_quads() && self_shadow.is_none() {
            return self.shade_mr_quad(d, quad, reads, out);
        }
        let m = d.material;
        let mut kept = quad.mask;
        let maps = reads.surface_maps();
        let back = m.double_sided && !quad.front_facing;
        // Parallax self-shadowing: each light scaled per pixel by what the relief lets through.
        let mut light_buf = parallax::light_buffer(self_shadow);
        // Map-free Phong: the quad's four pixels lit in lanes.
        let lit = (d.path == LightingPath::PerPixel
            && !d.projectors
            && self_shadow.is_none()
            && !maps
            && d.model == ShadingModel::Phong)
            .then(|| self.phong_lanes(d, quad));
        let factors = interpolated_factors(d, quad);
        // Every pixel's colour at once (each test once a quad; a helper pixel's is not used).
        let colors = surface_colors(d, quad, reads);
        for j in 0..4 {
            if quad.mask & (1 << j) == 0 {
                continue;
            }
            let c = colors[j];
            let (mut df, sp) = match d.path {
                LightingPath::Unlit => (Vec3::ONE, Vec3::ZERO),
                LightingPath::PerPixel => match (&lit, maps) {
                    (Some(q), _) => (q.d[j].truncate(), q.s[j].truncate()),
                    (None, maps) => {
                        // The lights, each scaled by the relief's self-shadowing at this
                        // pixel when the draw has it (only this path reads them).
                        let lighting =
                            parallax::self_shadowed(self_shadow, self.lighting, j, &mut light_buf);
                        let mut normal = d
                            .layout
                            .normal
                            .map_or(Vec3::ZERO, |s| s.pixel3(quad, j).normalize_or_zero());
                        let position = d.layout.position.map_or(Vec3::ZERO, |s| s.pixel3(quad, j));
                        // Double-sided back faces are lit from their side, after any tilt.
                        if !maps {
                            // A Phong material without maps (the model is known): only the
                            // normal and position vary, and this surface stays in registers.
                            if back {
                                normal = -normal;
                            }
                            let s = Surface {
                                position,
                                normal,
                                ..d.surface
                            };
                            add(
                                phong(&s, &lighting, self.viewer),
                                self.projected(d, quad, &s),
                            )
                        } else {
                            let mut s = Surface {
                                position,
                                normal,
                                ..d.surface
                            };
                            d.apply_maps(reads, quad, j, c, &mut s);
                            if back {
                                s.normal = -s.normal;
                                s.clearcoat_normal = -s.clearcoat_normal;
                            }
                            add(
                                d.lit_factors(&s, &lighting, self.viewer),
                                self.projected(d, quad, &s),
                            )
                        }
                    }
                },
                LightingPath::Interpolated => {
                    let Some(f) = factors else {
                        continue;
                    };
                    let mut df = f.d.pixel3(quad, j);
                    let mut sp = f.s.pixel3(quad, j);
                    if let (Some(texel), Some(map)) = (reads.get(Read::Occlusion), &d.occlusion_map)
                    {
                        // The factors carry the full ambient term; take (1 − O) of it away.
                        let o = 1.0 + map.scale * (texel[j].x - 1.0);
                        df -= d.ambient_d * (1.0 - o);
                    }
                    if let Some(texel) = reads.get(Read::Emission) {
                        // The factors carry I_E; the map scales it: I_E·texel = I_E + I_E·(texel − 1).
                        sp += m.emissive * (texel[j].truncate() - Vec3::ONE);
                    }
                    if d.projectors {
                        let s = self.interpolated_surface(d, quad, j, back);
                        add((df, sp), self.projected(d, quad, &s))
                    } else {
                        (df, sp)
                    }
                }
            };
            if let Some(l) = d.light_factor(reads, j) {
                df *= l;
            }
            match combine(m.alpha_mode, c, df, sp) {
                Some(color) => out[j] = color,
                None => kept &= !(1 << j),
            }
        }
        if let Some((weights, color)) = d.outline(quad, self.viewer) {
            apply_outline(out, weights, color);
        }
        kept
    }
}

/// The sum of two `(D, S)` pairs.
#[inline(always)]
fn add(a: (Vec3, Vec3), b: (Vec3, Vec3)) -> (Vec3, Vec3) {
    (a.0 + b.0, a.1 + b.1)
}

/// A quad's four premultiplied surface colours `C`: the base colour × its texture × opacity
/// × vertex colour × the procedural colour, as far as the draw has each (each test made once
/// for the quad, not once a pixel). The procedural colour is evaluated at covered pixels only
/// (a helper pixel's point can lie far outside the object); a helper pixel's colour is not
/// used.
#[inline(always)]
pub(super) fn pixel_colors(
    d: &DrawInfo,
    quad: &Quad,
    texels: Option<&[Vec4; 4]>,
    opacity: Option<&[Vec4; 4]>,
) -> [Vec4; 4] {
    let mut c = [d.base; 4];
    if let Some(t) = texels {
        for (c, t) in c.iter_mut().zip(t) {
            *c *= *t;
        }
    }
    if let Some(t) = opacity {
        // Premultiplied: scaling alpha scales the whole colour.
        for (c, t) in c.iter_mut().zip(t) {
            *c *= if d.alpha_from_w { t.w } else { t.x };
        }
    }
    if let Some(slot) = d.layout.color {
        for (j, c) in c.iter_mut().enumerate() {
            let vc = Vec4::from_array(slot.pixel(quad, j));
            *c *= (vc.truncate() * vc.w).extend(vc.w);
        }
    }
    if let Some(proc) = &d.material.procedural {
        for (j, c) in c.iter_mut().enumerate() {
            if quad.mask & (1 << j) != 0 {
                *c *= d.procedural_color(proc, quad, j);
            }
        }
    }
    c
}

/// A plain textured batch's colours: quad `i`'s texels (in `out[i]`, replaced by its colours)
/// under `factors(i, quad)`; every shaded pixel kept.
#[inline(always)]
fn texels_colors<'f>(
    d: &DrawInfo,
    quads: &[Quad],
    out: &mut [[Vec4; 4]],
    kept: &mut [u8],
    factors: impl Fn(usize, &Quad) -> &'f QuadFactors,
) {
    for (i, ((quad, o), k)) in quads
        .iter()
        .zip(out.iter_mut())
        .zip(kept.iter_mut())
        .enumerate()
    {
        let texels = *o;
        plain_colors(d, factors(i, quad), Some(&texels), o);
        *k = quad.mask;
    }
}

crate::cpu::dispatch! {
    /// [`into_tile_in`] at the CPU's level.
    fn into_tile(
        d: &DrawInfo,
        quads: &[Quad],
        out: &mut [[Vec4; 4]],
        tile: &mut TileColors,
    ) => into_tile_in, into_tile_v3
}

/// [`SceneShader::plain_batch_at`]'s colours of a plain textured draw whose factors are
/// constant over a side, written into `tile` as each quad's are made
/// (`FragmentShader::shade_into_tile`): every texture read of the batch first (into
/// `out`), then each quad's colours, as [`texels_colors`] makes them, straight to its
/// pixels. The same values.
#[inline(always)]
fn into_tile_in(d: &DrawInfo, quads: &[Quad], out: &mut [[Vec4; 4]], tile: &mut TileColors) {
    let (Some(t), Some(sides)) = (d.texture.as_ref(), constant_factors(d)) else {
        unreachable!("into_tile: a plain textured draw with constant factors");
    };
    for (quads, out) in quads.chunks(BATCH).zip(out.chunks_mut(BATCH)) {
        t.quads(quads, out);
        for (quad, texels) in quads.iter().zip(out.iter()) {
            let mut c = [Vec4::ZERO; 4];
            plain_colors(d, side(d, sides, quad), Some(texels), &mut c);
            tile.write(quad, quad.mask, &c);
        }
    }
}

/// Unlit factors for the front and the back.
const UNLIT_SIDES: [QuadFactors; 2] = [QuadFactors::UNLIT; 2];

/// A plain draw's factors for front and back faces when they do not vary over a side: unlit,
/// or lit once (`DrawInfo::uniform_factors`); `None` when they are lit per quad.
#[inline(always)]
fn constant_factors<'a>(d: &'a DrawInfo) -> Option<&'a [QuadFactors; 2]> {
    match d.path {
        LightingPath::Unlit => Some(&UNLIT_SIDES),
        LightingPath::PerPixel => d.uniform_factors.as_ref(),
        LightingPath::Interpolated => None,
    }
}

/// The factors of `quad`'s side: double-sided back faces are lit from their side, as
/// `phong_lanes` does.
#[inline(always)]
fn side<'a>(d: &DrawInfo, sides: &'a [QuadFactors; 2], quad: &Quad) -> &'a QuadFactors {
    &sides[usize::from(d.material.double_sided && !quad.front_facing)]
}

/// The factors a Gouraud or flat quad reads: those lit with −N on the back faces of
/// double-sided draws, else the front ones.
#[inline]
fn interpolated_factors(d: &DrawInfo, quad: &Quad) -> Option<Factors> {
    let back = d.layout.back_factors.filter(|_| !quad.front_facing);
    back.or(d.layout.factors)
}

/// A plain draw's colours from the factors and texels: `combine` for an opaque colour,
/// straight = c / a (unless a is 0 or 1), then straight·D + S with alpha 1 (the factors'
/// fourth lanes are 0).
/// A quad whose four colours are opaque (an opaque texture under an opaque base, most
/// quads) is finished without a division or a test per pixel: the same values.
#[inline(always)]
fn plain_colors(d: &DrawInfo, f: &QuadFactors, texels: Option<&[Vec4; 4]>, out: &mut [Vec4; 4]) {
    let c: [Vec4; 4] = match texels {
        Some(t) => std::array::from_fn(|j| d.base * t[j]),
        None => [d.base; 4],
    };
    let alphas = Vec4::new(c[0].w, c[1].w, c[2].w, c[3].w);
    if alphas.cmpeq(Vec4::ONE).all() {
        for j in 0..4 {
            out[j] = c[j] * f.d[j] + f.s[j] + Vec4::W;
        }
        return;
    }
    for j in 0..4 {
        let a = c[j].w;
        let straight = if a > 0.0 && a != 1.0 { c[j] / a } else { c[j] };
        out[j] = straight * f.d[j] + f.s[j] + Vec4::W;
    }
}

/// The texture reads of `quads` (of draw `d`) into `out`, map by map across the quads, so each
/// map's reads are staged ([`MapRead::quads`]).
fn read_batch(d: &DrawInfo, quads: &[Quad], out: &mut [QuadReads]) {
    let lobes = d.surface_maps && d.lobe_maps.any();
    for (o, quad) in out.iter_mut().zip(quads) {
        // Read only for draws with such maps: a plain draw pays one test per quad.
        o.clear(d.surface_maps, lobes);
        if d.surface_maps {
            o.bumps = d.bump_map.as_ref().map(|t| t.height_slopes(quad));
        }
    }
    // Made for the first map read on its own (a draw whose maps are all read together has
    // none: its kilobyte was zeroed for nothing, a `memset` call a batch).
    let mut buf = None;
    // The maps read at one set of coordinates, together.
    if let Some(shared) = &d.shared {
        read_shared(d, shared, quads, out);
    }
    let shared = d.shared.as_ref().map_or(0, |s| s.maps);
    let own = |k: u8| shared & (1 << k) == 0;
    let mut fill = |t: &MapRead, r: Read| {
        let buf = buf.get_or_insert([[Vec4::ZERO; 4]; BATCH]);
        for (quads, out) in quads.chunks(BATCH).zip(out.chunks_mut(BATCH)) {
            t.quads(quads, &mut buf[..quads.len()]);
            for (o, b) in out.iter_mut().zip(buf.iter()) {
                o.set(r, *b);
            }
        }
    };
    if let Some(t) = d.texture.as_ref().filter(|_| own(0)) {
        fill(t, Read::Texels);
    }
    if let Some(t) = &d.alpha_map {
        fill(t, Read::Opacity);
    }
    if let Some(t) = &d.light_map {
        fill(t, Read::Light);
    }
    if !d.surface_maps {
        fold_layers(d, quads, out);
        return;
    }
    let maps = [
        (d.normal_map.as_ref().filter(|_| own(1)), Read::Normals),
        (d.normal_object_map.as_ref(), Read::ObjectNormals),
        (
            d.occlusion_map
                .as_ref()
                .filter(|_| own(2) && !d.occlusion_from_mr),
            Read::Occlusion,
        ),
        (d.emissive_map.as_ref().filter(|_| own(3)), Read::Emission),
        (
            d.metal_rough_map.as_ref().filter(|_| own(4)),
            Read::MetalRough,
        ),
        (d.ambient_map.as_ref(), Read::Ambient),
        (d.specular_map.as_ref(), Read::Specular),
        (d.shininess_map.as_ref(), Read::Shininess),
    ];
    for (map, r) in maps {
        if let Some(t) = map {
            fill(t, r);
        }
    }
    if lobes {
        let l = &d.lobe_maps;
        let lobes = [
            (l.specular_weight.as_ref(), Read::SpecularWeight),
            (l.specular_color.as_ref(), Read::SpecularColor),
            (l.clearcoat.as_ref(), Read::Clearcoat),
            (l.clearcoat_roughness.as_ref(), Read::ClearcoatRoughness),
            (l.clearcoat_normal.as_ref(), Read::ClearcoatNormal),
            (l.sheen_color.as_ref(), Read::SheenColor),
            (l.sheen_roughness.as_ref(), Read::SheenRoughness),
            (l.thickness.as_ref(), Read::Thickness),
        ];
        for (map, r) in lobes {
            if let Some(t) = map {
                fill(t, r);
            }
        }
    }
    // An occlusion map in the metallic-roughness map's image, read the same way (an ORM
    // image), takes that read's values (read together, `read_shared` reads it once).
    if d.occlusion_from_mr {
        for o in out.iter_mut() {
            if let Some(&t) = o.get(Read::MetalRough) {
                o.set(Read::Occlusion, t);
            }
        }
    }
    fold_layers(d, quads, out);
}

/// The reads of the maps `shared` names (bits over [`DrawInfo::shared_candidates`]) of
/// `quads` into `out`, the maps read together ([`MapRead::quads_shared`]), each image once.
fn read_shared(d: &DrawInfo, shared: &SharedReads, quads: &[Quad], out: &mut [QuadReads]) {
    let Some(first) = d.shared_candidates()[shared.first] else {
        return;
    };
    // The surface's maps only for a draw that has them (the base colour always).
    let kept = if d.surface_maps { 0b11111 } else { 1 };
    for (quads, out) in quads.chunks(BATCH).zip(out.chunks_mut(BATCH)) {
        first.quads_shared(&shared.reads, quads, |t, i, v| {
            // Most images feed one map: one pass of the loop.
            let mut bits = shared.feeds[t] & kept;
            while bits != 0 {
                out[i].set(DrawInfo::SHARED_READS[bits.trailing_zeros() as usize], v);
                bits &= bits - 1;
            }
        });
    }
}
