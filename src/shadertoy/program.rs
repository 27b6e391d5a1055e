//! A ShaderToy program as files: the Common tab, Buffers A–D and the Image pass, and what
//! each pass's `iChannel0`–`3` read (ShaderToy's defaults, overridden with `--channel`).

use std::path::{Path, PathBuf};

pub use crate::shadertoy::directives::{channel_directives, channel_settings};
use crate::shadertoy::directives::{is_cube_map, is_self, vertex_shader_line, AUDIO_EXTENSIONS};

/// The usage of `--channel`, which its syntax errors end with.
const CHANNEL_USAGE: &str = "expected PASS.N=SOURCE, e.g. image.1=buffer-b (PASS: buffer-a..buffer-d or image, N: 0..3, SOURCE: buffer-a..buffer-d, an image file, or cube:FILE for a cube map: six images sky_{}.png or an equirectangular .exr/.hdr)";

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
    /// The Image tab's `#iChannelN "self"` directive, where it cannot run as a hidden buffer
    /// (`wire_channel_directives` alone, or Buffer D already given).
    #[error(
        "{}:{line}: #iChannel{channel} \"self\": the Image pass cannot read itself ({reason})",
        path.display()
    )]
    ImageReadsItself {
        /// The Image tab's file.
        path: PathBuf,
        /// The directive's line (from 1).
        line: usize,
        /// Its channel.
        channel: usize,
        /// Why it cannot run as a hidden buffer.
        reason: &'static str,
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
    /// A channel directive that vkpath cannot supply (a URL, audio, a cube map without its
    /// file).
    #[error("{}:{line}: #iChannel{channel}{what}", path.display())]
    UnsupportedChannel {
        /// The tab's file.
        path: PathBuf,
        /// The directive's line (from 1).
        line: usize,
        /// Its channel.
        channel: usize,
        /// What it asks and why it cannot be, in words (from the text after `#iChannelN`).
        what: String,
    },
    /// The extension's `#iVertex` (a vertex shader whose outputs the fragment shader reads).
    #[error(
        "{}:{line}: #iVertex: vkpath runs no vertex shaders (each pass is one full-screen compute dispatch), so what it outputs cannot be supplied",
        path.display()
    )]
    VertexShader {
        /// The tab's file.
        path: PathBuf,
        /// The directive's line (from 1).
        line: usize,
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
    /// A cube map (`samplerCube`): six images named by a pattern with `{}`, or an
    /// equirectangular `.exr`/`.hdr` map (`crate::shadertoy::textures`).
    Cube(PathBuf),
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

    /// Parses `image.1=buffer-b`, `buffer-a.2=buffer-a`, `image.3=noise.png` or
    /// `image.1=cube:sky_{}.png`.
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
            None => match source.strip_prefix("cube:") {
                Some("") => return Err(syntax()),
                Some(cube) => ChannelSource::Cube(PathBuf::from(cube)),
                None => ChannelSource::File(PathBuf::from(source)),
            },
        };
        Ok(ChannelBinding {
            pass,
            channel,
            source,
        })
    }
}

