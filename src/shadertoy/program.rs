//! A ShaderToy program as files: the Common tab, Buffers A–D and the Image pass, and what
//! each pass's `iChannel0`–`3` read (ShaderToy's defaults, overridden with `--channel`).

use std::path::{Path, PathBuf};

/// The usage of `--channel`, which its syntax errors end with.
const CHANNEL_USAGE: &str = "expected PASS.N=SOURCE, e.g. image.1=buffer-b (PASS: buffer-a..buffer-d or image, N: 0..3, SOURCE: buffer-a..buffer-d or an image file)";

/// What is wrong with a ShaderToy program's files or channels: one line, naming the file
/// (and line) or the `--channel` argument.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ProgramError {
    /// A `--channel` argument that is not `PASS.N=SOURCE`.
    #[error("'{text}': {CHANNEL_USAGE}")]
    ChannelSyntax {
        /// The argument as given.
        text: String,
    },
    /// A `--channel` argument whose PASS names no pass.
    #[error("'{text}': '{pass}' is not a pass; {CHANNEL_USAGE}")]
    NotAPass {
        /// The argument as given.
        text: String,
        /// Its PASS part.
        pass: String,
    },
    /// A `--channel` argument whose N is not 0..3.
    #[error("'{text}': channel '{channel}' is not 0..3")]
    NotAChannel {
        /// The argument as given.
        text: String,
        /// Its N part.
        channel: String,
    },
    /// A `--channel` argument whose SOURCE is the Image pass.
    #[error("'{text}': the Image pass cannot be read by a channel (as in ShaderToy)")]
    ImageAsSource {
        /// The argument as given.
        text: String,
    },
    /// A tab's file could not be read.
    #[error("cannot read '{}': {error}", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// What the system said.
        error: std::io::Error,
    },
    /// The same buffer was given two files.
    #[error("{} is given twice", kind.name())]
    GivenTwice {
        /// The buffer.
        kind: PassKind,
    },
    /// The Image tab's `#iChannelN "self"` directive.
    #[error(
        "{}:{line}: #iChannel{channel} \"self\": the Image pass cannot read itself (as in ShaderToy)",
        path.display()
    )]
    ImageReadsItself {
        /// The Image tab's file.
        path: PathBuf,
        /// The directive's line (from 1).
        line: usize,
        /// Its channel.
        channel: usize,
    },
    /// A channel directive that names a `.glsl` file that is none of the buffers given.
    #[error(
        "{}:{line}: #iChannel{channel} reads {target}, which is not one of the buffers given (give it as a buffer tab)",
        path.display()
    )]
    NotABufferTab {
        /// The tab's file.
        path: PathBuf,
        /// The directive's line (from 1).
        line: usize,
        /// Its channel.
        channel: usize,
        /// The file it names.
        target: String,
    },
    /// A binding that reads a buffer the program lacks.
    #[error(
        "--channel {}.{channel}={}: the program has no {} (give it with --{})",
        pass.name(),
        reads.name(),
        reads.name(),
        reads.name()
    )]
    MissingSource {
        /// The pass whose channel it sets.
        pass: PassKind,
        /// The channel.
        channel: usize,
        /// The buffer it reads.
        reads: PassKind,
    },
    /// A binding that sets a channel of a pass the program lacks.
    #[error(
        "--channel {}.{channel}: the program has no {} pass",
        pass.name(),
        pass.name()
    )]
    MissingPass {
        /// The pass.
        pass: PassKind,
        /// The channel.
        channel: usize,
    },
}

/// A pass of a ShaderToy program, in the order ShaderToy runs them each frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PassKind {
    /// Buffer A.
    BufferA,
    /// Buffer B.
    BufferB,
    /// Buffer C.
    BufferC,
    /// Buffer D.
    BufferD,
    /// The Image pass (what ShaderToy displays).
    Image,
}

