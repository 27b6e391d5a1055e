//! Hostile input, fuzzed: seeded mutations of glTF, GLB and OBJ (+ MTL) files through
//! `Scene::load_with`, a bounded number of cases so that it runs in CI (`cargo fuzz` targets in
//! `fuzz/` are for longer runs).
//!
//! Every case must end, within `CASE_TIMEOUT`, in a scene or in an error, and
//! - never panic (each load runs under `catch_unwind` in a worker thread named after the case);
//! - never hang (the worker is waited for at most `CASE_TIMEOUT`);
//! - give an error whose text is one line (no `\n` or `\r`);
//! - give a scene whose triangles are finite, with unit normals, albedo in [0, 1] and emission
//!   in [0, `MAX_EMISSION`], and a finite camera (what `SceneBuilder` promises the renderer);
//! - keep memory bounded: a counting global allocator charges each worker thread's heap, a case
//!   whose live heap peaks above `CASE_HEAP_LIMIT` (the inputs are at most a few MiB, so more is
//!   amplification) fails, one that would pass `CASE_HEAP_ABORT` stops the process with a line
//!   naming the case and its input (an allocation cannot be turned into a panic), and each fuzz
//!   test checks the process's peak RSS (`VmHWM` in /proc/self/status) against `PROCESS_RSS_LIMIT`.
//!
//! Seeds: `tests/data` (cube.obj + cube.mtl, emissive_quad.gltf, lines.gltf, malformed.gltf,
//! skinned_morphed.gltf from `scripts/make_skinned_morphed_gltf.py`) and,
//! made here, emissive_quad.gltf with its buffer in a `.bin` file, GLB versions of
//! emissive_quad.gltf and lines.gltf, and the built-in Cornell box as OBJ + MTL.
//!
//! Each case applies 1 to 4 mutations drawn by a xorshift generator seeded from the seed file's
//! name, the case number and `VKPATH_FUZZ_SEED` (default 0), so a run is deterministic. A failing
//! case is reported with its label (`cube.obj#17`), its mutations and a folder that holds its
//! input; environment variables:
//! - `VKPATH_FUZZ_CASES=N`: N cases per seed file (default `DEFAULT_CASES_PER_SEED`);
//! - `VKPATH_FUZZ_SEED=S`: another deterministic run;
//! - `VKPATH_FUZZ_CASE=cube.obj#17`: only that case, its input kept and its outcome printed;
//! - `VKPATH_FUZZ_WRITE_SEEDS=DIR`: write the seeds as corpora for `cargo fuzz` (see
//!   fuzz/README.md) into DIR/load_gltf, DIR/load_glb and DIR/load_obj.
//!
//! Inputs that once failed live in `tests/data/fuzz_regressions/` and are loaded by
//! `regressions_load_cleanly` with the same checks.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use serde_json::{json, Value};
use vkpath::scene::files::LoadOptions;
use vkpath::scene::MAX_EMISSION;
use vkpath::Scene;

/// Cases per seed file unless `VKPATH_FUZZ_CASES` says otherwise (8 seeds, so 8 times this in
/// all). 1500 keeps the suite within its 15 minutes on 2 cores (2500 took 87 s of a 15 min
/// 51 s CI run); a deeper run sets `VKPATH_FUZZ_CASES`, and what any run finds is kept in
/// `tests/data/fuzz_regressions/`.
const DEFAULT_CASES_PER_SEED: usize = 1500;
/// How long one load may take before it counts as a hang, unless `VKPATH_FUZZ_TIMEOUT_S`
/// says otherwise (on a machine shared by other builds, a debug load of the 6-million-
/// triangle `instanced_primitives.gltf` can take longer in wall time than it needs of CPU).
const CASE_TIMEOUT: Duration = Duration::from_secs(10);

/// `CASE_TIMEOUT`, or `VKPATH_FUZZ_TIMEOUT_S` seconds where it is set.
fn case_timeout() -> Duration {
    std::env::var("VKPATH_FUZZ_TIMEOUT_S")
        .ok()
        .and_then(|s| s.parse().ok())
        .map_or(CASE_TIMEOUT, Duration::from_secs)
}
/// The most live heap one case may reach: a small file may still describe up to
/// `MAX_SCENE_TRIANGLES` (16 M) triangles through glTF instancing, about 100 bytes each while
/// loading, so the loaders' own bound is about 1.6 GiB.
const CASE_HEAP_LIMIT: isize = 1792 << 20;
/// The live heap at which a case stops the process (reported first): beyond this an
/// allocation could take the machine's memory.
const CASE_HEAP_ABORT: isize = 3 << 30;
/// The most resident memory the test process may have reached after a fuzz test.
const PROCESS_RSS_LIMIT: u64 = 3 << 30;

// ---------------------------------------------------------------------------------------------
// Memory: a global allocator that charges every thread's allocations to that thread.

/// `System`, counting each thread's live heap bytes and their peak.
struct CountingAllocator;

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

thread_local! {
    /// Bytes this thread allocated and not freed (frees of other threads' blocks subtract).
    static LIVE: Cell<isize> = const { Cell::new(0) };
    /// The largest `LIVE` has been.
    static PEAK: Cell<isize> = const { Cell::new(0) };
    /// In a case's worker: the line to print before refusing an allocation beyond
    /// `CASE_HEAP_ABORT` (points into a `String` that the worker keeps alive).
    static ABORT_NOTE: Cell<(*const u8, usize)> = const { Cell::new((std::ptr::null(), 0)) };
}

impl CountingAllocator {
    /// Charges `bytes` to this thread; false (after printing why) when a case's worker would
    /// pass `CASE_HEAP_ABORT`.
    fn charge(bytes: usize) -> bool {
        LIVE.try_with(|live| {
            let total = live.get().saturating_add(bytes as isize);
            let (note, length) = ABORT_NOTE
                .try_with(Cell::get)
                .unwrap_or((std::ptr::null(), 0));
            if !note.is_null() && total > CASE_HEAP_ABORT {
                // No allocation here: print straight to stderr, which survives the abort.
                let note = unsafe { std::slice::from_raw_parts(note, length) };
                let mut digits = [0u8; 20];
                let mut err = std::io::stderr();
                use std::io::Write as _;
                let _ = err.write_all(b"\nfuzz_loaders: ");
                let _ = err.write_all(note);
                let _ = err.write_all(b" asks for ");
                let _ = err.write_all(decimal(bytes as u64, &mut digits));
                let _ = err.write_all(b" more heap bytes, past the 2 GiB bound; aborting\n");
                return false;
            }
            live.set(total);
            let _ = PEAK.try_with(|peak| peak.set(peak.get().max(total)));
            true
        })
        .unwrap_or(true)
    }

    fn discharge(bytes: usize) {
        let _ = LIVE.try_with(|live| live.set(live.get().saturating_sub(bytes as isize)));
    }
}

/// `value` in decimal, in `buffer`.
fn decimal(mut value: u64, buffer: &mut [u8; 20]) -> &[u8] {
    let mut at = buffer.len();
    loop {
        at -= 1;
        buffer[at] = b'0' + (value % 10) as u8;
        value /= 10;
        if value == 0 {
            return &buffer[at..];
        }
    }
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !Self::charge(layout.size()) {
            return std::ptr::null_mut();
        }
        let pointer = unsafe { System.alloc(layout) };
        if pointer.is_null() {
            Self::discharge(layout.size());
        }
        pointer
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !Self::charge(layout.size()) {
            return std::ptr::null_mut();
        }
        let pointer = unsafe { System.alloc_zeroed(layout) };
        if pointer.is_null() {
            Self::discharge(layout.size());
        }
        pointer
    }

    unsafe fn dealloc(&self, pointer: *mut u8, layout: Layout) {
        unsafe { System.dealloc(pointer, layout) };
        Self::discharge(layout.size());
    }

    unsafe fn realloc(&self, pointer: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old_size = layout.size();
        if new_size > old_size && !Self::charge(new_size - old_size) {
            return std::ptr::null_mut();
        }
        let moved = unsafe { System.realloc(pointer, layout, new_size) };
        if moved.is_null() {
            if new_size > old_size {
                Self::discharge(new_size - old_size);
            }
        } else if new_size < old_size {
            Self::discharge(old_size - new_size);
        }
        moved
    }
}

/// The process's peak resident set size (`VmHWM`), in bytes.
fn peak_rss() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|line| line.strip_prefix("VmHWM:"))
        .and_then(|rest| {
            rest.trim()
                .trim_end_matches("kB")
                .trim()
                .parse::<u64>()
                .ok()
        })
        .map_or(0, |kib| kib * 1024)
}

// ---------------------------------------------------------------------------------------------
// Randomness: xorshift64*, seeded through splitmix64.

struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        let mut z = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        Rng((z ^ (z >> 31)) | 1)
    }

    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A number in `0..n` (`n` > 0).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    /// True one time in `n`.
    fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// FNV-1a: a stable hash of a seed file's name.
fn fnv(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |hash, byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x100_0000_01b3)
    })
}

// ---------------------------------------------------------------------------------------------
// Seeds and cases.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Gltf,
    Glb,
    Obj,
}

/// A file set to load: the scene file first, then the files next to it.
#[derive(Clone)]
struct Seed {
    name: String,
    format: Format,
    files: Vec<(String, Vec<u8>)>,
}

