//! `vkpath.render`: the command line's `vkpath render` as a function. The settings a call
//! leaves out are the library's `production_settings()`, which `vkpath render` starts from
//! too, and the render runs through the library's `RenderSession`, as every render of
//! `vkpath render` does, so the same settings give the same pixels bit for bit.
//! The GIL is released while rendering; a progress callback and Ctrl-C stop it after the
//! current batch (about 250 ms).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use glam::{UVec2, Vec3};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyByteArray, PyDict};
use vkpath::camera_data::CameraData;
use vkpath::cli::frames::DEFAULT_FPS;
use vkpath::image_io::output::ImageLayer;
use vkpath::lens_request::{Focus, FocusError};
use vkpath::lights::environment_source::{EnvironmentOptionNames, EnvironmentSource};
use vkpath::render::adaptive::{NoiseThreshold, DEFAULT_MIN_SPP};
use vkpath::render::aov::Aov;
use vkpath::render::job::{production_settings, JobOptions, LiveImage};
use vkpath::render::motion_vectors::{FrameNeighbours, NeighbourPose};
use vkpath::render::post_process::PostProcess;
use vkpath::render::region::PixelRegion;
use vkpath::render::sequence::SequenceCache;
use vkpath::render::settings::default_russian_roulette_start;
use vkpath::render::RenderSession;
use vkpath::render::StopReason;
use vkpath::scene::motion::{
    SceneMotion, Shutter, ShutterPosition, DEFAULT_MOTION_STEPS, MAX_MOTION_STEPS,
    MAX_SHUTTER_FRAMES,
};
use vkpath::{Context, ContextOptions, Integrator, RenderSettings, RenderedImage};

use crate::errors::{argument_error, message, to_py};
use crate::medium::medium_of;
use crate::names::{in_python_words, name_of, parse, parse_optional};
use crate::scene::{Scene, SequenceFacts};

/// What a render may be told; `None` takes the default.
#[derive(Default)]
struct Choices<'a> {
    width: Option<u32>,
    height: Option<u32>,
    spp: Option<u32>,
    seed: Option<u32>,
    integrator: Option<&'a str>,
    sampler: Option<&'a str>,
    light_sampling: Option<&'a str>,
    light_selection: Option<&'a str>,
    pixel_filter: Option<&'a str>,
    accel: Option<&'a str>,
    max_path_length: Option<u32>,
    samples_per_frame: Option<u32>,
    russian_roulette_start: Option<u32>,
    region: Option<(u32, u32, u32, u32)>,
    guiding: bool,
    guide_training_spp: Option<u32>,
    sample_range: Option<(u32, u32)>,
    noise_threshold: Option<f32>,
    noise_min_spp: Option<u32>,
    /// `--medium`'s text (`vkpath.Medium`'s `str`).
    medium: Option<&'a str>,
}

