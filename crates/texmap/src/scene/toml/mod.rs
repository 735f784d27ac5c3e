//! TOML scene files: cameras, lights, materials with any texture channel, meshes from model
//! files or built-in primitives, and volumes. The format is documented in `docs/scenes.md`.
//!
//! Rules every table follows:
//! - Unknown keys are refused (a typo is an error naming the file and the line), and a
//!   table's bad value is an error naming the file and the table (`materials.wood: …`,
//!   `meshes[2]: …`), one line.
//! - Relative paths resolve from the scene file's folder. A scene file is written by its
//!   user, like a command line, so its own paths may go anywhere; the model files it names
//!   follow the folder rule inside their own folders. A scene file cannot include another.
//! - Colours are linear (RGB, or RGBA with straight alpha); angles are degrees.
//! - Meshes and volumes are placed alike: scale, then rotate (about x, then y, then z), then
//!   translate, or a column-major `matrix`; a mesh may generate its texture coordinates
//!   (`texgen`).
//! - Without lights in the file, surfaces get the peers' directional light and shaded
//!   volumes a headlight; with lights, both use the file's; `lights = []` means none.
//!
//! Files: `spec` (the tables as serde reads them), `document` (the file → [`Loaded`]),
//! then one file per kind of table: `cameras`, `lights`, `environment`, `materials`, `textures` and
//! `sampler` (texture tables), `procedural` (solid and projected colour sources), `meshes`,
//! `texgen`, `placement`, `volumes`, `projectors`, `layers` (texture layers, light maps, toon
//! shading), `relief` (parallax and displacement).
//!
//! [`Loaded`]: crate::scene::Loaded

mod cameras;
mod document;
mod environment;
mod layers;
mod lights;
mod materials;
mod meshes;
mod placement;
mod procedural;
mod projectors;
mod relief;
mod sampler;
mod spec;
mod texgen;
mod textures;
mod virtual_texture;
mod volumes;

#[cfg(test)]
mod tests;

pub use document::load;
