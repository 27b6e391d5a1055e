//! Ground truth for machine learning (issue 56): what the camera ray through each pixel's
//! centre hits first, exactly, never averaged: the IDs of the object (glTF node), the mesh
//! instance and the material it hit, and the point it hit (world position, first UV set,
//! the point in the object's own frame, camera-space z).
//!
//! One render of the kernels' INTEGRATOR_TRIANGLE serves every layer: one sample per pixel,
//! through the pixel centre (`PixelFilter::Center`; with a lens, sample 0's point on it),
//! alpha masks honoured and alpha blend by sample 0's coverage draw, as every camera ray of
//! the colour honours them. It returns the hit triangle's index + 1 (in the uploaded order,
//! exact in a float: a scene has at most 2^24 triangles) and the hit's barycentrics; the
//! host maps the index back to the scene's triangle (`Renderer::triangle_order`) and reads
//! the rest from the scene.
//!
//! IDs are integers stored as floats (exact up to 2^24, checked), 0 where the ray escapes:
//! `object_id` is the glTF node's index + 1 (1 for the whole scene where the file has no
//! nodes: OBJ, the Cornell box, Python's arrays), `instance_id` the mesh copy's index in
//! `Scene::mesh_instances` + 1 (1 likewise), `material_id` the material's index + 1 (for
//! the workshop's plain triangles, the index of `SceneMaterials::from_plain`'s).

use std::sync::Arc;

use glam::{Vec2, Vec3};

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::render::settings::{Integrator, PixelFilter, RenderSettings};
use crate::render::Renderer;
use crate::scene::instances::{MeshInstance, NodeLabel};
use crate::scene::materials::SceneMaterials;
use crate::scene::Scene;
use crate::vk::Context;
use crate::RenderedImage;

/// The largest integer that every smaller one is exact in an f32: the largest ID a layer
/// can hold.
pub const MAX_FLOAT_EXACT_ID: u64 = 1 << 24;

/// What one pixel's centre ray hit first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstHit {
    /// Index in `Scene::triangles`.
    pub triangle: u32,
    /// The hit point's barycentrics (b_0, b_1, b_2) in that triangle (as the kernel's
    /// `get_barycentrics()` computed them).
    pub barycentrics: Vec3,
}

/// Each pixel's first hit (`None`: the ray escaped), rows top-down.
#[derive(Clone, Debug, PartialEq)]
pub struct FirstHits {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// One entry per pixel.
    pub hits: Vec<Option<FirstHit>>,
}

/// Renders each pixel's first hit with `settings`' camera rays (its integrator, sample count
/// and pixel filter replaced: one sample through the centre).
pub fn render_first_hits(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
) -> Result<FirstHits> {
    check_triangle_count(scene)?;
    let settings = RenderSettings {
        integrator: Integrator::Triangle,
        spp: 1,
        pixel_filter: PixelFilter::Center,
        noise_threshold: None,
        ..settings.clone()
    };
    let mut renderer = Renderer::new(context, scene, camera, settings)?;
    let image = renderer.render_all()?;
    Ok(first_hits_of(&image, renderer.triangle_order()))
}

/// Refuses a scene whose triangle indices + 1 are not exact in a float (the kernels'
/// INTEGRATOR_TRIANGLE returns them so).
pub fn check_triangle_count(scene: &Scene) -> Result<()> {
    if scene.triangles.len() as u64 >= MAX_FLOAT_EXACT_ID {
        return Err(Error::InvalidSettings(format!(
            "the ground-truth AOVs name at most {} triangles exactly; the scene has {}",
            MAX_FLOAT_EXACT_ID - 1,
            scene.triangles.len()
        )));
    }
    Ok(())
}

/// The first hits that a render of INTEGRATOR_TRIANGLE holds, mapped to the scene's
/// triangles through the upload's `order` (`Renderer::triangle_order`).
pub fn first_hits_of(image: &RenderedImage, order: Option<&[u32]>) -> FirstHits {
    let hits = image
        .mean
        .iter()
        .map(|pixel| first_hit(*pixel, order))
        .collect();
    FirstHits {
        width: image.width,
        height: image.height,
        hits,
    }
}

