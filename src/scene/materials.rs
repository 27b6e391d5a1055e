//! What real assets carry beyond the workshop's diffuse triangles: glTF metallic-roughness
//! materials (with KHR_materials_specular, KHR_materials_ior, textures and alpha, and the
//! layers of KHR_materials_transmission, KHR_materials_volume and KHR_materials_clearcoat),
//! and per
//! vertex normals, texture coordinates and tangents. A scene that has none of it (flat,
//! untextured, opaque Lambertian triangles) keeps `Scene::materials` at `None` and renders
//! with the workshop's kernels, bit for bit as before.

use glam::{Vec2, Vec3, Vec4};

use super::textures::{Texture, TextureTransform};

/// How a material's alpha (base colour alpha times its texture's) is used (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface is opaque.
    Opaque,
    /// The surface is there where alpha >= `cutoff` and absent elsewhere (foliage).
    Mask {
        /// glTF `alphaCutoff` (default 0.5).
        cutoff: f32,
    },
    /// The surface is there with probability alpha (stochastic coverage: decals, glass
    /// without refraction), for camera, bounce and shadow rays alike.
    Blend,
}

/// A texture as one material slot uses it.
#[derive(Clone, Copy, PartialEq)]
pub struct TextureBinding {
    /// Index into `SceneMaterials::textures`.
    pub texture: u32,
    /// KHR_texture_transform's matrix (identity without the extension).
    pub transform: TextureTransform,
    /// The texture coordinate set it reads: 0 (`TEXCOORD_0`) or 1 (`TEXCOORD_1`, glTF's
    /// `texCoord`, or KHR_texture_transform's override).
    pub tex_coord: u32,
}

impl TextureBinding {
    /// A binding of texture `texture` on `TEXCOORD_0` with `transform`.
    pub fn new(texture: u32, transform: TextureTransform) -> TextureBinding {
        TextureBinding {
            texture,
            transform,
            tex_coord: 0,
        }
    }
}

/// The set is written only where it is 1: the scene hash (`render::metadata`) takes the
/// materials' Debug text, so scenes that read set 0 keep the hash they had before the set
/// was a field.
impl std::fmt::Debug for TextureBinding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut debug = f.debug_struct("TextureBinding");
        debug
            .field("texture", &self.texture)
            .field("transform", &self.transform);
        if self.tex_coord != 0 {
            debug.field("tex_coord", &self.tex_coord);
        }
        debug.finish()
    }
}

/// KHR_materials_transmission with KHR_materials_volume: light through the surface (glass).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Transmission {
    /// `transmissionFactor` in [0, 1] (0: opaque, the glTF default).
    pub factor: f32,
    /// `transmissionTexture` (linear; R multiplies `factor`).
    pub texture: Option<TextureBinding>,
    /// KHR_materials_volume `thicknessFactor` (0, or no volume: thin-walled, light passes
    /// straight through; above 0: the mesh encloses a refracting volume).
    pub thickness: f32,
    /// `thicknessTexture` (linear; G multiplies `thickness`).
    pub thickness_texture: Option<TextureBinding>,
    /// The volume's absorption coefficient sigma_a per unit length (Beer-Lambert). From
    /// `attenuationColor` c and `attenuationDistance` d the extinction is
    /// sigma_t = -ln(c) / d per channel (0: none, the default's infinite distance); without
    /// KHR_materials_volume_scatter all of it absorbs, with it sigma_a = sigma_t (1 - rho_ss)
    /// (`Transmission::volume_coefficients`).
    pub attenuation: Vec3,
    /// KHR_materials_volume_scatter: the volume's scattering coefficient sigma_s per unit
    /// length, sigma_t rho_ss per channel (0: the volume only absorbs, as without the
    /// extension).
    pub scattering: Vec3,
    /// KHR_materials_volume_scatter `scatterAnisotropy`: the Henyey-Greenstein g of the
    /// volume's scattering, in (-1, 1) (0: isotropic, the default).
    pub anisotropy: f32,
}

impl Transmission {
    /// The absorption coefficient of `attenuationColor` and `attenuationDistance`: a ray
    /// `distance` long inside keeps `color` of its light. Infinite distances, and colours
    /// of 1, absorb nothing; a colour of 0 absorbs everything within any distance (a large
    /// finite coefficient, so that exp(-sigma t) stays a number).
    pub fn attenuation_coefficient(color: Vec3, distance: f32) -> Vec3 {
        if !(distance > 0.0) || distance.is_infinite() {
            return Vec3::ZERO;
        }
        Vec3::from(
            color
                .to_array()
                .map(|c| (-c.clamp(0.0, 1.0).max(1e-30).ln() / distance).min(1e30)),
        )
    }

