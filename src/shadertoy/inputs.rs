//! ShaderToy's inputs as the pass kernel (`src/shadertoy/pass.comp`) receives them: what
//! stays the same through a run in a uniform buffer, what changes per frame in push
//! constants. Time advances in fixed steps of 1/60 s from 0, so a run is deterministic.

use bytemuck::{Pod, Zeroable};

/// Frames per second of the fixed time step.
pub const FRAME_RATE: f32 = 60.0;
/// `iDate`: 1 January 2024, midnight (year, month from 0, day, seconds), fixed.
pub const DATE: [f32; 4] = [2024.0, 0.0, 1.0, 0.0];
/// `iSampleRate`, as ShaderToy's.
pub const SAMPLE_RATE: f32 = 44100.0;

/// The uniform block `vkpath_pass_constants` (std140), one per pass.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct PassConstants {
    /// `iResolution`: width, height, 1.
    pub resolution: [f32; 3],
    /// `iFrameRate`.
    pub frame_rate: f32,
    /// `iMouse`: zero.
    pub mouse: [f32; 4],
    /// `iDate`.
    pub date: [f32; 4],
    /// `iChannelResolution[4]`: each channel's width, height, 1 (the fourth component is
    /// std140's padding of a `vec3` array element).
    pub channel_resolution: [[f32; 4]; 4],
    /// `iSampleRate`.
    pub sample_rate: f32,
    /// std140 pads the block to a multiple of 16 bytes.
    pub padding: [f32; 3],
}

impl PassConstants {
    /// The constants of a pass over `width` x `height` pixels whose channels are
    /// `channel_sizes` texels (width, height) large.
    pub fn new(width: u32, height: u32, channel_sizes: [(u32, u32); 4]) -> PassConstants {
        PassConstants {
            resolution: [width as f32, height as f32, 1.0],
            frame_rate: FRAME_RATE,
            mouse: [0.0; 4],
            date: DATE,
            channel_resolution: channel_sizes.map(|(w, h)| [w as f32, h as f32, 1.0, 0.0]),
            sample_rate: SAMPLE_RATE,
            padding: [0.0; 3],
        }
    }
}

/// The push constants `vkpath_frame_constants` (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct FramePushConstants {
    /// `iTime`: `iFrame / 60` seconds.
    pub time: f32,
    /// `iTimeDelta`: 1/60 s.
    pub time_delta: f32,
    /// `iFrame`, from 0.
    pub frame: i32,
    /// `iChannelTime[4]`: `iTime` for each channel.
    pub channel_time: [f32; 4],
}

impl FramePushConstants {
    /// The inputs of frame `frame` (from 0).
    pub fn for_frame(frame: u32) -> FramePushConstants {
        let time = frame as f32 / FRAME_RATE;
        FramePushConstants {
            time,
            time_delta: 1.0 / FRAME_RATE,
            frame: i32::try_from(frame).unwrap_or(i32::MAX),
            channel_time: [time; 4],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn layouts_match_the_kernel() {
        // std140 offsets of vkpath_pass_constants in pass.comp.
        assert_eq!(offset_of!(PassConstants, resolution), 0);
        assert_eq!(offset_of!(PassConstants, frame_rate), 12);
        assert_eq!(offset_of!(PassConstants, mouse), 16);
        assert_eq!(offset_of!(PassConstants, date), 32);
        assert_eq!(offset_of!(PassConstants, channel_resolution), 48);
        assert_eq!(offset_of!(PassConstants, sample_rate), 112);
        assert_eq!(size_of::<PassConstants>(), 128);
        // std430 offsets of vkpath_frame_constants.
        assert_eq!(offset_of!(FramePushConstants, time), 0);
        assert_eq!(offset_of!(FramePushConstants, time_delta), 4);
        assert_eq!(offset_of!(FramePushConstants, frame), 8);
        assert_eq!(offset_of!(FramePushConstants, channel_time), 12);
        assert_eq!(size_of::<FramePushConstants>(), 28);
    }

    #[test]
    fn time_advances_in_fixed_steps() {
        let frame = FramePushConstants::for_frame(90);
        assert_eq!(frame.frame, 90);
        assert_eq!(frame.time, 1.5);
        assert_eq!(frame.time_delta, 1.0 / 60.0);
    }
}
