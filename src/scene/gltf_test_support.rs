//! Test support for the glTF loader's tests: glTF and GLB files written by hand (buffers,
//! accessors, base64 data URIs), and the pixel where a camera sees a world point.

use std::path::PathBuf;

use glam::{Mat3, Vec2, Vec3};
use serde_json::{json, Value};

use crate::camera::Camera;

/// Standard base64 with padding (RFC 4648), for data URIs.
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut text = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let bits = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for i in 0..4 {
            if i <= chunk.len() {
                text.push(ALPHABET[(bits >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                text.push('=');
            }
        }
    }
    text
}

/// Binary data of one glTF buffer with its buffer views and accessors.
#[derive(Default)]
pub struct TestBuffer {
    /// The buffer's contents, each view aligned to 4 bytes.
    pub bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl TestBuffer {
    /// Appends a view and returns its index.
    pub fn view(&mut self, data: &[u8]) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        let view = json!({"buffer": 0, "byteOffset": self.bytes.len(), "byteLength": data.len()});
        self.bytes.extend_from_slice(data);
        self.views.push(view);
        self.views.len() - 1
    }

    /// A VEC3 FLOAT accessor (with the min and max that POSITION requires); its index.
    pub fn positions(&mut self, points: &[[f32; 3]]) -> usize {
        let data: Vec<u8> = points
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let view = self.view(&data);
        let min = (0..3).map(|i| points.iter().map(|p| p[i]).fold(f32::MAX, f32::min));
        let max = (0..3).map(|i| points.iter().map(|p| p[i]).fold(f32::MIN, f32::max));
        self.accessors.push(json!({
            "bufferView": view, "componentType": 5126, "count": points.len(), "type": "VEC3",
            "min": min.collect::<Vec<_>>(), "max": max.collect::<Vec<_>>(),
        }));
        self.accessors.len() - 1
    }

    /// A FLOAT accessor of `kind` ("SCALAR", "VEC2", "VEC3", "VEC4", "MAT4") over `values`, element after
    /// element; its index.
    pub fn floats(&mut self, kind: &str, values: &[f32]) -> usize {
        let width = match kind {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "MAT4" => 16,
            _ => 4,
        };
        let data: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&data);
        self.accessors.push(json!({
            "bufferView": view, "componentType": 5126, "count": values.len() / width, "type": kind,
        }));
        self.accessors.len() - 1
    }

    /// A VEC4 UNSIGNED_SHORT accessor (JOINTS_n); its index.
    pub fn joints(&mut self, joints: &[[u16; 4]]) -> usize {
        let data: Vec<u8> = joints
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let view = self.view(&data);
        self.accessors.push(json!({
            "bufferView": view, "componentType": 5123, "count": joints.len(), "type": "VEC4",
        }));
        self.accessors.len() - 1
    }

    /// An accessor of `kind` over `data` (little-endian elements of `component_type`,
    /// glTF's code: 5121 unsigned byte, 5123 unsigned short, 5126 float), `normalized` or
    /// not; its index.
    pub fn accessor(
        &mut self,
        kind: &str,
        component_type: u32,
        normalized: bool,
        count: usize,
        data: &[u8],
    ) -> usize {
        let view = self.view(data);
        self.accessors.push(json!({
            "bufferView": view, "componentType": component_type, "count": count,
            "type": kind, "normalized": normalized,
        }));
        self.accessors.len() - 1
    }

    /// A SCALAR UNSIGNED_SHORT accessor; its index.
    pub fn indices(&mut self, indices: &[u16]) -> usize {
        let data: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&data);
        self.accessors.push(json!({
            "bufferView": view, "componentType": 5123, "count": indices.len(), "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }

    /// The whole document: `rest` (nodes, meshes, ...) plus this buffer, stored at `uri` or,
    /// without one, in a GLB's BIN chunk.
    pub fn document(&self, uri: Option<String>, mut rest: Value) -> Value {
        let mut buffer = json!({"byteLength": self.bytes.len()});
        if let Some(uri) = uri {
            buffer["uri"] = json!(uri);
        }
        rest["asset"] = json!({"version": "2.0"});
        rest["buffers"] = json!([buffer]);
        rest["bufferViews"] = json!(self.views);
        rest["accessors"] = json!(self.accessors);
        rest
    }

    /// The document as a `.gltf` with the buffer in a base64 data URI.
    pub fn embedded(&self, rest: Value) -> String {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64(&self.bytes)
        );
        self.document(Some(uri), rest).to_string()
    }

    /// The document as a `.glb`: 12-byte header, then a JSON chunk and a BIN chunk, each
    /// with an 8-byte header and padded to 4 bytes (glTF 2.0 spec, section 4.4).
    pub fn glb(&self, rest: Value) -> Vec<u8> {
        let mut json_chunk = self.document(None, rest).to_string().into_bytes();
        while !json_chunk.len().is_multiple_of(4) {
            json_chunk.push(b' ');
        }
        let mut bin_chunk = self.bytes.clone();
        while !bin_chunk.len().is_multiple_of(4) {
            bin_chunk.push(0);
        }
        let total = 12 + 8 + json_chunk.len() + 8 + bin_chunk.len();
        let mut glb = Vec::new();
        glb.extend_from_slice(b"glTF");
        glb.extend_from_slice(&2u32.to_le_bytes());
        glb.extend_from_slice(&(total as u32).to_le_bytes());
        for (kind, chunk) in [(b"JSON", &json_chunk), (b"BIN\0", &bin_chunk)] {
            glb.extend_from_slice(&(chunk.len() as u32).to_le_bytes());
            glb.extend_from_slice(kind);
            glb.extend_from_slice(chunk);
        }
        glb
    }
}

/// Writes `bytes` to the file `name` in `directory`; its path.
pub fn write(directory: &tempfile::TempDir, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let path = directory.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// Where `point` lands in a `width` x `height` image seen through `camera`, in pixels from
/// the left and from the top: the ray from the pinhole through the point meets the image
/// plane left_bottom + x * right + y * up at (x, y) in [0, 1]^2 (y up).
pub fn project(camera: &Camera, width: f32, height: f32, point: Vec3) -> Vec2 {
    let plane = camera.image_plane(width / height);
    // Solve position + t * (point - position) = left_bottom + x * right + y * up.
    let system = Mat3::from_cols(point - plane.camera_position, -plane.right, -plane.up);
    let [t, x, y] = (system.inverse() * (plane.left_bottom - plane.camera_position)).to_array();
    assert!(t > 0.0, "{point} is behind the camera");
    Vec2::new(x * width, (1.0 - y) * height)
}

mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc_4648_examples() {
        let cases = [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foobar", "Zm9vYmFy"),
        ];
        for (plain, encoded) in cases {
            assert_eq!(base64(plain.as_bytes()), encoded);
        }
    }
}