    /// KHR_materials_volume_scatter's single-scatter albedo rho_ss of a multi-scatter albedo
    /// rho_ms (`multiscatterColor`), per channel, as the draft defines it (its section
    /// "Multi-Scatter Albedo", after Kulla and Conty 2017, "Revisiting Physically Based
    /// Shading at Imageworks"):
    /// rho_ss = 1 - (4.09712 + 4.20863 rho_ms - sqrt(9.59217 + 41.6808 rho_ms + 17.7126 rho_ms^2))^2.
    /// Evaluated in f64 and clamped to [0, 1] (rho_ms is clamped to [0, 1] first). Two
    /// ends are exact here where the fit is not: rho_ms = 0 gives 0 (the fit's 6.0e-6 is its
    /// residual, and a volume of multiscatterColor 0 then absorbs exactly as one without the
    /// extension), and rho_ms = 1 gives 1 (the fit's 1 - 3e-11 rounds to 1 in f32 anyway).
    pub fn single_scatter_albedo(multiscatter: Vec3) -> Vec3 {
        Vec3::from(multiscatter.to_array().map(|ms| {
            let ms = f64::from(ms.clamp(0.0, 1.0));
            if ms == 0.0 {
                return 0.0;
            }
            let root = (9.59217 + 41.6808 * ms + 17.7126 * ms * ms).sqrt();
            let k = 4.09712 + 4.20863 * ms - root;
            (1.0 - k * k).clamp(0.0, 1.0) as f32
        }))
    }

    /// The volume's absorption and scattering coefficients (sigma_a, sigma_s) of
    /// KHR_materials_volume's `attenuationColor` and `attenuationDistance` with
    /// KHR_materials_volume_scatter's `multiscatterColor` (the draft's section "Attenuation":
    /// the extinction sigma_t = -ln(c) / d now counts scattering too, sigma_s = sigma_t rho_ss,
    /// sigma_a = sigma_t (1 - rho_ss)). A `multiscatter` of 0 (the extension absent) gives
    /// (sigma_t, 0), bit for bit `attenuation_coefficient`.
    pub fn volume_coefficients(color: Vec3, distance: f32, multiscatter: Vec3) -> (Vec3, Vec3) {
        let extinction = Transmission::attenuation_coefficient(color, distance);
        let albedo = Transmission::single_scatter_albedo(multiscatter);
        let scattering = extinction * albedo;
        (extinction - scattering, scattering)
    }

    /// Whether the volume scatters light (KHR_materials_volume_scatter with sigma_s above 0
    /// in some channel): the kernels then track it as the path's medium inside
    /// (`SCENE_HAS_VOLUME_SCATTER`).
    pub fn scatters(&self) -> bool {
        self.scattering.max_element() > 0.0
    }
}

/// KHR_materials_clearcoat: a clear dielectric coat (ior 1.5) over the material.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Clearcoat {
    /// `clearcoatFactor` in [0, 1] (0: no coat, the default).
    pub factor: f32,
    /// `clearcoatTexture` (linear; R multiplies `factor`).
    pub texture: Option<TextureBinding>,
    /// `clearcoatRoughnessFactor` in [0, 1] (perceptual, as `roughness`).
    pub roughness: f32,
    /// `clearcoatRoughnessTexture` (linear; G multiplies `roughness`).
    pub roughness_texture: Option<TextureBinding>,
    /// `clearcoatNormalTexture` (tangent space; without it the coat follows the
    /// interpolated vertex normal, not the base's normal map).
    pub normal_texture: Option<TextureBinding>,
    /// `clearcoatNormalTexture.scale` (default 1).
    pub normal_scale: f32,
}

/// KHR_materials_sheen: a Charlie sheen lobe (cloth) over the material.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sheen {
    /// `sheenColorFactor`, linear RGB (0: no sheen, the default).
    pub color: Vec3,
    /// `sheenColorTexture` (sRGB; multiplies `color`).
    pub color_texture: Option<TextureBinding>,
    /// `sheenRoughnessFactor` in [0, 1].
    pub roughness: f32,
    /// `sheenRoughnessTexture` (linear; A multiplies `roughness`).
    pub roughness_texture: Option<TextureBinding>,
}

