//! The screen through ratatui's `TestBackend`: status line, fields, help.

use std::time::Duration;

use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use relief::app::view::{areas, framebuffer_size, help_lines, layout, status_line};
use relief::app::{Action, State, update, view};
use relief_core::framebuffer::Framebuffer;
use relief_core::settings::Settings;
use relief_options::OptId;
use relief_term::{ColorDepth, Symbols};

const BG: [u8; 3] = [16, 24, 32];

fn state() -> State {
    let mut s = State::new(Settings::default(), ColorDepth::Truecolor);
    s.frame.frame_time = Duration::from_micros(3_250);
    s.frame.fps = Some(30.0);
    s.frame.bytes = 41_234;
    s
}

fn screen(s: &State, w: u16, h: u16) -> Buffer {
    let mut term = Terminal::new(TestBackend::new(w, h)).unwrap();
    let a = layout(s, Rect::new(0, 0, w, h));
    let (fw, fh) = framebuffer_size(a.viewport, Symbols::Half);
    let mut fb = Framebuffer::new(fw, fh);
    fb.fill([200, 100, 50]);
    term.draw(|f| view(f, s, &fb, BG)).unwrap();
    term.backend().buffer().clone()
}

fn row_text(buf: &Buffer, y: u16) -> String {
    (0..buf.area.width)
        .map(|x| buf[(x, y)].symbol().to_string())
        .collect()
}

