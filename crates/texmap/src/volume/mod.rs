//! Volumes: scalar fields on a grid (CT, MRI), classified by transfer functions and rendered
//! by ray marching ([`raymarch`](fn@raymarch)) or by view-aligned texture slices
//! ([`slice`](mod@slice)).
//!
//! Conventions:
//! - Voxels are points (vertex-centred, as VTK and NIfTI): voxel `(i, j, k)` sits at
//!   `world_from_voxel · (i, j, k, 1)`, and the volume's box in voxel space is
//!   `[0, n − 1]` on each axis. The 3D texture's texel centres `(i + ½)/n` are the same points.
//! - Values are the file's values after its scale and offset (NIfTI `scl_slope`/`scl_inter`):
//!   Hounsfield units for CT. Transfer functions are written in those units.
//! - Lengths (`--step`, the opacity unit distance) are world units, i.e. the file's spacing
//!   units (mm for NIfTI and most NRRD), like VTK's `SampleDistance`.
//!
//! Files, in layers; a file imports only files of the layers above it or before it in its own
//! (no two files import each other, and this one only declares and re-exports):
//! - the grid: the voxel types of files (`scalar_type`), trilinear reads (`cell`), normals
//!   (`normals`), rays from the camera and the samples along them (`rays`), empty-space
//!   skipping (`bricks`), the camera that frames a box (`framing`), the [`Volume`] itself
//!   (`grid`), which way a scan's patient faces ([`patient`]) and its loaders ([`load`]);
//! - the options: [`transfer`] functions (and [`auto_transfer`], one chosen from a scan's
//!   values), how a sample reflects light (`shade`), the
//!   [`MarchParams`] (`params`), and what both methods share at the frame's edges (`output`);
//! - the ray marcher: the per-frame state and per-sample reads (`marcher`), the loops per
//!   mode (`composite`, `intensity`, `iso`) and the frame loop (`raymarch`);
//! - the other method, view-aligned slices ([`slice`](mod@slice)), and a volume as a scene
//!   holds it ([`scene_volume`]).
//! - orthogonal slice views ([`section`]): one plane of voxels drawn flat.
//! - signed distance fields ([`sdf`]): built from meshes, scans and analytic shapes, written
//!   as files the loaders read back; a field becomes a [`Volume`] to be rendered.

pub mod auto_transfer;
mod bricks;
mod cell;
mod composite;
mod composite_lanes;
mod framing;
mod grid;
mod intensity;
mod iso;
pub mod load;
mod marcher;
mod normals;
mod output;
mod params;
pub mod patient;
mod raymarch;
mod rays;
mod scalar_type;
pub mod scene_volume;
pub mod sdf;
pub mod section;
mod shade;
mod shaded_lanes;
pub mod slice;
pub mod transfer;

pub use bricks::{Bricks, BRICK};
pub use framing::vtk_camera_for_bounds;
pub use grid::Volume;
pub use iso::iso_hit;
pub use load::{
    load_scalars_with, load_volume, load_volume_with, RawDesc, ScalarGrid, VolumeOptions,
};
pub use params::{Classification, MarchParams, Mode, MAX_SAMPLES_PER_RAY};
pub use raymarch::raymarch;
pub use rays::{camera_ray, ray_distances_from_depth};
pub use scalar_type::ScalarType;
pub use scene_volume::{Method, SceneVolume};
pub use shade::Reflectance;
pub use slice::{render_slices, render_slices_until};
pub use transfer::{PreIntegrated, TransferFunction, TransferFunction2D, TransferLut};