/// A glTF metallic-roughness material, with glTF's defaults where a file says nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PbrMaterial {
    /// `baseColorFactor`: linear RGB in [0, 1] and alpha.
    pub base_color: Vec4,
    /// `emissiveFactor` times KHR_materials_emissive_strength, linear RGB radiance.
    pub emission: Vec3,
    /// `metallicFactor` in [0, 1] (glTF default 1).
    pub metallic: f32,
    /// `roughnessFactor` in [0, 1] (glTF default 1).
    pub roughness: f32,
    /// KHR_materials_specular `specularFactor` (default 1; 0 with metallic 0: Lambertian).
    pub specular: f32,
    /// KHR_materials_specular `specularColorFactor` (default white), linear RGB.
    pub specular_color: Vec3,
    /// KHR_materials_ior `ior` (default 1.5).
    pub ior: f32,
    /// `normalTexture.scale` (default 1).
    pub normal_scale: f32,
    /// `alphaMode` and `alphaCutoff`.
    pub alpha_mode: AlphaMode,
    /// Whether the emission shines from the back side too (glTF `doubleSided`).
    pub double_sided: bool,
    /// `baseColorTexture` (sRGB): multiplies `base_color`.
    pub base_color_texture: Option<TextureBinding>,
    /// `metallicRoughnessTexture` (linear; G = roughness, B = metallic): multiplies the factors.
    pub metallic_roughness_texture: Option<TextureBinding>,
    /// `normalTexture` (linear, tangent space).
    pub normal_texture: Option<TextureBinding>,
    /// `emissiveTexture` (sRGB): multiplies `emission`.
    pub emissive_texture: Option<TextureBinding>,
    /// KHR_materials_specular `specularTexture` (linear; A multiplies `specular`).
    pub specular_texture: Option<TextureBinding>,
    /// KHR_materials_specular `specularColorTexture` (sRGB; multiplies `specular_color`).
    pub specular_color_texture: Option<TextureBinding>,
    /// KHR_materials_transmission and KHR_materials_volume.
    pub transmission: Transmission,
    /// KHR_materials_clearcoat.
    pub clearcoat: Clearcoat,
    /// KHR_materials_sheen.
    pub sheen: Sheen,
    /// KHR_materials_unlit: camera rays see the base colour; the surface neither reflects
    /// nor emits light.
    pub unlit: bool,
}

impl PbrMaterial {
    /// The workshop's material as glTF says it: metallic 0, specular 0 (Lambertian), opaque.
    pub fn lambertian(color: Vec3, emission: Vec3, double_sided: bool) -> PbrMaterial {
        PbrMaterial {
            base_color: color.extend(1.0),
            emission,
            metallic: 0.0,
            roughness: 1.0,
            specular: 0.0,
            specular_color: Vec3::ONE,
            ior: 1.5,
            normal_scale: 1.0,
            alpha_mode: AlphaMode::Opaque,
            double_sided,
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            emissive_texture: None,
            specular_texture: None,
            specular_color_texture: None,
            transmission: Transmission::default(),
            clearcoat: Clearcoat {
                normal_scale: 1.0,
                ..Clearcoat::default()
            },
            sheen: Sheen::default(),
            unlit: false,
        }
    }

    /// Whether the material has layers beyond metallic-roughness (transmission, a clear
    /// coat, sheen), which the kernels compile in only for scenes that have them.
    pub fn is_layered(&self) -> bool {
        self.transmission.factor > 0.0
            || self.clearcoat.factor > 0.0
            || self.sheen.color.max_element() > 0.0
    }

    /// Whether the workshop's diffuse material describes this one exactly: metallic 0,
    /// specular 0, no textures, opaque.
    pub fn is_plain_lambertian(&self) -> bool {
        self.metallic == 0.0
            && self.specular == 0.0
            && self.alpha_mode == AlphaMode::Opaque
            && self.base_color_texture.is_none()
            && self.metallic_roughness_texture.is_none()
            && self.normal_texture.is_none()
            && self.emissive_texture.is_none()
            && !self.is_layered()
            && !self.unlit
    }

