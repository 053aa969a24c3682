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
use rayon::prelude::*;

use super::plain_lines::{
    FaceCorner, Kind, after_ending, corner_at, face_at, kind_at, line_end, number_at, numbers_at,
    words_at,
};
use crate::corners::{IndexedCorners, MAX_FACE_CORNERS, NO_INDEX, bytes_of, hold};
use crate::load_progress::{self, LoadStep};
use crate::model_error::{ObjError, quote};
use relief_core::budget::Reservation;

/// Bytes the reading holds per triangle: its corners' three indices and
/// its part (besides the `v`, `vt`, `vn` arrays).
pub const READ_BYTES_PER_TRIANGLE: u64 =
    3 * std::mem::size_of::<[u32; 3]>() as u64 + std::mem::size_of::<u32>() as u64;

/// The lines of `bytes`, ended by `\n`, `\r\n` or `\r`, without the
/// ending: how the readers below walk them.
#[cfg(test)]
fn lines(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    let mut at = 0;
    std::iter::from_fn(move || {
        if at == bytes.len() {
            return None;
        }
        let end = line_end(bytes, at);
        let line = &bytes[at..end];
        at = after_ending(bytes, end);
        Some(line)
    })
}

/// The first word of `s` and the text after it, none when only blanks or
/// a `#` comment are left: words are split by ASCII blanks and a `#` ends
/// the line's data (one scan, no search for the comment first).
fn next_word(s: &[u8]) -> Option<(&[u8], &[u8])> {
    let start = s.iter().position(|b| !b.is_ascii_whitespace())?;
    let s = &s[start..];
    if s[0] == b'#' {
        return None;
    }
    let end = s
        .iter()
        .position(|&b| b == b'#' || b.is_ascii_whitespace())
        .unwrap_or(s.len());
    Some(s.split_at(end))
}

/// The words of a line, its `#` comment cut off.
fn words(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    let mut rest = line;
    std::iter::from_fn(move || {
        let (word, after) = next_word(rest)?;
        rest = after;
        Some(word)
    })
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
    if let Some(x) = plain_number(word) {
        return Ok((x, false));
    }
    let len = number_prefix(word);
    std::str::from_utf8(&word[..len])
        .ok()
        .filter(|_| len > 0)
        .and_then(|s| s.parse::<f32>().ok())
        .filter(|x| x.is_finite())
        .map(|x| (x, len < word.len()))
        .ok_or_else(|| format!("{what}: {} is not a finite number", quote_bytes(word)))
}

/// The usual number form, a sign, at most 19 digits and a point (no
/// exponent), read with the same bits as `str::parse::<f32>` gives, or none
/// (the caller takes the general path): see [`number_at`].
fn plain_number(word: &[u8]) -> Option<f32> {
    number_at(word, 0).map(|(x, _)| x)
}

/// Most numbers a line gives (a position with its colour).
const MAX_NUMBERS: usize = 6;

/// At least `min` and at most `max` (at most [`MAX_NUMBERS`]) numbers from
/// `words`, and how many; `cut` is set when a word had text after its number.
fn numbers<'a>(
    words: impl Iterator<Item = &'a [u8]>,
    min: usize,
    max: usize,
    what: &str,
    cut: &mut bool,
) -> Result<([f32; MAX_NUMBERS], usize), String> {
    let mut out = [0.0; MAX_NUMBERS];
    let mut len = 0;
    for word in words {
        if len == max {
            return Err(format!("{what} has more than {max} numbers"));
        }
        // A vertex's numbers after the third are its colour (or w).
        let what = if what == "position" && len >= 3 {
            "vertex colour"
        } else {
            what
        };
        let (x, trailing) = number(word, what)?;
        *cut |= trailing;
        out[len] = x;
        len += 1;
    }
    if len < min {
        return Err(format!("{what} needs {min} numbers, found {len}"));
    }
    Ok((out, len))
}

