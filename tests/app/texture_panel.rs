//! The texture panel (key `T`): keys and mouse through `update`, what it
//! draws (names, sizes, the marker, the thumbnail's colours), the loop
//! filling it, and the heights taken from another texture of the list.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::sync::{Arc, mpsc};

use crossterm::event::{
    Event, KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind,
};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use relief::app::event_loop::{Looper, Msg};
use relief::app::keys::Mode;
use relief::app::stage::Stage;
use relief::app::texture_list::TextureList;
use relief::app::textures::{TextureListing, TextureRow, listing};
use relief::app::view::status_line;
use relief::app::{Action, Command, DragButton, State, action_for_event, action_for_key, update};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_options::OptId;
use relief_pipeline::render::Renderer;
use relief_scene::{ModelChoice, SceneKind};
use relief_term::{ColorDepth, HalfBlocks, SgrBackend};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

fn press(code: KeyCode) -> KeyEvent {
    KeyEvent::new(code, KeyModifiers::NONE)
}

fn ch(c: char) -> KeyEvent {
    press(KeyCode::Char(c))
}

/// Presses a key and applies its action; the command it asks for.
fn key(s: &mut State, event: KeyEvent) -> Option<Command> {
    let action = action_for_key(s, &event).expect("a bound key");
    update(s, action)
}

fn mouse(s: &mut State, kind: MouseEventKind, col: u16, row: u16) -> Option<Action> {
    action_for_event(
        s,
        &Event::Mouse(MouseEvent {
            kind,
            column: col,
            row,
            modifiers: KeyModifiers::NONE,
        }),
    )
}

/// A listing of `n` rows named t0, t1, … (no previews), `current` applied.
fn rows(n: usize, current: usize) -> TextureListing {
    TextureListing {
        rows: (0..n)
            .map(|i| TextureRow {
                label: format!("t{i}"),
                preview: None,
            })
            .collect(),
        current,
        heights: None,
        model: Vec::new(),
    }
}

/// A state with the panel open over 6 entries, 3 shown (rows 1–6 of a
/// panel at the top-left, two rows per entry).
fn open_panel() -> State {
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    update(&mut s, Action::TexturesListed(rows(6, 1)));
    assert_eq!(Mode::of(&s), Mode::Normal);
    assert_eq!(key(&mut s, ch('T')), Some(Command::ListTextures));
    assert_eq!(Mode::of(&s), Mode::Textures);
    assert_eq!(s.textures.cursor, 1, "the cursor starts on the applied one");
    update(&mut s, Action::TexturesFit(Some(Rect::new(0, 0, 34, 8))));
    s
}

