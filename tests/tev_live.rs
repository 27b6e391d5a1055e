//! `render --tev HOST:PORT` (issue 43): a small in-test server that speaks tev's TCP protocol
//! (the packets tev reads: a little-endian u32 length, a type byte, then the fields) receives
//! the live view; the last image it holds must be the output EXR, value for value.

use crate::common;

use std::collections::BTreeMap;
use std::io::Read;
use std::net::TcpListener;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// What the server saw: the images created (name, width, height, channels) and, per image,
/// its channels' values after every update, with how many updates came.
#[derive(Debug, Default)]
struct Received {
    created: Vec<(String, u32, u32, Vec<String>)>,
    updates: usize,
    channels: BTreeMap<String, Vec<f32>>,
}

/// Reads little-endian fields from a packet's bytes.
struct Fields<'a>(&'a [u8]);

impl Fields<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        head
    }
    fn u8(&mut self) -> u8 {
        self.take(1)[0]
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.take(4).try_into().unwrap())
    }
    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.take(8).try_into().unwrap())
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.take(4).try_into().unwrap())
    }
    fn string(&mut self) -> String {
        let end = self
            .0
            .iter()
            .position(|&b| b == 0)
            .expect("a terminated string");
        let text = String::from_utf8(self.0[..end].to_vec()).unwrap();
        self.0 = &self.0[end + 1..];
        text
    }
}

/// Serves one connection as tev would: CreateImage (4) makes an image of zeros, UpdateImage
/// (6, tev's v3) writes a rectangle of channels with offsets and strides into it.
fn serve_one(listener: TcpListener) -> JoinHandle<Received> {
    std::thread::spawn(move || {
        let (mut socket, _) = listener.accept().unwrap();
        let mut received = Received::default();
        let mut size = (0u32, 0u32);
        loop {
            let mut length = [0u8; 4];
            if socket.read_exact(&mut length).is_err() {
                return received;
            }
            let mut packet = vec![0u8; u32::from_le_bytes(length) as usize - 4];
            socket.read_exact(&mut packet).unwrap();
            let mut fields = Fields(&packet);
            match fields.u8() {
                4 => {
                    let _grab_focus = fields.u8();
                    let name = fields.string();
                    let (width, height) = (fields.u32(), fields.u32());
                    let count = fields.u32();
                    let names: Vec<String> = (0..count).map(|_| fields.string()).collect();
                    size = (width, height);
                    received.channels = names
                        .iter()
                        .map(|n| (n.clone(), vec![0.0; (width * height) as usize]))
                        .collect();
                    received.created.push((name, width, height, names));
                }
                6 => {
                    let _grab_focus = fields.u8();
                    let _name = fields.string();
                    let count = fields.u32() as usize;
                    let names: Vec<String> = (0..count).map(|_| fields.string()).collect();
                    let (x, y, w, h) = (fields.u32(), fields.u32(), fields.u32(), fields.u32());
                    let offsets: Vec<u64> = (0..count).map(|_| fields.u64()).collect();
                    let strides: Vec<u64> = (0..count).map(|_| fields.u64()).collect();
                    let data: Vec<f32> = (0..fields.0.len() / 4).map(|_| fields.f32()).collect();
                    for (k, name) in names.iter().enumerate() {
                        let plane = received.channels.get_mut(name).expect("a created channel");
                        for row in 0..h {
                            for column in 0..w {
                                let i = u64::from(row * w + column);
                                let value = data[(offsets[k] + i * strides[k]) as usize];
                                plane[((y + row) * size.0 + x + column) as usize] = value;
                            }
                        }
                    }
                    received.updates += 1;
                }
                other => panic!("unexpected packet type {other}"),
            }
        }
    })
}

