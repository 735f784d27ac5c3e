//! `KHR_materials_variants`: the document's variant names (listed by `texmap info`) and the
//! material a primitive takes under the chosen variant (`--variant NAME`, the TOML mesh key
//! `variant`). Read from the raw extension objects: the `gltf` crate's own parser for the
//! extension is a feature texmap does not enable (one more typed layer for two arrays).
//!
//! The root's `extensions.KHR_materials_variants.variants` names the variants; a primitive's
//! `extensions.KHR_materials_variants.mappings` lists `{material, variants}` pairs. Under a
//! variant, a primitive whose mappings list it takes that material; the others keep their
//! own `material` (the extension's rule).

use std::path::Path;

use crate::{Error, Result};

/// The extension's name.
pub(super) const VARIANTS: &str = "KHR_materials_variants";

/// The document's variant names, in order (empty without the extension); a variant without
/// a name is called by its index.
pub(super) fn names(doc: &gltf::Document) -> Vec<String> {
    let Some(list) = doc
        .extension_value(VARIANTS)
        .and_then(|v| v.get("variants"))
        .and_then(|v| v.as_array())
    else {
        return Vec::new();
    };
    list.iter()
        .enumerate()
        .map(|(i, v)| {
            v.get("name")
                .and_then(|n| n.as_str())
                .map_or_else(|| format!("variant {i}"), str::to_string)
        })
        .collect()
}

/// The index of variant `name` among `names`; an error naming the file and listing the
/// variants when there is no such variant.
pub(super) fn resolve(path: &Path, names: &[String], name: &str) -> Result<usize> {
    names.iter().position(|n| n == name).ok_or_else(|| {
        let available = if names.is_empty() {
            "the file defines no material variants".to_string()
        } else {
            format!("its variants are: {}", names.join(", "))
        };
        Error::Parameter(format!(
            "{}: no material variant named {name:?}; {available}",
            path.display()
        ))
    })
}

/// The material `prim` takes under variant `variant`: the first mapping that lists it, if
/// any (`None`: the primitive keeps its own material).
pub(super) fn material_of(prim: &gltf::Primitive, variant: usize) -> Option<usize> {
    let mappings = prim
        .extension_value(VARIANTS)?
        .get("mappings")?
        .as_array()?;
    mappings.iter().find_map(|m| {
        let lists = m
            .get("variants")?
            .as_array()?
            .iter()
            .any(|v| v.as_u64() == Some(variant as u64));
        if !lists {
            return None;
        }
        usize::try_from(m.get("material")?.as_u64()?).ok()
    })
}
