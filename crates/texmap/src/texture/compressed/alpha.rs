//! Single-channel blocks: BC2's explicit 4-bit alpha, and the interpolated channel of BC3's
//! alpha, BC4 and BC5 (two 8-bit endpoints and sixteen 3-bit codes), unsigned and signed.
//!
//! The interpolated channel follows D3D11.3 §19.5.9–19.5.10 (and the Khronos RGTC chapter):
//! when `red_0 > red_1` (an unsigned compare, or a signed one for the signed formats) the codes
//! select the two endpoints and their six sevenths-steps; otherwise the endpoints, four
//! fifths-steps, and the range's ends (0 and 1, or −1 and 1). A signed endpoint is
//! `max(v, −127)/127`, so −128 and −127 are both −1. The comparison is made on the stored
//! bytes, so (−127, −128) is an eight-value block and (−128, −127) a six-value one (the case
//! the Khronos text leaves undefined; D3D's pseudocode compares the stored values).
//!
//! D3D requires these values to 1/65535 (1/32767 signed), finer than 8 bits, so the exact
//! values are kept: [`Channel`] holds each one as an integer over 35 (the common denominator of
//! the sevenths and fifths) and 255 or 127. The `f32` output is that fraction. The unsigned
//! 8-bit output truncates it (`(6·a0 + a1)/7` in integers, the rule of the reference decoder
//! and of most software decoders, so dumps compare byte for byte); the signed one is the
//! nearest SNORM8 value (a seventh or a fifth never falls on a half, so no tie).

/// BC2's alpha half: sixteen 4-bit values, texel 0 in the low nibble of byte 0. `a/15` is
/// exactly the UNORM8 value `a·17`.
pub(super) fn explicit_alpha(block: &[u8; 8]) -> [u8; 16] {
    let bits = u64::from_le_bytes(*block);
    std::array::from_fn(|i| ((bits >> (4 * i)) & 15) as u8 * 17)
}

/// Whether a channel block's bytes are unsigned or two's-complement signed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Signedness {
    Unsigned,
    Signed,
}

/// The sixteen decoded values of a channel block, exactly: value = `num / (35 · scale)` with
/// `scale` 255 (unsigned) or 127 (signed).
pub(super) struct Channel {
    num: [i32; 16],
    signedness: Signedness,
}

impl Channel {
    /// Decodes an 8-byte channel block.
    pub(super) fn decode(block: &[u8; 8], signedness: Signedness) -> Self {
        // The mode comes from the stored bytes; signed values clamp −128 to −127.
        let (eight, r0, r1, lo, hi) = match signedness {
            Signedness::Unsigned => {
                let (a, b) = (block[0], block[1]);
                (a > b, i32::from(a), i32::from(b), 0, 255)
            }
            Signedness::Signed => {
                let (a, b) = (block[0] as i8, block[1] as i8);
                let (va, vb) = (i32::from(a.max(-127)), i32::from(b.max(-127)));
                (a > b, va, vb, -127, 127)
            }
        };
        // Each entry over 35: endpoints ×35, sevenths ×5, fifths ×7.
        let mut pal = [35 * r0, 35 * r1, 0, 0, 0, 0, 0, 0];
        if eight {
            for (k, p) in pal[2..].iter_mut().enumerate() {
                let j = k as i32 + 1; // code 2 + k: (7 − j)·r0 + j·r1, over 7
                *p = 5 * ((7 - j) * r0 + j * r1);
            }
        } else {
            for (k, p) in pal[2..6].iter_mut().enumerate() {
                let j = k as i32 + 1;
                *p = 7 * ((5 - j) * r0 + j * r1);
            }
            pal[6] = 35 * lo;
            pal[7] = 35 * hi;
        }
        let mut codes = [0u8; 8];
        codes[..6].copy_from_slice(&block[2..]);
        let codes = u64::from_le_bytes(codes);
        Channel {
            num: std::array::from_fn(|i| pal[((codes >> (3 * i)) & 7) as usize]),
            signedness,
        }
    }

    /// The values as UNORM8 (unsigned: the weighted sum divided with truncation, the integer
    /// rule of the common decoders and of the reference) or SNORM8 two's-complement bytes
    /// (signed: the nearest 8-bit value).
    pub(super) fn to_8bit(&self) -> [u8; 16] {
        match self.signedness {
            // num = 35·(weighted sum over 7 or 5): floor(num / 35) is the truncated division.
            Signedness::Unsigned => self.num.map(|n| (n / 35) as u8),
            // floor((num + 17.5) / 35): no value is a tie, and this rounds negatives too.
            Signedness::Signed => self.num.map(|n| (2 * n + 35).div_euclid(70) as u8),
        }
    }