    /// The material made safe for the shaders: factors clamped to their ranges (NaN to
    /// the range's low end), emission to [0, f32::MAX], ior to [1, 10^4] (0 and inf, which
    /// KHR_materials_specular's conversions use for F0 = 1, become 10^4: F0 = 0.9996).
    #[allow(clippy::manual_clamp)]
    pub fn sanitized(mut self) -> PbrMaterial {
        let unit = |x: f32| x.max(0.0).min(1.0);
        self.base_color = Vec4::from(self.base_color.to_array().map(unit));
        self.emission = Vec3::from(self.emission.to_array().map(|e| e.max(0.0).min(f32::MAX)));
        self.metallic = unit(self.metallic);
        self.roughness = unit(self.roughness);
        self.specular = unit(self.specular);
        self.specular_color =
            Vec3::from(self.specular_color.to_array().map(|c| c.max(0.0).min(1e4)));
        self.ior = if self.ior == 0.0 || self.ior.is_infinite() {
            1e4
        } else {
            self.ior.max(1.0).min(1e4)
        };
        self.normal_scale = self.normal_scale.max(-1e4).min(1e4);
        self.transmission.factor = unit(self.transmission.factor);
        self.transmission.thickness = self.transmission.thickness.max(0.0).min(f32::MAX);
        self.transmission.attenuation = Vec3::from(
            self.transmission
                .attenuation
                .to_array()
                .map(|a| a.max(0.0).min(1e30)),
        );
        self.transmission.scattering = Vec3::from(
            self.transmission
                .scattering
                .to_array()
                .map(|a| a.max(0.0).min(1e30)),
        );
        // g in (-1, 1): the Henyey-Greenstein sampler divides by g at |g| near 1
        self.transmission.anisotropy = if self.transmission.anisotropy.is_nan() {
            0.0
        } else {
            self.transmission.anisotropy.max(-0.999).min(0.999)
        };
        self.clearcoat.factor = unit(self.clearcoat.factor);
        self.clearcoat.roughness = unit(self.clearcoat.roughness);
        self.clearcoat.normal_scale = self.clearcoat.normal_scale.max(-1e4).min(1e4);
        self.sheen.color = Vec3::from(self.sheen.color.to_array().map(unit));
        self.sheen.roughness = unit(self.sheen.roughness);
        if let AlphaMode::Mask { cutoff } = self.alpha_mode {
            self.alpha_mode = AlphaMode::Mask {
                cutoff: cutoff.max(0.0).min(1.0),
            };
        }
        self
    }
}

/// A triangle's per-vertex shading data, parallel to `Scene::triangles`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleShading {
    /// Index into `SceneMaterials::materials`.
    pub material: u32,
    /// Unit vertex normals, world space (the face normal where the file has none).
    pub normals: [Vec3; 3],
    /// `TEXCOORD_0` per vertex (0 where the file has none).
    pub tex_coords: [Vec2; 3],
    /// World-space unit tangents (xyz) and bitangent signs (w), from the file's `TANGENT`
    /// or MikkTSpace; 0 where no normal texture needs them.
    pub tangents: [Vec4; 3],
}

/// A triangle's vertex attributes that few files have, per vertex, as a loader hands them
/// to `SceneBuilder::push_shaded_extra`. They are not stored per triangle: the scene keeps
/// each one in a side table (`ExtraAttributeTables`) only where some triangle has it, so a
/// scene without them takes no memory for them; the kernels read them only then
/// (`SceneMaterials::vertex_attributes`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtraVertexAttributes {
    /// glTF's `COLOR_0`: linear RGBA in [0, 1], multiplied into the base colour and its
    /// alpha; 1 where the file has none.
    pub colors: [Vec4; 3],
    /// glTF's `TEXCOORD_1` (0 where the file has none).
    pub tex_coords_1: [Vec2; 3],
}

impl ExtraVertexAttributes {
    /// No vertex colour (white, opaque) and no second texture coordinates.
    pub const NONE: ExtraVertexAttributes = ExtraVertexAttributes {
        colors: [Vec4::ONE; 3],
        tex_coords_1: [Vec2::ZERO; 3],
    };

    /// Swaps the attributes of vertices `a` and `b` (as a mirroring transform swaps the
    /// corners).
    pub fn swap(&mut self, a: usize, b: usize) {
        self.colors.swap(a, b);
        self.tex_coords_1.swap(a, b);
    }
}

impl Default for ExtraVertexAttributes {
    fn default() -> ExtraVertexAttributes {
        ExtraVertexAttributes::NONE
    }
}

