//! The built-in textures: PNGs in `assets/`, made by `procedural.rs`
//! (`relief assets DIR` rewrites them), embedded in the program and decoded
//! by the same loader as the user's files.

use std::path::{Path, PathBuf};

use super::load::{TextureError, load_texture_from_bytes};
use super::procedural;
use crate::Texture;

/// One built-in texture: its name, its shipped PNG and the code that drew it.
#[derive(Clone, Copy)]
pub struct Builtin {
    /// Short name shown in the texture list.
    pub name: &'static str,
    /// File name under `assets/`.
    pub file: &'static str,
    /// The shipped PNG, embedded.
    pub png: &'static [u8],
    /// The generator: width, height, RGBA top row first (alpha = height).
    pub generate: fn() -> (usize, usize, Vec<u8>),
}

impl std::fmt::Debug for Builtin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Builtin")
            .field("name", &self.name)
            .field("file", &self.file)
            .finish()
    }
}

impl Builtin {
    /// Decodes the embedded PNG.
    pub fn load(&self) -> Result<Texture, TextureError> {
        let mut tex = load_texture_from_bytes(self.file, self.png)?;
        tex.name = format!("{} (built-in)", self.name);
        Ok(tex)
    }
}

/// Every built-in texture, the default (brick) first.
pub fn builtins() -> Vec<Builtin> {
    vec![
        Builtin {
            name: "brick",
            file: "brick.png",
            png: include_bytes!("../../../../assets/brick.png"),
            generate: procedural::brick_rgba,
        },
        Builtin {
            name: "tiles",
            file: "tiles.png",
            png: include_bytes!("../../../../assets/tiles.png"),
            generate: procedural::tiles_rgba,
        },
        Builtin {
            name: "waves",
            file: "waves.png",
            png: include_bytes!("../../../../assets/waves.png"),
            generate: procedural::waves_rgba,
        },
    ]
}

/// Writes every built-in texture as an RGBA PNG into `dir` (created if
/// needed) and returns the paths written.
pub fn write_assets(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    for b in builtins() {
        let (w, h, rgba) = (b.generate)();
        let path = dir.join(b.file);
        let picture = image::RgbaImage::from_raw(w as u32, h as u32, rgba)
            .ok_or_else(|| anyhow::anyhow!("{}: {w}x{h} does not match its texels", b.file))?;
        crate::picture::save(&picture.into(), &path)?;
        written.push(path);
    }
    Ok(written)
}
