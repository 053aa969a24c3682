//! The texture panel (key `T`): the texture list shown with each entry's
//! name, size and thumbnail, the applied one marked; a row is picked with
//! the keys or the mouse, as the colour texture or as the one that gives
//! the heights (the bump), as a separate height map does.
//!
//! The list itself lives with the event loop ([`TextureList`]); the state
//! holds a copy of what the panel shows ([`TextureListing`]), which the
//! loop sends after every texture command. Thumbnails are made once per
//! entry, and only while the panel is open.

use std::sync::Arc;

use ratatui::layout::Rect;

use super::texture_list::TextureList;
use super::thumbnail::{Preview, THUMB_HEIGHT, THUMB_WIDTH};

/// Terminal rows per entry: the thumbnail's height (two pixels a row).
pub const ENTRY_ROWS: u16 = THUMB_HEIGHT.div_ceil(2) as u16;
/// Columns before an entry's text: the marker, a space, the thumbnail, a space.
pub const TEXT_COLUMN: u16 = 2 + THUMB_WIDTH as u16 + 1;
/// The panel's narrowest and widest width, borders included.
const MIN_WIDTH: u16 = 34;
const MAX_WIDTH: u16 = 60;

/// One entry as the panel shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureRow {
    /// The list's label (already sanitised).
    pub label: String,
    /// Size and thumbnail (`None`: not made, the panel being closed, or
    /// the entry does not load).
    pub preview: Option<Arc<Preview>>,
}

/// What the panel shows of the texture list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TextureListing {
    pub rows: Vec<TextureRow>,
    /// The applied entry.
    pub current: usize,
    /// The entry that gives the heights, when not the applied one's own.
    pub heights: Option<usize>,
    /// The shown model's own textures, a line per map of each material
    /// (`scene::model_textures`), drawn under the list; not entries.
    pub model: Vec<String>,
}

impl TextureListing {
    /// The label of the entry giving the heights, when one does.
    pub fn heights_label(&self) -> Option<&str> {
        self.heights
            .and_then(|h| self.rows.get(h))
            .map(|r| r.label.as_str())
    }
}

/// The listing of `list`, with each entry's preview when `previews` (made
/// on the first call, kept by the list).
pub fn listing(list: &mut TextureList, previews: bool) -> TextureListing {
    let labels: Vec<String> = list.entries().iter().map(|e| e.label.clone()).collect();
    let rows = labels
        .into_iter()
        .enumerate()
        .map(|(i, label)| TextureRow {
            label,
            preview: if previews { list.preview(i) } else { None },
        })
        .collect();
    TextureListing {
        rows,
        current: list.current(),
        heights: list.heights(),
        model: Vec::new(),
    }
}

/// The panel's state.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TexturePanel {
    pub open: bool,
    /// The highlighted entry (Enter applies it).
    pub cursor: usize,
    /// The first entry shown when the list is taller than the panel.
    pub scroll: usize,
    pub listing: TextureListing,
    /// Where the panel was last drawn (the loop reports it before each
    /// frame, so the mouse finds the rows the user sees).
    pub area: Option<Rect>,
}

/// Where the panel goes over `viewport` for `listing`: the top-left
/// corner, as wide as the longest label needs within bounds, as tall as the
/// list within the picture. `None` when the picture is too small.
pub fn panel_area(viewport: Rect, listing: &TextureListing) -> Option<Rect> {
    let longest = listing
        .rows
        .iter()
        .map(|r| r.label.chars().count())
        .max()
        .unwrap_or(0) as u16;
    let width = (TEXT_COLUMN + longest.saturating_add(3))
        .clamp(MIN_WIDTH, MAX_WIDTH)
        .min(viewport.width);
    let wanted = 2 + ENTRY_ROWS.saturating_mul(listing.rows.len().max(1) as u16);
    let height = wanted.min(viewport.height);
    (width > TEXT_COLUMN + 2 && height >= 2 + ENTRY_ROWS)
        .then(|| Rect::new(viewport.x, viewport.y, width, height))
}