    /// The values as `f32`: in [0, 1] unsigned, [−1, 1] signed.
    pub(super) fn to_f32(&self) -> [f32; 16] {
        let den = match self.signedness {
            Signedness::Unsigned => 35.0 * 255.0,
            Signedness::Signed => 35.0 * 127.0,
        };
        self.num.map(|n| n as f32 / den)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A channel block whose texels 0–7 use codes 0–7 (texels 8–15 code 0).
    fn block(r0: u8, r1: u8) -> [u8; 8] {
        let codes: u64 = (0..8).map(|c| c << (3 * c)).sum();
        let c = codes.to_le_bytes();
        [r0, r1, c[0], c[1], c[2], c[3], c[4], c[5]]
    }

    fn first_eight<T: Copy>(v: [T; 16]) -> [T; 8] {
        std::array::from_fn(|i| v[i])
    }

    #[test]
    fn explicit_alpha_is_nibbles_times_17() {
        let b = 0xfedc_ba98_7654_3210u64.to_le_bytes();
        let got = explicit_alpha(&b);
        assert_eq!(got, std::array::from_fn(|i| i as u8 * 17));
    }

    #[test]
    fn eight_value_block_rounds_to_nearest() {
        let ch = Channel::decode(&block(200, 10), Signedness::Unsigned);
        // (6·200 + 10)/7 = 172.86, (5·200 + 20)/7 = 145.71, … (200 + 60)/7 = 37.14: truncated.
        assert_eq!(
            first_eight(ch.to_8bit()),
            [200, 10, 172, 145, 118, 91, 64, 37]
        );
        let f = ch.to_f32();
        assert_eq!(f[0], 200.0 / 255.0);
        assert_eq!(f[1], 10.0 / 255.0);
        assert_eq!(f[2], 1210.0 / 1785.0);
        assert_eq!(f[7], 260.0 / 1785.0);
    }

    #[test]
    fn six_value_block_has_zero_and_one() {
        let ch = Channel::decode(&block(10, 200), Signedness::Unsigned);
        // (4·10 + 200)/5 = 48, (30 + 400)/5 = 86, (20 + 600)/5 = 124, (10 + 800)/5 = 162.
        assert_eq!(
            first_eight(ch.to_8bit()),
            [10, 200, 48, 86, 124, 162, 0, 255]
        );
        let f = ch.to_f32();
        assert_eq!((f[6], f[7]), (0.0, 1.0));
        // Close endpoints: (4·3 + 4)/5 = 3.2, 3.4, 3.6, 3.8 all truncate to 3.
        let ch = Channel::decode(&block(3, 4), Signedness::Unsigned);
        assert_eq!(first_eight(ch.to_8bit()), [3, 4, 3, 3, 3, 3, 0, 255]);
    }

    #[test]
    fn equal_endpoints_are_a_six_value_block() {
        let ch = Channel::decode(&block(77, 77), Signedness::Unsigned);
        assert_eq!(first_eight(ch.to_8bit()), [77, 77, 77, 77, 77, 77, 0, 255]);
    }

    #[test]
    fn signed_minus_128_and_minus_127_are_both_minus_one() {
        let m128 = (-128i8) as u8;
        let m127 = (-127i8) as u8;
        // (−127, −128): −127 > −128, an eight-value block whose every value is −1.
        let ch = Channel::decode(&block(m127, m128), Signedness::Signed);
        assert_eq!(first_eight(ch.to_f32()), [-1.0; 8]);
        assert_eq!(first_eight(ch.to_8bit()), [m127; 8]);
        // (−128, −127): a six-value block: −1 four times, then −1 and +1.
        let ch = Channel::decode(&block(m128, m127), Signedness::Signed);
        assert_eq!(
            first_eight(ch.to_f32()),
            [-1.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, 1.0]
        );
        assert_eq!(first_eight(ch.to_8bit())[7], 127);
    }

    #[test]
    fn signed_interpolation_is_exact_and_rounds_both_ways() {
        let m128 = (-128i8) as u8;
        // (−128, 127): six-value; (4·−127 + 127)/5 = −76.2, (3·−127 + 254)/5 = −25.4,
        // (2·−127 + 381)/5 = 25.4, (−127 + 508)/5 = 76.2.
        let ch = Channel::decode(&block(m128, 127), Signedness::Signed);
        let bytes = first_eight(ch.to_8bit()).map(|b| b as i8);
        assert_eq!(bytes, [-127, 127, -76, -25, 25, 76, -127, 127]);
        let f = ch.to_f32();
        assert_eq!(f[2], -381.0 / 635.0);
        // (100, −50): eight-value; (600 − 50)/7 = 78.57 → 79, (100 − 300)/7 = −28.57 → −29.
        let ch = Channel::decode(&block(100, (-50i8) as u8), Signedness::Signed);
        let bytes = first_eight(ch.to_8bit()).map(|b| b as i8);
        assert_eq!(bytes[2], 79);
        assert_eq!(bytes[7], -29);
        assert_eq!(ch.to_f32()[7], -200.0 / 889.0);
    }
}