fn all_text(buf: &Buffer) -> String {
    (0..buf.area.height)
        .map(|y| row_text(buf, y))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn status_line_shows_every_mode_and_the_frame_cost() {
    let s = state();
    let buf = screen(&s, 160, 20);
    let status = row_text(&buf, 19);
    assert_eq!(
        status.trim_end(),
        "Phong │ vertex │ tex on │ col on │ bump on │ Blinn │ bilinear │ dH filtered │ AA off │ fill │ cube │ lights on │ att off │ 24b │   3.2ms  30fps 41.2kB │ ? help"
    );
    let status = row_text(&screen(&s, 250, 20), 19);
    for want in [
        "Phong",
        "normals vertex",
        "texture on",
        "colours on",
        "bump on k=0.006",
        "Blinn",
        "bilinear",
        "dH filtered",
        "AA off",
        "fill",
        "model cube",
        "lights on",
        "attenuation off",
        "24-bit",
        "3.2 ms",
        "30 fps",
        "41.2 kB",
        "? help",
    ] {
        assert!(status.contains(want), "{want:?} missing in {status:?}");
    }
    assert!(!status.contains("Phong only"));
}

#[test]
fn status_line_shows_the_clip_and_whether_it_plays() {
    let mut s = state();
    let notes = relief_scene::LoadedNotes {
        clips: vec![("Walk".into(), 2.0), ("Run".into(), 1.0)],
        ..Default::default()
    };
    update(&mut s, Action::ModelNotes(notes));
    let status = row_text(&screen(&s, 250, 20), 19);
    assert!(status.contains("clip 1/2 Walk ▶"), "{status}");
    update(&mut s, Action::TogglePlay);
    update(&mut s, Action::NextClip);
    let status = row_text(&screen(&s, 250, 20), 19);
    assert!(status.contains("clip 2/2 Run ‖"), "{status}");
    // Narrow, the short form.
    let status = row_text(&screen(&s, 160, 20), 19);
    assert!(status.contains("clip ‖"), "{status}");
}

#[test]
fn status_line_follows_each_toggle() {
    let mut s = state();
    update(&mut s, Action::next(OptId::Shading));
    let st = status_line(&s, 200);
    assert!(st.starts_with("flat"), "{st}");
    assert!(st.contains("bump on (Phong only)"), "{st}");
    update(&mut s, Action::next(OptId::Shading));
    assert!(status_line(&s, 250).starts_with("Gouraud"));
    update(&mut s, Action::next(OptId::Normals));
    update(&mut s, Action::next(OptId::Texture));
    update(&mut s, Action::next(OptId::Colors));
    let st = status_line(&s, 250);
    for want in ["normals face", "texture off", "colours off", "(Phong only)"] {
        assert!(st.contains(want), "{want:?} in {st}");
    }
    update(&mut s, Action::next(OptId::Bump));
    let st = status_line(&s, 250);
    assert!(
        st.contains("bump off") && !st.contains("Phong only"),
        "{st}"
    );
    s.depth = ColorDepth::Palette256;
    assert!(status_line(&s, 200).contains("256 colours"));
    s.depth = ColorDepth::Palette16;
    assert!(status_line(&s, 200).contains("16 colours"));
}

#[test]
fn narrow_terminals_split_modes_and_cost_over_two_lines() {
    let mut s = state();
    update(&mut s, Action::next(OptId::Shading));
    let buf = screen(&s, 40, 12);
    let status = row_text(&buf, 11);
    assert_eq!(status.trim_end(), "flat │ cube │ 24b │ +11 more │ ? help");
    let panel = row_text(&buf, 10);
    assert_eq!(panel.trim_end(), "X25° Y35° Z0°   3.2ms  30fps 41.2kB");
    // 80 columns, 12 rows (one status row): the modes that fit and how
    // many do not, the cost on the line above with the full-size fields.
    let buf = screen(&state(), 80, 12);
    let status = row_text(&buf, 11);
    assert!(
        status.starts_with("Phong │ ") && status.trim_end().ends_with("│ 24b │ +7 more │ ? help"),
        "{status}"
    );
    assert!(!status.contains("3.2"), "{status}");
    assert_eq!(
        row_text(&buf, 10).trim_end(),
        " X     25° Y     35° Z      0°   3.2 ms │  30 fps │ 41.2 kB"
    );
    // Whatever the size, nothing panics, down to one cell.
    for (w, h) in [(10, 3), (3, 2), (1, 1), (1, 5), (200, 1), (0, 0)] {
        let _ = screen(&s, w, h);
    }
}

/// The status and panel lines of a screen.
fn text_lines(s: &State, w: u16) -> (String, String) {
    let buf = screen(s, w, 12);
    (row_text(&buf, 10), row_text(&buf, 11))
}

#[test]
fn the_layout_does_not_move_with_the_figures() {
    // Figures of every size, a lone frame (no rate) and a preview: at any
    // width the status line keeps its form and the cost stays where it
    // is, at the same columns.
    let figures = [
        (Duration::from_micros(3_250), Some(30.0), 41_234, false),
        (Duration::from_micros(250), Some(8.0), 999, false),
        (Duration::from_millis(12), None, 1_234, false),
        (Duration::from_millis(1234), Some(99.0), 123_456, false),
        (Duration::from_millis(40), Some(12.0), 5_678_901, true),
    ];
    for w in 20..=220u16 {
        let mut shapes = Vec::new();
        for (time, fps, bytes, preview) in figures {
            let mut s = state();
            s.frame.frame_time = time;
            s.frame.fps = fps;
            s.frame.bytes = bytes;
            s.frame.preview = preview;
            let (panel, status) = text_lines(&s, w);
            // The column of the rate in each line (None: not there).
            let col = |t: &str| t.find("fps").map(|i| t[..i].chars().count());
            let form = status.split(" │ ").next().unwrap().to_string();
            shapes.push((col(&panel), col(&status), form));
        }
        assert!(
            shapes.windows(2).all(|p| p[0] == p[1]),
            "{w} columns: {shapes:?}"
        );
    }
    // The help opening and closing changes nothing either.
    let mut s = state();
    let before = text_lines(&s, 160);
    update(&mut s, Action::ToggleHelp);
    update(&mut s, Action::CloseHelp);
    assert_eq!(text_lines(&s, 160), before);
}

#[test]
fn idle_shows_no_rate_and_a_preview_says_so() {
    let mut s = state();
    s.frame.fps = None;
    let status = status_line(&s, 250);
    assert!(status.contains("  3.2 ms │   — fps │ 41.2 kB"), "{status}");
    assert!(!status.contains("preview"));
    s.frame.fps = Some(9.0);
    s.frame.preview = true;
    s.frame.bytes = 5_210;
    let status = status_line(&s, 250);
    assert!(status.contains("preview │   9 fps │ 5.21 kB"), "{status}");
    // On a narrow screen the line above says it.
    let (panel, _) = text_lines(&s, 40);
    assert!(panel.contains("preview"), "{panel}");
}

#[test]
fn a_message_longer_than_its_line_is_shown_whole() {
    let mut s = state();
    update(&mut s, Action::PanelNext);
    for c in "abc".chars() {
        update(&mut s, Action::PanelInput(c));
    }
    update(&mut s, Action::PanelNext);
    for c in "1e999".chars() {
        update(&mut s, Action::PanelInput(c));
    }
    update(&mut s, Action::PanelApply);
    let msg = s.message.clone().unwrap();
    assert!(msg.len() > 60, "{msg}");
    for w in [40u16, 60, 80, 100] {
        let text = all_text(&screen(&s, w, 12));
        // Every word of the message is on the screen, in order.
        let flat: String = text.split_whitespace().collect::<Vec<_>>().join(" ");
        let words: String = msg.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(flat.contains(&words), "{w} columns:\n{text}");
    }
}

#[test]
fn the_picture_fills_the_viewport_above_the_two_lines() {
    let s = state();
    let buf = screen(&s, 20, 8);
    for y in 0..6 {
        for x in 0..20 {
            let cell = &buf[(x, y)];
            assert_eq!(cell.symbol(), " ");
            assert_eq!(cell.bg, ratatui::style::Color::Rgb(200, 100, 50));
        }
    }
    assert_eq!(
        framebuffer_size(areas(Rect::new(0, 0, 160, 48)).viewport, Symbols::Half),
        (160, 92)
    );
    assert_eq!(
        framebuffer_size(areas(Rect::new(0, 0, 40, 12)).viewport, Symbols::Half),
        (40, 20)
    );
    assert_eq!(
        framebuffer_size(areas(Rect::new(0, 0, 1, 1)).viewport, Symbols::Half),
        (1, 2)
    );
}

#[test]
fn orientation_fields_and_messages_are_on_the_line_above_the_status() {
    let mut s = state();
    let buf = screen(&s, 120, 10);
    let line = row_text(&buf, 8);
    assert!(
        line.contains("X     25°") && line.contains("Y     35°") && line.contains("Z      0°"),
        "{line}"
    );
    update(&mut s, Action::PanelNext);
    update(&mut s, Action::PanelInput('7'));
    let line = row_text(&screen(&s, 80, 10), 8);
    assert!(
        line.contains("X     7_°") && line.contains("Enter apply"),
        "{line}"
    );
    update(&mut s, Action::PanelInput('z'));
    update(&mut s, Action::PanelApply);
    let line = row_text(&screen(&s, 120, 10), 8);
    assert!(
        line.contains("X: '7z' is not a number (kept 25°)"),
        "{line}"
    );
    // Pasted control characters never reach the screen.
    update(&mut s, Action::PanelCancel);
    update(&mut s, Action::Paste("a\x1b]0;evil\x07b".into()));
    let text = all_text(&screen(&s, 120, 10));
    assert!(text.contains("pasted: a?]0;evil?b"), "{text}");
    assert!(!text.contains('\x1b'));
}

#[test]
fn help_overlay_lists_every_key_and_mouse_action() {
    let mut s = state();
    assert!(!all_text(&screen(&s, 100, 30)).contains("keys and mouse"));
    update(&mut s, Action::ToggleHelp);
    // One column when it fits the height, two when it fits the width.
    // 33 rows: the smallest height that holds the help in two columns
    // (since Z and the animation keys have lines of their own).
    for (w, h) in [(160, 48), (160, 33)] {
        let text = all_text(&screen(&s, w, h));
        assert!(text.contains("keys and mouse"));
        for (k, t) in help_lines() {
            assert!(text.contains(k), "{k} at {w}x{h}");
            assert!(text.contains(t), "{t} at {w}x{h}");
        }
    }
    for key in [
        "m",
        "n",
        "t",
        "c",
        "b",
        "+ -",
        "left drag",
        "right drag",
        "arrows",
        "Tab",
        "space",
        "r",
        "s",
        "?",
        "q Esc Ctrl-C",
        "e",
        "v N",
        "h",
        "a",
        "d F u U",
        "l 1 2 3 4",
        "L",
        "o",
        "p",
        "z",
        "pointer",
    ] {
        assert!(
            help_lines().iter().any(|(k, _)| *k == key),
            "{key} not in help"
        );
    }
    // In a tiny terminal the overlay is cut, not a crash.
    let _ = screen(&s, 12, 4);
}

/// The help entries a screen shows, read back: every text line of the
/// overlay, the key column and the wrapped text joined.
fn help_rows(buf: &Buffer) -> Vec<String> {
    (0..buf.area.height)
        .map(|y| row_text(buf, y))
        .filter(|r| r.starts_with('│'))
        .map(|r| r.trim_matches(|c| c == '│' || c == ' ').to_string())
        .collect()
}

#[test]
fn help_too_tall_for_the_screen_scrolls_to_every_entry() {
    let mut s = state();
    update(&mut s, Action::ToggleHelp);
    let (w, h) = (40, 12);
    let first = screen(&s, w, h);
    let title = row_text(&first, 0);
    assert!(title.contains("lines 1-10/"), "{title}");
    assert!(help_rows(&first)[0].starts_with("m  lighting"));
    // Page by page to the end: every entry's key and every word of its text shows up.
    let mut seen = String::new();
    let max = relief::app::view::help_max_scroll(w, h);
    for _ in 0..=max {
        seen.push_str(&help_rows(&screen(&s, w, h)).join("\n"));
        seen.push('\n');
        update(&mut s, Action::HelpScroll(1));
        s.help_scroll = s.help_scroll.min(relief::app::view::help_max_scroll(w, h));
    }
    for (k, t) in help_lines() {
        assert!(seen.contains(k), "{k}");
        for word in t.split(' ') {
            assert!(seen.contains(word), "{word} of {t}");
        }
    }
    let last = screen(&s, w, h);
    let rows = help_rows(&last);
    let (k, t) = help_lines().last().copied().unwrap();
    assert!(
        rows.last().unwrap().starts_with(&format!("{k}  {t}")),
        "{rows:?}"
    );
    // Scrolled as far as it goes: one line back shows at once.
    assert_eq!(s.help_scroll, max);
    update(&mut s, Action::HelpScroll(-1));
    assert_ne!(help_rows(&screen(&s, w, h)), rows);
    // A screen where it fits does not scroll at all.
    assert_eq!(relief::app::view::help_max_scroll(160, 48), 0);
    // Reopening starts at the top.
    update(&mut s, Action::ToggleHelp);
    update(&mut s, Action::ToggleHelp);
    assert_eq!(s.help_scroll, 0);
}

#[test]
fn help_on_a_narrow_screen_wraps_its_text_inside_the_border() {
    let mut s = state();
    update(&mut s, Action::ToggleHelp);
    update(&mut s, Action::HelpScroll(i32::MAX));
    for w in [20u16, 33, 47, 60] {
        s.help_scroll = 0;
        // Tall enough for every wrapped line: this is about width.
        let buf = screen(&s, w, 400);
        let text = all_text(&buf);
        // Nothing is cut: each text's words all appear, in order, within the box.
        for (_, t) in help_lines() {
            for word in t.split(' ') {
                assert!(text.contains(word), "{word} at width {w}");
            }
        }
        for y in 0..buf.area.height {
            let row = row_text(&buf, y);
            if row.starts_with('│') {
                assert!(row.trim_end().ends_with('│'), "{row:?} at width {w}");
            }
        }
    }
}

/// A model file is lit by the model view's rig (key, fill, back) or by its
/// own lights: keys 1–4 name those, and a key beyond them says so.
#[test]
fn light_keys_name_the_rig_of_a_model_file() {
    use relief_scene::{LoadedNotes, ModelChoice, SceneKind};
    let mut s = state();
    let file = ModelChoice::File("helmet.glb".into());
    update(&mut s, Action::SceneBuilt(Ok((SceneKind::Cube, file))));
    update(&mut s, Action::ToggleLight(0));
    let full = status_line(&s, 300);
    assert!(full.contains("lights on (key off)"), "{full}");
    update(&mut s, Action::ToggleLight(3));
    assert_eq!(
        s.light_on,
        [false, true, true, true],
        "no fourth light to switch"
    );
    assert_eq!(s.message.as_deref(), Some("this view has 3 lights (1-3)"));
    update(&mut s, Action::ToggleLight(2));
    assert!(status_line(&s, 300).contains("lights on (key, back off)"));
    // Its own two lights instead of the rig.
    let notes = LoadedNotes {
        lights: 2,
        ..LoadedNotes::default()
    };
    update(&mut s, Action::ModelNotes(notes));
    assert!(status_line(&s, 300).contains("lights on (light 1 off)"));
    // The reference cube names its four coloured lights again.
    update(
        &mut s,
        Action::SceneBuilt(Ok((SceneKind::Cube, ModelChoice::Cube))),
    );
    assert!(status_line(&s, 300).contains("lights on (white, green off)"));
}

/// A model file shaded physically in Phong does not use the bump
/// techniques, the Blinn highlight or the environment reflection: their
/// keys say so and change nothing; in flat shading the highlight acts.
#[test]
fn phong_only_keys_are_refused_on_a_physically_shaded_model() {
    use relief_core::settings::Shading;
    use relief_scene::{LoadedNotes, ModelChoice, SceneKind};
    let mut s = state();
    let file = ModelChoice::File("helmet.glb".into());
    update(&mut s, Action::SceneBuilt(Ok((SceneKind::Cube, file))));
    let notes = LoadedNotes {
        physical: true,
        ..LoadedNotes::default()
    };
    update(&mut s, Action::ModelNotes(notes));
    let before = s.settings;
    use relief_options::Press;
    for (id, press) in [
        (OptId::BumpStrength, Press::Up),
        (OptId::Technique, Press::Next),
        (OptId::Specular, Press::Next),
        (OptId::Environment, Press::Next),
    ] {
        update(&mut s, Action::Option { id, press });
        let message = s.message.clone().unwrap_or_default();
        assert!(message.contains("physical shading"), "{id:?}: {message}");
        assert_eq!(s.settings, before, "{id:?} changed nothing");
    }
    s.settings.shading = Shading::Flat;
    s.message = None;
    update(&mut s, Action::next(OptId::Specular));
    assert_ne!(
        s.settings.specular, before.specular,
        "flat: the highlight acts"
    );
    // Another model, not shaded physically: the technique acts again.
    s.settings.shading = Shading::Phong;
    update(
        &mut s,
        Action::SceneBuilt(Ok((SceneKind::Cube, ModelChoice::Sphere))),
    );
    update(&mut s, Action::next(OptId::Technique));
    assert_ne!(s.settings.technique, before.technique);
}

/// The height derivative `h` acts on a physically shaded model's normal
/// maps only where the filter reads their mip levels, with bump on; in the
/// reference scenes only where the bump shows. Elsewhere it says why and
/// changes nothing.
#[test]
fn the_height_derivative_is_refused_where_it_changes_nothing() {
    use relief_core::settings::Filter;
    use relief_scene::{LoadedNotes, ModelChoice, SceneKind};
    let h = || Action::next(OptId::HeightDerivative);
    let mut s = state();
    // The reference cube: with its bump it acts, without it it is refused.
    update(&mut s, h());
    assert_ne!(
        s.settings.height_derivative,
        Settings::default().height_derivative
    );
    s.settings.bump = false;
    let before = s.settings;
    update(&mut s, h());
    assert_eq!(s.settings, before);
    let message = s.message.clone().unwrap_or_default();
    assert!(message.contains("h (height derivative)"), "{message}");
    // A physically shaded model: refused at the default (bilinear) filter
    // and with its normal maps off, whatever the bump strength.
    s.settings = Settings::default();
    let file = ModelChoice::File("helmet.glb".into());
    update(
        &mut s,
        Action::SceneBuilt(Ok((SceneKind::Cube, file.clone()))),
    );
    use relief_scene::model_view::ModelFeatures;
    let notes = LoadedNotes {
        physical: true,
        features: ModelFeatures {
            normal_maps: false,
            ..ModelFeatures::default()
        },
        ..LoadedNotes::default()
    };
    // Without normal maps it has nothing to change.
    update(&mut s, Action::ModelNotes(notes.clone()));
    s.settings.filter = Filter::Trilinear;
    update(&mut s, h());
    let message = s.message.clone().unwrap_or_default();
    assert!(message.contains("no normal maps"), "{message}");
    update(&mut s, Action::SceneBuilt(Ok((SceneKind::Cube, file))));
    let notes = LoadedNotes {
        features: ModelFeatures::default(),
        ..notes
    };
    update(&mut s, Action::ModelNotes(notes));
    for (filter, bump, acts) in [
        (Filter::Bilinear, true, false),
        (Filter::Nearest, true, false),
        (Filter::Trilinear, false, false),
        (Filter::Trilinear, true, true),
        (Filter::Anisotropic, true, true),
    ] {
        s.settings.filter = filter;
        s.settings.bump = bump;
        s.settings.bump_strength = 0.0;
        s.message = None;
        let before = s.settings;
        update(&mut s, h());
        let message = s.message.clone().unwrap_or_default();
        if acts {
            assert_ne!(s.settings, before, "{filter:?}: acts");
            assert!(message.is_empty(), "{message}");
        } else {
            assert_eq!(s.settings, before, "{filter:?}, bump {bump}: unchanged");
            assert!(message.contains("normal maps"), "{message}");
        }
    }
}

/// On a model file whose parts take no material (an STL), `t` and `b`
/// say that no texture shows and how to lay one, until one is applied;
/// the reference scenes and a model with its own materials take them.
#[test]
fn texture_keys_are_refused_where_no_texture_shows() {
    use relief_scene::model_view::TextureReach;
    use relief_scene::{LoadedNotes, ModelChoice, SceneKind};
    let mut s = state();
    let file = ModelChoice::File("teapot.stl".into());
    update(
        &mut s,
        Action::SceneBuilt(Ok((SceneKind::Cube, file.clone()))),
    );
    let notes = |reach| LoadedNotes {
        texture_reach: Some(reach),
        ..LoadedNotes::default()
    };
    update(&mut s, Action::ModelNotes(notes(TextureReach::WhenChosen)));
    assert!(status_line(&s, 300).contains("texture none"));
    let before = s.settings;
    for id in [OptId::Texture, OptId::Bump] {
        update(&mut s, Action::next(id));
        let message = s.message.clone().unwrap_or_default();
        assert!(
            message.contains("x, T or a picture's path"),
            "{id:?}: {message}"
        );
        assert_eq!(s.settings, before, "{id:?} changed nothing");
    }
    // A texture applied: the keys act.
    update(&mut s, Action::TextureResult(Ok("brick (built-in)".into())));
    assert!(status_line(&s, 300).contains("texture on"));
    update(&mut s, Action::next(OptId::Texture));
    assert_ne!(s.settings.texture, before.texture);
    update(&mut s, Action::next(OptId::Texture));
    // Its own maps, or the reference cube: `t` acts.
    for (model, reach) in [(file, Some(TextureReach::Own)), (ModelChoice::Cube, None)] {
        update(&mut s, Action::SceneBuilt(Ok((SceneKind::Cube, model))));
        if let Some(reach) = reach {
            update(&mut s, Action::ModelNotes(notes(reach)));
        }
        update(&mut s, Action::next(OptId::Texture));
        assert_ne!(s.settings.texture, before.texture, "{reach:?}");
        update(&mut s, Action::next(OptId::Texture));
    }
}

#[test]
fn status_line_shows_technique_aa_display_scene_lights_and_plasma() {
    use relief_plasma::PlasmaNormal;
    use relief_scene::{ModelChoice, SceneKind};
    let mut s = state();
    for a in [
        // Before dot3, which reads no height derivative at this filter.
        Action::next(OptId::HeightDerivative),
        Action::next(OptId::Technique),
        Action::next(OptId::Technique),
        Action::next(OptId::LightVector),
        Action::next(OptId::Aa),
        Action::next(OptId::Display),
        Action::ToggleLight(1),
        Action::ToggleLight(3),
        Action::next(OptId::Attenuation),
        Action::SceneBuilt(Ok((SceneKind::Cube, ModelChoice::Sphere))),
    ] {
        update(&mut s, a);
    }
    let full = status_line(&s, 300);
    for want in [
        "dot3 (L per vertex)",
        "dH texel",
        "AA SSAA 2x2",
        "│ points │",
        "model sphere",
        "lights on (red, blue off)",
        "attenuation on",
    ] {
        assert!(full.contains(want), "{want:?} in {full}");
    }
    let short = row_text(&screen(&s, 160, 20), 19);
    assert!(
        short.contains("lights 1·3·") && short.contains("att on"),
        "{short}"
    );
    // Narrow and low: the modes at their default go before the changed
    // ones, and the line counts them; the lighting, the colour depth and
    // the hint stay.
    let at40 = row_text(&screen(&s, 40, 12), 11);
    assert!(
        at40.starts_with("Phong │") && at40.trim_end().ends_with("24b │ +11 more │ ? help"),
        "{at40}"
    );
    let at60 = status_line(&s, 60);
    assert!(
        !at60.contains("Blinn") && !at60.contains("bilinear"),
        "{at60}"
    );
    assert!(
        at60.contains("sphere") && at60.ends_with("more │ ? help"),
        "{at60}"
    );
    update(&mut s, Action::next(OptId::Lights));
    assert!(status_line(&s, 300).contains("lights off"));
    update(
        &mut s,
        Action::SceneBuilt(Ok((SceneKind::Shadow, ModelChoice::Sphere))),
    );
    assert!(status_line(&s, 300).contains("│ shadow │"));
    // The plasma has its own line: the normal mode and the light.
    update(
        &mut s,
        Action::SceneBuilt(Ok((SceneKind::Plasma, ModelChoice::Sphere))),
    );
    let st = status_line(&s, 160);
    assert!(
        st.starts_with("plasma │ Z² table │ light centre │ 24-bit │  3.2 ms"),
        "{st}"
    );
    update(&mut s, Action::TogglePlasmaNormal);
    update(&mut s, Action::Pointer { col: 10, row: 4 });
    assert!(status_line(&s, 160).contains("exact normal │ light 10,9"));
    let at20 = status_line(&s, 20);
    assert!(
        at20.starts_with("plasma │ 24b") && at20.ends_with("? help"),
        "{at20}"
    );
    assert_eq!(s.plasma_normal, PlasmaNormal::Exact);
}

#[test]
fn the_path_prompt_is_shown_with_control_characters_replaced() {
    let mut s = relief::app::State::new(
        relief_core::settings::Settings::default(),
        relief_term::ColorDepth::Truecolor,
    );
    s.prompt = Some("tex/\x1b[2Jbrick.png".into());
    // The cursor at the end, as after typing.
    s.prompt_cursor = s.prompt.as_ref().unwrap().len();
    for (w, h) in [(160, 48), (40, 12)] {
        let text = all_text(&screen(&s, w, h));
        assert!(text.contains("texture path:"), "{w}x{h}");
        assert!(!text.contains('\x1b'));
    }
    let text = all_text(&screen(&s, 160, 48));
    assert!(text.contains("tex/?[2Jbrick.png_"));
    // What Tab found shows on the prompt's line.
    s.message = Some("2 matches: brick.png  brick-normal.png".into());
    let text = all_text(&screen(&s, 160, 48));
    assert!(text.contains("brick.png_  2 matches: brick.png  brick-normal.png"));
    s.message = None;
    // The help lists the key.
    s.prompt = None;
    s.help = true;
    assert!(all_text(&screen(&s, 160, 48)).contains("type a texture path"));
}

#[test]
fn the_status_line_shortens_field_by_field_and_keeps_the_help_hint() {
    let s = state();
    let full = status_line(&s, 1000);
    assert!(
        full.contains("bump on k=0.006") && full.ends_with("│ ? help"),
        "{full}"
    );
    let n = full.chars().count();
    // One column less: only the bump strength goes.
    assert_eq!(status_line(&s, n - 1), full.replace(" k=0.006", ""));
    // Then the attenuation takes its short form.
    let second = full
        .replace(" k=0.006", "")
        .replace("attenuation off", "att off");
    assert_eq!(status_line(&s, n - 9), second);
    // Narrower and narrower: never wider than the screen, never longer
    // than the line before, always the lighting, the depth and the hint.
    for w in (12..=n).rev() {
        let line = status_line(&s, w);
        let len = line.chars().count();
        assert!(len <= w, "{w}: {line}");
        assert!(line.ends_with("? help"), "{w}: {line}");
        if w >= 20 {
            assert!(
                line.starts_with("Phong │") && line.contains("24"),
                "{w}: {line}"
            );
        }
    }
    // What does not fit is counted; narrower still, the cut says so.
    assert_eq!(
        status_line(&s, 40),
        "Phong │ cube │ 24b │ +11 more │ ? help"
    );
    assert_eq!(status_line(&s, 20), "Phong │ 24b … ? help");
    // Through the TestBackend at several widths: the last row.
    for w in [250u16, 160, 120, 80, 60, 40] {
        let row = row_text(&screen(&s, w, 20), 19);
        assert!(row.trim_end().ends_with("? help"), "{w}: {row}");
    }
}

#[test]
fn the_status_line_says_dithered_when_dithering_shows() {
    let mut s = state();
    s.dither = true;
    assert!(!status_line(&s, 300).contains("dither"));
    s.depth = ColorDepth::Palette256;
    assert!(status_line(&s, 300).contains("256 colours dithered"));
    assert!(
        status_line(&s, 40).contains("256c+dith"),
        "{}",
        status_line(&s, 40)
    );
    s.dither = false;
    assert!(!status_line(&s, 300).contains("dither"));
}

#[test]
fn the_plasma_shows_no_orientation_fields() {
    use relief_scene::{ModelChoice, SceneKind};
    let mut s = state();
    assert!(row_text(&screen(&s, 160, 20), 18).contains("X "));
    update(
        &mut s,
        Action::SceneBuilt(Ok((SceneKind::Plasma, ModelChoice::Cube))),
    );
    let row = row_text(&screen(&s, 160, 20), 18);
    assert!(!row.contains('°'), "{row}");
}

#[test]
fn a_message_clears_at_the_next_key_even_one_bound_to_nothing() {
    use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
    use relief::app::action_for_event;
    let keys = [
        KeyEvent::new(KeyCode::F(5), KeyModifiers::NONE),
        KeyEvent::new(KeyCode::Insert, KeyModifiers::NONE),
        KeyEvent::new(KeyCode::Char('m'), KeyModifiers::ALT),
        KeyEvent::new(KeyCode::Char('j'), KeyModifiers::CONTROL),
    ];
    let said = "texture: cannot read x.png";
    for key in keys {
        // Over the picture, and with the help open (it passes the key on).
        for help in [false, true] {
            let mut s = state();
            if help {
                update(&mut s, Action::ToggleHelp);
            }
            update(&mut s, Action::TextureResult(Err(said.into())));
            assert!(all_text(&screen(&s, 200, 90)).contains(said));
            let action = action_for_event(&s, &Event::Key(key)).expect("every key acts");
            assert_eq!(action, Action::Unbound, "{key:?}");
            update(&mut s, action);
            assert_eq!(s.message, None, "{key:?}");
            assert!(!all_text(&screen(&s, 200, 90)).contains(said), "{key:?}");
            assert_eq!(s.help, help, "nothing else changed");
        }
    }
}

/// The modes a status text shows (not the frame cost, the count or the
/// hint), and the count of those it leaves out (`+N more`).
fn modes_in(text: &str) -> (usize, usize) {
    let (mut shown, mut more) = (0, 0);
    for part in text.lines().flat_map(|row| row.trim_end().split(" │ ")) {
        let cost = part.contains("fps") || part.contains("3.2") || part.contains("41.2");
        if let Some(n) = part.strip_prefix('+').and_then(|p| p.strip_suffix(" more")) {
            more = n.parse().unwrap();
        } else if !cost && part != "? help" {
            shown += 1;
        }
    }
    (shown, more)
}

/// States with many modes away from their default, and the plasma.
fn busy_states() -> Vec<State> {
    use relief_scene::{ModelChoice, SceneKind};
    let mut changed = state();
    for a in [
        Action::next(OptId::Technique),
        Action::next(OptId::Aa),
        Action::next(OptId::Display),
        Action::ToggleLight(1),
        Action::next(OptId::Attenuation),
        Action::ToggleAutoRotate,
        Action::ZoomIn,
    ] {
        update(&mut changed, a);
    }
    let mut plasma = state();
    update(
        &mut plasma,
        Action::SceneBuilt(Ok((SceneKind::Plasma, ModelChoice::Sphere))),
    );
    vec![state(), changed, plasma]
}

#[test]
fn the_status_line_wraps_before_it_leaves_a_mode_out_and_counts_what_it_leaves_out() {
    for s in busy_states() {
        let (all, _) = modes_in(&status_line(&s, 10_000));
        for h in [3u16, 8, 12, 16, 24, 48] {
            let allowed = relief::app::view::status::max_rows(h);
            for w in 8..=250u16 {
                let buf = screen(&s, w, h);
                let area = layout(&s, Rect::new(0, 0, w, h)).status.unwrap();
                let text: String = (area.top()..area.bottom())
                    .map(|y| row_text(&buf, y).trim_end().to_string() + "\n")
                    .collect();
                let at = format!("{w}x{h}:\n{text}");
                assert!(area.height <= allowed, "{at}");
                assert!(text.trim_end().ends_with("? help") || w < 6, "{at}");
                if text.contains('…') {
                    // Too narrow for the count itself: the cut says so.
                    continue;
                }
                let (shown, more) = modes_in(&text);
                assert_eq!(shown + more, all, "every mode shown or counted: {at}");
                if more > 0 {
                    assert_eq!(area.height, allowed, "rows first: {at}");
                }
            }
        }
    }
}

#[test]
fn at_80_by_24_the_status_line_takes_two_rows_and_shows_every_mode() {
    let s = state();
    let buf = screen(&s, 80, 24);
    let a = layout(&s, Rect::new(0, 0, 80, 24));
    assert_eq!(a.status, Some(Rect::new(0, 22, 80, 2)));
    assert_eq!(a.viewport.height, 21);
    let (top, bottom) = (row_text(&buf, 22), row_text(&buf, 23));
    assert!(top.starts_with("Phong │ vertex │ tex on │"), "{top}");
    assert!(bottom.trim_end().ends_with("│ 24b │ ? help"), "{bottom}");
    assert!(
        !top.contains('+') && !bottom.contains('+'),
        "{top}\n{bottom}"
    );
    let (shown, more) = modes_in(&format!("{top}\n{bottom}"));
    assert_eq!((shown, more), (modes_in(&status_line(&s, 10_000)).0, 0));
    // The cost on the line above, as on any screen where it does not fit.
    assert!(row_text(&buf, 21).contains("3.2 ms │  30 fps │ 41.2 kB"));
    // The figures never change the number of rows.
    let mut busy = state();
    busy.frame.frame_time = Duration::from_millis(1234);
    busy.frame.bytes = 5_678_901;
    busy.frame.fps = None;
    for w in 20..=220u16 {
        for h in [16u16, 24, 48] {
            assert_eq!(
                relief::app::view::status_rows(&s, w, h),
                relief::app::view::status_rows(&busy, w, h),
                "{w}x{h}"
            );
        }
    }
}

/// An STL stands Z up (its notes say so): the view turns it upright and
/// goes back to Y up for the next scene; an axis the user set (`Z`, or
/// `--up`) stays for every model.
#[test]
fn an_stl_stands_z_up_unless_the_user_set_the_axis() {
    use relief_core::settings::UpAxis;
    use relief_scene::{LoadedNotes, ModelChoice, SceneKind};
    let mut s = state();
    let stl = ModelChoice::File("teapot.stl".into());
    let z_up = LoadedNotes {
        z_up: true,
        ..LoadedNotes::default()
    };
    let open = |s: &mut relief::app::State, model: &ModelChoice, notes: Option<&LoadedNotes>| {
        update(s, Action::SceneBuilt(Ok((SceneKind::Cube, model.clone()))));
        if let Some(notes) = notes {
            update(s, Action::ModelNotes(notes.clone()));
        }
    };
    open(&mut s, &stl, Some(&z_up));
    assert_eq!(s.settings.up, UpAxis::Z);
    assert!(status_line(&s, 300).contains("Z up"));
    open(&mut s, &ModelChoice::Cube, None);
    assert_eq!(
        s.settings.up,
        UpAxis::Y,
        "the cube stands as it always does"
    );
    let obj = ModelChoice::File("fox.obj".into());
    open(&mut s, &obj, Some(&LoadedNotes::default()));
    assert_eq!(s.settings.up, UpAxis::Y);
    // The user stands the STL Y up: kept for the next STL and the cube.
    open(&mut s, &stl, Some(&z_up));
    update(&mut s, Action::next(OptId::Up));
    assert_eq!(s.settings.up, UpAxis::Y);
    open(&mut s, &stl, Some(&z_up));
    assert_eq!(s.settings.up, UpAxis::Y);
    update(&mut s, Action::next(OptId::Up));
    open(&mut s, &ModelChoice::Cube, None);
    assert_eq!(s.settings.up, UpAxis::Z, "the user's axis stays");
}