#[test]
fn keys_move_pick_and_close() {
    let mut s = open_panel();
    assert_eq!(key(&mut s, ch('j')), None);
    assert_eq!(key(&mut s, press(KeyCode::Down)), None);
    assert_eq!(s.textures.cursor, 3);
    // Three entries shown: the list scrolled to keep the cursor in view.
    assert_eq!(s.textures.first_shown(), 1);
    assert_eq!(key(&mut s, ch('k')), None);
    assert_eq!(key(&mut s, press(KeyCode::Up)), None);
    assert_eq!(s.textures.cursor, 1);
    assert_eq!(key(&mut s, press(KeyCode::End)), None);
    assert_eq!((s.textures.cursor, s.textures.first_shown()), (5, 3));
    assert_eq!(key(&mut s, press(KeyCode::Home)), None);
    assert_eq!((s.textures.cursor, s.textures.first_shown()), (0, 0));
    key(&mut s, ch('j'));
    key(&mut s, ch('j'));
    assert_eq!(
        key(&mut s, press(KeyCode::Enter)),
        Some(Command::SelectTexture(2))
    );
    assert_eq!(key(&mut s, ch('H')), Some(Command::SetHeights(Some(2))));
    // The loop's answer marks entry 2 as the heights: H again goes back.
    let mut l = rows(6, 2);
    l.heights = Some(2);
    update(&mut s, Action::TexturesListed(l));
    assert_eq!(key(&mut s, ch('H')), Some(Command::SetHeights(None)));
    // Keys the panel does not take act on the picture (`k` is the panel's).
    assert_eq!(
        action_for_key(&s, &ch('m')),
        Some(Action::next(OptId::Shading))
    );
    assert_eq!(action_for_key(&s, &ch('x')), Some(Action::NextTexture));
    assert_eq!(action_for_key(&s, &ch('k')), Some(Action::TexturesMove(-1)));
    assert_eq!(action_for_key(&s, &ch('q')), Some(Action::Quit));
    // Esc closes the panel, not the program; so does T.
    assert_eq!(key(&mut s, press(KeyCode::Esc)), None);
    assert!(!s.textures.open && !s.quit);
    assert_eq!(Mode::of(&s), Mode::Normal);
    key(&mut s, ch('T'));
    key(&mut s, ch('T'));
    assert_eq!(Mode::of(&s), Mode::Normal);
    // The help, drawn on top, takes Esc first.
    key(&mut s, ch('T'));
    key(&mut s, ch('?'));
    assert_eq!(Mode::of(&s), Mode::Help);
    key(&mut s, press(KeyCode::Esc));
    assert_eq!(Mode::of(&s), Mode::Textures);
}

#[test]
fn clicks_pick_rows_and_the_wheel_scrolls_over_the_panel_only() {
    let mut s = open_panel();
    let down = |b| MouseEventKind::Down(b);
    // Row 3 is the second entry shown (rows 1-2 the first, 3-4 the second).
    let a = mouse(&mut s, down(MouseButton::Left), 10, 3).unwrap();
    assert_eq!(
        a,
        Action::TexturesClick {
            button: DragButton::Left,
            col: 10,
            row: 3
        }
    );
    assert_eq!(update(&mut s, a), Some(Command::SelectTexture(1)));
    let a = mouse(&mut s, down(MouseButton::Right), 10, 6).unwrap();
    assert_eq!(update(&mut s, a), Some(Command::SetHeights(Some(2))));
    assert_eq!(s.textures.cursor, 2);
    // The border is no row.
    let a = mouse(&mut s, down(MouseButton::Left), 0, 3).unwrap();
    assert_eq!(update(&mut s, a), None);
    // The wheel over the panel scrolls it, the cursor stays.
    let a = mouse(&mut s, MouseEventKind::ScrollDown, 5, 5).unwrap();
    assert_eq!(a, Action::TexturesScroll(1));
    update(&mut s, a.clone());
    update(&mut s, a.clone());
    update(&mut s, a);
    assert_eq!(s.textures.first_shown(), 3, "no further than the last page");
    assert_eq!(s.textures.cursor, 2);
    let a = mouse(&mut s, down(MouseButton::Left), 10, 1).unwrap();
    assert_eq!(update(&mut s, a), Some(Command::SelectTexture(3)));
    let distance = s.distance;
    // Elsewhere the wheel still zooms and a press still starts a drag.
    assert_eq!(
        mouse(&mut s, MouseEventKind::ScrollUp, 60, 5),
        Some(Action::ZoomIn)
    );
    update(&mut s, Action::ZoomIn);
    assert!(s.distance < distance);
    assert!(matches!(
        mouse(&mut s, down(MouseButton::Left), 60, 5),
        Some(Action::MouseDown { .. })
    ));
    // Closed, the same cells belong to the picture again.
    update(&mut s, Action::CloseTextures);
    assert_eq!(
        mouse(&mut s, MouseEventKind::ScrollUp, 5, 5),
        Some(Action::ZoomIn)
    );
}

