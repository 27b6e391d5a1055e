//! Intel Open Image Denoise (OIDN), loaded at run time: its `RT` filter (the generic
//! ray-tracing denoiser) on a linear HDR image, optionally guided by albedo and normal layers.
//!
//! vkpath neither links OIDN nor needs it to build or run: [`denoise`] and [`available`] look
//! for the shared library the first time they are called, in this order, and keep what they
//! found (or why nothing was found) for the life of the process:
//! 1. the file named by `VKPATH_OIDN_LIBRARY`, when that variable is set (then only that file);
//! 2. [`INSTALL_DIR`], where `scripts/install-oidn.sh` puts it;
//! 3. the plain sonames through the dynamic loader (`LD_LIBRARY_PATH`, `ldconfig`'s cache):
//!    `libOpenImageDenoise.so.2`, `.so.1`, `.so`.
//!
//! OIDN 1.x and 2.x both work: the few C functions used here have kept their signatures, and
//! the one that was renamed (`oidnSetFilter1b`, `oidnSetFilterBool` in 2.x) is looked up
//! under both names. The device is always OIDN's CPU device, because the images are shared
//! from host memory (`oidnSetSharedFilterImage`), which a GPU device could not read.
//!
//! All of vkpath's `unsafe` for OIDN is in this file.

use std::ffi::{c_char, c_int, c_void, CStr};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libloading::Library;

/// Environment variable naming the OIDN shared library file to load (searched first).
pub const LIBRARY_ENV: &str = "VKPATH_OIDN_LIBRARY";

/// Folder where `scripts/install-oidn.sh` installs OIDN (searched second).
pub const INSTALL_DIR: &str = "/opt/vkpath-oidn/lib";

/// Sonames tried in [`INSTALL_DIR`] and then through the dynamic loader, newest major first.
const SONAMES: [&str; 3] = [
    "libOpenImageDenoise.so.2",
    "libOpenImageDenoise.so.1",
    "libOpenImageDenoise.so",
];

/// The TBB that OIDN needs; loaded first from the OIDN library's own folder when it is
/// there, since a library unpacked from a Python wheel (whose RPATH is `$ORIGIN/../lib`)
/// does not find it otherwise.
const TBB_SONAME: &str = "libtbb.so.12";

/// How to install OIDN, the tail of the not-found messages.
const INSTALL_HINT: &str =
    "install it with `bash scripts/install-oidn.sh` (as root, from a vkpath \
     checkout), or download Intel's OIDN 1.x release (github.com/OpenImageDenoise/oidn/releases) \
     and set VKPATH_OIDN_LIBRARY to its lib/libOpenImageDenoise.so";

/// What can go wrong when denoising. Every message is one line.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum DenoiseError {
    /// No OIDN library was found anywhere vkpath looks.
    #[error("Intel Open Image Denoise not found (looked in {INSTALL_DIR} and for {}): {INSTALL_HINT}", SONAMES.join(", "))]
    NotFound,
    /// A file that should be OIDN was found but could not be loaded or lacks a function.
    #[error("cannot use Intel Open Image Denoise from {path}: {reason}; {INSTALL_HINT}")]
    Unusable {
        /// The file (or soname) that was tried.
        path: String,
        /// What the dynamic loader said, or the missing function.
        reason: String,
    },
    /// An OIDN call reported an error.
    #[error("Intel Open Image Denoise failed to {step}: {message} (OIDN error {code})")]
    Oidn {
        /// What vkpath was doing, e.g. "execute the RT filter".
        step: &'static str,
        /// OIDN's `OIDNError` code (1 unknown, 2 invalid argument, 3 invalid operation,
        /// 4 out of memory, 5 unsupported hardware, 6 cancelled).
        code: i32,
        /// OIDN's message.
        message: String,
    },
    /// The images passed to [`denoise`] do not fit together.
    #[error("cannot denoise: {0}")]
    InvalidInput(String),
}

/// Where OIDN was found: the file given in `VKPATH_OIDN_LIBRARY`, the file in
/// [`INSTALL_DIR`], or the soname the dynamic loader resolved. Loads the library on the first
/// call.
pub fn available() -> Result<String, DenoiseError> {
    library().map(|api| api.location.clone())
}

