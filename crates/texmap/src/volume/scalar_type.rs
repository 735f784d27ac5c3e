//! The voxel types of volume files (`u8` … `f64`): their sizes, names and the spellings the
//! loaders and the command line accept.
//!
//! A volume keeps the type it was read as ([`super::grid::Volume::scalar_type`]) for listings
//! only: values are converted to `f32` on load and then to 16-bit levels, whatever the type.

/// Voxel types the loaders read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScalarType {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    F32,
    F64,
}

impl ScalarType {
    /// Bytes per voxel.
    #[must_use]
    pub fn size(self) -> usize {
        match self {
            ScalarType::U8 | ScalarType::I8 => 1,
            ScalarType::U16 | ScalarType::I16 => 2,
            ScalarType::U32 | ScalarType::I32 | ScalarType::F32 => 4,
            ScalarType::F64 => 8,
        }
    }

    /// Parses `u8`, `uint8`, `i16`, `int16`, `u16`, `uint16`, `f32`, `float32`, … .
    #[must_use]
    pub fn parse(s: &str) -> Option<ScalarType> {
        Some(match s {
            "u8" | "uint8" => ScalarType::U8,
            "i8" | "int8" => ScalarType::I8,
            "u16" | "uint16" => ScalarType::U16,
            "i16" | "int16" => ScalarType::I16,
            "u32" | "uint32" => ScalarType::U32,
            "i32" | "int32" => ScalarType::I32,
            "f32" | "float32" | "float" => ScalarType::F32,
            "f64" | "float64" | "double" => ScalarType::F64,
            _ => return None,
        })
    }
}

impl std::fmt::Display for ScalarType {
    /// `u8`, `i16`, `f32`, … (the names [`ScalarType::parse`] reads).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ScalarType::U8 => "u8",
            ScalarType::I8 => "i8",
            ScalarType::U16 => "u16",
            ScalarType::I16 => "i16",
            ScalarType::U32 => "u32",
            ScalarType::I32 => "i32",
            ScalarType::F32 => "f32",
            ScalarType::F64 => "f64",
        })
    }
}