/// A 4×4 PNG: red, green / blue, white quadrants (no alpha: the heights
/// are the mean of RGB).
fn quadrants(name: &str) -> PathBuf {
    let mut fb = Framebuffer::new(4, 4);
    for y in 0..4 {
        for x in 0..4 {
            let c = match (x < 2, y < 2) {
                (true, true) => [255, 0, 0],
                (false, true) => [0, 255, 0],
                (true, false) => [0, 0, 255],
                (false, false) => [255, 255, 255],
            };
            fb.set(x, y, c);
        }
    }
    let path = crate::common::scratch::scratch_file(&format!("panel-{name}"));
    fb.save_png(&path).unwrap();
    path
}

fn draw(s: &State, w: u16, h: u16) -> Buffer {
    let mut term = Terminal::new(TestBackend::new(w, h)).unwrap();
    let fb = Framebuffer::new(w as usize, 2 * h as usize);
    term.draw(|f| relief::app::view(f, s, &fb, [0, 0, 0]))
        .unwrap();
    term.backend().buffer().clone()
}

fn row_text(buf: &Buffer, y: u16) -> String {
    (0..buf.area.width)
        .map(|x| buf[(x, y)].symbol().to_string())
        .collect()
}

#[test]
fn the_panel_shows_names_sizes_the_marker_and_thumbnails_in_the_screen_s_colours() {
    let path = quadrants("q.png");
    let (mut list, errors) = TextureList::from_args(std::slice::from_ref(&path), None);
    assert!(errors.is_empty(), "{errors:?}");
    let n = list.len();
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    update(&mut s, Action::TexturesListed(listing(&mut list, false)));
    update(&mut s, Action::ToggleTextures);
    update(&mut s, Action::TexturesListed(listing(&mut list, true)));
    let buf = draw(&s, 100, 40);
    let rows: Vec<String> = (0..40).map(|y| row_text(&buf, y)).collect();
    assert!(
        rows[0].contains(&format!("textures {n}/{n}")),
        "{}",
        rows[0]
    );
    assert!(rows[1].contains("brick (built-in)"), "{}", rows[1]);
    assert!(rows[2].contains("256×256"), "{}", rows[2]);
    // The file is the applied entry: marked, its size below its name.
    let y = 1 + 2 * (n - 1) as u16;
    let name = path.file_name().unwrap().to_str().unwrap();
    assert!(rows[y as usize].contains(name), "{}", rows[y as usize]);
    assert!(rows[y as usize].starts_with("│▶"), "{}", rows[y as usize]);
    assert!(rows[y as usize + 1].contains("4×4"));
    assert_eq!(rows.iter().filter(|r| r.contains('▶')).count(), 1);
    // The thumbnail (columns 3-6): the texture's 4×4 pixels, two per cell.
    let rgb = |c: [u8; 3]| Color::Rgb(c[0], c[1], c[2]);
    let cell = |x: u16, y: u16| &buf[(3 + x, y)];
    for (x, y, want) in [
        (0, 0, [255, 0, 0]),
        (2, 0, [0, 255, 0]),
        (0, 1, [0, 0, 255]),
        (3, 1, [255, 255, 255]),
    ] {
        assert_eq!(cell(x, y + y_of(n)).bg, rgb(want), "cell {x},{y}");
    }
    // In 256 colours the cells take the picture encoder's colours.
    s.depth = ColorDepth::Palette256;
    let buf = draw(&s, 100, 40);
    let preview = s.textures.listing.rows[n - 1].preview.clone().unwrap();
    let mut own = Buffer::empty(Rect::new(0, 0, 4, 2));
    HalfBlocks {
        fb: &preview.thumb,
        depth: ColorDepth::Palette256,
        dither: false,
        pad: [0, 0, 0],
    }
    .render_from_row(0, own.area, &mut own);
    for y in 0..2 {
        for x in 0..4 {
            let got = &buf[(3 + x, y + y_of(n))];
            assert!(matches!(got.bg, Color::Indexed(_)), "{got:?}");
            assert_eq!((got.fg, got.bg), (own[(x, y)].fg, own[(x, y)].bg));
        }
    }
    // The heights mark and the status line, once another entry gives them.
    let mut l = s.textures.listing.clone();
    l.heights = Some(0);
    update(&mut s, Action::TexturesListed(l));
    let buf = draw(&s, 100, 40);
    assert!(row_text(&buf, 2).contains("◆ heights"));
    assert!(status_line(&s, 400).contains("heights brick"));
    assert!(
        status_line(&s, 60).contains("H:brick"),
        "{}",
        status_line(&s, 60)
    );
    std::fs::remove_file(path).unwrap();
}

