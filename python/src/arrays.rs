//! `vkpath.Scene.from_arrays`'s inputs: numpy arrays (or anything `numpy.asarray` takes)
//! checked for shape and type, materials as dicts of glTF's factors (`MaterialFactors`,
//! by `material_keys`, the parameter table's factors) and punctual lights as dicts of KHR_lights_punctual's values. Every
//! mistake is a `vkpath.ArgumentError` (a `ValueError`) that names the parameter or key.

use glam::{Vec2, Vec3};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use vkpath::lights::{PunctualKind, PunctualLight};
use vkpath::scene::material_params::{self, ParamKind, MATERIAL_PARAMS};
use vkpath::scene::materials::AlphaMode;
use vkpath::scene::MaterialFactors;

use crate::errors::argument_error;

/// A material dict's keys: glTF's factor names in snake case (`baseColorFactor` is
/// `base_color`, `emissiveFactor` is `emission`, KHR_materials_*'s factors by their
/// extension's words), the factors of the material parameter table
/// (`vkpath::scene::material_params::MATERIAL_PARAMS`), in its order.
pub fn material_keys() -> Vec<&'static str> {
    material_params::material_keys()
}

/// A light dict's keys (KHR_lights_punctual's, with the node's placement as `position` and
/// `direction`).
pub const LIGHT_KEYS: [&str; 7] = [
    "type",
    "color",
    "intensity",
    "position",
    "direction",
    "inner_cone_angle",
    "outer_cone_angle",
];

/// `value` as a contiguous numpy array (`numpy.asarray`), with its shape and dtype kind
/// ('f', 'i', 'u', 'b', ...).
fn numpy_array<'py>(
    value: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<(Bound<'py, PyAny>, Vec<usize>, String)> {
    let numpy = value.py().import("numpy")?;
    let array = numpy
        .call_method1("asarray", (value,))
        .map_err(|e| argument_error(format!("{name}: not an array ({e})")))?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    Ok((array, shape, kind))
}

/// The rows of an array of shape (N, `columns`) of numbers, as float32 (float64 values
/// rounded as numpy rounds them).
pub fn float_rows(value: &Bound<'_, PyAny>, name: &str, columns: usize) -> PyResult<Vec<f32>> {
    let (array, shape, kind) = numpy_array(value, name)?;
    if shape.len() != 2 || shape[1] != columns {
        return Err(argument_error(format!(
            "{name} must have shape (N, {columns}), not {}",
            shape_text(&shape)
        )));
    }
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(argument_error(format!(
            "{name} must hold numbers, not {}",
            array.getattr("dtype")?.str()?
        )));
    }
    let numpy = value.py().import("numpy")?;
    let floats = numpy.call_method1("ascontiguousarray", (array, "float32"))?;
    let bytes: Vec<u8> = floats.call_method0("tobytes")?.extract()?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// The triangles' vertex indices: shape (M, 3), or flat with a multiple of 3 entries,
