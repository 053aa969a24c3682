//! The texture list the app shows: built-in textures, files from the command
//! line, pasted and typed paths. A plain model (no terminal code): every
//! operation that fails returns the error and leaves the list and the current
//! texture exactly as they were.

use std::collections::HashMap;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::thumbnail::Preview;
use relief_core::sanitize;
use relief_texture::Texture;
use relief_texture::decode::builtin::{Builtin, builtins};
use relief_texture::decode::load::{TextureError, load_texture, with_height_map};

/// Where an entry's pixels come from.
#[derive(Clone, Debug)]
pub enum Source {
    Builtin(Builtin),
    /// A file, as the user gave it.
    File(PathBuf),
}

/// One line of the list.
#[derive(Clone, Debug)]
pub struct Entry {
    pub source: Source,
    /// A separate height map, when one was given with the picture.
    pub height_map: Option<PathBuf>,
    /// What the list shows (control characters replaced).
    pub label: String,
    /// Identity for de-duplication: canonical paths where they resolve.
    key: (String, Option<PathBuf>),
}

impl Entry {
    fn new(source: Source, height_map: Option<PathBuf>) -> Entry {
        let (name, key) = match &source {
            Source::Builtin(b) => (
                format!("{} (built-in)", b.name),
                format!("builtin:{}", b.name),
            ),
            Source::File(p) => (
                sanitize::display_path(p),
                format!("file:{}", identity(p).display()),
            ),
        };
        let label = match &height_map {
            Some(h) => format!("{name} + {}", sanitize::display_path(h)),
            None => name,
        };
        let key = (key, height_map.as_deref().map(identity));
        Entry {
            source,
            height_map,
            label,
            key,
        }
    }

    /// Reads the entry's pictures (from disk for files).
    pub fn load(&self) -> Result<Texture, TextureError> {
        let color = match &self.source {
            Source::Builtin(b) => b.load()?,
            Source::File(p) => load_texture(p)?,
        };
        match &self.height_map {
            Some(h) => with_height_map(color, &load_texture(h)?),
            None => Ok(color),
        }
    }

    /// The file behind the entry, if any.
    pub fn path(&self) -> Option<&Path> {
        match &self.source {
            Source::File(p) => Some(p),
            Source::Builtin(_) => None,
        }
    }
}

/// A path's identity: its canonical form when it resolves, else itself.
fn identity(path: &Path) -> PathBuf {
    std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}

/// Why a list operation did nothing.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ListError {
    #[error(transparent)]
    Texture(#[from] TextureError),
    #[error("no texture number {index} (the list has {len})")]
    NoEntry { index: usize, len: usize },
    #[error("no file path in the pasted text")]
    NoPath,
}

/// The list, the applied entry and its loaded texture.
#[derive(Debug)]
pub struct TextureList {
    entries: Vec<Entry>,
    /// The entry whose texture is applied.
    current: usize,
    /// The entry last tried by `cycle` (so a broken file is stepped over
    /// the next time, not retried forever).
    cursor: usize,
    texture: Arc<Texture>,
    /// Bumped each time the applied texture changes (a cache key for views).
    generation: u64,
    /// The entry whose heights the applied texture takes (`None`: the
    /// applied entry's own, as loaded).
    heights: Option<usize>,
    /// Each entry's preview, made the first time it is asked for (`None`:
    /// the entry did not load then).
    previews: HashMap<usize, Option<Arc<Preview>>>,
}

impl Default for TextureList {
    fn default() -> Self {
        Self::new()
    }
}

impl TextureList {
    /// The built-in textures, the first (brick) applied.
    pub fn new() -> TextureList {
        let entries: Vec<Entry> = builtins()
            .into_iter()
            .map(|b| Entry::new(Source::Builtin(b), None))
            .collect();
        // The embedded PNG is checked by the tests; should it ever fail to
        // decode, the generator gives the same texels.
        let texture = entries[0]
            .load()
            .unwrap_or_else(|_| relief_texture::decode::procedural::brick());
        TextureList {
            entries,
            current: 0,
            cursor: 0,
            texture: Arc::new(texture),
            generation: 0,
            heights: None,
            previews: HashMap::new(),
        }
    }

