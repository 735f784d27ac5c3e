//! Analytic signed distance functions and their constructive solid geometry.
//!
//! Primitives (exact distances, negative inside): a sphere, a box (the exact box distance,
//! outside and inside), a torus around the y axis. Combinations follow the usual rules:
//! union = min, intersection = max, difference = max(a, −b); these are exact outside for a
//! union and bounds elsewhere (the zero set is always right). The smooth union is the
//! polynomial smooth minimum with blend radius `k` (Quílez):
//! `h = clamp(½ + ½(b − a)/k, 0, 1)`, `mix(b, a, h) − k·h·(1 − h)`.

use glam::DVec3;
use rayon::prelude::*;

use super::{Field, FieldGrid};

/// A shape with a signed distance.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A ball.
    Sphere { center: DVec3, radius: f64 },
    /// An axis-aligned box given by its centre and half sizes.
    Box { center: DVec3, half: DVec3 },
    /// A torus around the y axis through `center`: `major` from the axis to the tube's
    /// centre line, `minor` the tube's radius.
    Torus {
        center: DVec3,
        major: f64,
        minor: f64,
    },
    /// Inside either.
    Union(Box<Shape>, Box<Shape>),
    /// Inside both.
    Intersection(Box<Shape>, Box<Shape>),
    /// Inside the first and not the second.
    Difference(Box<Shape>, Box<Shape>),
    /// The union with its crease rounded over a blend radius `k` (> 0).
    SmoothUnion(Box<Shape>, Box<Shape>, f64),
}

impl Shape {
    /// The signed distance at `p` (exact for primitives and outside unions; see the module
    /// docs).
    #[must_use]
    pub fn distance(&self, p: DVec3) -> f64 {
        match self {
            Shape::Sphere { center, radius } => (p - *center).length() - radius,
            Shape::Box { center, half } => {
                let q = (p - *center).abs() - *half;
                q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
            }
            Shape::Torus {
                center,
                major,
                minor,
            } => {
                let q = p - *center;
                let ring = (q.x * q.x + q.z * q.z).sqrt() - major;
                (ring * ring + q.y * q.y).sqrt() - minor
            }
            Shape::Union(a, b) => a.distance(p).min(b.distance(p)),
            Shape::Intersection(a, b) => a.distance(p).max(b.distance(p)),
            Shape::Difference(a, b) => a.distance(p).max(-b.distance(p)),
            Shape::SmoothUnion(a, b, k) => {
                let (da, db) = (a.distance(p), b.distance(p));
                if *k <= 0.0 {
                    return da.min(db);
                }
                let h = (0.5 + 0.5 * (db - da) / k).clamp(0.0, 1.0);
                db + (da - db) * h - k * h * (1.0 - h)
            }
        }
    }

    /// `self ∪ other`.
    #[must_use]
    pub fn union(self, other: Shape) -> Shape {
        Shape::Union(Box::new(self), Box::new(other))
    }
    /// `self ∩ other`.
    #[must_use]
    pub fn intersect(self, other: Shape) -> Shape {
        Shape::Intersection(Box::new(self), Box::new(other))
    }
    /// `self − other`.
    #[must_use]
    pub fn subtract(self, other: Shape) -> Shape {
        Shape::Difference(Box::new(self), Box::new(other))
    }
    /// `self ∪ other`, rounded over `k`.
    #[must_use]
    pub fn smooth_union(self, other: Shape, k: f64) -> Shape {
        Shape::SmoothUnion(Box::new(self), Box::new(other), k)
    }
}

/// `shape`'s distance at every voxel of `grid` (rows in parallel).
#[must_use]
pub fn shape_field(shape: &Shape, grid: &FieldGrid) -> Field {
    let [nx, ny, _] = grid.dims.map(|d| d as usize);
    let mut values = vec![0.0f32; grid.voxel_count() as usize];
    values
        .par_chunks_mut(nx)
        .enumerate()
        .for_each(|(row, out)| {
            let (j, k) = ((row % ny) as u32, (row / ny) as u32);
            for (i, v) in out.iter_mut().enumerate() {
                *v = shape.distance(grid.point(i as u32, j, k)) as f32;
            }
        });
    Field {
        grid: *grid,
        values,
    }
}
