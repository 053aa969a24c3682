//! The specular map: a grey picture whose value scales the highlight
//! (docs/specular.md). A separate file, as the lecture's second texture
//! unit is, since the colour texture's four channels are already taken
//! (RGB the albedo, alpha the height map).

use std::path::Path;

use super::{Level, Texture, TextureError, load_texture};

/// The picture at `path` as a specular map (see [`grey`]).
pub fn load_specular_map(path: &Path) -> Result<Level, TextureError> {
    Ok(grey(&load_texture(path)?))
}

/// A texture's base level as grey: the mean of R, G and B in every channel,
/// so a grey picture reads as itself and a coloured one as its brightness.
pub fn grey(texture: &Texture) -> Level {
    let base = texture.base();
    Level {
        width: base.width,
        height: base.height,
        texels: base
            .texels
            .iter()
            .map(|t| {
                let g = (t[0] + t[1] + t[2]) / 3.0;
                [g; 4]
            })
            .collect(),
    }
}
