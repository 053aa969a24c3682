//! A model's files: read whole (large ones mapped), their bytes reserved
//! against the memory budget first, and the files it names found beside it.

use std::fs::File;
use std::io::Read;
use std::ops::Deref;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::file_map::MappedFile;
use super::load_progress::{self, LoadStep, cancelled};
use super::model_error::ObjError;
use relief_core::budget::{self, Reservation};
use relief_core::sanitize::display_path;

/// A model file's bytes: mapped when the file is large, read otherwise.
pub(crate) enum FileBytes {
    Read(Vec<u8>),
    Mapped(MappedFile),
}

impl Deref for FileBytes {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        match self {
            FileBytes::Read(bytes) => bytes,
            FileBytes::Mapped(map) => map,
        }
    }
}

impl FileBytes {
    /// An error when the file shrank while it was mapped: its lost bytes
    /// read as zeros, so what was made of them is not the file. Asked
    /// after reading, whatever the reading gave.
    pub fn check(&self, name: &str) -> Result<(), ObjError> {
        match self {
            FileBytes::Mapped(map) if map.was_cut() => Err(ObjError::Read {
                name: name.to_string(),
                reason: "the file shrank while it was read".into(),
            }),
            _ => Ok(()),
        }
    }
}

/// Files from this size on are mapped, not read (`file_map`): below it
/// the copy costs little, and reading reports its progress.
pub(crate) const MAP_FROM: u64 = 16 << 20;

/// Reads a whole model file, its bytes reserved against the memory budget
/// before they are read (there is no fixed size limit).
pub(crate) fn read_model_file(path: &Path) -> Result<(FileBytes, Reservation), ObjError> {
    read_model_file_mapping_from(path, MAP_FROM)
}

/// [`read_model_file`], files from `map_from` bytes on mapped.
pub(crate) fn read_model_file_mapping_from(
    path: &Path,
    map_from: u64,
) -> Result<(FileBytes, Reservation), ObjError> {
    let name = display_path(path);
    let read_error = |e: std::io::Error| open_error(&name, &e);
    let meta = std::fs::metadata(path).map_err(read_error)?;
    if !meta.is_file() {
        return Err(ObjError::NotAFile { name });
    }
    let held = reserve(&name, "the file", meta.len())?;
    let file = File::open(path).map_err(read_error)?;
    if meta.len() >= map_from
        && let Some(map) = MappedFile::new(&file, meta.len())
    {
        // No reading step: the pages come in as the parse first walks them.
        if let Some(p) = load_progress::current() {
            p.begin(LoadStep::Parsing, 0);
        }
        return Ok((FileBytes::Mapped(map), held));
    }
    let bytes = read_file_reporting(&file, meta.len())
        .map_err(|e| e.map_or_else(|| cancelled(&name), read_error))?;
    Ok((FileBytes::Read(bytes), held))
}

/// Bytes read between two progress reports and cancel checks: a few
/// milliseconds from a disk, well under one from the page cache.
const READ_CHUNK: usize = 4 << 20;

/// Reads at most `len` bytes of `file` into a buffer of exactly that
/// capacity (a growing one would take up to twice), chunk by chunk,
/// reporting to the current load ([`load_progress`]) and stopping when it
/// is cancelled (`Err(None)`); the load's next step is then the parse.
pub(crate) fn read_reporting(file: impl Read, len: u64) -> Result<Vec<u8>, Option<std::io::Error>> {
    let progress = load_progress::current();
    if let Some(p) = &progress {
        p.begin(LoadStep::Reading, len);
    }
    let mut bytes = Vec::with_capacity(len as usize);
    let mut file = file.take(len);
    loop {
        if progress.as_ref().is_some_and(|p| p.cancelled()) {
            return Err(None);
        }
        let before = bytes.len();
        let got = (&mut file)
            .take(READ_CHUNK as u64)
            .read_to_end(&mut bytes)
            .map_err(Some)?;
        if let Some(p) = &progress {
            p.advance((bytes.len() - before) as u64);
        }
        if got == 0 {
            // What follows a read is the parse (an OBJ reader counts it).
            if let Some(p) = &progress {
                p.begin(LoadStep::Parsing, 0);
            }
            return Ok(bytes);
        }
    }
}

