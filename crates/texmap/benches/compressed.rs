//! Block decoding throughput: ns per 4×4 block for BC1, BC3 and BC7 (to RGBA8) and BC6H
//! (to `f32`), over 4096 pseudo-random blocks (`cargo bench --bench compressed`; criterion
//! reports time per batch and elements/s, so ns/block = time / 4096).
//!
//! `storage/*`: sampling a 2048² BC1 or BC7 texture (full chain) held `compressed` (the
//! blocks, decoded on read through the per-thread block cache), `native` (8-bit RGBA) and
//! `decoded` (16-bit linear, the default), trilinear, over the 64×64 footprint grid of
//! `benches/sampling.rs` — read by quads as the rasterizer reads (`quads`) and one footprint
//! at a time (`sample`) — magnifying (½ texel a pixel) and minifying 4:1. ns/sample = time
//! / 4096.
//!
//! Random bytes would make nearly every BC7 block mode 0 and a fifth of BC6H blocks reserved,
//! so each block's mode field is set to cycle through the valid modes (8 for BC7, 14 for BC6H).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use glam::{Vec2, Vec4};
use texmap::texture::compressed::{
    decode_block_f32, decode_block_rgba8, decode_level_rgba8, BlockFormat,
};
use texmap::texture::{
    level_count, sample_batch, sample_quads_lanes, ColorSpace, Filter, Footprint, Format,
    QuadCoords, Sampler, Storage, Texture2D, TextureOptions, Wrap,
};

const N: usize = 4096;

fn blocks(block_bytes: usize, seed: u64) -> Vec<u8> {
    random_bytes(N * block_bytes, seed)
}

fn random_bytes(n: usize, seed: u64) -> Vec<u8> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 32) as u8
        })
        .collect()
}

fn bc7_blocks() -> Vec<u8> {
    bc7_modes(blocks(16, 0x7777_1234_5678_9abc))
}

/// Sets each block's mode field to cycle through BC7's eight modes.
fn bc7_modes(mut data: Vec<u8>) -> Vec<u8> {
    for (k, block) in data.chunks_exact_mut(16).enumerate() {
        let mode = k % 8;
        block[0] = (((u32::from(block[0]) << (mode + 1)) | (1 << mode)) & 0xff) as u8;
    }
    data
}

fn bc6h_blocks() -> Vec<u8> {
    const MODES: [u8; 14] = [0, 1, 2, 6, 10, 14, 18, 22, 26, 30, 3, 7, 11, 15];
    let mut data = blocks(16, 0x6666_8765_4321_0fed);
    for (k, block) in data.chunks_exact_mut(16).enumerate() {
        let mode = MODES[k % MODES.len()];
        let mask = if mode < 2 { 3 } else { 31 };
        block[0] = (block[0] & !mask) | mode;
    }
    data
}

fn decode(c: &mut Criterion) {
    let mut g = c.benchmark_group("block");
    g.throughput(Throughput::Elements(N as u64));
    let cases = [
        ("bc1", BlockFormat::Bc1, blocks(8, 0x1111_2222_3333_4444)),
        ("bc3", BlockFormat::Bc3, blocks(16, 0x3333_4444_5555_6666)),
        ("bc7", BlockFormat::Bc7, bc7_blocks()),
    ];
    for (name, format, data) in &cases {
        g.bench_function(*name, |b| {
            let mut out = [[0u8; 4]; 16];
            b.iter(|| {
                let mut sum = 0u32;
                for block in data.chunks_exact(format.block_bytes()) {
                    decode_block_rgba8(*format, black_box(block), &mut out);
                    sum = sum.wrapping_add(u32::from(out[5][0]));
                }
                sum
            })
        });
    }
    let data = bc6h_blocks();
    for (name, format) in [
        ("bc6h_unsigned", BlockFormat::Bc6hUnsigned),
        ("bc6h_signed", BlockFormat::Bc6hSigned),
    ] {
        g.bench_function(name, |b| {
            let mut out = [[0f32; 4]; 16];
            b.iter(|| {
                let mut sum = 0f32;
                for block in data.chunks_exact(16) {
                    decode_block_f32(format, black_box(block), &mut out);
                    sum += out[5][0];
                }
                sum
            })
        });
    }
    g.finish();
}

