//! Tests of the glTF loader as a whole: small documents written to a scratch folder and
//! loaded.

use glam::{Vec2, Vec3, Vec4};

use super::load;
use crate::scene::{Light, LoadOptions, ShadingModel};
use crate::shading::MapChannel;

/// A data-URI glTF: a non-indexed strip, a sparse POSITION, u8-normalized COLOR_0, and a
/// base-colour texture whose KHR_texture_transform reads TEXCOORD_1.
#[test]
fn data_uris_strips_sparse_colors_and_texcoord_override() {
    use base64::Engine;
    let mut b: Vec<u8> = Vec::new();
    for p in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ] {
        p.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    }
    b.extend_from_slice(&[
        255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128,
    ]);
    for uv in [[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]] {
        uv.iter()
            .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    }
    b.extend_from_slice(&[3, 0, 0, 0]);
    [2.0f32, 2.0, 0.0]
        .iter()
        .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    assert_eq!(b.len(), 112);
    let enc = |x: &[u8]| base64::engine::general_purpose::STANDARD.encode(x);
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([9, 9, 9, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": ["KHR_texture_transform"],
  "nodes": [{{"mesh": 0, "translation": [0, 0, -1]}}],
  "meshes": [{{"primitives": [{{"mode": 5, "material": 0,
 "attributes": {{"POSITION": 0, "COLOR_0": 1, "TEXCOORD_1": 2}}}}]}}],
  "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0,
 "extensions": {{"KHR_texture_transform": {{"texCoord": 1, "scale": [2, 2]}}}}}}}},
 "normalTexture": {{"index": 0, "scale": 0.5,
   "extensions": {{"KHR_texture_transform": {{"offset": [0.25, 0.5], "rotation": 0.5}}}}}},
 "occlusionTexture": {{"index": 0,
   "extensions": {{"KHR_texture_transform": {{"texCoord": 1, "scale": [3, 4]}}}}}}}}],
  "textures": [{{"source": 0}}],
  "images": [{{"uri": "data:image/png;base64,{}"}}],
  "buffers": [{{"byteLength": 112, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 16}},
              {{"buffer": 0, "byteOffset": 64, "byteLength": 32}}, {{"buffer": 0, "byteOffset": 96, "byteLength": 4}},
              {{"buffer": 0, "byteOffset": 100, "byteLength": 12}}],
  "accessors": [
{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [2, 2, 0],
  "sparse": {{"count": 1, "indices": {{"bufferView": 3, "componentType": 5121}}, "values": {{"bufferView": 4}}}}}},
{{"bufferView": 1, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC4"}},
{{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}}]}}"#,
        enc(&png),
        enc(&b)
    );
    let p = crate::scene::test_file("gltf", "data.gltf", json);
    let l = load(&p, &LoadOptions::default()).unwrap();
    let m = &l.scene.meshes[0];
    assert_eq!(m.indices, [0, 1, 2, 1, 3, 2]);
    assert_eq!(m.positions[3], Vec3::new(2.0, 2.0, 0.0));
    assert_eq!(m.colors[3], Vec4::new(1.0, 1.0, 1.0, 128.0 / 255.0));
    assert_eq!(m.uvs1.len(), 4);
    assert!(m.uvs.is_empty());
    assert_eq!(m.world_from_object.w_axis.z, -1.0);
    let slot = l.scene.materials[0].base_color_texture.as_ref().unwrap();
    assert_eq!(slot.tex_coord, 1);
    assert_eq!(slot.transform.scale, Vec2::splat(2.0));
    // Normal and occlusion textures carry their own transforms.
    let mat = &l.scene.materials[0];
    let normal = mat.map(MapChannel::Normal).unwrap();
    assert_eq!(normal.scale, 0.5);
    assert_eq!(normal.slot.transform.offset, Vec2::new(0.25, 0.5));
    assert_eq!(normal.slot.transform.rotation, 0.5);
    assert_eq!(normal.slot.transform.scale, Vec2::ONE);
    assert_eq!(normal.slot.tex_coord, 0);
    let occlusion = mat.map(MapChannel::Occlusion).unwrap();
    assert_eq!(occlusion.slot.transform.scale, Vec2::new(3.0, 4.0));
    assert_eq!(occlusion.slot.tex_coord, 1);
    // One image, decoded twice: as sRGB colour and as linear data.
    assert_eq!(l.info.textures.len(), 2);
    // glTF materials are metallic-roughness, the default one a white rough metal.
    let (mat, default) = (&l.scene.materials[0], l.scene.materials.last().unwrap());
    assert_eq!(mat.model, ShadingModel::MetallicRoughness);
    assert_eq!((mat.metallic, mat.roughness), (1.0, 1.0));
    assert_eq!(default.model, ShadingModel::MetallicRoughness);
    assert_eq!((default.metallic, default.roughness), (1.0, 1.0));
}