/// The hit that a pixel of INTEGRATOR_TRIANGLE holds: (uploaded index + 1, b_1, b_2).
fn first_hit(pixel: [f32; 4], order: Option<&[u32]>) -> Option<FirstHit> {
    if !(pixel[0] >= 1.0) {
        return None;
    }
    let uploaded = pixel[0] as u32 - 1;
    let triangle = match order {
        Some(order) => *order.get(uploaded as usize)?,
        None => uploaded,
    };
    let (b_1, b_2) = (pixel[1], pixel[2]);
    Some(FirstHit {
        triangle,
        barycentrics: Vec3::new(1.0 - b_1 - b_2, b_1, b_2),
    })
}

/// Which of a scene's mesh copies holds each triangle, and the materials' indices: what
/// the ID layers read.
pub struct SceneIds<'a> {
    scene: &'a Scene,
    /// `(first_triangle, end, index in mesh_instances)`, sorted by `first_triangle`.
    ranges: Vec<(usize, usize, usize)>,
    /// The plain triangles' materials, where the scene has no materials of its own.
    plain_materials: Option<SceneMaterials>,
}

impl<'a> SceneIds<'a> {
    /// The lookups of `scene`.
    pub fn new(scene: &'a Scene) -> SceneIds<'a> {
        let mut ranges: Vec<(usize, usize, usize)> = scene
            .mesh_instances
            .iter()
            .enumerate()
            .map(|(index, instance)| {
                let range = instance.triangles();
                (range.start, range.end, index)
            })
            .collect();
        ranges.sort_unstable();
        let plain_materials = scene
            .materials
            .is_none()
            .then(|| SceneMaterials::from_plain(&scene.triangles));
        SceneIds {
            scene,
            ranges,
            plain_materials,
        }
    }

    /// The index in `Scene::mesh_instances` of the copy that holds `triangle`, if one does.
    pub fn instance_of(&self, triangle: u32) -> Option<usize> {
        let triangle = triangle as usize;
        let after = self.ranges.partition_point(|r| r.0 <= triangle);
        let (first, end, index) = *self.ranges.get(after.checked_sub(1)?)?;
        (first..end).contains(&triangle).then_some(index)
    }

    fn instance(&self, triangle: u32) -> Option<&MeshInstance> {
        self.instance_of(triangle)
            .map(|index| &self.scene.mesh_instances[index])
    }

    /// The node that draws `triangle`, if the scene's file has nodes.
    pub fn node_of(&self, triangle: u32) -> Option<&NodeLabel> {
        self.instance(triangle)?.node.as_deref()
    }

    /// `object_id`: the node's index + 1, or 1 (the whole scene).
    pub fn object_id(&self, triangle: u32) -> u64 {
        self.node_of(triangle)
            .map_or(1, |node| node.index as u64 + 1)
    }

    /// `instance_id`: the copy's index + 1, or 1 (the whole scene).
    pub fn instance_id(&self, triangle: u32) -> u64 {
        self.instance_of(triangle)
            .map_or(1, |index| index as u64 + 1)
    }

    /// `material_id`: the material's index + 1.
    pub fn material_id(&self, triangle: u32) -> u64 {
        let materials = self
            .scene
            .materials
            .as_ref()
            .or(self.plain_materials.as_ref());
        materials
            .and_then(|m| m.triangles.get(triangle as usize))
            .map_or(1, |shading| shading.material as u64 + 1)
    }

    /// The largest `object_id` the scene can show.
    pub fn largest_object_id(&self) -> u64 {
        let nodes = self
            .scene
            .mesh_instances
            .iter()
            .filter_map(|i| i.node.as_deref());
        nodes.map(|node| node.index as u64 + 1).max().unwrap_or(1)
    }

    /// The largest `instance_id` the scene can show.
    pub fn largest_instance_id(&self) -> u64 {
        self.scene.mesh_instances.len().max(1) as u64
    }

    /// The largest `material_id` the scene can show.
    pub fn largest_material_id(&self) -> u64 {
        let materials = self
            .scene
            .materials
            .as_ref()
            .or(self.plain_materials.as_ref());
        materials.map_or(1, |m| m.materials.len().max(1) as u64)
    }

    /// The hit's world-space point.
    pub fn position(&self, hit: &FirstHit) -> Vec3 {
        let corners = self.scene.triangles[hit.triangle as usize].positions;
        interpolate(corners, hit.barycentrics)
    }

    /// The hit's first UV set (glTF's TEXCOORD_0; 0 where the scene has none).
    pub fn uv(&self, hit: &FirstHit) -> Vec2 {
        let Some(shading) = self
            .scene
            .materials
            .as_ref()
            .and_then(|m| m.triangles.get(hit.triangle as usize))
        else {
            return Vec2::ZERO;
        };
        let [a, b, c] = shading.tex_coords;
        let w = hit.barycentrics;
        w.x * a + w.y * b + w.z * c
    }

    /// The hit in its object's own frame (the node's, before its world transform; a skinned
    /// mesh's and a loose triangle's is world space).
    pub fn object_position(&self, hit: &FirstHit) -> Vec3 {
        match self.instance(hit.triangle) {
            Some(instance) => {
                let corners =
                    instance.object_positions[hit.triangle as usize - instance.first_triangle];
                interpolate(corners, hit.barycentrics)
            }
            None => self.position(hit),
        }
    }
}

/// What the IDs of the ID layers name (`render -o NAME.exr --aov object_id` writes it as
/// `NAME.ids.json`): ID 0 is always the background (nothing hit).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct IdNames {
    /// Each `object_id`: a glTF node that draws a mesh.
    pub objects: Vec<ObjectName>,
    /// Each `instance_id`: a mesh copy and the node that draws it.
    pub instances: Vec<InstanceName>,
    /// Each `material_id`: the material's index in the scene's list (glTF's `materials`).
    pub materials: Vec<MaterialName>,
}

