//! A small XPM3 decoder (no crate in the ecosystem reads XPM), as lenient as
//! libXpm where real icons need it and strict elsewhere.
//!
//! Accepted: the `/* XPM */` comment, a C array of string literals (comments
//! allowed between them, the ',' between two strings optional), the `"width height ncolors cpp [x y] [XPMEXT]"`
//! header, a colour table whose entries carry a `c` key (or, failing that,
//! `g`, `g4` or `m`), colours written `#RGB`, `#RRGGBB`, `#RRRRGGGGBBBB`,
//! `#RRRGGGBBB`, `None` or `transparent`, or any X11 colour name (the whole
//! `rgb.txt` list, in any case, blanks ignored), and pixel rows of
//! `width × cpp` characters; strings after the last row (extensions, a stray
//! row) are ignored. Anything else is an error that says what and where.

use std::collections::HashMap;

mod colors;
use colors::X11_COLORS;

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

/// Text from the file as messages quote it: control characters replaced,
/// at most 32 characters, in quotes.
fn shown(text: &str) -> String {
    let mut s: String = relief_core::sanitize::clean(text)
        .chars()
        .take(32)
        .collect();
    if text.chars().count() > 32 {
        s.push('…');
    }
    format!("'{s}'")
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
    header.check_size(max_texels)?;
    header.check_string_count(rest)?;
    let (table, rest) = rest.split_at(header.colors);
    // Strings after the last row (XPMEXT extensions, or a stray extra row
    // as some real icons have) are ignored, as libXpm ignores them.
    let rows = &rest[..header.height];
    let colours = Colours::parse(table, header.cpp)?;
    header.check_row_lengths(rows)?;
    let rgba = header.pixels(rows, &colours)?;
    Ok(XpmImage {
        width: header.width,
        height: header.height,
        has_alpha: colours.has_alpha,
        rgba,
    })
}

/// The colour table: each pixel code's colour.
struct Colours<'a> {
    by_code: HashMap<&'a [u8], [f32; 4]>,
    /// True when an entry is transparent (`None`).
    has_alpha: bool,
}

impl<'a> Colours<'a> {
    /// The entries of `table`, each code `cpp` characters; a code defined
    /// twice is an error.
    fn parse(table: &[&'a [u8]], cpp: usize) -> Result<Colours<'a>, XpmError> {
        let mut colours: HashMap<&[u8], [f32; 4]> = HashMap::with_capacity(table.len());
        let mut has_alpha = false;
        for (i, entry) in table.iter().enumerate() {
            let (key, colour) = parse_colour_entry(entry, cpp)
                .map_err(|XpmError(m)| XpmError(format!("colour {}: {m}", i + 1)))?;
            has_alpha |= colour[3] < 1.0;
            if colours.insert(key, colour).is_some() {
                return err(format!(
                    "colour {}: pixel code {} defined twice",
                    i + 1,
                    shown(&String::from_utf8_lossy(key))
                ));
            }
        }
        Ok(Colours {
            by_code: colours,
            has_alpha,
        })
    }
}

struct Header {
    width: usize,
    height: usize,
    colors: usize,
    cpp: usize,
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
                "header {} must be \"width height colours chars-per-pixel [x y] [XPMEXT]\"",
                shown(text)
            ));
        }
        let mut values = [0usize; 6];
        for (slot, word) in values.iter_mut().zip(numbers) {
            *slot = word
                .parse()
                .map_err(|_| XpmError(format!("header: {} is not a whole number", shown(word))))?;
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
        })
    }

    /// Refuses a picture of more than `max_texels` pixels.
    fn check_size(&self, max_texels: usize) -> Result<(), XpmError> {
        let texels = self.width.checked_mul(self.height);
        match texels {
            Some(n) if n <= max_texels => Ok(()),
            _ => err(format!(
                "{}x{} pixels is too large (limit {max_texels} pixels)",
                self.width, self.height
            )),
        }
    }

    /// Refuses `rest` (the strings after the header) when it holds fewer
    /// strings than the colour table and rows announced.
    fn check_string_count(&self, rest: &[&[u8]]) -> Result<(), XpmError> {
        if rest.len() < self.colors + self.height {
            return err(format!(
                "truncated: {} colours and {} rows announced, {} strings found",
                self.colors,
                self.height,
                rest.len()
            ));
        }
        Ok(())
    }

    /// Refuses the first row that is not `width × cpp` characters long
    /// (checked for every row before any pixel is looked up).
    fn check_row_lengths(&self, rows: &[&[u8]]) -> Result<(), XpmError> {
        let row_len = self.width * self.cpp;
        for (y, row) in rows.iter().enumerate() {
            if row.len() != row_len {
                return err(format!(
                    "row {}: {} characters, expected {} ({} pixels x {} chars)",
                    y + 1,
                    row.len(),
                    row_len,
                    self.width,
                    self.cpp
                ));
            }
        }
        Ok(())
    }

    /// Each pixel's colour, top row first.
    fn pixels(&self, rows: &[&[u8]], colours: &Colours) -> Result<Vec<[f32; 4]>, XpmError> {
        let mut rgba = Vec::with_capacity(self.width * self.height);
        for (y, row) in rows.iter().enumerate() {
            for (x, code) in row.chunks_exact(self.cpp).enumerate() {
                match colours.by_code.get(code) {
                    Some(c) => rgba.push(*c),
                    None => {
                        return err(format!(
                            "row {}, column {}: pixel code {} is not in the colour table",
                            y + 1,
                            x + 1,
                            shown(&String::from_utf8_lossy(code))
                        ));
                    }
                }
            }
        }
        Ok(rgba)
    }
}

