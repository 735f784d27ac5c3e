//! `texmap info`'s lines for a material's surface detail: each texture layer (mode, format,
//! image, size, uv set, scale and constant), the light map (image, uv set, intensity) and toon
//! shading (ramp, outline).

use texmap::shading::{MapChannel, Material};

/// The lines describing `m`'s layers, light map and toon shading (none when it has none).
pub(crate) fn describe(m: &Material) -> Vec<String> {
    let mut out = Vec::new();
    for (k, l) in m.layers.iter().enumerate() {
        let s = &l.slot;
        let c = l.constant;
        out.push(format!(
            "layer {k}: {} ({}) {} {}x{} uv{} scale {}, constant ({}, {}, {}, {})",
            l.mode.name(),
            l.format.name(),
            l.source,
            s.texture.width(),
            s.texture.height(),
            s.tex_coord,
            s.uv_scale,
            c.x,
            c.y,
            c.z,
            c.w
        ));
    }
    if let Some(map) = m.map(MapChannel::Light) {
        out.push(format!(
            "light map: {}x{} uv{}, intensity {} (multiplies the diffuse term)",
            map.slot.texture.width(),
            map.slot.texture.height(),
            map.slot.tex_coord,
            map.scale
        ));
    }
    if let Some(t) = &m.toon {
        let outline = match t.outline {
            Some(o) => format!(
                "outline ({}, {}, {}) {} px",
                o.color.x, o.color.y, o.color.z, o.width
            ),
            None => "no outline".into(),
        };
        out.push(format!("toon: ramp {}, {outline}", t.source));
    }
    out
}