/// An OBJ index (1-based, or negative relative to the end) into `count`
/// items, as a 0-based index.
fn resolve(word: &[u8], count: usize, what: &str) -> Result<usize, String> {
    // The usual case, a short run of digits in range, without going
    // through text; anything else takes the general path and its message.
    if let Some(i) = small_index(word)
        && (1..=count).contains(&i)
    {
        return Ok(i - 1);
    }
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

/// A positive whole number of at most 18 ASCII digits, else none.
fn small_index(word: &[u8]) -> Option<usize> {
    if word.is_empty() || word.len() > 18 || !word.iter().all(u8::is_ascii_digit) {
        return None;
    }
    let value = word.iter().fold(0u64, |n, &d| n * 10 + u64::from(d - b'0'));
    usize::try_from(value).ok()
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

    /// Adds the tally of a later chunk whose lines start at `offset`.
    fn merge(&mut self, later: &Tally, offset: usize) {
        if self.count == 0 {
            self.first_line = later.first_line + offset;
        }
        self.count += later.count;
    }
}

/// What the counting pass found: upper bounds for the reading pass.
#[derive(Default, Clone, Copy)]
struct Counts {
    lines: usize,
    positions: usize,
    texcoords: usize,
    normals: usize,
    /// Corners − 2 summed over the faces (before repeats are dropped).
    triangles: usize,
}

impl Counts {
    fn add(self, o: Counts) -> Counts {
        Counts {
            lines: self.lines + o.lines,
            positions: self.positions + o.positions,
            texcoords: self.texcoords + o.texcoords,
            normals: self.normals + o.normals,
            triangles: self.triangles + o.triangles,
        }
    }
}

/// The model's triangle corners, and the reservation that covers them
/// until it is dropped (the builder grows it for what it allocates).
pub(super) struct ReadModel {
    /// The `v`, `vt`, `vn` arrays and the corners' indices into them;
    /// `part_of` indexes `parts`.
    pub corners: IndexedCorners,
    /// The material each part names (`usemtl`); part 0 is the faces before
    /// any `usemtl` (or after an empty one).
    pub parts: Vec<Option<String>>,
    /// The `mtllib` lines, as written.
    pub libraries: Vec<String>,
    /// One line each, naming the file.
    pub warnings: Vec<String>,
    pub reservation: Reservation,
}

/// Bytes of text per chunk read by one task: below this a file is read as
/// one chunk (splitting would cost more than it gains).
const CHUNK_BYTES: usize = 1 << 20;

/// A problem on a line of a chunk (0-based within the chunk).
type LineProblem = (usize, String);

/// `bytes` cut into at most `parts` pieces of about equal size, each but
/// the last ending just after a `\n`: every piece holds whole lines, and
/// the lines of the pieces, in order, are the lines of `bytes`.
fn line_chunks(bytes: &[u8], parts: usize) -> Vec<&[u8]> {
    let target = bytes.len().div_ceil(parts.max(1)).max(1);
    let mut out = Vec::with_capacity(parts);
    let mut rest = bytes;
    while out.len() + 1 < parts && rest.len() > target {
        match rest[target..].iter().position(|&b| b == b'\n') {
            Some(at) => {
                let (piece, tail) = rest.split_at(target + at + 1);
                out.push(piece);
                rest = tail;
            }
            None => break,
        }
    }
    out.push(rest);
    out
}

/// The kind of the line at `at` (`None` when the counting pass skips
/// it), an `f` line with its corners, and where the next line starts: the
/// usual lines known by their first bytes, the others word by word.
fn counted_line(chunk: &[u8], at: usize) -> (Option<(Kind, usize)>, usize) {
    match kind_at(chunk, at) {
        Some((Kind::Face, words)) => {
            let (corners, next) = words_at(chunk, words);
            (Some((Kind::Face, corners)), next)
        }
        Some((kind, _)) => (Some((kind, 0)), after_ending(chunk, line_end(chunk, at))),
        None => {
            let end = line_end(chunk, at);
            let mut w = words(&chunk[at..end]);
            let kind = match w.next() {
                Some(b"v") => Some((Kind::Position, 0)),
                Some(b"vt") => Some((Kind::Texcoord, 0)),
                Some(b"vn") => Some((Kind::Normal, 0)),
                Some(b"f") => Some((Kind::Face, w.count())),
                _ => None,
            };
            (kind, after_ending(chunk, end))
        }
    }
}

/// The counting pass over one chunk.
fn count(chunk: &[u8]) -> Result<Counts, LineProblem> {
    let mut counts = Counts::default();
    let mut at = 0;
    while at < chunk.len() {
        let (kind, next) = counted_line(chunk, at);
        at = next;
        match kind {
            Some((Kind::Position, _)) => counts.positions += 1,
            Some((Kind::Texcoord, _)) => counts.texcoords += 1,
            Some((Kind::Normal, _)) => counts.normals += 1,
            Some((Kind::Face, corners)) => {
                if corners > MAX_FACE_CORNERS {
                    return Err((
                        counts.lines,
                        format!("a face of {corners} corners (limit {MAX_FACE_CORNERS})"),
                    ));
                }
                counts.triangles += corners.saturating_sub(2);
            }
            None => {}
        }
        counts.lines += 1;
    }
    Ok(counts)
}

/// Where one chunk writes its `v`, `vt` and `vn` lines.
struct Attributes<'a> {
    positions: &'a mut [Vec3],
    /// Made at the chunk's first colour (most files have none), then one
    /// entry for each position from the chunk's first.
    colors: Vec<Option<Vec3>>,
    texcoords: &'a mut [Vec2],
    normals: &'a mut [Vec3],
}

impl Attributes<'_> {
    /// The colour of position `p` (the chunk's): the array is made at the
    /// first colour, earlier positions having none.
    fn add_color(&mut self, p: usize, color: Option<Vec3>) {
        if color.is_some() && self.colors.is_empty() {
            self.colors.reserve_exact(self.positions.len());
            self.colors.resize(p, None);
        }
        if color.is_some() || !self.colors.is_empty() {
            self.colors.push(color);
        }
    }
}

/// Everything read from the faces and keywords of one chunk. Parts are
/// local: part 0 is the one in effect when the chunk begins, the others
/// are `names[k - 1]` in order of first use within the chunk.
#[derive(Default)]
struct FaceChunk {
    /// Triangles written at the start of the chunk's slices.
    triangles: usize,
    names: Vec<Option<String>>,
    /// The local part in effect at the end of the chunk.
    end_part: u32,
    libraries: Vec<String>,
    /// The chunk's positions' colours, when it has any ([`Attributes`]).
    colors: Vec<Option<Vec3>>,
    all_uv: bool,
    all_normals: bool,
    bad_uv: Tally,
    bad_normal: Tally,
    problem: Option<LineProblem>,
}

/// Where one chunk writes its triangles: their corners' indices and their
/// (chunk-local) parts, sized by the counting pass.
struct FaceSlots<'a> {
    corners: &'a mut [[u32; 3]],
    part_of: &'a mut [u32],
}