    /// The list for `relief [--height-map H] IMAGE…`: the built-ins, then
    /// every image that loads; the first image is applied. The height map
    /// goes with the first image, or with the brick when no image is given.
    /// Images that fail are left out and their errors returned.
    pub fn from_args(
        images: &[PathBuf],
        height_map: Option<&Path>,
    ) -> (TextureList, Vec<ListError>) {
        let mut list = TextureList::new();
        let mut errors = Vec::new();
        if images.is_empty() {
            if let Some(h) = height_map {
                let brick = list.entries[0].source.clone();
                if let Err(e) = list.add_entry(Entry::new(brick, Some(h.to_path_buf()))) {
                    errors.push(e);
                }
            }
            return (list, errors);
        }
        let mut applied = None;
        for (i, image) in images.iter().enumerate() {
            let height = if i == 0 {
                height_map.map(Path::to_path_buf)
            } else {
                None
            };
            let entry = Entry::new(Source::File(image.clone()), height);
            match entry.load() {
                Ok(tex) => {
                    let index = list.push_unique(entry);
                    if applied.is_none() {
                        applied = Some((index, tex));
                    }
                }
                Err(e) => errors.push(e.into()),
            }
        }
        if let Some((index, tex)) = applied {
            list.apply(index, tex);
        }
        (list, errors)
    }

    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Index of the applied entry.
    pub fn current(&self) -> usize {
        self.current
    }

    /// The applied entry.
    pub fn current_entry(&self) -> &Entry {
        &self.entries[self.current]
    }

    /// The applied texture.
    pub fn texture(&self) -> &Arc<Texture> {
        &self.texture
    }

    /// Changes each time the applied texture does (select, add, reload).
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// One line for a status bar: "4/5 photo.png", and where the heights
    /// come from when another entry gives them.
    pub fn summary(&self) -> String {
        let heights = match self.heights {
            Some(h) => format!(" (heights: {})", self.entries[h].label),
            None => String::new(),
        };
        format!(
            "{}/{} {}{heights}",
            self.current + 1,
            self.entries.len(),
            self.entries[self.current].label
        )
    }

    /// The entry whose heights the applied texture takes, when it is not
    /// the applied entry's own (see [`TextureList::set_heights`]).
    pub fn heights(&self) -> Option<usize> {
        self.heights
    }

    /// `color` with the heights of the chosen heights entry, if any.
    fn with_heights(&self, color: Texture) -> Result<Texture, ListError> {
        match self.heights {
            Some(h) => Ok(with_height_map(color, &self.entries[h].load()?)?),
            None => Ok(color),
        }
    }

    /// Entry `index`'s colour with the chosen heights.
    fn load_applied(&self, index: usize) -> Result<Texture, ListError> {
        self.with_heights(self.entries[index].load()?)
    }

    /// Takes the heights (the bump) from entry `index` whatever texture is
    /// applied, as a separate height map does; `None`: each texture's own
    /// again. On failure nothing changes.
    pub fn set_heights(&mut self, index: Option<usize>) -> Result<(), ListError> {
        if let Some(i) = index
            && i >= self.entries.len()
        {
            return Err(ListError::NoEntry {
                index: i,
                len: self.entries.len(),
            });
        }
        let old = std::mem::replace(&mut self.heights, index);
        match self.load_applied(self.current) {
            Ok(texture) => {
                self.texture = Arc::new(texture);
                self.generation += 1;
                Ok(())
            }
            Err(e) => {
                self.heights = old;
                Err(e)
            }
        }
    }

    /// Entry `index`'s size and thumbnail, made once (the applied entry's
    /// from the texture in use, the others by loading them); `None` when it
    /// does not load.
    pub fn preview(&mut self, index: usize) -> Option<Arc<Preview>> {
        if let Some(p) = self.previews.get(&index) {
            return p.clone();
        }
        let made = if index == self.current {
            Some(Arc::new(Preview::of(&self.texture)))
        } else {
            let entry = self.entries.get(index)?;
            entry.load().ok().map(|t| Arc::new(Preview::of(&t)))
        };
        self.previews.insert(index, made.clone());
        made
    }

    fn apply(&mut self, index: usize, texture: Texture) {
        self.current = index;
        self.cursor = index;
        self.texture = Arc::new(texture);
        self.generation += 1;
    }

    /// Index of an equal entry, or of the entry just appended.
    fn push_unique(&mut self, entry: Entry) -> usize {
        match self.entries.iter().position(|e| e.key == entry.key) {
            Some(i) => i,
            None => {
                self.entries.push(entry);
                self.entries.len() - 1
            }
        }
    }

    /// Loads an entry and, if it loads, puts it in the list (once) and applies it.
    fn add_entry(&mut self, entry: Entry) -> Result<usize, ListError> {
        let texture = self.with_heights(entry.load()?)?;
        let index = self.push_unique(entry);
        // Read again: an entry already listed may have changed on disk.
        self.previews.remove(&index);
        self.apply(index, texture);
        Ok(index)
    }

