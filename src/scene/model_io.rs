//! A model's files: read whole, their bytes reserved against the memory
//! budget first, and the files it names found beside it.

use std::io::Read;
use std::path::{Path, PathBuf};

use super::model_error::ObjError;
use crate::budget::{self, Reservation};
use crate::sanitize::{clean, display_path};

/// Reads a whole model file, its bytes reserved against the memory budget
/// before they are read (there is no fixed size limit).
pub(crate) fn read_model_file(path: &Path) -> Result<(Vec<u8>, Reservation), ObjError> {
    let name = display_path(path);
    let read_error = |e: std::io::Error| ObjError::Read {
        name: name.clone(),
        reason: clean(&e.to_string()),
    };
    let meta = std::fs::metadata(path).map_err(read_error)?;
    if !meta.is_file() {
        return Err(ObjError::NotAFile { name });
    }
    let held = reserve(&name, "the file", meta.len())?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)
        .and_then(|f| f.take(meta.len()).read_to_end(&mut bytes))
        .map_err(read_error)?;
    Ok((bytes, held))
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
    let direct = dir.join(&written);
    if direct.is_file() {
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
    at.is_file().then_some(at)
}