#[test]
fn punctual_light_intensities_are_divided_by_pi() {
    let json = r#"{"asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_unlit"],
  "extensions": {"KHR_lights_punctual": {"lights": [
{"type": "directional", "color": [1, 0.5, 0.25], "intensity": 6.283185307179586},
{"type": "point", "intensity": 31.41592653589793}]}},
  "materials": [{"extensions": {"KHR_materials_unlit": {}}}],
  "nodes": [{"extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 1}}}]}"#;
    let p = crate::scene::test_file("gltf", "lights.gltf", json);
    let l = load(&p, &LoadOptions::default()).unwrap();
    match l.scene.lights[..] {
        [Light::Directional { direction, color }, Light::Point {
            position,
            color: point,
            ..
        }] => {
            assert!((color - Vec3::new(2.0, 1.0, 0.5)).abs().max_element() < 1e-6);
            assert!((direction - Vec3::Z).length() < 1e-6, "{direction}");
            assert!((point - Vec3::splat(10.0)).abs().max_element() < 1e-5);
            assert_eq!(position, Vec3::new(0.0, 2.0, 0.0));
        }
        ref other => panic!("{other:?}"),
    }
    // KHR_materials_unlit keeps the Phong model (and ignores lights).
    assert!(l.scene.materials[0].unlit);
    assert_eq!(l.scene.materials[0].model, ShadingModel::Phong);
}

/// A 4×4 BC1 DDS of one colour (RGB565 `c`, every index 0).
fn bc1_dds(c: u16) -> Vec<u8> {
    let mut hdr = [0u32; 31];
    (hdr[0], hdr[1], hdr[2], hdr[3], hdr[6]) = (124, 0x1007, 4, 4, 1);
    (hdr[18], hdr[19], hdr[20]) = (32, 0x4, u32::from_le_bytes(*b"DXT1"));
    hdr[26] = 0x1000;
    let mut f = b"DDS ".to_vec();
    hdr.iter().for_each(|v| f.extend(v.to_le_bytes()));
    f.extend(c.to_le_bytes());
    f.extend(0u16.to_le_bytes());
    f.extend([0u8; 4]);
    f
}

/// MSFT_texture_dds: the texture reads the DDS its extension names, not its PNG fallback;
/// without the extension (or with a `source` naming no image) the fallback is read.
#[test]
fn msft_texture_dds_reads_the_dds_image() {
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(4, 4, image::Rgba([255, 0, 0, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    crate::scene::test_file("gltf", "fallback.png", &png);
    // Pure green in RGB565.
    crate::scene::test_file("gltf", "green.dds", bc1_dds(0x07e0));
    let doc = |ext: &str| {
        format!(
            r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": ["MSFT_texture_dds"],
  "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}}}}],
  "textures": [{{"source": 0{ext}}}],
  "images": [{{"uri": "fallback.png"}}, {{"uri": "green.dds"}}]}}"#
        )
    };
    let base = |name: &str, ext: &str| {
        let p = crate::scene::test_file("gltf", name, doc(ext));
        let l = load(&p, &LoadOptions::default()).unwrap();
        assert!(l.warnings.is_empty(), "{:?}", l.warnings);
        let slot = l.scene.materials[0].base_color_texture.clone().unwrap();
        slot.texture.texel(0, 1, 1)
    };
    let dds = base(
        "dds.gltf",
        r#", "extensions": {"MSFT_texture_dds": {"source": 1}}"#,
    );
    assert!(
        (dds - Vec4::new(0.0, 1.0, 0.0, 1.0)).abs().max_element() < 1e-4,
        "{dds}"
    );
    let png = base("png.gltf", "");
    assert!(
        (png - Vec4::new(1.0, 0.0, 0.0, 1.0)).abs().max_element() < 1e-4,
        "{png}"
    );
    let missing = base(
        "missing.gltf",
        r#", "extensions": {"MSFT_texture_dds": {"source": 7}}"#,
    );
    assert_eq!(missing, png);
}

/// Material extensions read from the raw JSON (factors, textures with their uv set and
/// transform, emissive strength) and variants choosing a primitive's material.
#[test]
fn material_extensions_and_variants() {
    use crate::pipeline::CullMode;
    use base64::Engine;
    let mut b: Vec<u8> = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        p.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    }
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(1, 1, image::Rgba([9, 9, 9, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let enc = |x: &[u8]| base64::engine::general_purpose::STANDARD.encode(x);
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}},
  "extensionsUsed": ["KHR_materials_specular", "KHR_materials_clearcoat", "KHR_materials_sheen",
    "KHR_materials_volume", "KHR_materials_emissive_strength", "KHR_materials_variants"],
  "extensions": {{"KHR_materials_variants": {{"variants": [{{"name": "a"}}, {{"name": "b"}}]}}}},
  "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "material": 0,
    "extensions": {{"KHR_materials_variants": {{"mappings": [{{"material": 1, "variants": [1]}}]}}}}}}]}}],
  "materials": [{{"emissiveFactor": [0.5, 0.25, 1], "doubleSided": true, "extensions": {{
      "KHR_materials_emissive_strength": {{"emissiveStrength": 4}},
      "KHR_materials_specular": {{"specularFactor": 0.5, "specularColorFactor": [1, 0.5, 0.25],
        "specularColorTexture": {{"index": 0, "texCoord": 1}}}},
      "KHR_materials_clearcoat": {{"clearcoatFactor": 0.75, "clearcoatRoughnessFactor": 0.25,
        "clearcoatNormalTexture": {{"index": 0, "scale": 0.5,
          "extensions": {{"KHR_texture_transform": {{"offset": [0.5, 0], "texCoord": 1}}}}}}}},
      "KHR_materials_sheen": {{"sheenColorFactor": [0.1, 0.2, 0.3], "sheenRoughnessFactor": 0.4}},
      "KHR_materials_volume": {{"thicknessFactor": 2, "attenuationDistance": 3,
        "attenuationColor": [0.9, 0.8, 0.7]}}}}}},
    {{"name": "other"}}],
  "textures": [{{"source": 0}}],
  "images": [{{"uri": "data:image/png;base64,{}"}}],
  "buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
    "min": [0, 0, 0], "max": [1, 1, 0]}}]}}"#,
        enc(&png),
        enc(&b)
    );
    let p = crate::scene::test_file("gltf", "extensions.gltf", json);
    let l = load(&p, &LoadOptions::default()).unwrap();
    let m = &l.scene.materials[0];
    assert_eq!(m.emissive, Vec3::new(2.0, 1.0, 4.0));
    assert_eq!(m.lobes.specular, 0.5);
    assert_eq!(m.lobes.specular_color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(
        (m.lobes.clearcoat, m.lobes.clearcoat_roughness),
        (0.75, 0.25)
    );
    assert_eq!(m.lobes.sheen_color, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(m.lobes.sheen_roughness, 0.4);
    assert_eq!(m.lobes.thickness, 2.0);
    assert_eq!(m.lobes.attenuation_distance, 3.0);
    assert_eq!(m.lobes.attenuation_color, Vec3::new(0.9, 0.8, 0.7));
    let color = m.map(MapChannel::SpecularColor).unwrap();
    assert_eq!(color.slot.tex_coord, 1);
    let coat = m.map(MapChannel::ClearcoatNormal).unwrap();
    assert_eq!((coat.scale, coat.slot.tex_coord), (0.5, 1));
    assert_eq!(coat.slot.transform.offset, Vec2::new(0.5, 0.0));
    // Double-sided: never culled; glTF's default material is single-sided: back faces.
    assert_eq!(m.cull, CullMode::Back);
    assert!(m.double_sided);
    assert_eq!(l.scene.materials[1].cull, CullMode::Back);
    assert_eq!(l.info.variants, ["a", "b"]);
    assert_eq!(l.scene.meshes[0].material, 0);
    // Variant "b" maps the primitive to material 1; "a" maps nothing.
    let b = load(&p, &LoadOptions::default().variant(Some("b".into()))).unwrap();
    assert_eq!(b.scene.meshes[0].material, 1);
    assert_eq!(b.info.variant.as_deref(), Some("b"));
    let a = load(&p, &LoadOptions::default().variant(Some("a".into()))).unwrap();
    assert_eq!(a.scene.meshes[0].material, 0);
    let e = load(&p, &LoadOptions::default().variant(Some("c".into()))).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("extensions.gltf") && msg.contains("a, b"),
        "{msg}"
    );
}