/// An `object_id` and its node.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ObjectName {
    /// The ID in the layer.
    pub id: u64,
    /// The node's index in the file (`null`: the whole scene of a file without nodes).
    pub node: Option<usize>,
    /// Its name (`#index` where it has none; `scene` for a file without nodes).
    pub name: String,
    /// Its path in the node tree (`/` for a file without nodes).
    pub path: String,
}

/// An `instance_id` and its copy.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct InstanceName {
    /// The ID in the layer.
    pub id: u64,
    /// The `object_id` of the node that draws it.
    pub object_id: u64,
    /// The index in the file's `meshes` of the mesh it copies (`null` without nodes).
    pub mesh: Option<usize>,
}

/// A `material_id` and its material.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MaterialName {
    /// The ID in the layer.
    pub id: u64,
    /// The material's index in the scene's list.
    pub index: usize,
}

impl IdNames {
    /// The names of every ID `scene` can show.
    pub fn of(scene: &Scene) -> IdNames {
        let ids = SceneIds::new(scene);
        let whole_scene = || ObjectName {
            id: 1,
            node: None,
            name: "scene".to_owned(),
            path: "/".to_owned(),
        };
        let mut objects: Vec<ObjectName> = Vec::new();
        let mut instances = Vec::new();
        for (index, instance) in scene.mesh_instances.iter().enumerate() {
            let object = match instance.node.as_deref() {
                Some(node) => ObjectName {
                    id: node.index as u64 + 1,
                    node: Some(node.index),
                    name: node.name.clone(),
                    path: node.path.clone(),
                },
                None => whole_scene(),
            };
            instances.push(InstanceName {
                id: index as u64 + 1,
                object_id: object.id,
                mesh: instance.node.as_deref().map(|node| node.mesh),
            });
            if !objects.iter().any(|o| o.id == object.id) {
                objects.push(object);
            }
        }
        if scene.mesh_instances.is_empty() {
            objects.push(whole_scene());
            instances.push(InstanceName {
                id: 1,
                object_id: 1,
                mesh: None,
            });
        }
        objects.sort_by_key(|o| o.id);
        let materials = (0..ids.largest_material_id())
            .map(|index| MaterialName {
                id: index + 1,
                index: index as usize,
            })
            .collect();
        IdNames {
            objects,
            instances,
            materials,
        }
    }
}

/// One visible object of an `object_id` layer (`render --json`'s `objects`), as
/// BlenderProc's and Kubric's annotations count them.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ObjectSummary {
    /// Its `object_id`.
    pub id: u64,
    /// Its node's name (`IdNames`).
    pub name: String,
    /// Pixels whose centre ray hits it first.
    pub pixels: u64,
    /// Those pixels' box, [x0, y0, x1, y1] with x1 and y1 past the last column and row
    /// (rows top-down, in the image's or region's own pixels).
    pub bbox: [u32; 4],
    /// `pixels` over the image's pixels.
    pub visible_fraction: f64,
}

