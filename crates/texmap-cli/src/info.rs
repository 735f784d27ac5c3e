//! `texmap info FILE`: what a model, scene or texture holds.

use std::path::PathBuf;

use clap::Args;
use texmap::camera::CameraProjection;
use texmap::scene::{Environment, LoadOptions, Loaded};
use texmap::shading::{AlphaMode, MapChannel, Procedural, ShadingModel, SolidChannel};
use texmap::texture::container::{read_texture_file, texture_from_file, Container, TextureFile};
use texmap::texture::load::{load_texture_with, Limits};
use texmap::texture::{ColorSpace, EnvironmentMap, Texture2D, TextureOptions};
use texmap::volume::{load_volume_with, SceneVolume, Volume};
use texmap::Error;

#[derive(Args)]
pub struct InfoArgs {
    /// A scene (.gltf, .glb, .obj, .toml), an image, a texture file (DDS, KTX, KTX2), or a
    /// volume.
    file: PathBuf,
    /// A missing texture becomes a warning and a placeholder.
    #[arg(long)]
    lenient: bool,
    /// Describe the scene under this glTF material variant (KHR_materials_variants).
    #[arg(long, value_name = "NAME")]
    variant: Option<String>,
    /// Let the file's references leave its folder.
    #[arg(long)]
    allow_outside_paths: bool,
    /// How the textures would be held (decoded, native, compressed, rgba8), to see their memory.
    #[arg(long, value_parser = crate::render::parse_storage, value_name = "decoded|native|compressed|rgba8")]
    texture_storage: Option<texmap::texture::Storage>,
    #[command(flatten)]
    raw: crate::volume::RawArgs,
}

/// Appends a line to a `String` (writing to a `String` cannot fail).
macro_rules! outln {
    ($out:expr, $($t:tt)*) => {{
        use std::fmt::Write as _;
        let _ = writeln!($out, $($t)*);
    }};
}

const IMAGE_EXTENSIONS: &[&str] = &["png", "jpg", "jpeg", "tga", "bmp", "hdr", "exr"];

pub fn run(args: InfoArgs) -> Result<(), Error> {
    let path = &args.file;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let storage = args.texture_storage.unwrap_or_default();
    let held = |t: &Texture2D| {
        format!(
            "  held {}{}: {} bytes with its mip levels",
            t.storage().name(),
            t.block_format()
                .map(|b| format!(" ({})", b.name()))
                .unwrap_or_default(),
            t.texel_bytes()
        )
    };
    let options = TextureOptions::default().with_storage(storage);
    if Container::of_file(path).is_some() {
        let file = read_texture_file(path, &Limits::default())?;
        let mut out = describe_texture_file(&file);
        if args.texture_storage.is_some() {
            // A 2D texture's memory as the renderer would hold it.
            let t = texture_from_file(&file, ColorSpace::Srgb, options)?;
            outln!(out, "{}", held(&t));
        }
        return crate::output::stdout(&out);
    }
    if IMAGE_EXTENSIONS.contains(&ext.as_str()) {
        let t = load_texture_with(path, ColorSpace::Srgb, &Limits::default(), options)?;
        let mut out = String::new();
        let out = &mut out;
        outln!(out, "{}: image", path.display());
        outln!(
            out,
            "  {}x{}, {:?}, {} mip levels",
            t.width(),
            t.height(),
            t.format(),
            t.levels().len()
        );
        outln!(out, "{}", held(&t));
        return crate::output::stdout(out);
    }
    let options = LoadOptions::default()
        .allow_outside_paths(args.allow_outside_paths)
        .lenient(args.lenient)
        .variant(args.variant.clone())
        .texture_storage(args.texture_storage.unwrap_or_default());
    if crate::volume::is_volume_path(&path.to_string_lossy()) {
        let vol = load_volume_with(path, args.raw.desc().as_ref(), &options.volume_options())?;
        let mut out = String::new();
        outln!(out, "{}: volume", path.display());
        outln!(out, "  {}", describe_volume(&vol));
        return crate::output::stdout(&out);
    }
    let loaded = texmap::scene::load(path, &options)?;
    if args.variant.is_some() && loaded.info.variant.is_none() {
        return Err(Error::parameter(format!(
            "{}: --variant names a glTF material variant (KHR_materials_variants); the scene \
             holds no glTF file with variants",
            path.display()
        )));
    }
    let mut out = String::new();
    print_scene(&mut out, path, &loaded);
    crate::output::stdout(&out)
}

