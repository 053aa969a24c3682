//! The OBJ text, read line by line into triangle corners.
//!
//! It reads what tinyobjloader reads, and says where when it cannot:
//! - lines end with `\n`, `\r\n` or a lone `\r`; a UTF-8 byte-order mark at
//!   the start is skipped; text is bytes, so a Latin-1 name or comment is
//!   no error (only numbers and indices must be ASCII);
//! - `#` starts a comment anywhere on a line;
//! - `v x y z [w]` or `v x y z r g b`; when only some positions carry a
//!   colour, the others are white (as tinyobjloader fills them);
//! - `vt u [v [w]]` (v is 0 when missing), `vn x y z`;
//! - `f` corners `v`, `v/vt`, `v//vn`, `v/vt/vn`, indices 1-based or
//!   negative (relative to the items so far); a corner repeating the
//!   previous one's position is dropped (a zero-length edge), polygons are
//!   split into fans;
//! - everything else (`o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, …) is
//!   ignored: materials are never opened.
//!
//! A first pass counts, so limits and the memory budget are checked before
//! anything of the model's size is allocated.

use glam::{Vec2, Vec3};

use super::{Corner, MAX_FACE_CORNERS, MAX_POSITIONS, MAX_TRIANGLES, ObjError, quote};
use crate::budget::{self, Reservation};

/// Bytes the loader holds per triangle at its peak (corners as read, the
/// triangles being built, the vertex and position maps, the mesh), an upper
/// bound measured on the worst cases (every corner a vertex of its own).
pub const MODEL_BYTES_PER_TRIANGLE: u64 = 920;
/// Bytes per `v` line (position and optional colour), `vt` and `vn` line.
const BYTES_PER_POSITION: u64 = 12 + 16;
const BYTES_PER_TEXCOORD: u64 = 8;
const BYTES_PER_NORMAL: u64 = 12;

/// The lines of `bytes`, ended by `\n`, `\r\n` or `\r`, without the ending.
fn lines(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    let mut rest = bytes;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let end = rest
            .iter()
            .position(|&b| b == b'\n' || b == b'\r')
            .unwrap_or(rest.len());
        let line = &rest[..end];
        let skip = match rest.get(end..end + 2) {
            Some(b"\r\n") => 2,
            _ if end < rest.len() => 1,
            _ => 0,
        };
        rest = &rest[end + skip..];
        Some(line)
    })
}

/// The words of a line, its `#` comment cut off.
fn words(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    let data = match line.iter().position(|&b| b == b'#') {
        Some(at) => &line[..at],
        None => line,
    };
    data.split(|b| b.is_ascii_whitespace())
        .filter(|w| !w.is_empty())
}

fn quote_bytes(word: &[u8]) -> String {
    quote(&String::from_utf8_lossy(word))
}

fn number(word: &[u8], what: &str) -> Result<f32, String> {
    std::str::from_utf8(word)
        .ok()
        .and_then(|s| s.parse::<f32>().ok())
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("{what}: {} is not a finite number", quote_bytes(word)))
}

/// At least `min` and at most `max` numbers from `words`.
fn numbers<'a>(
    words: impl Iterator<Item = &'a [u8]>,
    min: usize,
    max: usize,
    what: &str,
) -> Result<Vec<f32>, String> {
    let mut out = Vec::with_capacity(max);
    for word in words {
        if out.len() == max {
            return Err(format!("{what} has more than {max} numbers"));
        }
        // A vertex's numbers after the third are its colour (or w).
        let what = if what == "position" && out.len() >= 3 {
            "vertex colour"
        } else {
            what
        };
        out.push(number(word, what)?);
    }
    if out.len() < min {
        return Err(format!("{what} needs {min} numbers, found {}", out.len()));
    }
    Ok(out)
}

/// An OBJ index (1-based, or negative relative to the end) into `count`
/// items, as a 0-based index.
fn resolve(word: &[u8], count: usize, what: &str) -> Result<usize, String> {
    let index: i64 = std::str::from_utf8(word)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| format!("{what} index {} is not a whole number", quote_bytes(word)))?;
    let resolved = match index {
        i if i > 0 && (i as u64) <= count as u64 => Some(i as usize - 1),
        i if i < 0 && i.unsigned_abs() <= count as u64 => Some(count - i.unsigned_abs() as usize),
        _ => None,
    };
    resolved
        .ok_or_else(|| format!("{what} index {index} is out of range (there are {count} so far)"))
}