impl Choices<'_> {
    /// The settings: each choice made, else `production_settings()`'s (what `vkpath render`
    /// starts from), and the warnings about choices that have no effect.
    fn settings(&self) -> PyResult<(RenderSettings, Vec<String>)> {
        let default = production_settings();
        let mut warnings = Vec::new();
        // As `--sample-range`: the range decides the samples, and spp= has no effect.
        let spp = match self.sample_range {
            Some((start, end)) if start >= end => {
                return Err(argument_error(format!(
                    "sample_range=({start}, {end}) is not (start, end) with start < end"
                )))
            }
            Some((start, end)) => {
                if self.spp.is_some() {
                    warnings.push(
                        "spp= has no effect with sample_range=: the range decides the samples"
                            .to_owned(),
                    );
                }
                if self.guiding && self.guide_training_spp.is_none() {
                    return Err(argument_error("guiding=True with sample_range= needs guide_training_spp=: every shard must train the same guide as the whole render (its default depends on spp, which differs per shard)"));
                }
                end - start
            }
            None => self.spp.unwrap_or(default.spp),
        };
        let settings = RenderSettings {
            width: self.width.unwrap_or(default.width),
            height: self.height.unwrap_or(default.height),
            spp,
            seed: self.seed.unwrap_or(default.seed),
            integrator: parse_optional("integrator", self.integrator)?
                .unwrap_or(default.integrator),
            sampler: parse_optional("sampler", self.sampler)?.unwrap_or(default.sampler),
            light_sampling: parse_optional("light_sampling", self.light_sampling)?
                .unwrap_or(default.light_sampling),
            light_selection: parse_optional("light_selection", self.light_selection)?
                .unwrap_or(default.light_selection),
            pixel_filter: parse_optional("pixel_filter", self.pixel_filter)?
                .unwrap_or(default.pixel_filter),
            accel: parse_optional("accel", self.accel)?.unwrap_or(default.accel),
            max_path_length: self.max_path_length.unwrap_or(default.max_path_length),
            samples_per_frame: self.samples_per_frame.unwrap_or(default.samples_per_frame),
            russian_roulette_start: self
                .russian_roulette_start
                .unwrap_or(default_russian_roulette_start(self.guiding)),
            region: self
                .region
                .map(|(x0, y0, x1, y1)| PixelRegion { x0, y0, x1, y1 }),
            medium: self.medium.map(medium_of).transpose()?,
            ..default
        };
        // As `--noise-threshold T --noise-min-spp N`.
        let noise_threshold = match (self.noise_threshold, self.noise_min_spp) {
            (Some(threshold), min_spp) => Some(NoiseThreshold {
                threshold,
                min_spp: min_spp.unwrap_or(DEFAULT_MIN_SPP),
            }),
            (None, Some(_)) => {
                return Err(argument_error(
                    "noise_min_spp= has no effect without noise_threshold=",
                ))
            }
            (None, None) => None,
        };
        if noise_threshold.is_some() && self.sample_range.is_some() {
            return Err(argument_error("noise_threshold= decides per pixel how many of all the samples it takes: it cannot be split with sample_range="));
        }
        let settings = RenderSettings {
            noise_threshold,
            ..settings
        };
        // As `vkpath render --guiding`: the training budget's default (about a million paths, at
        // most a quarter of spp).
        let settings = RenderSettings {
            guiding: self
                .guiding
                .then(|| settings.guide_training(self.guide_training_spp)),
            ..settings
        };
        settings
            .validate()
            .map_err(|error| argument_error(in_python_words(&error.to_string())))?;
        // As `vkpath render` does: the workshop's integrators always use PCG2D, so a render
        // with one of them records (and reports) "pcg", and a sampler chosen for it is
        // ignored with a warning.
        if !settings.integrator.is_importance_sampled() {
            if let Some(sampler) = self.sampler.filter(|s| *s != "pcg") {
                warnings.push(format!(
                    "sampler='{sampler}' has no effect with integrator '{}': it always uses pcg",
                    name_of(&settings.integrator)
                ));
            }
        }
        Ok((settings.with_effective_sampler(), warnings))
    }
}

/// Python's names for the environment's parameters, for `EnvironmentSource::from_options`.
const PYTHON_NAMES: EnvironmentOptionNames = EnvironmentOptionNames {
    map: "environment",
    strength: "environment_strength",
    rotation: "environment_rotation",
    background: "background",
};

/// After each batch: lets Python run its signal handlers (Ctrl-C raises KeyboardInterrupt
/// there) and calls `progress(done, total)`. Either's exception (kept in `error`, to raise
/// once the render has stopped), or the callback returning `False`, sets `stop`, the job's
/// cancel flag, which ends the render after this batch.
fn after_batch(
    stop: &AtomicBool,
    error: &Mutex<Option<PyErr>>,
    progress: Option<&Py<PyAny>>,
    done: u32,
    total: u32,
    image: Option<&RenderedImage>,
) {
    Python::attach(|py| {
        let call = |callback: &Py<PyAny>| match image {
            // A callback of three parameters gets the image so far as well.
            Some(image) => {
                let so_far = ImageSoFar {
                    image: image.clone(),
                };
                callback.call1(py, (done, total, so_far))
            }
            None => callback.call1(py, (done, total)),
        };
        let result = py.check_signals().and_then(|()| match progress {
            Some(callback) => call(callback).map(|value| {
                // Only False stops: a callback that returns nothing (None) goes on.
                let value = value.bind(py);
                value.is_instance_of::<PyBool>() && !value.is_truthy().unwrap_or(true)
            }),
            None => Ok(false),
        });
        match result {
            Ok(false) => {}
            Ok(true) => stop.store(true, Ordering::SeqCst),
            Err(raised) => {
                error
                    .lock()
                    .unwrap_or_else(|poisoned| poisoned.into_inner())
                    .get_or_insert(raised);
                stop.store(true, Ordering::SeqCst);
            }
        }
    });
}