/// The scene's virtual textures: size, levels, pages, what stays resident, the cache.
fn print_virtual_textures(out: &mut String, s: &texmap::scene::Scene) {
    use texmap::texture::virtual_texture::{PAGE_BORDER, PAGE_BYTES, PAGE_SIDE, PAGE_TEXELS};
    let virtuals = s.virtual_textures();
    if virtuals.is_empty() {
        return;
    }
    let mib = |b: f64| b / f64::from(1u32 << 20);
    outln!(out, "virtual textures: {}", virtuals.len());
    for (vt, _) in &virtuals {
        let l = vt.layout();
        let side = u64::from(vt.side());
        let tail = l.tail().count() as u64;
        let (wu, wv) = vt.wraps();
        outln!(
            out,
            "  {side}x{side}, {} levels, wrap {}/{}: {}",
            l.levels(),
            wu.name(),
            wv.name(),
            vt.describe()
        );
        outln!(
            out,
            "  whole it would be {:.1} GiB (RGBA16F with its mip levels)",
            (side * side * 8) as f64 * 4.0 / 3.0 / f64::from(1u32 << 30)
        );
        outln!(
            out,
            "  pages: {PAGE_TEXELS}² texels + {PAGE_BORDER}-texel border ({PAGE_SIDE}² RGBA16F, {PAGE_BYTES} bytes); {} in all, {}² at level 0; levels {}..{} are one page each, pinned",
            l.total_pages(),
            l.pages(0),
            l.tail_start(),
            l.levels() - 1
        );
        outln!(
            out,
            "  cache: budget {:.2} MiB = {} pages ({tail} pinned); page tables {:.2} MiB",
            mib(vt.budget() as f64),
            vt.slots().0,
            mib(l.total_pages() as f64 * 4.0)
        );
    }
}

/// A texture container: its format, shape, levels and bytes.
fn describe_texture_file(f: &TextureFile) -> String {
    let mut out = String::new();
    let plural = |n: u32, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    outln!(
        out,
        "{}: {} texture",
        f.path().display(),
        f.container().name()
    );
    let space = if f.format().is_float() {
        "float, linear"
    } else if f.color_space() == ColorSpace::Srgb {
        "sRGB"
    } else {
        "8-bit, colour space unstated"
    };
    match f.transcoded_from() {
        Some(codec) => outln!(
            out,
            "  Basis Universal {codec}, transcoded to {} ({space})",
            f.format().name()
        ),
        None => outln!(out, "  format {} ({space})", f.format().name()),
    }
    outln!(
        out,
        "  {}x{}, depth {}, {}{}, {}, {}",
        f.width(),
        f.height(),
        f.depth(),
        plural(f.levels(), "mip level"),
        if f.has_full_chain() {
            " (full chain)"
        } else {
            ""
        },
        plural(f.faces(), "face"),
        plural(f.layers(), "layer")
    );
    let sizes: Vec<String> = (0..f.levels())
        .map(|l| {
            let (w, h, d) = f.level_size(l);
            if f.depth() > 1 {
                format!("{w}x{h}x{d}")
            } else {
                format!("{w}x{h}")
            }
        })
        .collect();
    outln!(out, "  levels: {}", sizes.join(", "));
    outln!(
        out,
        "  bytes: file {}, texel data {}, decoded {} ({})",
        f.file_bytes(),
        f.texel_bytes(),
        f.decoded_bytes(),
        if f.format().is_float() {
            "RGBA f32"
        } else {
            "RGBA8"
        }
    );
    out
}

