//! The BC1 colour block: two RGB 5:6:5 endpoints and sixteen 2-bit codes. BC1 itself uses it,
//! and BC2 and BC3 store one in their second half.
//!
//! The rules are D3D11.3 §19.5.6 (and the Khronos Data Format Specification's S3TC chapter):
//! the endpoints are promoted to UNORM8 by bit replication; when `color_0 > color_1` (as
//! unsigned 16-bit numbers) the codes select `color_0`, `color_1`, `(2·color_0 + color_1)/3`
//! and `(color_0 + 2·color_1)/3`; otherwise `color_0`, `color_1`, `(color_0 + color_1)/2` and
//! transparent black. BC2 and BC3 always use the four-colour rule, whatever the endpoint order.
//!
//! D3D defines the palette as UNORM8 values and allows 1/255 (plus 3% of the endpoint distance)
//! of error in them. The divisions here truncate, as the reference decoder this module is
//! checked against does (texture2ddecoder, Perfare's Texture2DDecoder): within that tolerance,
//! and byte for byte what the reference gives.

/// Which palette rule a colour block follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ColourRule {
    /// BC1: three colours and transparent black when `color_0 <= color_1`.
    Bc1,
    /// BC2 and BC3: always four opaque colours.
    FourColour,
}

/// An RGB 5:6:5 endpoint promoted to UNORM8 by bit replication (D3D11.3 §19.5.3).
fn promote565(c: u16) -> [u16; 3] {
    let r = (c >> 11) & 31;
    let g = (c >> 5) & 63;
    let b = c & 31;
    [
        (r << 3) | (r >> 2),
        (g << 2) | (g >> 4),
        (b << 3) | (b >> 2),
    ]
}

/// The four RGBA8 colours a block's codes select.
fn palette(block: &[u8; 8], rule: ColourRule) -> [[u8; 4]; 4] {
    let c0 = u16::from_le_bytes([block[0], block[1]]);
    let c1 = u16::from_le_bytes([block[2], block[3]]);
    let (e0, e1) = (promote565(c0), promote565(c1));
    let mix = |w0: u16, w1: u16, d: u16| -> [u8; 4] {
        let ch = |i: usize| ((w0 * e0[i] + w1 * e1[i]) / d) as u8;
        [ch(0), ch(1), ch(2), 255]
    };
    let (c2, c3) = if rule == ColourRule::FourColour || c0 > c1 {
        (mix(2, 1, 3), mix(1, 2, 3))
    } else {
        (mix(1, 1, 2), [0, 0, 0, 0])
    };
    [mix(1, 0, 1), mix(0, 1, 1), c2, c3]
}

/// Decodes a colour block into 16 RGBA8 texels, row-major (alpha 255 except BC1's
/// transparent black).
pub(super) fn decode(block: &[u8; 8], rule: ColourRule, out: &mut [[u8; 4]; 16]) {
    let pal = palette(block, rule);
    let codes = u32::from_le_bytes([block[4], block[5], block[6], block[7]]);
    for (i, texel) in out.iter_mut().enumerate() {
        *texel = pal[((codes >> (2 * i)) & 3) as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block with endpoints `c0`, `c1` whose texels 0–3 use codes 0–3 (the rest code 0).
    fn block(c0: u16, c1: u16) -> [u8; 8] {
        let [a, b] = c0.to_le_bytes();
        let [c, d] = c1.to_le_bytes();
        [a, b, c, d, 0b1110_0100, 0, 0, 0]
    }

    fn first_four(block: &[u8; 8], rule: ColourRule) -> [[u8; 4]; 4] {
        let mut out = [[0; 4]; 16];
        decode(block, rule, &mut out);
        [out[0], out[1], out[2], out[3]]
    }

    #[test]
    fn endpoints_promote_by_bit_replication() {
        assert_eq!(promote565(0xffff), [255, 255, 255]);
        assert_eq!(promote565(0), [0, 0, 0]);
        // r = 1, g = 1, b = 1: 8, 4, 8; r = 16: 132.
        assert_eq!(promote565(0x0821), [8, 4, 8]);
        assert_eq!(promote565(16 << 11), [132, 0, 0]);
    }

    #[test]
    fn four_colour_thirds_truncate() {
        let got = first_four(&block(0xffff, 0x0000), ColourRule::Bc1);
        assert_eq!(
            got,
            [
                [255; 4],
                [0, 0, 0, 255],
                [170, 170, 170, 255],
                [85, 85, 85, 255]
            ]
        );
        // Red 2 (16) and 1 (8): (2·16 + 8)/3 = 13.3 → 13, (16 + 2·8)/3 = 10.7 → 10.
        let got = first_four(&block(2 << 11, 1 << 11), ColourRule::Bc1);
        assert_eq!(got[2], [13, 0, 0, 255]);
        assert_eq!(got[3], [10, 0, 0, 255]);
    }

    #[test]
    fn three_colour_mode_has_transparent_black() {
        // color_0 < color_1: the midpoint and transparent black.
        let got = first_four(&block(1 << 11, 2 << 11), ColourRule::Bc1);
        assert_eq!(
            got,
            [
                [8, 0, 0, 255],
                [16, 0, 0, 255],
                [12, 0, 0, 255],
                [0, 0, 0, 0]
            ]
        );
        // Equal endpoints are the three-colour mode too; the midpoint truncates.
        let got = first_four(&block(0x0841, 0x0841), ColourRule::Bc1);
        assert_eq!(got[2], [8, 8, 8, 255]);
        assert_eq!(got[3], [0, 0, 0, 0]);
        // Red 1 (8) and 5 (41): (8 + 41)/2 = 24.5 → 24; blue 0 and 1 (8): 4.
        let got = first_four(&block(1 << 11, (5 << 11) | 1), ColourRule::Bc1);
        assert_eq!(got[2], [24, 0, 4, 255]);
    }

    #[test]
    fn bc2_and_bc3_colour_is_always_four_colour() {
        let got = first_four(&block(1 << 11, 2 << 11), ColourRule::FourColour);
        assert_eq!(got[2], [10, 0, 0, 255]); // (2·8 + 16)/3 = 10.7
        assert_eq!(got[3], [13, 0, 0, 255]); // (8 + 2·16)/3 = 13.3
        let got = first_four(&block(0x1234, 0x1234), ColourRule::FourColour);
        assert!(got.iter().all(|c| *c == got[0]));
    }

    #[test]
    fn codes_are_read_from_the_low_bits_row_major() {
        // Texel 15 takes the top two bits.
        let mut b = block(0xffff, 0);
        b[4..8].copy_from_slice(&(0b01u32 << 30).to_le_bytes());
        let mut out = [[0; 4]; 16];
        decode(&b, ColourRule::Bc1, &mut out);
        assert_eq!(out[15], [0, 0, 0, 255]);
        assert!(out[..15].iter().all(|c| *c == [255; 4]));
    }
}