/// Texture side for the storage benchmark, and the footprint grid's.
const SIDE: u32 = 2048;
const GRID: u32 = 64;

/// A `SIDE`² texture of random `format` blocks (BC7's modes cycled), full chain, held as
/// `storage`.
fn block_texture(format: BlockFormat, storage: Storage) -> Texture2D {
    let levels: Vec<Vec<u8>> = (0..level_count(SIDE, SIDE))
        .map(|i| {
            let side = (SIDE >> i).max(1);
            let bytes = random_bytes(format.level_bytes(side, side) as usize, 7 + i as u64);
            if format == BlockFormat::Bc7 {
                bc7_modes(bytes)
            } else {
                bytes
            }
        })
        .collect();
    let options = TextureOptions::default().with_storage(storage);
    if storage == Storage::Compressed {
        let slices: Vec<&[u8]> = levels.iter().map(Vec::as_slice).collect();
        return Texture2D::from_blocks(
            SIDE,
            SIDE,
            format,
            ColorSpace::Srgb,
            &slices,
            options,
            false,
        )
        .unwrap();
    }
    let texels: Vec<Vec<u8>> = levels
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let side = (SIDE >> i).max(1);
            decode_level_rgba8(format, l, side, side).unwrap()
        })
        .collect();
    let slices: Vec<&[u8]> = texels.iter().map(Vec::as_slice).collect();
    Texture2D::from_texel_levels(
        SIDE,
        SIDE,
        Format::Rgba8,
        ColorSpace::Srgb,
        &slices,
        options,
    )
    .unwrap()
}

/// The footprint grid (derivatives in texels), as single footprints and as 2×2 quads.
fn footprints(d: f32) -> (Vec<Footprint>, Vec<QuadCoords>) {
    let (dx, dy) = (
        Vec2::new(d, 0.0) / SIDE as f32,
        Vec2::new(0.0, d) / SIDE as f32,
    );
    let origin = Vec2::new(0.123, 0.377);
    let fps: Vec<Footprint> = (0..GRID * GRID)
        .map(|i| {
            let (x, y) = ((i % GRID) as f32, (i / GRID) as f32);
            Footprint::new(origin + dx * x + dy * y, dx, dy)
        })
        .collect();
    let g = GRID as usize;
    let mut quads = Vec::new();
    for qy in (0..g).step_by(2) {
        for qx in (0..g).step_by(2) {
            let px = |j: usize| &fps[(qy + (j >> 1)) * g + qx + (j & 1)];
            quads.push(QuadCoords {
                u: Vec4::from_array(std::array::from_fn(|j| px(j).uv.x)),
                v: Vec4::from_array(std::array::from_fn(|j| px(j).uv.y)),
                duv_dx: dx,
                duv_dy: dy,
            });
        }
    }
    (fps, quads)
}

fn storage(c: &mut Criterion) {
    let s = Sampler::new(Filter::TRILINEAR, Wrap::Repeat);
    for (fname, format) in [("bc1", BlockFormat::Bc1), ("bc7", BlockFormat::Bc7)] {
        let textures: Vec<(&str, Texture2D)> = Storage::NAMES
            .iter()
            .map(|&(name, st)| (name, block_texture(format, st)))
            .collect();
        for (case, d) in [("magnify", 0.5f32), ("minify4", 4.0)] {
            let (fps, quads) = footprints(d);
            let masks = vec![0b1111u8; quads.len()];
            let mut g = c.benchmark_group(format!("storage/{fname}/{case}"));
            g.throughput(Throughput::Elements(fps.len() as u64));
            for (name, tex) in &textures {
                let mut out = vec![[Vec4::ZERO; 4]; quads.len()];
                g.bench_function(format!("quads/{name}"), |b| {
                    b.iter(|| {
                        for ((q, m), o) in
                            quads.chunks(8).zip(masks.chunks(8)).zip(out.chunks_mut(8))
                        {
                            sample_quads_lanes(tex, &s, q, m, o);
                        }
                    })
                });
                let mut out = vec![Vec4::ZERO; fps.len()];
                g.bench_function(format!("sample/{name}"), |b| {
                    b.iter(|| sample_batch(tex, &s, &fps, &mut out))
                });
            }
            g.finish();
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = decode, storage
}
criterion_main!(benches);