/// The extra vertex attributes of a scene's triangles, each a table parallel to
/// `SceneMaterials::triangles` that exists only where some triangle's value differs from
/// `ExtraVertexAttributes::NONE`'s (a scene without vertex colours has no colour table, and
/// the same memory, layout and hash as before they existed).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExtraAttributeTables {
    /// glTF's `COLOR_0` per triangle and vertex (linear RGBA), or `None`: white everywhere.
    pub colors: Option<Vec<[Vec4; 3]>>,
    /// glTF's `TEXCOORD_1` per triangle and vertex, or `None`: 0 everywhere (loaders read
    /// it only for primitives whose material samples a texture on set 1).
    pub tex_coords_1: Option<Vec<[Vec2; 3]>>,
}

impl ExtraAttributeTables {
    /// Appends the attributes of triangle `index` (the tables' length so far, where they
    /// exist): a table is made, filled with the default up to `index`, when the first
    /// value other than the default arrives.
    pub fn push(&mut self, index: usize, extra: &ExtraVertexAttributes) {
        push_sparse(
            &mut self.colors,
            index,
            extra.colors,
            ExtraVertexAttributes::NONE.colors,
        );
        push_sparse(
            &mut self.tex_coords_1,
            index,
            extra.tex_coords_1,
            ExtraVertexAttributes::NONE.tex_coords_1,
        );
    }

    /// Triangle `index`'s attributes (the defaults where a table does not exist).
    pub fn get(&self, index: usize) -> ExtraVertexAttributes {
        let none = ExtraVertexAttributes::NONE;
        ExtraVertexAttributes {
            colors: self
                .colors
                .as_ref()
                .and_then(|t| t.get(index).copied())
                .unwrap_or(none.colors),
            tex_coords_1: self
                .tex_coords_1
                .as_ref()
                .and_then(|t| t.get(index).copied())
                .unwrap_or(none.tex_coords_1),
        }
    }

    /// Whether no table exists (no triangle has an extra attribute).
    pub fn is_empty(&self) -> bool {
        self.colors.is_none() && self.tex_coords_1.is_none()
    }
}

/// Appends `value` to `table` as triangle `index`'s, making the table (filled with
/// `default` before it) where it is the first value that is not `default`.
fn push_sparse<T: Copy + PartialEq>(
    table: &mut Option<Vec<T>>,
    index: usize,
    value: T,
    default: T,
) {
    match table {
        Some(values) => values.push(value),
        None if value != default => {
            let mut values = vec![default; index];
            values.push(value);
            *table = Some(values);
        }
        None => {}
    }
}

/// A scene's materials, textures and per-triangle shading data.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneMaterials {
    /// The materials that triangles refer to.
    pub materials: Vec<PbrMaterial>,
    /// The decoded textures that materials refer to.
    pub textures: Vec<Texture>,
    /// One entry per triangle of the scene, in the same order.
    pub triangles: Vec<TriangleShading>,
    /// The vertex colours and second texture coordinates, parallel to `triangles` where
    /// some triangle has them (empty tables otherwise).
    pub extra: ExtraAttributeTables,
}

/// Vertex normals closer to the face normal than this (1 - cos of 0.8 degrees) count as
/// flat: a mesh exported with its face normals renders as the workshop's faceted triangles.
pub const FLAT_NORMAL_TOLERANCE: f32 = 1e-4;

impl SceneMaterials {
    /// The materials of flat, diffuse triangles (one per distinct albedo, emission and
    /// sidedness), for a plain scene rendered with the material kernels (an environment or
    /// punctual lights need them).
    pub fn from_plain(triangles: &[super::Triangle]) -> SceneMaterials {
        let mut indices = std::collections::HashMap::new();
        let mut materials = Vec::new();
        let shading = triangles
            .iter()
            .map(|triangle| {
                let key = (
                    triangle.color.to_array().map(f32::to_bits),
                    triangle.emission.to_array().map(f32::to_bits),
                    triangle.double_sided,
                );
                let material = *indices.entry(key).or_insert_with(|| {
                    materials.push(PbrMaterial::lambertian(
                        triangle.color,
                        triangle.emission,
                        triangle.double_sided,
                    ));
                    materials.len() as u32 - 1
                });
                TriangleShading {
                    material,
                    normals: [triangle.normal; 3],
                    tex_coords: [Vec2::ZERO; 3],
                    tangents: [Vec4::ZERO; 3],
                }
            })
            .collect();
        SceneMaterials {
            materials,
            textures: Vec::new(),
            triangles: shading,
            extra: ExtraAttributeTables::default(),
        }
    }