/// Denoises a linear HDR image with OIDN's `RT` filter (`hdr` on) and returns the denoised
/// image.
///
/// All layers are `width * height` pixels, rows in the same order (either order works, as
/// long as all layers agree). `color` is linear radiance (any non-negative range); `albedo`
/// the first-hit surface albedo in [0, 1]; `normal` the first-hit normal in any space
/// (OIDN only needs it consistent over the image), components in [-1, 1]. As OIDN requires,
/// `normal` may only be given together with `albedo`.
///
/// Non-finite input values (NaN, ±inf, e.g. from a firefly that overflowed) are replaced by 0
/// before denoising: OIDN would spread one such pixel over its neighbourhood.
pub fn denoise(
    color: &[[f32; 3]],
    albedo: Option<&[[f32; 3]]>,
    normal: Option<&[[f32; 3]]>,
    width: u32,
    height: u32,
) -> Result<Vec<[f32; 3]>, DenoiseError> {
    let pixel_count = check_layers(color, albedo, normal, width, height)?;
    let api = library()?;
    // Owned, sanitised copies: OIDN reads them through mutable pointers.
    let mut color = finite_or_zero(color);
    let mut albedo = albedo.map(finite_or_zero);
    let mut normal = normal.map(finite_or_zero);
    let mut output = vec![[0.0f32; 3]; pixel_count];

    let device = Device::new(api)?;
    let filter = Filter::new(&device)?;
    let (width, height) = (width as usize, height as usize);
    filter.set_image(c"color", &mut color, width, height)?;
    if let Some(albedo) = albedo.as_mut() {
        filter.set_image(c"albedo", albedo, width, height)?;
    }
    if let Some(normal) = normal.as_mut() {
        filter.set_image(c"normal", normal, width, height)?;
    }
    filter.set_image(c"output", &mut output, width, height)?;
    filter.set_hdr()?;
    filter.commit_and_execute()?;
    // The filter and device are released here, before `output` is handed out: OIDN holds
    // pointers into the images until then.
    drop(filter);
    drop(device);
    Ok(output)
}

/// Checks the layers' sizes; returns the pixel count.
fn check_layers(
    color: &[[f32; 3]],
    albedo: Option<&[[f32; 3]]>,
    normal: Option<&[[f32; 3]]>,
    width: u32,
    height: u32,
) -> Result<usize, DenoiseError> {
    let invalid = |message: String| Err(DenoiseError::InvalidInput(message));
    if width == 0 || height == 0 {
        return invalid(format!("the image is {width}x{height}"));
    }
    let Some(pixel_count) = (width as usize).checked_mul(height as usize) else {
        return invalid(format!("{width}x{height} pixels do not fit in memory"));
    };
    if normal.is_some() && albedo.is_none() {
        return invalid("OIDN takes a normal layer only together with an albedo layer".into());
    }
    let layers = [
        ("color", Some(color)),
        ("albedo", albedo),
        ("normal", normal),
    ];
    for (name, layer) in layers {
        if let Some(layer) = layer {
            if layer.len() != pixel_count {
                return invalid(format!(
                    "the {name} layer has {} pixels, a {width}x{height} image has {pixel_count}",
                    layer.len()
                ));
            }
        }
    }
    Ok(pixel_count)
}