/// The Image tab of vkpath's that shows a hidden buffer (`Program::hidden_buffer`): the
/// buffer's texels as they are, alpha included.
const SHOW_HIDDEN_BUFFER: &str =
    "// vkpath's Image pass: shows the hidden buffer that your Image tab runs as.\n\
void mainImage(out vec4 fragColor, in vec2 fragCoord) {\n\
    fragColor = texelFetch(iChannel0, ivec2(fragCoord), 0);\n\
}\n";

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
    /// error. An Image tab with `#iChannelN "self"` (VS Code Shader Toy's single-file
    /// feedback) runs as a hidden buffer after the buffers given, with the Image tab's
    /// default channels and its `--channel image.N` overrides, and an Image pass of vkpath's
    /// shows it (`hidden_buffer`); with Buffer D given there is no room, which is an error.
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
        let text = read_source(image)?;
        // The VS Code Shader Toy extension's single-file feedback: an Image tab that reads
        // itself runs as a hidden buffer after the others, and vkpath's Image pass shows it.
        let hidden = match channel_directives(&text)
            .into_iter()
            .find(|(_, _, target)| is_self(target))
        {
            None => None,
            Some((line, channel, _)) => {
                let after_last = passes
                    .iter()
                    .filter_map(|p| p.kind.buffer_index())
                    .max()
                    .map_or(0, |last| last + 1);
                Some(*PassKind::BUFFERS.get(after_last).ok_or_else(|| {
                    ProgramError::ImageReadsItself {
                        path: image.to_path_buf(),
                        line,
                        channel,
                        reason: "it would run as a hidden buffer after Buffer D, and a program has four",
                    }
                })?)
            }
        };
        passes.push(Pass {
            kind: hidden.unwrap_or(PassKind::Image),
            path: image.to_path_buf(),
            text,
            channels: image_channels,
        });
        if let Some(buffer) = hidden {
            let mut channels: [Option<ChannelSource>; 4] = Default::default();
            channels[0] = Some(ChannelSource::Buffer(buffer));
            passes.push(Pass {
                kind: PassKind::Image,
                path: PathBuf::from(format!("(vkpath's Image pass showing {})", buffer.name())),
                text: SHOW_HIDDEN_BUFFER.to_string(),
                channels,
            });
        }
        let mut program = Program { common, passes };
        program.wire_channel_directives()?;
        for binding in channels {
            // `image.N` is the user's Image tab, wherever it runs.
            let mut binding = binding.clone();
            if let Some(buffer) = hidden.filter(|_| binding.pass == PassKind::Image) {
                binding.pass = buffer;
            }
            program.bind(&binding)?;
        }
        Ok(program)
    }

    /// The hidden buffer that the user's Image tab runs as when it reads itself (VS Code
    /// Shader Toy's `#iChannel0 "self"` in the file previewed), shown by vkpath's Image pass;
    /// `None` for other programs.
    pub fn hidden_buffer(&self) -> Option<&Pass> {
        let image = self.pass(PassKind::Image)?;
        if image.text != SHOW_HIDDEN_BUFFER {
            return None;
        }
        match &image.channels[0] {
            Some(ChannelSource::Buffer(buffer)) => self.pass(*buffer),
            _ => None,
        }
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
            if let Some(line) = vertex_shader_line(&pass.text) {
                return Err(ProgramError::VertexShader {
                    path: pass.path.clone(),
                    line,
                });
            }
            for (line, channel, target) in channel_directives(&pass.text) {
                let target = target.strip_prefix("file://").unwrap_or(&target);
                let source = if is_self(target) {
                    if pass.kind == PassKind::Image {
                        return Err(ProgramError::ImageReadsItself {
                            path: pass.path.clone(),
                            line,
                            channel,
                            reason: "as in ShaderToy",
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
                } else if target.contains("://") {
                    return Err(ProgramError::UnsupportedChannel {
                        path: pass.path.clone(),
                        line,
                        channel,
                        what: format!(
                            " reads '{target}': vkpath reads no URLs; download it and name the file (\"file://name.png\")"
                        ),
                    });
                } else if AUDIO_EXTENSIONS.iter().any(|e| {
                    Path::new(target)
                        .extension()
                        .is_some_and(|x| x.eq_ignore_ascii_case(e))
                }) {
                    return Err(ProgramError::UnsupportedChannel {
                        path: pass.path.clone(),
                        line,
                        channel,
                        what: format!(
                            " reads the audio file '{target}': vkpath runs no audio input"
                        ),
                    });
                } else {
                    let folder = pass.path.parent().unwrap_or(Path::new(""));
                    let file = folder.join(target);
                    if is_cube_map(&pass.text, channel) {
                        ChannelSource::Cube(file)
                    } else {
                        ChannelSource::File(file)
                    }
                };
                bindings.push(ChannelBinding {
                    pass: pass.kind,
                    channel,
                    source,
                });
            }
        }
        for pass in &self.passes {
            for (line, channel, key, value) in channel_settings(&pass.text) {
                let cube = key == "Type" && value.eq_ignore_ascii_case("CubeMap");
                let wired = bindings
                    .iter()
                    .find(|b| b.pass == pass.kind && b.channel == channel);
                if cube && !wired.is_some_and(|b| matches!(b.source, ChannelSource::Cube(_))) {
                    return Err(ProgramError::UnsupportedChannel {
                        path: pass.path.clone(),
                        line,
                        channel,
                        what: format!(
                            "::Type \"CubeMap\" needs an #iChannel{channel} \"file://…\" line in the same file naming six images with {{}} (sky_{{}}.png) or an equirectangular .exr/.hdr map"
                        ),
                    });
                }
            }
        }
        for binding in &bindings {
            self.bind(binding)?;
        }
        Ok(())
    }

    /// One note per channel setting of the extension's that vkpath does not apply
    /// (`#iChannelN::MinFilter`, `::MagFilter`, `::WrapMode`: every channel is sampled with
    /// linear filtering and clamp to edge), naming the file and line.
    pub fn setting_notes(&self) -> Vec<String> {
        self.passes
            .iter()
            .flat_map(|pass| {
                channel_settings(&pass.text)
                    .into_iter()
                    .filter(|(_, _, key, _)| key != "Type")
                    .map(|(line, channel, key, value)| {
                        format!(
                            "{}:{line}: #iChannel{channel}::{key} \"{value}\" is not applied: vkpath samples every channel with linear filtering and clamp to edge",
                            pass.path.display()
                        )
                    })
            })
            .collect()
    }

    /// The note that says the user's Image tab runs as a hidden buffer
    /// (`hidden_buffer`), naming the file and the directive's channel.
    pub fn hidden_buffer_note(&self) -> Option<String> {
        let pass = self.hidden_buffer()?;
        let channel = channel_directives(&pass.text)
            .into_iter()
            .find(|(_, _, target)| is_self(target))
            .map_or(0, |(_, channel, _)| channel);
        Some(format!(
            "{}: reads itself (#iChannel{channel} \"self\"): it runs as a hidden {}, which vkpath's Image pass shows, as VS Code Shader Toy runs it",
            pass.path.display(),
            pass.kind.name()
        ))
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

    fn program_of(text: &str, buffers: usize) -> Result<Program, ProgramError> {
        let dir = tempfile::tempdir().unwrap();
        let image = dir.path().join("image.glsl");
        std::fs::write(&image, text).unwrap();
        let buffers: Vec<(PassKind, PathBuf)> = PassKind::BUFFERS[..buffers]
            .iter()
            .map(|kind| {
                let path = dir.path().join(format!("{}.glsl", kind.name()));
                std::fs::write(
                    &path,
                    "void mainImage(out vec4 c, in vec2 p) { c = vec4(1.0); }\n",
                )
                .unwrap();
                (*kind, path)
            })
            .collect();
        Program::from_files(&image, None, &buffers, &[])
    }

    #[test]
    fn an_image_tab_that_reads_itself_runs_as_the_buffer_after_the_others() {
        let text = "#iChannel0 \"file://self\"\nvoid main() { gl_FragColor = texture(iChannel0, vec2(0.5)); }\n";
        let program = program_of(text, 0).unwrap();
        let kinds: Vec<PassKind> = program.passes.iter().map(|p| p.kind).collect();
        assert_eq!(kinds, [PassKind::BufferA, PassKind::Image]);
        let hidden = program.hidden_buffer().expect("a hidden buffer");
        assert_eq!(hidden.text, text);
        assert_eq!(
            hidden.channels[0],
            Some(ChannelSource::Buffer(PassKind::BufferA))
        );
        let note = program.hidden_buffer_note().unwrap_or_default();
        assert!(
            note.ends_with("image.glsl: reads itself (#iChannel0 \"self\"): it runs as a hidden buffer-a, which vkpath's Image pass shows, as VS Code Shader Toy runs it"),
            "{note}"
        );
        // After two buffers it is Buffer C; with all four there is no room.
        let program = program_of(text, 2).unwrap();
        assert_eq!(
            program.hidden_buffer().map(|p| p.kind),
            Some(PassKind::BufferC)
        );
        let message = program_of(text, 4).expect_err("an error").to_string();
        assert!(message.contains("image.glsl:1: #iChannel0 \"self\": the Image pass cannot read itself (it would run"), "{message}");
        assert!(program_of(
            "void mainImage(out vec4 c, in vec2 p) { c = vec4(0.0); }\n",
            1
        )
        .unwrap()
        .hidden_buffer()
        .is_none());
    }

    #[test]
    fn channels_vkpath_cannot_supply_are_one_line_each() {
        for (text, expected) in [
            (
                "#iChannel2 \"https://example.com/duck.png\"\n",
                "image.glsl:1: #iChannel2 reads 'https://example.com/duck.png': vkpath reads no URLs",
            ),
            (
                "\n#iChannel3 \"file://music/epic.mp3\"\n",
                "image.glsl:2: #iChannel3 reads the audio file 'music/epic.mp3': vkpath runs no audio input",
            ),
            (
                "\n\n#iVertex \"file://vertex.glsl\"\n",
                "image.glsl:3: #iVertex: vkpath runs no vertex shaders",
            ),
            (
                "#iChannel1::Type \"CubeMap\"\n",
                "image.glsl:1: #iChannel1::Type \"CubeMap\" needs an #iChannel1 \"file://…\" line",
            ),
        ] {
            let message = program_of(text, 0).expect_err("an error").to_string();
            assert!(message.contains(expected), "{message}");
            assert_eq!(message.lines().count(), 1, "{message}");
        }
        let text = "#iChannel1 \"file://sky_{}.png\"\n#iChannel1::Type \"CubeMap\"\n#iChannel1::WrapMode \"Repeat\"\n";
        let program = program_of(text, 0).unwrap();
        let image = program.pass(PassKind::Image).unwrap();
        assert!(
            matches!(&image.channels[1], Some(ChannelSource::Cube(p)) if p.ends_with("sky_{}.png"))
        );
        let notes = program.setting_notes();
        assert_eq!(notes.len(), 1);
        assert!(notes[0].ends_with("image.glsl:3: #iChannel1::WrapMode \"Repeat\" is not applied: vkpath samples every channel with linear filtering and clamp to edge"), "{notes:?}");
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
        let binding: ChannelBinding = "image.1=cube:sky_{}.png".parse().unwrap();
        assert_eq!(binding.source, ChannelSource::Cube("sky_{}.png".into()));
        for bad in [
            "image.4=buffer-a",
            "image=buffer-a",
            "sound.0=buffer-a",
            "image.0=image",
            "image.0=",
            "image.0=cube:",
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