/// The `v`, `vt` and `vn` lines of one chunk into `out`, its faces into
/// `slots` (both sized by the counting pass), and its `usemtl` and
/// `mtllib` lines, in one walk over its lines; `before` counts the lines of
/// the chunks before it. Stops at the first bad line (`problem`); also
/// returns the lines whose numbers had text after them.
fn read_chunk(
    chunk: &[u8],
    before: Counts,
    out: Attributes,
    slots: FaceSlots,
) -> (FaceChunk, Tally) {
    let mut walk = ChunkWalk {
        before,
        out,
        slots,
        faces: FaceChunk {
            all_uv: true,
            all_normals: true,
            ..FaceChunk::default()
        },
        p: 0,
        t: 0,
        n: 0,
        face: Vec::new(),
        part: 0,
    };
    let mut cut_numbers = Tally::default();
    let (mut at, mut lines) = (0, 0);
    while at < chunk.len() {
        let number = lines;
        lines += 1;
        // The usual lines in one scan; the others (or one of those the
        // scan does not take) word by word, below.
        if let Some(next) = walk.scanned_line(chunk, at, number) {
            at = next;
            continue;
        }
        let end = line_end(chunk, at);
        let line = &chunk[at..end];
        at = after_ending(chunk, end);
        let Some((keyword, rest)) = next_word(line) else {
            continue;
        };
        let mut cut = false;
        if let Err(problem) = walk.word_line((keyword, rest, line), number, &mut cut) {
            walk.faces.problem = Some((number, problem));
            break;
        }
        if cut {
            cut_numbers.add(number);
        }
    }
    walk.faces.end_part = walk.part;
    walk.faces.colors = walk.out.colors;
    (walk.faces, cut_numbers)
}

/// One chunk's walk over its lines: where it writes, and what it has read.
struct ChunkWalk<'a, 'b> {
    /// The lines and items of the chunks before it.
    before: Counts,
    out: Attributes<'a>,
    slots: FaceSlots<'b>,
    faces: FaceChunk,
    /// Items of this chunk so far; faces may use those before it too.
    p: usize,
    t: usize,
    n: usize,
    /// The corners of the face being read (kept to reuse its capacity).
    face: Vec<FaceCorner>,
    /// The chunk-local part in effect.
    part: u32,
}

impl ChunkWalk<'_, '_> {
    /// The positions, texture coordinates and normals a face may use.
    fn counts(&self) -> (usize, usize, usize) {
        (
            self.before.positions + self.p,
            self.before.texcoords + self.t,
            self.before.normals + self.n,
        )
    }

    /// A usual `v`, `vt`, `vn` or `f` line at `at`, read in one scan:
    /// where the next line starts, or `None` when the scan does not take
    /// it (then it is read word by word).
    fn scanned_line(&mut self, chunk: &[u8], at: usize, number: usize) -> Option<usize> {
        let (kind, words) = kind_at(chunk, at)?;
        match kind {
            Kind::Position => numbers_at::<3>(chunk, words)
                .filter(|&(_, len, _)| len == 3)
                .map(|(x, _, next)| {
                    self.out.positions[self.p] = Vec3::from_array(x);
                    self.out.add_color(self.p, None);
                    self.p += 1;
                    next
                }),
            Kind::Texcoord => numbers_at::<3>(chunk, words)
                .filter(|&(_, len, _)| len >= 1)
                .map(|(x, _, next)| {
                    // A missing v is 0.
                    self.out.texcoords[self.t] = Vec2::new(x[0], x[1]);
                    self.t += 1;
                    next
                }),
            Kind::Normal => numbers_at::<3>(chunk, words)
                .filter(|&(_, len, _)| len == 3)
                .map(|(x, _, next)| {
                    self.out.normals[self.n] = Vec3::from_array(x);
                    self.n += 1;
                    next
                }),
            Kind::Face => {
                let counts = self.counts();
                face_at(chunk, words, counts, &mut self.face).inspect(|_| {
                    add_face(
                        &mut self.faces,
                        &mut self.face,
                        (false, false),
                        number,
                        self.part,
                        &mut self.slots,
                    )
                })
            }
        }
    }

    /// A line read word by word: its `keyword`, the `rest` after it, and
    /// the whole `line`. Sets `cut` when a number had text after it.
    fn word_line(
        &mut self,
        (keyword, rest, line): (&[u8], &[u8], &[u8]),
        number: usize,
        cut: &mut bool,
    ) -> Result<(), String> {
        match keyword {
            b"v" => self.position_line(rest, cut),
            b"vt" => numbers(words(rest), 1, 3, "texture coordinate", cut).map(|(x, _)| {
                // A missing v is 0.
                self.out.texcoords[self.t] = Vec2::new(x[0], x[1]);
                self.t += 1;
            }),
            b"vn" => numbers(words(rest), 3, 3, "normal", cut).map(|(x, _)| {
                self.out.normals[self.n] = Vec3::new(x[0], x[1], x[2]);
                self.n += 1;
            }),
            b"mtllib" => {
                self.faces.libraries.push(rest_of_line(line, b"mtllib"));
                Ok(())
            }
            b"usemtl" => {
                self.use_material(rest_of_line(line, b"usemtl"));
                Ok(())
            }
            b"f" => {
                let counts = self.counts();
                read_face(words(rest), counts, &mut self.face).map(|dropped| {
                    add_face(
                        &mut self.faces,
                        &mut self.face,
                        dropped,
                        number,
                        self.part,
                        &mut self.slots,
                    )
                })
            }
            _ => Ok(()),
        }
    }

