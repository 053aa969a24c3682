//! A small, strict XPM3 decoder (no crate in the ecosystem reads XPM).
//!
//! Accepted: the `/* XPM */` comment, a C array of string literals (comments
//! allowed between them), the `"width height ncolors cpp [x y] [XPMEXT]"`
//! header, a colour table whose entries carry a `c` key (or, failing that,
//! `g`, `g4` or `m`), colours written `#RGB`, `#RRGGBB`, `#RRRRGGGGBBBB`,
//! `None` (transparent) or an X11 name from a short table, and pixel rows of
//! `width × cpp` characters. Anything else is an error that says what and where.

use std::collections::HashMap;

/// A decoded XPM: RGBA in 0..1, **top row first** (as written in the file).
#[derive(Clone, Debug, PartialEq)]
pub struct XpmImage {
    pub width: usize,
    pub height: usize,
    /// True when the colour table has a `None` (transparent) entry.
    pub has_alpha: bool,
    pub rgba: Vec<[f32; 4]>,
}

/// What is wrong with an XPM file, in one line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct XpmError(pub String);

fn err<T>(msg: impl Into<String>) -> Result<T, XpmError> {
    Err(XpmError(msg.into()))
}

/// Largest chars-per-pixel accepted (real files use 1 to 4).
const MAX_CPP: usize = 8;

/// True when `bytes` starts (after blanks) with the XPM3 magic comment.
pub fn looks_like_xpm(bytes: &[u8]) -> bool {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let rest = &bytes[start..];
    let rest = rest.strip_prefix(b"/*").unwrap_or(b"");
    let n = rest
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(rest.len());
    rest[n..].starts_with(b"XPM")
}

/// Decodes an XPM3 file. `max_texels` bounds width × height before anything
/// of that size is allocated.
pub fn decode(bytes: &[u8], max_texels: usize) -> Result<XpmImage, XpmError> {
    if !looks_like_xpm(bytes) {
        return err("missing the '/* XPM */' header (only XPM3 is read)");
    }
    let strings = string_literals(bytes)?;
    let Some((header, rest)) = strings.split_first() else {
        return err("no header string");
    };
    let header = Header::parse(header)?;
    let texels = header.width.checked_mul(header.height);
    match texels {
        Some(n) if n <= max_texels => {}
        _ => {
            return err(format!(
                "{}x{} pixels is too large (limit {max_texels} pixels)",
                header.width, header.height
            ));
        }
    }
    if rest.len() < header.colors + header.height {
        return err(format!(
            "truncated: {} colours and {} rows announced, {} strings found",
            header.colors,
            header.height,
            rest.len()
        ));
    }
    let (table, rest) = rest.split_at(header.colors);
    let (rows, extra) = rest.split_at(header.height);
    check_extensions(extra, header.extensions)?;

    let mut colours: HashMap<&[u8], [f32; 4]> = HashMap::with_capacity(table.len());
    let mut has_alpha = false;
    for (i, entry) in table.iter().enumerate() {
        let (key, colour) = parse_colour_entry(entry, header.cpp)
            .map_err(|XpmError(m)| XpmError(format!("colour {}: {m}", i + 1)))?;
        has_alpha |= colour[3] < 1.0;
        if colours.insert(key, colour).is_some() {
            return err(format!(
                "colour {}: pixel code '{}' defined twice",
                i + 1,
                String::from_utf8_lossy(key)
            ));
        }
    }

    let row_len = header.width * header.cpp;
    for (y, row) in rows.iter().enumerate() {
        if row.len() != row_len {
            return err(format!(
                "row {}: {} characters, expected {} ({} pixels x {} chars)",
                y + 1,
                row.len(),
                row_len,
                header.width,
                header.cpp
            ));
        }
    }
    let mut rgba = Vec::with_capacity(header.width * header.height);
    for (y, row) in rows.iter().enumerate() {
        for (x, code) in row.chunks_exact(header.cpp).enumerate() {
            match colours.get(code) {
                Some(c) => rgba.push(*c),
                None => {
                    return err(format!(
                        "row {}, column {}: pixel code '{}' is not in the colour table",
                        y + 1,
                        x + 1,
                        String::from_utf8_lossy(code)
                    ));
                }
            }
        }
    }
    Ok(XpmImage {
        width: header.width,
        height: header.height,
        has_alpha,
        rgba,
    })
}

struct Header {
    width: usize,
    height: usize,
    colors: usize,
    cpp: usize,
    extensions: bool,
}

