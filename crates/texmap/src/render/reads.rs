//! What a quad's texture reads gave on the general path ([`QuadReads`]): one slot of four
//! texels per kind of read ([`Read`]) and one word that says which slots hold a read.
//!
//! The word keeps the record compact where it counts: a batch's records are written by the
//! reads and read back by the shading, and with a tag beside each read (an `Option` a
//! read, each tag on a cache line of its own) clearing a record touched a dozen lines and
//! the shading missed the first-level cache on the tags. Here clearing a record writes the
//! word (and the bump slopes' tag beside it), and the metallic-roughness path's five reads
//! sit in the first slots, side by side (docs/performance.md, "The 15:48 session's steps").

use std::mem::MaybeUninit;

use glam::{Vec2, Vec4};

/// The kinds of texture read a quad can have, each a slot of [`QuadReads`]: the
/// metallic-roughness path's first, so its reads share cache lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Read {
    /// The base colour texture.
    Texels,
    /// The tangent-space normal map.
    Normals,
    MetalRough,
    Occlusion,
    Emission,
    /// The opacity map.
    Opacity,
    /// The surface colour after the texture layers (draws with layers).
    Layered,
    /// The light map.
    Light,
    /// The object-space normal map.
    ObjectNormals,
    /// The OBJ colour maps.
    Ambient,
    Specular,
    Shininess,
    // glTF's extension maps.
    SpecularWeight,
    SpecularColor,
    Clearcoat,
    ClearcoatRoughness,
    ClearcoatNormal,
    SheenColor,
    SheenRoughness,
    Thickness,
}

/// How many kinds of [`Read`] there are.
const SLOTS: usize = Read::Thickness as usize + 1;
// The slots' bits stay below [`SURFACE`] and [`LOBES`].
const _: () = assert!(SLOTS <= 30);

/// [`QuadReads::made`]'s bit for a draw with maps that feed the
/// [`crate::shading::Surface`] (above the slots' bits).
const SURFACE: u32 = 1 << 30;
/// [`QuadReads::made`]'s bit for a draw with glTF's extension maps.
const LOBES: u32 = 1 << 31;

/// A quad's texture reads on the general path: the base colour texture, the opacity map,
/// the light map, the layers' colour and (for draws with any) the maps that feed the
/// [`crate::shading::Surface`].
#[derive(Clone, Copy)]
pub(super) struct QuadReads {
    /// Bit `r` for each [`Read`] `r` made, and [`SURFACE`] and [`LOBES`].
    made: u32,
    /// Height slopes `(∂h/∂x, ∂h/∂y)` of the bump map (computed, not a slot's texels).
    pub bumps: Option<[Vec2; 4]>,
    /// Each read's texels, written before its bit is set (not zeroed: a batch's records
    /// are made on the stack for every batch, and zeroing them was a 21-kilobyte `memset`).
    slots: [MaybeUninit<[Vec4; 4]>; SLOTS],
}

impl Default for QuadReads {
    fn default() -> Self {
        QuadReads {
            made: 0,
            bumps: None,
            slots: [MaybeUninit::uninit(); SLOTS],
        }
    }
}

impl QuadReads {
    /// No read made, for a draw with maps that feed the surface (`surface`) and, among them,
    /// glTF's extension maps (`lobes`): one word written (and the bumps' tag).
    #[inline(always)]
    pub(super) fn clear(&mut self, surface: bool, lobes: bool) {
        self.made = if surface { SURFACE } else { 0 } | if lobes { LOBES } else { 0 };
        self.bumps = None;
    }

    /// The four texels of read `r`, if it was made.
    #[inline(always)]
    pub(super) fn get(&self, r: Read) -> Option<&[Vec4; 4]> {
        let slot = &self.slots[r as usize];
        // SAFETY: a slot's bit is set only once `set` has written its texels.
        (self.made & (1 << r as u32) != 0).then(|| unsafe { slot.assume_init_ref() })
    }

    /// Read `r` made: its four texels.
    #[inline(always)]
    pub(super) fn set(&mut self, r: Read, texels: [Vec4; 4]) {
        self.slots[r as usize].write(texels);
        self.made |= 1 << r as u32;
    }

    /// Whether the draw has maps that feed the surface (their reads may still be none).
    #[inline(always)]
    pub(super) fn surface_maps(&self) -> bool {
        self.made & SURFACE != 0
    }

    /// Whether the draw has glTF's extension maps.
    #[inline(always)]
    pub(super) fn lobe_maps(&self) -> bool {
        self.made & LOBES != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_read_is_there_once_set_and_gone_once_cleared() {
        let mut r = QuadReads::default();
        r.clear(true, false);
        assert!(r.surface_maps() && !r.lobe_maps());
        assert!(r.get(Read::Thickness).is_none());
        let t = [Vec4::ONE, Vec4::X, Vec4::Y, Vec4::Z];
        r.set(Read::Thickness, t);
        r.set(Read::Texels, [Vec4::W; 4]);
        assert_eq!(r.get(Read::Thickness), Some(&t));
        assert_eq!(r.get(Read::Texels), Some(&[Vec4::W; 4]));
        assert!(r.get(Read::Normals).is_none());
        r.clear(false, true);
        assert!(!r.surface_maps() && r.lobe_maps());
        assert!(r.get(Read::Thickness).is_none() && r.get(Read::Texels).is_none());
    }
}
