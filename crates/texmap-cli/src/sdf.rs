//! `texmap sdf`: a signed distance field from a mesh or a scan, written as NIfTI or NRRD.
//!
//! - `texmap sdf MESH.obj|.gltf|.glb|.toml --res N [--pad P] -o out.nii.gz`: the exact
//!   distance to the mesh's world-space triangles, signed by the winding number, on the grid
//!   of `../shared/peers/sdf_ref.py mesh` (the bounding box grown by P × its largest side,
//!   N cubic voxels along that side).
//! - `texmap sdf SCAN.nii|.nii.gz|.nrrd|.nhdr --threshold T -o out.nii.gz`: inside is
//!   `value ≥ T`; the exact Euclidean distance transform on the scan's own grid and spacing,
//!   written with the scan's placement (the rule of `sdf_ref.py mask`).
//!
//! Every check (flags that do not apply, the output's name, the memory the field needs
//! against `--max-memory`) runs before the work; a failure is one line naming the file and
//! nothing is written. The output is written atomically.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use texmap::scene::{load, LoadOptions};
use texmap::volume::sdf::{
    mask_field, mesh_field, Field, FieldFormat, FieldGrid, Mask, MeshFieldStats, Triangles,
};
use texmap::volume::{load_scalars_with, VolumeOptions};
use texmap::Error;

use crate::render::limits;

#[derive(Args)]
pub struct SdfArgs {
    /// A mesh (.obj, .gltf, .glb, or a .toml scene) or a scan (.nii, .nii.gz, .nrrd, .nhdr).
    input: PathBuf,
    /// The output field: .nii, .nii.gz or .nrrd (f32).
    #[arg(short, long)]
    output: PathBuf,
    /// Meshes: voxels along the padded box's largest side [default: 128].
    #[arg(long)]
    res: Option<u32>,
    /// Meshes: the margin around the mesh on every side, as a fraction of its largest side
    /// [default: 0.1].
    #[arg(long)]
    pad: Option<f64>,
    /// Scans: voxels with a value at or above this are inside (required for a scan).
    #[arg(long, allow_negative_numbers = true)]
    threshold: Option<f64>,
    /// Worker threads (default: every core); the field is the same for any count.
    #[arg(long)]
    threads: Option<usize>,
    /// Refuse an input or a field that would need more memory than this (K, M, G, T
    /// suffixes; default 4G).
    #[arg(long, value_parser = limits::parse_bytes)]
    max_memory: Option<u64>,
    /// Print one JSON line (grid, timings) instead of text.
    #[arg(long)]
    json: bool,
}

/// What the input is.
enum Kind {
    Mesh,
    Scan,
}

fn kind_of(path: &Path) -> Result<Kind, Error> {
    let name = path.to_string_lossy().to_ascii_lowercase();
    if [".obj", ".gltf", ".glb", ".toml"]
        .iter()
        .any(|e| name.ends_with(e))
    {
        Ok(Kind::Mesh)
    } else if [".nii", ".nii.gz", ".nrrd", ".nhdr"]
        .iter()
        .any(|e| name.ends_with(e))
    {
        Ok(Kind::Scan)
    } else {
        Err(Error::parameter(format!(
            "{}: neither a mesh (.obj, .gltf, .glb, .toml) nor a scan (.nii, .nii.gz, .nrrd, \
             .nhdr)",
            path.display()
        )))
    }
}

/// Bytes a mesh field needs besides the loaded scene: the values, their encoded copy, and
/// the tree (triangles twice, nodes and dipoles).
fn mesh_bytes(voxels: u64, triangles: u64) -> u64 {
    voxels
        .saturating_mul(8)
        .saturating_add(triangles.saturating_mul(160))
}

/// Bytes a scan field needs besides the loaded values: the mask and its complement, two
/// squared-distance arrays, one pass's planes, the field and its encoded copy.
fn scan_bytes(voxels: u64) -> u64 {
    voxels.saturating_mul(2 + 8 + 8 + 8 + 4 + 4)
}

fn check_memory(path: &Path, need: u64, max: u64, what: &str) -> Result<(), Error> {
    if need > max {
        return Err(Error::limits(
            path,
            format!(
                "{what} needs about {} MiB, above --max-memory {} MiB",
                need.div_ceil(1 << 20),
                max >> 20
            ),
        ));
    }
    Ok(())
}