/// The Vulkan context of a render, opened as `vkpath render` opens it.
fn open_context(device: Option<String>, validate: bool) -> vkpath::Result<Arc<Context>> {
    Ok(Context::new(&ContextOptions {
        validate,
        device,
        require_gpu: false,
        pipeline_cache: user_pipeline_cache(),
        ..ContextOptions::default()
    })?)
}

/// A device kept open for several renders (`vkpath.render_frames` renders every frame on
/// one, as `vkpath render --frames` does), with what each render leaves for the next
/// (`SequenceCache`: the kernel of the same variant, the accumulation image of the same
/// size, the scene upload while the scene's data stay the same).
#[pyclass(module = "vkpath", frozen)]
pub struct Session {
    /// The context every render of the session uses.
    context: Arc<Context>,
    /// What the session's renders keep for the next (one render at a time holds it).
    sequence: Arc<Mutex<SequenceCache>>,
    /// What the sequence decides once, on its first frame (`Scene::at_time`).
    facts: Mutex<Option<SequenceFacts>>,
}

#[pymethods]
impl Session {
    /// Opens `device` (as `render`'s `device=`), with the validation layers if `validate`.
    #[new]
    #[pyo3(signature = (device=None, validate=false))]
    fn new(py: Python<'_>, device: Option<String>, validate: bool) -> PyResult<Session> {
        let context = py
            .detach(|| open_context(device, validate))
            .map_err(to_py)?;
        Ok(Session {
            context,
            sequence: Arc::default(),
            facts: Mutex::new(None),
        })
    }
}

/// The estimate a render has so far, handed to a progress callback of three parameters:
/// calling it gives a dict of `mean` (bytearray of height x width x 4 float32), `width`
/// and `height`.
#[pyclass(module = "vkpath", frozen)]
pub struct ImageSoFar {
    /// The image read back after the batch.
    image: RenderedImage,
}

#[pymethods]
impl ImageSoFar {
    fn __call__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let image = &self.image;
        let dict = PyDict::new(py);
        dict.set_item(
            "mean",
            PyByteArray::new(py, bytemuck::cast_slice(&image.mean)),
        )?;
        dict.set_item("width", image.width)?;
        dict.set_item("height", image.height)?;
        Ok(dict)
    }
}

