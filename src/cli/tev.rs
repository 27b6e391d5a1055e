//! `render --tev HOST:PORT`: a live view of the render in a running tev (the HDR viewer),
//! as pbrt-v4's `--display-server` gives one. The image so far goes to tev over its TCP
//! protocol (the `tev_client` crate: CreateImage, then UpdateImage in bands of rows) every
//! `--tev-interval` seconds, and the finished image, with its AOV layers, at the end.
//!
//! The render never waits for tev: updates are handed to a sending thread through a queue of
//! one, and an update that finds the thread still sending the last one is dropped (the next
//! one carries newer pixels anyway). A tev that cannot be reached, or that closes, costs one
//! warning line; the render and its outputs go on as without `--tev`.
//!
//! Nor does the end of the command wait for a tev that does not read (issue 58: a listener
//! that accepted and never read held the command for ever): every write to the socket gives
//! up after `WRITE_TIMEOUT`, which drops the view, and the finished image gets
//! `FINISH_TIMEOUT` in all to reach tev; after that the sending thread is left behind (it
//! ends with its next write's timeout, or with the process) and one warning says so.

use std::net::{TcpStream, ToSocketAddrs};
use std::sync::mpsc::{sync_channel, SyncSender, TrySendError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use tev_client::{PacketCreateImage, PacketUpdateImage, TevClient};

use crate::image_io::output::ImageLayer;
use crate::RenderedImage;

/// How long connecting to tev may take before the render goes on without it.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(2);
/// How long one write to tev may stall (tev reads nothing) before the view is dropped.
const WRITE_TIMEOUT: Duration = Duration::from_secs(2);
/// How long the end of the command waits for the finished image to reach tev, in all.
const FINISH_TIMEOUT: Duration = Duration::from_secs(4);
/// How often the end of the command looks whether the sending thread is done.
const FINISH_POLL: Duration = Duration::from_millis(10);
/// Most values (pixels times channels) one UpdateImage packet carries: bands of rows keep
/// each packet a few MB, whatever the image's size.
const VALUES_PER_PACKET: usize = 1 << 20;

/// An image as tev receives it: named channels, each one plane of `width * height` values,
/// rows top-down.
struct TevImage {
    width: u32,
    height: u32,
    channels: Vec<(String, Vec<f32>)>,
}

/// What the sending thread is asked to do.
enum TevMessage {
    /// Replace the pixels of the channels it names.
    Update(TevImage),
    /// Create the image anew with these channels (the finished image's AOV layers), then
    /// fill it.
    Recreate(TevImage),
}

/// Why the live view could not start: one line, for a warning.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TevError {
    /// The address did not resolve, the connection failed, or creating the image failed.
    #[error("no live view: cannot reach tev at {address}: {error}")]
    Unreachable {
        /// HOST:PORT as given.
        address: String,
        /// What the system said.
        error: std::io::Error,
    },
    /// The address resolved to no socket address.
    #[error("no live view: cannot reach tev at {address}: the address resolves to nothing")]
    NoAddress {
        /// HOST:PORT as given.
        address: String,
    },
}

/// A connection to tev showing one image, named after the render's first output.
pub struct TevView {
    address: String,
    queue: Option<SyncSender<TevMessage>>,
    sender: Option<JoinHandle<std::io::Result<()>>>,
}

impl TevView {
    /// Connects to tev at `address` (HOST:PORT) and creates the image `name`, `width` x
    /// `height`, with channels R, G and B. An error says why in one line (the caller warns
    /// and renders without the view).
    pub fn connect(
        address: &str,
        name: &str,
        width: u32,
        height: u32,
    ) -> Result<TevView, TevError> {
        let fail = |error: std::io::Error| TevError::Unreachable {
            address: address.to_string(),
            error,
        };
        let target = address
            .to_socket_addrs()
            .map_err(fail)?
            .next()
            .ok_or_else(|| TevError::NoAddress {
                address: address.to_string(),
            })?;
        let socket = TcpStream::connect_timeout(&target, CONNECT_TIMEOUT).map_err(fail)?;
        let _ = socket.set_nodelay(true);
        // A tev that stops reading must not hold a write (and so the command) for ever.
        socket
            .set_write_timeout(Some(WRITE_TIMEOUT))
            .map_err(fail)?;
        let mut client = TevClient::wrap(socket);
        create(&mut client, name, width, height, &["R", "G", "B"]).map_err(fail)?;
        let (queue, updates) = sync_channel::<TevMessage>(1);
        let name = name.to_string();
        let sender = std::thread::spawn(move || {
            for message in updates {
                let sent = match message {
                    TevMessage::Update(image) => update(&mut client, &name, &image),
                    TevMessage::Recreate(image) => {
                        let names: Vec<&str> =
                            image.channels.iter().map(|(n, _)| n.as_str()).collect();
                        create(&mut client, &name, image.width, image.height, &names)
                            .and_then(|()| update(&mut client, &name, &image))
                    }
                };
                sent?;
            }
            Ok(())
        });
        Ok(TevView {
            address: address.to_string(),
            queue: Some(queue),
            sender: Some(sender),
        })
    }

    /// Shows `image` (the render so far) unless the last update is still being sent: never
    /// waits.
    pub fn show(&self, image: &RenderedImage) {
        if let Some(queue) = &self.queue {
            match queue.try_send(TevMessage::Update(colour_of(image))) {
                Ok(()) | Err(TrySendError::Full(_)) | Err(TrySendError::Disconnected(_)) => {}
            }
        }
    }

