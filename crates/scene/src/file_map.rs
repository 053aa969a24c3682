//! A large model file mapped into memory instead of read. Reading copies
//! every byte into fresh pages the kernel must first clear (a third of a
//! 100 MB OBJ's load); a map shares the page cache's own pages.
//!
//! A map has one hazard: if another program shrinks the file while it is
//! mapped, touching a page past the new end raises SIGBUS, which would end
//! relief with the terminal still in raw mode. A SIGBUS handler, which the
//! program installs (a process-wide setting: relief's binary does, through
//! [`install_bus_guard`]; until then files are read, never mapped), catches
//! faults inside the maps made here, lays zero pages over the lost part and
//! marks the map, and the loader then reports that the file changed while
//! it was read. Bytes rewritten in place, without shrinking, are read as
//! whatever they are then: the readers take any bytes. Files are mapped
//! on Linux only (the handler reads its fault address the Linux way);
//! elsewhere every file is read.

use std::fs::File;
use std::ops::Deref;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The maps that may be read at once (a load maps one file; a view may run
/// a load beside a render of another): a map is only made in a free slot.
const SLOTS: usize = 8;

/// Where one live map is, and whether part of it was lost.
struct Slot {
    start: AtomicUsize,
    end: AtomicUsize,
    cut: AtomicBool,
}

static MAPS: [Slot; SLOTS] = [const {
    Slot {
        start: AtomicUsize::new(0),
        end: AtomicUsize::new(0),
        cut: AtomicBool::new(false),
    }
}; SLOTS];

/// The SIGBUS action that was in place before ours (the standard
/// library's, or the default), set before ours is installed; the page
/// size; whether ours is installed.
#[cfg(target_os = "linux")]
static BEFORE: OnceLock<libc::sigaction> = OnceLock::new();
static PAGE: AtomicUsize = AtomicUsize::new(0);
static INSTALLED: OnceLock<bool> = OnceLock::new();

/// A file's bytes, mapped read-only, with the slot that guards them.
pub(crate) struct MappedFile {
    map: memmap2::Mmap,
    slot: usize,
}

impl MappedFile {
    /// Maps the first `len` bytes of `file`; none when the map cannot be
    /// made (an empty file, a file system that cannot map, every slot
    /// taken, no handler): the caller reads the file instead.
    pub fn new(file: &File, len: u64) -> Option<MappedFile> {
        let len = usize::try_from(len).ok().filter(|&l| l > 0)?;
        let page = guard_installed()?;
        // SAFETY: the map is only read. A file changed in place is read as
        // it is then; a shrunk one is caught by the handler (module text).
        let map = unsafe { memmap2::MmapOptions::new().len(len).map(file) }.ok()?;
        let start = map.as_ptr() as usize;
        let end = (start + len).next_multiple_of(page);
        let slot = MAPS.iter().position(|s| {
            s.start
                .compare_exchange(0, start, Ordering::AcqRel, Ordering::Relaxed)
                .is_ok()
        })?;
        MAPS[slot].cut.store(false, Ordering::Release);
        MAPS[slot].end.store(end, Ordering::Release);
        Some(MappedFile { map, slot })
    }

    /// Whether part of the file went away while it was mapped (those bytes
    /// then read as zeros).
    pub fn was_cut(&self) -> bool {
        MAPS[self.slot].cut.load(Ordering::Acquire)
    }
}

impl Deref for MappedFile {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        &self.map
    }
}

impl Drop for MappedFile {
    fn drop(&mut self) {
        // The slot is freed before the map goes (the map's own drop unmaps
        // it, zero pages included): a fault can no longer reach either.
        let slot = &MAPS[self.slot];
        slot.end.store(0, Ordering::Release);
        slot.start.store(0, Ordering::Release);
    }
}

/// The page size once the SIGBUS handler is installed; none before (or
/// when it could not be).
fn guard_installed() -> Option<usize> {
    INSTALLED
        .get()
        .is_some_and(|&on| on)
        .then(|| PAGE.load(Ordering::Acquire))
}