/// Renders `scene` and returns a dict: `mean` (bytearray of height x width x 4 float32,
/// rows top-down), `second_moment` (x 3), `sample_count` (x 1), `width`, `height`, `spp`
/// (samples per pixel taken), `spp_requested`, `stop`, `seconds`, `device`, `settings` and
/// `warnings`. See `vkpath.render` for the parameters.
#[pyfunction]
#[pyo3(signature = (scene, *, width=None, height=None, spp=None, seed=None, integrator=None,
    sampler=None, light_sampling=None, light_selection=None, pixel_filter=None, accel=None, max_path_length=None,
    samples_per_frame=None, russian_roulette_start=None, environment_map=None,
    environment_strength=1.0, environment_rotation=0.0, background=None, time_limit=None,
    progress=None, device=None, validate=false, region=None, guiding=false,
    guide_training_spp=None, time=None, sample_range=None, noise_threshold=None,
    noise_min_spp=None, aovs=None, denoise=false, progress_image=false, session=None,
    focus_at=None, fps=None, shutter=None, shutter_position=None, motion_steps=None,
    medium=None))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    scene: PyRef<'py, Scene>,
    width: Option<u32>,
    height: Option<u32>,
    spp: Option<u32>,
    seed: Option<u32>,
    integrator: Option<&str>,
    sampler: Option<&str>,
    light_sampling: Option<&str>,
    light_selection: Option<&str>,
    pixel_filter: Option<&str>,
    accel: Option<&str>,
    max_path_length: Option<u32>,
    samples_per_frame: Option<u32>,
    russian_roulette_start: Option<u32>,
    environment_map: Option<PathBuf>,
    environment_strength: f32,
    environment_rotation: f32,
    background: Option<(f32, f32, f32)>,
    time_limit: Option<f64>,
    progress: Option<Py<PyAny>>,
    device: Option<String>,
    validate: bool,
    region: Option<(u32, u32, u32, u32)>,
    guiding: bool,
    guide_training_spp: Option<u32>,
    time: Option<f64>,
    sample_range: Option<(u32, u32)>,
    noise_threshold: Option<f32>,
    noise_min_spp: Option<u32>,
    aovs: Option<Vec<String>>,
    denoise: bool,
    progress_image: bool,
    session: Option<PyRef<'py, Session>>,
    focus_at: Option<(u32, u32)>,
    fps: Option<f64>,
    shutter: Option<f64>,
    shutter_position: Option<&str>,
    motion_steps: Option<u32>,
    medium: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let (settings, mut warnings) = Choices {
        width,
        height,
        spp,
        seed,
        integrator,
        sampler,
        light_sampling,
        light_selection,
        pixel_filter,
        accel,
        max_path_length,
        samples_per_frame,
        russian_roulette_start,
        region,
        guiding,
        guide_training_spp,
        sample_range,
        noise_threshold,
        noise_min_spp,
        medium,
    }
    .settings()?;
    let aovs = aovs
        .unwrap_or_default()
        .iter()
        .map(|name| parse::<Aov>("aovs", name))
        .collect::<PyResult<Vec<_>>>()?;
    if (denoise || !aovs.is_empty()) && sample_range.is_some() {
        return Err(argument_error(
            "aovs= and denoise= work on whole renders, not with sample_range=",
        ));
    }
    if denoise {
        vkpath::denoise::available().map_err(to_py)?;
    }
    let time_limit = time_limit
        .map(|seconds| {
            if seconds > 0.0 && seconds < 1e9 {
                Ok(Duration::from_secs_f64(seconds))
            } else {
                Err(message(format!(
                    "time_limit={seconds} is not a positive number of seconds"
                )))
            }
        })
        .transpose()?;
    let environment = EnvironmentSource::from_options(
        environment_map.as_deref(),
        environment_strength,
        environment_rotation,
        background.map(Vec3::from),
        &PYTHON_NAMES,
    )
    .map_err(|e| message(e.to_string()))?;
    let facts = session.as_ref().map(|s| &s.facts);
    let (world, camera) = scene.at_time(time, settings.aspect(), facts)?;
    let camera = with_lens(camera, &world, &scene, focus_at, &settings)?;
    let fps = frame_rate(fps)?;
    let poser = Poser {
        scene: &scene,
        frame: (&world, &camera),
        settings: &settings,
        facts,
    };
    let neighbours = match aovs.contains(&Aov::Motion) {
        true => motion_neighbours(&poser, time, fps)?,
        false => None,
    };
    let shutter = shutter_of(shutter, shutter_position, motion_steps)?;
    let motion = match shutter {
        Some(shutter) => motion_keys(&poser, shutter, time, fps)?,
        None => None,
    };
    if shutter.is_some() && motion.is_none() {
        warnings.push(
            "shutter=: nothing in the scene moves across the shutter, so the image is the still one"
                .into(),
        );
    }
    let world = vkpath::Scene { motion, ..world };
    if aovs.contains(&Aov::Motion) && neighbours.is_none() {
        warnings.push(
            "aovs=['motion']: nothing in the scene moves around this time, so the motion vectors are 0"
                .into(),
        );
    }
    let moving_geometry = facts
        .and_then(|f| *f.lock().unwrap_or_else(|e| e.into_inner()))
        .is_some_and(|f| f.moving_geometry);
    let world = world
        .with_environment(environment.as_ref())
        .map_err(|e| message(e.to_string()))?;
    let first_sample = sample_range.map_or(0, |(start, _)| start);
    warnings.extend(lighting_warnings(&world, settings.integrator));
    let stop = AtomicBool::new(false);
    let raised: Mutex<Option<PyErr>> = Mutex::new(None);
    let total = settings.spp;
    let progress = progress.as_ref();
    if session.is_some() && (device.is_some() || validate) {
        return Err(argument_error(
            "a session has its device: device= and validate= belong to the session",
        ));
    }
    let shared = session.map(|s| (s.context.clone(), s.sequence.clone()));
    let result = py.detach(|| {
        let (context, sequence) = match shared {
            Some((context, sequence)) => (context, Some(sequence)),
            None => (open_context(device, validate)?, None),
        };
        // A session's renders take what the one before left (a poisoned lock: a render
        // that panicked; its cache is dropped for a fresh one).
        let mut sequence = sequence.as_ref().map(|s| {
            let mut guard = s.lock().unwrap_or_else(|poisoned| {
                let mut guard = poisoned.into_inner();
                *guard = SequenceCache::default();
                guard
            });
            guard.moving_geometry = moving_geometry;
            guard
        });
        // The library's render session, as `vkpath render` runs one: the whole state kept
        // (a shard's, and as Python always has, never tile by tile), stopped by Ctrl-C or
        // the callback through `stop`.
        // `progress_image`: the callback is called from the live view, after every batch
        // but the last, and once more below with the final image.
        let (last_done, reported) = (AtomicU32::new(0), AtomicU32::new(0));
        let with_image = |image: &RenderedImage| {
            reported.store(last_done.load(Ordering::SeqCst), Ordering::SeqCst);
            let done = last_done.load(Ordering::SeqCst);
            after_batch(&stop, &raised, progress, done, total, Some(image));
        };
        let mut render_session = RenderSession {
            job: JobOptions {
                samples: first_sample..first_sample + settings.spp,
                time_limit,
                cancel: Some(&stop),
                live: progress_image.then_some(LiveImage {
                    interval: Duration::ZERO,
                    show: &with_image,
                }),
                keep_state: true,
                ..JobOptions::default()
            },
            post: PostProcess {
                aovs: aovs.clone(),
                denoise,
                neighbours,
                cryptomatte: Default::default(),
            },
            sequence: sequence.as_deref_mut(),
            ..RenderSession::new(&context, &world, &camera, &settings)
        };
        let job = render_session.run(|done| {
            last_done.store(done.samples_done, Ordering::SeqCst);
            if !progress_image {
                after_batch(&stop, &raised, progress, done.samples_done, total, None);
            }
        })?;
        let outcome = &job.outcome;
        let already_raised = raised.lock().map_or(true, |raised| raised.is_some());
        if progress_image && outcome.samples > reported.load(Ordering::SeqCst) && !already_raised {
            after_batch(
                &stop,
                &raised,
                progress,
                outcome.samples,
                total,
                Some(&outcome.image),
            );
        }
        // As `--aov` and `--denoise` (which renders the albedo and normal it needs): after a
        // finished render (every sample, or the time limit reached); one stopped early (the
        // callback, Ctrl-C) is returned as it is.
        let post = render_session.post_process(&job)?;
        let validation = context
            .validation_messages()
            .map(|m| m.total())
            .unwrap_or(0);
        Ok::<_, vkpath::Error>((job.outcome, context.info.name.clone(), validation, post))
    });
    // An exception from the callback or Ctrl-C wins over everything else: the render has
    // stopped and freed its device by now.
    if let Some(error) = raised
        .into_inner()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
    {
        return Err(error);
    }
    let (outcome, device_name, validation_messages, post) = result.map_err(to_py)?;
    if let Some(error) = &outcome.failure {
        return Err(message(format!(
            "rendering stopped after {} of {total} spp: {error:#}",
            outcome.samples
        )));
    }
    if validation_messages > 0 {
        return Err(message(format!(
            "the validation layer reported {validation_messages} messages (see the log)"
        )));
    }
    // A shard's image is its state's (what `--sample-range` writes, for `vkpath merge`):
    // the mean of its sums, which may differ from the device's in the last bit.
    let shard_image = sample_range.and_then(|_| outcome.state.as_ref().map(|s| s.image()));
    let dict = PyDict::new(py);
    let layers = PyDict::new(py);
    let manifests = PyDict::new(py);
    // The post-processed image, with its AOVs (in `aovs`' order) and the noisy original of
    // a denoised one as layers.
    let image = match post {
        Some((image, post_layers)) => {
            for layer in &post_layers {
                layers.set_item(&layer.name, PyByteArray::new(py, &layer_bytes(layer)))?;
                // Cryptomatte's manifests, by type name (the first layer of each kind)
                let attribute = |field: &str| {
                    let suffix = format!("/{field}");
                    layer.attributes.iter().find(|(n, _)| n.ends_with(&suffix))
                };
                if let (Some((_, name)), Some((_, manifest))) =
                    (attribute("name"), attribute("manifest"))
                {
                    manifests.set_item(name, manifest)?;
                }
            }
            image
        }
        None => {
            if denoise || !aovs.is_empty() {
                warnings.push(format!(
                    "the render stopped early ({}): returned without aovs= and denoise=",
                    outcome.stop.name()
                ));
            }
            shard_image.unwrap_or_else(|| outcome.image.clone())
        }
    };
    dict.set_item("layers", layers)?;
    dict.set_item("cryptomatte", manifests)?;
    let image = &image;
    dict.set_item(
        "mean",
        PyByteArray::new(py, bytemuck::cast_slice(&image.mean)),
    )?;
    dict.set_item(
        "second_moment",
        PyByteArray::new(py, bytemuck::cast_slice(&image.second_moment)),
    )?;
    dict.set_item(
        "sample_count",
        PyByteArray::new(py, bytemuck::cast_slice(&image.sample_count)),
    )?;
    dict.set_item("width", image.width)?;
    dict.set_item("height", image.height)?;
    dict.set_item("spp", outcome.samples)?;
    dict.set_item("spp_requested", total)?;
    dict.set_item(
        "sample_range",
        (first_sample, first_sample + outcome.samples),
    )?;
    dict.set_item(
        "stop",
        match outcome.stop {
            StopReason::Cancelled => "stopped",
            other => other.name(),
        },
    )?;
    dict.set_item("seconds", outcome.seconds)?;
    dict.set_item("device", device_name)?;
    dict.set_item("settings", settings_dict(py, &settings)?)?;
    // The camera as datasets take it (`render --json`'s `camera_data`), as JSON text
    let camera_data = CameraData::of(&camera, settings.width, settings.height);
    let camera_json = serde_json::to_string(&camera_data).map_err(|e| message(e.to_string()))?;
    dict.set_item("camera", camera_json)?;
    dict.set_item("warnings", warnings)?;
    Ok(dict)
}