impl PassKind {
    /// The four buffers, in ShaderToy's order.
    pub const BUFFERS: [PassKind; 4] = [
        PassKind::BufferA,
        PassKind::BufferB,
        PassKind::BufferC,
        PassKind::BufferD,
    ];

    /// The pass's name on the command line (`buffer-a` … `buffer-d`, `image`).
    pub fn name(self) -> &'static str {
        match self {
            PassKind::BufferA => "buffer-a",
            PassKind::BufferB => "buffer-b",
            PassKind::BufferC => "buffer-c",
            PassKind::BufferD => "buffer-d",
            PassKind::Image => "image",
        }
    }

    /// The pass of a command-line name (also `a` … `d` for the buffers).
    pub fn from_name(name: &str) -> Option<PassKind> {
        match name.to_ascii_lowercase().as_str() {
            "buffer-a" | "a" => Some(PassKind::BufferA),
            "buffer-b" | "b" => Some(PassKind::BufferB),
            "buffer-c" | "c" => Some(PassKind::BufferC),
            "buffer-d" | "d" => Some(PassKind::BufferD),
            "image" => Some(PassKind::Image),
            _ => None,
        }
    }

    /// The buffer's index 0..4 (`None` for the Image pass).
    pub fn buffer_index(self) -> Option<usize> {
        PassKind::BUFFERS.iter().position(|&b| b == self)
    }
}

/// What a channel reads.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ChannelSource {
    /// A buffer's contents: this frame's if the buffer runs before the reading pass, else
    /// the previous frame's (zero before the first frame).
    Buffer(PassKind),
    /// An image file (PNG or JPEG as 8-bit values / 255, EXR as its floats), flipped so that
    /// texture coordinate (0, 0) is its bottom-left corner, as ShaderToy loads textures.
    File(PathBuf),
}

/// One pass: its kind, its file and what its four channels read (`None`: black).
#[derive(Clone, Debug, PartialEq)]
pub struct Pass {
    /// Which pass.
    pub kind: PassKind,
    /// The user's file, for messages.
    pub path: PathBuf,
    /// Its text (byte-order mark removed, line ends `\n`).
    pub text: String,
    /// `iChannel0`–`3`.
    pub channels: [Option<ChannelSource>; 4],
}

/// A whole program: the Common tab (prepended to every pass) and the passes, buffers first,
/// in ShaderToy's order, the Image pass last.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    /// The Common tab: (file, text).
    pub common: Option<(PathBuf, String)>,
    /// The passes in the order they run each frame.
    pub passes: Vec<Pass>,
}

/// A `--channel PASS.N=SOURCE` override.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ChannelBinding {
    /// The pass whose channel it sets.
    pub pass: PassKind,
    /// The channel, 0..4.
    pub channel: usize,
    /// What it reads.
    pub source: ChannelSource,
}

impl std::str::FromStr for ChannelBinding {
    type Err = ProgramError;

    /// Parses `image.1=buffer-b`, `buffer-a.2=buffer-a` or `image.3=noise.png`.
    fn from_str(text: &str) -> Result<ChannelBinding, ProgramError> {
        let syntax = || ProgramError::ChannelSyntax { text: text.into() };
        let (target, source) = text.split_once('=').ok_or_else(syntax)?;
        let (pass, channel) = target.rsplit_once('.').ok_or_else(syntax)?;
        let pass = PassKind::from_name(pass).ok_or_else(|| ProgramError::NotAPass {
            text: text.into(),
            pass: pass.into(),
        })?;
        let channel: usize =
            channel
                .parse()
                .ok()
                .filter(|c| *c < 4)
                .ok_or_else(|| ProgramError::NotAChannel {
                    text: text.into(),
                    channel: channel.into(),
                })?;
        let source = match PassKind::from_name(source) {
            Some(PassKind::Image) => return Err(ProgramError::ImageAsSource { text: text.into() }),
            Some(buffer) => ChannelSource::Buffer(buffer),
            None if source.is_empty() => return Err(syntax()),
            None => ChannelSource::File(PathBuf::from(source)),
        };
        Ok(ChannelBinding {
            pass,
            channel,
            source,
        })
    }
}

