//! The mode keys (technique, AA, display, lights, model, scene, plasma)
//! through `action_for_event` and the pure `update`; the pointer → light mapping.

use std::path::PathBuf;

use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers, MouseEvent, MouseEventKind};
use relief::app::state::plasma_light;
use relief::app::{Action, Command, DragButton, State, action_for_event, update};
use relief_core::settings::{
    AntiAlias, Display, HeightDerivative, LightVector, Settings, Technique,
};
use relief_plasma::PlasmaNormal;
use relief_scene::{ModelChoice, SceneKind};
use relief_term::ColorDepth;

fn state() -> State {
    State::new(Settings::default(), ColorDepth::Truecolor)
}

/// Feeds a key (shifted when upper case) through the mapping and `update`.
fn ch(s: &mut State, c: char) -> Option<Command> {
    let m = if c.is_uppercase() {
        KeyModifiers::SHIFT
    } else {
        KeyModifiers::NONE
    };
    let action = action_for_event(s, &Event::Key(KeyEvent::new(KeyCode::Char(c), m)))?;
    update(s, action)
}

fn mouse(s: &State, kind: MouseEventKind, column: u16, row: u16) -> Option<Action> {
    action_for_event(
        s,
        &Event::Mouse(MouseEvent {
            kind,
            column,
            row,
            modifiers: KeyModifiers::NONE,
        }),
    )
}

/// What `o` or `p` asks for, as the loop would answer it when the build works.
fn build(s: &mut State, c: char) -> (SceneKind, ModelChoice) {
    let Some(Command::BuildScene(kind, model)) = ch(s, c) else {
        panic!("{c} asks for a scene build")
    };
    update(s, Action::SceneBuilt(Ok((kind, model.clone()))));
    (kind, model)
}

#[test]
fn e_cycles_every_technique_and_v_h_toggle() {
    let mut s = state();
    let mut seen = vec![s.settings.technique];
    for _ in 0..5 {
        assert_eq!(ch(&mut s, 'e'), None);
        seen.push(s.settings.technique);
    }
    use Technique::*;
    assert_eq!(seen, [Blinn, Emboss, Dot3, Parallax, Pom, Blinn]);
    // v acts with dot3 (the only technique that reads it).
    ch(&mut s, 'v');
    assert_eq!(s.settings.light_vector, LightVector::Pixel);
    assert!(s.message.take().unwrap().contains("dot3"));
    ch(&mut s, 'e');
    ch(&mut s, 'e');
    ch(&mut s, 'v');
    assert_eq!(s.settings.light_vector, LightVector::Vertex);
    ch(&mut s, 'v');
    assert_eq!(s.settings.light_vector, LightVector::Pixel);
    for _ in 0..3 {
        ch(&mut s, 'e');
    }
    ch(&mut s, 'h');
    assert_eq!(s.settings.height_derivative, HeightDerivative::Texel);
    ch(&mut s, 'h');
    assert_eq!(s.settings.height_derivative, HeightDerivative::Filtered);
    assert_eq!(s, state(), "a full cycle is back where it started");
}

#[test]
fn a_cycles_anti_aliasing_and_d_the_display() {
    let mut s = state();
    let mut aa = vec![s.settings.aa];
    let mut display = vec![s.settings.display];
    for _ in 0..4 {
        ch(&mut s, 'a');
        aa.push(s.settings.aa);
    }
    for _ in 0..3 {
        ch(&mut s, 'd');
        display.push(s.settings.display);
    }
    use AntiAlias::*;
    assert_eq!(aa, [Off, Ssaa2, Ssaa4, Msaa4, Off]);
    assert_eq!(
        display,
        [
            Display::Fill,
            Display::Points,
            Display::Lines,
            Display::Fill
        ]
    );
}

#[test]
fn l_switches_all_lights_capital_l_attenuation_and_digits_one_light() {
    let mut s = state();
    ch(&mut s, 'l');
    assert!(!s.settings.lights);
    ch(&mut s, 'l');
    assert!(s.settings.lights);
    ch(&mut s, 'L');
    assert!(s.settings.attenuation);
    ch(&mut s, 'L');
    assert!(!s.settings.attenuation);
    for (c, i) in [('1', 0), ('2', 1), ('3', 2), ('4', 3)] {
        ch(&mut s, c);
        let mut want = [true; 4];
        want[i] = false;
        assert_eq!(s.light_on, want, "{c}");
        ch(&mut s, c);
        assert_eq!(s.light_on, [true; 4], "{c}");
    }
    // No fifth light, and out-of-range toggles change nothing.
    assert_eq!(ch(&mut s, '5'), None);
    update(&mut s, Action::ToggleLight(9));
    assert_eq!(s, state());
}