/// What the counting pass found: upper bounds for the reading pass.
#[derive(Default)]
struct Counts {
    positions: usize,
    texcoords: usize,
    normals: usize,
    /// Corners − 2 summed over the faces (before repeats are dropped).
    triangles: usize,
}

/// One face corner: indices into the positions, UVs and normals read so far.
#[derive(Clone, Copy, PartialEq)]
struct FaceCorner {
    position: usize,
    uv: Option<usize>,
    normal: Option<usize>,
}

/// The model's triangle corners, and the reservation that covers them
/// (and the mesh built from them) until it is dropped.
pub(super) struct ReadModel {
    pub corners: Vec<Corner>,
    pub reservation: Reservation,
}

/// Reads `bytes` (a whole OBJ file); `name` (already sanitised) is used in errors.
pub(super) fn read(name: &str, bytes: &[u8]) -> Result<ReadModel, ObjError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let too_many = |what, limit| ObjError::TooMany {
        name: name.to_string(),
        what,
        limit,
    };
    let at = |line: usize| {
        move |problem: String| ObjError::Line {
            name: name.to_string(),
            line,
            problem,
        }
    };

    let mut counts = Counts::default();
    for (number, line) in lines(bytes).enumerate() {
        let mut w = words(line);
        match w.next() {
            Some(b"v") => counts.positions += 1,
            Some(b"vt") => counts.texcoords += 1,
            Some(b"vn") => counts.normals += 1,
            Some(b"f") => {
                let corners = w.count();
                if corners > MAX_FACE_CORNERS {
                    return Err(at(number + 1)(format!(
                        "a face of {corners} corners (limit {MAX_FACE_CORNERS})"
                    )));
                }
                counts.triangles += corners.saturating_sub(2);
            }
            _ => {}
        }
    }
    for (count, what) in [
        (counts.positions, "vertices"),
        (counts.texcoords, "texture coordinates"),
        (counts.normals, "normals"),
    ] {
        if count > MAX_POSITIONS {
            return Err(too_many(what, MAX_POSITIONS));
        }
    }
    if counts.triangles > MAX_TRIANGLES {
        return Err(too_many("triangles", MAX_TRIANGLES));
    }
    let need = (bytes.len() as u64)
        + counts.positions as u64 * BYTES_PER_POSITION
        + counts.texcoords as u64 * BYTES_PER_TEXCOORD
        + counts.normals as u64 * BYTES_PER_NORMAL
        + counts.triangles as u64 * MODEL_BYTES_PER_TRIANGLE;
    let reservation =
        budget::reserve(&format!("model {name}"), need).map_err(|e| ObjError::Budget {
            name: name.to_string(),
            reason: e.to_string(),
        })?;

    let mut positions: Vec<Vec3> = Vec::with_capacity(counts.positions);
    let mut colors: Vec<Option<Vec3>> = Vec::with_capacity(counts.positions);
    let mut texcoords: Vec<Vec2> = Vec::with_capacity(counts.texcoords);
    let mut normals: Vec<Vec3> = Vec::with_capacity(counts.normals);
    let mut face: Vec<FaceCorner> = Vec::new();
    let mut corners: Vec<Corner> = Vec::with_capacity(counts.triangles * 3);
    let (mut all_uv, mut all_normals) = (true, true);
    for (number, line) in lines(bytes).enumerate() {
        let at = at(number + 1);
        let mut w = words(line);
        match w.next() {
            Some(b"v") => {
                let n = numbers(w, 3, 6, "position").map_err(at)?;
                match n.len() {
                    3 => colors.push(None),
                    4 if n[3] != 0.0 => colors.push(None),
                    4 => return Err(at("bad w '0'".into())),
                    6 => colors.push(Some(Vec3::new(n[3], n[4], n[5]))),
                    k => return Err(at(format!("position has {k} numbers"))),
                }
                positions.push(Vec3::new(n[0], n[1], n[2]));
            }
            Some(b"vt") => {
                let n = numbers(w, 1, 3, "texture coordinate").map_err(at)?;
                texcoords.push(Vec2::new(n[0], n.get(1).copied().unwrap_or(0.0)));
            }
            Some(b"vn") => {
                let n = numbers(w, 3, 3, "normal").map_err(at)?;
                normals.push(Vec3::new(n[0], n[1], n[2]));
            }
            Some(b"f") => {
                face.clear();
                for word in w {
                    let mut parts = word.split(|&b| b == b'/');
                    let (p, t, n) = (parts.next(), parts.next(), parts.next());
                    let p = match p {
                        Some(p) if !p.is_empty() && parts.next().is_none() => p,
                        _ => return Err(at(format!("bad face corner {}", quote_bytes(word)))),
                    };
                    let position = resolve(p, positions.len(), "vertex").map_err(&at)?;
                    let uv = match t {
                        Some(t) if !t.is_empty() => {
                            Some(resolve(t, texcoords.len(), "texture coordinate").map_err(&at)?)
                        }
                        _ => None,
                    };
                    let normal = match n {
                        Some(n) if !n.is_empty() => {
                            Some(resolve(n, normals.len(), "normal").map_err(&at)?)
                        }
                        _ => None,
                    };
                    let corner = FaceCorner {
                        position,
                        uv,
                        normal,
                    };
                    // A repeated position is a zero-length edge.
                    if face.last().is_none_or(|p| p.position != position) {
                        face.push(corner);
                    }
                }
                while face.len() > 1
                    && face.first().map(|c| c.position) == face.last().map(|c| c.position)
                {
                    face.pop();
                }
                // One or two corners are a point or a line: not drawn.
                if face.len() >= 3 {
                    all_uv &= face.iter().all(|c| c.uv.is_some());
                    all_normals &= face.iter().all(|c| c.normal.is_some());
                    let corner = |c: &FaceCorner| Corner {
                        position: positions[c.position],
                        uv: c.uv.map(|i| texcoords[i]),
                        normal: c.normal.map(|i| normals[i]),
                        color: colors[c.position],
                    };
                    for k in 1..face.len() - 1 {
                        corners.extend([&face[0], &face[k], &face[k + 1]].map(corner));
                    }
                }
            }
            _ => {}
        }
    }
    if corners.is_empty() {
        return Err(ObjError::Empty {
            name: name.to_string(),
        });
    }
    // UVs and normals are used when every corner has one; colours when any
    // position has one (the others are white).
    let any_color = colors.iter().any(Option::is_some);
    for c in corners.iter_mut() {
        if !all_uv {
            c.uv = None;
        }
        if !all_normals {
            c.normal = None;
        }
        if any_color {
            c.color = Some(c.color.unwrap_or(Vec3::ONE));
        }
    }
    Ok(ReadModel {
        corners,
        reservation,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_end_with_any_of_the_three_endings() {
        let got: Vec<&[u8]> = lines(b"a\nb\r\nc\rd\n\ne").collect();
        let want: Vec<&[u8]> = vec![b"a", b"b", b"c", b"d", b"", b"e"];
        assert_eq!(got, want);
        assert_eq!(lines(b"").count(), 0);
        assert_eq!(lines(b"x\r\n").count(), 1);
    }

    #[test]
    fn comments_are_cut_anywhere() {
        let got: Vec<&[u8]> = words(b"f 1 2\t3 # a #comment").collect();
        assert_eq!(got, vec![&b"f"[..], b"1", b"2", b"3"]);
        assert_eq!(words(b"# v 1 2 3").count(), 0);
    }

    #[test]
    fn indices_resolve_forwards_and_backwards() {
        assert_eq!(resolve(b"1", 3, "vertex"), Ok(0));
        assert_eq!(resolve(b"3", 3, "vertex"), Ok(2));
        assert_eq!(resolve(b"-1", 3, "vertex"), Ok(2));
        assert_eq!(resolve(b"-3", 3, "vertex"), Ok(0));
        for bad in [
            &b"0"[..],
            b"4",
            b"-4",
            b"x",
            b"\xe9",
            b"-9223372036854775808",
        ] {
            assert!(resolve(bad, 3, "vertex").is_err());
        }
    }
}
