//! Procedural textures: Perlin's improved noise and the solid textures built on it.

pub mod perlin;
pub mod solid;

pub use solid::Solid;
