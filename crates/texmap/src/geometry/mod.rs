//! Geometry processing: texture-coordinate generation (projection parameterizations).

pub mod texgen;

pub use texgen::Projection;
