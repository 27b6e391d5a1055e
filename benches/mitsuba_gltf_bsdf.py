"""The glTF 2.0 metallic-roughness BRDF (the specification's Appendix B) as a Mitsuba 3 BSDF
written in Python, for benches/mitsuba_textured.py --metallic-roughness.

Mitsuba's own BSDFs do not model it: `principled` has Disney's retro-reflective diffuse and
its own specular tint, `roughconductor` a complex (not Schlick) Fresnel and separable Smith
masking. So this plugin evaluates what vkpath's glsl/brdf.glsl evaluates, written again here
from the specification (not translated from the Rust twin), for glTF's defaults
(KHR_materials_specular factor 1, colour white; ior 1.5, so F0 = 0.04):

    f = mix(dielectric, metal, metallic)
    dielectric = (1 - F_d) base_color / pi + F_d D V,   F_d = Schlick(0.04, 1, |v.h|)
    metal      = F_m D V,                               F_m = Schlick(base_color, 1, |v.h|)
    D = GGX (Trowbridge-Reitz) with alpha = max(roughness^2, 1e-4),
    V = height-correlated Smith visibility G_2 / (4 n.l n.v) (Heitz 2014),

with metallic = metallic_factor * B and roughness = roughness_factor * G of the
metallic-roughness texture (glTF 2.0, 3.9.2: "The metalness values are sampled from the B
channel. The roughness values are sampled from the G channel."). The texture must be given
as a `bitmap` with raw True: glTF stores it linearly (3.9.4: "Texture contents are linear"),
and raw False would decode it as sRGB.

Sampling (any unbiased scheme would do; Mitsuba's `path` integrator combines it with light
samples by MIS through pdf()): with probability p_s a visible GGX normal (Dupuy and Benyoub
2023, spherical caps) reflected, else a cosine-weighted direction; p_s is the specular share
of the energy estimated by Fresnel at n.v, as vkpath does (it only changes the noise).
"""

import math