    /// Shows the finished `image` with its `layers` (waiting until it is sent, at most
    /// `FINISH_TIMEOUT`), closes the connection, and returns a warning if tev went away
    /// during the render or did not take the image in time.
    pub fn finish(mut self, image: &RenderedImage, layers: &[ImageLayer]) -> Option<String> {
        let deadline = Instant::now() + FINISH_TIMEOUT;
        let mut final_image = colour_of(image);
        let mut message = if layers.is_empty() {
            TevMessage::Update(final_image)
        } else {
            for layer in layers {
                final_image.channels.extend(layer_channels(layer));
            }
            TevMessage::Recreate(final_image)
        };
        // The queue may still hold an update while the thread sends another: wait for room,
        // but not past the deadline.
        if let Some(queue) = self.queue.take() {
            loop {
                match queue.try_send(message) {
                    Ok(()) | Err(TrySendError::Disconnected(_)) => break,
                    Err(TrySendError::Full(back)) if Instant::now() < deadline => {
                        message = back;
                        std::thread::sleep(FINISH_POLL);
                    }
                    Err(TrySendError::Full(_)) => break,
                }
            }
        }
        let sender = self.sender.take()?;
        while !sender.is_finished() {
            if Instant::now() >= deadline {
                // Left behind: its next write gives up, or the process ends first.
                return Some(format!(
                    "the live view at {} did not take the finished image within {} s: dropped it",
                    self.address,
                    FINISH_TIMEOUT.as_secs()
                ));
            }
            std::thread::sleep(FINISH_POLL);
        }
        match sender.join() {
            Ok(Ok(())) => None,
            Ok(Err(error)) => Some(format!(
                "the live view at {} stopped: {} (the render went on)",
                self.address,
                describe(&error)
            )),
            Err(_) => Some(format!("the live view at {} failed", self.address)),
        }
    }
}

/// A failed write to tev in words: a timeout says that tev stopped reading.
fn describe(error: &std::io::Error) -> String {
    match error.kind() {
        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut => {
            format!("it read nothing for {} s", WRITE_TIMEOUT.as_secs())
        }
        _ => error.to_string(),
    }
}

/// The colour channels of `image` as tev planes.
fn colour_of(image: &RenderedImage) -> TevImage {
    let plane = |c: usize| image.mean.iter().map(|p| p[c]).collect::<Vec<f32>>();
    TevImage {
        width: image.width,
        height: image.height,
        channels: vec![
            ("R".into(), plane(0)),
            ("G".into(), plane(1)),
            ("B".into(), plane(2)),
        ],
    }
}

/// An AOV layer's channels as the EXR names them (`albedo.R`..., `depth.Z`, or with
/// `.A`).
fn layer_channels(layer: &ImageLayer) -> Vec<(String, Vec<f32>)> {
    let plane = |c: usize| layer.pixels.iter().map(|p| p[c]).collect::<Vec<f32>>();
    if layer.single_channel {
        return vec![(format!("{}.Z", layer.name), plane(0))];
    }
    let mut channels: Vec<(String, Vec<f32>)> = ["R", "G", "B"]
        .iter()
        .enumerate()
        .map(|(c, suffix)| (format!("{}.{suffix}", layer.name), plane(c)))
        .collect();
    if let Some(alpha) = &layer.alpha {
        channels.push((format!("{}.A", layer.name), alpha.clone()));
    }
    channels
}

/// Sends CreateImage.
fn create(
    client: &mut TevClient,
    name: &str,
    width: u32,
    height: u32,
    channels: &[&str],
) -> std::io::Result<()> {
    client.send(PacketCreateImage {
        image_name: name,
        grab_focus: true,
        width,
        height,
        channel_names: channels,
    })
}

/// Sends `image`'s channels as UpdateImage packets of whole rows, `VALUES_PER_PACKET` values
/// at most each (one row at least).
fn update(client: &mut TevClient, name: &str, image: &TevImage) -> std::io::Result<()> {
    let width = image.width as usize;
    let count = image.channels.len();
    if width == 0 || count == 0 {
        return Ok(());
    }
    let names: Vec<&str> = image.channels.iter().map(|(n, _)| n.as_str()).collect();
    let rows_per_packet = (VALUES_PER_PACKET / (width * count)).max(1);
    let mut first_row = 0;
    while first_row < image.height as usize {
        let rows = rows_per_packet.min(image.height as usize - first_row);
        let pixels = rows * width;
        // Planar: channel k's band at k * pixels, stride 1.
        let mut data = Vec::with_capacity(pixels * count);
        for (_, plane) in &image.channels {
            data.extend_from_slice(&plane[first_row * width..first_row * width + pixels]);
        }
        let offsets: Vec<u64> = (0..count).map(|k| (k * pixels) as u64).collect();
        let strides = vec![1u64; count];
        client.send(PacketUpdateImage {
            image_name: name,
            grab_focus: false,
            channel_names: &names,
            channel_offsets: &offsets,
            channel_strides: &strides,
            x: 0,
            y: first_row as u32,
            width: image.width,
            height: rows as u32,
            data: &data,
        })?;
        first_row += rows;
    }
    Ok(())
}