/// Every object an `object_id` layer (`width` columns, one ID per pixel in the first
/// component) shows, by ID, with the names of `names`.
pub fn object_summaries(ids: &[[f32; 3]], width: u32, names: &IdNames) -> Vec<ObjectSummary> {
    let mut found = std::collections::BTreeMap::<u64, (u64, [u32; 4])>::new();
    for (index, pixel) in ids.iter().enumerate() {
        let id = pixel[0] as u64;
        if id == 0 {
            continue;
        }
        let (x, y) = (index as u32 % width.max(1), index as u32 / width.max(1));
        let (count, bbox) = found.entry(id).or_insert((0, [x, y, x + 1, y + 1]));
        *count += 1;
        *bbox = [
            bbox[0].min(x),
            bbox[1].min(y),
            bbox[2].max(x + 1),
            bbox[3].max(y + 1),
        ];
    }
    let total = ids.len().max(1) as f64;
    found
        .into_iter()
        .map(|(id, (pixels, bbox))| ObjectSummary {
            id,
            name: names
                .objects
                .iter()
                .find(|o| o.id == id)
                .map_or_else(String::new, |o| o.name.clone()),
            pixels,
            bbox,
            visible_fraction: pixels as f64 / total,
        })
        .collect()
}

/// b_0 a + b_1 b + b_2 c.
fn interpolate([a, b, c]: [Vec3; 3], w: Vec3) -> Vec3 {
    w.x * a + w.y * b + w.z * c
}

/// Refuses IDs above `MAX_FLOAT_EXACT_ID` (a float layer would round them): `largest` is the
/// largest ID a layer of `what` may hold.
pub fn check_float_exact(what: &str, largest: u64) -> Result<()> {
    if largest > MAX_FLOAT_EXACT_ID {
        return Err(Error::InvalidSettings(format!(
            "--aov {what}: IDs up to {largest} do not fit a float layer exactly (at most 2^24 = {MAX_FLOAT_EXACT_ID})"
        )));
    }
    Ok(())
}

/// The camera's unit optical axis (the pinhole towards the image plane's middle).
pub fn camera_forward(camera: &Camera) -> Vec3 {
    (camera.image_plane_middle - camera.position).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixel_names_its_triangle_through_the_upload_order() {
        let order = [5u32, 3, 9];
        let hit = first_hit([2.0, 0.25, 0.5, 1.0], Some(&order)).unwrap();
        assert_eq!(hit.triangle, 3);
        assert_eq!(hit.barycentrics, Vec3::new(0.25, 0.25, 0.5));
        assert_eq!(first_hit([0.0, 0.0, 0.0, 1.0], Some(&order)), None);
        assert_eq!(first_hit([f32::NAN, 0.0, 0.0, 1.0], None), None);
        // The largest index a scene may have is exact in the float
        let last = (MAX_FLOAT_EXACT_ID - 1) as u32;
        let hit = first_hit([(last + 1) as f32, 0.0, 0.0, 1.0], None).unwrap();
        assert_eq!(hit.triangle, last);
    }

    #[test]
    fn objects_are_counted_with_their_boxes() {
        // 3 x 2 pixels: object 2 at (0, 0) and (1, 1), object 5 at (2, 0), background else
        let layer = [[2.0; 3], [0.0; 3], [5.0; 3], [0.0; 3], [2.0; 3], [0.0; 3]];
        let names = IdNames {
            objects: vec![ObjectName {
                id: 2,
                node: Some(1),
                name: "Leaf".into(),
                path: "/Tree/Leaf".into(),
            }],
            instances: Vec::new(),
            materials: Vec::new(),
        };
        let summaries = object_summaries(&layer, 3, &names);
        assert_eq!(summaries.len(), 2);
        assert_eq!(
            (summaries[0].id, summaries[0].pixels, summaries[0].bbox),
            (2, 2, [0, 0, 2, 2])
        );
        assert_eq!(summaries[0].name, "Leaf");
        assert_eq!((summaries[1].id, summaries[1].bbox), (5, [2, 0, 3, 1]));
        assert!((summaries[0].visible_fraction - 2.0 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn ids_past_2_to_the_24_are_refused_for_float_layers() {
        assert!(check_float_exact("object_id", MAX_FLOAT_EXACT_ID).is_ok());
        let error = check_float_exact("object_id", MAX_FLOAT_EXACT_ID + 1).unwrap_err();
        assert_eq!(
            error.to_string(),
            "invalid settings: --aov object_id: IDs up to 16777217 do not fit a float layer exactly (at most 2^24 = 16777216)"
        );
        // ...because the next integer is not exact
        assert_eq!((MAX_FLOAT_EXACT_ID + 1) as f32 as u64, MAX_FLOAT_EXACT_ID);
    }
}