/// The first row of entry `n - 1` (the last) of a panel at the top.
fn y_of(n: usize) -> u16 {
    1 + 2 * (n - 1) as u16
}

#[test]
fn thumbnails_are_made_once_and_only_while_the_panel_is_open() {
    let mut list = TextureList::new();
    let closed = listing(&mut list, false);
    assert!(closed.rows.iter().all(|r| r.preview.is_none()));
    let first = listing(&mut list, true);
    let again = listing(&mut list, true);
    for (a, b) in first.rows.iter().zip(&again.rows) {
        let (a, b) = (a.preview.as_ref().unwrap(), b.preview.as_ref().unwrap());
        assert!(Arc::ptr_eq(a, b), "made again");
    }
}

/// Runs the loop over `msgs` with `list` on a 100×30 screen.
fn run(list: &RefCell<TextureList>, state: State, msgs: Vec<Msg>) -> State {
    let (tx, rx) = mpsc::channel();
    for m in msgs {
        tx.send(m).unwrap();
    }
    tx.send(Msg::InputClosed("end".into())).unwrap();
    let mut term = Terminal::new(SgrBackend::with_size(Vec::new(), 100, 30)).unwrap();
    let mut state = state;
    Looper {
        textures: Some(list),
        ..Looper::new(&mut term, &rx, |_: &State, fb: &mut Framebuffer| {
            fb.fill([1, 2, 3]);
            relief_core::stats::FrameStats::default()
        })
    }
    .run(&mut state)
    .unwrap();
    state
}

#[test]
fn the_loop_fills_the_panel_and_applies_what_it_picks() {
    let list = RefCell::new(TextureList::new());
    let state = State::new(Settings::default(), ColorDepth::Truecolor);
    let k = |c| Msg::Input(Event::Key(ch(c)));
    // Closed: the names only.
    let s = run(&list, state, vec![]);
    assert_eq!(s.textures.listing.rows.len(), list.borrow().len());
    assert!(s.textures.listing.rows.iter().all(|r| r.preview.is_none()));
    // Open, down one, Enter: the second texture applied, thumbnails made.
    let s = run(
        &list,
        s,
        vec![
            k('T'),
            k('j'),
            Msg::Input(Event::Key(press(KeyCode::Enter))),
        ],
    );
    assert_eq!(list.borrow().current(), 1);
    assert_eq!(s.textures.listing.current, 1);
    assert!(s.textures.listing.rows.iter().all(|r| r.preview.is_some()));
    // H on the first row: its heights under the second's colour.
    let s = run(
        &list,
        s,
        vec![Msg::Input(Event::Key(press(KeyCode::Home))), k('H')],
    );
    assert_eq!(list.borrow().heights(), Some(0));
    assert_eq!(s.textures.listing.heights, Some(0));
    assert!(s.message.as_deref().unwrap().contains("heights: brick"));
    // A right click on it again: each texture's own heights. (The loop
    // reports where the panel is before each frame; these runs end before
    // their first, so the report is made here as the loop makes it.)
    let mut s = s;
    let viewport = relief::app::view::areas(Rect::new(0, 0, 100, 30)).viewport;
    let area = relief::app::view::texture_panel_area(viewport, &s);
    assert_eq!(area.map(|a| (a.x, a.y)), Some((0, 0)));
    update(&mut s, Action::TexturesFit(area));
    let click = Msg::Input(Event::Mouse(MouseEvent {
        kind: MouseEventKind::Down(MouseButton::Right),
        column: 10,
        row: 1,
        modifiers: KeyModifiers::NONE,
    }));
    let s = run(&list, s, vec![click]);
    assert_eq!(list.borrow().heights(), None);
    assert_eq!(s.textures.listing.heights, None);
}