/// Where the model's texture lines go: under the panel `above`, as wide,
/// as tall as they need within `viewport` (`None`: no lines, or no room).
pub fn model_area(viewport: Rect, above: Rect, listing: &TextureListing) -> Option<Rect> {
    if listing.model.is_empty() {
        return None;
    }
    let longest = listing
        .model
        .iter()
        .map(|l| l.chars().count())
        .max()
        .unwrap_or(0) as u16;
    let width = longest
        .saturating_add(2)
        .clamp(MIN_WIDTH, MAX_WIDTH)
        .min(viewport.width);
    let y = above.y + above.height;
    let room = (viewport.y + viewport.height).saturating_sub(y);
    let height = (listing.model.len() as u16).saturating_add(2).min(room);
    (height >= 3).then(|| Rect::new(above.x, y, width, height))
}

/// Entries a panel of `area` shows at once.
pub fn visible_entries(area: Rect) -> usize {
    (area.height.saturating_sub(2) / ENTRY_ROWS) as usize
}

impl TexturePanel {
    fn len(&self) -> usize {
        self.listing.rows.len()
    }

    fn visible(&self) -> usize {
        self.area.map_or(usize::MAX, visible_entries).max(1)
    }

    /// The first entry shown: `scroll`, kept where the panel is full.
    pub fn first_shown(&self) -> usize {
        self.scroll
            .min(self.len().saturating_sub(self.visible().min(self.len())))
    }

    /// Whether the cell is on the panel (open and drawn).
    pub fn contains(&self, col: u16, row: u16) -> bool {
        self.open
            && self
                .area
                .is_some_and(|a| a.contains(ratatui::layout::Position::new(col, row)))
    }

    /// The entry drawn at a cell of the panel, if any (not the border).
    pub fn entry_at(&self, col: u16, row: u16) -> Option<usize> {
        let a = self.area?;
        if !self.contains(col, row)
            || col == a.x
            || col + 1 >= a.x + a.width
            || row == a.y
            || row + 1 >= a.y + a.height
        {
            return None;
        }
        let slot = ((row - a.y - 1) / ENTRY_ROWS) as usize;
        if slot >= self.visible() {
            return None;
        }
        let i = self.first_shown() + slot;
        (i < self.len()).then_some(i)
    }

    /// Moves the cursor by `delta` entries (clamped to the list) and
    /// scrolls to keep it shown.
    pub fn move_cursor(&mut self, delta: i32) {
        let last = self.len().saturating_sub(1) as i64;
        self.cursor = (self.cursor as i64 + i64::from(delta)).clamp(0, last) as usize;
        self.show_cursor();
    }

    /// Scrolls just enough for the cursor to be shown.
    pub fn show_cursor(&mut self) {
        let visible = self.visible();
        self.scroll = self.first_shown();
        if self.cursor < self.scroll {
            self.scroll = self.cursor;
        } else if self.cursor >= self.scroll.saturating_add(visible) {
            self.scroll = self.cursor + 1 - visible;
        }
    }

    /// Scrolls the list by `delta` entries, the cursor staying where it is.
    pub fn scroll_by(&mut self, delta: i32) {
        let max = self.len().saturating_sub(self.visible()) as i64;
        self.scroll = (self.first_shown() as i64 + i64::from(delta)).clamp(0, max) as usize;
    }

    /// A new listing from the loop: the cursor stays on the list.
    pub fn set_listing(&mut self, listing: TextureListing) {
        self.listing = listing;
        self.cursor = self.cursor.min(self.len().saturating_sub(1));
        self.scroll = self.first_shown();
    }

    /// The heights choice for entry `i`: from it, or (when it already
    /// gives them) back to each texture's own.
    pub fn heights_for(&self, i: usize) -> Option<usize> {
        if self.listing.heights == Some(i) {
            None
        } else {
            Some(i)
        }
    }
}