impl Header {
    fn parse(text: &[u8]) -> Result<Header, XpmError> {
        let text = std::str::from_utf8(text).map_err(|_| XpmError("header is not text".into()))?;
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        let extensions = words.last() == Some(&"XPMEXT");
        let numbers = if extensions {
            &words[..words.len() - 1]
        } else {
            &words[..]
        };
        if numbers.len() != 4 && numbers.len() != 6 {
            return err(format!(
                "header '{text}' must be \"width height colours chars-per-pixel [x y] [XPMEXT]\""
            ));
        }
        let mut values = [0usize; 6];
        for (slot, word) in values.iter_mut().zip(numbers) {
            *slot = word
                .parse()
                .map_err(|_| XpmError(format!("header: '{word}' is not a whole number")))?;
        }
        let [width, height, colors, cpp, ..] = values;
        if width == 0 || height == 0 {
            return err(format!("empty picture ({width}x{height})"));
        }
        if colors == 0 {
            return err("header announces no colours");
        }
        if cpp == 0 || cpp > MAX_CPP {
            return err(format!(
                "{cpp} characters per pixel (1 to {MAX_CPP} accepted)"
            ));
        }
        Ok(Header {
            width,
            height,
            colors,
            cpp,
            extensions,
        })
    }
}

/// After the pixel rows: nothing, or (when the header says XPMEXT) extension
/// strings ending with `XPMENDEXT`.
fn check_extensions(extra: &[&[u8]], announced: bool) -> Result<(), XpmError> {
    if extra.is_empty() {
        return Ok(());
    }
    if announced && extra.last().is_some_and(|s| s.starts_with(b"XPMENDEXT")) {
        return Ok(());
    }
    err(format!(
        "{} string(s) after the last pixel row",
        extra.len()
    ))
}

/// The C string literals of the array, in order, without quotes. Comments
/// are skipped; the array must open with `{` and close with `}`.
fn string_literals(bytes: &[u8]) -> Result<Vec<&[u8]>, XpmError> {
    let mut i = 0;
    let mut line = 1;
    let mut out = Vec::new();
    let mut opened = false;
    let skip_comment = |i: &mut usize, line: &mut usize| -> Result<(), XpmError> {
        // At "/*": find "*/".
        let start_line = *line;
        *i += 2;
        while *i + 1 < bytes.len() {
            if bytes[*i] == b'*' && bytes[*i + 1] == b'/' {
                *i += 2;
                return Ok(());
            }
            if bytes[*i] == b'\n' {
                *line += 1;
            }
            *i += 1;
        }
        err(format!("comment opened on line {start_line} never closes"))
    };
    // The declaration: anything up to '{', comments skipped.
    while i < bytes.len() {
        match bytes[i] {
            b'/' if bytes.get(i + 1) == Some(&b'*') => skip_comment(&mut i, &mut line)?,
            b'{' => {
                opened = true;
                i += 1;
                break;
            }
            b'"' => return err(format!("line {line}: string before the array's '{{'")),
            b'\n' => {
                line += 1;
                i += 1;
            }
            _ => i += 1,
        }
    }
    if !opened {
        return err("no '{' opening the array of strings");
    }
    let mut expect_string = true;
    loop {
        let Some(&b) = bytes.get(i) else {
            return err("truncated: the array of strings never closes with '}'");
        };
        match b {
            b'\n' => {
                line += 1;
                i += 1;
            }
            b if b.is_ascii_whitespace() => i += 1,
            b'/' if bytes.get(i + 1) == Some(&b'*') => skip_comment(&mut i, &mut line)?,
            b'"' => {
                if !expect_string {
                    return err(format!("line {line}: missing ',' between strings"));
                }
                let start = i + 1;
                let mut j = start;
                loop {
                    match bytes.get(j) {
                        None | Some(b'\n') => {
                            return err(format!("line {line}: string not closed"));
                        }
                        Some(b'"') => break,
                        Some(b'\\') => {
                            return err(format!(
                                "line {line}: escape sequences are not allowed in XPM strings"
                            ));
                        }
                        Some(_) => j += 1,
                    }
                }
                out.push(&bytes[start..j]);
                i = j + 1;
                expect_string = false;
            }
            b',' if !expect_string => {
                expect_string = true;
                i += 1;
            }
            b'}' => {
                if out.is_empty() {
                    return err("the array holds no strings");
                }
                return Ok(out);
            }
            other => {
                return err(format!(
                    "line {line}: unexpected character '{}'",
                    char::from(other).escape_default()
                ));
            }
        }
    }
}

