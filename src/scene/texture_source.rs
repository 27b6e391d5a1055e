//! Why a material's texture cannot be used: where its bytes should come from (a buffer
//! view, a data URI, a file beside the scene) or their decoding. The loaders turn it into a
//! warning, and the material uses its factor instead.

use super::textures::TextureError;
use super::SceneError;

/// A texture that is ignored, and why, in words that follow "is ignored (…): ".
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TextureSourceError {
    /// The image's buffer view names a buffer the file lacks.
    #[error("its buffer view's buffer is missing")]
    MissingBuffer,
    /// The image's buffer view reaches past its buffer's end.
    #[error("its buffer view lies outside its buffer")]
    ViewOutsideBuffer,
    /// A `data:` URI that is not base64.
    #[error("its data URI is not base64")]
    NotBase64,
    /// A base64 `data:` URI whose data does not decode.
    #[error("bad base64 data: {0}")]
    BadBase64(base64::DecodeError),
    /// A URI with a scheme other than `file:` (a web address).
    #[error("it is at '{uri}'; vkpath reads local files only")]
    Remote {
        /// The URI, printable.
        uri: String,
    },
    /// A URI whose percent-decoding is not UTF-8.
    #[error("its URI is not valid UTF-8")]
    UriNotUtf8,
    /// An OBJ texture outside the OBJ file's folder.
    #[error("it lies outside the OBJ file's folder, where vkpath does not read")]
    OutsideObjFolder,
    /// The file could not be read.
    #[error("cannot read '{file}': {error}")]
    Unreadable {
        /// The file, printable.
        file: String,
        /// What the system said.
        error: std::io::Error,
    },
    /// The file is not a regular file.
    #[error("'{file}' is not a regular file")]
    NotAFile {
        /// The file, printable.
        file: String,
    },
    /// The reference was refused as a scene's references are (outside the folder, ...).
    #[error("{0}")]
    Reference(SceneError),
    /// The bytes do not decode as a texture vkpath reads.
    #[error("{0}")]
    Decode(TextureError),
    /// The texture names no image of the file (neither its `source` nor a WebP
    /// extension's).
    #[error("it names no image of the file")]
    NoImage,
    /// What went wrong with the texture's image, naming it.
    #[error("image '{image}': {reason}")]
    Image {
        /// The image's name, or `#index`.
        image: String,
        /// What is wrong with it.
        reason: Box<TextureSourceError>,
    },
}