/// One input: files and symbolic links in a fresh folder, and how to load it.
#[derive(Clone, Default)]
struct Case {
    label: String,
    /// The scene file first.
    files: Vec<(String, Vec<u8>)>,
    /// Symbolic links (name in the folder, target).
    links: Vec<(String, PathBuf)>,
    allow_external_paths: bool,
    /// The mutations applied, in order.
    recipe: Vec<String>,
}

impl Case {
    fn file_mut(&mut self, name: &str) -> Option<&mut Vec<u8>> {
        self.files
            .iter_mut()
            .find(|(n, _)| n == name)
            .map(|(_, bytes)| bytes)
    }

    fn link(&mut self, name: &str, target: impl Into<PathBuf>) {
        if !self.links.iter().any(|(n, _)| n == name) {
            self.links.push((name.to_owned(), target.into()));
        }
    }

    /// Writes the case into `dir`; the scene file's path.
    fn write(&self, dir: &Path) -> PathBuf {
        for (name, bytes) in &self.files {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        for (name, target) in &self.links {
            let _ = std::os::unix::fs::symlink(target, dir.join(name));
        }
        dir.join(&self.files[0].0)
    }
}

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn read_data(name: &str) -> Vec<u8> {
    std::fs::read(data_dir().join(name)).unwrap_or_else(|e| panic!("tests/data/{name}: {e}"))
}

/// A glTF document with its data-URI buffer moved out: (JSON without the buffer's `uri`, the
/// buffer's bytes).
fn split_data_uri(gltf: &[u8]) -> (Value, Vec<u8>) {
    let mut document: Value = serde_json::from_slice(gltf).unwrap();
    let uri = document["buffers"][0]["uri"].as_str().unwrap().to_owned();
    let (_, encoded) = uri.split_once(";base64,").unwrap();
    let bytes = base64::decode(encoded).unwrap();
    document["buffers"][0]
        .as_object_mut()
        .unwrap()
        .remove("uri");
    (document, bytes)
}

/// A GLB chunk; `length` overrides the length written in its header.
#[derive(Clone)]
struct Chunk {
    kind: [u8; 4],
    length: Option<u32>,
    data: Vec<u8>,
    /// Pad the data to 4 bytes (with spaces for JSON, zeros otherwise).
    pad: bool,
}

/// A GLB file in parts, so that mutations can break its structure on purpose.
#[derive(Clone)]
struct Glb {
    magic: [u8; 4],
    version: u32,
    /// Overrides the total length written in the header.
    length: Option<u32>,
    chunks: Vec<Chunk>,
}

impl Glb {
    fn new(json: Vec<u8>, bin: Option<Vec<u8>>) -> Glb {
        let mut chunks = vec![Chunk {
            kind: *b"JSON",
            length: None,
            data: json,
            pad: true,
        }];
        if let Some(bin) = bin {
            chunks.push(Chunk {
                kind: *b"BIN\0",
                length: None,
                data: bin,
                pad: true,
            });
        }
        Glb {
            magic: *b"glTF",
            version: 2,
            length: None,
            chunks,
        }
    }

    /// Splits a well-formed GLB (the seeds) into its parts.
    fn parse(bytes: &[u8]) -> Glb {
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
        let mut chunks = Vec::new();
        let mut at = 12;
        while at + 8 <= bytes.len() {
            let length = word(at) as usize;
            let kind: [u8; 4] = bytes[at + 4..at + 8].try_into().unwrap();
            chunks.push(Chunk {
                kind,
                length: None,
                data: bytes[at + 8..at + 8 + length].to_vec(),
                pad: true,
            });
            at += 8 + length;
        }
        Glb {
            magic: bytes[0..4].try_into().unwrap(),
            version: word(4),
            length: None,
            chunks,
        }
    }

    fn assemble(&self) -> Vec<u8> {
        let mut body = Vec::new();
        for chunk in &self.chunks {
            let mut data = chunk.data.clone();
            while chunk.pad && data.len() % 4 != 0 {
                data.push(if &chunk.kind == b"JSON" { b' ' } else { 0 });
            }
            let length = chunk.length.unwrap_or(data.len() as u32);
            body.extend_from_slice(&length.to_le_bytes());
            body.extend_from_slice(&chunk.kind);
            body.extend_from_slice(&data);
        }
        let mut bytes = Vec::with_capacity(12 + body.len());
        bytes.extend_from_slice(&self.magic);
        bytes.extend_from_slice(&self.version.to_le_bytes());
        let length = self.length.unwrap_or(12 + body.len() as u32);
        bytes.extend_from_slice(&length.to_le_bytes());
        bytes.extend_from_slice(&body);
        bytes
    }
}

/// The built-in Cornell box as OBJ text and its MTL library (`Kd` and `Ke` per distinct
/// material).
fn cornell_obj() -> (Vec<u8>, Vec<u8>) {
    let scene = Scene::builtin_cornell_box().unwrap();
    let mut materials: Vec<([f32; 3], [f32; 3])> = Vec::new();
    let mut obj = String::from("# The built-in Cornell box, written by tests/fuzz_loaders.rs\n");
    obj.push_str("mtllib cornell.mtl\no cornell\n");
    let mut current = usize::MAX;
    for (index, triangle) in scene.triangles.iter().enumerate() {
        let key = (triangle.color.to_array(), triangle.emission.to_array());
        let material = match materials.iter().position(|m| *m == key) {
            Some(found) => found,
            None => {
                materials.push(key);
                materials.len() - 1
            }
        };
        if material != current {
            obj.push_str(&format!("usemtl m{material}\n"));
            current = material;
        }
        for p in triangle.positions {
            obj.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
        }
        let first = 3 * index + 1;
        obj.push_str(&format!("f {} {} {}\n", first, first + 1, first + 2));
    }
    let mut mtl = String::new();
    for (index, (kd, ke)) in materials.iter().enumerate() {
        mtl.push_str(&format!(
            "newmtl m{index}\nKd {} {} {}\nKe {} {} {}\n",
            kd[0], kd[1], kd[2], ke[0], ke[1], ke[2]
        ));
    }
    (obj.into_bytes(), mtl.into_bytes())
}

/// Every seed: the files in tests/data and the ones made from them here.
fn seeds() -> Vec<Seed> {
    let gltf = |name: &str| Seed {
        name: name.to_owned(),
        format: Format::Gltf,
        files: vec![(name.to_owned(), read_data(name))],
    };
    let glb = |name: &str, from: &str| {
        let (document, bin) = split_data_uri(&read_data(from));
        Seed {
            name: name.to_owned(),
            format: Format::Glb,
            files: vec![(
                name.to_owned(),
                Glb::new(serde_json::to_vec(&document).unwrap(), Some(bin)).assemble(),
            )],
        }
    };
    let external = {
        let (mut document, bin) = split_data_uri(&read_data("emissive_quad.gltf"));
        document["buffers"][0]["uri"] = json!("quad.bin");
        Seed {
            name: "emissive_quad_external.gltf".into(),
            format: Format::Gltf,
            files: vec![
                (
                    "emissive_quad_external.gltf".into(),
                    serde_json::to_vec_pretty(&document).unwrap(),
                ),
                ("quad.bin".into(), bin),
            ],
        }
    };
    let (cornell, cornell_mtl) = cornell_obj();
    vec![
        gltf("emissive_quad.gltf"),
        external,
        gltf("lines.gltf"),
        gltf("malformed.gltf"),
        gltf("skinned_morphed.gltf"),
        glb("emissive_quad.glb", "emissive_quad.gltf"),
        glb("lines.glb", "lines.gltf"),
        Seed {
            name: "cube.obj".into(),
            format: Format::Obj,
            files: vec![
                ("cube.obj".into(), read_data("cube.obj")),
                ("cube.mtl".into(), read_data("cube.mtl")),
            ],
        },
        Seed {
            name: "cornell.obj".into(),
            format: Format::Obj,
            files: vec![
                ("cornell.obj".into(), cornell),
                ("cornell.mtl".into(), cornell_mtl),
            ],
        },
    ]
}

/// A named pipe for the cases that point at one: `$TMPDIR/vkpath-fuzz-fifo/pipe`, made with
/// `mkfifo` where it is missing and left there for the next run; `None` where that fails.
fn fifo() -> Option<&'static Path> {
    use std::os::unix::fs::FileTypeExt as _;
    static FIFO: OnceLock<Option<PathBuf>> = OnceLock::new();
    FIFO.get_or_init(|| {
        let dir = std::env::temp_dir().join("vkpath-fuzz-fifo");
        std::fs::create_dir_all(&dir).ok()?;
        let fifo = dir.join("pipe");
        let is_fifo =
            |path: &Path| std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_fifo());
        if !is_fifo(&fifo) {
            let _ = std::fs::remove_file(&fifo);
            let _ = std::process::Command::new("mkfifo").arg(&fifo).status();
        }
        // Another test process may have made it meanwhile.
        is_fifo(&fifo).then_some(fifo)
    })
    .as_deref()
}

// ---------------------------------------------------------------------------------------------
// Mutations.

/// Integers and floats that break assumptions (as JSON values).
fn interesting_number(rng: &mut Rng) -> Value {
    let values = [
        json!(0),
        json!(1),
        json!(-1),
        json!(2),
        json!(3),
        json!(4),
        json!(7),
        json!(255),
        json!(256),
        json!(65535),
        json!(65536),
        json!(i32::MAX),
        json!(i32::MAX as i64 + 1),
        json!(u32::MAX),
        json!(u32::MAX as u64 + 1),
        json!(1u64 << 40),
        json!(i64::MAX),
        json!(u64::MAX),
        json!(i64::MIN),
        json!(1e39),
        json!(-1e39),
        json!(3.4e38),
        json!(1e-45),
        json!(-0.0),
        json!(0.5),
        json!(1.5),
        json!(4294967295.5),
    ];
    rng.pick(&values).clone()
}