/// `fps=` checked (default 24 frames per second).
fn frame_rate(fps: Option<f64>) -> PyResult<f64> {
    let fps = fps.unwrap_or(DEFAULT_FPS);
    if !(fps > 0.0 && fps.is_finite()) {
        return Err(argument_error(format!(
            "fps={fps} is not a frame rate above 0"
        )));
    }
    Ok(fps)
}

/// Poses a render's scene at other times than the frame's (motion blur's keys, the motion
/// vectors' neighbours), each with the camera `Scene::at_time` gives then, as `vkpath
/// render` poses them: a camera that frames a file without one keeps the frame's framing,
/// and every pose keeps the frame camera's lens.
struct Poser<'a> {
    /// The scene as Python holds it (its file, its chosen camera).
    scene: &'a Scene,
    /// The frame's scene and camera.
    frame: (&'a vkpath::Scene, &'a vkpath::Camera),
    /// The render's settings (its aspect frames a camera-less file).
    settings: &'a RenderSettings,
    /// What a sequence (`render_frames`) decided once.
    facts: Option<&'a Mutex<Option<SequenceFacts>>>,
}

impl Poser<'_> {
    /// The scene and its camera at `time` seconds. A time before 0 is posed at 0: glTF's
    /// animations hold their first key before it, so the pose is the same.
    fn pose(&self, time: f64) -> PyResult<(vkpath::Scene, vkpath::Camera)> {
        let (world, camera) = self.frame;
        let own_camera = world.camera.is_some()
            || self.scene.camera.is_some()
            || self.scene.camera_index.is_some();
        let (posed, posed_camera) =
            self.scene
                .at_time(Some(time.max(0.0)), self.settings.aspect(), self.facts)?;
        let seen_by = match own_camera {
            true => vkpath::Camera {
                lens: camera.lens,
                ..posed_camera
            },
            false => *camera,
        };
        Ok((posed, seen_by))
    }
}