/// The C string literals of the array, in order, without quotes. Comments
/// are skipped; the array must open with `{` and close with `}`.
fn string_literals(bytes: &[u8]) -> Result<Vec<&[u8]>, XpmError> {
    let mut scanner = Scanner {
        bytes,
        i: 0,
        line: 1,
    };
    scanner.open_array()?;
    scanner.array_strings()
}

/// A position in the file, with its line number for messages.
struct Scanner<'a> {
    bytes: &'a [u8],
    i: usize,
    line: usize,
}

impl<'a> Scanner<'a> {
    /// Whether a comment opens here ("/*").
    fn at_comment(&self) -> bool {
        self.bytes[self.i] == b'/' && self.bytes.get(self.i + 1) == Some(&b'*')
    }

    /// At "/*": moves past the "*/" that closes it.
    fn skip_comment(&mut self) -> Result<(), XpmError> {
        let bytes = self.bytes;
        let start_line = self.line;
        self.i += 2;
        while self.i + 1 < bytes.len() {
            if bytes[self.i] == b'*' && bytes[self.i + 1] == b'/' {
                self.i += 2;
                return Ok(());
            }
            if bytes[self.i] == b'\n' {
                self.line += 1;
            }
            self.i += 1;
        }
        err(format!("comment opened on line {start_line} never closes"))
    }

    /// The declaration: anything up to '{' (moved past), comments skipped.
    fn open_array(&mut self) -> Result<(), XpmError> {
        while self.i < self.bytes.len() {
            let line = self.line;
            match self.bytes[self.i] {
                b'/' if self.at_comment() => self.skip_comment()?,
                b'{' => {
                    self.i += 1;
                    return Ok(());
                }
                b'"' => return err(format!("line {line}: string before the array's '{{'")),
                b'\n' => {
                    self.line += 1;
                    self.i += 1;
                }
                _ => self.i += 1,
            }
        }
        err("no '{' opening the array of strings")
    }

