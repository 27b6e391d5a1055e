//! Animation channels without a `node`: `KHR_animation_pointer` targets a property by a
//! JSON pointer (`/materials/0/pbrMetallicRoughness/baseColorFactor`, a light's intensity,
//! a camera's `yfov`) instead of a node. The `gltf` crate's schema requires `node`, so such
//! a valid file would be refused as malformed: where it is, the channels without a node are
//! dropped from the JSON before it is parsed again, with one warning (the node channels
//! still play).

use gltf::{Document, Gltf};
use serde_json::Value;

/// The file's document and GLB binary chunk, as `Gltf::from_slice_without_validation`
/// gives them, and where channels without a node were dropped to parse it, the warning that
/// says so (`None` where the file names `KHR_animation_pointer` in `extensionsUsed`: the
/// extension's own warning says it). A file that fails for another reason gives the
/// crate's error.
pub(super) fn parse(bytes: &[u8]) -> Result<(Gltf, Option<String>), gltf::Error> {
    let error = match Gltf::from_slice_without_validation(bytes) {
        Ok(gltf) => return Ok((gltf, None)),
        Err(error) => error,
    };
    match without_node_less_channels(bytes) {
        Some(parsed) => parsed,
        None => Err(error),
    }
}

/// The file parsed without its channels that have no node (or whose path is `pointer`),
/// and the warning; `None` where it has none (or its JSON does not parse at all).
fn without_node_less_channels(bytes: &[u8]) -> Option<Result<(Gltf, Option<String>), gltf::Error>> {
    let mut glb = None;
    let json: &[u8] = if bytes.starts_with(b"glTF") {
        let found = gltf::Glb::from_slice(bytes).ok()?;
        &glb.insert(found).json
    } else {
        bytes
    };
    let mut root: Value = serde_json::from_slice(json).ok()?;
    let pointers = drop_node_less_channels(&mut root);
    if pointers.is_empty() {
        return None;
    }
    let named = root["extensionsUsed"]
        .as_array()
        .is_some_and(|used| used.iter().any(|e| e == "KHR_animation_pointer"));
    let warning = (!named).then(|| skipped_warning(&pointers));
    let parsed = serde_json::to_vec(&root)
        .and_then(|json| gltf::json::deserialize::from_slice(&json))
        .map(|json| Gltf {
            document: Document::from_json_without_validation(json),
            blob: glb.and_then(|g| g.bin).map(|b| b.into_owned()),
        })
        .map_err(gltf::Error::from);
    Some(parsed.map(|gltf| (gltf, warning)))
}

/// Removes every animation channel whose target has no `node` or targets a `pointer`,
/// returning what each targeted (its KHR_animation_pointer pointer, or "?").
fn drop_node_less_channels(root: &mut Value) -> Vec<String> {
    let mut pointers = Vec::new();
    let Some(animations) = root.get_mut("animations").and_then(Value::as_array_mut) else {
        return pointers;
    };
    for animation in animations {
        let Some(channels) = animation.get_mut("channels").and_then(Value::as_array_mut) else {
            continue;
        };
        channels.retain(|channel| {
            let target = &channel["target"];
            let keep = target.get("node").is_some() && target["path"] != "pointer";
            if !keep {
                let pointer = &target["extensions"]["KHR_animation_pointer"]["pointer"];
                pointers.push(pointer.as_str().unwrap_or("?").to_string());
            }
            keep
        });
    }
    pointers
}

/// "3 animation channels without a node skipped (KHR_animation_pointer: /a, /b, /c)".
fn skipped_warning(pointers: &[String]) -> String {
    let mut shown: Vec<String> = pointers
        .iter()
        .take(3)
        .map(|p| crate::scene::printable(p))
        .collect();
    if pointers.len() > 3 {
        shown.push("...".into());
    }
    format!(
        "{} animation channel(s) without a node skipped (KHR_animation_pointer targets: {}); node animations play",
        pointers.len(),
        shown.join(", ")
    )
}
