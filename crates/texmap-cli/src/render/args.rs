//! The flags of `texmap render`: `RenderArgs` (clap), the enums behind their values and the
//! parsers of sizes, vectors and colours.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use glam::{Vec3, Vec4};
use texmap::shading::shadow::ShadowFilter;
use texmap::texture::{Filter, Storage, Wrap};

use super::limits;
use crate::formats::OutputFormat;

#[derive(Args, Clone)]
pub struct RenderArgs {
    /// `builtin:demo` (default), `builtin:plane`, `builtin:sphere`, `builtin:marble`, a scene
    /// file (`.gltf`, `.glb`, `.obj` or `.toml`), a volume (`.nii`, `.nii.gz`, `.nrrd`,
    /// `.nhdr`, `.raw`), or a folder (its .gltf, .glb, .obj and .toml files, sorted by
    /// name). Several are a batch: each is rendered in turn, a failure reported and the rest
    /// still rendered.
    #[arg(value_name = "SCENE")]
    pub(crate) inputs: Vec<String>,
    /// The input being rendered (one of `inputs`, set by the batch).
    #[arg(skip)]
    pub(crate) scene: Option<String>,
    /// A file naming inputs, one path a line (relative paths from the current folder; blank
    /// lines and lines starting with # are skipped), after the SCENE arguments.
    #[arg(long, value_name = "FILE")]
    pub(crate) list: Option<PathBuf>,
    /// A missing or undecodable texture becomes a warning and a magenta placeholder.
    #[arg(long)]
    pub(crate) lenient: bool,
    /// A glTF material variant (KHR_materials_variants; `texmap info FILE` lists them): each
    /// primitive takes the material the variant maps it to.
    #[arg(long, value_name = "NAME")]
    pub(crate) variant: Option<String>,
    /// Let a file's references leave its folder (`..`, absolute paths).
    #[arg(long)]
    pub(crate) allow_outside_paths: bool,
    /// Ignore the file's own camera and frame what is drawn as the peer scripts do, so their
    /// images line up: meshes from +z as `gl_render.py`, volumes along +y as
    /// `vtk_volume.py` (without it, a file without a camera is seen in a three-quarter view,
    /// a scan facing its patient).
    #[arg(long)]
    pub(crate) auto_camera: bool,
    /// A standard view of everything drawn, in place of the file's camera: from +z (front),
    /// −z, −x, +x, +y (top, −z up), −y, or (1, 1, 1) (iso); the bounding sphere in frame.
    #[arg(long, value_enum)]
    pub(crate) view: Option<ViewArg>,
    /// Output image, its format from the extension: `.png` (8/16-bit sRGB), `.exr` (OpenEXR,
    /// 32-bit float linear RGBA, premultiplied), `.hdr` (Radiance, linear RGB), `.jpg`,
    /// `.gif` or `.apng` (animations: every frame in one file); `-` is stdout (PNG unless
    /// --format). `{frame}` (`{frame:06}`: 6 digits) is the frame number, counted from 1,
    /// `{scene}` the input's name [default: texmap-{scene}.png, texmap-{scene}-{frame}.png
    /// for several frames; the extension of --format].
    #[arg(short = 'o', long = "output")]
    pub(crate) output: Option<PathBuf>,
    /// The output's format where its name does not say (`-`, a device, no extension); a name
    /// with another format's extension is refused.
    #[arg(long, value_enum)]
    pub(crate) format: Option<OutputFormat>,
    /// Keep alpha, for compositing: the background is left out (unless --background names
    /// one), alpha is the coverage of the surfaces and the opacity of the volumes, and PNG is
    /// written RGBA with straight alpha. OpenEXR always carries alpha; Radiance HDR has none.
    #[arg(long)]
    pub(crate) alpha: bool,
    /// Bits a channel of PNG and APNG: 8 or 16 (sRGB-encoded either way).
    #[arg(long, value_name = "8|16", default_value_t = 8)]
    pub(crate) bit_depth: u8,
    /// JPEG quality, 1–100 [default: 90].
    #[arg(long, value_name = "Q")]
    pub(crate) quality: Option<u8>,
    /// Frames a second of an animation (.gif, .apng), 1–100 [default: 25].
    #[arg(long, value_name = "N")]
    pub(crate) fps: Option<u16>,
    /// Image size, WxH.
    #[arg(long, default_value = "640x360", value_parser = parse_size)]
    pub(crate) size: (u32, u32),
    /// Camera position x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) eye: Option<Vec3>,
    /// Point the camera looks at, x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) target: Option<Vec3>,
    /// Camera up vector, x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) up: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(long)]
    pub(crate) fov: Option<f32>,
    /// Orthographic projection showing HEIGHT world units vertically (the width follows the
    /// image's aspect); without a value, the height that frames the scene's bounding sphere.
    #[arg(
        long,
        value_name = "HEIGHT",
        num_args = 0..=1,
        allow_negative_numbers = true,
        conflicts_with = "fov"
    )]
    pub(crate) ortho: Option<Option<f32>>,
    // The help is the library's list of names (a doc comment cannot name a constant).
    #[arg(long, value_parser = Filter::parse, help = Filter::SPELLINGS)]
    pub(crate) filter: Option<Filter>,
    #[arg(long, value_parser = Wrap::parse, help = Wrap::SPELLINGS)]
    pub(crate) wrap: Option<Wrap>,
    /// Texture coordinate scale: multiplies every texture's coordinates (the plane's repeat
    /// count, 64 by default, as in gl_render.py).
    #[arg(long)]
    pub(crate) uv_scale: Option<f32>,
    /// An image that becomes every material's base-colour texture (materials with a
    /// procedural colour keep theirs).
    #[arg(long)]
    pub(crate) texture: Option<PathBuf>,
    /// What --texture's 8/16-bit channels hold [default: srgb].
    #[arg(long, value_enum)]
    pub(crate) color_space: Option<ColorSpaceArg>,
    /// LOD rule of every texture: gl (longer derivative) or rss (root of the sum of squares,
    /// the article's).
    #[arg(long, value_enum)]
    pub(crate) lod_rule: Option<LodRuleArg>,
    /// Added to every texture's level of detail.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) lod_bias: Option<f32>,
    /// The lowest level of detail any texture read uses (GL's TEXTURE_MIN_LOD).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) min_lod: Option<f32>,
    /// The highest level of detail any texture read uses (GL's TEXTURE_MAX_LOD; 0 reads the
    /// full-size image only).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) max_lod: Option<f32>,
    /// Border colour r,g,b,a (linear, straight alpha, each in 0..1) read outside the image
    /// with --wrap border.
    #[arg(long, value_parser = parse_rgba)]
    pub(crate) border: Option<Vec4>,
    /// perspective | affine | subdivide [default: perspective].
    #[arg(long, value_enum)]
    pub(crate) interp: Option<InterpArg>,
    /// Largest affine error in pixels before --interp subdivide splits a triangle
    /// [default: 0.5].
    #[arg(long)]
    pub(crate) subdivide_error: Option<f32>,
    /// flat | gouraud | phong [default: phong].
    #[arg(long, value_enum)]
    pub(crate) shading: Option<ShadingArg>,
    /// zbuffer | depth-sort [default: zbuffer].
    #[arg(long, value_enum)]
    pub(crate) visibility: Option<VisibilityArg>,
    /// none | back | front, for every single-sided material [default: each material's own: back for
    /// glTF's single-sided materials (its specification's rule), none for OBJ and TOML unless
    /// the material's `cull` key says].
    #[arg(long, value_enum)]
    pub(crate) cull: Option<CullArg>,
    /// Multisample anti-aliasing of the meshes: 1, 2, 4, 8 or 16 samples per pixel.
    #[arg(long)]
    pub(crate) msaa: Option<u32>,
    /// Supersampling of the meshes: render N×N samples per pixel and average.
    #[arg(long)]
    pub(crate) ssaa: Option<u32>,
    /// Texture colour only, no lighting.
    #[arg(long)]
    pub(crate) unlit: bool,
    /// Shadow maps: every light casts shadows; `--shadows=false`: none does, whatever the
    /// scene file says.
    #[arg(long, num_args = 0..=1, require_equals = true, default_missing_value = "true")]
    pub(crate) shadows: Option<bool>,
    /// Shadow map texels a side (each cube face of a point light) [default: 2048].
    #[arg(long, value_name = "N")]
    pub(crate) shadow_map_size: Option<u32>,
    // The help is the library's list of names.
    #[arg(long, value_parser = ShadowFilter::parse, help = ShadowFilter::SPELLINGS)]
    pub(crate) shadow_filter: Option<ShadowFilter>,
    /// Constant shadow bias, in map texels [default: 0.5].
    #[arg(long, value_name = "TEXELS")]
    pub(crate) shadow_bias: Option<f32>,
    /// Slope-scaled shadow bias: texels per unit of tan θ (θ between normal and light)
    /// [default: 1].
    #[arg(long, value_name = "TEXELS")]
    pub(crate) shadow_slope_bias: Option<f32>,
    /// Normal offset of shadow lookups, in map texels [default: 0.5].
    #[arg(long, value_name = "TEXELS")]
    pub(crate) shadow_normal_offset: Option<f32>,
    /// PCSS: angular diameter of directional lights, degrees [default: 2].
    #[arg(long, value_name = "DEG")]
    pub(crate) shadow_light_angle: Option<f32>,
    /// PCSS: radius of point and spot lights, world units [default: 0.05].
    #[arg(long, value_name = "R")]
    pub(crate) shadow_light_radius: Option<f32>,
    /// An environment map: a 2:1 equirectangular image (HDR, EXR, PNG…), a 4:3 or 3:4 cross,
    /// a 1:1 sphere map, or a folder of six faces posx…negz. Replaces the scene's own; it is
    /// drawn behind the surfaces, lights them (image-based light, in place of the uniform
    /// ambient light) and is seen in their reflections and refractions.
    #[arg(long, value_name = "FILE")]
    pub(crate) env: Option<PathBuf>,
    /// Rotates the environment about +y, in degrees.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub(crate) env_rotate: Option<f32>,
    /// Multiplies the environment's radiance.
    #[arg(long, value_name = "K")]
    pub(crate) env_intensity: Option<f32>,
    /// What is seen where no surface is: the environment (the scene's or --env's), the
    /// scene's colour, or nothing (transparent black) [default: env with an environment, else
    /// color; none with --alpha].
    #[arg(long, value_enum)]
    pub(crate) background: Option<BackgroundArg>,
    /// Image-based light from the environment (irradiance, and the prefiltered specular of
    /// metallic-roughness materials); off lights with the scene's uniform ambient light
    /// [default: on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) ibl: Option<Switch>,
    /// The scene's slide projectors (`[[projectors]]`): off draws the scene without their
    /// light [default: on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) projectors: Option<Switch>,
    /// Reflected and refracted environment (K_R, K_T, transmission) [default: on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) reflections: Option<Switch>,
    /// Texture layers (multitexturing, detail maps) of the scene's materials [default: on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) layers: Option<Switch>,
    /// Light maps: baked irradiance multiplying the diffuse term [default: on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) light_maps: Option<Switch>,
    /// Toon shading: off drops the scene's; on gives every lit material without one a ramp
    /// of three bands (no outline) [default: the scene's].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) toon: Option<Switch>,
    /// How image textures are held in memory: `decoded` (sRGB colour as 16-bit linear
    /// premultiplied, 8 bytes a texel: the fastest reads; linear data as `rgba8`), `native` (as the file stores them: 8-bit RGBA in 4
    /// bytes, RGB in 3), `compressed` (DDS/KTX/KTX2 BC1–BC7 files stay block-compressed,
    /// each block decoded when first read through a small cache per thread; other images as
    /// native), `rgba8` (8-bit RGB and RGBA as RGBA8 in 4 bytes, sRGB or linear, mip chain
    /// built in 8 bits, read through the same fixed-point path as decoded) [default: decoded].
    #[arg(long, value_parser = parse_storage, value_name = "decoded|native|compressed|rgba8")]
    pub(crate) texture_storage: Option<Storage>,
    /// The resident page cache of each virtual texture in the scene, e.g. 64M (replaces the
    /// scene's `budget_mib`): pages of 128² texels plus a 4-texel border, 148 KiB each,
    /// least recently used evicted first. It must hold the texture's coarsest levels (one
    /// page each) and 4 pages more; the caches together count against --max-memory.
    #[arg(long, value_parser = limits::parse_bytes, value_name = "BYTES")]
    pub(crate) vt_budget: Option<u64>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub(crate) threads: Option<usize>,
    /// The most memory loading one input and the frame may take, e.g. 8G or 512M (default
    /// 4G): a larger request is refused before anything is allocated.
    #[arg(long, value_parser = limits::parse_bytes)]
    pub(crate) max_memory: Option<u64>,
    /// Turntable frames: frame k is the camera turned about its target by 360·(k−1)/N
    /// degrees (frame 1 is the requested view).
    #[arg(long, default_value_t = 1)]
    pub(crate) frames: u32,
    /// The frames rendered, A..B: inclusive, counted from 1, within --frames
    /// [default: 1..N].
    #[arg(long, value_name = "A..B")]
    pub(crate) frame_range: Option<String>,
    /// Render the I-th of N contiguous slices of the outputs (inputs × frames, in order),
    /// I counted from 1; `auto` takes the index from Slurm (SLURM_ARRAY_TASK_ID, _MIN,
    /// _COUNT) or Kubernetes (JOB_COMPLETION_INDEX, with --shard-count).
    #[arg(long, value_name = "I/N|auto")]
    pub(crate) shard: Option<String>,
    /// With --shard auto under a Kubernetes Indexed Job: the number of shards (its
    /// completions).
    #[arg(long, value_name = "N")]
    pub(crate) shard_count: Option<u64>,
    /// Skip an output that already exists and is complete: it decodes whole, at --size, with
    /// every frame of an animation.
    #[arg(long)]
    pub(crate) skip_existing: bool,
    /// Append one JSON line per output written (input, frame, settings, bytes, SHA-256, ms)
    /// to FILE, each line in one write; `texmap manifest verify FILE` checks them.
    #[arg(long, value_name = "FILE")]
    pub(crate) manifest: Option<PathBuf>,
    /// Triangle count of builtin:sphere [default: 199200].
    #[arg(long)]
    pub(crate) tris: Option<usize>,
    /// Print statistics as JSON on stdout.
    #[arg(long)]
    pub(crate) stats: bool,
    /// Render and time every frame, and write no image: the frames run back to back, as a
    /// benchmark times them (with --stats, their times; without, a line with the median).
    /// The output's options (-o, --format, --manifest, --skip-existing, --bit-depth,
    /// --quality, --fps) are refused with it.
    #[arg(long)]
    pub(crate) discard: bool,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub(crate) quiet: bool,
    #[command(flatten)]
    pub volume: Box<crate::volume::VolumeArgs>,
    #[command(flatten)]
    pub field: Box<crate::field::FieldArgs>,
    #[command(flatten)]
    pub relief: Box<super::relief::ReliefArgs>,
    #[command(flatten)]
    pub section: Box<crate::section::SectionArgs>,
}