/// Number tokens to write into JSON text (some are not JSON at all).
const JSON_NUMBER_TOKENS: &[&str] = &[
    "0",
    "-0",
    "-1",
    "4294967295",
    "4294967296",
    "2147483648",
    "18446744073709551615",
    "18446744073709551616",
    "9223372036854775808",
    "-9223372036854775809",
    "1e39",
    "-1e39",
    "1e309",
    "1e-400",
    "NaN",
    "Infinity",
    "-Infinity",
    "0x10",
    "01",
    "1.",
    "1e",
    "99999999999999999999999999999999999999999",
];

/// Values of another type, or extreme ones, to put anywhere in a JSON document.
fn strange_value(rng: &mut Rng) -> Value {
    match rng.below(12) {
        0 => Value::Null,
        1 => json!(true),
        2 => json!("x"),
        3 => json!([]),
        4 => json!({}),
        5 => {
            // Deeper than serde_json's recursion limit (128).
            let mut value = json!(0);
            for _ in 0..200 {
                value = json!([value]);
            }
            value
        }
        6 => json!("line one\nline two"),
        7 => json!("x".repeat(10_000)),
        8 => json!([0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]),
        9 => json!({"0": 0}),
        10 => json!("\u{0}"),
        _ => interesting_number(rng),
    }
}

/// Names that must not break an error's one line or the terminal.
const HOSTILE_NAMES: &[&str] = &[
    "line one\nline two",
    "carriage\rreturn",
    "tab\there",
    "\u{1b}[31mred\u{1b}[0m",
    "",
    "%0a",
    "\u{202e}txt.exe",
    "nul\u{0}byte",
    "'quoted'",
    "{}",
];

/// Escapes a key for a JSON pointer.
fn pointer_token(key: &str) -> String {
    key.replace('~', "~0").replace('/', "~1")
}

