//! SHA-256 digests of lists of parts, each part prefixed by its length in bytes, so that no
//! two lists of parts give the same stream: what a sequence of renders compares to keep a
//! part of a scene's upload (`crate::render::gpu_scene::UploadDigest`, and the lights'
//! own, `crate::lights::LightsDigest`).

use sha2::{Digest, Sha256};

/// Items hashed at once: their words go to the hasher in one slice, without a copy of the
/// whole scene's words.
const CHUNK: usize = 4096;

/// A SHA-256 hasher of parts.
pub(crate) struct Parts(Sha256);

impl Parts {
    /// A hasher with nothing hashed yet.
    pub(crate) fn new() -> Parts {
        Parts(Sha256::new())
    }

    /// Hashes one part: `bytes`.
    pub(crate) fn part(&mut self, bytes: &[u8]) {
        self.0.update((bytes.len() as u64).to_le_bytes());
        self.0.update(bytes);
    }

    /// Hashes one part: the words `words` makes of each of `items`, in their order (chunk by
    /// chunk).
    pub(crate) fn words_of<T, W: bytemuck::Pod>(&mut self, items: &[T], words: impl Fn(&T) -> W) {
        let bytes = items.len() as u64 * std::mem::size_of::<W>() as u64;
        self.0.update(bytes.to_le_bytes());
        let mut chunk = Vec::with_capacity(CHUNK.min(items.len()));
        for items in items.chunks(CHUNK) {
            chunk.clear();
            chunk.extend(items.iter().map(&words));
            self.0.update(bytemuck::cast_slice(&chunk));
        }
    }

    /// The digest of what was hashed.
    pub(crate) fn finish(self) -> [u8; 32] {
        self.0.finalize().into()
    }
}