/// A copy of `pixels` with every non-finite component replaced by 0.
fn finite_or_zero(pixels: &[[f32; 3]]) -> Vec<[f32; 3]> {
    pixels
        .iter()
        .map(|pixel| pixel.map(|value| if value.is_finite() { value } else { 0.0 }))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// The C API (OpenImageDenoise/oidn.h, identical in 1.4 and 2.x for what is used here).
// Handles are opaque pointers; C enums are `int` on the platforms OIDN ships for.

/// `OIDNDevice`, `OIDNFilter`: opaque handles.
type Handle = *mut c_void;
/// `OIDN_DEVICE_TYPE_CPU`.
const OIDN_DEVICE_TYPE_CPU: c_int = 1;
/// `OIDN_FORMAT_FLOAT3`: three 32-bit floats per pixel.
const OIDN_FORMAT_FLOAT3: c_int = 3;
/// `OIDN_ERROR_NONE`.
const OIDN_ERROR_NONE: c_int = 0;

type NewDeviceFn = unsafe extern "C" fn(device_type: c_int) -> Handle;
type DeviceFn = unsafe extern "C" fn(device: Handle);
type GetDeviceErrorFn =
    unsafe extern "C" fn(device: Handle, out_message: *mut *const c_char) -> c_int;
type NewFilterFn = unsafe extern "C" fn(device: Handle, filter_type: *const c_char) -> Handle;
type FilterFn = unsafe extern "C" fn(filter: Handle);
type SetSharedFilterImageFn = unsafe extern "C" fn(
    filter: Handle,
    name: *const c_char,
    pointer: *mut c_void,
    format: c_int,
    width: usize,
    height: usize,
    byte_offset: usize,
    byte_pixel_stride: usize,
    byte_row_stride: usize,
);
type SetFilterBoolFn = unsafe extern "C" fn(filter: Handle, name: *const c_char, value: bool);

/// The loaded library and the functions vkpath calls. Lives in a static for the whole
/// process (never unloaded: TBB's worker threads must not outlive their code), which keeps
/// the function pointers valid.
struct Api {
    /// Where the library was found, for [`available`].
    location: String,
    new_device: NewDeviceFn,
    commit_device: DeviceFn,
    release_device: DeviceFn,
    get_device_error: GetDeviceErrorFn,
    new_filter: NewFilterFn,
    set_shared_filter_image: SetSharedFilterImageFn,
    set_filter_bool: SetFilterBoolFn,
    commit_filter: FilterFn,
    execute_filter: FilterFn,
    release_filter: FilterFn,
    /// Keeps the code behind the pointers above mapped.
    _library: Library,
    /// TBB preloaded from the library's folder, if it was there.
    _tbb: Option<Library>,
}

/// The library, loaded on first use; a failure is remembered too.
fn library() -> Result<&'static Api, DenoiseError> {
    static API: OnceLock<Result<Api, DenoiseError>> = OnceLock::new();
    API.get_or_init(load).as_ref().map_err(Clone::clone)
}

/// Searches for OIDN in the documented order.
fn load() -> Result<Api, DenoiseError> {
    if let Some(path) = std::env::var_os(LIBRARY_ENV).filter(|path| !path.is_empty()) {
        // An explicit choice: never fall back to another library behind the user's back.
        return load_file(Path::new(&path));
    }
    // An installed file that exists but does not load (a missing TBB, a wrong architecture)
    // is worth reporting rather than "not found".
    let mut first_failure = None;
    for soname in SONAMES {
        let path = Path::new(INSTALL_DIR).join(soname);
        if path.exists() {
            match load_file(&path) {
                Ok(api) => return Ok(api),
                Err(error) => {
                    first_failure.get_or_insert(error);
                }
            }
        }
    }
    for soname in SONAMES {
        // SAFETY: loading a library runs its initialisers; OIDN's (and TBB's) are plain C++
        // static initialisers with no preconditions on the host process.
        if let Ok(library) = unsafe { Library::new(soname) } {
            return resolve(library, None, soname.to_string());
        }
    }
    Err(first_failure.unwrap_or(DenoiseError::NotFound))
}

/// Loads OIDN from a file, with the `libtbb.so.12` beside it first when there is one.
fn load_file(path: &Path) -> Result<Api, DenoiseError> {
    let unusable = |reason: String| DenoiseError::Unusable {
        path: path.display().to_string(),
        reason: one_line(&reason),
    };
    let tbb = match sibling_tbb(path) {
        // SAFETY: as in `load`: TBB's initialisers have no preconditions. Once loaded, the
        // dynamic loader satisfies OIDN's dependency on the soname libtbb.so.12 with it.
        Some(tbb_path) => {
            Some(unsafe { Library::new(&tbb_path) }.map_err(|error| unusable(error.to_string()))?)
        }
        None => None,
    };
    // SAFETY: as in `load`.
    let library = unsafe { Library::new(path) }.map_err(|error| unusable(error.to_string()))?;
    resolve(library, tbb, path.display().to_string())
}

/// The TBB beside the OIDN library `path`: `libtbb.so.12`, or else a `libtbb.so.12.*` (a
/// wheel ships the versioned file alone).
fn sibling_tbb(path: &Path) -> Option<PathBuf> {
    let exact = path.with_file_name(TBB_SONAME);
    if exact.exists() {
        return Some(exact);
    }
    let folder = path.parent()?.read_dir().ok()?;
    let versioned_prefix = format!("{TBB_SONAME}.");
    folder
        .filter_map(|entry| entry.ok())
        .map(|entry| entry.path())
        .find(|candidate| {
            candidate
                .file_name()
                .and_then(|name| name.to_str())
                .is_some_and(|name| name.starts_with(&versioned_prefix))
        })
}