impl RenderArgs {
    /// The options that say how or where an output is written, each with whether it was
    /// given: refused where nothing is written (`--discard`, the viewer).
    pub(crate) fn output_options(&self) -> [(&'static str, bool); 7] {
        [
            ("-o", self.output.is_some()),
            ("--format", self.format.is_some()),
            ("--bit-depth", self.bit_depth != 8),
            ("--quality", self.quality.is_some()),
            ("--fps", self.fps.is_some()),
            ("--skip-existing", self.skip_existing),
            ("--manifest", self.manifest.is_some()),
        ]
    }
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum BackgroundArg {
    Env,
    Color,
    None,
}
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum ViewArg {
    Front,
    Back,
    Left,
    Right,
    Top,
    Bottom,
    Iso,
}
#[derive(Clone, Copy, PartialEq, Eq, Debug, ValueEnum)]
pub(crate) enum Switch {
    On,
    Off,
}
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum ColorSpaceArg {
    Srgb,
    Linear,
}
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum LodRuleArg {
    Gl,
    Rss,
}
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum InterpArg {
    Perspective,
    Affine,
    Subdivide,
}
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum ShadingArg {
    Flat,
    Gouraud,
    Phong,
}
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum VisibilityArg {
    Zbuffer,
    DepthSort,
}
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum CullArg {
    None,
    Back,
    Front,
}

pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .to_lowercase()
        .split_once('x')
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .ok_or("expected WxH")?;
    let w: u32 = w.parse().map_err(|_| "width is not a number")?;
    let h: u32 = h.parse().map_err(|_| "height is not a number")?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!("{w}x{h} is outside 1x1..16384x16384"));
    }
    Ok((w, h))
}

