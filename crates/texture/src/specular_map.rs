//! The specular map: a grey picture whose value scales the highlight
//! (docs/specular.md). A separate file, as the lecture's second texture
//! unit is, since the colour texture's four channels are already taken
//! (RGB the albedo, alpha the height map).

use std::path::Path;

use super::{Level, Texture, TextureError, load_texture};
use crate::sample::texels::{Texels, pack_grey8, to_unorm16};

/// The picture at `path` as a specular map (see [`grey`]).
pub fn load_specular_map(path: &Path) -> Result<Level, TextureError> {
    Ok(grey(&load_texture(path)?))
}

/// A texture's base level as grey: the mean of R, G and B in every channel,
/// so a grey picture reads as itself and a coloured one as its brightness.
/// One channel is stored (2 bytes a texel): for an 8-bit picture exactly
/// the f32 mean, for others the mean to the nearest 1/65535.
pub fn grey(texture: &Texture) -> Level {
    let base = texture.base();
    let grey8 =
        |v: &[[u8; 4]]| Texels::Grey8(v.iter().map(|t| pack_grey8(t[0], t[1], t[2])).collect());
    let texels = match base.texels.compact() {
        Texels::Rgba8(v) | Texels::Rgb8(v) => grey8(v),
        other => Texels::Grey16(
            other
                .iter()
                .map(|t| to_unorm16((t[0] + t[1] + t[2]) / 3.0))
                .collect(),
        ),
    };
    Level {
        wrap: Default::default(),
        width: base.width,
        height: base.height,
        texels,
    }
}