/// [`read_reporting`] of a file, its chunks read into their places in
/// parallel (the copy from the page cache, and the first touch of each
/// page of the buffer, take as long as a quick parse): the same bytes,
/// the file's first `len` or all of it when it is shorter, or the error or
/// cancel the first chunk to meet one meets.
fn read_file_reporting(file: &File, len: u64) -> Result<Vec<u8>, Option<std::io::Error>> {
    let progress = load_progress::current();
    if let Some(p) = &progress {
        p.begin(LoadStep::Reading, len);
    }
    // Zeroed by the allocator as fresh pages: each is first touched by
    // the read that fills it.
    let mut bytes = vec![0u8; len as usize];
    let got: Vec<Result<usize, Option<std::io::Error>>> = bytes
        .par_chunks_mut(READ_CHUNK)
        .enumerate()
        .map(|(k, piece)| {
            if progress.as_ref().is_some_and(|p| p.cancelled()) {
                return Err(None);
            }
            let (at, mut filled) = ((k * READ_CHUNK) as u64, 0);
            while filled < piece.len() {
                match file.read_at(&mut piece[filled..], at + filled as u64) {
                    Ok(0) => break,
                    Ok(n) => filled += n,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                    Err(e) => return Err(Some(e)),
                }
            }
            if let Some(p) = &progress {
                p.advance(filled as u64);
            }
            Ok(filled)
        })
        .collect();
    // The file ends where the first chunk came back short.
    let mut total = 0;
    for piece in got {
        let filled = piece?;
        total += filled;
        if filled < READ_CHUNK {
            break;
        }
    }
    bytes.truncate(total);
    // What follows a read is the parse (an OBJ reader counts it).
    if let Some(p) = &progress {
        p.begin(LoadStep::Parsing, 0);
    }
    Ok(bytes)
}

/// The error reading `path` would start with, if any: a missing file, one
/// that is not a regular file or cannot be opened (the view says so before
/// it starts, and loads the file on its worker afterwards).
pub fn check_openable(path: &Path) -> Result<(), ObjError> {
    let name = display_path(path);
    let read_error = |e: std::io::Error| open_error(&name, &e);
    if !std::fs::metadata(path).map_err(read_error)?.is_file() {
        return Err(ObjError::NotAFile { name });
    }
    std::fs::File::open(path).map_err(read_error)?;
    Ok(())
}

/// Why model `name` could not be opened or read, in plain words: a
/// missing file is "not found", other errors without their "(os error N)".
pub(crate) fn open_error(name: &str, e: &std::io::Error) -> ObjError {
    match e.kind() {
        std::io::ErrorKind::NotFound => ObjError::NotFound {
            name: name.to_string(),
        },
        _ => ObjError::Read {
            name: name.to_string(),
            reason: relief_core::sanitize::io_reason(e),
        },
    }
}

/// Reserves `bytes` for `what` of model `name`, or the budget's error.
pub(crate) fn reserve(name: &str, what: &str, bytes: u64) -> Result<Reservation, ObjError> {
    budget::reserve(&format!("{what} of model {name}"), bytes).map_err(|e| ObjError::Budget {
        name: name.to_string(),
        reason: e.to_string(),
    })
}

/// The model's path with another file name resolved next to it: `\` read as
/// `/`, and when that file is not there, each part of the path matched
/// without regard to case (files from Windows name their textures loosely).
pub fn resolve_beside(dir: &Path, written: &str) -> Option<PathBuf> {
    let written = written.trim().trim_matches('"').replace('\\', "/");
    if written.is_empty() {
        return None;
    }
    // What is there, file or not: reading it says what it is (a device
    // or a FIFO is not a regular file, which "not found" would hide).
    let direct = dir.join(&written);
    if direct.exists() {
        return Some(direct);
    }
    let mut at = if Path::new(&written).is_absolute() {
        PathBuf::from("/")
    } else {
        dir.to_path_buf()
    };
    for part in written.split('/').filter(|p| !p.is_empty() && *p != ".") {
        if part == ".." {
            at.push("..");
            continue;
        }
        let exact = at.join(part);
        if exact.exists() {
            at = exact;
            continue;
        }
        let lower = part.to_lowercase();
        let found = std::fs::read_dir(&at).ok()?.flatten().find(|entry| {
            entry
                .file_name()
                .to_str()
                .is_some_and(|n| n.to_lowercase() == lower)
        })?;
        at.push(found.file_name());
    }
    at.exists().then_some(at)
}

#[cfg(test)]
mod tests {
    use std::io::Cursor;
    use std::sync::Arc;

    use super::*;
    use crate::load_progress::{LoadProgress, ProgressNow, run_with};

    /// Gives `data`, and cancels the load once it has given anything.
    struct CancelOnFirstRead {
        data: Cursor<Vec<u8>>,
        progress: Arc<LoadProgress>,
    }