fn render(texture: Arc<relief_texture::Texture>) -> Framebuffer {
    let mut stage = Stage::new(SceneKind::Cube, &ModelChoice::Cube, texture, false).unwrap();
    let state = State::new(Settings::default(), ColorDepth::Truecolor);
    let mut fb = Framebuffer::new(96, 72);
    stage.render(&mut Renderer::new(), &state, &mut fb);
    fb
}

#[test]
fn heights_from_another_texture_change_the_bump_as_the_height_map_option_does() {
    let colour = data("formats/basn2c08.png");
    let heights = data("formats/basn0g08.png");
    let (mut list, errors) = TextureList::from_args(&[colour.clone(), heights.clone()], None);
    assert!(errors.is_empty(), "{errors:?}");
    let own = render(Arc::clone(list.texture()));
    let h = list
        .entries()
        .iter()
        .position(|e| e.path() == Some(heights.as_path()))
        .unwrap();
    let applied = list.current();
    list.set_heights(Some(h)).unwrap();
    assert_eq!(list.current(), applied, "the colour stays");
    let swapped = render(Arc::clone(list.texture()));
    assert_ne!(swapped, own, "other heights, another bump");
    // `relief --height-map basn0g08.png basn2c08.png` draws the same.
    let (cli, errors) = TextureList::from_args(&[colour], Some(&heights));
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(render(Arc::clone(cli.texture())), swapped);
    // The colour is the same in all three; only the bump moved.
    let t = list.texture();
    assert!(
        t.base()
            .texels
            .iter()
            .zip(&cli.texture().base().texels)
            .all(|(a, b)| a == b)
    );
    // Back to the texture's own heights, and a bad index changes nothing.
    assert!(list.set_heights(Some(list.len())).is_err());
    assert_eq!(list.heights(), Some(h));
    list.set_heights(None).unwrap();
    assert_eq!(render(Arc::clone(list.texture())), own);
}

/// A loaded model's own textures are listed under the panel, a line per
/// map of each material; the built-in models list none.
#[test]
fn the_panel_lists_the_model_s_own_textures() {
    let cube = Stage::new(
        SceneKind::Cube,
        &ModelChoice::Cube,
        Arc::new(relief_texture::decode::procedural::brick()),
        false,
    )
    .unwrap();
    assert!(cube.model_textures(&ModelChoice::Cube).is_empty());
    let path = data("models/gltf/BoxTextured.glb");
    let model = ModelChoice::File(path);
    let stage = Stage::new(
        SceneKind::Cube,
        &model,
        Arc::new(relief_texture::decode::procedural::brick()),
        false,
    )
    .unwrap();
    let lines = stage.model_textures(&model);
    assert!(lines[0].starts_with("material 1:"), "{lines:?}");
    assert!(
        lines[0].contains("base") && lines[0].contains("BoxTextured.glb images[0]"),
        "{lines:?}"
    );
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    update(&mut s, Action::ToggleTextures);
    let mut shown = rows(1, 0);
    shown.model = lines.clone();
    update(&mut s, Action::TexturesListed(shown));
    let buf = draw(&s, 100, 40);
    let text: Vec<String> = (0..40).map(|y| row_text(&buf, y)).collect();
    let at = text
        .iter()
        .position(|r| r.contains("model textures"))
        .expect("the model's box");
    assert!(text[at + 1].contains("material 1:"), "{}", text[at + 1]);
}