    /// A `v` line: x y z, with a w that is not 0, or with an r g b colour.
    fn position_line(&mut self, rest: &[u8], cut: &mut bool) -> Result<(), String> {
        let (x, len) = numbers(words(rest), 3, 6, "position", cut)?;
        let color = match len {
            3 => Ok(None),
            4 if x[3] != 0.0 => Ok(None),
            4 => Err("bad w '0'".to_string()),
            6 => Ok(Some(Vec3::new(x[3], x[4], x[5]))),
            k => Err(format!("position has {k} numbers")),
        };
        color.map(|color| {
            self.out.positions[self.p] = Vec3::new(x[0], x[1], x[2]);
            self.out.add_color(self.p, color);
            self.p += 1;
        })
    }

    /// A `usemtl` line: the faces after it are in the part of that material
    /// (none when the name is empty), numbered in order of first use.
    fn use_material(&mut self, material: String) {
        let key = (!material.is_empty()).then_some(material);
        let names = &mut self.faces.names;
        self.part = match names.iter().position(|p| *p == key) {
            Some(i) => i as u32 + 1,
            None => {
                names.push(key);
                names.len() as u32
            }
        };
    }
}

/// The corners of a face read from line `number` (`dropped`: whether a
/// `vt`, and a `vn`, index was out of range) as the triangles of its fan,
/// into `slots` after the chunk's triangles so far.
fn add_face(
    out: &mut FaceChunk,
    face: &mut Vec<FaceCorner>,
    (uv_dropped, normal_dropped): (bool, bool),
    number: usize,
    part: u32,
    slots: &mut FaceSlots,
) {
    if uv_dropped {
        out.bad_uv.add(number);
        face.iter_mut().for_each(|c| c.uv = None);
    }
    if normal_dropped {
        out.bad_normal.add(number);
        face.iter_mut().for_each(|c| c.normal = None);
    }
    while face.len() > 1 && face.first().map(|c| c.position) == face.last().map(|c| c.position) {
        face.pop();
    }
    // One or two corners are a point or a line: not drawn.
    if face.len() >= 3 {
        // A face that lost an attribute gets a computed one; it
        // does not make the model drop the file's everywhere.
        out.all_uv &= uv_dropped || face.iter().all(|c| c.uv.is_some());
        out.all_normals &= normal_dropped || face.iter().all(|c| c.normal.is_some());
        let corner = |c: &FaceCorner| {
            let index = |i: Option<usize>| i.map_or(NO_INDEX, |i| i as u32);
            [c.position as u32, index(c.uv), index(c.normal)]
        };
        for k in 1..face.len() - 1 {
            let t = out.triangles;
            slots.corners[3 * t..3 * t + 3]
                .copy_from_slice(&[&face[0], &face[k], &face[k + 1]].map(corner));
            slots.part_of[t] = part;
            out.triangles += 1;
        }
    }
}