/// Which lights cast shadows and how their maps are made and read.
fn print_shadows(out: &mut String, s: &texmap::scene::Scene) {
    let casting: Vec<usize> = s
        .shadows
        .lights
        .iter()
        .copied()
        .filter(|&i| i < s.lights.len())
        .collect();
    let projectors = s.projectors.iter().filter(|p| p.shadows).count();
    if casting.is_empty() {
        if projectors > 0 {
            outln!(
                out,
                "shadows: no light casts; {projectors} projector(s) cast, maps {}², filter {}",
                s.shadows.params.map_size,
                s.shadows.params.filter.name()
            );
        } else {
            outln!(
                out,
                "shadows: none (no light casts; --shadows makes every light cast)"
            );
        }
        return;
    }
    let p = &s.shadows.params;
    let kinds: Vec<String> = casting
        .iter()
        .map(|&i| {
            let kind = match s.lights[i] {
                texmap::scene::Light::Directional { .. } => "directional",
                texmap::scene::Light::Point { .. } => "point, a cube of six maps",
                texmap::scene::Light::Spot { outer_deg, .. }
                    if outer_deg <= texmap::render::MAX_SPOT_MAP_DEG =>
                {
                    "spot"
                }
                texmap::scene::Light::Spot { .. } => "spot, a cube of six maps",
            };
            format!("[{i}] {kind}")
        })
        .collect();
    outln!(
        out,
        "shadows: {} cast{} ({}); maps {}², filter {}, bias {} + slope {} texels, normal offset {} \
         texels",
        casting.len(),
        if casting.len() == 1 { "s" } else { "" },
        kinds.join(", "),
        p.map_size,
        p.filter.name(),
        p.bias,
        p.slope_bias,
        p.normal_offset
    );
    if p.filter == texmap::shading::shadow::ShadowFilter::Pcss {
        outln!(
            out,
            "  pcss: directional lights {}° across, point and spot lights of radius {}",
            p.light_angle,
            p.light_radius
        );
    }
}

/// The slide projectors: where each stands and aims, its frustum, slide and light.
fn print_projectors(out: &mut String, s: &texmap::scene::Scene) {
    if s.projectors.is_empty() {
        return;
    }
    outln!(
        out,
        "projectors: {} (--projectors off draws without them)",
        s.projectors.len()
    );
    for (k, p) in s.projectors.iter().enumerate() {
        let t = &p.slide.texture;
        outln!(
            out,
            "  [{k}] position {:.3?} target {:.3?} fov {}° aspect {:.3}, slide {}x{} {}, light {:.3?}{}{}",
            p.position.to_array(),
            p.target.to_array(),
            p.fov_deg,
            p.aspect,
            t.width(),
            t.height(),
            p.slide.sampler.filter.name(),
            p.color.to_array(),
            if p.falloff { ", inverse-square" } else { ", no falloff" },
            if p.shadows { ", casts (its depth map)" } else { "" }
        );
    }
}