pub fn run(args: SdfArgs) -> Result<(), Error> {
    let start = Instant::now();
    let kind = kind_of(&args.input)?;
    let format = FieldFormat::for_path(&args.output)?;
    limits::check_output(&args.output, &[args.input.as_path()])?;
    let threads = limits::frames_and_threads(1, args.threads)?;
    let max_memory = args.max_memory.unwrap_or(texmap::files::DEFAULT_MAX_BYTES);
    match kind {
        Kind::Mesh if args.threshold.is_some() => {
            return Err(Error::parameter(format!(
                "--threshold applies to scans; {} is a mesh",
                args.input.display()
            )))
        }
        Kind::Scan if args.res.is_some() || args.pad.is_some() => {
            return Err(Error::parameter(format!(
                "--res and --pad apply to meshes; {} is a scan (its field has the scan's grid)",
                args.input.display()
            )))
        }
        Kind::Scan if args.threshold.is_none() => {
            return Err(Error::parameter(format!(
                "{}: a scan needs --threshold T (inside: value ≥ T)",
                args.input.display()
            )))
        }
        _ => {}
    }
    if let Some(t) = args.threshold {
        if !t.is_finite() {
            return Err(Error::parameter(format!("--threshold {t} is not finite")));
        }
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::parameter(format!("--threads: {e}")))?;
    let (field, mut report) = match kind {
        Kind::Mesh => pool.install(|| build_mesh(&args, max_memory))?,
        Kind::Scan => pool.install(|| build_scan(&args, max_memory))?,
    };
    let t = Instant::now();
    let bytes = format
        .encode(&field)
        .map_err(|e| Error::parameter(format!("{}: {e}", args.output.display())))?;
    crate::output::write_bytes(&args.output, &bytes)?;
    let (lo, hi) = field.range();
    let g = &field.grid;
    let sp = g.spacing();
    let origin = g.point(0, 0, 0);
    report.insert("grid".into(), serde_json::json!(g.dims));
    report.insert("spacing".into(), serde_json::json!(sp.to_array()));
    report.insert("origin".into(), serde_json::json!(origin.to_array()));
    report.insert("min".into(), serde_json::json!(lo));
    report.insert("max".into(), serde_json::json!(hi));
    report.insert(
        "threads".into(),
        serde_json::json!(pool.current_num_threads()),
    );
    report.insert("write_ms".into(), ms(t));
    report.insert("total_ms".into(), ms(start));
    report.insert(
        "out".into(),
        serde_json::json!(args.output.display().to_string()),
    );
    if args.json {
        crate::output::stdout(&format!("{}\n", serde_json::Value::Object(report)))
    } else {
        crate::output::stdout(&format!(
            "{}: {}x{}x{} voxels of {:.6} ({} to {}), field {:.3} to {:.3}, {} ms in all\n",
            args.output.display(),
            g.dims[0],
            g.dims[1],
            g.dims[2],
            sp.max_element(),
            format_point(origin),
            format_point(g.point(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1)),
            lo,
            hi,
            report["total_ms"]
        ))
    }
}

type Report = serde_json::Map<String, serde_json::Value>;

fn ms(t: Instant) -> serde_json::Value {
    serde_json::json!((t.elapsed().as_secs_f64() * 1e4).round() / 10.0)
}

fn format_point(p: glam::DVec3) -> String {
    format!("({:.4}, {:.4}, {:.4})", p.x, p.y, p.z)
}

fn build_mesh(args: &SdfArgs, max_memory: u64) -> Result<(Field, Report), Error> {
    let path = &args.input;
    let t = Instant::now();
    let mut options = LoadOptions::default()
        .lenient(true)
        .max_buffer_bytes(max_memory.min(1 << 30));
    options.max_volume_bytes = max_memory;
    let loaded = load(path, &options)?;
    for w in &loaded.warnings {
        crate::output::stderr_line(&format!("texmap: warning: {w}"));
    }
    let tris = loaded.scene.world_triangles();
    drop(loaded);
    let load_ms = ms(t);
    let (field, stats) = mesh_to_field(
        path,
        &tris,
        args.res.unwrap_or(128),
        args.pad.unwrap_or(0.1),
        max_memory,
    )?;
    let mut r = Report::new();
    r.insert(
        "input".into(),
        serde_json::json!(path.display().to_string()),
    );
    r.insert("kind".into(), serde_json::json!("mesh"));
    r.insert("triangles".into(), serde_json::json!(tris.len()));
    r.insert("load_ms".into(), load_ms);
    r.insert("tree_ms".into(), serde_json::json!(round1(stats.tree_ms)));
    r.insert("fill_ms".into(), serde_json::json!(round1(stats.fill_ms)));
    r.insert(
        "sdf_ms".into(),
        serde_json::json!(round1(stats.tree_ms + stats.fill_ms)),
    );
    r.insert(
        "winding_evaluations".into(),
        serde_json::json!(stats.winding_evaluations),
    );
    Ok((field, r))
}