/// For `aovs=["motion"]`: the scene one frame interval (1 / `fps`) before and after `time`
/// (default 0), as `vkpath render --aov motion` poses them; `None` where nothing moves (no
/// animation, or the same triangles and camera).
fn motion_neighbours(
    poser: &Poser,
    time: Option<f64>,
    fps: f64,
) -> PyResult<Option<Arc<FrameNeighbours>>> {
    if !poser.scene.is_animated()? {
        return Ok(None);
    }
    let time = time.unwrap_or(0.0);
    let neighbour = |at: f64| -> PyResult<NeighbourPose> {
        let (posed, camera) = poser.pose(at)?;
        Ok(NeighbourPose::new(at, &posed, camera))
    };
    let (world, camera) = poser.frame;
    let neighbours = FrameNeighbours::new(
        world.triangles.len(),
        neighbour(time - 1.0 / fps)?,
        neighbour(time + 1.0 / fps)?,
    )
    .map_err(|e| message(e.to_string()))?;
    Ok((!neighbours.is_still(world, camera)).then(|| Arc::new(neighbours)))
}

/// `shutter=`, `shutter_position=` and `motion_steps=` checked as `--shutter`,
/// `--shutter-position` and `--motion-steps` are; `None` without a shutter (or 0).
fn shutter_of(
    frames: Option<f64>,
    position: Option<&str>,
    steps: Option<u32>,
) -> PyResult<Option<Shutter>> {
    let position = parse_optional::<ShutterPosition>("shutter_position", position)?
        .unwrap_or(ShutterPosition::Center);
    let steps = steps.unwrap_or(DEFAULT_MOTION_STEPS);
    if !(2..=MAX_MOTION_STEPS).contains(&steps) {
        return Err(argument_error(format!(
            "motion_steps={steps}: give 2 to {MAX_MOTION_STEPS} keys across the shutter"
        )));
    }
    match frames.filter(|&frames| frames != 0.0) {
        None => Ok(None),
        Some(frames) if frames > 0.0 && frames <= MAX_SHUTTER_FRAMES => {
            Shutter::new(frames, position, steps)
                .map(Some)
                .map_err(|e| argument_error(e.to_string()))
        }
        Some(frames) => Err(argument_error(format!(
            "shutter={frames}: give 0 (none) to {MAX_SHUTTER_FRAMES} frame intervals"
        ))),
    }
}