#[test]
fn z_toggles_the_plasma_normal() {
    let mut s = state();
    update(
        &mut s,
        Action::SceneBuilt(Ok((SceneKind::Plasma, ModelChoice::Cube))),
    );
    ch(&mut s, 'z');
    assert_eq!(s.plasma_normal, PlasmaNormal::Exact);
    ch(&mut s, 'z');
    assert_eq!(s.plasma_normal, PlasmaNormal::Table);
}

#[test]
fn o_walks_the_models_and_the_obj_file() {
    let mut s = state();
    let models: Vec<ModelChoice> = (0..5).map(|_| build(&mut s, 'o').1).collect();
    use ModelChoice::*;
    assert_eq!(models, [Sphere, Triangle, Plane, Cube, Sphere]);
    // With --model FILE.obj, the file comes after the sphere.
    let obj = PathBuf::from("teapot.obj");
    s.obj = Some(obj.clone());
    assert_eq!(build(&mut s, 'o'), (SceneKind::Cube, File(obj)));
    assert_eq!(build(&mut s, 'o').1, Triangle);
    assert_eq!(s.model, Triangle);
}

#[test]
fn the_model_changes_only_once_built_and_a_failure_keeps_it() {
    let mut s = state();
    s.obj = Some("bad.obj".into());
    s.model = ModelChoice::Sphere;
    let cmd = ch(&mut s, 'o');
    assert_eq!(
        cmd,
        Some(Command::BuildScene(
            SceneKind::Cube,
            ModelChoice::File("bad.obj".into())
        ))
    );
    assert_eq!(s.model, ModelChoice::Sphere, "not before it is built");
    update(
        &mut s,
        Action::SceneBuilt(Err("model bad.obj\x1b[2J, line 2: bad".into())),
    );
    assert_eq!(s.model, ModelChoice::Sphere);
    assert_eq!(s.scene, SceneKind::Cube);
    let msg = s.message.clone().unwrap();
    assert!(msg.contains("bad.obj") && !msg.contains('\x1b'), "{msg}");
}

#[test]
fn p_walks_the_scenes_and_o_comes_back_to_the_model() {
    let mut s = state();
    s.model = ModelChoice::Plane;
    let scenes: Vec<SceneKind> = (0..3).map(|_| build(&mut s, 'p').0).collect();
    assert_eq!(
        scenes,
        [SceneKind::Shadow, SceneKind::Plasma, SceneKind::Cube]
    );
    assert_eq!(s.model, ModelChoice::Plane, "the model is kept");
    build(&mut s, 'p');
    // From the shadow scene, `o` shows the model first, then the next ones.
    assert_eq!(build(&mut s, 'o'), (SceneKind::Cube, ModelChoice::Plane));
    assert_eq!(build(&mut s, 'o'), (SceneKind::Cube, ModelChoice::Cube));
}

#[test]
fn in_the_plasma_the_pointer_moves_the_light_and_drags_do_not_turn() {
    let mut s = state();
    // Outside the plasma, motion without a button is ignored.
    assert_eq!(mouse(&s, MouseEventKind::Moved, 3, 4), None);
    update(&mut s, Action::Pointer { col: 3, row: 4 });
    assert_eq!(s.pointer, None);
    assert_eq!(
        mouse(
            &s,
            MouseEventKind::Down(crossterm::event::MouseButton::Left),
            3,
            4
        ),
        Some(Action::MouseDown {
            button: DragButton::Left,
            col: 3,
            row: 4
        })
    );
    build(&mut s, 'p');
    build(&mut s, 'p');
    assert_eq!(s.scene, SceneKind::Plasma);
    let rotation = s.settings.rotation;
    for kind in [
        MouseEventKind::Moved,
        MouseEventKind::Down(crossterm::event::MouseButton::Left),
        MouseEventKind::Drag(crossterm::event::MouseButton::Left),
    ] {
        let a = mouse(&s, kind, 30, 7).unwrap();
        assert_eq!(a, Action::Pointer { col: 30, row: 7 });
        update(&mut s, a);
    }
    assert_eq!(s.pointer, Some((30, 7)));
    assert_eq!(s.settings.rotation, rotation, "nothing turned");
    assert_eq!(s.drag, None);
    assert_eq!(s.look().pointer, Some((30, 7)));
    // Leaving the plasma forgets the pointer.
    build(&mut s, 'p');
    assert_eq!((s.pointer, s.look().pointer), (None, None));
}

#[test]
fn the_pointer_cell_lights_the_lower_pixel_of_that_cell() {
    assert_eq!(plasma_light(Some((0, 0)), 160, 92), (0.0, 1.0));
    assert_eq!(plasma_light(Some((79, 22)), 160, 92), (79.0, 45.0));
    // Below the viewport (over the text lines) the light is off the picture.
    assert_eq!(plasma_light(Some((5, 47)), 160, 92), (5.0, 95.0));
    assert_eq!(plasma_light(Some((u16::MAX, u16::MAX)), 1, 1).1, 131071.0);
    // No pointer yet: the centre.
    assert_eq!(plasma_light(None, 160, 92), (80.0, 46.0));
}