fn print_scene(out: &mut String, path: &std::path::Path, l: &Loaded) {
    let s = &l.scene;
    outln!(out, "{}: {}", path.display(), l.info.format);
    outln!(
        out,
        "meshes: {} ({} triangles, {} vertices)",
        s.meshes.len(),
        s.triangle_count(),
        s.meshes.iter().map(|m| m.positions.len()).sum::<usize>()
    );
    for (i, m) in s.meshes.iter().enumerate() {
        let name = l.info.mesh_names.get(i).map_or("", String::as_str);
        let mut attrs = vec!["POSITION"];
        for (has, a) in [
            (!m.normals.is_empty(), "NORMAL"),
            (!m.uvs.is_empty(), "TEXCOORD_0"),
            (!m.uvs1.is_empty(), "TEXCOORD_1"),
            (!m.colors.is_empty(), "COLOR_0"),
            (!m.tangents.is_empty(), "TANGENT"),
        ] {
            if has {
                attrs.push(a);
            }
        }
        outln!(
            out,
            "  [{i}] {name}: {} triangles, {} vertices, material {}, {}",
            m.triangle_count(),
            m.positions.len(),
            m.material,
            attrs.join(" ")
        );
    }
    print_virtual_textures(out, s);
    if !l.info.variants.is_empty() {
        let chosen = l
            .info
            .variant
            .as_deref()
            .map_or_else(String::new, |v| format!("; drawn: {v}"));
        outln!(
            out,
            "variants: {} ({}{chosen})",
            l.info.variants.len(),
            l.info.variants.join(", ")
        );
    }
    outln!(out, "materials: {}", s.materials.len());
    for (i, m) in s.materials.iter().enumerate() {
        let name = l.info.material_names.get(i).map_or("", String::as_str);
        let alpha = match m.alpha_mode {
            AlphaMode::Opaque => "opaque".to_string(),
            AlphaMode::Mask(c) => format!("mask {c}"),
            AlphaMode::Blend => "blend".to_string(),
        };
        let mut maps = Vec::new();
        if let Some(t) = &m.base_color_texture {
            maps.push(match &t.virtual_texture {
                Some(vt) => format!(
                    "base_color virtual {}x{} uv{}",
                    vt.side(),
                    vt.side(),
                    t.tex_coord
                ),
                None => format!(
                    "base_color {}x{} uv{}",
                    t.texture.width(),
                    t.texture.height(),
                    t.tex_coord
                ),
            });
        }
        for map in &m.maps {
            maps.push(format!(
                "{} {}x{} uv{}",
                map.channel.name(),
                map.slot.texture.width(),
                map.slot.texture.height(),
                map.slot.tex_coord
            ));
        }
        match &m.procedural {
            Some(Procedural::Solid {
                solid, antialias, ..
            }) => maps.push(format!(
                "colour solid {solid:?}{}",
                if *antialias { "" } else { " (not antialiased)" }
            )),
            Some(Procedural::Projected { slot, projection }) => maps.push(format!(
                "colour projected {projection:?} {}x{}",
                slot.texture.width(),
                slot.texture.height()
            )),
            Some(Procedural::Texture3D {
                texture, min, max, ..
            }) => {
                let [x, y, z] = texture.dims();
                maps.push(format!("colour 3D texture {x}x{y}x{z} over {min}..{max}"));
            }
            None => {}
        }
        for solid in &m.solid_maps {
            maps.push(match solid.channel {
                SolidChannel::Roughness { range } => {
                    format!("roughness solid {:?} {range:?}", solid.solid)
                }
                SolidChannel::Bump { scale } => {
                    format!("bump solid {:?} scale {scale}", solid.solid)
                }
            });
        }
        maps.extend(crate::render::relief::describe(m));
        let mut env_terms = String::new();
        if m.emissive != glam::Vec3::ZERO {
            // glTF's emissive factor times KHR_materials_emissive_strength, linear.
            let e = m.emissive;
            env_terms += &format!(", emissive ({:.3}, {:.3}, {:.3})", e.x, e.y, e.z);
        }
        if m.reflection > 0.0 {
            env_terms += &format!(", reflection K_R {}", m.reflection);
        }
        if m.transmission > 0.0 || m.map(MapChannel::Transmission).is_some() {
            env_terms += &format!(", transmission {}", m.transmission);
        }
        if m.ior != 1.5 {
            env_terms += &format!(", ior {}", m.ior);
        }
        env_terms += &describe_lobes(&m.lobes);
        let b = m.base_color;
        let model = match m.model {
            ShadingModel::Phong => format!(
                "Phong (K_A {}, K_D {}, K_S {}, n {})",
                m.ambient, m.diffuse, m.specular, m.shininess
            ),
            ShadingModel::MetallicRoughness => format!(
                "metallic-roughness (metallic {}, roughness {})",
                m.metallic, m.roughness
            ),
        };
        outln!(
            out,
            "  [{i}] {name}: {model}, base colour ({:.3}, {:.3}, {:.3}, {:.3}), {alpha}{env_terms}{}{}; maps: {}",
            b.x,
            b.y,
            b.z,
            b.w,
            if m.double_sided { ", double-sided" } else { "" },
            if m.unlit { ", unlit" } else { "" },
            if maps.is_empty() {
                "none".to_string()
            } else {
                maps.join(", ")
            }
        );
        for line in crate::detail_info::describe(m) {
            outln!(out, "      {line}");
        }
    }
    outln!(out, "textures: {}", l.info.textures.len());
    for t in &l.info.textures {
        outln!(
            out,
            "  {}: {}x{}, {:?}, {:?}, held {}{}, {} bytes{}",
            t.name,
            t.width,
            t.height,
            t.format,
            t.color_space,
            t.storage.name(),
            t.block_format
                .map(|b| format!(" ({})", b.name()))
                .unwrap_or_default(),
            t.bytes,
            if t.placeholder { " (placeholder)" } else { "" }
        );
    }
    outln!(out, "cameras: {}", l.cameras.len());
    for (i, c) in l.cameras.iter().enumerate() {
        let projection = match c.projection {
            CameraProjection::Perspective { fov_y_deg } => {
                format!("perspective fov {fov_y_deg:.1}°")
            }
            CameraProjection::Orthographic { half_height } => {
                format!("orthographic height {}", 2.0 * half_height)
            }
        };
        outln!(
            out,
            "  [{i}] {projection} eye {:.3?} target {:.3?} near {} far {}",
            c.eye.to_array(),
            c.target.to_array(),
            c.near,
            c.far
        );
    }
    outln!(
        out,
        "lights: {} (ambient I_AL {:.3?})",
        s.lights.len(),
        s.ambient_light.to_array()
    );
    print_shadows(out, s);
    match &s.environment {
        None => outln!(out, "environment: none"),
        Some(e) => outln!(out, "environment: {}", describe_environment(e)),
    }
    print_projectors(out, s);
    outln!(out, "volumes: {}", l.volumes.len());
    for (i, v) in l.volumes.iter().enumerate() {
        outln!(out, "  [{i}] {}", describe_scene_volume(v));
    }
    let (lo, hi) = s.bounds();
    outln!(
        out,
        "bounds: {:.3?} .. {:.3?}",
        lo.to_array(),
        hi.to_array()
    );
    for w in &l.warnings {
        outln!(out, "warning: {w}");
    }
}

