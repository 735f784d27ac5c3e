//! Block decoding throughput: ns per 4×4 block for BC1, BC3 and BC7 (to RGBA8) and BC6H
//! (to `f32`), over 4096 pseudo-random blocks (`cargo bench --bench compressed`; criterion
//! reports time per batch and elements/s, so ns/block = time / 4096).
//!
//! Random bytes would make nearly every BC7 block mode 0 and a fifth of BC6H blocks reserved,
//! so each block's mode field is set to cycle through the valid modes (8 for BC7, 14 for BC6H).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use texmap::texture::compressed::{decode_block_f32, decode_block_rgba8, BlockFormat};

const N: usize = 4096;

fn blocks(block_bytes: usize, seed: u64) -> Vec<u8> {
    let mut s = seed;
    (0..N * block_bytes)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 32) as u8
        })
        .collect()
}

fn bc7_blocks() -> Vec<u8> {
    let mut data = blocks(16, 0x7777_1234_5678_9abc);
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

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = decode
}
criterion_main!(benches);
