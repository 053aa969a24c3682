//! Textures: colour in RGB, height (the bump map) in the fourth channel.
//!
//! Texels read as `f32` in 0..1 (stored at their source's precision, see
//! `texels`), **top row first** (as image files
//! are), and (u, v) index the storage directly: texture coordinate v = 0 is
//! the top of the picture, as it is for OpenGL renderers fed an image's rows
//! in file order (Mesa llvmpipe, euc) and in the documented program's files.
//! Coordinates wrap (repeat): u = 1.0 reads texel 0.

pub mod decode;
pub mod environment;
pub mod ibl;
pub mod lat_long;
pub mod normal_map_file;
pub mod picture;
pub mod sample;
pub mod specular_map;
pub mod studio;

// The modules' old paths (`texture::load`, `texture::filter`, ...) stay
// valid, so code outside `texture/` names them as before.
pub use decode::builtin::{Builtin, builtins};
pub use decode::load::{Range, TextureError, load_picture, load_texture, load_texture_with_height};
pub use sample::level::Level;
pub use sample::normal_map::NormalMap;
pub use sample::texture::Texture;
