//! The program's allocator: the system's, with the inside of every big
//! block advised to be backed by huge pages (Linux's transparent huge
//! pages, in the `madvise` mode many distributions ship).
//!
//! Why: a model's arrays are written once, right after they are allocated.
//! With 4 KiB pages each 4 KiB written first is a page fault and a page
//! cleared by the kernel: about a fifth of a 100 MB OBJ's load
//! (docs/models.md). A 2 MiB page takes one fault for 512 of them.
//! What is allocated does not change: only whole 2 MiB pieces inside a
//! block are advised, so no block holds more memory than its own size
//! rounded to its pages (the budget's accounting stands).

use std::alloc::{GlobalAlloc, Layout, System};

/// Blocks of this size and more are advised; smaller ones would gain
/// little and could not hold a whole huge page often enough.
pub const ADVISED_FROM: usize = 4 << 20;
/// The size (and alignment) of a huge page on x86-64 and arm64 (4 KiB base pages).
const HUGE_PAGE: usize = 2 << 20;

/// The system allocator, advising big blocks to take huge pages.
pub struct HugePages;

// SAFETY: every block comes from, and returns to, the system allocator with
// the layout it was asked for; the advice changes how the kernel backs a
// block's pages, never where the block is or what it holds.
unsafe impl GlobalAlloc for HugePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) }
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, size: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, layout, size) };
        advise(q, size);
        q
    }
}

/// The whole huge pages inside the block of `size` bytes at `at`, as a
/// start and an end address; none for a small block or one that holds no
/// whole huge page.
pub fn advised_range(at: usize, size: usize) -> Option<(usize, usize)> {
    if at == 0 || size < ADVISED_FROM {
        return None;
    }
    let start = at.checked_next_multiple_of(HUGE_PAGE)?;
    let end = at.checked_add(size)? & !(HUGE_PAGE - 1);
    (end > start).then_some((start, end))
}

#[cfg(target_os = "linux")]
fn advise(p: *mut u8, size: usize) {
    if let Some((start, end)) = advised_range(p as usize, size) {
        // SAFETY: the range lies inside the block just allocated. A kernel
        // without transparent huge pages refuses the advice: nothing
        // changes then.
        unsafe { libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE) };
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_: *mut u8, _: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_whole_huge_pages_inside_a_big_block_are_advised() {
        assert_eq!(advised_range(HUGE_PAGE, ADVISED_FROM - 1), None);
        assert_eq!(advised_range(0, ADVISED_FROM), None);
        // Aligned: the whole block.
        assert_eq!(
            advised_range(HUGE_PAGE, ADVISED_FROM),
            Some((HUGE_PAGE, HUGE_PAGE + ADVISED_FROM))
        );
        // Unaligned: the pages inside, none past either end.
        let at = 3 * HUGE_PAGE + 16;
        let (start, end) = advised_range(at, ADVISED_FROM + 100).unwrap();
        assert_eq!((start, end), (4 * HUGE_PAGE, 5 * HUGE_PAGE));
        for at in [1, 4095, HUGE_PAGE - 1, 7 * HUGE_PAGE + 12_345] {
            for size in [
                ADVISED_FROM,
                ADVISED_FROM + 1,
                3 * HUGE_PAGE - 1,
                9 * HUGE_PAGE,
            ] {
                if let Some((start, end)) = advised_range(at, size) {
                    assert!(start >= at && end <= at + size);
                    assert_eq!((start % HUGE_PAGE, end % HUGE_PAGE), (0, 0));
                    // At most one huge page lost at each end.
                    assert!(end - start > size - 2 * HUGE_PAGE);
                }
            }
        }
        // A block reaching the end of the address space.
        assert_eq!(advised_range(usize::MAX - HUGE_PAGE, ADVISED_FROM), None);
    }

    /// The mapping of the block is marked for huge pages (`hg` among its
    /// flags in /proc/self/smaps) where the kernel has them at all.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_big_block_is_marked_for_huge_pages() {
        if !std::path::Path::new("/sys/kernel/mm/transparent_hugepage/enabled").exists() {
            return;
        }
        let layout = Layout::from_size_align(16 << 20, 64).unwrap();
        // SAFETY: a non-zero size; freed below with the same layout.
        let p = unsafe { HugePages.alloc(layout) };
        assert!(!p.is_null());
        let (start, _) = advised_range(p as usize, layout.size()).unwrap();
        let smaps = std::fs::read_to_string("/proc/self/smaps").unwrap();
        let mut inside = false;
        let mut flags = None;
        for line in smaps.lines() {
            let range = line
                .split_whitespace()
                .next()
                .and_then(|w| w.split_once('-'));
            if let Some((a, b)) = range
                && let (Ok(a), Ok(b)) = (usize::from_str_radix(a, 16), usize::from_str_radix(b, 16))
            {
                inside = (a..b).contains(&start);
            } else if inside && let Some(f) = line.strip_prefix("VmFlags:") {
                flags = Some(f.split_whitespace().map(str::to_string).collect::<Vec<_>>());
            }
        }
        // SAFETY: allocated above with this layout.
        unsafe { HugePages.dealloc(p, layout) };
        let flags = flags.expect("the block's mapping in /proc/self/smaps");
        assert!(flags.iter().any(|f| f == "hg"), "{flags:?}");
    }
}