/// Looks up the functions vkpath calls.
fn resolve(library: Library, tbb: Option<Library>, location: String) -> Result<Api, DenoiseError> {
    let missing = |name: &str| DenoiseError::Unusable {
        path: location.clone(),
        reason: format!("it has no function {name}, so it is not Open Image Denoise 1.x or 2.x"),
    };
    // SAFETY (every `get` below): each symbol is declared in OpenImageDenoise/oidn.h with
    // exactly the signature of the function-pointer type it is read as (see the types above).
    // The pointers are copied out of their `Symbol`s; they stay valid because `Api` owns the
    // `Library` and is never dropped (it lives in a static).
    macro_rules! function {
        ($name:literal, $type:ty) => {
            *unsafe { library.get::<$type>(concat!($name, "\0").as_bytes()) }
                .map_err(|_| missing($name))?
        };
    }
    // oidnSetFilter1b became oidnSetFilterBool in OIDN 2 (same signature).
    let set_filter_bool: SetFilterBoolFn =
        match unsafe { library.get::<SetFilterBoolFn>(b"oidnSetFilterBool\0") } {
            Ok(symbol) => *symbol,
            Err(_) => function!("oidnSetFilter1b", SetFilterBoolFn),
        };
    Ok(Api {
        new_device: function!("oidnNewDevice", NewDeviceFn),
        commit_device: function!("oidnCommitDevice", DeviceFn),
        release_device: function!("oidnReleaseDevice", DeviceFn),
        get_device_error: function!("oidnGetDeviceError", GetDeviceErrorFn),
        new_filter: function!("oidnNewFilter", NewFilterFn),
        set_shared_filter_image: function!("oidnSetSharedFilterImage", SetSharedFilterImageFn),
        set_filter_bool,
        commit_filter: function!("oidnCommitFilter", FilterFn),
        execute_filter: function!("oidnExecuteFilter", FilterFn),
        release_filter: function!("oidnReleaseFilter", FilterFn),
        location,
        _library: library,
        _tbb: tbb,
    })
}

/// `text` with line breaks turned into spaces (errors are one line).
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Reads and clears OIDN's first pending error on `device` (null: the error of a failed
/// `oidnNewDevice`), as an error saying what vkpath was doing.
fn check(api: &Api, device: Handle, step: &'static str) -> Result<(), DenoiseError> {
    let mut message: *const c_char = std::ptr::null();
    // SAFETY: oidnGetDeviceError accepts a null or live device and writes a pointer to a
    // NUL-terminated string (or leaves null) into `message`, valid until the next OIDN call.
    let code = unsafe { (api.get_device_error)(device, &mut message) };
    if code == OIDN_ERROR_NONE {
        return Ok(());
    }
    let message = if message.is_null() {
        "no message".to_string()
    } else {
        // SAFETY: non-null and NUL-terminated, see above; copied before any other OIDN call.
        one_line(&unsafe { CStr::from_ptr(message) }.to_string_lossy())
    };
    Err(DenoiseError::Oidn {
        step,
        code,
        message,
    })
}

/// An OIDN CPU device, released on drop.
struct Device {
    api: &'static Api,
    handle: Handle,
}

impl Device {
    fn new(api: &'static Api) -> Result<Device, DenoiseError> {
        // SAFETY: oidnNewDevice takes any device type and returns null on failure.
        let handle = unsafe { (api.new_device)(OIDN_DEVICE_TYPE_CPU) };
        if handle.is_null() {
            check(api, handle, "create a CPU device")?;
            return Err(DenoiseError::Oidn {
                step: "create a CPU device",
                code: 1,
                message: "oidnNewDevice returned no device".into(),
            });
        }
        let device = Device { api, handle };
        check(api, handle, "create a CPU device")?;
        // SAFETY: `handle` is a live device.
        unsafe { (api.commit_device)(handle) };
        check(api, handle, "commit the CPU device")?;
        Ok(device)
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: `handle` is a live device whose only reference is this one; every filter
        // made from it (which holds its own reference) is released first by declaration order
        // in `denoise`.
        unsafe { (self.api.release_device)(self.handle) };
    }
}

/// An `RT` filter on a [`Device`], released on drop.
struct Filter<'device> {
    device: &'device Device,
    handle: Handle,
}