/// One colour-table entry: `<code> <key> <value> [<key> <value>]…`.
fn parse_colour_entry(entry: &[u8], cpp: usize) -> Result<(&[u8], [f32; 4]), XpmError> {
    if entry.len() < cpp {
        return err("shorter than its pixel code");
    }
    let (code, rest) = entry.split_at(cpp);
    let rest = std::str::from_utf8(rest).map_err(|_| XpmError("not text".into()))?;
    let mut pairs: Vec<(&str, Vec<&str>)> = Vec::new();
    for word in rest.split_ascii_whitespace() {
        if matches!(word, "c" | "m" | "g" | "g4" | "s") {
            pairs.push((word, Vec::new()));
        } else if let Some((_, value)) = pairs.last_mut() {
            value.push(word);
        } else {
            return err(format!("'{word}' is not a key (c, m, g, g4 or s)"));
        }
    }
    if let Some((key, _)) = pairs.iter().find(|(_, v)| v.is_empty()) {
        return err(format!("key '{key}' has no value"));
    }
    // Colour visual first, then the greyscale and mono ones.
    let value = ["c", "g", "g4", "m"]
        .iter()
        .find_map(|k| pairs.iter().find(|(key, _)| key == k))
        .map(|(_, v)| v.join(" "))
        .ok_or_else(|| XpmError("no 'c' colour".into()))?;
    Ok((code, parse_colour(&value)?))
}

/// `#RGB`, `#RRGGBB`, `#RRRRGGGGBBBB`, `None` or an X11 name.
pub fn parse_colour(value: &str) -> Result<[f32; 4], XpmError> {
    if let Some(hex) = value.strip_prefix('#') {
        let digits = hex.len() / 3;
        if hex.len() % 3 != 0 || !matches!(digits, 1 | 2 | 4) {
            return err(format!(
                "colour '{value}' must be #RGB, #RRGGBB or #RRRRGGGGBBBB"
            ));
        }
        let max = ((1u32 << (4 * digits)) - 1) as f32;
        let mut rgb = [0.0f32; 3];
        for (c, slot) in rgb.iter_mut().enumerate() {
            let part = &hex[c * digits..(c + 1) * digits];
            let n = u32::from_str_radix(part, 16)
                .map_err(|_| XpmError(format!("colour '{value}' has a non-hex digit")))?;
            *slot = n as f32 / max;
        }
        return Ok([rgb[0], rgb[1], rgb[2], 1.0]);
    }
    let name: String = value
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect();
    if name == "none" {
        return Ok([0.0, 0.0, 0.0, 0.0]);
    }
    let rgb = named(&name)
        .ok_or_else(|| XpmError(format!("unknown colour name '{value}' (use #RRGGBB)")))?;
    Ok([
        rgb[0] as f32 / 255.0,
        rgb[1] as f32 / 255.0,
        rgb[2] as f32 / 255.0,
        1.0,
    ])
}

/// X11's greyN levels (rgb.txt), N = 0..=100: its rounding is not one formula.
const GREY_LEVELS: [u8; 101] = [
    0, 3, 5, 8, 10, 13, 15, 18, 20, 23, 26, 28, 31, 33, 36, 38, 41, 43, 46, 48, 51, 54, 56, 59, 61,
    64, 66, 69, 71, 74, 77, 79, 82, 84, 87, 89, 92, 94, 97, 99, 102, 105, 107, 110, 112, 115, 117,
    120, 122, 125, 127, 130, 133, 135, 138, 140, 143, 145, 148, 150, 153, 156, 158, 161, 163, 166,
    168, 171, 173, 176, 179, 181, 184, 186, 189, 191, 194, 196, 199, 201, 204, 207, 209, 212, 214,
    217, 219, 222, 224, 227, 229, 232, 235, 237, 240, 242, 245, 247, 250, 252, 255,
];