pub(crate) fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err("expected three finite numbers x,y,z".into());
    }
    Ok(Vec3::new(v[0], v[1], v[2]))
}

pub(crate) fn parse_rgba(s: &str) -> Result<Vec4, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    if v.len() != 4 || v.iter().any(|x| !(0.0..=1.0).contains(x)) {
        return Err("expected four numbers r,g,b,a in 0..1".into());
    }
    Ok(Vec4::new(v[0], v[1], v[2], v[3]))
}

/// A `--texture-storage` value, from the library's list of names.
pub(crate) fn parse_storage(s: &str) -> Result<Storage, String> {
    Storage::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Storage::NAMES.iter().map(|(n, _)| *n).collect();
        format!("{s:?} is not one of {}", names.join(", "))
    })
}

#[cfg(test)]
mod tests {
    use clap::{Args, Command};

    use super::*;

    fn command() -> Command {
        RenderArgs::augment_args(Command::new("render"))
    }

    #[test]
    fn filter_and_wrap_help_is_the_library_list() {
        let cmd = command();
        let help = |id: &str| {
            let arg = cmd.get_arguments().find(|a| a.get_id() == id);
            arg.and_then(|a| a.get_help()).map(|h| h.to_string())
        };
        assert_eq!(help("filter").as_deref(), Some(Filter::SPELLINGS));
        assert_eq!(help("wrap").as_deref(), Some(Wrap::SPELLINGS));
    }

    #[test]
    fn unknown_filter_and_wrap_names_are_refused_with_the_list() {
        let refused = |args: &[&str]| {
            let e = command().try_get_matches_from(args).unwrap_err();
            e.to_string()
        };
        for bad in ["aniso32", "aniso17-area", "aniso-area"] {
            let e = refused(&["render", "--filter", bad]);
            assert!(e.contains(Filter::SPELLINGS), "{bad}: {e}");
        }
        let e = refused(&["render", "--wrap", "tile"]);
        assert!(e.contains(Wrap::SPELLINGS), "{e}");
    }

    #[test]
    fn mipmapped_filter_names_reach_the_sampler() {
        let m = command()
            .try_get_matches_from(["render", "--filter", "nearest-mipmap-linear"])
            .unwrap();
        assert_eq!(
            m.get_one::<Filter>("filter").map(|f| f.name()).as_deref(),
            Some("nearest-mipmap-linear")
        );
        let m = command()
            .try_get_matches_from(["render", "--filter", "aniso5-area"])
            .unwrap();
        assert_eq!(
            m.get_one::<Filter>("filter").copied(),
            Some(Filter::Anisotropic {
                max_aniso: 5,
                lod: texmap::texture::AnisoLod::Area
            })
        );
    }
}
