//! The usual lines read in one scan of their bytes, the line's end found
//! on the way: `v`, `vt` and `vn` of plain numbers, `f` of plain corners
//! (most of a big file's bytes). A line any of them does not take is left
//! to the general path (`read`), which reads the lines these take to the
//! same bits: plain numbers and corners are read here for both.

/// One face corner: indices into the positions, UVs and normals read so
/// far (both paths read corners into it).
#[derive(Clone, Copy, PartialEq)]
pub(super) struct FaceCorner {
    pub position: usize,
    pub uv: Option<usize>,
    pub normal: Option<usize>,
}

/// Powers of ten that are exact in f64.
const EXACT_POWERS: [f64; 20] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19,
];

/// Whether `b` ends a word: a blank, a `#` or a line's end (a word within
/// a line ends at ASCII whitespace or `#`).
#[inline]
fn ends_word(b: Option<&u8>) -> bool {
    matches!(
        b,
        None | Some(b' ' | b'\t' | b'\x0C' | b'\n' | b'\r' | b'#')
    )
}

/// Where the line whose data stops at `at` ends: the first `\n` or `\r`
/// from `at`, or the text's end.
#[inline]
pub(super) fn line_end(text: &[u8], mut at: usize) -> usize {
    // A usual line ends within a few words: looked for eight bytes at a
    // time first (a search call costs more than a short line's scan).
    for _ in 0..SHORT_LINE_WORDS {
        let Some(eight) = text.get(at..at + 8) else {
            break;
        };
        let x = u64::from_le_bytes(eight.try_into().unwrap_or_default());
        let ends = bytes_equal(x, b'\n') | bytes_equal(x, b'\r');
        if ends != 0 {
            return at + (ends.trailing_zeros() / 8) as usize;
        }
        at += 8;
    }
    memchr::memchr2(b'\n', b'\r', &text[at..]).map_or(text.len(), |e| at + e)
}

/// Words of eight bytes [`line_end`] scans before it searches.
const SHORT_LINE_WORDS: usize = 8;

/// Where the next line starts after a line ending at `end` (a `\n`, a
/// `\r\n`, a lone `\r`, or the text's end).
#[inline]
pub(super) fn after_ending(text: &[u8], end: usize) -> usize {
    match text.get(end) {
        Some(b'\r') if text.get(end + 1) == Some(&b'\n') => end + 2,
        Some(_) => end + 1,
        None => end,
    }
}

/// The plain number (a sign, at most 19 digits and a point, no exponent)
/// starting at `at`, read with the same bits as `str::parse::<f32>` gives,
/// and where it ends; none for anything else, or a number that must go to
/// the parser (see below).
///
/// The digits `w` (below 2^53) and 10^q are exact in f64, so `w / 10^q` is
/// the value rounded once to f64; rounding that to f32 is the value
/// rounded once to f32 unless the f64 lies exactly halfway between two
/// f32s, the one case left to the parser.
#[inline]
pub(super) fn number_at(text: &[u8], mut at: usize) -> Option<(f32, usize)> {
    let negative = text.get(at) == Some(&b'-');
    if matches!(text.get(at), Some(b'-' | b'+')) {
        at += 1;
    }
    // Digits, a point, digits: `w` is exact while there are at most 19
    // (more are left to the parser, so its wrapping does not matter).
    let mut w = 0u64;
    let mut digits = |at: &mut usize| {
        let start = *at;
        while let Some(&b @ b'0'..=b'9') = text.get(*at) {
            w = w.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
            *at += 1;
        }
        *at - start
    };
    let whole = digits(&mut at);
    let fraction = if text.get(at) == Some(&b'.') {
        at += 1;
        digits(&mut at)
    } else {
        0
    };
    let count = whole + fraction;
    if !ends_word(text.get(at)) || count == 0 || count > 19 || w > 1 << 53 {
        return None;
    }
    let x = w as f64 / EXACT_POWERS[fraction];
    // The 29 bits an f32 drops from an f64's 52: exactly half is a tie
    // the f64 may have made.
    if x.to_bits() & 0x1FFF_FFFF == 0x1000_0000 {
        return None;
    }
    let x = x as f32;
    Some((if negative { -x } else { x }, at))
}

/// The numbers of a line whose words start at `at` (after its keyword),
/// how many, and where the next line starts; none when a word is not a
/// plain number or there are more than `N`.
#[inline]
pub(super) fn numbers_at<const N: usize>(
    text: &[u8],
    mut at: usize,
) -> Option<([f32; N], usize, usize)> {
    let mut out = [0.0; N];
    let mut len = 0;
    loop {
        match text.get(at) {
            Some(b' ' | b'\t' | b'\x0C') => at += 1,
            Some(b'#') => return Some((out, len, after_ending(text, line_end(text, at)))),
            Some(b'\n' | b'\r') | None => return Some((out, len, after_ending(text, at))),
            Some(_) if len == N => return None,
            Some(_) => {
                let (x, next) = number_at(text, at)?;
                out[len] = x;
                len += 1;
                at = next;
            }
        }
    }
}

/// At most 18 digits from `at`: their value, how many, and where they end;
/// none when there are more.
#[inline]
fn index_at(text: &[u8], mut at: usize) -> Option<(u64, usize, usize)> {
    let start = at;
    let mut value = 0u64;
    // Past 18 digits the value may wrap, but is then not used.
    while let Some(&b @ b'0'..=b'9') = text.get(at) {
        value = value.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
        at += 1;
    }
    (at - start <= 18).then_some((value, at - start, at))
}