/// The corners of one `f` line into `face`, given the `v`, `vt`, `vn`
/// counts so far. Returns whether a `vt`, and a `vn`, index was out of
/// range (the caller drops that attribute for the whole face).
fn read_face<'a>(
    words: impl Iterator<Item = &'a [u8]>,
    (positions, texcoords, normals): (usize, usize, usize),
    face: &mut Vec<FaceCorner>,
) -> Result<(bool, bool), String> {
    face.clear();
    let (mut uv_dropped, mut normal_dropped) = (false, false);
    for word in words {
        if let Some(corner) = plain_corner(word, (positions, texcoords, normals)) {
            // A repeated position is a zero-length edge.
            if face.last().is_none_or(|p| p.position != corner.position) {
                face.push(corner);
            }
            continue;
        }
        let mut pieces = word.split(|&b| b == b'/');
        let (p, t, n) = (pieces.next(), pieces.next(), pieces.next());
        let p = match p {
            Some(p) if !p.is_empty() && pieces.next().is_none() => p,
            _ => return Err(format!("bad face corner {}", quote_bytes(word))),
        };
        let position = resolve(p, positions, "vertex")?;
        // Out of range: tinyobjloader drops the attribute (with a warning).
        let optional =
            |word: Option<&[u8]>, count: usize, what: &str, dropped: &mut bool| match word {
                Some(x) if !x.is_empty() => match resolve(x, count, what) {
                    Ok(i) => Ok(Some(i)),
                    Err(e) if e.contains("out of range") => {
                        *dropped = true;
                        Ok(None)
                    }
                    Err(e) => Err(e),
                },
                _ => Ok(None),
            };
        let uv = optional(t, texcoords, "texture coordinate", &mut uv_dropped)?;
        let normal = optional(n, normals, "normal", &mut normal_dropped)?;
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
    Ok((uv_dropped, normal_dropped))
}

/// The usual corner, `v`, `v/vt`, `v//vn` or `v/vt/vn` with positive
/// indices in range, read in one scan; none for anything else (the
/// general path then reads it, or says what is wrong with it): see
/// [`corner_at`].
fn plain_corner(word: &[u8], counts: (usize, usize, usize)) -> Option<FaceCorner> {
    corner_at(word, 0, counts).map(|(c, _)| c)
}

/// Reads `bytes` (a whole OBJ file); `name` (already sanitised) is used in
/// errors. Big files are cut into line-aligned chunks read in parallel
/// (see [`read_in_chunks`]).
pub(super) fn read(name: &str, bytes: &[u8]) -> Result<ReadModel, ObjError> {
    let parts = (bytes.len() / CHUNK_BYTES).clamp(1, 4 * rayon::current_num_threads());
    read_in_chunks(name, bytes, parts)
}

/// [`read`] with the text cut into at most `parts` chunks: whatever the
/// cut, the same model, warnings and first error as one chunk gives.
///
/// Two passes, each over the chunks in parallel: counting (sizes and
/// budget are settled before anything of the model's size is allocated),
/// then the reading, each chunk putting its `v`/`vt`/`vn` lines into arrays
/// sized by the counts and its faces into the triangle arrays (each chunk
/// knows where its own start; a face may use any item before its line,
/// whose numbers another chunk may be reading at the same time). Parts, warnings and errors are merged in chunk
/// order, so the first line in the file wins as it does when read in one go.
pub(super) fn read_in_chunks(
    name: &str,
    bytes: &[u8],
    parts: usize,
) -> Result<ReadModel, ObjError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let chunks = line_chunks(bytes, parts);
    // Two passes over the text: the view's progress line counts each
    // chunk's bytes as the counting finishes it and twice as the reading
    // does (it parses what it walks: the units of the three passes this
    // reading once made), and a cancel stops the reading between passes.
    let progress = load_progress::current();
    if let Some(p) = &progress {
        p.begin(LoadStep::Parsing, 3 * bytes.len() as u64);
    }
    let passed = |chunk: &[u8]| {
        if let Some(p) = &progress {
            p.advance(chunk.len() as u64);
        }
    };
    let (before, counts) = count_pass(name, &chunks, &passed)?;
    let mut reservation = reserve_model(name, counts)?;
    let (mut arrays, read) = read_pass(&chunks, &before, counts, &passed);
    load_progress::check(name)?;
    // The first bad line of the file: that of the first chunk with one.
    if let Some((f, b)) = read
        .iter()
        .map(|(f, _)| f)
        .zip(&before)
        .find(|(f, _)| f.problem.is_some())
        && let Some((line, problem)) = &f.problem
    {
        return Err(line_error(name, b.lines + line, problem.clone()));
    }
    let faces = (&mut arrays.corners[..], &mut arrays.part_of[..]);
    let merged = merge_chunks(name, read, &before, counts, faces, &mut reservation)?;
    let triangles = merged.triangles;
    if triangles == 0 {
        let name = name.to_string();
        // Faces were there, but repeated corners left none with three.
        return Err(if counts.triangles > 0 {
            ObjError::Degenerate { name }
        } else {
            ObjError::Empty { name }
        });
    }
    arrays.corners.truncate(3 * triangles);
    arrays.part_of.truncate(triangles);
    let warnings = merged.warnings(name);
    let Merged {
        parts,
        libraries,
        colors,
        all_uv,
        all_normals,
        ..
    } = merged;
    let mut corners = IndexedCorners {
        positions: arrays.positions,
        colors,
        uvs: arrays.texcoords,
        normals: arrays.normals,
        corners: arrays.corners,
        part_of: arrays.part_of,
    };
    keep_used(&mut corners, all_uv, all_normals);
    Ok(ReadModel {
        corners,
        parts,
        libraries,
        warnings,
        reservation,
    })
}

/// Bad line `line` (0-based in the file) of model `name`.
fn line_error(name: &str, line: usize, problem: String) -> ObjError {
    ObjError::Line {
        name: name.to_string(),
        line: line + 1,
        problem,
    }
}

/// The counting pass, over the chunks in parallel: the counts of the
/// chunks before each, and the whole file's; its first bad line, else a
/// cancel, is an error.
fn count_pass(
    name: &str,
    chunks: &[&[u8]],
    passed: &(impl Fn(&[u8]) + Sync),
) -> Result<(Vec<Counts>, Counts), ObjError> {
    let counted: Vec<Result<Counts, LineProblem>> = chunks
        .par_iter()
        .map(|c| {
            let counts = count(c);
            passed(c);
            counts
        })
        .collect();
    load_progress::check(name)?;
    counts_before(counted).map_err(|(l, problem)| line_error(name, l, problem))
}

/// The memory budget for the model the counts describe, asked before
/// anything of its size is allocated; too many items for an index is
/// refused.
fn reserve_model(name: &str, counts: Counts) -> Result<Reservation, ObjError> {
    // No fixed limit: the memory budget decides, before anything is
    // allocated. The text itself is held by whoever read it.
    let need = read_bytes(&counts);
    let reservation = crate::model_io::reserve(name, "the triangles", need)?;
    if counts.positions.max(counts.texcoords).max(counts.normals) >= NO_INDEX as usize {
        return Err(ObjError::Unsupported {
            name: name.to_string(),
            what: format!("more than {} positions, UVs or normals", NO_INDEX - 1),
        });
    }
    Ok(reservation)
}

/// The model's arrays, sized by the counting pass.
struct Arrays {
    positions: Vec<Vec3>,
    texcoords: Vec<Vec2>,
    normals: Vec<Vec3>,
    corners: Vec<[u32; 3]>,
    part_of: Vec<u32>,
}