/// Installs the SIGBUS handler, once for the process: from then on large
/// model files are mapped. Whether it is installed.
#[cfg(target_os = "linux")]
pub fn install_bus_guard() -> bool {
    *INSTALLED.get_or_init(|| {
        // SAFETY: plain system calls on values made here.
        unsafe {
            let Ok(page) = usize::try_from(libc::sysconf(libc::_SC_PAGESIZE)) else {
                return false;
            };
            PAGE.store(page, Ordering::Release);
            let mut before: libc::sigaction = std::mem::zeroed();
            if page == 0 || libc::sigaction(libc::SIGBUS, std::ptr::null(), &mut before) != 0 {
                return false;
            }
            // Known before ours can run and need it.
            let _ = BEFORE.set(before);
            let mut ours: libc::sigaction = std::mem::zeroed();
            ours.sa_sigaction = on_bus_error as *const () as usize;
            ours.sa_flags = libc::SA_SIGINFO | libc::SA_ONSTACK;
            libc::sigemptyset(&mut ours.sa_mask);
            libc::sigaction(libc::SIGBUS, &ours, std::ptr::null_mut()) == 0
        }
    })
}

/// A fault inside a live map: zero pages from the faulting page to the
/// map's end (a shrunk file lost its tail), the map marked, and the read
/// goes on. Any other fault goes to the action before ours, which then
/// sees the access run again. Only atomics and system calls: what a
/// signal handler may do.
#[cfg(target_os = "linux")]
extern "C" fn on_bus_error(signal: libc::c_int, info: *mut libc::siginfo_t, _: *mut libc::c_void) {
    // SAFETY: the kernel passes a valid siginfo with SA_SIGINFO.
    let at = unsafe { (*info).si_addr() } as usize;
    let page = PAGE.load(Ordering::Acquire);
    for slot in &MAPS {
        let (start, end) = (
            slot.start.load(Ordering::Acquire),
            slot.end.load(Ordering::Acquire),
        );
        if start <= at && at < end {
            let from = at & !(page - 1);
            // SAFETY: the range lies inside a map this module made and
            // still holds (its slot is live), which only it reads.
            let zeros = unsafe {
                libc::mmap(
                    from as *mut libc::c_void,
                    end - from,
                    libc::PROT_READ,
                    libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | libc::MAP_FIXED,
                    -1,
                    0,
                )
            };
            if zeros != libc::MAP_FAILED {
                slot.cut.store(true, Ordering::Release);
                return;
            }
        }
    }
    // SAFETY: restores an action the kernel gave us, or the default.
    unsafe {
        match BEFORE.get() {
            Some(before) => libc::sigaction(signal, before, std::ptr::null_mut()),
            None => {
                libc::signal(signal, libc::SIG_DFL);
                0
            }
        };
    }
}

/// Elsewhere the handler's signal details differ: files are read.
#[cfg(not(target_os = "linux"))]
pub fn install_bus_guard() -> bool {
    let _ = INSTALLED.set(false);
    false
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;
    use std::io::Write;

    fn temp_file(tag: &str, bytes: &[u8]) -> (std::path::PathBuf, File) {
        let path = std::env::temp_dir().join(format!("relief-map-{tag}-{}", std::process::id()));
        let mut f = File::create(&path).unwrap();
        f.write_all(bytes).unwrap();
        let f = File::options().read(true).write(true).open(&path).unwrap();
        (path, f)
    }

    #[test]
    fn a_map_holds_the_files_bytes() {
        install_bus_guard();
        let bytes: Vec<u8> = (0..100_000u32).map(|i| (i % 251) as u8).collect();
        let (path, file) = temp_file("whole", &bytes);
        let map = MappedFile::new(&file, bytes.len() as u64).unwrap();
        assert_eq!(&map[..], &bytes[..]);
        assert!(!map.was_cut());
        drop(map);
        std::fs::remove_file(path).unwrap();
    }

    #[test]
    fn a_file_shrunk_while_mapped_reads_as_zeros_past_its_new_end() {
        install_bus_guard();
        let page = guard_installed().unwrap();
        let bytes = vec![b'v'; 8 * page];
        let (path, file) = temp_file("shrunk", &bytes);
        let map = MappedFile::new(&file, bytes.len() as u64).unwrap();
        // Another program cuts the file to a page and a half.
        file.set_len((page + page / 2) as u64).unwrap();
        let seen = map.to_vec();
        assert!(map.was_cut());
        assert!(seen[..page + page / 2].iter().all(|&b| b == b'v'));
        // The rest of the kept page is the file's zeros; the pages after
        // it are ours.
        assert!(seen[page + page / 2..].iter().all(|&b| b == 0));
        drop(map);
        // The slot is free again: a new map is not marked.
        let again = MappedFile::new(&file, (page + page / 2) as u64).unwrap();
        assert!(!again.was_cut());
        drop(again);
        std::fs::remove_file(path).unwrap();
    }

    #[test]
    fn an_empty_file_is_not_mapped() {
        let (path, file) = temp_file("empty", b"");
        assert!(MappedFile::new(&file, 0).is_none());
        std::fs::remove_file(path).unwrap();
    }
}