#[test]
fn the_live_view_reaches_tev_progressively_and_ends_with_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let server = serve_one(listener);
    // Long enough (about 1.3 s on lavapipe, 2 cores; batches last up to 0.25 s) for several
    // updates at 0.1 s.
    let output = common::vkpath(
        dir.path(),
        &[
            "render",
            "--width",
            "48",
            "--height",
            "32",
            "--spp",
            "8192",
            "--integrator",
            "workshop",
            "--aov",
            "albedo",
            "-o",
            "out.exr",
            "--tev",
            &address,
            "--tev-interval",
            "0.1",
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
    let received = server.join().unwrap();
    // Created for the render (R, G, B), then again at the end with the AOV layer.
    let created: Vec<(String, u32, u32, usize)> = received
        .created
        .iter()
        .map(|(name, w, h, channels)| (name.clone(), *w, *h, channels.len()))
        .collect();
    assert_eq!(
        created,
        [("out.exr".into(), 48, 32, 3), ("out.exr".into(), 48, 32, 6)]
    );
    assert!(
        received.updates >= 3,
        "progressive updates and the final one: {}",
        received.updates
    );
    // The last image tev holds is the output, value for value.
    let image = vkpath::image_io::exr_input::read_exr(&dir.path().join("out.exr")).unwrap();
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let expected: Vec<f32> = image.image.mean.iter().map(|p| p[c]).collect();
        assert!(received.channels[*name] == expected, "channel {name}");
    }
    assert!(received.channels["albedo.R"].iter().any(|&v| v > 0.0));
}

#[test]
fn an_unreachable_tev_is_one_warning_and_the_render_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    // A port nothing listens on: bind one, then free it.
    let address = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .to_string();
    let output = common::vkpath(
        dir.path(),
        &[
            "render", "--width", "8", "--height", "8", "--spp", "2", "-o", "out.png", "--tev",
            &address,
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(
        warnings[0].contains(&format!("no live view: cannot reach tev at {address}")),
        "{}",
        warnings[0]
    );
    assert!(dir.path().join("out.png").is_file());
}

/// Runs `vkpath ARGS` in `dir`, killing it and failing the test if it runs past `limit`: a
/// render held by its live view must show as a failure, not as a hung suite.
fn vkpath_within(dir: &std::path::Path, args: &[&str], limit: Duration) -> std::process::Output {
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_vkpath"))
        .args(args)
        .current_dir(dir)
        .env_remove("RUST_LOG")
        .env("VKPATH_CACHE_DIR", common::test_cache_dir())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the vkpath binary runs");
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > limit {
            child.kill().unwrap();
            let output = child.wait_with_output().unwrap();
            panic!(
                "vkpath {args:?} still ran after {limit:?} (killed): {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

/// A render whose live view takes megabytes: 640 x 480 with an AOV layer is 7.4 MB for the
/// finished image alone, more than a loopback socket holds for a peer that reads nothing
/// (its receive window stays at its first ~128 KB, the sender's buffer at most 4 MB).
fn render_with_a_big_view(dir: &std::path::Path, address: &str) -> std::process::Output {
    // The render itself takes a few seconds at most; before issue 58's fix the command
    // never ended.
    vkpath_within(
        dir,
        &[
            "render",
            "--width",
            "640",
            "--height",
            "480",
            "--spp",
            "2",
            "--integrator",
            "workshop",
            "--aov",
            "albedo",
            "-o",
            "out.exr",
            "--tev",
            address,
            "--tev-interval",
            "0.05",
        ],
        Duration::from_secs(90),
    )
}

#[test]
fn a_live_view_that_never_reads_does_not_hold_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    // Accepts, then holds the connection open without reading until the test ends.
    let (done, wait) = std::sync::mpsc::channel::<()>();
    let server = std::thread::spawn(move || {
        let (socket, _) = listener.accept().unwrap();
        let _ = wait.recv();
        drop(socket);
    });
    let output = render_with_a_big_view(dir.path(), &address);
    done.send(()).unwrap();
    server.join().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(
        warnings[0].contains(&format!("the live view at {address}")),
        "{}",
        warnings[0]
    );
    assert!(dir.path().join("out.exr").is_file(), "{stderr}");
}

#[test]
fn a_live_view_that_closes_mid_image_costs_one_warning() {
    let dir = tempfile::tempdir().unwrap();
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    // Reads the start of the stream (CreateImage and part of the first image), then closes.
    let server = std::thread::spawn(move || {
        let (mut socket, _) = listener.accept().unwrap();
        let mut start = vec![0u8; 100_000];
        let _ = socket.read_exact(&mut start);
    });
    let output = render_with_a_big_view(dir.path(), &address);
    server.join().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(
        warnings[0].contains(&format!("the live view at {address} stopped")),
        "{}",
        warnings[0]
    );
    assert!(dir.path().join("out.exr").is_file(), "{stderr}");
}
