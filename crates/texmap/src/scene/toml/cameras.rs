//! `[[cameras]]` → [`Camera`]: perspective (`fov`, vertical degrees, default 60) or
//! orthographic (`height`, the visible world height, required). Each projection refuses the
//! other's key rather than ignoring it, so a half-edited camera is an error, not a surprise.

use glam::Vec3;

use super::spec::CameraSpec;
use crate::camera::{Camera, CameraProjection};

/// The camera a `[[cameras]]` entry describes, validated; the error is the entry's problem,
/// for the caller to prefix with the file and the entry.
pub(super) fn camera(c: &CameraSpec) -> Result<Camera, String> {
    let projection = match (c.projection.as_deref(), c.fov, c.height) {
        (None | Some("perspective"), fov, None) => CameraProjection::Perspective {
            fov_y_deg: fov.unwrap_or(60.0),
        },
        (Some("orthographic"), None, Some(height)) => CameraProjection::Orthographic {
            half_height: 0.5 * height,
        },
        (Some("orthographic"), None, None) => {
            return Err("an orthographic camera needs `height` (visible world height)".to_string())
        }
        (Some("orthographic"), Some(_), _) => {
            return Err(
                "`fov` is for perspective cameras; orthographic ones take `height`".to_string(),
            )
        }
        (None | Some("perspective"), _, Some(_)) => {
            return Err(
                "`height` is for orthographic cameras; perspective ones take `fov`".to_string(),
            )
        }
        (Some(other), _, _) => {
            return Err(format!(
                "projection {other:?} is not perspective or orthographic"
            ))
        }
    };
    let cam = Camera {
        eye: Vec3::from(c.eye),
        target: Vec3::from(c.target),
        up: Vec3::from(c.up),
        projection,
        near: c.near,
        far: c.far,
    };
    cam.validate().map_err(|e| e.to_string())?;
    Ok(cam)
}