    /// Whether the workshop's flat, diffuse triangles describe the scene exactly: every
    /// material is plain Lambertian, every vertex normal is its face's normal and no
    /// triangle has vertex colours.
    pub fn is_plain(&self, face_normals: impl Iterator<Item = Vec3>) -> bool {
        self.extra.colors.is_none()
            && self.materials.iter().all(PbrMaterial::is_plain_lambertian)
            && self
                .triangles
                .iter()
                .zip(face_normals)
                .all(|(shading, face)| {
                    shading
                        .normals
                        .iter()
                        .all(|n| n.dot(face) >= 1.0 - FLAT_NORMAL_TOLERANCE)
                })
    }

    /// Whether any material needs the kernels' layers (`SCENE_HAS_LAYERS`): transmission,
    /// a clear coat, KHR_materials_specular's textures or KHR_materials_unlit.
    pub fn uses_layers(&self) -> bool {
        self.materials.iter().any(|m| {
            m.is_layered()
                || m.unlit
                || m.specular_texture.is_some()
                || m.specular_color_texture.is_some()
        })
    }

    /// Whether any material encloses a scattering volume (`SCENE_HAS_VOLUME_SCATTER`): a
    /// refracting volume (transmission, thickness above 0, ior not 1) whose
    /// KHR_materials_volume_scatter gives it a scattering coefficient above 0. False in
    /// every scene without the extension, whose kernels then compile the volume's medium
    /// out.
    pub fn uses_volume_scatter(&self) -> bool {
        self.materials.iter().any(|m| {
            m.transmission.factor > 0.0
                && m.transmission.thickness > 0.0
                && m.ior != 1.0
                && m.transmission.scatters()
        })
    }

    /// Whether any material has a specular (GGX) lobe (`SCENE_HAS_SPECULAR`): metallic or
    /// KHR_materials_specular's specular above 0, or the layers (`uses_layers`). False where
    /// every material is Lambertian, whose BRDF the kernels then evaluate as albedo / pi.
    pub fn uses_specular(&self) -> bool {
        self.uses_layers()
            || self
                .materials
                .iter()
                .any(|m| m.metallic != 0.0 || m.specular != 0.0)
    }

    /// The vertex attributes beyond normals, UVs and tangents that the kernels must read
    /// (`SPEC_SCENE_VERTEX_ATTRIBUTES`): `VERTEX_ATTRIBUTE_COLOR` where some triangle has a
    /// vertex colour other than opaque white (white changes nothing, so it is left out);
    /// `VERTEX_ATTRIBUTE_TEX_COORD_1` where some triangle has a second texture coordinate
    /// other than 0 or some material reads one (where every one is 0 there is no table, and
    /// the kernels read 0).
    pub fn vertex_attributes(&self) -> u32 {
        let mut attributes = 0;
        if self.extra.colors.is_some() {
            attributes |= crate::contract::VERTEX_ATTRIBUTE_COLOR;
        }
        if self.extra.tex_coords_1.is_some() || self.reads_tex_coord_1() {
            attributes |= crate::contract::VERTEX_ATTRIBUTE_TEX_COORD_1;
        }
        attributes
    }

    /// Whether some material has a texture on `TEXCOORD_1`.
    pub fn reads_tex_coord_1(&self) -> bool {
        self.materials
            .iter()
            .any(|m| super::material_params::first_slot_on_tex_coord_1(m).is_some())
    }

