//! The varyings of one draw, laid out by name.
//!
//! The pipeline interpolates up to [`MAX_VARYINGS`] anonymous floats per vertex. A draw
//! decides once ([`VaryingLayout`]) which values it carries — uv sets, a normal and a
//! position for per-pixel lighting, lit factors for Gouraud and flat shading, a vertex
//! colour, a tangent, an object-space point for solid textures — and where each sits; the
//! vertex stage writes through the same [`Slot`]s the fragment stage reads, so the two cannot
//! disagree on an offset.

use glam::{Vec3, Vec4};

use crate::pipeline::{Quad, MAX_VARYINGS};

/// `N` consecutive varyings starting at a fixed offset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Slot<const N: usize> {
    at: usize,
}

impl<const N: usize> Slot<N> {
    /// Writes `values` into a vertex's varyings.
    #[inline]
    pub fn write(self, varyings: &mut [f32; MAX_VARYINGS], values: [f32; N]) {
        varyings[self.at..self.at + N].copy_from_slice(&values);
    }

    /// The slot's varyings of `quad` (one range check, so the reads below need none).
    #[inline(always)]
    fn of(self, quad: &Quad) -> &[Vec4] {
        &quad.varyings[self.at..self.at + N]
    }

    /// Pixel `j`'s values.
    #[inline(always)]
    pub fn pixel(self, quad: &Quad, j: usize) -> [f32; N] {
        let v = self.of(quad);
        std::array::from_fn(|c| v[c][j])
    }

    /// The quad's values, one lane per pixel.
    #[inline(always)]
    pub fn lanes(self, quad: &Quad) -> [Vec4; N] {
        let v = self.of(quad);
        std::array::from_fn(|c| v[c])
    }

    /// Replaces the quad's values (one lane per pixel).
    #[inline]
    pub fn set_lanes(self, quad: &mut Quad, values: [Vec4; N]) {
        quad.varyings[self.at..self.at + N].copy_from_slice(&values);
    }

    /// ∂/∂x of each value (coarse, the quad's top row).
    #[inline(always)]
    pub fn ddx(self, quad: &Quad) -> [f32; N] {
        let v = self.of(quad);
        std::array::from_fn(|c| v[c].y - v[c].x)
    }

    /// ∂/∂y of each value (coarse, the quad's left column).
    #[inline(always)]
    pub fn ddy(self, quad: &Quad) -> [f32; N] {
        let v = self.of(quad);
        std::array::from_fn(|c| v[c].z - v[c].x)
    }
}

impl Slot<3> {
    #[inline(always)]
    pub fn pixel3(self, quad: &Quad, j: usize) -> Vec3 {
        Vec3::from_array(self.pixel(quad, j))
    }

    #[inline(always)]
    pub fn ddx3(self, quad: &Quad) -> Vec3 {
        Vec3::from_array(self.ddx(quad))
    }

    #[inline(always)]
    pub fn ddy3(self, quad: &Quad) -> Vec3 {
        Vec3::from_array(self.ddy(quad))
    }
}

/// The Gouraud/flat factors `I = C·D + S` of one side: D at three varyings, S at the next
/// three.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Factors {
    pub d: Slot<3>,
    pub s: Slot<3>,
}

impl Factors {
    #[inline]
    pub fn write(self, varyings: &mut [f32; MAX_VARYINGS], (d, s): (Vec3, Vec3)) {
        self.d.write(varyings, d.to_array());
        self.s.write(varyings, s.to_array());
    }
}

/// What a draw's vertices carry to its fragments, and where.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct VaryingLayout {
    /// Texture coordinate set 0 (always present; (0, 0) for meshes without uvs).
    pub uv0: Slot<2>,
    /// Per-pixel lighting: the world-space normal.
    pub normal: Option<Slot<3>>,
    /// Per-pixel lighting: the world-space position (when lights, specular terms or bumps
    /// need it).
    pub position: Option<Slot<3>>,
    /// Gouraud and flat shading: the lit factors of the front side.
    pub factors: Option<Factors>,
    /// Double-sided Gouraud draws: the factors lit with −N, read on back faces.
    pub back_factors: Option<Factors>,
    /// Linear straight-alpha vertex colour.
    pub color: Option<Slot<4>>,
    /// Object-space position (solid textures, projections).
    pub object_position: Option<Slot<3>>,
    /// Object-space normal (projections that choose by the normal).
    pub object_normal: Option<Slot<3>>,
    /// Texture coordinate set 1, when some texture reads it.
    pub uv1: Option<Slot<2>>,
    /// World-space tangent and handedness, for tangent-space normal maps.
    pub tangent: Option<Slot<4>>,
    /// Floats per vertex.
    pub count: usize,
}

impl Default for VaryingLayout {
    /// uv set 0 alone.
    fn default() -> Self {
        VaryingLayout {
            uv0: Slot { at: 0 },
            normal: None,
            position: None,
            factors: None,
            back_factors: None,
            color: None,
            object_position: None,
            object_normal: None,
            uv1: None,
            tangent: None,
            count: 2,
        }
    }
}

impl VaryingLayout {
    /// The next `N` varyings.
    pub fn add<const N: usize>(&mut self) -> Slot<N> {
        let slot = Slot { at: self.count };
        self.count += N;
        assert!(
            self.count <= MAX_VARYINGS,
            "varying layout exceeds MAX_VARYINGS"
        );
        slot
    }

    /// The next six varyings, as factors D and S.
    pub fn add_factors(&mut self) -> Factors {
        Factors {
            d: self.add(),
            s: self.add(),
        }
    }

    /// Drops the normal's varyings when they are the last laid out (true then).
    pub fn drop_last_normal(&mut self) -> bool {
        match self.normal {
            Some(n) if n.at + 3 == self.count => {
                self.normal = None;
                self.count = n.at;
                true
            }
            _ => false,
        }
    }

    /// The uv set a texture on `tex_coord` reads: set 1 when the draw carries it, else set 0
    /// (a texture on set 1 of a mesh without it reads set 0; the peers read (0, 0)).
    pub fn uv_set(&self, tex_coord: u32) -> Slot<2> {
        match (tex_coord, self.uv1) {
            (1, Some(s)) => s,
            _ => self.uv0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_follow_each_other_without_overlap() {
        let mut l = VaryingLayout::default();
        let n: Slot<3> = l.add();
        let f = l.add_factors();
        let c: Slot<4> = l.add();
        assert_eq!((n.at, f.d.at, f.s.at, c.at, l.count), (2, 5, 8, 11, 15));
    }

    #[test]
    fn writes_land_where_reads_look() {
        let mut l = VaryingLayout::default();
        let _: Slot<3> = l.add();
        let t: Slot<4> = l.add();
        let mut v = [0.0; MAX_VARYINGS];
        t.write(&mut v, [1.0, 2.0, 3.0, 4.0]);
        let mut quad = Quad {
            x: 0,
            y: 0,
            mask: 0b1111,
            front_facing: true,
            varyings: [Vec4::ZERO; MAX_VARYINGS],
        };
        for (k, x) in v.iter().enumerate() {
            quad.varyings[k] = Vec4::splat(*x);
        }
        assert_eq!(t.pixel(&quad, 2), [1.0, 2.0, 3.0, 4.0]);
        assert_eq!(t.lanes(&quad)[3], Vec4::splat(4.0));
        assert_eq!(t.ddx(&quad), [0.0; 4]);
    }
}
