//! Where the tests write their files: one folder per test process under
//! the system's temporary folder, `relief-tests-PID`, removed when the
//! process exits. A run that was killed leaves its folder behind; the
//! next run removes the folders of processes that no longer exist.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

const PREFIX: &str = "relief-tests-";

static ROOT: OnceLock<PathBuf> = OnceLock::new();

/// Folder `name` of this process's scratch folder, made if missing (a
/// test may write several files into it).
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = root().join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The same folder emptied first, for a test that reads back what it lists.
pub fn fresh_scratch_dir(name: &str) -> PathBuf {
    let dir = root().join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A path for file `name` in this process's scratch folder.
pub fn scratch_file(name: &str) -> PathBuf {
    root().join(name)
}

fn root() -> &'static Path {
    ROOT.get_or_init(|| {
        let temp = std::env::temp_dir();
        remove_abandoned(&temp);
        let root = temp.join(format!("{PREFIX}{}", std::process::id()));
        std::fs::create_dir_all(&root).unwrap();
        // libtest ends the process with `exit`, which runs this.
        // SAFETY: `remove_root` is a plain function that lives as long as
        // the program; `atexit` only records it.
        unsafe { libc::atexit(remove_root) };
        root
    })
}

extern "C" fn remove_root() {
    if let Some(root) = ROOT.get() {
        let _ = std::fs::remove_dir_all(root);
    }
}

/// Removes the scratch folders of test processes that have ended (known
/// on Linux by their missing `/proc` entry).
#[cfg(not(target_os = "linux"))]
fn remove_abandoned(_: &Path) {}

#[cfg(target_os = "linux")]
fn remove_abandoned(temp: &Path) {
    let Ok(entries) = std::fs::read_dir(temp) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let pid = name.to_str().and_then(|n| n.strip_prefix(PREFIX));
        let Some(pid) = pid.and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        if !Path::new(&format!("/proc/{pid}")).exists() {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}