/// Motion blur's keys: the scene posed at `shutter`'s keys around `time` (default 0), frames
/// 1 / `fps` apart, as `vkpath render --shutter` poses them; `None` where nothing moves
/// across the shutter (the still image is the blurred one).
fn motion_keys(
    poser: &Poser,
    shutter: Shutter,
    time: Option<f64>,
    fps: f64,
) -> PyResult<Option<SceneMotion>> {
    if !poser.scene.is_animated()? {
        return Ok(None);
    }
    let times = shutter.key_times(time.unwrap_or(0.0), fps);
    let poses = times
        .iter()
        .map(|&at| poser.pose(at))
        .collect::<PyResult<Vec<_>>>()?;
    let motion = SceneMotion::new(shutter, poses, &times).map_err(|e| message(e.to_string()))?;
    Ok((!motion.is_still()).then_some(motion))
}

/// `camera` with the scene's thin lens (`Camera(aperture_radius=|f_stop=, ...)`) resolved for
/// the render's image of `world`, focused on `focus_at`'s pixel (column, row from the top)
/// where given, as `vkpath render --focus-at` focuses.
fn with_lens(
    mut camera: vkpath::Camera,
    world: &vkpath::Scene,
    scene: &Scene,
    focus_at: Option<(u32, u32)>,
    settings: &RenderSettings,
) -> PyResult<vkpath::Camera> {
    let mut request =
        match (scene.lens_request, focus_at) {
            (None, None) => return Ok(camera),
            (None, Some(_)) => return Err(argument_error(
                "focus_at= needs a camera with a lens (Camera(..., aperture_radius= or f_stop=))",
            )),
            (Some(request), _) => request,
        };
    if let Some((x, y)) = focus_at {
        request.focus = Focus::Pixel(UVec2::new(x, y));
    }
    let (width, height) = (settings.width, settings.height);
    camera.lens = match request.resolve(&camera, &world.triangles, width, height) {
        Ok((lens, _)) => lens,
        Err(FocusError::OutsideImage { pixel, .. }) => {
            return Err(argument_error(format!(
                "focus_at=({}, {}) is outside the {width}x{height} image",
                pixel.x, pixel.y
            )))
        }
        Err(FocusError::NothingHit { pixel }) => {
            return Err(message(format!(
                "the camera ray through pixel ({}, {}) hits nothing to focus on: give focus_distance= or another focus_at=",
                pixel.x, pixel.y
            )))
        }
    };
    Ok(camera)
}