/// The reading pass, over the chunks in parallel: each chunk fills its
/// own slices of the arrays; what each read besides, in chunk order.
fn read_pass(
    chunks: &[&[u8]],
    before: &[Counts],
    counts: Counts,
    passed: &(impl Fn(&[u8]) + Sync),
) -> (Arrays, Vec<(FaceChunk, Tally)>) {
    // Zeroed by the allocator as fresh pages, each first touched by the
    // chunk that fills it.
    let mut positions: Vec<Vec3> = bytemuck::zeroed_vec(counts.positions);
    let mut texcoords: Vec<Vec2> = bytemuck::zeroed_vec(counts.texcoords);
    let mut normals: Vec<Vec3> = bytemuck::zeroed_vec(counts.normals);
    let outs = attribute_slices(&mut positions, &mut texcoords, &mut normals, before, counts);
    // Each chunk's triangles go to its own slices (at most what it counted),
    // closed up afterwards: no copy of the whole.
    let mut corners = vec![[0u32; 3]; counts.triangles * 3];
    let mut part_of = vec![0u32; counts.triangles];
    let slots = face_slices(&mut corners, &mut part_of, before, counts);
    let read: Vec<(FaceChunk, Tally)> = chunks
        .par_iter()
        .zip(before.par_iter())
        .zip(outs.into_par_iter().zip(slots.into_par_iter()))
        .map(|((chunk, b), (out, slots))| {
            let read = read_chunk(chunk, *b, out, slots);
            passed(chunk);
            passed(chunk);
            read
        })
        .collect();
    let arrays = Arrays {
        positions,
        texcoords,
        normals,
        corners,
        part_of,
    };
    (arrays, read)
}

/// UVs and normals are used when every corner has one; colours when any
/// position has one (the others are white).
fn keep_used(c: &mut IndexedCorners, all_uv: bool, all_normals: bool) {
    if !all_uv {
        c.uvs = Vec::new();
        c.corners.par_iter_mut().for_each(|c| c[1] = NO_INDEX);
    }
    if !all_normals {
        c.normals = Vec::new();
        c.corners.par_iter_mut().for_each(|c| c[2] = NO_INDEX);
    }
    if c.colors.iter().any(Option::is_some) {
        c.colors
            .par_iter_mut()
            .for_each(|c| *c = Some(c.unwrap_or(Vec3::ONE)));
    } else {
        c.colors = Vec::new();
    }
}

/// What comes before each chunk, and the whole file's counts; the first
/// chunk's problem with its line in the file.
fn counts_before(
    counted: Vec<Result<Counts, LineProblem>>,
) -> Result<(Vec<Counts>, Counts), LineProblem> {
    let mut before = Vec::with_capacity(counted.len());
    let mut counts = Counts::default();
    for c in counted {
        match c {
            Ok(c) => {
                before.push(counts);
                counts = counts.add(c);
            }
            Err((line, problem)) => return Err((counts.lines + line, problem)),
        }
    }
    Ok((before, counts))
}

/// The `v`, `vt` and `vn` arrays cut into each chunk's slices (`before`:
/// what comes before each chunk; `counts`: the whole file's).
fn attribute_slices<'a>(
    positions: &'a mut [Vec3],
    texcoords: &'a mut [Vec2],
    normals: &'a mut [Vec3],
    before: &[Counts],
    counts: Counts,
) -> Vec<Attributes<'a>> {
    let mut outs = Vec::with_capacity(before.len());
    let (mut p, mut t, mut n) = (positions, texcoords, normals);
    for (k, b) in before.iter().enumerate() {
        let next = before.get(k + 1).copied().unwrap_or(counts);
        let (p1, p2) = std::mem::take(&mut p).split_at_mut(next.positions - b.positions);
        let (t1, t2) = std::mem::take(&mut t).split_at_mut(next.texcoords - b.texcoords);
        let (n1, n2) = std::mem::take(&mut n).split_at_mut(next.normals - b.normals);
        outs.push(Attributes {
            positions: p1,
            colors: Vec::new(),
            texcoords: t1,
            normals: n1,
        });
        (p, t, n) = (p2, t2, n2);
    }
    outs
}

/// The triangle arrays cut into each chunk's slices, sized by what it
/// counted.
fn face_slices<'a>(
    corners: &'a mut [[u32; 3]],
    part_of: &'a mut [u32],
    before: &[Counts],
    counts: Counts,
) -> Vec<FaceSlots<'a>> {
    let mut slots = Vec::with_capacity(before.len());
    let (mut c, mut p) = (corners, part_of);
    for (k, b) in before.iter().enumerate() {
        let next = before.get(k + 1).copied().unwrap_or(counts);
        let n = next.triangles - b.triangles;
        let (c1, c2) = std::mem::take(&mut c).split_at_mut(3 * n);
        let (p1, p2) = std::mem::take(&mut p).split_at_mut(n);
        slots.push(FaceSlots {
            corners: c1,
            part_of: p1,
        });
        (c, p) = (c2, p2);
    }
    slots
}

/// The chunks merged in order: their triangles closed up, their parts
/// made the file's, what they found added up.
struct Merged {
    triangles: usize,
    parts: Vec<Option<String>>,
    libraries: Vec<String>,
    /// One per position when any chunk has a colour, else empty.
    colors: Vec<Option<Vec3>>,
    all_uv: bool,
    all_normals: bool,
    bad_uv: Tally,
    bad_normal: Tally,
    cut_numbers: Tally,
}