    /// Applies entry `index` (re-reading a file from disk).
    pub fn select(&mut self, index: usize) -> Result<(), ListError> {
        let Some(entry) = self.entries.get(index) else {
            return Err(ListError::NoEntry {
                index,
                len: self.entries.len(),
            });
        };
        let texture = self.with_heights(entry.load()?)?;
        self.apply(index, texture);
        Ok(())
    }

    /// Applies the next (`forward`) or previous entry. If that one fails,
    /// the error is returned and the current texture kept, but the next call
    /// moves on past the failed entry.
    pub fn cycle(&mut self, forward: bool) -> Result<(), ListError> {
        let n = self.entries.len();
        let next = if forward {
            (self.cursor + 1) % n
        } else {
            (self.cursor + n - 1) % n
        };
        let result = self.select(next);
        self.cursor = next;
        result
    }

    /// Adds a file (with an optional height map) and applies it. A file
    /// already in the list is not added twice: it is re-read and applied.
    pub fn add_path(&mut self, path: &Path, height_map: Option<&Path>) -> Result<usize, ListError> {
        self.add_entry(Entry::new(
            Source::File(path.to_path_buf()),
            height_map.map(Path::to_path_buf),
        ))
    }

    /// Pairs the applied entry's colour with a height map (`None`: its own
    /// alpha or mean of RGB again) as an entry of its own, and applies it.
    pub fn set_height_map(&mut self, height_map: Option<&Path>) -> Result<usize, ListError> {
        let source = self.entries[self.current].source.clone();
        self.add_entry(Entry::new(source, height_map.map(Path::to_path_buf)))
    }

    /// Adds every path of a paste (see [`parse_paste`]); the last one that
    /// loads is applied. Returns the errors of the others, or `NoPath`.
    pub fn add_paste(&mut self, text: &str) -> Vec<ListError> {
        let paths = parse_paste(text);
        if paths.is_empty() {
            return vec![ListError::NoPath];
        }
        paths
            .iter()
            .filter_map(|p| self.add_path(p, None).err())
            .collect()
    }

    /// Re-reads the applied entry from disk. On failure the texture in use
    /// stays.
    pub fn reload(&mut self) -> Result<(), ListError> {
        let texture = self.load_applied(self.current)?;
        self.previews.remove(&self.current);
        self.texture = Arc::new(texture);
        self.generation += 1;
        Ok(())
    }
}

/// Paths from a bracketed paste or a typed prompt line, using the real file
/// system to recognise a whole line that is one path with spaces, and `$HOME`
/// for a leading `~/`.
pub fn parse_paste(text: &str) -> Vec<PathBuf> {
    let home = std::env::var_os("HOME").map(PathBuf::from);
    parse_paste_with(text, &|p: &Path| p.exists(), home.as_deref())
}

/// [`parse_paste`] with the file-system test and home directory given.
///
/// What terminals send when a file is dropped on them: a path with spaces
/// backslash-escaped (`/a/my\ file.png`), or quoted (`'/a/my file.png'`,
/// with `'\''` for a quote), or a `file://` URI with %-escapes, one or
/// several separated by blanks or newlines. A line that is, as it stands,
/// the name of an existing file is taken whole (an unquoted path with spaces).
pub fn parse_paste_with(
    text: &str,
    exists: &dyn Fn(&Path) -> bool,
    home: Option<&Path>,
) -> Vec<PathBuf> {
    let text = text.trim_matches(|c: char| c.is_whitespace() || c == '\0');
    if text.is_empty() {
        return Vec::new();
    }
    if !text.contains('\n') {
        let whole = finish(text, home);
        if text.contains(' ') && exists(&whole) {
            return vec![whole];
        }
    }
    words(text)
        .iter()
        .filter(|w| !w.is_empty())
        .map(|w| finish(w, home))
        .collect()
}

/// A word made a path: `file://` URIs decoded, `~/` expanded.
fn finish(word: &str, home: Option<&Path>) -> PathBuf {
    if let Some(rest) = word.strip_prefix("file://") {
        // The host part (empty or "localhost") runs to the next '/'.
        let path = match rest.find('/') {
            Some(i) => &rest[i..],
            None => rest,
        };
        return bytes_to_path(percent_decode(path));
    }
    if let (Some(rest), Some(home)) = (word.strip_prefix("~/"), home) {
        return home.join(rest);
    }
    PathBuf::from(word)
}