/// A few X11 colour names (lower case, no spaces), enough for the files
/// ImageMagick and GIMP write.
fn named(name: &str) -> Option<[u8; 3]> {
    let grey = name
        .strip_prefix("gray")
        .or_else(|| name.strip_prefix("grey"));
    if let Some(level) = grey
        && !level.is_empty()
    {
        let n: usize = level.parse().ok()?;
        let v = *GREY_LEVELS.get(n)?;
        return Some([v, v, v]);
    }
    Some(match name {
        "black" => [0, 0, 0],
        "white" => [255, 255, 255],
        "red" => [255, 0, 0],
        "green" => [0, 255, 0],
        "blue" => [0, 0, 255],
        "yellow" => [255, 255, 0],
        "cyan" => [0, 255, 255],
        "magenta" => [255, 0, 255],
        "gray" | "grey" => [190, 190, 190],
        "lightgray" | "lightgrey" => [211, 211, 211],
        "darkgray" | "darkgrey" => [169, 169, 169],
        "dimgray" | "dimgrey" => [105, 105, 105],
        "gainsboro" => [220, 220, 220],
        "orange" => [255, 165, 0],
        "brown" => [165, 42, 42],
        "navy" | "navyblue" => [0, 0, 128],
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "/* XPM */\nstatic char *x[] = {\n/* w h n cpp */\n\"3 2 3 2\",\n\"aa c #FF0000\",\n\"bb c None\",\n\"c. c #0f0\",\n\"aabbc.\",\n\"c.c.aa\"\n};\n";

    #[test]
    fn decodes_a_small_file_with_two_chars_per_pixel() {
        let img = decode(SMALL.as_bytes(), 100).unwrap();
        assert_eq!((img.width, img.height, img.has_alpha), (3, 2, true));
        assert_eq!(img.rgba[0], [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(img.rgba[1], [0.0, 0.0, 0.0, 0.0]);
        assert_eq!(img.rgba[2], [0.0, 1.0, 0.0, 1.0]);
        assert_eq!(img.rgba[5], [1.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn colours_in_every_notation() {
        assert_eq!(parse_colour("#fff").unwrap(), [1.0; 4]);
        assert_eq!(parse_colour("#000000").unwrap(), [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(parse_colour("#FFFF00000000").unwrap(), [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(parse_colour("None").unwrap(), [0.0; 4]);
        assert_eq!(parse_colour("White").unwrap(), [1.0; 4]);
        assert_eq!(parse_colour("light gray").unwrap()[0], 211.0 / 255.0);
        assert_eq!(parse_colour("grey50").unwrap()[1], 127.0 / 255.0);
        assert!(parse_colour("#12").is_err());
        assert!(parse_colour("#GGGGGG").is_err());
        assert!(parse_colour("gray101").is_err());
        assert!(parse_colour("chartreuse-ish").is_err());
    }

    #[test]
    fn malformed_files_say_what_is_wrong() {
        let cases: &[(&str, &str)] = &[
            ("P6\n1 1\n255\n", "header"),
            (
                "/* XPM */ static char *x[] = {\"1 1 1 1\", \"a c #000\"};",
                "truncated",
            ),
            (
                "/* XPM */ static char *x[] = {\"1 1 1 1\", \"a c #000\", \"b\"};",
                "not in the colour table",
            ),
            (
                "/* XPM */ static char *x[] = {\"2 1 1 1\", \"a c #000\", \"a\"};",
                "row 1",
            ),
            (
                "/* XPM */ static char *x[] = {\"1 1 1 1\", \"a c #000\", \"a\"",
                "never closes",
            ),
            (
                "/* XPM */ static char *x[] = {\"1 1 1 1\" \"a c #000\", \"a\"};",
                "missing ','",
            ),
            (
                "/* XPM */ static char *x[] = {\"1 1 1 1\", \"a q #000\", \"a\"};",
                "not a key",
            ),
            (
                "/* XPM */ static char *x[] = {\"0 1 1 1\", \"a c #000\"};",
                "empty picture",
            ),
            (
                "/* XPM */ static char *x[] = {\"1 1 1 9\", \"a c #000\", \"a\"};",
                "characters per pixel",
            ),
            (
                "/* XPM */ static char *x[] = {\"1 1 2 1\", \"a c #000\", \"a c #fff\", \"a\"};",
                "twice",
            ),
            (
                "/* XPM */ static char *x[] = {\"1 1 1 1\", \"a m white\", \"a\", \"extra\"};",
                "after the last",
            ),
            (
                "/* XPM */ static char *x[] = {\"99999 99999 1 1\", \"a c #000\", \"a\"};",
                "too large",
            ),
        ];
        for (text, needle) in cases {
            let e = decode(text.as_bytes(), 1 << 24).unwrap_err();
            assert!(e.0.contains(needle), "{text:?}: {e} (wanted '{needle}')");
        }
    }

    #[test]
    fn mono_key_is_used_when_there_is_no_colour_key() {
        let text = "/* XPM */ static char *x[] = {\"1 1 1 1\", \"a m white\", \"a\"};";
        assert_eq!(decode(text.as_bytes(), 10).unwrap().rgba, vec![[1.0; 4]]);
    }
}