def register(mi, dr):
    """Registers the plugin `gltf_metallic_roughness` (call after mi.set_variant). Its
    properties: base_color (texture, linear RGB), metallic_roughness (optional texture,
    roughness in G, metallic in B), metallic_factor, roughness_factor (floats, default 1),
    metallic_channel, roughness_channel (0..2, default 2 and 1: for --break mr-swap)."""

    def schlick(f0, f90, view_dot_half):
        weight = dr.maximum(0.0, 1.0 - dr.abs(view_dot_half))
        weight2 = weight * weight
        return f0 + (f90 - f0) * (weight2 * weight2 * weight)

    def luminance(color):
        return 0.2126 * color.x + 0.7152 * color.y + 0.0722 * color.z

    def ggx_distribution(alpha, half):
        stretched = (half.x * half.x + half.y * half.y) / (alpha * alpha) + half.z * half.z
        return dr.select(half.z > 0.0, 1.0 / (math.pi * alpha * alpha * stretched * stretched), 0.0)

    class GltfMetallicRoughness(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.base_color = props.get_texture("base_color")
            self.metallic_roughness = (props.get_texture("metallic_roughness")
                                       if props.has_property("metallic_roughness") else None)
            get = lambda name, default: props[name] if props.has_property(name) else default  # noqa: E731
            self.metallic_factor = float(get("metallic_factor", 1.0))
            self.roughness_factor = float(get("roughness_factor", 1.0))
            self.metallic_channel = int(get("metallic_channel", 2))
            self.roughness_channel = int(get("roughness_channel", 1))
            glossy = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            diffuse = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide
            self.m_components = [glossy, diffuse]
            self.m_flags = glossy | diffuse

        def material(self, si, active):
            """(base colour, metallic, GGX alpha) at the interaction."""
            base = self.base_color.eval(si, active)
            if self.metallic_roughness is not None:
                texel = self.metallic_roughness.eval(si, active)
                metallic = self.metallic_factor * texel[self.metallic_channel]
                roughness = self.roughness_factor * texel[self.roughness_channel]
            else:
                metallic = mi.Float(self.metallic_factor)
                roughness = mi.Float(self.roughness_factor)
            return base, metallic, dr.maximum(roughness * roughness, 1.0e-4)

        def specular_probability(self, base, metallic, cos_view):
            dielectric = schlick(0.04, 1.0, cos_view)
            metal = schlick(base, 1.0, cos_view)
            specular = luminance(dielectric * (1.0 - metallic) + metal * metallic)
            diffuse = (1.0 - metallic) * luminance((1.0 - dielectric) * base)
            total = specular + diffuse
            return dr.select(total > 0.0, specular / dr.maximum(total, 1e-30), 0.5)

        def eval_pdf(self, ctx, si, wo, active=True):
            base, metallic, alpha = self.material(si, active)
            wi = si.wi
            cos_view, cos_light = wi.z, wo.z
            half = dr.normalize(wi + wo)
            a2 = alpha * alpha
            root_view = dr.sqrt(a2 + (1.0 - a2) * cos_view * cos_view)
            root_light = dr.sqrt(dr.maximum(a2 + (1.0 - a2) * cos_light * cos_light, 0.0))
            distribution = ggx_distribution(alpha, half)
            visibility = 0.5 / (cos_light * root_view + cos_view * root_light)
            specular = distribution * visibility
            view_dot_half = dr.dot(wi, half)
            fresnel_d = schlick(0.04, 1.0, view_dot_half)
            fresnel_m = schlick(base, 1.0, view_dot_half)
            dielectric = (1.0 - fresnel_d) * base / math.pi + fresnel_d * specular
            metal = fresnel_m * specular
            brdf = dielectric * (1.0 - metallic) + metal * metallic
            valid = active & (cos_view > 0.0) & (cos_light > 0.0)
            value = dr.select(valid, brdf * cos_light, 0.0)
            p_s = self.specular_probability(base, metallic, cos_view)
            density = (p_s * distribution / (2.0 * (cos_view + root_view))
                       + (1.0 - p_s) * dr.maximum(cos_light, 0.0) / math.pi)
            density = dr.select(active & (cos_view > 0.0), density, 0.0)
            return value, density

        def eval(self, ctx, si, wo, active=True):
            return self.eval_pdf(ctx, si, wo, active)[0]

        def pdf(self, ctx, si, wo, active=True):
            return self.eval_pdf(ctx, si, wo, active)[1]

        def sample(self, ctx, si, sample1, sample2, active=True):
            base, metallic, alpha = self.material(si, active)
            wi = si.wi
            active = active & (wi.z > 0.0)
            p_s = self.specular_probability(base, metallic, wi.z)
            choose_specular = sample1 < p_s
            # A visible normal: the stretched view plus a uniform point on the cap below it.
            stretched = dr.normalize(mi.Vector3f(alpha * wi.x, alpha * wi.y, wi.z))
            phi = 2.0 * math.pi * sample2.x
            z = (1.0 - sample2.y) * (1.0 + stretched.z) - stretched.z
            sin_theta = dr.sqrt(dr.clip(1.0 - z * z, 0.0, 1.0))
            cap = mi.Vector3f(sin_theta * dr.cos(phi), sin_theta * dr.sin(phi), z) + stretched
            half = dr.normalize(mi.Vector3f(alpha * cap.x, alpha * cap.y, cap.z))
            reflected = 2.0 * dr.dot(wi, half) * half - wi
            cosine = mi.warp.square_to_cosine_hemisphere(sample2)
            wo = dr.select(choose_specular, reflected, cosine)
            value, density = self.eval_pdf(ctx, si, wo, active)
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = wo
            bs.pdf = density
            bs.eta = 1.0
            bs.sampled_component = dr.select(choose_specular, mi.UInt32(0), mi.UInt32(1))
            bs.sampled_type = dr.select(choose_specular, mi.UInt32(+mi.BSDFFlags.GlossyReflection),
                                        mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
            weight = dr.select(active & (density > 0.0), value / dr.maximum(density, 1e-30), 0.0)
            return bs, weight

        def traverse(self, callback):
            pass

        def parameters_changed(self, keys):
            pass

        def to_string(self):
            return (f"GltfMetallicRoughness[metallic_factor={self.metallic_factor}, "
                    f"roughness_factor={self.roughness_factor}, textured="
                    f"{self.metallic_roughness is not None}]")

    mi.register_bsdf("gltf_metallic_roughness", lambda props: GltfMetallicRoughness(props))