fn percent_decode(text: &str) -> Vec<u8> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%'
            && let (Some(h), Some(l)) = (
                bytes.get(i + 1).and_then(|b| hex(*b)),
                bytes.get(i + 2).and_then(|b| hex(*b)),
            )
        {
            out.push((h * 16 + l) as u8);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    out
}

#[cfg(unix)]
fn bytes_to_path(bytes: Vec<u8>) -> PathBuf {
    use std::os::unix::ffi::OsStringExt;
    PathBuf::from(OsString::from_vec(bytes))
}

#[cfg(not(unix))]
fn bytes_to_path(bytes: Vec<u8>) -> PathBuf {
    PathBuf::from(OsString::from(String::from_utf8_lossy(&bytes).into_owned()))
}

/// Shell-like words: blanks separate, `'…'` is literal, `"…"` allows `\"`
/// and `\\`, and a backslash outside quotes keeps the next character. An
/// unclosed quote runs to the end.
fn words(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut in_word = false;
    let mut chars = text.chars();
    while let Some(c) = chars.next() {
        match c {
            c if c.is_whitespace() => {
                if in_word {
                    out.push(std::mem::take(&mut word));
                    in_word = false;
                }
            }
            '\'' => {
                in_word = true;
                for q in chars.by_ref() {
                    if q == '\'' {
                        break;
                    }
                    word.push(q);
                }
            }
            '"' => {
                in_word = true;
                while let Some(q) = chars.next() {
                    match q {
                        '"' => break,
                        '\\' => match chars.next() {
                            Some(e @ ('"' | '\\' | '$' | '`')) => word.push(e),
                            Some(e) => {
                                word.push('\\');
                                word.push(e);
                            }
                            None => word.push('\\'),
                        },
                        q => word.push(q),
                    }
                }
            }
            '\\' => {
                in_word = true;
                match chars.next() {
                    Some('\n') | None => {}
                    Some(e) => word.push(e),
                }
            }
            c => {
                in_word = true;
                word.push(c);
            }
        }
    }
    if in_word {
        out.push(word);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Vec<PathBuf> {
        parse_paste_with(text, &|_| false, Some(Path::new("/home/u")))
    }

    fn paths(list: &[&str]) -> Vec<PathBuf> {
        list.iter().map(PathBuf::from).collect()
    }

    #[test]
    fn dragged_files_in_every_terminal_style() {
        assert_eq!(parse("/a/b.png"), paths(&["/a/b.png"]));
        assert_eq!(parse("  /a/b.png \n"), paths(&["/a/b.png"]));
        assert_eq!(parse("/a/my\\ file.png"), paths(&["/a/my file.png"]));
        assert_eq!(parse("'/a/my file.png' "), paths(&["/a/my file.png"]));
        assert_eq!(parse("'/a/it'\\''s.png'"), paths(&["/a/it's.png"]));
        assert_eq!(parse("\"/a/q\\\"x.png\""), paths(&["/a/q\"x.png"]));
        assert_eq!(parse("file:///a/my%20file.png"), paths(&["/a/my file.png"]));
        assert_eq!(parse("file://localhost/a/b.png"), paths(&["/a/b.png"]));
        assert_eq!(
            parse("file:///a/x.png\r\nfile:///b/y%2Bz.png\r\n"),
            paths(&["/a/x.png", "/b/y+z.png"])
        );
        assert_eq!(
            parse("'/a/1.png' '/b/2.png'"),
            paths(&["/a/1.png", "/b/2.png"])
        );
        assert_eq!(parse("~/t.png"), paths(&["/home/u/t.png"]));
        assert_eq!(parse("'unclosed name.png"), paths(&["unclosed name.png"]));
        assert!(parse("   \n ").is_empty());
        assert!(parse("''").is_empty());
    }

    #[test]
    fn an_existing_path_with_spaces_is_taken_whole() {
        let exists = |p: &Path| p == Path::new("/a/my file.png");
        assert_eq!(
            parse_paste_with("/a/my file.png", &exists, None),
            paths(&["/a/my file.png"])
        );
        assert_eq!(
            parse_paste_with("/a/other file.png", &exists, None),
            paths(&["/a/other", "file.png"])
        );
    }

    #[cfg(unix)]
    #[test]
    fn percent_escapes_may_be_any_bytes() {
        use std::os::unix::ffi::OsStrExt;
        let p = parse("file:///a/%FF.png");
        assert_eq!(p[0].as_os_str().as_bytes(), b"/a/\xff.png");
    }
}