    /// The strings up to the '}' that closes the array.
    fn array_strings(&mut self) -> Result<Vec<&'a [u8]>, XpmError> {
        let mut out = Vec::new();
        let mut after_string = false;
        loop {
            let Some(&b) = self.bytes.get(self.i) else {
                return err("truncated: the array of strings never closes with '}'");
            };
            let line = self.line;
            match b {
                b'\n' => {
                    self.line += 1;
                    self.i += 1;
                }
                b if b.is_ascii_whitespace() => self.i += 1,
                b'/' if self.at_comment() => self.skip_comment()?,
                // A missing ',' between two strings is read as libXpm reads
                // it (two strings), not as C would (one).
                b'"' => {
                    out.push(self.string()?);
                    after_string = true;
                }
                b',' if after_string => {
                    after_string = false;
                    self.i += 1;
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

    /// At '"': the string up to the next '"' (moved past), which must close
    /// it on the same line, with no escape sequence.
    fn string(&mut self) -> Result<&'a [u8], XpmError> {
        let line = self.line;
        let start = self.i + 1;
        let mut j = start;
        loop {
            match self.bytes.get(j) {
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
        self.i = j + 1;
        Ok(&self.bytes[start..j])
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
            return err(format!("{} is not a key (c, m, g, g4 or s)", shown(word)));
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

/// `#RGB`, `#RRGGBB`, `#RRRGGGBBB`, `#RRRRGGGGBBBB`, `None`/`transparent`
/// or an X11 name.
pub fn parse_colour(value: &str) -> Result<[f32; 4], XpmError> {
    if let Some(hex) = value.strip_prefix('#') {
        if !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
            return err(format!("colour {} has a non-hex digit", shown(value)));
        }
        let digits = hex.len() / 3;
        if hex.len() % 3 != 0 || !(1..=4).contains(&digits) {
            return err(format!(
                "colour {} must be #RGB, #RRGGBB, #RRRGGGBBB or #RRRRGGGGBBBB",
                shown(value)
            ));
        }
        let max = ((1u32 << (4 * digits)) - 1) as f32;
        let mut rgb = [0.0f32; 3];
        for (c, slot) in rgb.iter_mut().enumerate() {
            let part = &hex[c * digits..(c + 1) * digits];
            let n = u32::from_str_radix(part, 16)
                .map_err(|_| XpmError(format!("colour {} has a non-hex digit", shown(value))))?;
            *slot = n as f32 / max;
        }
        return Ok([rgb[0], rgb[1], rgb[2], 1.0]);
    }
    let name: String = value
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect();
    if name == "none" || name == "transparent" {
        return Ok([0.0, 0.0, 0.0, 0.0]);
    }
    let rgb = named(&name).ok_or_else(|| {
        XpmError(format!(
            "unknown colour name {} (not an X11 colour name; use #RRGGBB)",
            shown(value)
        ))
    })?;
    Ok([
        rgb[0] as f32 / 255.0,
        rgb[1] as f32 / 255.0,
        rgb[2] as f32 / 255.0,
        1.0,
    ])
}

/// An X11 colour name (already lower case, without blanks) from the whole
/// `rgb.txt` list.
fn named(name: &str) -> Option<[u8; 3]> {
    X11_COLORS
        .binary_search_by(|(key, _)| key.cmp(&name))
        .ok()
        .map(|i| X11_COLORS[i].1)
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

    fn rgb8(value: &str) -> [u8; 3] {
        let c = parse_colour(value).unwrap_or_else(|e| panic!("{value}: {e}"));
        assert_eq!(c[3], 1.0, "{value} is opaque");
        [c[0], c[1], c[2]].map(|x| (x * 255.0).round() as u8)
    }

    #[test]
    fn colours_in_every_notation() {
        assert_eq!(parse_colour("#fff").unwrap(), [1.0; 4]);
        assert_eq!(parse_colour("#000000").unwrap(), [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(parse_colour("#FFF000000").unwrap(), [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(parse_colour("#FFFF00000000").unwrap(), [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(rgb8("#4682b4"), [70, 130, 180]);
        assert_eq!(parse_colour("None").unwrap(), [0.0; 4]);
        assert_eq!(parse_colour("none").unwrap(), [0.0; 4]);
        assert_eq!(parse_colour("Transparent").unwrap(), [0.0; 4]);
        assert_eq!(parse_colour("White").unwrap(), [1.0; 4]);
        assert_eq!(parse_colour("light gray").unwrap()[0], 211.0 / 255.0);
        assert_eq!(parse_colour("grey50").unwrap()[1], 127.0 / 255.0);
        for bad in [
            "#12",
            "#GGGGGG",
            "#+f+f+f",
            "#\u{e9}ab",
            "#1234567890123",
            "#",
        ] {
            assert!(parse_colour(bad).is_err(), "{bad} must be refused");
        }
    }

    #[test]
    fn every_x11_name_is_known_in_any_case_and_spacing() {
        // Values as X.Org's rgb.txt gives them.
        let cases: &[(&str, [u8; 3])] = &[
            ("steelblue1", [99, 184, 255]),
            ("SteelBlue1", [99, 184, 255]),
            ("darkolivegreen", [85, 107, 47]),
            ("DarkOliveGreen", [85, 107, 47]),
            ("dark olive green", [85, 107, 47]),
            ("wheat", [245, 222, 179]),
            ("tan", [210, 180, 140]),
            ("light goldenrod", [238, 221, 130]),
            ("LightGoldenrod", [238, 221, 130]),
            ("LIGHTGOLDENRODYELLOW", [250, 250, 210]),
            ("gray", [190, 190, 190]),
            ("gray0", [0, 0, 0]),
            ("grey0", [0, 0, 0]),
            ("gray1", [3, 3, 3]),
            ("gray50", [127, 127, 127]),
            ("Grey51", [130, 130, 130]),
            ("gray100", [255, 255, 255]),
            ("grey100", [255, 255, 255]),
            ("dark grey", [169, 169, 169]),
            ("navy blue", [0, 0, 128]),
            ("aliceblue", [240, 248, 255]),
            ("yellowgreen", [154, 205, 50]),
            ("mediumpurple4", [93, 71, 139]),
        ];
        for (name, rgb) in cases {
            assert_eq!(rgb8(name), *rgb, "{name}");
        }
        for bad in [
            "gray101",
            "grey-1",
            "steelblue5",
            "chartreuse-ish",
            "",
            "bluee",
            "aliceblu",
            "zzz",
            "#",
            "light_gray",
            "r\u{e9}d",
        ] {
            let e = parse_colour(bad).unwrap_err();
            assert!(e.0.contains("colour"), "{bad}: {e}");
        }
    }

    #[test]
    fn the_name_table_is_sorted_unique_and_normalised() {
        assert!(X11_COLORS.len() > 600);
        for pair in X11_COLORS.windows(2) {
            assert!(pair[0].0 < pair[1].0, "{} before {}", pair[0].0, pair[1].0);
        }
        for (name, _) in X11_COLORS {
            assert!(
                name.bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit()),
                "{name}"
            );
            assert!(named(name).is_some());
        }
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
    fn read_as_libxpm_reads_real_icons() {
        // No ',' between two strings, and a stray row after the last one.
        let text = "/* XPM */\nstatic char *x[] = {\n\"2 2 2 1\",\n\". c steelblue1\",\n\"# c light goldenrod\"\n\".#\",\n\"#.\",\n\"..\"};\n";
        let img = decode(text.as_bytes(), 10).unwrap();
        assert_eq!((img.width, img.height), (2, 2));
        let sb = [99.0 / 255.0, 184.0 / 255.0, 1.0, 1.0];
        let lg = [238.0 / 255.0, 221.0 / 255.0, 130.0 / 255.0, 1.0];
        assert_eq!(img.rgba, vec![sb, lg, lg, sb]);
        // Extensions after the rows are skipped.
        let ext = "/* XPM */ static char *x[] = {\"1 1 1 1 XPMEXT\", \"a c tan\", \"a\", \"XPMEXT x\", \"XPMENDEXT\"};";
        assert_eq!(decode(ext.as_bytes(), 10).unwrap().rgba.len(), 1);
    }

    #[test]
    fn mono_key_is_used_when_there_is_no_colour_key() {
        let text = "/* XPM */ static char *x[] = {\"1 1 1 1\", \"a m white\", \"a\"};";
        assert_eq!(decode(text.as_bytes(), 10).unwrap().rgba, vec![[1.0; 4]]);
    }
}
