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
//! - numbers are read as tinyobjloader reads them: the longest number at the
//!   start of the word, so `3.1+e2` is 3.1 (with a warning); a word with no
//!   number at its start, NaN or infinity is an error;
//! - `f` corners `v`, `v/vt`, `v//vn`, `v/vt/vn`, indices 1-based or
//!   negative (relative to the items so far); a corner repeating the
//!   previous one's position is dropped (a zero-length edge), polygons are
//!   split into fans; a `vt` or `vn` index out of range drops that
//!   attribute for the face (with a warning), a `v` index out of range is
//!   an error;
//! - `mtllib` names material libraries (several on a line, or one name with
//!   spaces), `usemtl` starts a part of the model with that material;
//! - everything else (`o`, `g`, `s`, `l`, `p`, …) is ignored.
//!
//! A first pass counts, so face sizes and the memory budget are checked
//! before anything of the model's size is allocated.

use glam::{Vec2, Vec3};

use super::{Corner, MAX_FACE_CORNERS, ObjError, quote};
use crate::budget::Reservation;

/// Bytes the loader holds per triangle at its peak (corners as read, the
/// triangles being built, the vertex and position maps, the mesh), an upper
/// bound measured on the worst cases (every corner a vertex of its own).
pub const MODEL_BYTES_PER_TRIANGLE: u64 = 920;
/// Bytes per `v` line (position and optional colour), `vt` and `vn` line.
const BYTES_PER_POSITION: u64 = 12 + 16;
/// Bytes per triangle of the part each triangle belongs to.
const BYTES_PER_PART_ID: u64 = 4;
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

/// Length of the number at the start of `word` (sign, digits, fraction,
/// exponent when complete), 0 when there is none: what tinyobjloader reads.
fn number_prefix(word: &[u8]) -> usize {
    let digits = |from: usize| {
        word[from.min(word.len())..]
            .iter()
            .take_while(|b| b.is_ascii_digit())
            .count()
    };
    let mut at = usize::from(matches!(word.first(), Some(b'+' | b'-')));
    let whole = digits(at);
    at += whole;
    let mut fraction = 0;
    if word.get(at) == Some(&b'.') {
        fraction = digits(at + 1);
        if whole + fraction > 0 {
            at += 1 + fraction;
        }
    }
    if whole + fraction == 0 {
        return 0;
    }
    if matches!(word.get(at), Some(b'e' | b'E')) {
        let sign = usize::from(matches!(word.get(at + 1), Some(b'+' | b'-')));
        let exponent = digits(at + 1 + sign);
        if exponent > 0 {
            at += 1 + sign + exponent;
        }
    }
    at
}

/// A number as tinyobjloader reads it, and whether text followed it.
fn number(word: &[u8], what: &str) -> Result<(f32, bool), String> {
    let len = number_prefix(word);
    std::str::from_utf8(&word[..len])
        .ok()
        .filter(|_| len > 0)
        .and_then(|s| s.parse::<f32>().ok())
        .filter(|x| x.is_finite())
        .map(|x| (x, len < word.len()))
        .ok_or_else(|| format!("{what}: {} is not a finite number", quote_bytes(word)))
}

/// At least `min` and at most `max` numbers from `words`; `cut` is set when
/// a word had text after its number.
fn numbers<'a>(
    words: impl Iterator<Item = &'a [u8]>,
    min: usize,
    max: usize,
    what: &str,
    cut: &mut bool,
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
        let (x, trailing) = number(word, what)?;
        *cut |= trailing;
        out.push(x);
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

/// Where the first of several alike problems was, and how many there were.
#[derive(Default)]
struct Tally {
    first_line: usize,
    count: usize,
}