/// Merges the chunks' reading in order into `faces` (the triangles'
/// corners and parts, as the chunks left them in their slices).
fn merge_chunks(
    name: &str,
    read: Vec<(FaceChunk, Tally)>,
    before: &[Counts],
    counts: Counts,
    (corners, part_of): (&mut [[u32; 3]], &mut [u32]),
    reservation: &mut Reservation,
) -> Result<Merged, ObjError> {
    let mut m = Merged {
        triangles: 0,
        parts: vec![None],
        libraries: Vec::new(),
        colors: Vec::new(),
        all_uv: true,
        all_normals: true,
        bad_uv: Tally::default(),
        bad_normal: Tally::default(),
        cut_numbers: Tally::default(),
    };
    let mut part = 0u32;
    // The chunks' colours, when any has one, one after the other (the
    // reading reserved them once; the whole is a second copy for a moment).
    if read.iter().any(|(f, _)| !f.colors.is_empty()) {
        hold(
            reservation,
            name,
            "the colours",
            bytes_of::<Option<Vec3>>(counts.positions as u64),
        )?;
        m.colors.reserve_exact(counts.positions);
    }
    for (k, ((f, cut), b)) in read.into_iter().zip(before).enumerate() {
        if m.colors.capacity() > 0 {
            let next = before.get(k + 1).copied().unwrap_or(counts);
            let from = m.colors.len();
            m.colors.extend(f.colors);
            m.colors.resize(from + next.positions - b.positions, None);
        }
        let global = global_parts(&mut m.parts, part, f.names);
        part = global[f.end_part as usize];
        // A chunk whose triangles are already in place (none before it
        // fell short of its count) and whose parts are the file's is left
        // as it is.
        let (first, triangles) = (b.triangles, m.triangles);
        if first != triangles {
            corners.copy_within(3 * first..3 * (first + f.triangles), 3 * triangles);
        }
        if first != triangles || global.iter().enumerate().any(|(k, &g)| g as usize != k) {
            for t in 0..f.triangles {
                part_of[triangles + t] = global[part_of[first + t] as usize];
            }
        }
        m.triangles += f.triangles;
        m.libraries.extend(f.libraries);
        m.all_uv &= f.all_uv;
        m.all_normals &= f.all_normals;
        m.bad_uv.merge(&f.bad_uv, b.lines);
        m.bad_normal.merge(&f.bad_normal, b.lines);
        m.cut_numbers.merge(&cut, b.lines);
    }
    Ok(m)
}

/// A chunk's local parts as the file's, in order of first use: local part
/// 0 is `part`, the one in effect when the chunk begins; `names` are the
/// others, added to `parts` when new.
fn global_parts(
    parts: &mut Vec<Option<String>>,
    part: u32,
    names: Vec<Option<String>>,
) -> Vec<u32> {
    let mut global = vec![part];
    for key in names {
        global.push(match parts.iter().position(|p| *p == key) {
            Some(i) => i as u32,
            None => {
                parts.push(key);
                (parts.len() - 1) as u32
            }
        });
    }
    global
}

impl Merged {
    /// One warning per kind of line read with something dropped or cut,
    /// naming its first.
    fn warnings(&self, name: &str) -> Vec<String> {
        let mut warnings = Vec::new();
        for (tally, what) in [
            (
                &self.bad_uv,
                "a texture coordinate index out of range: their UVs were dropped",
            ),
            (
                &self.bad_normal,
                "a normal index out of range: their normals were computed",
            ),
            (
                &self.cut_numbers,
                "a number followed by other text (read as the number alone, as tinyobjloader does)",
            ),
        ] {
            if tally.count > 0 {
                warnings.push(format!(
                    "model {name}, line {}: {} line(s) with {what}",
                    tally.first_line + 1,
                    tally.count
                ));
            }
        }
        warnings
    }
}