    impl Read for CancelOnFirstRead {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            self.progress.cancel();
            self.data.read(buf)
        }
    }

    #[test]
    fn a_read_reports_every_byte_then_the_parse_begins() {
        let data: Vec<u8> = (0..READ_CHUNK * 2 + 1000).map(|i| i as u8).collect();
        let p = LoadProgress::new();
        let got = run_with(&p, || {
            read_reporting(Cursor::new(data.clone()), data.len() as u64)
        });
        assert_eq!(got.unwrap(), data);
        // The read's last report was all of it; the parse follows, size unknown.
        assert_eq!(
            p.now(),
            ProgressNow {
                step: LoadStep::Parsing,
                done: 0,
                total: 0
            }
        );
    }

    #[test]
    fn a_file_read_in_parallel_pieces_gives_its_first_len_bytes() {
        let data: Vec<u8> = (0..READ_CHUNK * 2 + 1000)
            .map(|i| (i % 251) as u8)
            .collect();
        let path = std::env::temp_dir().join(format!("relief-read-{}.bin", std::process::id()));
        std::fs::write(&path, &data).unwrap();
        let file = File::open(&path).unwrap();
        let len = data.len();
        // The whole file, a prefix (it grew), all of it when it is shorter
        // than said (it shrank), and nothing.
        for (asked, got) in [
            (len, len),
            (READ_CHUNK + 7, READ_CHUNK + 7),
            (len + READ_CHUNK, len),
            (0, 0),
        ] {
            let bytes = read_file_reporting(&file, asked as u64).unwrap();
            assert_eq!(bytes, data[..got], "{asked}");
        }
        std::fs::remove_file(&path).unwrap();
    }

    /// A name that is there but is not a regular file (a device, a FIFO,
    /// a folder) is found: reading it then says what it is, where "not
    /// found" would mislead.
    #[test]
    #[cfg(unix)]
    fn what_is_not_a_regular_file_is_found_and_refused_as_such() {
        let dir = std::env::temp_dir().join(format!("relief-beside-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("Maps")).unwrap();
        assert_eq!(
            resolve_beside(&dir, "/dev/zero"),
            Some(PathBuf::from("/dev/zero"))
        );
        assert_eq!(resolve_beside(&dir, "maps"), Some(dir.join("Maps")));
        assert_eq!(resolve_beside(&dir, "none.png"), None);
        let e = read_model_file(Path::new("/dev/zero")).err().unwrap();
        assert!(matches!(e, ObjError::NotAFile { .. }), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_cancelled_read_stops_after_the_chunk_under_way() {
        let len = READ_CHUNK * 3;
        let p = LoadProgress::new();
        let file = CancelOnFirstRead {
            data: Cursor::new(vec![7; len]),
            progress: p.clone(),
        };
        let got = run_with(&p, || read_reporting(file, len as u64));
        assert!(matches!(got, Err(None)), "stopped, not an I/O error");
        assert_eq!(
            p.now(),
            ProgressNow {
                step: LoadStep::Reading,
                done: READ_CHUNK as u64,
                total: len as u64
            },
            "one chunk read, then the check"
        );
    }

    #[test]
    #[cfg(target_os = "linux")]
    fn a_mapped_file_gives_the_bytes_a_read_gives() {
        crate::file_map::install_bus_guard();
        let path = Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/data/models/tinyobjloader/map-bump.obj"
        ));
        let (mapped, _held) = read_model_file_mapping_from(path, 0).unwrap();
        let (read, _held) = read_model_file_mapping_from(path, u64::MAX).unwrap();
        assert!(matches!(mapped, FileBytes::Mapped(_)));
        assert!(matches!(read, FileBytes::Read(_)));
        assert_eq!(&mapped[..], &read[..]);
        assert!(mapped.check("m").is_ok());
    }

    #[test]
    #[cfg(target_os = "linux")]
    fn a_file_that_shrinks_while_mapped_is_an_error_naming_it() {
        crate::file_map::install_bus_guard();
        let path = std::env::temp_dir().join(format!("relief-shrinks-{}.obj", std::process::id()));
        std::fs::write(&path, "v 0 0 0\n".repeat(100_000)).unwrap();
        let (bytes, _held) = read_model_file_mapping_from(&path, 0).unwrap();
        std::fs::File::options()
            .write(true)
            .open(&path)
            .unwrap()
            .set_len(10)
            .unwrap();
        assert!(bytes.iter().skip(10).all(|&b| b == 0));
        let e = bytes.check("shrinks.obj").unwrap_err().to_string();
        assert!(
            e.contains("shrinks.obj") && e.contains("shrank while it was read"),
            "{e}"
        );
        drop(bytes);
        std::fs::remove_file(path).unwrap();
    }
}