/// The distance field of `tris` (from `path`) on `sdf_ref.py`'s grid of `res` voxels with
/// margin `pad`, after the checks: triangles present, a grid that fits `max_memory`.
pub(crate) fn mesh_to_field(
    path: &Path,
    tris: &Triangles,
    res: u32,
    pad: f64,
    max_memory: u64,
) -> Result<(Field, MeshFieldStats), Error> {
    let (lo, hi) = tris
        .bounds()
        .ok_or_else(|| Error::decode(path, "has no triangles: there is no surface to measure"))?;
    let grid = FieldGrid::around_box(lo, hi, res, pad)
        .map_err(|e| Error::parameter(format!("{}: {e}", path.display())))?;
    check_memory(
        path,
        mesh_bytes(grid.voxel_count(), tris.len() as u64),
        max_memory,
        &format!(
            "a {}x{}x{} field of {} triangles",
            grid.dims[0],
            grid.dims[1],
            grid.dims[2],
            tris.len()
        ),
    )?;
    mesh_field(tris, &grid).map_err(|e| match e {
        Error::Parameter(m) => Error::decode(path, m),
        other => other,
    })
}

/// The distance field of the scan at `path` thresholded at `threshold` (inside: value ≥
/// it), after the checks: a finite threshold within the scan's values, memory within
/// `max_memory`. Also the number of inside voxels and the load and transform times (ms).
pub(crate) fn scan_to_field(
    path: &Path,
    threshold: f64,
    max_memory: u64,
) -> Result<(Field, usize, [f64; 2]), Error> {
    let t = Instant::now();
    if !threshold.is_finite() {
        return Err(Error::parameter(format!(
            "--threshold {threshold} is not finite"
        )));
    }
    let scan = load_scalars_with(path, None, &VolumeOptions::default().max_bytes(max_memory))?;
    let voxels: u64 = scan.dims.iter().map(|&d| u64::from(d)).product();
    check_memory(
        path,
        scan_bytes(voxels).saturating_add(voxels * 4),
        max_memory,
        &format!(
            "the distance field of {}x{}x{} voxels",
            scan.dims[0], scan.dims[1], scan.dims[2]
        ),
    )?;
    let (lo, hi) = scan
        .values
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if !(threshold > f64::from(lo) && threshold <= f64::from(hi)) {
        return Err(Error::parameter(format!(
            "{}: --threshold {threshold} is outside the scan's values ({lo} to {hi}): it \
             must be above the lowest and at most the highest, so that some voxels are \
             inside and some outside",
            path.display()
        )));
    }
    let load_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    let grid = FieldGrid {
        dims: scan.dims,
        world_from_voxel: scan.world_from_voxel.as_dmat4(),
    };
    let mask = Mask::threshold(scan.dims, &scan.values, threshold);
    let inside = mask.inside.iter().filter(|&&b| b).count();
    drop(scan);
    let field = mask_field(&mask, &grid).map_err(|e| match e {
        Error::Parameter(m) => Error::decode(path, m),
        other => other,
    })?;
    Ok((field, inside, [load_ms, t.elapsed().as_secs_f64() * 1e3]))
}

fn round1(x: f64) -> f64 {
    (x * 10.0).round() / 10.0
}

fn build_scan(args: &SdfArgs, max_memory: u64) -> Result<(Field, Report), Error> {
    let path = &args.input;
    let threshold = args.threshold.unwrap_or_default();
    let (field, inside, [load_ms, edt_ms]) = scan_to_field(path, threshold, max_memory)?;
    let mut r = Report::new();
    r.insert(
        "input".into(),
        serde_json::json!(path.display().to_string()),
    );
    r.insert("kind".into(), serde_json::json!("scan"));
    r.insert("threshold".into(), serde_json::json!(threshold));
    r.insert("inside_voxels".into(), serde_json::json!(inside));
    r.insert("load_ms".into(), serde_json::json!(round1(load_ms)));
    r.insert("edt_ms".into(), serde_json::json!(round1(edt_ms)));
    Ok((field, r))
}