/// The VS Code Shader Toy extension's channel directives of a tab, `#iChannelN "TARGET"`:
/// (line from 1, N, TARGET) each.
pub fn channel_directives(text: &str) -> Vec<(usize, usize, String)> {
    text.lines()
        .enumerate()
        .filter_map(|(index, line)| {
            let rest = line.trim_start().strip_prefix('#')?.trim_start();
            let rest = rest.strip_prefix("iChannel")?;
            let channel = rest.get(..1)?.parse::<usize>().ok().filter(|c| *c < 4)?;
            let target = rest[1..].trim().trim_matches('"').to_string();
            Some((index + 1, channel, target))
        })
        .collect()
}

/// Reads a user's file as text: a byte-order mark dropped, Windows line ends made `\n`.
pub fn read_source(path: &Path) -> Result<String, ProgramError> {
    let bytes = std::fs::read(path).map_err(|error| ProgramError::Unreadable {
        path: path.to_path_buf(),
        error,
    })?;
    Ok(String::from_utf8_lossy(&bytes)
        .trim_start_matches('\u{feff}')
        .replace("\r\n", "\n"))
}

impl Program {
    /// A program from its files (`buffers` in any order, at most one per buffer) and the
    /// `--channel` overrides. Default channels, as ShaderToy's templates have them: a
    /// buffer's `iChannel0` is its own previous frame, the Image pass's `iChannel0` is
    /// Buffer A (when there is one); all others are black until `channels` sets them. A
    /// channel that names a buffer the program lacks, or a pass the program lacks, is an
    /// error.
    pub fn from_files(
        image: &Path,
        common: Option<&Path>,
        buffers: &[(PassKind, PathBuf)],
        channels: &[ChannelBinding],
    ) -> Result<Program, ProgramError> {
        let common = match common {
            Some(path) => Some((path.to_path_buf(), read_source(path)?)),
            None => None,
        };
        let mut passes = Vec::new();
        for kind in PassKind::BUFFERS {
            let mut files = buffers.iter().filter(|(k, _)| *k == kind);
            if let Some((_, path)) = files.next() {
                if files.next().is_some() {
                    return Err(ProgramError::GivenTwice { kind });
                }
                let mut defaults: [Option<ChannelSource>; 4] = Default::default();
                defaults[0] = Some(ChannelSource::Buffer(kind));
                passes.push(Pass {
                    kind,
                    path: path.clone(),
                    text: read_source(path)?,
                    channels: defaults,
                });
            }
        }
        let mut image_channels: [Option<ChannelSource>; 4] = Default::default();
        if passes.iter().any(|p| p.kind == PassKind::BufferA) {
            image_channels[0] = Some(ChannelSource::Buffer(PassKind::BufferA));
        }
        passes.push(Pass {
            kind: PassKind::Image,
            path: image.to_path_buf(),
            text: read_source(image)?,
            channels: image_channels,
        });
        let mut program = Program { common, passes };
        program.wire_channel_directives()?;
        for binding in channels {
            program.bind(binding)?;
        }
        Ok(program)
    }

