//! The bytes of a glTF file: the GLB container checked chunk by chunk, the
//! JSON, the buffers (GLB, data URI or a file beside the model) and the
//! images' encoded bytes. Every length a file claims is checked against
//! what is there, and the memory budget is asked, before anything of that
//! length is allocated.

use std::path::{Component, Path, PathBuf};

use base64::Engine;

use relief_core::budget::{self, Reservation};

/// The first word of a GLB file.
const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// A problem found while reading, with the place it was found: the caller
/// names the file.
pub(super) type Problem = String;

/// The file's JSON and its GLB binary chunk, if any.
pub(super) struct Container<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

/// Reads the whole file after reserving its size.
pub(super) fn read_file(path: &Path, what: &str) -> Result<(Vec<u8>, Reservation), Problem> {
    let meta = std::fs::metadata(path).map_err(|e| relief_core::sanitize::io_reason(&e))?;
    if !meta.is_file() {
        return Err("not a regular file".into());
    }
    let held = budget::reserve(what, meta.len()).map_err(|e| e.to_string())?;
    // Exactly the reserved size, reported to the view's progress line.
    let file = std::fs::File::open(path).map_err(|e| relief_core::sanitize::io_reason(&e))?;
    let bytes = crate::model_io::read_reporting(file, meta.len()).map_err(|e| match e {
        Some(e) => relief_core::sanitize::io_reason(&e),
        None => "the load was cancelled".to_string(),
    })?;
    Ok((bytes, held))
}

fn word(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// Splits a GLB file into its chunks, or takes the whole file as JSON.
pub(super) fn container(bytes: &[u8]) -> Result<Container<'_>, Problem> {
    if !bytes.starts_with(GLB_MAGIC) {
        return Ok(Container {
            json: bytes,
            bin: None,
        });
    }
    if bytes.len() < 20 {
        return Err(format!(
            "GLB header: the file ends at byte {} (a header and a chunk header take 20)",
            bytes.len()
        ));
    }
    let version = word(bytes, 4);
    if version != 2 {
        return Err(format!(
            "GLB header, byte 4: version {version} (only glTF 2.0 is read)"
        ));
    }
    let total = word(bytes, 8) as usize;
    if total > bytes.len() {
        return Err(format!(
            "GLB header, byte 8: claims {total} bytes but the file has {}",
            bytes.len()
        ));
    }
    let bytes = &bytes[..total];
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    let mut index = 0;
    while at + 8 <= bytes.len() {
        let length = word(bytes, at) as usize;
        let kind = word(bytes, at + 4);
        let start = at + 8;
        if length > bytes.len() - start {
            return Err(format!(
                "GLB chunk {index} at byte {at}: claims {length} bytes but {} remain",
                bytes.len() - start
            ));
        }
        let data = &bytes[start..start + length];
        match (index, kind) {
            (0, CHUNK_JSON) => json = Some(data),
            (0, _) => {
                return Err(format!(
                    "GLB chunk 0 at byte {at}: type {kind:#010x}, not JSON"
                ));
            }
            (1, CHUNK_BIN) => bin = Some(data),
            // Other chunks are to be skipped (glTF 2.0 §4.4.3).
            _ => {}
        }
        // Chunks are 4-byte aligned.
        at = start + length.div_ceil(4) * 4;
        index += 1;
    }
    match json {
        Some(json) => Ok(Container { json, bin }),
        None => Err("GLB: no JSON chunk".into()),
    }
}

/// What a URI in the file points at.
pub(super) enum Uri<'a> {
    /// Bytes inside the URI (`data:...;base64,`).
    Data(&'a str),
    /// A file beside the model (percent-decoded relative path).
    File(String),
}

pub(super) fn parse_uri(uri: &str) -> Result<Uri<'_>, Problem> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((head, payload)) = rest.split_once(',') else {
            return Err("a data URI without a comma".into());
        };
        if !head.ends_with(";base64") {
            return Err("a data URI that is not base64".into());
        }
        return Ok(Uri::Data(payload));
    }
    if uri.contains("://") {
        return Err(format!(
            "the URI '{}' is not a relative file (nothing is fetched)",
            relief_core::sanitize::clean(&uri.chars().take(40).collect::<String>())
        ));
    }
    Ok(Uri::File(percent_decode(uri)))
}