/// An occlusion map in its own image, of the metallic-roughness map's size, is packed into
/// that map's red channel (one texture, read once); where another use could tell (the
/// occlusion image also an emissive map), the two stay apart.
#[test]
fn occlusion_is_packed_into_the_metallic_roughness_image() {
    let png = |name: &str, f: &dyn Fn(u32, u32) -> [u8; 3]| {
        let img = image::RgbImage::from_fn(8, 4, |x, y| image::Rgb(f(x, y)));
        let mut bytes = Vec::new();
        img.write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
        crate::scene::test_file("gltf-orm", name, bytes)
    };
    let mr = |x: u32, y: u32| [200, (x * 30) as u8, (y * 60) as u8];
    let ao = |x: u32, y: u32| [(x * 20 + y * 5) as u8, 7, 9];
    png("mr.png", &mr);
    png("ao.png", &ao);
    let doc = |emissive: &str| {
        format!(
            r#"{{"asset": {{"version": "2.0"}},
  "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"material": 0, "attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}}}]}}],
  "materials": [{{"pbrMetallicRoughness": {{"metallicRoughnessTexture": {{"index": 0}}}},
                  "occlusionTexture": {{"index": 1, "strength": 0.5}}}}{emissive}],
  "textures": [{{"source": 0}}, {{"source": 1}}],
  "images": [{{"uri": "mr.png"}}, {{"uri": "ao.png"}}],
  "buffers": [{{"byteLength": 60, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 24}}],
  "accessors": [
{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
{{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}}]}}"#,
            {
                use base64::Engine;
                let mut b = Vec::new();
                for v in [
                    0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0,
                ] {
                    b.extend_from_slice(&v.to_le_bytes());
                }
                base64::engine::general_purpose::STANDARD.encode(b)
            }
        )
    };
    let maps = |l: &crate::scene::Loaded| {
        let m = &l.scene.materials[0];
        (
            m.map(MapChannel::MetallicRoughness)
                .unwrap()
                .slot
                .texture
                .clone(),
            m.map(MapChannel::Occlusion).unwrap().slot.texture.clone(),
        )
    };
    let p = crate::scene::test_file("gltf-orm", "packed.gltf", doc(""));
    let l = load(&p, &LoadOptions::default()).unwrap();
    let (metal_rough, occlusion) = maps(&l);
    assert!(std::sync::Arc::ptr_eq(&metal_rough, &occlusion));
    assert_eq!(l.info.textures.len(), 1, "{:?}", l.info.textures);
    assert!(l.info.textures[0].name.contains("red channel from image 1"));
    let texels = metal_rough.decode_level(0);
    for y in 0..4 {
        for x in 0..8 {
            let t = texels[(y * 8 + x) as usize];
            let unorm = |c: u8| f32::from(c) / 255.0;
            let want = [unorm(ao(x, y)[0]), unorm(mr(x, y)[1]), unorm(mr(x, y)[2])];
            for (k, w) in want.iter().enumerate() {
                assert!(
                    (t[k] - w).abs() < 1e-6,
                    "({x}, {y}) channel {k}: {t} vs {want:?}"
                );
            }
        }
    }
    // The occlusion image is also an emissive map: its other channels are read, no packing.
    let also = r#", {"emissiveTexture": {"index": 1}}"#;
    let p = crate::scene::test_file("gltf-orm", "apart.gltf", doc(also));
    let l = load(&p, &LoadOptions::default()).unwrap();
    let (metal_rough, occlusion) = maps(&l);
    assert!(!std::sync::Arc::ptr_eq(&metal_rough, &occlusion));
    assert_eq!(occlusion.decode_level(0)[0].y, 7.0 / 255.0);
}