    /// Wires the channels that the VS Code Shader Toy extension's directives name in each
    /// pass (`#iChannel0 "self"`, `#iChannel1 "file://bufferA.glsl"`, `#iChannel2
    /// "file://noise.png"` or a plain texture path): `self` is the pass's own previous frame,
    /// a `.glsl` file is the pass given with that file name, anything else an image file
    /// beside the tab. The intake drops the directive lines themselves. An error names a tab
    /// that the program was not given.
    pub fn wire_channel_directives(&mut self) -> Result<(), ProgramError> {
        let mut bindings = Vec::new();
        for pass in &self.passes {
            for (line, channel, target) in channel_directives(&pass.text) {
                let target = target.strip_prefix("file://").unwrap_or(&target);
                let source = if target == "self" {
                    if pass.kind == PassKind::Image {
                        return Err(ProgramError::ImageReadsItself {
                            path: pass.path.clone(),
                            line,
                            channel,
                        });
                    }
                    ChannelSource::Buffer(pass.kind)
                } else if target.ends_with(".glsl") {
                    let wanted = Path::new(target).file_name();
                    let reader = self
                        .passes
                        .iter()
                        .find(|p| p.kind != PassKind::Image && p.path.file_name() == wanted);
                    match reader {
                        Some(buffer) => ChannelSource::Buffer(buffer.kind),
                        None => {
                            return Err(ProgramError::NotABufferTab {
                                path: pass.path.clone(),
                                line,
                                channel,
                                target: target.to_string(),
                            })
                        }
                    }
                } else {
                    let folder = pass.path.parent().unwrap_or(Path::new(""));
                    ChannelSource::File(folder.join(target))
                };
                bindings.push(ChannelBinding {
                    pass: pass.kind,
                    channel,
                    source,
                });
            }
        }
        for binding in &bindings {
            self.bind(binding)?;
        }
        Ok(())
    }

    /// Applies one `--channel` override.
    pub fn bind(&mut self, binding: &ChannelBinding) -> Result<(), ProgramError> {
        if let ChannelSource::Buffer(source) = binding.source {
            if !self.passes.iter().any(|p| p.kind == source) {
                return Err(ProgramError::MissingSource {
                    pass: binding.pass,
                    channel: binding.channel,
                    reads: source,
                });
            }
        }
        let pass = self
            .passes
            .iter_mut()
            .find(|p| p.kind == binding.pass)
            .ok_or(ProgramError::MissingPass {
                pass: binding.pass,
                channel: binding.channel,
            })?;
        pass.channels[binding.channel] = Some(binding.source.clone());
        Ok(())
    }

    /// The pass of `kind`, if the program has it.
    pub fn pass(&self, kind: PassKind) -> Option<&Pass> {
        self.passes.iter().find(|p| p.kind == kind)
    }
}

/// Whether a pass reading `source` sees the frame before the current one: ShaderToy runs
/// A, B, C, D, Image each frame, so a pass sees this frame's result of a buffer that runs
/// before it, and the previous frame's of itself and of later buffers.
pub fn reads_previous_frame(reader: PassKind, source: PassKind) -> bool {
    source >= reader
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_directives_are_read_with_their_line() {
        let text = "// tab\n#iChannel0 \"self\"\n  # iChannel3 \"file://textures/noise.png\"\n#iChannel7 \"x\"\n";
        assert_eq!(
            channel_directives(text),
            [
                (2, 0, "self".to_string()),
                (3, 3, "file://textures/noise.png".to_string())
            ]
        );
    }

    #[test]
    fn channel_overrides_parse() {
        let binding: ChannelBinding = "image.1=buffer-b".parse().unwrap();
        assert_eq!(
            binding,
            ChannelBinding {
                pass: PassKind::Image,
                channel: 1,
                source: ChannelSource::Buffer(PassKind::BufferB)
            }
        );
        let binding: ChannelBinding = "buffer-a.3=noise.png".parse().unwrap();
        assert_eq!(binding.source, ChannelSource::File("noise.png".into()));
        for bad in [
            "image.4=buffer-a",
            "image=buffer-a",
            "sound.0=buffer-a",
            "image.0=image",
            "image.0=",
        ] {
            assert!(bad.parse::<ChannelBinding>().is_err(), "{bad}");
        }
    }

    #[test]
    fn earlier_buffers_are_this_frames_later_ones_the_previous() {
        assert!(!reads_previous_frame(PassKind::Image, PassKind::BufferA));
        assert!(!reads_previous_frame(PassKind::BufferB, PassKind::BufferA));
        assert!(reads_previous_frame(PassKind::BufferA, PassKind::BufferA));
        assert!(reads_previous_frame(PassKind::BufferA, PassKind::BufferB));
    }
}