/// The file a relative URI names inside the model's folder `dir`: a URI
/// that is absolute or climbs out of the folder (`../`, or a link inside it
/// that points elsewhere) is refused, as a viewer that opens files from the
/// internet must (a model could otherwise read any file of the machine).
pub(super) fn beside(dir: &Path, rel: &str) -> Result<PathBuf, Problem> {
    let outside = || {
        format!(
            "the URI '{}' points outside the model's folder (only files in it are read)",
            relief_core::sanitize::clean(&rel.chars().take(60).collect::<String>())
        )
    };
    let mut inside = PathBuf::new();
    for part in Path::new(rel).components() {
        match part {
            Component::Normal(name) => inside.push(name),
            Component::CurDir => {}
            Component::ParentDir => {
                if !inside.pop() {
                    return Err(outside());
                }
            }
            Component::RootDir | Component::Prefix(_) => return Err(outside()),
        }
    }
    // "C:/x" or "\\server\x" are not absolute on Linux, but are meant to be.
    if rel.starts_with('\\') || rel.as_bytes().get(1) == Some(&b':') {
        return Err(outside());
    }
    let path = dir.join(&inside);
    // A link inside the folder may lead out of it; a missing file is
    // reported by the read that follows.
    if let (Ok(real), Ok(root)) = (path.canonicalize(), dir.canonicalize())
        && !real.starts_with(&root)
    {
        return Err(outside());
    }
    Ok(path)
}

/// `%20` and the like in a relative URI, decoded; malformed escapes stay as they are.
fn percent_decode(uri: &str) -> String {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%'
            && i + 2 < b.len()
            && let Ok(v) =
                u8::from_str_radix(std::str::from_utf8(&b[i + 1..i + 3]).unwrap_or("zz"), 16)
        {
            out.push(v);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The bytes of a base64 payload, its decoded size checked against the
/// budget before decoding.
pub(super) fn decode_data(payload: &str, what: &str) -> Result<(Vec<u8>, Reservation), Problem> {
    let size = (payload.len() as u64 / 4 + 1) * 3;
    let held = budget::reserve(what, size).map_err(|e| e.to_string())?;
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(payload.trim_end())
        .map_err(|_| "its data URI is not valid base64".to_string())?;
    Ok((bytes, held))
}

/// One buffer's bytes: the GLB chunk, a data URI or a file next to the
/// model, at least `length` bytes long (the JSON's `byteLength`).
pub(super) fn buffer(
    source: ::gltf::buffer::Source,
    length: usize,
    bin: Option<&[u8]>,
    dir: &Path,
    what: &str,
) -> Result<(Vec<u8>, Option<Reservation>), Problem> {
    let (bytes, held) = match source {
        ::gltf::buffer::Source::Bin => {
            let Some(bin) = bin else {
                return Err("refers to the GLB binary chunk, which the file lacks".into());
            };
            if length > bin.len() {
                return Err(format!(
                    "byteLength {length} is more than the {} bytes of the GLB binary chunk",
                    bin.len()
                ));
            }
            let held = budget::reserve(what, length as u64).map_err(|e| e.to_string())?;
            (bin[..length].to_vec(), Some(held))
        }
        ::gltf::buffer::Source::Uri(uri) => match parse_uri(uri)? {
            Uri::Data(payload) => {
                let (b, h) = decode_data(payload, what)?;
                (b, Some(h))
            }
            Uri::File(rel) => {
                let (b, h) = read_file(&beside(dir, &rel)?, what)
                    .map_err(|p| format!("file '{}': {p}", relief_core::sanitize::clean(&rel)))?;
                (b, Some(h))
            }
        },
    };
    if bytes.len() < length {
        return Err(format!(
            "byteLength {length} is more than the {} bytes it holds",
            bytes.len()
        ));
    }
    Ok((bytes, held))
}
