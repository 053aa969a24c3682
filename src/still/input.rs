//! `-` as `relief render`'s FILE: the model or the picture standard input
//! holds, read whole (its bytes held against the memory budget as they
//! come) and known by its bytes (`scene::model_bytes`).

use std::io::{IsTerminal, Read};

use relief_core::budget::{self, Reservation};
use relief_core::sanitize::io_reason;
use relief_scene::model_bytes::{self, BytesModel, Content};
use relief_texture::Texture;

/// How a model from standard input is named in messages ("model from
/// standard input, line 3: …").
pub const MODEL_NAME: &str = "from standard input";
/// How a picture from standard input is named in messages.
pub const PICTURE_NAME: &str = "standard input";

/// What standard input held.
pub enum StdinFile {
    Model(BytesModel),
    Picture(Texture),
}

/// Bytes read between two reservations.
const CHUNK: usize = 4 << 20;

/// Reads standard input and loads the model or picture it holds.
pub fn read_stdin_file() -> anyhow::Result<StdinFile> {
    let (bytes, _held) = read_stdin()?;
    match model_bytes::content_of(&bytes) {
        Some(Content::Picture) => Ok(StdinFile::Picture(
            relief_texture::decode::load::load_texture_from_bytes(PICTURE_NAME, &bytes)?,
        )),
        Some(Content::Model(format)) => Ok(StdinFile::Model(model_bytes::load_model(
            MODEL_NAME, format, &bytes,
        )?)),
        None => anyhow::bail!(
            "standard input holds neither a model nor a picture relief reads (glTF or GLB, OBJ, STL, PLY; PNG, JPEG and the other picture formats)"
        ),
    }
}

/// Standard input's bytes, refused when it is a terminal (a preview is
/// given the file through a pipe or a redirection) or empty.
fn read_stdin() -> anyhow::Result<(Vec<u8>, Reservation)> {
    let stdin = std::io::stdin();
    if stdin.is_terminal() {
        anyhow::bail!(
            "standard input is a terminal: give the model or picture through a pipe or a redirection (relief render --ansi - < model.glb)"
        );
    }
    let mut held = budget::reserve("standard input", 0)?;
    let mut bytes = Vec::new();
    let mut input = stdin.lock();
    loop {
        // Reserved before it is allocated; the vector grows by exactly it.
        held.grow("standard input", CHUNK as u64)?;
        bytes.reserve_exact(CHUNK);
        let start = bytes.len();
        bytes.resize(start + CHUNK, 0);
        let got = fill(&mut input, &mut bytes[start..])
            .map_err(|e| anyhow::anyhow!("cannot read standard input: {}", io_reason(&e)))?;
        bytes.truncate(start + got);
        if got < CHUNK {
            break;
        }
    }
    if bytes.is_empty() {
        anyhow::bail!("standard input is empty: give the model or picture through it");
    }
    Ok((bytes, held))
}

/// Reads into `buf` until it is full or the input ends; how much was read.
fn fill(input: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buf.len() {
        match input.read(&mut buf[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(filled)
}