    /// Whether any material uses alpha (mask or blend).
    pub fn uses_alpha(&self) -> bool {
        self.materials
            .iter()
            .any(|m| m.alpha_mode != AlphaMode::Opaque)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambertian_is_plain_and_defaults_are_not() {
        let plain = PbrMaterial::lambertian(Vec3::splat(0.5), Vec3::ZERO, false);
        assert!(plain.is_plain_lambertian());
        let metal = PbrMaterial {
            metallic: 1.0,
            ..plain
        };
        assert!(!metal.is_plain_lambertian());
        let shiny = PbrMaterial {
            specular: 1.0,
            ..plain
        };
        assert!(!shiny.is_plain_lambertian());
        let masked = PbrMaterial {
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            ..plain
        };
        assert!(!masked.is_plain_lambertian());
    }

    #[test]
    fn sanitized_clamps_and_maps_special_iors() {
        let material = PbrMaterial {
            base_color: Vec4::new(2.0, -1.0, f32::NAN, 0.5),
            metallic: 3.0,
            roughness: f32::NAN,
            ior: 0.0,
            ..PbrMaterial::lambertian(Vec3::ONE, Vec3::ZERO, false)
        }
        .sanitized();
        assert_eq!(material.base_color, Vec4::new(1.0, 0.0, 0.0, 0.5));
        assert_eq!(
            (material.metallic, material.roughness, material.ior),
            (1.0, 0.0, 1e4)
        );
        let inf = PbrMaterial {
            ior: f32::INFINITY,
            ..material
        }
        .sanitized();
        assert_eq!(inf.ior, 1e4);
    }

    #[test]
    fn attenuation_keeps_the_colour_over_the_distance() {
        let sigma = Transmission::attenuation_coefficient(Vec3::new(0.5, 1.0, 0.25), 2.0);
        assert!((sigma.x - std::f32::consts::LN_2 / 2.0).abs() < 1e-7);
        assert_eq!(sigma.y, 0.0);
        assert!(((-sigma.z * 2.0).exp() - 0.25).abs() < 1e-7);
        assert_eq!(
            Transmission::attenuation_coefficient(Vec3::splat(0.5), f32::INFINITY),
            Vec3::ZERO
        );
        let black = Transmission::attenuation_coefficient(Vec3::ZERO, 1.0);
        assert!(black.x.is_finite() && (-black.x).exp() < 1e-29);
    }

    #[test]
    fn layers_are_not_plain() {
        let mut glass = PbrMaterial::lambertian(Vec3::ONE, Vec3::ZERO, false);
        glass.transmission.factor = 1.0;
        assert!(glass.is_layered() && !glass.is_plain_lambertian());
        let mut coated = PbrMaterial::lambertian(Vec3::ONE, Vec3::ZERO, false);
        coated.clearcoat.factor = 0.5;
        assert!(coated.is_layered() && !coated.is_plain_lambertian());
    }

    #[test]
    fn flat_vertex_normals_are_plain() {
        let shading = TriangleShading {
            material: 0,
            normals: [Vec3::Z; 3],
            tex_coords: [Vec2::ZERO; 3],
            tangents: [Vec4::ZERO; 3],
        };
        let mut materials = SceneMaterials {
            materials: vec![PbrMaterial::lambertian(Vec3::ONE, Vec3::ZERO, false)],
            textures: vec![],
            triangles: vec![shading],
            extra: ExtraAttributeTables::default(),
        };
        assert!(materials.is_plain([Vec3::Z].into_iter()));
        // Vertex colours are not plain
        let mut coloured = materials.clone();
        coloured.extra.colors = Some(vec![[Vec4::new(1.0, 0.0, 0.0, 1.0); 3]]);
        assert!(!coloured.is_plain([Vec3::Z].into_iter()));
        materials.triangles[0].normals[1] = Vec3::new(0.1, 0.0, 1.0).normalize();
        assert!(!materials.is_plain([Vec3::Z].into_iter()));
    }

    #[test]
    fn extra_attribute_tables_exist_only_from_the_first_value_that_is_not_the_default() {
        let mut tables = ExtraAttributeTables::default();
        let none = ExtraVertexAttributes::NONE;
        // Defaults: no table at all (a scene without vertex colours keeps its memory)
        tables.push(0, &none);
        tables.push(1, &none);
        assert!(tables.is_empty());
        let red = ExtraVertexAttributes {
            colors: [Vec4::new(1.0, 0.0, 0.0, 1.0); 3],
            ..none
        };
        tables.push(2, &red);
        tables.push(3, &none);
        let colors = tables.colors.as_ref().expect("a colour table");
        assert_eq!(colors.len(), 4);
        assert_eq!(colors[..2], [none.colors; 2]);
        assert_eq!(tables.get(2), red);
        assert_eq!(tables.get(3), none);
        // Only the colours were given: no texture-coordinate table
        assert!(tables.tex_coords_1.is_none());
        assert_eq!(tables.get(2).tex_coords_1, [Vec2::ZERO; 3]);
    }
}