impl Tally {
    fn add(&mut self, line: usize) {
        if self.count == 0 {
            self.first_line = line;
        }
        self.count += 1;
    }
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
    /// The part of each triangle (an index into `parts`).
    pub part_of: Vec<u32>,
    /// The material each part names (`usemtl`); part 0 is the faces before
    /// any `usemtl` (or after an empty one).
    pub parts: Vec<Option<String>>,
    /// The `mtllib` lines, as written.
    pub libraries: Vec<String>,
    /// One line each, naming the file.
    pub warnings: Vec<String>,
    pub reservation: Reservation,
}

/// Reads `bytes` (a whole OBJ file); `name` (already sanitised) is used in errors.
pub(super) fn read(name: &str, bytes: &[u8]) -> Result<ReadModel, ObjError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
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
    // No fixed limit: the memory budget decides, before anything is allocated.
    let need = (bytes.len() as u64)
        .saturating_add(counts.positions as u64 * BYTES_PER_POSITION)
        .saturating_add(counts.texcoords as u64 * BYTES_PER_TEXCOORD)
        .saturating_add(counts.normals as u64 * BYTES_PER_NORMAL)
        .saturating_add(
            (counts.triangles as u64).saturating_mul(MODEL_BYTES_PER_TRIANGLE + BYTES_PER_PART_ID),
        );
    let reservation = crate::scene::model_file::reserve(name, "the triangles", need)?;

    let mut positions: Vec<Vec3> = Vec::with_capacity(counts.positions);
    let mut colors: Vec<Option<Vec3>> = Vec::with_capacity(counts.positions);
    let mut texcoords: Vec<Vec2> = Vec::with_capacity(counts.texcoords);
    let mut normals: Vec<Vec3> = Vec::with_capacity(counts.normals);
    let mut face: Vec<FaceCorner> = Vec::new();
    let mut corners: Vec<Corner> = Vec::with_capacity(counts.triangles * 3);
    let mut part_of: Vec<u32> = Vec::with_capacity(counts.triangles);
    let mut parts: Vec<Option<String>> = vec![None];
    let mut part = 0u32;
    let mut libraries = Vec::new();
    let (mut all_uv, mut all_normals) = (true, true);
    let (mut bad_uv, mut bad_normal, mut cut_numbers) =
        (Tally::default(), Tally::default(), Tally::default());
    for (number, line) in lines(bytes).enumerate() {
        let at = at(number + 1);
        let mut w = words(line);
        let mut cut = false;
        match w.next() {
            Some(b"v") => {
                let n = numbers(w, 3, 6, "position", &mut cut).map_err(at)?;
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
                let n = numbers(w, 1, 3, "texture coordinate", &mut cut).map_err(at)?;
                texcoords.push(Vec2::new(n[0], n.get(1).copied().unwrap_or(0.0)));
            }
            Some(b"vn") => {
                let n = numbers(w, 3, 3, "normal", &mut cut).map_err(at)?;
                normals.push(Vec3::new(n[0], n[1], n[2]));
            }
            Some(b"mtllib") => libraries.push(rest_of_line(line, b"mtllib")),
            Some(b"usemtl") => {
                let material = rest_of_line(line, b"usemtl");
                let key = (!material.is_empty()).then_some(material);
                part = match parts.iter().position(|p| *p == key) {
                    Some(i) => i as u32,
                    None => {
                        parts.push(key);
                        (parts.len() - 1) as u32
                    }
                };
            }
            Some(b"f") => {
                face.clear();
                let (mut uv_dropped, mut normal_dropped) = (false, false);
                for word in w {
                    let mut pieces = word.split(|&b| b == b'/');
                    let (p, t, n) = (pieces.next(), pieces.next(), pieces.next());
                    let p = match p {
                        Some(p) if !p.is_empty() && pieces.next().is_none() => p,
                        _ => return Err(at(format!("bad face corner {}", quote_bytes(word)))),
                    };
                    let position = resolve(p, positions.len(), "vertex").map_err(&at)?;
                    // Out of range: tinyobjloader drops the attribute (with a warning).
                    let uv = match t {
                        Some(t) if !t.is_empty() => {
                            match resolve(t, texcoords.len(), "texture coordinate") {
                                Ok(i) => Some(i),
                                Err(e) if e.contains("out of range") => {
                                    uv_dropped = true;
                                    None
                                }
                                Err(e) => return Err(at(e)),
                            }
                        }
                        _ => None,
                    };
                    let normal = match n {
                        Some(n) if !n.is_empty() => match resolve(n, normals.len(), "normal") {
                            Ok(i) => Some(i),
                            Err(e) if e.contains("out of range") => {
                                normal_dropped = true;
                                None
                            }
                            Err(e) => return Err(at(e)),
                        },
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
                if uv_dropped {
                    bad_uv.add(number + 1);
                    face.iter_mut().for_each(|c| c.uv = None);
                }
                if normal_dropped {
                    bad_normal.add(number + 1);
                    face.iter_mut().for_each(|c| c.normal = None);
                }
                while face.len() > 1
                    && face.first().map(|c| c.position) == face.last().map(|c| c.position)
                {
                    face.pop();
                }
                // One or two corners are a point or a line: not drawn.
                if face.len() >= 3 {
                    // A face that lost an attribute gets a computed one; it
                    // does not make the model drop the file's everywhere.
                    all_uv &= uv_dropped || face.iter().all(|c| c.uv.is_some());
                    all_normals &= normal_dropped || face.iter().all(|c| c.normal.is_some());
                    let corner = |c: &FaceCorner| Corner {
                        position: positions[c.position],
                        uv: c.uv.map(|i| texcoords[i]),
                        normal: c.normal.map(|i| normals[i]),
                        color: colors[c.position],
                    };
                    for k in 1..face.len() - 1 {
                        corners.extend([&face[0], &face[k], &face[k + 1]].map(corner));
                        part_of.push(part);
                    }
                }
            }
            _ => {}
        }
        if cut {
            cut_numbers.add(number + 1);
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
    let mut warnings = Vec::new();
    for (tally, what) in [
        (
            &bad_uv,
            "a texture coordinate index out of range: their UVs were dropped",
        ),
        (
            &bad_normal,
            "a normal index out of range: their normals were computed",
        ),
        (
            &cut_numbers,
            "a number followed by other text (read as the number alone, as tinyobjloader does)",
        ),
    ] {
        if tally.count > 0 {
            warnings.push(format!(
                "model {name}, line {}: {} line(s) with {what}",
                tally.first_line, tally.count
            ));
        }
    }
    Ok(ReadModel {
        corners,
        part_of,
        parts,
        libraries,
        warnings,
        reservation,
    })
}

/// The text after a line's keyword, its comment cut and its blanks trimmed
/// (names may hold spaces and any 8-bit text).
fn rest_of_line(line: &[u8], keyword: &[u8]) -> String {
    let data = match line.iter().position(|&b| b == b'#') {
        Some(at) => &line[..at],
        None => line,
    };
    let data = data.trim_ascii_start();
    let rest = data.strip_prefix(keyword).unwrap_or(data);
    String::from_utf8_lossy(rest.trim_ascii()).into_owned()
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
    fn numbers_are_read_as_tinyobjloader_reads_them() {
        assert_eq!(number(b"3.1+e2", "x"), Ok((3.1, true)));
        assert_eq!(number(b"1.5e2", "x"), Ok((150.0, false)));
        assert_eq!(number(b"-.5", "x"), Ok((-0.5, false)));
        assert_eq!(number(b"2e", "x"), Ok((2.0, true)));
        assert_eq!(number(b"7.", "x"), Ok((7.0, false)));
        for bad in [&b"nan"[..], b"inf", b"-", b".", b"e5", b"1e999", b"x1"] {
            assert!(
                number(bad, "x").is_err(),
                "{:?}",
                String::from_utf8_lossy(bad)
            );
        }
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