/// whole numbers in [0, 2^32).
pub fn index_triples(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[u32; 3]>> {
    let flat = whole_numbers(value, name, true)?;
    Ok(flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect())
}

/// One whole number per triangle (`material_indices`): shape (M,).
pub fn whole_number_list(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<u32>> {
    whole_numbers(value, name, false)
}

/// The entries of an integer array, flattened: `triples` takes (M, 3) or a flat multiple of
/// 3, else a flat list.
fn whole_numbers(value: &Bound<'_, PyAny>, name: &str, triples: bool) -> PyResult<Vec<u32>> {
    let (array, shape, kind) = numpy_array(value, name)?;
    let shape_ok = if triples {
        (shape.len() == 2 && shape[1] == 3) || (shape.len() == 1 && shape[0] % 3 == 0)
    } else {
        shape.len() == 1
    };
    if !shape_ok {
        let wanted = if triples {
            "(M, 3) or (3 M,)"
        } else {
            "(M,), one per triangle"
        };
        return Err(argument_error(format!(
            "{name} must have shape {wanted}, not {}",
            shape_text(&shape)
        )));
    }
    if !matches!(kind.as_str(), "i" | "u") {
        return Err(argument_error(format!(
            "{name} must hold integers, not {}",
            array.getattr("dtype")?.str()?
        )));
    }
    if shape.iter().product::<usize>() == 0 {
        return Ok(Vec::new());
    }
    let (low, high): (i128, i128) = (
        array.call_method0("min")?.extract()?,
        array.call_method0("max")?.extract()?,
    );
    if low < 0 || high > i128::from(u32::MAX) {
        let bad = if low < 0 { low } else { high };
        return Err(argument_error(format!(
            "{name} holds {bad}, outside [0, {}]",
            u32::MAX
        )));
    }
    let numpy = value.py().import("numpy")?;
    let words = numpy.call_method1("ascontiguousarray", (array, "uint32"))?;
    let bytes: Vec<u8> = words.call_method0("tobytes")?.extract()?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// A shape as Python writes it: `(4, 2)`, `(7,)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// Each key of `dict` that is not in `known`: an error naming the first, with the known ones.
fn check_keys(dict: &Bound<'_, PyDict>, what: &str, known: &[&str]) -> PyResult<()> {
    for key in dict.keys() {
        let name: String = match key.cast::<PyString>() {
            Ok(text) => text.to_string(),
            Err(_) => {
                return Err(argument_error(format!(
                    "{what}: key {} is not a string",
                    key.repr()?
                )))
            }
        };
        if !known.contains(&name.as_str()) {
            return Err(argument_error(format!(
                "{what}: unknown key '{name}' (known: {})",
                known.join(", ")
            )));
        }
    }
    Ok(())
}

/// A dict's value for `key`, extracted; `None` when absent. A wrong type names the key.
fn get<'py, T: for<'a> FromPyObjectOwned<'py>>(
    dict: &Bound<'py, PyDict>,
    what: &str,
    key: &str,
    expected: &str,
) -> PyResult<Option<T>> {
    match dict.get_item(key)? {
        None => Ok(None),
        Some(value) => value.extract::<T>().map(Some).map_err(|_| {
            argument_error(format!(
                "{what}: {key}={} is not {expected}",
                value.repr().map_or_else(|_| "?".into(), |r| r.to_string())
            ))
        }),
    }
}

/// An RGB or XYZ value for `key`: any sequence of three numbers (a tuple, a list, a NumPy
/// array).
fn vec3(dict: &Bound<'_, PyDict>, what: &str, key: &str) -> PyResult<Option<Vec3>> {
    let Some(value) = dict.get_item(key)? else {
        return Ok(None);
    };
    match numbers(&value).as_deref() {
        Some(&[x, y, z]) => Ok(Some(Vec3::new(x, y, z))),
        _ => Err(argument_error(format!(
            "{what}: {key}={} is not three numbers",
            value.repr().map_or_else(|_| "?".into(), |r| r.to_string())
        ))),
    }
}

/// The numbers of a sequence (a tuple, a list, a NumPy array; not a string); `None` when
/// `value` is not one.
fn numbers(value: &Bound<'_, PyAny>) -> Option<Vec<f32>> {
    if value.is_instance_of::<PyString>() {
        return None;
    }
    value
        .try_iter()
        .ok()?
        .map(|item| item.ok()?.extract::<f32>().ok())
        .collect()
}

/// A colour factor that is not finite and at least 0 in every component: an error naming
/// the key (a negative emission would subtract light).
fn check_colour(what: &str, key: &str, colour: Vec3) -> PyResult<()> {
    if colour.is_finite() && colour.min_element() >= 0.0 {
        return Ok(());
    }
    Err(argument_error(format!(
        "{what}: {key}=({}, {}, {}) has a negative or non-finite component: a colour factor is at least 0",
        colour.x, colour.y, colour.z
    )))
}

/// A number for `key`.
fn number(dict: &Bound<'_, PyDict>, what: &str, key: &str) -> PyResult<Option<f32>> {
    get::<f32>(dict, what, key, "a number")
}

/// The factors a material dict gives, glTF's defaults for the keys it leaves out.
pub fn material_factors(value: &Bound<'_, PyAny>, index: usize) -> PyResult<MaterialFactors> {
    let what = format!("materials[{index}]");
    let dict = value
        .cast::<PyDict>()
        .map_err(|_| argument_error(format!("{what} is not a dict of glTF factors")))?;
    check_keys(dict, &what, &material_keys())?;
    let mut factors = MaterialFactors::default();
    let factor_rows = || {
        MATERIAL_PARAMS
            .iter()
            .filter_map(|param| Some((param, param.factor?)))
    };
    // RGBA first, then the numbers, the multipliers' check, the colours (each checked).
    for (param, factor) in factor_rows().filter(|(p, _)| p.kind == ParamKind::Rgba) {
        if let Some(color) = dict.get_item(param.name)? {
            let value = match numbers(&color).as_deref() {
                Some(&[r, g, b, a]) => [r, g, b, a],
                Some(&[r, g, b]) => [r, g, b, 1.0],
                _ => {
                    return Err(argument_error(format!(
                        "{what}: {} is not RGB or RGBA numbers",
                        param.name
                    )))
                }
            };
            (factor.set)(&mut factors, value);
        }
    }
    let is_number = |kind| matches!(kind, ParamKind::Number | ParamKind::NonNegative);
    for (param, factor) in factor_rows().filter(|(p, _)| is_number(p.kind)) {
        if let Some(value) = number(dict, &what, param.name)? {
            (factor.set)(&mut factors, [value, 0.0, 0.0, 0.0]);
        }
    }
    for (param, factor) in factor_rows().filter(|(p, _)| p.kind == ParamKind::NonNegative) {
        let value = (factor.get)(&factors)[0];
        if !(value.is_finite() && value >= 0.0) {
            return Err(argument_error(format!(
                "{what}: {}={value} is not a number at least 0",
                param.name
            )));
        }
    }
    for (param, factor) in factor_rows().filter(|(p, _)| p.kind == ParamKind::Rgb) {
        if let Some(value) = vec3(dict, &what, param.name)? {
            check_colour(&what, param.name, value)?;
            (factor.set)(&mut factors, value.extend(0.0).to_array());
        }
    }
    let cutoff = number(dict, &what, "alpha_cutoff")?;
    factors.alpha_mode = match get::<String>(dict, &what, "alpha_mode", "a string")?.as_deref() {
        None | Some("opaque") => AlphaMode::Opaque,
        Some("mask") => AlphaMode::Mask {
            cutoff: cutoff.unwrap_or(0.5),
        },
        Some("blend") => AlphaMode::Blend,
        Some(other) => {
            return Err(argument_error(format!(
                "{what}: alpha_mode='{other}' is not one of opaque, mask, blend"
            )))
        }
    };
    for (param, factor) in factor_rows().filter(|(p, _)| p.kind == ParamKind::Bool) {
        if let Some(value) = get::<bool>(dict, &what, param.name, "True or False")? {
            (factor.set)(&mut factors, [f32::from(u8::from(value)), 0.0, 0.0, 0.0]);
        }
    }
    Ok(factors)
}

/// The light a light dict describes (KHR_lights_punctual's `type`, `color`, `intensity`,
/// spot cone angles in radians, and its `position` and `direction` in world space).
pub fn punctual_light(value: &Bound<'_, PyAny>, index: usize) -> PyResult<PunctualLight> {
    let what = format!("lights[{index}]");
    let dict = value
        .cast::<PyDict>()
        .map_err(|_| argument_error(format!("{what} is not a dict")))?;
    check_keys(dict, &what, &LIGHT_KEYS)?;
    let kind = match get::<String>(dict, &what, "type", "a string")?.as_deref() {
        Some("point") => PunctualKind::Point,
        Some("directional") => PunctualKind::Directional,
        Some("spot") => PunctualKind::Spot {
            // KHR_lights_punctual's defaults.
            inner_cone_angle: number(dict, &what, "inner_cone_angle")?.unwrap_or(0.0),
            outer_cone_angle: number(dict, &what, "outer_cone_angle")?
                .unwrap_or(std::f32::consts::FRAC_PI_4),
        },
        other => {
            return Err(argument_error(format!(
                "{what}: type={} is not one of 'point', 'spot', 'directional'",
                other.map_or_else(|| "None".to_owned(), |name| format!("'{name}'"))
            )))
        }
    };
    let color = vec3(dict, &what, "color")?.unwrap_or(Vec3::ONE);
    let intensity = number(dict, &what, "intensity")?.unwrap_or(1.0);
    let position = vec3(dict, &what, "position")?.unwrap_or(Vec3::ZERO);
    let direction = vec3(dict, &what, "direction")?
        .unwrap_or(Vec3::NEG_Z)
        .try_normalize()
        .ok_or_else(|| argument_error(format!("{what}: direction has no length")))?;
    // As `PunctualLight::new` makes a glTF node's light.
    let intensity = color.max(Vec3::ZERO) * intensity.max(0.0);
    if !(position.is_finite() && intensity.is_finite()) {
        return Err(argument_error(format!(
            "{what}: position and intensity must be finite"
        )));
    }
    Ok(PunctualLight {
        kind,
        position,
        direction,
        intensity,
    })
}

/// Vec3s from float rows of 3.
pub fn vec3s(floats: &[f32]) -> Vec<Vec3> {
    floats.chunks_exact(3).map(Vec3::from_slice).collect()
}

/// Vec2s from float rows of 2.
pub fn vec2s(floats: &[f32]) -> Vec<Vec2> {
    floats.chunks_exact(2).map(Vec2::from_slice).collect()
}