/// What the command line warns about the lights before rendering.
fn lighting_warnings(scene: &vkpath::Scene, integrator: Integrator) -> Vec<String> {
    let mut warnings = Vec::new();
    if !scene.emits_light() {
        warnings.push("nothing lights the scene (no emissive surface, punctual light, environment or background): the image is black".to_owned());
    }
    if !scene.punctual_lights.is_empty() && !matches!(integrator, Integrator::Nee | Integrator::Mis)
    {
        warnings.push(format!(
            "the scene's {} punctual lights are invisible to integrator '{}': only nee and mis sample them",
            scene.punctual_lights.len(),
            name_of(&integrator)
        ));
    }
    warnings
}

/// `settings` with the command line's names.
fn settings_dict<'py>(py: Python<'py>, settings: &RenderSettings) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("width", settings.width)?;
    dict.set_item("height", settings.height)?;
    dict.set_item("spp", settings.spp)?;
    dict.set_item("seed", settings.seed)?;
    dict.set_item("integrator", name_of(&settings.integrator))?;
    dict.set_item("sampler", name_of(&settings.sampler))?;
    dict.set_item("light_sampling", name_of(&settings.light_sampling))?;
    dict.set_item("light_selection", name_of(&settings.light_selection))?;
    dict.set_item("pixel_filter", name_of(&settings.pixel_filter))?;
    dict.set_item("accel", name_of(&settings.accel))?;
    dict.set_item("max_path_length", settings.max_path_length)?;
    dict.set_item("samples_per_frame", settings.samples_per_frame)?;
    dict.set_item("russian_roulette_start", settings.russian_roulette_start)?;
    dict.set_item("region", settings.region.map(|r| (r.x0, r.y0, r.x1, r.y1)))?;
    dict.set_item("guide_training_spp", settings.guiding.map(|g| g.samples))?;
    dict.set_item("medium", settings.medium.map(|m| m.to_string()))?;
    Ok(dict)
}

/// The settings a render takes where a call says nothing (`production_settings()`, what
/// `vkpath render` starts from), with the command line's names.
#[pyfunction]
pub fn default_settings(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let (settings, _) = Choices::default().settings()?;
    settings_dict(py, &settings)
}

/// The pipeline cache of the user's cache directory, as `vkpath render` keeps it (its
/// warnings on stderr); none when no cache directory can be found.
fn user_pipeline_cache() -> Option<std::sync::Arc<dyn vkpath::vk::PipelineCacheStore>> {
    use vkpath::render::pipeline_cache::{default_cache_dir, PipelineCacheDir};
    let dir = default_cache_dir()?;
    Some(std::sync::Arc::new(PipelineCacheDir::new(
        dir,
        |warning| eprintln!("vkpath: warning: {warning}"),
        || {},
    )))
}

/// A layer's pixels as Python reads them: 3 floats a pixel, or 4 (RGBA) where the layer
/// has an alpha (Cryptomatte's rank pairs).
fn layer_bytes(layer: &ImageLayer) -> Vec<u8> {
    match &layer.alpha {
        None => bytemuck::cast_slice(&layer.pixels).to_vec(),
        Some(alpha) => layer
            .pixels
            .iter()
            .zip(alpha)
            .flat_map(|(p, a)| [p[0], p[1], p[2], *a])
            .flat_map(f32::to_le_bytes)
            .collect(),
    }
}