/// An environment on one line: its source and layout, placement, and what it is used for.
fn describe_environment(e: &Environment) -> String {
    let (w, h) = e.map().size();
    let layout = match e.map() {
        EnvironmentMap::Equirect(_) => format!("equirectangular {w}x{h}"),
        EnvironmentMap::Cube(_) => format!("cube map, faces {w}x{h}"),
        EnvironmentMap::Sphere(_) => format!("sphere map {w}x{h}"),
    };
    format!(
        "{}: {layout}, {} mip levels; rotate {}°, intensity {}, background {}, image-based \
         light {}, reflections {}, filter {}",
        e.source,
        e.map().levels(),
        e.rotation_deg,
        e.intensity,
        e.background.name(),
        if e.ibl { "on" } else { "off" },
        if e.reflections { "on" } else { "off" },
        e.sampler.filter.name()
    )
}

/// Grid, voxel type, spacing, value range and world box of a volume, on one line.
fn describe_volume(v: &Volume) -> String {
    let [x, y, z] = v.dims();
    let s = v.spacing();
    let (lo, hi) = v.range();
    let (a, b) = v.world_bounds();
    format!(
        "{x}x{y}x{z} {}, spacing ({}, {}, {}), values {lo} .. {hi}, box {:.3?} .. {:.3?}",
        v.scalar_type()
            .map_or("values".to_string(), |t| t.to_string()),
        s.x,
        s.y,
        s.z,
        a.to_array(),
        b.to_array()
    )
}

/// A scene's volume: its file, [`describe_volume`] and how it is rendered.
fn describe_scene_volume(v: &SceneVolume) -> String {
    let p = &v.params;
    if v.method.is_distance_field() {
        return format!(
            "{}: {}; distance field, {}",
            v.source.display(),
            describe_volume(&v.volume),
            crate::field::describe(v)
        );
    }
    format!(
        "{}: {}; tf {}, {}, {}, step {}{}{}",
        v.source.display(),
        describe_volume(&v.volume),
        v.transfer_name,
        format!("{:?}", p.mode).to_lowercase(),
        format!("{:?}", v.method).to_lowercase(),
        p.step,
        if p.shade { ", shaded" } else { "" },
        match (p.shade, p.lights.len()) {
            (false, _) => String::new(),
            (true, 0) => " (headlight)".to_string(),
            (true, n) => format!(" ({n} scene light{})", if n == 1 { "" } else { "s" }),
        }
    )
}

/// glTF's extension lobes of a material that differ from the plain model, for its line.
fn describe_lobes(l: &texmap::shading::lobes::Lobes) -> String {
    let d = texmap::shading::lobes::Lobes::default();
    let v = |c: glam::Vec3| format!("({:.3}, {:.3}, {:.3})", c.x, c.y, c.z);
    let mut out = String::new();
    if l.specular != d.specular || l.specular_color != d.specular_color {
        out += &format!(", specular {} colour {}", l.specular, v(l.specular_color));
    }
    if l.clearcoat > 0.0 {
        out += &format!(
            ", clearcoat {} roughness {}",
            l.clearcoat, l.clearcoat_roughness
        );
    }
    if l.sheen_color != glam::Vec3::ZERO {
        out += &format!(
            ", sheen {} roughness {}",
            v(l.sheen_color),
            l.sheen_roughness
        );
    }
    if l.thickness > 0.0 || l.attenuation_distance.is_finite() {
        out += &format!(
            ", volume thickness {} attenuation {} over {}",
            l.thickness,
            v(l.attenuation_color),
            l.attenuation_distance
        );
    }
    out
}