impl<'device> Filter<'device> {
    fn new(device: &'device Device) -> Result<Filter<'device>, DenoiseError> {
        let api = device.api;
        // SAFETY: live device, NUL-terminated filter type; null on failure.
        let handle = unsafe { (api.new_filter)(device.handle, c"RT".as_ptr()) };
        if handle.is_null() {
            check(api, device.handle, "create the RT filter")?;
            return Err(DenoiseError::Oidn {
                step: "create the RT filter",
                code: 1,
                message: "oidnNewFilter returned no filter".into(),
            });
        }
        // Owned from here on, so that an error below still releases it.
        let filter = Filter { device, handle };
        check(api, device.handle, "create the RT filter")?;
        Ok(filter)
    }

    /// Shares `pixels` (tightly packed rows of `width` RGB floats) as the image `name`. OIDN
    /// keeps the pointer until the filter is released, so `pixels` must outlive the filter
    /// and must not move: `denoise` drops the filter before any image.
    fn set_image(
        &self,
        name: &'static CStr,
        pixels: &mut [[f32; 3]],
        width: usize,
        height: usize,
    ) -> Result<(), DenoiseError> {
        let pixel_stride = std::mem::size_of::<[f32; 3]>();
        // SAFETY: live filter; `pixels` holds width * height FLOAT3 pixels (checked by
        // `check_layers`) with the strides given, and outlives the filter (see above).
        unsafe {
            (self.device.api.set_shared_filter_image)(
                self.handle,
                name.as_ptr(),
                pixels.as_mut_ptr().cast(),
                OIDN_FORMAT_FLOAT3,
                width,
                height,
                0,
                pixel_stride,
                pixel_stride * width,
            )
        };
        check(
            self.device.api,
            self.device.handle,
            "set an image of the RT filter",
        )
    }

    /// Tells the filter that the colour is HDR (linear, any range), not [0, 1] sRGB-like.
    fn set_hdr(&self) -> Result<(), DenoiseError> {
        // SAFETY: live filter, NUL-terminated parameter name.
        unsafe { (self.device.api.set_filter_bool)(self.handle, c"hdr".as_ptr(), true) };
        check(
            self.device.api,
            self.device.handle,
            "set the RT filter's hdr mode",
        )
    }

    fn commit_and_execute(&self) -> Result<(), DenoiseError> {
        let (api, device) = (self.device.api, self.device.handle);
        // SAFETY: live filter whose images are all set and alive (see `set_image`).
        unsafe { (api.commit_filter)(self.handle) };
        check(api, device, "commit the RT filter")?;
        // SAFETY: as above; oidnExecuteFilter is synchronous, the output is written on return.
        unsafe { (api.execute_filter)(self.handle) };
        check(api, device, "execute the RT filter")
    }
}

impl Drop for Filter<'_> {
    fn drop(&mut self) {
        // SAFETY: `handle` is a live filter whose only reference is this one.
        unsafe { (self.device.api.release_filter)(self.handle) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layers_must_fit_the_image() {
        let pixels = vec![[0.5f32; 3]; 6];
        assert!(check_layers(&pixels, None, None, 3, 2).is_ok());
        assert!(check_layers(&pixels, Some(&pixels), Some(&pixels), 3, 2).is_ok());
        let errors = [
            check_layers(&pixels, None, None, 2, 2),
            check_layers(&pixels, None, None, 0, 6),
            check_layers(&pixels, None, Some(&pixels), 3, 2),
            check_layers(&pixels, Some(&pixels[..5]), None, 3, 2),
        ];
        for error in errors {
            let message = error.unwrap_err().to_string();
            assert!(message.starts_with("cannot denoise: "), "{message}");
            assert!(!message.contains('\n'), "{message}");
        }
    }

    #[test]
    fn non_finite_values_become_zero() {
        let pixels = [
            [f32::NAN, f32::INFINITY, 1.5],
            [f32::NEG_INFINITY, -2.0, 0.0],
        ];
        assert_eq!(
            finite_or_zero(&pixels),
            vec![[0.0, 0.0, 1.5], [0.0, -2.0, 0.0]]
        );
    }

    #[test]
    fn not_found_says_how_to_install() {
        let message = DenoiseError::NotFound.to_string();
        assert!(message.contains("scripts/install-oidn.sh"), "{message}");
        assert!(message.contains(LIBRARY_ENV), "{message}");
        assert!(!message.contains('\n'), "{message}");
    }
}