/// JSON pointers to every value for which `wanted(key, value)` holds, where `key` is the
/// value's key in its object, or the key of the array that holds it.
fn pointers(document: &Value, wanted: &dyn Fn(&str, &Value) -> bool) -> Vec<String> {
    fn walk(
        value: &Value,
        key: &str,
        at: String,
        wanted: &dyn Fn(&str, &Value) -> bool,
        out: &mut Vec<String>,
    ) {
        if wanted(key, value) {
            out.push(at.clone());
        }
        match value {
            Value::Object(map) => {
                for (k, v) in map {
                    walk(v, k, format!("{at}/{}", pointer_token(k)), wanted, out);
                }
            }
            Value::Array(items) => {
                for (i, v) in items.iter().enumerate() {
                    walk(v, key, format!("{at}/{i}"), wanted, out);
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(document, "", String::new(), wanted, &mut out);
    out
}

/// Sets the value at a random pointer among `candidates`; its description.
fn set_random(
    rng: &mut Rng,
    document: &mut Value,
    candidates: &[String],
    value: Value,
) -> Option<String> {
    let at = rng.pick(candidates).clone();
    let slot = document.pointer_mut(&at)?;
    let text = value.to_string();
    let shown: String = text.chars().take(40).collect();
    *slot = value;
    Some(format!("{at} = {shown}"))
}

/// The elements of the top-level array `key` (empty when there is none).
fn top_array_len(document: &Value, key: &str) -> usize {
    document
        .get(key)
        .and_then(Value::as_array)
        .map_or(0, Vec::len)
}

/// A random element of the top-level array `key`.
fn top_element<'a>(
    rng: &mut Rng,
    document: &'a mut Value,
    key: &str,
) -> Option<(usize, &'a mut Value)> {
    let length = top_array_len(document, key);
    if length == 0 {
        return None;
    }
    let index = rng.below(length);
    Some((index, &mut document[key][index]))
}

/// The keys whose values are indices into other arrays.
const REFERENCE_KEYS: &[&str] = &[
    "mesh",
    "camera",
    "skin",
    "scene",
    "indices",
    "material",
    "bufferView",
    "buffer",
    "POSITION",
    "NORMAL",
    "TEXCOORD_0",
    "children",
    "nodes",
    "index",
    "source",
    "sampler",
];

/// Buffer URIs that point where a scene must not read, or at nothing readable. Links named
/// here are made in the case's folder.
fn hostile_uri(rng: &mut Rng, case: &mut Case) -> String {
    let scene_name = case.files[0].0.clone();
    let choice = rng.below(30);
    match choice {
        0 => "/dev/zero".into(),
        1 => "/dev/urandom".into(),
        2 => "file:///dev/zero".into(),
        3 => "../../etc/passwd".into(),
        4 => "file:///etc/passwd".into(),
        5 => "/etc/passwd".into(),
        6 => "file:../../etc/passwd".into(),
        7 => "%2e%2e/%2e%2e/etc/passwd".into(),
        8 => match fifo() {
            Some(fifo) => fifo.display().to_string(),
            None => "/dev/zero".into(),
        },
        9 => {
            if let Some(fifo) = fifo() {
                case.link("pipe.bin", fifo);
            }
            "pipe.bin".into()
        }
        10 => {
            case.link("zero.bin", "/dev/zero");
            "zero.bin".into()
        }
        11 => {
            case.link("passwd.bin", "/etc/passwd");
            "passwd.bin".into()
        }
        12 => {
            case.link("loop.bin", "loop.bin");
            "loop.bin".into()
        }
        13 => {
            case.link("dir.bin", ".");
            "dir.bin".into()
        }
        14 => ".".into(),
        15 => "".into(),
        16 => "/".into(),
        17 => scene_name,
        18 => "missing.bin".into(),
        19 => "http://example.com/a.bin".into(),
        20 => "C:\\windows\\a.bin".into(),
        21 => "data:application/octet-stream;base64,!!!!".into(),
        22 => "data:,abc".into(),
        23 => "data:application/octet-stream;base64,".into(),
        24 => "a%0Ab.bin".into(),
        25 => "%ff%fe.bin".into(),
        26 => "%".into(),
        27 => "a".repeat(5000),
        28 => "/proc/self/mem".into(),
        _ => "/proc/self/status".into(),
    }
}

/// A structured change to a glTF JSON document; its description.
fn mutate_document(rng: &mut Rng, document: &mut Value, case: &mut Case) -> Option<String> {
    if !document.is_object() {
        *document = json!({});
    }
    let kind = rng.below(17);
    match kind {
        // Counts, lengths, offsets and strides blown up (or zeroed, or negative).
        0..=2 => {
            let keys: &[&str] = match kind {
                0 => &["count"],
                1 => &["byteLength"],
                _ => &["byteOffset", "byteStride"],
            };
            let candidates = pointers(document, &|k, v| keys.contains(&k) && v.is_number());
            if candidates.is_empty() || rng.one_in(4) {
                // Add the field where it is missing.
                let array = match kind {
                    0 => "accessors",
                    1 => "bufferViews",
                    _ => *rng.pick(&["bufferViews", "accessors"]),
                };
                let length = top_array_len(document, array);
                if length == 0 {
                    return None;
                }
                let key = *rng.pick(keys);
                let index = rng.below(length);
                let value = interesting_number(rng);
                document[array][index]
                    .as_object_mut()?
                    .insert(key.to_owned(), value.clone());
                return Some(format!("/{array}/{index}/{key} = {value}"));
            }
            let value = interesting_number(rng);
            set_random(rng, document, &candidates, value)
        }
        // An index into another array out of range, negative or huge.
        3 => {
            let candidates = pointers(document, &|k, v| {
                REFERENCE_KEYS.contains(&k) && v.is_number()
            });
            if candidates.is_empty() {
                return None;
            }
            let value = if rng.one_in(3) {
                json!(rng.below(4) as u64 + top_array_len(document, "nodes") as u64)
            } else {
                interesting_number(rng)
            };
            set_random(rng, document, &candidates, value)
        }
        // Node cycles and nodes reached twice.
        4 => add_node_cycle(rng, document),
        // Buffer URIs at devices, pipes, files outside the folder, nothing.
        5 => {
            let (index, buffer) = top_element(rng, document, "buffers")?;
            let uri = hostile_uri(rng, case);
            buffer.as_object_mut()?.insert("uri".into(), json!(uri));
            if rng.one_in(2) {
                case.allow_external_paths = true;
            }
            Some(format!(
                "buffers[{index}].uri = {uri:?}{}",
                if case.allow_external_paths {
                    " (external paths allowed)"
                } else {
                    ""
                }
            ))
        }
        // Any number.
        6 => {
            let candidates = pointers(document, &|_, v| v.is_number());
            if candidates.is_empty() {
                return None;
            }
            let value = interesting_number(rng);
            set_random(rng, document, &candidates, value)
        }
        // Any value, of another type.
        7 => {
            let candidates = pointers(document, &|_, _| true);
            let candidates: Vec<String> =
                candidates.into_iter().filter(|p| !p.is_empty()).collect();
            if candidates.is_empty() {
                return None;
            }
            let value = strange_value(rng);
            set_random(rng, document, &candidates, value)
        }
        // A key removed.
        8 => {
            let candidates = pointers(document, &|_, v| {
                v.as_object().is_some_and(|m| !m.is_empty())
            });
            if candidates.is_empty() {
                return None;
            }
            let at = rng.pick(&candidates).clone();
            let object = document.pointer_mut(&at)?.as_object_mut()?;
            let keys: Vec<String> = object.keys().cloned().collect();
            let key = rng.pick(&keys).clone();
            object.remove(&key);
            Some(format!("removed {at}/{key}"))
        }
        // Primitive modes.
        9 => {
            let candidates = pointers(document, &|k, v| k == "primitives" && v.is_object());
            if candidates.is_empty() {
                return None;
            }
            let at = rng.pick(&candidates).clone();
            let mode = *rng.pick(&[0i64, 1, 2, 3, 4, 5, 6, 7, 255, -1, u32::MAX as i64]);
            document
                .pointer_mut(&at)?
                .as_object_mut()?
                .insert("mode".into(), json!(mode));
            Some(format!("{at}/mode = {mode}"))
        }
        // Accessor component types and element types.
        10 => {
            let (index, accessor) = top_element(rng, document, "accessors")?;
            let accessor = accessor.as_object_mut()?;
            if rng.one_in(2) {
                let value = *rng.pick(&[5120i64, 5121, 5122, 5123, 5124, 5125, 5126, 0, 65535, -1]);
                accessor.insert("componentType".into(), json!(value));
                Some(format!("accessors[{index}].componentType = {value}"))
            } else {
                let value = *rng.pick(&[
                    "SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4", "BOGUS",
                ]);
                accessor.insert("type".into(), json!(value));
                if rng.one_in(3) {
                    accessor.insert("normalized".into(), json!(true));
                }
                Some(format!("accessors[{index}].type = {value}"))
            }
        }
        // Sparse accessors.
        11 => {
            let views = top_array_len(document, "bufferViews").max(1);
            let (index, accessor) = top_element(rng, document, "accessors")?;
            let count = if rng.one_in(2) {
                json!(rng.below(8) + 1)
            } else {
                interesting_number(rng)
            };
            let sparse = json!({
                "count": count,
                "indices": {
                    "bufferView": rng.below(views + 1),
                    "componentType": *rng.pick(&[5121, 5123, 5125, 5126]),
                    "byteOffset": *rng.pick(&[0u64, 1, 4, 100, u32::MAX as u64]),
                },
                "values": {
                    "bufferView": rng.below(views + 1),
                    "byteOffset": *rng.pick(&[0u64, 1, 4, 100, u32::MAX as u64]),
                },
            });
            let text = sparse.to_string();
            accessor.as_object_mut()?.insert("sparse".into(), sparse);
            if rng.one_in(3) {
                accessor.as_object_mut()?.remove("bufferView");
            }
            Some(format!("accessors[{index}].sparse = {text}"))
        }
        // Extensions and material factors.
        12 => change_material(rng, document),
        // Cameras and node transforms.
        13 => change_camera_or_transform(rng, document),
        // Names that are not one line.
        14 => {
            let candidates = pointers(document, &|k, v| {
                v.is_object()
                    && [
                        "meshes",
                        "nodes",
                        "buffers",
                        "materials",
                        "cameras",
                        "accessors",
                        "bufferViews",
                        "scenes",
                    ]
                    .contains(&k)
            });
            if candidates.is_empty() {
                return None;
            }
            let at = rng.pick(&candidates).clone();
            let name = *rng.pick(HOSTILE_NAMES);
            document
                .pointer_mut(&at)?
                .as_object_mut()?
                .insert("name".into(), json!(name));
            Some(format!("{at}/name = {name:?}"))
        }
        // Growth: copies of an element, deep or wide node trees.
        15 => grow(rng, document),
        // The default scene.
        _ => {
            let what = rng.below(4);
            let object = document.as_object_mut()?;
            match what {
                0 => {
                    let value = interesting_number(rng);
                    object.insert("scene".into(), value.clone());
                    Some(format!("scene = {value}"))
                }
                1 => {
                    object.remove("scenes");
                    Some("no scenes".into())
                }
                2 => {
                    object.insert("scenes".into(), json!([]));
                    Some("scenes = []".into())
                }
                _ => {
                    object.insert("scenes".into(), json!([{"nodes": []}]));
                    Some("scenes = [{nodes: []}]".into())
                }
            }
        }
    }
}

/// Node cycles and nodes reached twice; the description.
fn add_node_cycle(rng: &mut Rng, document: &mut Value) -> Option<String> {
    if top_array_len(document, "nodes") < 2 {
        document["nodes"] = json!([{"mesh": 0}, {"mesh": 0}]);
    }
    let count = top_array_len(document, "nodes");
    let a = rng.below(count);
    let b = rng.below(count);
    let how = rng.below(5);
    let nodes = document["nodes"].as_array_mut()?;
    let add_child = |nodes: &mut Vec<Value>, parent: usize, child: usize| {
        if let Some(node) = nodes[parent].as_object_mut() {
            let children = node.entry("children").or_insert_with(|| json!([]));
            if let Some(list) = children.as_array_mut() {
                list.push(json!(child));
            } else {
                *children = json!([child]);
            }
        }
    };
    match how {
        0 => {
            add_child(nodes, a, a);
            Some(format!("node {a} is its own child"))
        }
        1 => {
            add_child(nodes, a, b);
            add_child(nodes, b, a);
            Some(format!("nodes {a} and {b} are each other's child"))
        }
        2 => {
            add_child(nodes, a, b);
            add_child(nodes, a, b);
            Some(format!("node {b} is twice a child of node {a}"))
        }
        3 => {
            let c = (b + 1) % count;
            add_child(nodes, a, b);
            add_child(nodes, b, c);
            add_child(nodes, c, a);
            Some(format!("cycle {a} -> {b} -> {c} -> {a}"))
        }
        _ => {
            let scene = document
                .get_mut("scenes")
                .and_then(|s| s.get_mut(0))
                .and_then(|s| s.get_mut("nodes"))
                .and_then(Value::as_array_mut)?;
            scene.push(json!(a));
            scene.push(json!(a));
            Some(format!("scene 0 lists node {a} twice more"))
        }
    }
}

/// Required extensions, emission strengths, colour factors and textures; the description.
fn change_material(rng: &mut Rng, document: &mut Value) -> Option<String> {
    match rng.below(4) {
        0 => {
            let name = *rng.pick(&[
                "KHR_draco_mesh_compression",
                "KHR_materials_emissive_strength",
                "",
                "x\ny",
            ]);
            document
                .as_object_mut()?
                .insert("extensionsRequired".into(), json!([name]));
            Some(format!("extensionsRequired = [{name:?}]"))
        }
        1 => {
            let (index, material) = top_element(rng, document, "materials")?;
            let strength = interesting_number(rng);
            material.as_object_mut()?.insert(
                "extensions".into(),
                json!({"KHR_materials_emissive_strength": {"emissiveStrength": strength}}),
            );
            material
                .as_object_mut()?
                .insert("emissiveFactor".into(), json!([1, 1, 1]));
            Some(format!("materials[{index}] emissiveStrength = {strength}"))
        }
        2 => {
            let (index, material) = top_element(rng, document, "materials")?;
            let value = interesting_number(rng);
            let key = *rng.pick(&["emissiveFactor", "baseColorFactor"]);
            let factor = if key == "emissiveFactor" {
                json!([value, 1, 1])
            } else {
                json!([value, 1, 1, 1])
            };
            if key == "emissiveFactor" {
                material.as_object_mut()?.insert(key.into(), factor);
            } else {
                material.as_object_mut()?.insert(
                    "pbrMetallicRoughness".into(),
                    json!({"baseColorFactor": factor}),
                );
            }
            Some(format!("materials[{index}].{key}[0] = {value}"))
        }
        _ => {
            let (index, material) = top_element(rng, document, "materials")?;
            material.as_object_mut()?.insert(
                "pbrMetallicRoughness".into(),
                json!({"baseColorTexture": {"index": rng.below(3)}}),
            );
            Some(format!("materials[{index}] has a baseColorTexture"))
        }
    }
}

/// Camera types and parameters, degenerate and huge node transforms; the description.
fn change_camera_or_transform(rng: &mut Rng, document: &mut Value) -> Option<String> {
    if rng.one_in(2) {
        let (index, camera) = top_element(rng, document, "cameras")?;
        let camera = camera.as_object_mut()?;
        match rng.below(4) {
            0 => {
                let kind = *rng.pick(&["orthographic", "perspective", "bogus"]);
                camera.insert("type".into(), json!(kind));
                Some(format!("cameras[{index}].type = {kind}"))
            }
            1 => {
                camera.remove("perspective");
                Some(format!("cameras[{index}] has no perspective"))
            }
            2 => {
                let yfov = interesting_number(rng);
                camera.insert("perspective".into(), json!({"yfov": yfov, "znear": 0.01}));
                Some(format!("cameras[{index}].yfov = {yfov}"))
            }
            _ => {
                camera.insert(
                    "orthographic".into(),
                    json!({"xmag": 1, "ymag": 1, "znear": 0, "zfar": 1}),
                );
                Some(format!("cameras[{index}] has orthographic parameters"))
            }
        }
    } else {
        let (index, node) = top_element(rng, document, "nodes")?;
        let node = node.as_object_mut()?;
        let big = interesting_number(rng);
        let (key, value) = match rng.below(6) {
            0 => ("matrix", json!(vec![0; 16])),
            1 => (
                "matrix",
                json!([big, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]),
            ),
            2 => ("scale", json!([0, 0, 0])),
            3 => ("scale", json!([-1, 1, 1])),
            4 => ("rotation", json!(*rng.pick(&[[0, 0, 0, 0], [1, 1, 1, 1]]))),
            _ => ("translation", json!([big, 0, 0])),
        };
        let text = value.to_string();
        node.insert(key.into(), value);
        Some(format!("nodes[{index}].{key} = {text}"))
    }
}

/// Growth: copies of an array element, deep or wide node trees; the description.
fn grow(rng: &mut Rng, document: &mut Value) -> Option<String> {
    match rng.below(3) {
        0 => {
            let candidates = pointers(document, &|_, v| {
                v.as_array().is_some_and(|a| !a.is_empty())
            });
            if candidates.is_empty() {
                return None;
            }
            let at = rng.pick(&candidates).clone();
            let copies = *rng.pick(&[1usize, 2, 10, 100, 1000]);
            let array = document.pointer_mut(&at)?.as_array_mut()?;
            let element = array[rng.below(array.len())].clone();
            array.extend(std::iter::repeat_n(element, copies));
            Some(format!("{at} gets {copies} copies of an element"))
        }
        _ => {
            let deep = rng.one_in(2);
            let count = *rng.pick(&[10usize, 100, 1000, 10_000]);
            let first = top_array_len(document, "nodes");
            if !document["nodes"].is_array() {
                document["nodes"] = json!([]);
            }
            let nodes = document["nodes"].as_array_mut()?;
            for i in 0..count {
                let index = first + i;
                let node = if deep {
                    if i + 1 < count {
                        json!({"children": [index + 1], "translation": [0.001, 0, 0]})
                    } else {
                        json!({"mesh": 0})
                    }
                } else {
                    json!({"mesh": 0, "translation": [i as f64 * 0.01, 0, 0]})
                };
                nodes.push(node);
            }
            if !deep {
                nodes.push(json!({"children": (first..first + count).collect::<Vec<_>>()}));
            }
            let root = if deep { first } else { first + count };
            match document
                .get_mut("scenes")
                .and_then(|s| s.get_mut(0))
                .and_then(|s| s.get_mut("nodes"))
                .and_then(Value::as_array_mut)
            {
                Some(roots) => roots.push(json!(root)),
                None => {
                    document["scenes"] = json!([{"nodes": [root]}]);
                    document["scene"] = json!(0);
                }
            }
            Some(format!(
                "{count} more nodes, {}",
                if deep {
                    "a chain"
                } else {
                    "all children of one"
                }
            ))
        }
    }
}

/// Spans of number-like tokens in text.
fn number_spans(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            || (bytes[i] == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        let after_word = i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        if starts && !after_word {
            let start = i;
            i += 1;
            while i < bytes.len() && (bytes[i].is_ascii_digit() || b".eE+-".contains(&bytes[i])) {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

/// Replaces a random number token with one of `tokens`; its description.
fn replace_number(rng: &mut Rng, bytes: &mut Vec<u8>, tokens: &[&str]) -> Option<String> {
    let spans = number_spans(bytes);
    if spans.is_empty() {
        return None;
    }
    let (start, end) = *rng.pick(&spans);
    let token = *rng.pick(tokens);
    let old = String::from_utf8_lossy(&bytes[start..end]).into_owned();
    bytes.splice(start..end, token.bytes());
    Some(format!("number {old} at byte {start} -> {token}"))
}

/// A change to JSON text that a parsed document cannot express; its description.
fn mutate_json_text(rng: &mut Rng, bytes: &mut Vec<u8>) -> Option<String> {
    match rng.below(6) {
        0 | 1 => replace_number(rng, bytes, JSON_NUMBER_TOKENS),
        2 => {
            let braces: Vec<usize> = (0..bytes.len()).filter(|&i| bytes[i] == b'{').collect();
            if braces.is_empty() {
                return None;
            }
            let at = *rng.pick(&braces) + 1;
            let text = *rng.pick(&[
                "\"scene\": 0, ",
                "\"nodes\": [0], ",
                "\"count\": 4294967295, ",
                "\"__proto__\": null, ",
                "\"byteLength\": 1e39, ",
            ]);
            bytes.splice(at..at, text.bytes());
            Some(format!("inserted {text:?} at byte {at}"))
        }
        3 => {
            bytes.splice(0..0, *b"\xef\xbb\xbf");
            Some("byte order mark".into())
        }
        4 => {
            // A raw control character or invalid UTF-8 inside a string.
            let quotes: Vec<usize> = (0..bytes.len()).filter(|&i| bytes[i] == b'"').collect();
            if quotes.is_empty() {
                return None;
            }
            let at = *rng.pick(&quotes) + 1;
            let choices: [&[u8]; 5] = [b"\n", b"\0", b"\xff\xfe", b"\\u0000", b"\\ud800"];
            let inserted = *rng.pick(&choices);
            bytes.splice(at..at, inserted.iter().copied());
            Some(format!(
                "inserted {:?} at byte {at}",
                String::from_utf8_lossy(inserted)
            ))
        }
        _ => {
            let braces: Vec<usize> = (0..bytes.len()).filter(|&i| bytes[i] == b'{').collect();
            let at = braces.first().map_or(0, |&i| i + 1);
            let depth = *rng.pick(&[100usize, 10_000]);
            let mut text = b"\"deep\": ".to_vec();
            text.extend(std::iter::repeat_n(b'[', depth));
            text.extend(std::iter::repeat_n(b']', depth));
            text.extend_from_slice(b", ");
            bytes.splice(at..at, text);
            Some(format!("value nested {depth} deep at byte {at}"))
        }
    }
}

/// Little-endian values that break binary layouts.
const INTERESTING_WORDS: &[u32] = &[
    0,
    1,
    0x7f,
    0x80,
    0xff,
    0xffff,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x7f7f_ffff, // f32::MAX
    0x7fc0_0000, // NaN
    0x7f80_0000, // inf
    0xff80_0000, // -inf
    0x0000_0001, // the smallest subnormal
];

/// Tokens inserted into any file.
const INSERTED_TOKENS: &[&str] = &[
    "4294967295",
    "1e39",
    "-1",
    "NaN",
    "inf",
    "\n",
    "\0",
    "\u{feff}",
    "18446744073709551616",
];

/// A change to raw bytes; its description.
fn mutate_bytes(rng: &mut Rng, bytes: &mut Vec<u8>) -> String {
    let length = bytes.len();
    let kind = if length == 0 { 7 } else { rng.below(9) };
    match kind {
        0 => {
            let flips = rng.below(8) + 1;
            let mut at = Vec::new();
            for _ in 0..flips {
                let i = rng.below(length);
                bytes[i] ^= 1 << rng.below(8);
                at.push(i);
            }
            format!("flipped bits at bytes {at:?}")
        }
        1 => {
            let i = rng.below(length);
            let count = (rng.below(8) + 1).min(length - i);
            for b in &mut bytes[i..i + count] {
                *b = rng.next() as u8;
            }
            format!("{count} random bytes at byte {i}")
        }
        2 | 3 => {
            let word = *rng.pick(INTERESTING_WORDS);
            let width = *rng.pick(&[1usize, 2, 4, 4, 4, 8]);
            let i = if rng.one_in(2) {
                rng.below(length) & !3
            } else {
                rng.below(length)
            };
            let mut value = u64::from(word).to_le_bytes();
            if width == 8 && word == 0xffff_ffff {
                value = u64::MAX.to_le_bytes();
            }
            let end = (i + width).min(length);
            bytes[i..end].copy_from_slice(&value[..end - i]);
            format!("{width}-byte word {word:#x} at byte {i}")
        }
        4 => {
            let at = rng.below(length);
            bytes.truncate(at);
            format!("cut at byte {at}")
        }
        5 => {
            let start = rng.below(length);
            let end = (start + rng.below(4096) + 1).min(length);
            let slice = bytes[start..end].to_vec();
            let copies = *rng.pick(&[1usize, 1, 2, 16, 100]);
            let at = rng.below(length + 1);
            let inserted: Vec<u8> = slice
                .iter()
                .copied()
                .cycle()
                .take(slice.len() * copies)
                .collect();
            bytes.splice(at..at, inserted);
            format!("{copies} copies of bytes {start}..{end} inserted at byte {at}")
        }
        6 => {
            let start = rng.below(length);
            let end = (start + rng.below(256) + 1).min(length);
            bytes.drain(start..end);
            format!("removed bytes {start}..{end}")
        }
        _ => {
            let at = rng.below(length + 1);
            let token = *rng.pick(INSERTED_TOKENS);
            bytes.splice(at..at, token.bytes());
            format!("inserted {token:?} at byte {at}")
        }
    }
}

/// A change to a glTF JSON text: structured when it parses (most of the time), else textual,
/// else bytes.
fn mutate_json_bytes(rng: &mut Rng, bytes: &mut Vec<u8>, case: &mut Case) -> String {
    if !rng.one_in(4) {
        if let Ok(mut document) = serde_json::from_slice::<Value>(bytes) {
            if let Some(what) = mutate_document(rng, &mut document, case) {
                *bytes = if rng.one_in(2) {
                    serde_json::to_vec(&document).unwrap()
                } else {
                    serde_json::to_vec_pretty(&document).unwrap()
                };
                return what;
            }
        }
    }
    if !rng.one_in(3) {
        if let Some(what) = mutate_json_text(rng, bytes) {
            return what;
        }
    }
    mutate_bytes(rng, bytes)
}

/// Changes the bytes of a glTF's first buffer: its data URI or its `.bin` file.
fn mutate_gltf_buffer(rng: &mut Rng, case: &mut Case) -> Option<String> {
    let mut document: Value = serde_json::from_slice(&case.files[0].1).ok()?;
    let uri = document.pointer("/buffers/0/uri")?.as_str()?.to_owned();
    if let Some((head, encoded)) = uri.split_once(";base64,") {
        let mut data = base64::decode(encoded).ok()?;
        let what = if data.is_empty() {
            return None;
        } else {
            mutate_bytes(rng, &mut data)
        };
        document["buffers"][0]["uri"] = json!(format!("{head};base64,{}", base64::encode(&data)));
        case.files[0].1 = serde_json::to_vec_pretty(&document).ok()?;
        Some(format!("data URI buffer: {what}"))
    } else {
        let data = case.file_mut(&uri)?;
        Some(format!("{uri}: {}", mutate_bytes(rng, data)))
    }
}

/// A glTF case: 1 to 4 changes to the JSON or the buffer.
fn mutate_gltf(rng: &mut Rng, case: &mut Case) {
    for _ in 0..rng.below(4) + 1 {
        let what = if rng.one_in(5) {
            mutate_gltf_buffer(rng, case)
        } else {
            None
        };
        let what = what.unwrap_or_else(|| {
            let mut bytes = std::mem::take(&mut case.files[0].1);
            let what = mutate_json_bytes(rng, &mut bytes, case);
            case.files[0].1 = bytes;
            what
        });
        case.recipe.push(what);
    }
}

/// A GLB case: 1 to 4 changes to the JSON chunk, the binary chunk, the container, or (after
/// assembly) the bytes.
fn mutate_glb(rng: &mut Rng, case: &mut Case) {
    let mut glb = Glb::parse(&case.files[0].1);
    let mut raw = Vec::new();
    for _ in 0..rng.below(4) + 1 {
        let what = match rng.below(10) {
            0..=3 if !glb.chunks.is_empty() => {
                let mut json = std::mem::take(&mut glb.chunks[0].data);
                let what = mutate_json_bytes(rng, &mut json, case);
                glb.chunks[0].data = json;
                format!("JSON chunk: {what}")
            }
            4 => match glb.chunks.get_mut(1) {
                Some(bin) if !bin.data.is_empty() => {
                    format!("BIN chunk: {}", mutate_bytes(rng, &mut bin.data))
                }
                _ => "no BIN chunk to change".into(),
            },
            5 | 6 if !glb.chunks.is_empty() => {
                let chunk_count = glb.chunks.len();
                match rng.below(9) {
                    0 => {
                        glb.magic = *rng.pick(&[*b"gltf", *b"\0\0\0\0", *b"GLTF", *b"glTF"]);
                        format!("magic {:?}", String::from_utf8_lossy(&glb.magic))
                    }
                    1 => {
                        glb.version = *rng.pick(&[0, 1, 3, u32::MAX]);
                        format!("version {}", glb.version)
                    }
                    2 | 3 => {
                        let total = glb.assemble().len() as u32;
                        let length = *rng.pick(&[
                            0,
                            11,
                            12,
                            13,
                            total.wrapping_sub(1),
                            total + 1,
                            total + 4,
                            0x7fff_ffff,
                            u32::MAX,
                        ]);
                        glb.length = Some(length);
                        format!("total length {length} (file has {total})")
                    }
                    4 | 5 => {
                        let index = rng.below(chunk_count);
                        let chunk = &mut glb.chunks[index];
                        let real = chunk.data.len() as u32;
                        let length = *rng.pick(&[
                            0,
                            1,
                            real.wrapping_sub(1),
                            real + 1,
                            real + 4,
                            0x7fff_fff8,
                            u32::MAX - 7,
                            u32::MAX,
                        ]);
                        chunk.length = Some(length);
                        format!("chunk {index} length {length} (has {real})")
                    }
                    6 => {
                        let index = rng.below(chunk_count);
                        let kind = *rng.pick(&[*b"JSON", *b"BIN\0", *b"XXXX", *b"\0\0\0\0"]);
                        glb.chunks[index].kind = kind;
                        format!("chunk {index} type {:?}", String::from_utf8_lossy(&kind))
                    }
                    7 => {
                        if rng.one_in(2) && chunk_count > 1 {
                            glb.chunks.swap(0, 1);
                            "chunks swapped".into()
                        } else if chunk_count > 1 {
                            glb.chunks.truncate(1);
                            "BIN chunk removed".into()
                        } else {
                            glb.chunks.clear();
                            "all chunks removed".into()
                        }
                    }
                    _ => {
                        let kind = *rng.pick(&[*b"BIN\0", *b"JSON", *b"ABCD"]);
                        let size = *rng.pick(&[0usize, 3, 4, 1000]);
                        glb.chunks.push(Chunk {
                            kind,
                            length: None,
                            data: vec![0x41; size],
                            pad: rng.one_in(2),
                        });
                        format!(
                            "extra chunk {:?} of {size} bytes",
                            String::from_utf8_lossy(&kind)
                        )
                    }
                }
            }
            0..=7 => {
                for chunk in &mut glb.chunks {
                    chunk.pad = false;
                }
                "chunks unpadded".into()
            }
            _ => {
                raw.push(rng.next());
                continue;
            }
        };
        case.recipe.push(what);
    }
    let mut bytes = glb.assemble();
    for seed in raw {
        let what = mutate_bytes(&mut Rng::new(seed), &mut bytes);
        case.recipe.push(format!("bytes: {what}"));
    }
    case.files[0].1 = bytes;
}

/// OBJ lines that break assumptions about indices, numbers and files.
fn hostile_obj_line(rng: &mut Rng, case: &mut Case) -> String {
    let lines = [
        "f 1 2 4294967295",
        "f 1 2 4294967296",
        "f 0 1 2",
        "f -1 -2 -3",
        "f -1000000 1 2",
        "f -4294967295 1 2",
        "f 1 2 99999999999999999999",
        "f 2147483647 2147483648 -2147483648",
        "f 1/1/1 2/2/2 3/3/3",
        "f 1/999999/1 2/1/1 3/1/1",
        "f 1//4294967295 2//1 3//1",
        "f 1",
        "f",
        "f 1 2",
        "f 1 1 1",
        "f a b c",
        "f 1/ /2 //",
        "v nan nan nan",
        "v NaN 0 0",
        "v inf 0 0",
        "v -inf 1 1",
        "v 1e39 1e39 1e39",
        "v 3.4e38 -3.4e38 3.4e38",
        "v 1",
        "v",
        "v 1 2 3 4 5 6 7",
        "vt 1e39 nan",
        "vn nan 0 0",
        "vn 0 0 0",
        "usemtl",
        "usemtl nosuch",
        "usemtl light\nusemtl white",
        "o",
        "g",
        "o line one\rline two",
        "s off",
        "l 1 2 3",
        "p 1",
        "#",
        "\0",
        "f 1 2 3\\",
        "v 0 0 0\\",
        "\\",
        "mtllib",
        "mtllib .",
        "mtllib /",
        "mtllib ../../etc/passwd",
        "mtllib /etc/passwd",
        "mtllib /dev/zero",
        "mtllib /proc/self/status",
        "mtllib missing.mtl",
        "mtllib a.mtl b.mtl c.mtl",
    ];
    match rng.below(lines.len() + 6) {
        i if i < lines.len() => lines[i].to_owned(),
        n if n == lines.len() => {
            if let Some(fifo) = fifo() {
                case.link("pipe.mtl", fifo);
            }
            "mtllib pipe.mtl".into()
        }
        n if n == lines.len() + 1 => {
            case.link("zero.mtl", "/dev/zero");
            "mtllib zero.mtl".into()
        }
        n if n == lines.len() + 2 => format!("mtllib {}", case.files[0].0),
        n if n == lines.len() + 3 => format!("mtllib {}", "a".repeat(5000)),
        n if n == lines.len() + 4 => {
            let count = *rng.pick(&[100usize, 10_000]);
            let mut line = String::from("f");
            for i in 0..count {
                line.push_str(&format!(" {}", i % 8 + 1));
            }
            line
        }
        _ => {
            let count = *rng.pick(&[100usize, 10_000]);
            let mut line = String::new();
            for i in 0..count {
                line.push_str(&format!("v {i} {} 0\n", i % 7));
            }
            line.push_str(&format!("f 1 {} {}", count / 2, count));
            line
        }
    }
}

/// MTL lines with bad numbers and files.
const HOSTILE_MTL_LINES: &[&str] = &[
    "Kd nan nan nan",
    "Kd -1 -1 -1",
    "Kd 1e39 1e39 1e39",
    "Kd 1",
    "Kd",
    "Ke 1e39 1e39 1e39",
    "Ke inf inf inf",
    "Ke nan 1 1",
    "Ke -1 -1 -1",
    "Ke 1e30 1e30 1e30",
    "Ke 1.0000001e30 0 0",
    "Ke 3.4e38 3.4e38 3.4e38",
    "newmtl",
    "newmtl white",
    "newmtl light",
    "map_Kd /dev/zero",
    "map_Kd ../../etc/passwd",
    "map_Ke glow.png",
    "Ns 1e39",
    "d nan",
    "illum 4294967295",
    "\0",
];

/// Number tokens for OBJ and MTL text.
const OBJ_NUMBER_TOKENS: &[&str] = &[
    "0",
    "-1",
    "-0",
    "4294967295",
    "4294967296",
    "2147483648",
    "-2147483649",
    "99999999999999999999",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e39",
    "-1e39",
    "1e-45",
    "1e30",
    "3.5e38",
    "0x10",
    "1/2/3",
    "//",
];

/// Changes line-based text (OBJ or MTL): a hostile line inserted or replacing one, a number
/// token replaced, lines duplicated or removed; its description.
fn mutate_lines(rng: &mut Rng, bytes: &mut Vec<u8>, hostile: String) -> String {
    let mut lines: Vec<Vec<u8>> = bytes.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
    let count = lines.len();
    let at = rng.below(count);
    let what = match rng.below(6) {
        0 | 1 => {
            let at = rng.below(count + 1);
            lines.insert(at, hostile.clone().into_bytes());
            format!("line {at} inserted: {:?}", shorten(&hostile))
        }
        2 => {
            let old = String::from_utf8_lossy(&lines[at]).into_owned();
            lines[at] = hostile.clone().into_bytes();
            format!(
                "line {at} {:?} replaced with {:?}",
                shorten(&old),
                shorten(&hostile)
            )
        }
        3 => {
            let mut line = std::mem::take(&mut lines[at]);
            let what = replace_number(rng, &mut line, OBJ_NUMBER_TOKENS)
                .unwrap_or_else(|| "no number".into());
            lines[at] = line;
            format!("line {at}: {what}")
        }
        4 => {
            let copies = *rng.pick(&[1usize, 10, 1000]);
            let line = lines[at].clone();
            for _ in 0..copies {
                lines.insert(at, line.clone());
            }
            format!("line {at} repeated {copies} more times")
        }
        _ => {
            lines.remove(at);
            format!("line {at} removed")
        }
    };
    *bytes = lines.join(&b'\n');
    what
}

fn shorten(text: &str) -> String {
    let short: String = text.chars().take(60).collect();
    if short.len() < text.len() {
        format!("{short}...")
    } else {
        short
    }
}

/// An OBJ case: 1 to 4 changes to the OBJ or its MTL library.
fn mutate_obj(rng: &mut Rng, case: &mut Case) {
    for _ in 0..rng.below(4) + 1 {
        let mtl = rng.one_in(4) && case.files.len() > 1;
        let index = usize::from(mtl);
        let name = case.files[index].0.clone();
        let mut bytes = std::mem::take(&mut case.files[index].1);
        let what = if rng.one_in(5) {
            mutate_bytes(rng, &mut bytes)
        } else {
            let hostile = if mtl {
                (*rng.pick(HOSTILE_MTL_LINES)).to_owned()
            } else {
                hostile_obj_line(rng, case)
            };
            mutate_lines(rng, &mut bytes, hostile)
        };
        case.files[index].1 = bytes;
        case.recipe.push(format!("{name}: {what}"));
    }
}

/// Case `index` of `seed` (deterministic for a given `base`).
fn make_case(seed: &Seed, index: usize, base: u64) -> Case {
    let mut rng = Rng::new(
        fnv(&seed.name)
            ^ base.wrapping_mul(0x2545_f491_4f6c_dd1d)
            ^ (index as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15),
    );
    let mut case = Case {
        label: format!("{}#{index}", seed.name),
        files: seed.files.clone(),
        ..Case::default()
    };
    match seed.format {
        Format::Gltf => mutate_gltf(&mut rng, &mut case),
        Format::Glb => mutate_glb(&mut rng, &mut case),
        Format::Obj => mutate_obj(&mut rng, &mut case),
    }
    case
}

// ---------------------------------------------------------------------------------------------
// Running cases.

/// How a load ended, as seen from the worker.
enum Outcome {
    Loaded { triangles: usize },
    Refused { message: String },
}

/// What went wrong with a case.
struct Failure {
    label: String,
    recipe: Vec<String>,
    what: String,
    input: PathBuf,
}

/// What one case did.
struct Run {
    /// `Err` when the case broke a rule (panic, hang, several lines, bad scene, memory).
    outcome: Result<Outcome, String>,
    elapsed: Duration,
    peak_heap: isize,
    hung: bool,
}

/// Checks what `SceneBuilder` promises about a loaded scene.
fn check_scene(scene: &Scene) -> Result<(), String> {
    if scene.triangles.is_empty() {
        return Err("a scene without triangles".into());
    }
    for (i, t) in scene.triangles.iter().enumerate() {
        let ok = t.positions.iter().all(|p| p.is_finite())
            && t.normal.is_finite()
            && (t.normal.length() - 1.0).abs() < 1e-3
            && t.color.cmpge(glam::Vec3::ZERO).all()
            && t.color.cmple(glam::Vec3::ONE).all()
            && t.emission.cmpge(glam::Vec3::ZERO).all()
            && t.emission.max_element() <= MAX_EMISSION;
        if !ok {
            return Err(format!("triangle {i} breaks the scene's promises: {t:?}"));
        }
    }
    if let Some(camera) = &scene.camera {
        let finite = camera.position.is_finite()
            && camera.image_plane_middle.is_finite()
            && camera.up.is_finite()
            && camera.right_per_unit_aspect.is_finite();
        if !finite {
            return Err(format!("a non-finite camera: {camera:?}"));
        }
    }
    for warning in &scene.warnings {
        if warning.contains(['\n', '\r']) {
            return Err(format!("a warning of several lines: {warning:?}"));
        }
    }
    Ok(())
}

/// Loads `path` in a worker thread named `label`, with a timeout, counting its heap.
fn run_load(label: &str, path: &Path, options: LoadOptions) -> Run {
    let (sender, receiver) = mpsc::sync_channel(1);
    let note = format!("case {label} (input: {})", path.display());
    let thread_path = path.to_owned();
    let start = Instant::now();
    let spawned = std::thread::Builder::new()
        .name(label.to_owned())
        .spawn(move || {
            let note = note;
            ABORT_NOTE.with(|n| n.set((note.as_ptr(), note.len())));
            let result =
                std::panic::catch_unwind(|| match Scene::load_with(&thread_path, &options) {
                    Ok(scene) => check_scene(&scene).map(|()| Outcome::Loaded {
                        triangles: scene.triangles.len(),
                    }),
                    Err(error) => {
                        let message = error.to_string();
                        if message.is_empty() || message.contains(['\n', '\r']) {
                            Err(format!("an error that is not one line: {message:?}"))
                        } else {
                            Ok(Outcome::Refused { message })
                        }
                    }
                });
            let outcome = match result {
                Ok(outcome) => outcome,
                Err(payload) => {
                    let message = payload
                        .downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| payload.downcast_ref::<String>().cloned())
                        .unwrap_or_else(|| "(not a string)".into());
                    Err(format!("panicked: {message}"))
                }
            };
            ABORT_NOTE.with(|n| n.set((std::ptr::null(), 0)));
            let peak = PEAK.with(Cell::get);
            let _ = sender.send((outcome, peak));
        })
        .expect("spawn a worker thread");
    let timeout = case_timeout();
    match receiver.recv_timeout(timeout) {
        Ok((outcome, peak_heap)) => {
            let elapsed = start.elapsed();
            let _ = spawned.join();
            let outcome = if peak_heap > CASE_HEAP_LIMIT {
                Err(format!(
                    "its heap peaked at {} MiB, over the {} MiB bound",
                    peak_heap >> 20,
                    CASE_HEAP_LIMIT >> 20
                ))
            } else {
                outcome
            };
            Run {
                outcome,
                elapsed,
                peak_heap,
                hung: false,
            }
        }
        Err(mpsc::RecvTimeoutError::Timeout) => Run {
            // The worker is left behind: a thread cannot be stopped.
            outcome: Err(format!("hung: no result after {timeout:?}")),
            elapsed: start.elapsed(),
            peak_heap: 0,
            hung: true,
        },
        Err(mpsc::RecvTimeoutError::Disconnected) => Run {
            outcome: Err("the worker ended without a result".into()),
            elapsed: start.elapsed(),
            peak_heap: 0,
            hung: false,
        },
    }
}

/// Copies a case's input into a folder that stays (for the failure report).
fn keep_input(case: &Case) -> PathBuf {
    let folder_name: String = case
        .label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    let dir = std::env::temp_dir()
        .join("vkpath-fuzz-failures")
        .join(format!("{folder_name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    case.write(&dir);
    let mut recipe = case.recipe.join("\n");
    recipe.push('\n');
    if case.allow_external_paths {
        recipe.push_str("(loaded with allow_external_paths: true)\n");
    }
    std::fs::write(dir.join("RECIPE.txt"), recipe).unwrap();
    dir
}

/// A failure's message without the things that vary between cases of one kind: quoted paths,
/// what lies in brackets (a panic's `Err` value) and digits.
fn failure_kind(what: &str) -> String {
    let mut kind = String::new();
    let mut in_path = false;
    let mut in_brackets = false;
    let mut previous = ' ';
    for c in what.chars() {
        if in_path {
            in_path = c != '\'';
        } else if in_brackets {
            in_brackets = c != ']';
        } else if c == '[' {
            in_brackets = true;
            kind.push_str("[..]");
        } else if c == '/' && previous == '\'' {
            in_path = true;
            kind.push_str("PATH'");
        } else if c.is_ascii_digit() {
            if !kind.ends_with('#') {
                kind.push('#');
            }
        } else {
            kind.push(c);
        }
        previous = c;
    }
    kind
}

/// Counts for one seed.
#[derive(Default)]
struct Tally {
    cases: usize,
    loaded: usize,
    refused: usize,
    slowest: Duration,
    slowest_label: String,
    peak_heap: isize,
}

/// Runs every case of every seed of `format`; panics listing the failures.
fn fuzz(format: Format) {
    let base: u64 = std::env::var("VKPATH_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let per_seed: usize = std::env::var("VKPATH_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(DEFAULT_CASES_PER_SEED);
    let only = std::env::var("VKPATH_FUZZ_CASE").ok();
    let start = Instant::now();
    let mut failures: Vec<Failure> = Vec::new();
    let mut total = 0;
    'seeds: for seed in seeds().into_iter().filter(|s| s.format == format) {
        let mut tally = Tally::default();
        let seed_start = Instant::now();
        for index in 0..per_seed {
            let label = format!("{}#{index}", seed.name);
            if only.as_ref().is_some_and(|only| *only != label) {
                continue;
            }
            let case = make_case(&seed, index, base);
            let dir = tempfile::tempdir().unwrap();
            let path = case.write(dir.path());
            let options = LoadOptions {
                allow_external_paths: case.allow_external_paths,
                ..LoadOptions::default()
            };
            let run = run_load(&case.label, &path, options);
            tally.cases += 1;
            total += 1;
            if run.elapsed > tally.slowest {
                tally.slowest = run.elapsed;
                tally.slowest_label = case.label.clone();
            }
            tally.peak_heap = tally.peak_heap.max(run.peak_heap);
            if only.is_some() {
                let input = keep_input(&case);
                println!(
                    "{}: {:#?}\ninput kept in {}",
                    case.label,
                    case.recipe,
                    input.display()
                );
                match &run.outcome {
                    Ok(Outcome::Loaded { triangles }) => println!("loaded {triangles} triangles"),
                    Ok(Outcome::Refused { message }) => println!("refused: {message}"),
                    Err(what) => println!("FAILED: {what}"),
                }
            }
            match run.outcome {
                Ok(Outcome::Loaded { .. }) => tally.loaded += 1,
                Ok(Outcome::Refused { .. }) => tally.refused += 1,
                Err(what) => {
                    let input = keep_input(&case);
                    failures.push(Failure {
                        label: case.label.clone(),
                        recipe: case.recipe.clone(),
                        what,
                        input,
                    });
                    if run.hung {
                        // Its worker still runs; the rest of the run would not mean much.
                        std::mem::forget(dir);
                        break 'seeds;
                    }
                }
            }
        }
        if tally.cases > 0 {
            println!(
                "{}: {} cases in {:.1} s: {} loaded, {} refused, {} failed; slowest {} ({:.0} ms); \
                 largest heap {:.1} MiB",
                seed.name,
                tally.cases,
                seed_start.elapsed().as_secs_f64(),
                tally.loaded,
                tally.refused,
                tally.cases - tally.loaded - tally.refused,
                tally.slowest_label,
                tally.slowest.as_secs_f64() * 1e3,
                tally.peak_heap as f64 / (1 << 20) as f64,
            );
        }
    }
    let rss = peak_rss();
    println!(
        "{format:?}: {total} cases in {:.1} s (VKPATH_FUZZ_SEED={base}); process peak RSS {} MiB",
        start.elapsed().as_secs_f64(),
        rss >> 20
    );
    assert!(
        rss < PROCESS_RSS_LIMIT,
        "the process's peak RSS reached {} MiB, over the {} MiB bound",
        rss >> 20,
        PROCESS_RSS_LIMIT >> 20
    );
    if !failures.is_empty() {
        // One entry per kind of failure (the message without paths and digits), with its
        // first case in full.
        let mut kinds: Vec<(String, Vec<&Failure>)> = Vec::new();
        for failure in &failures {
            let kind = failure_kind(&failure.what);
            match kinds.iter_mut().find(|(k, _)| *k == kind) {
                Some((_, list)) => list.push(failure),
                None => kinds.push((kind, vec![failure])),
            }
        }
        let mut report = format!(
            "{} of {total} {format:?} cases failed, {} kinds of failure:\n",
            failures.len(),
            kinds.len()
        );
        for (_, list) in kinds.iter().take(20) {
            let failure = list[0];
            let others: Vec<&str> = list[1..].iter().take(5).map(|f| f.label.as_str()).collect();
            report.push_str(&format!(
                "- {}: {}\n  mutations: {}\n  input: {}\n  again: VKPATH_FUZZ_SEED={base} VKPATH_FUZZ_CASE='{}' \
                 cargo test --release --test fuzz_loaders\n  {} more like it{}{}\n",
                failure.label,
                failure.what,
                failure.recipe.join("; "),
                failure.input.display(),
                failure.label,
                list.len() - 1,
                if others.is_empty() { "" } else { ": " },
                others.join(", "),
            ));
        }
        panic!("{report}");
    }
}

#[test]
fn fuzz_gltf() {
    fuzz(Format::Gltf);
}

#[test]
fn fuzz_glb() {
    fuzz(Format::Glb);
}

#[test]
fn fuzz_obj() {
    fuzz(Format::Obj);
}

/// The seeds themselves load (all but malformed.gltf and lines.gltf), the GLBs like the glTF files they were
/// made from and the Cornell box OBJ like the built-in scene; with `VKPATH_FUZZ_WRITE_SEEDS` they
/// are written out as `cargo fuzz` corpora.
#[test]
fn seeds_load() {
    let mut counts = std::collections::HashMap::new();
    for seed in seeds() {
        let dir = tempfile::tempdir().unwrap();
        let case = Case {
            label: seed.name.clone(),
            files: seed.files.clone(),
            ..Case::default()
        };
        let path = case.write(dir.path());
        let run = run_load(&seed.name, &path, LoadOptions::default());
        match run.outcome {
            Ok(Outcome::Loaded { triangles }) => {
                counts.insert(seed.name.clone(), triangles);
            }
            Ok(Outcome::Refused { message }) => {
                // lines.gltf has nothing but a line segment.
                let expected = match seed.name.as_str() {
                    "malformed.gltf" => "malformed glTF",
                    "lines.gltf" | "lines.glb" => "contains no triangles",
                    _ => panic!("{}: {message}", seed.name),
                };
                assert!(message.contains(expected), "{}: {message}", seed.name);
            }
            Err(what) => panic!("{}: {what}", seed.name),
        }
    }
    assert_eq!(counts["emissive_quad.glb"], counts["emissive_quad.gltf"]);
    assert_eq!(
        counts["emissive_quad_external.gltf"],
        counts["emissive_quad.gltf"]
    );
    assert_eq!(
        counts["cornell.obj"],
        Scene::builtin_cornell_box().unwrap().triangles.len()
    );

    if let Ok(out) = std::env::var("VKPATH_FUZZ_WRITE_SEEDS") {
        let out = PathBuf::from(out);
        for seed in seeds() {
            let (target, bytes) = match seed.format {
                Format::Gltf if seed.files.len() == 1 => ("load_gltf", seed.files[0].1.clone()),
                Format::Gltf => continue,
                Format::Glb => ("load_glb", seed.files[0].1.clone()),
                Format::Obj => {
                    // The OBJ, the separator and the MTL (fuzz/fuzz_targets/load_obj.rs writes
                    // it as scene.mtl).
                    let obj = String::from_utf8(seed.files[0].1.clone()).unwrap();
                    let library = format!("mtllib {}", seed.files[1].0);
                    let mut bytes = obj.replace(&library, "mtllib scene.mtl").into_bytes();
                    bytes.extend_from_slice(b"\n#--mtl--\n");
                    bytes.extend_from_slice(&seed.files[1].1);
                    ("load_obj", bytes)
                }
            };
            let dir = out.join(target);
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(dir.join(&seed.name), bytes).unwrap();
        }
        println!("seed corpora written to {}", out.display());
    }
}

/// Inputs that once failed (tests/data/fuzz_regressions/*.gltf, *.glb, *.obj, with the files
/// they name next to them) load or are refused cleanly.
#[test]
fn regressions_load_cleanly() {
    let dir = data_dir().join("fuzz_regressions");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension()
                .is_some_and(|e| ["gltf", "glb", "obj"].contains(&e.to_string_lossy().as_ref()))
        })
        .collect();
    paths.sort();
    let mut failures = Vec::new();
    for path in &paths {
        let label = path.file_name().unwrap().to_string_lossy().into_owned();
        let run = run_load(&label, path, LoadOptions::default());
        match run.outcome {
            Ok(Outcome::Loaded { triangles }) => println!(
                "{label}: {triangles} triangles, heap peak {:.1} MiB",
                run.peak_heap as f64 / (1 << 20) as f64
            ),
            Ok(Outcome::Refused { message }) => println!(
                "{label}: {message} (heap peak {:.1} MiB)",
                run.peak_heap as f64 / (1 << 20) as f64
            ),
            Err(what) => failures.push(format!("{label}: {what}")),
        }
        if run.hung {
            break;
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