/// The usual corner, `v`, `v/vt`, `v//vn` or `v/vt/vn` with positive
/// indices in range of the `v`, `vt`, `vn` counts so far, starting at
/// `at`, and where it ends; none for anything else (the general path then
/// reads it, or says what is wrong with it).
#[inline]
pub(super) fn corner_at(
    text: &[u8],
    at: usize,
    (positions, texcoords, normals): (usize, usize, usize),
) -> Option<(FaceCorner, usize)> {
    let (p, p_digits, mut at) = index_at(text, at)?;
    let (mut t, mut n) = ((0, 0), (0, 0));
    if text.get(at) == Some(&b'/') {
        let (value, digits, next) = index_at(text, at + 1)?;
        (t, at) = ((value, digits), next);
        if text.get(at) == Some(&b'/') {
            let (value, digits, next) = index_at(text, at + 1)?;
            (n, at) = ((value, digits), next);
        }
    }
    if !ends_word(text.get(at)) || p_digits == 0 || !(1..=positions as u64).contains(&p) {
        return None;
    }
    // An index of no digits is none, one in range is 0-based.
    let item = |(index, digits): (u64, usize), count: usize| match digits {
        0 => Some(None),
        _ => (1..=count as u64)
            .contains(&index)
            .then(|| Some(index as usize - 1)),
    };
    let corner = FaceCorner {
        position: p as usize - 1,
        uv: item(t, texcoords)?,
        normal: item(n, normals)?,
    };
    Some((corner, at))
}

/// The corners of an `f` line whose words start at `at` into `face` (a
/// corner repeating the previous one's position dropped, as the general
/// path does), and where the next line starts; none when a corner is not
/// plain ([`corner_at`]).
#[inline]
pub(super) fn face_at(
    text: &[u8],
    mut at: usize,
    counts: (usize, usize, usize),
    face: &mut Vec<FaceCorner>,
) -> Option<usize> {
    face.clear();
    loop {
        match text.get(at) {
            Some(b' ' | b'\t' | b'\x0C') => at += 1,
            Some(b'#') => return Some(after_ending(text, line_end(text, at))),
            Some(b'\n' | b'\r') | None => return Some(after_ending(text, at)),
            Some(_) => {
                let (corner, next) = corner_at(text, at, counts)?;
                // A repeated position is a zero-length edge.
                if face.last().is_none_or(|p| p.position != corner.position) {
                    face.push(corner);
                }
                at = next;
            }
        }
    }
}

/// A byte of `x` (eight bytes) equal to `b`, as its top bit (exact:
/// nothing carries from one byte to the next).
#[inline]
fn bytes_equal(x: u64, b: u8) -> u64 {
    const LOW: u64 = 0x7F7F_7F7F_7F7F_7F7F;
    let y = x ^ (0x0101_0101_0101_0101 * u64::from(b));
    !(((y & LOW) + LOW) | y) & !LOW
}

/// The number of words of a line from `at` (its `#` comment cut), and
/// where the next line starts: an `f` line's corners, counted.
#[inline]
pub(super) fn words_at(text: &[u8], mut at: usize) -> (usize, usize) {
    let (mut words, mut in_word) = (0, false);
    // Eight bytes at a time while they hold no line end, `#`, tab or form
    // feed: a word starts at each non-space after a space.
    while let Some(eight) = text.get(at..at + 8) {
        let x = u64::from_le_bytes(eight.try_into().unwrap_or_default());
        let odd = [b'\n', b'\r', b'#', b'\t', b'\x0C']
            .iter()
            .fold(0, |m, &b| m | bytes_equal(x, b));
        if odd != 0 {
            break;
        }
        let space = bytes_equal(x, b' ');
        let word = !space & 0x8080_8080_8080_8080;
        // Whether the byte before each one is a space (or no word).
        let after_space = space << 8 | u64::from(!in_word) << 7;
        words += (word & after_space).count_ones() as usize;
        in_word = word >> 63 != 0;
        at += 8;
    }
    loop {
        match text.get(at) {
            Some(b' ' | b'\t' | b'\x0C') => in_word = false,
            Some(b'#') => return (words, after_ending(text, line_end(text, at))),
            Some(b'\n' | b'\r') | None => return (words, after_ending(text, at)),
            Some(_) => {
                words += usize::from(!in_word);
                in_word = true;
            }
        }
        at += 1;
    }
}

/// The usual keywords, followed by a blank: the line kinds read here.
#[derive(Clone, Copy, PartialEq, Debug)]
pub(super) enum Kind {
    Position,
    Texcoord,
    Normal,
    Face,
}

/// The kind of the line starting at `at` when it starts with `v`, `vt`,
/// `vn` or `f` and a blank, and where its words start; none for any other
/// line (the general path reads those).
#[inline]
pub(super) fn kind_at(text: &[u8], at: usize) -> Option<(Kind, usize)> {
    let blank = |k: usize| matches!(text.get(at + k), Some(b' ' | b'\t' | b'\x0C'));
    match text.get(at)? {
        b'f' if blank(1) => Some((Kind::Face, at + 2)),
        b'v' if blank(1) => Some((Kind::Position, at + 2)),
        b'v' if blank(2) => match text[at + 1] {
            b't' => Some((Kind::Texcoord, at + 3)),
            b'n' => Some((Kind::Normal, at + 3)),
            _ => None,
        },
        _ => None,
    }
}