/// What the reading allocates for a file of `counts`: the `v` (position
/// and optional colour), `vt` and `vn` arrays, each triangle's corner
/// indices and part.
fn read_bytes(counts: &Counts) -> u64 {
    let (p, t) = (counts.positions as u64, counts.triangles as u64);
    bytes_of::<Vec3>(p)
        .saturating_add(bytes_of::<Option<Vec3>>(p))
        .saturating_add(bytes_of::<Vec2>(counts.texcoords as u64))
        .saturating_add(bytes_of::<Vec3>(counts.normals as u64))
        .saturating_add(t.saturating_mul(READ_BYTES_PER_TRIANGLE))
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

    /// A fixed linear congruential walk from `seed`: its high bits, one
    /// draw per call.
    fn lcg(mut seed: u64) -> impl FnMut() -> u64 {
        move || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            seed >> 33
        }
    }

    #[test]
    fn lines_end_with_any_of_the_three_endings() {
        let got: Vec<&[u8]> = lines(b"a\nb\r\nc\rd\n\ne").collect();
        let want: Vec<&[u8]> = vec![b"a", b"b", b"c", b"d", b"", b"e"];
        assert_eq!(got, want);
        assert_eq!(lines(b"").count(), 0);
        assert_eq!(lines(b"x\r\n").count(), 1);
    }

    #[test]
    fn a_line_ends_at_the_first_ending_from_anywhere() {
        // Endings at every distance, before and past the words scanned
        // eight bytes at a time, and none at all.
        let mut next = lcg(5);
        for _ in 0..300 {
            let len = (next() % 200) as usize;
            let text: Vec<u8> = (0..len)
                .map(|_| match next() % 40 {
                    0 => b'\n',
                    1 => b'\r',
                    2 => 0x8A,
                    k => b' ' + k as u8,
                })
                .collect();
            for at in 0..=len {
                let want = text[at..]
                    .iter()
                    .position(|&b| b == b'\n' || b == b'\r')
                    .map_or(len, |e| at + e);
                assert_eq!(line_end(&text, at), want, "{text:?} from {at}");
            }
        }
    }

    #[test]
    fn face_lines_are_counted_as_their_words_say() {
        // Lines of random words, blanks, comments and endings, long
        // enough for the eight-byte steps of the count.
        let mut walk = lcg(0x9e37_79b9_7f4a_7c15);
        let mut next = || walk() as usize;
        let pieces: [&[u8]; 10] = [
            b" ", b"  ", b"\t", b"\x0C", b"12", b"3/4/5", b"#", b"x", b"\xe9", b"//",
        ];
        for _ in 0..20_000 {
            let mut text = b"f ".to_vec();
            for _ in 0..next() % 24 {
                text.extend_from_slice(pieces[next() % pieces.len()]);
            }
            let line_len = text.len();
            text.extend_from_slice([&b"\n"[..], b"\r\n", b"\r"][next() % 3]);
            let next_line = text.len();
            text.extend_from_slice(b"v 1 2 3");
            let want = words(&text[2..line_len]).count();
            let text_shown = String::from_utf8_lossy(&text).into_owned();
            assert_eq!(
                counted_line(&text, 0),
                (Some((Kind::Face, want)), next_line),
                "{text_shown:?}"
            );
        }
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

    /// `str::parse`'s f32 for `text` (what the reader gave before the
    /// plain form was read by hand).
    fn parsed(text: &str) -> f32 {
        text.parse().expect("a number")
    }

    #[test]
    fn plain_numbers_have_the_parser_bits() {
        // Every sign, point place and digit count up to the 19 the plain
        // form takes, over digits from a fixed linear congruential walk.
        let mut next = lcg(0x2545_f491_4f6c_dd1d);
        let mut fast = 0;
        for _ in 0..200_000 {
            let count = 1 + next() as usize % 19;
            let point = next() as usize % (count + 2);
            let mut text = String::from(["", "-", "+"][next() as usize % 3]);
            for k in 0..count {
                if k == point {
                    text.push('.');
                }
                text.push(char::from(b'0' + (next() % 10) as u8));
            }
            if point == count {
                text.push('.');
            }
            if let Some(x) = plain_number(text.as_bytes()) {
                fast += 1;
                assert_eq!(x.to_bits(), parsed(&text).to_bits(), "{text}");
            }
            let (x, cut) = number(text.as_bytes(), "x").expect("a number");
            assert_eq!(
                (x.to_bits(), cut),
                (parsed(&text).to_bits(), false),
                "{text}"
            );
        }
        // Most of them are short enough for the plain form.
        assert!(fast > 100_000, "{fast}");
        for text in ["-0.0", "0", "7.", ".5", "+1.25", "-0.95374536", "1234567.0"] {
            let x = plain_number(text.as_bytes()).expect("plain");
            assert_eq!(x.to_bits(), parsed(text).to_bits(), "{text}");
        }
        // Exponents, more than 19 digits, signs alone and other text
        // take the general path.
        for text in [
            &b"1e5"[..],
            b"1.5E-3",
            b"12345678901234567890",
            b"-",
            b".",
            b"1.2.3",
            b"3.1+e2",
        ] {
            assert_eq!(
                plain_number(text),
                None,
                "{}",
                String::from_utf8_lossy(text)
            );
        }
    }

    #[test]
    fn a_number_whose_f64_is_an_f32_tie_is_left_to_the_parser() {
        // 8.295374393463135 rounds (in f64) to exactly halfway between
        // two f32s; the number itself is above that, so its f32 is the
        // upper one, not the even lower one a second rounding picks.
        let text = "8.295374393463135";
        let (lower, upper) = (f32::from_bits(1_090_828_762), f32::from_bits(1_090_828_763));
        let halfway = (f64::from(lower) + f64::from(upper)) / 2.0;
        assert_eq!(text.parse::<f64>(), Ok(halfway));
        assert_eq!(plain_number(text.as_bytes()), None);
        let (x, _) = number(text.as_bytes(), "x").expect("a number");
        assert_eq!(x.to_bits(), parsed(text).to_bits());
        assert_eq!(x.to_bits(), 1_090_828_763);
        assert_eq!(
            (text.parse::<f64>().unwrap() as f32).to_bits(),
            1_090_828_762
        );
    }

    #[test]
    fn plain_corners_are_read_in_one_scan_and_the_rest_left_to_the_general_path() {
        let counts = (5, 4, 3);
        let corner = |word: &[u8]| plain_corner(word, counts).map(|c| (c.position, c.uv, c.normal));
        assert_eq!(corner(b"5"), Some((4, None, None)));
        assert_eq!(corner(b"1/4"), Some((0, Some(3), None)));
        assert_eq!(corner(b"2//3"), Some((1, None, Some(2))));
        assert_eq!(corner(b"3/1/1"), Some((2, Some(0), Some(0))));
        assert_eq!(corner(b"3/1/"), Some((2, Some(0), None)));
        // Out of range (an error or a dropped attribute), negative, not a
        // number, too many pieces or digits, no position: the general path.
        for word in [
            &b"6"[..],
            b"0",
            b"1/5",
            b"1/1/4",
            b"-1",
            b"1/-1",
            b"/1",
            b"1/1/1/1",
            b"x",
            b"",
            b"0000000000000000001",
        ] {
            assert!(corner(word).is_none(), "{}", String::from_utf8_lossy(word));
        }
        // What the general path reads of those it takes.
        let mut face = Vec::new();
        assert_eq!(
            read_face(words(b"-1 1/5 2//-1"), counts, &mut face),
            Ok((true, false))
        );
        let got: Vec<_> = face.iter().map(|c| (c.position, c.uv, c.normal)).collect();
        assert_eq!(
            got,
            vec![(4, None, None), (0, None, None), (1, None, Some(2))]
        );
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
