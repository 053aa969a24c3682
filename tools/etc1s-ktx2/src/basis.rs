//! The parts of an ETC1S .basis file a KTX2 file holds (the .basis
//! header's packed little-endian fields, as the Basis Universal file
//! format lays them out: a 77-byte header, then 23-byte slice descriptions).

/// Where the header's fields lie, and their widths in bytes.
const SIG: usize = 0;
const HEADER_SIZE: usize = 4;
const TOTAL_SLICES: (usize, usize) = (14, 3);
const TEX_FORMAT: usize = 20;
const FLAGS: (usize, usize) = (21, 2);
const TOTAL_ENDPOINTS: (usize, usize) = (39, 2);
const ENDPOINT_CB: [(usize, usize); 2] = [(41, 4), (45, 3)];
const TOTAL_SELECTORS: (usize, usize) = (48, 2);
const SELECTOR_CB: [(usize, usize); 2] = [(50, 4), (54, 3)];
const TABLES: [(usize, usize); 2] = [(57, 4), (61, 4)];
const SLICE_DESCS: (usize, usize) = (65, 4);
const EXTENDED_SIZE: (usize, usize) = (73, 4);
const HEADER_BYTES: usize = 77;
/// A slice description's fields: level, flags, data offset and length.
const SLICE_BYTES: usize = 23;
const SLICE_LEVEL: (usize, usize) = (3, 1);
const SLICE_FLAGS: (usize, usize) = (4, 1);
const SLICE_DATA: [(usize, usize); 2] = [(13, 4), (17, 4)];
/// Header flag: ETC1S data; slice flag: an alpha slice.
const FLAG_ETC1S: u64 = 1;
const SLICE_HAS_ALPHA: u64 = 1;

/// One slice: a level's RGB or alpha data.
pub struct Slice<'a> {
    pub level: u32,
    pub alpha: bool,
    pub data: &'a [u8],
}

/// What the KTX2 file's global data and levels are made of.
pub struct Parts<'a> {
    pub endpoint_count: u16,
    pub selector_count: u16,
    pub endpoints: &'a [u8],
    pub selectors: &'a [u8],
    pub tables: &'a [u8],
    /// In the file's order: by level, each RGB slice before its alpha one.
    pub slices: Vec<Slice<'a>>,
}

impl Parts<'_> {
    pub fn levels(&self) -> u32 {
        self.slices.iter().map(|s| s.level + 1).max().unwrap_or(0)
    }

    pub fn has_alpha(&self) -> bool {
        self.slices.iter().any(|s| s.alpha)
    }
}

/// The packed little-endian number of `width` bytes at `at` in the
/// record that starts at `record`.
fn field(bytes: &[u8], record: usize, (at, width): (usize, usize)) -> u64 {
    (0..width).fold(0, |n, i| n | u64::from(bytes[record + at + i]) << (8 * i))
}

/// The bytes an (offset from the file's start, length) pair of fields of
/// the record at `record` points at.
fn span(bytes: &[u8], record: usize, [offset, length]: [(usize, usize); 2]) -> &[u8] {
    let start = field(bytes, record, offset) as usize;
    &bytes[start..start + field(bytes, record, length) as usize]
}

/// The parts of an ETC1S .basis file of one image (the encoder's output,
/// so trusted: a file it did not write panics here).
pub fn parse(bytes: &[u8]) -> Parts<'_> {
    let header = |f| field(bytes, 0, f);
    assert_eq!(&bytes[SIG..SIG + 2], b"sB", "not a .basis file");
    assert_eq!(header((HEADER_SIZE, 2)), HEADER_BYTES as u64);
    assert_eq!(bytes[TEX_FORMAT], 0, "not ETC1S");
    assert_ne!(header(FLAGS) & FLAG_ETC1S, 0, "not ETC1S");
    assert_eq!(header(EXTENDED_SIZE), 0, "extended data");
    let descs = header(SLICE_DESCS) as usize;
    let slices = (0..header(TOTAL_SLICES) as usize)
        .map(|i| slice(bytes, descs + i * SLICE_BYTES))
        .collect();
    Parts {
        endpoint_count: header(TOTAL_ENDPOINTS) as u16,
        selector_count: header(TOTAL_SELECTORS) as u16,
        endpoints: span(bytes, 0, ENDPOINT_CB),
        selectors: span(bytes, 0, SELECTOR_CB),
        tables: span(bytes, 0, TABLES),
        slices,
    }
}

/// The slice described at `record`.
fn slice(bytes: &[u8], record: usize) -> Slice<'_> {
    Slice {
        level: field(bytes, record, SLICE_LEVEL) as u32,
        alpha: field(bytes, record, SLICE_FLAGS) & SLICE_HAS_ALPHA != 0,
        data: span(bytes, record, SLICE_DATA),
    }
}
