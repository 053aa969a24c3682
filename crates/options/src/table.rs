//! The table: one entry per option of the view. An option is declared
//! here once; its flag, keys, help lines, status field, key messages and
//! bench rows are all made from its entry (see docs/architecture.md,
//! "Adding an option").
//!
//! Not in the table, each for a reason:
//! - `rotation` (`--rotate`, arrows, drags, the orientation fields): three
//!   angles edited in many ways, not one value moved by a key;
//! - `normal_map_file` (key `N`): on by itself when `--normal-map` loads,
//!   and its key also switches the technique to dot3 and says which file;
//! - the plasma normal (`z`), the camera distance (`i` `I`, wheel), the
//!   glyphs (`u`) and the lights `1`–`4`: they live in the app's state,
//!   not in [`Settings`], which is what the renderer reads.

use super::OptId;
use super::entry::{
    Bench, Ctx, Field, Flag, Form, KeyHelp, Kind, Opt, OptKey, Press, Shows, Status, Step, Value,
};
use super::text::{format_shininess, format_strength, on_off, parse_finite};
use super::values;
use relief_core::settings::{
    AntiAlias, BUMP_FACTOR, BUMP_MAX, BUMP_MIN, DEFAULT_FOV, Display, FOV_RANGE, Filter,
    HeightDerivative, IblDiffuse, IblSpecular, LightVector, Normals, SHININESS_RANGE, Settings,
    Shading, Technique, ToneMap, UpAxis,
};
use relief_pipeline::plan;

/// How an entry reads and writes its [`Settings`] field: `field!(name: bool)`,
/// `field!(name: f32)` or `field!(name: EnumType)`.
macro_rules! field {
    ($f:ident: bool) => {
        Field {
            get: |s| Value::Bool(s.$f),
            set: |s, v| s.$f = v.bool(),
        }
    };
    ($f:ident: f32) => {
        Field {
            get: |s| Value::Number(s.$f),
            set: |s, v| s.$f = v.number(),
        }
    };
    ($f:ident: $t:ty) => {
        Field {
            get: |s| Value::Index(super::index_of(s.$f)),
            set: |s, v| s.$f = super::variant::<$t>(v.index()),
        }
    };
}

/// A key with its own help line (the keys it shows are the entries';
/// see [`help_keys`]).
const fn key(keys: &'static [char], press: Press, text: &'static str) -> OptKey {
    OptKey {
        keys,
        press,
        help: KeyHelp::Line { text, others: "" },
    }
}

/// A key with its own help line shared with keys of the app's own
/// (`app/keys.rs`), shown after the entries' keys.
const fn key_and(
    keys: &'static [char],
    press: Press,
    text: &'static str,
    others: &'static str,
) -> OptKey {
    OptKey {
        keys,
        press,
        help: KeyHelp::Line { text, others },
    }
}

/// A key the help line above describes.
const fn also(keys: &'static [char], press: Press) -> OptKey {
    OptKey {
        keys,
        press,
        help: KeyHelp::Above,
    }
}

/// A flag whose value name is the option's in capitals, default shown.
const fn flag(help: &'static str) -> Flag {
    Flag {
        help,
        value_name: None,
        form: Form::Value,
    }
}

/// A field with one form.
const fn same(at: u8, long: fn(&Ctx) -> String, drop: Option<u8>) -> Status {
    Status {
        at,
        long,
        short: None,
        shorten: u8::MAX,
        drop,
        shown: None,
        at_default: None,
    }
}

/// A field with a long and a short form.
const fn two(
    at: u8,
    long: fn(&Ctx) -> String,
    short: fn(&Ctx) -> String,
    shorten: u8,
    drop: u8,
) -> Status {
    Status {
        at,
        long,
        short: Some(short),
        shorten,
        drop: Some(drop),
        shown: None,
        at_default: None,
    }
}

/// " (Phong only)" when the bump is on but the lighting hides it.
fn phong_only(s: &Settings) -> &'static str {
    if s.bump && !plan::bump_can_show(s) {
        " (Phong only)"
    } else {
        ""
    }
}

/// The bump technique, with dot3's light vector and, when it reads one,
/// the normal map file.
fn technique_text(c: &Ctx) -> String {
    let s = c.settings;
    if plan::normal_map_file_shows(s, c.normal_map_loaded) {
        format!("dot3 ({}, map file)", s.light_vector.label())
    } else if s.technique == Technique::Dot3 {
        format!("dot3 ({})", s.light_vector.label())
    } else {
        s.technique.label().into()
    }
}

/// Every option, in the order of the help (and of `--help`).
pub static OPTIONS: &[Opt] = &TABLE;

/// The table, one entry per [`OptId`] at the id's place.
const TABLE: [Opt; OptId::ALL.len()] = [
    Opt {
        id: OptId::Shading,
        name: "shading",
        title: "lighting",
        kind: Kind::Choice {
            values: values::<Shading>,
        },
        field: field!(shading: Shading),
        flag: flag("Lighting: per facet, per vertex (Gouraud) or per pixel (Phong)"),
        keys: &[key(&['m'], Press::Next, "lighting: flat → Gouraud → Phong")],
        shows: None,
        status: Some(same(0, |c| c.settings.shading.label().into(), None)),
        bench: Bench::Axis("shading"),
    },
    Opt {
        id: OptId::Normals,
        name: "normals",
        title: "normals",
        kind: Kind::Choice {
            values: values::<Normals>,
        },
        field: field!(normals: Normals),
        flag: flag("Normals used by Gouraud and Phong"),
        keys: &[key(&['n'], Press::Next, "normals: vertex / face")],
        shows: None,
        status: Some(two(
            1,
            |c| format!("normals {}", c.settings.normals.label()),
            |c| c.settings.normals.label().into(),
            5,
            8,
        )),
        bench: Bench::Axis("normals"),
    },
    Opt {
        id: OptId::Texture,
        name: "texture",
        title: "texture",
        kind: Kind::Toggle,
        field: field!(texture: bool),
        flag: flag("Colour texture"),
        keys: &[key(&['t'], Press::Next, "texture on / off")],
        shows: None,
        status: Some(two(
            2,
            |c| format!("texture {}", texture_shown(c)),
            |c| format!("tex {}", texture_shown(c)),
            3,
            7,
        )),
        bench: Bench::Axis("texture"),
    },
    Opt {
        id: OptId::Colors,
        name: "colors",
        title: "colours",
        kind: Kind::Toggle,
        field: field!(colors: bool),
        flag: flag("Per-vertex colours (off: white, or a model material's own colour)"),
        keys: &[key(&['c'], Press::Next, "colours on / off")],
        shows: None,
        status: Some(two(
            3,
            |c| format!("colours {}", on_off(c.settings.colors)),
            |c| format!("col {}", on_off(c.settings.colors)),
            2,
            6,
        )),
        bench: Bench::None,
    },
    Opt {
        id: OptId::Bump,
        name: "bump",
        title: "bump",
        kind: Kind::Toggle,
        field: field!(bump: bool),
        flag: flag("Bump mapping (shows in Phong only)"),
        keys: &[key(
            &['b'],
            Press::Next,
            "bump on / off (shows in Phong only)",
        )],
        shows: None,
        status: Some(Status {
            // "Phong only" says something: kept as a changed field.
            at_default: Some(|c| {
                c.settings.bump == Settings::default().bump && phong_only(c.settings).is_empty()
            }),
            ..two(
                4,
                |c| {
                    let s = c.settings;
                    let k = format_strength(s.bump_strength);
                    format!("bump {}{} k={k}", on_off(s.bump), phong_only(s))
                },
                |c| format!("bump {}{}", on_off(c.settings.bump), phong_only(c.settings)),
                0,
                12,
            )
        }),
        bench: Bench::Axis("bump"),
    },
    Opt {
        id: OptId::BumpStrength,
        name: "bump_strength",
        title: "bump strength",
        kind: Kind::Number {
            parse: super::text::parse_strength,
            step: Step {
                factor: BUMP_FACTOR,
                min: 0.0,
                max: BUMP_MAX,
                zero_below: Some(BUMP_MIN),
                wrap: false,
            },
            show: format_strength,
            negative: true,
        },
        field: field!(bump_strength: f32),
        flag: flag("Bump strength k (Blinn); 0 means no bump"),
        keys: &[
            key(&['+', '='], Press::Up, "bump strength"),
            also(&['-', '_'], Press::Down),
        ],
        shows: Some(Shows {
            when: |c| plan::bump_can_show(c.settings),
            why: "shows in Phong with bump on (m, b); unchanged",
        }),
        // Shown in the bump's field.
        status: None,
        bench: Bench::None,
    },
    Opt {
        id: OptId::Filter,
        name: "filter",
        title: "filter",
        kind: Kind::Choice {
            values: values::<Filter>,
        },
        field: field!(filter: Filter),
        flag: flag("Texture filter"),
        keys: &[key(
            &['f'],
            Press::Next,
            "filter: nearest, bilinear, nearest-mip, trilinear, aniso",
        )],
        shows: None,
        status: Some(same(6, |c| c.settings.filter.label().into(), Some(4))),
        bench: Bench::Axis("filter"),
    },
    Opt {
        id: OptId::Technique,
        name: "technique",
        title: "bump technique",
        kind: Kind::Choice {
            values: values::<Technique>,
        },
        field: field!(technique: Technique),
        flag: flag("Bump technique (shows in Phong with bump on)"),
        keys: &[key(
            &['e'],
            Press::Next,
            "bump technique: Blinn → emboss → dot3 → parallax → POM",
        )],
        shows: Some(Shows {
            when: |c| plan::technique_shows(c.settings),
            why: "shows in Phong with bump on and strength above 0 (m, b, +); unchanged",
        }),
        status: Some(Status {
            at_default: Some(|c| {
                c.settings.technique == Settings::default().technique
                    && !plan::normal_map_file_shows(c.settings, c.normal_map_loaded)
            }),
            ..same(5, technique_text, Some(5))
        }),
        bench: Bench::Axis("technique"),
    },
    Opt {
        id: OptId::LightVector,
        name: "light_vector",
        title: "dot3 light vector",
        kind: Kind::Choice {
            values: values::<LightVector>,
        },
        field: field!(light_vector: LightVector),
        flag: flag(
            "Dot3's light vector: interpolated from the vertices (the tutorial's artefact) or per pixel",
        ),
        keys: &[key_and(
            &['v'],
            Press::Next,
            "dot3: L per pixel / vertex; N: normal map file / derived",
            // The normal map file's key (app/keys.rs).
            "N",
        )],
        shows: Some(Shows {
            when: |c| plan::light_vector_shows(c.settings),
            why: "shows with the dot3 technique, in Phong with bump on (e, m, b); unchanged",
        }),
        // Shown in the technique's field.
        status: None,
        // Measured with dot3 (bench/config.rs): it matters to dot3 only.
        bench: Bench::None,
    },
    Opt {
        id: OptId::HeightDerivative,
        name: "height_derivative",
        title: "height derivative",
        kind: Kind::Choice {
            values: values::<HeightDerivative>,
        },
        field: field!(height_derivative: HeightDerivative),
        flag: flag(
            "Height derivative of the bump stage: the documented per-texel one or a filtered one",
        ),
        keys: &[key(
            &['h'],
            Press::Next,
            "height derivative: filtered / per texel",
        )],
        // The height map's gradient is read by the bump alone (a model
        // shaded physically has its own rule: `app/feedback.rs`).
        shows: Some(Shows {
            when: |c| plan::height_derivative_shows(c.settings),
            why: "shows in Phong with bump on and strength above 0 (m, b, +), with dot3 and emboss through a filter with mip levels (f); unchanged",
        }),
        status: Some(same(
            7,
            |c| format!("dH {}", c.settings.height_derivative.label()),
            Some(2),
        )),
        bench: Bench::Axis("derivative"),
    },
    Opt {
        id: OptId::Aa,
        name: "aa",
        title: "anti-aliasing",
        kind: Kind::Choice {
            values: values::<AntiAlias>,
        },
        field: field!(aa: AntiAlias),
        flag: flag(
            "Anti-aliasing: supersampling 2x2 or 4x4, or 4 coverage samples shaded once (msaa4)",
        ),
        keys: &[key(
            &['a'],
            Press::Next,
            "anti-aliasing: off → SSAA 2x2 → SSAA 4x4 → MSAA 4",
        )],
        shows: None,
        status: Some(same(
            8,
            |c| format!("AA {}", c.settings.aa.label()),
            Some(3),
        )),
        bench: Bench::Axis("aa"),
    },
    Opt {
        id: OptId::Display,
        name: "display",
        title: "display",
        kind: Kind::Choice {
            values: values::<Display>,
        },
        field: field!(display: Display),
        flag: flag("What is drawn: vertices, edges or filled triangles"),
        keys: &[key_and(
            &['d'],
            Press::Next,
            "display: points → lines → fill; tangent frames; glyphs; format",
            // The glyphs and the format (app/keys.rs).
            "u U",
        )],
        shows: None,
        status: Some(same(9, |c| c.settings.display.label().into(), Some(9))),
        bench: Bench::None,
    },
    Opt {
        id: OptId::TangentFrames,
        name: "tangent_frames",
        title: "tangent frames",
        kind: Kind::Toggle,
        field: field!(tangent_frames: bool),
        flag: Flag {
            form: Form::Switch,
            ..flag(
                "Draw the tangent frame at each vertex of the textured triangles: T red, B green, N blue (docs/tangent-frames.md)",
            )
        },
        keys: &[also(&['F'], Press::Next)],
        shows: None,
        // Shown only when drawn.
        status: Some(Status {
            shown: Some(|c| c.settings.tangent_frames),
            ..two(17, |_| "tangent frames".into(), |_| "TBN".into(), 11, 0)
        }),
        bench: Bench::Row("tangent-frames"),
    },
    Opt {
        id: OptId::Lights,
        name: "lights",
        title: "lights",
        kind: Kind::Toggle,
        field: field!(lights: bool),
        flag: flag("All lights on or off (the ambient term stays)"),
        keys: &[key_and(
            &['l'],
            Press::Next,
            "all lights / one light on / off (the status line names it)",
            // The lights 1–4 of the app's state (app/keys.rs).
            "1 2 3 4",
        )],
        shows: None,
        // Worded with the lights 1–4 of the app's state (app/view/status.rs).
        status: None,
        bench: Bench::Axis("lights"),
    },
    Opt {
        id: OptId::Attenuation,
        name: "attenuation",
        title: "attenuation",
        kind: Kind::Toggle,
        field: field!(attenuation: bool),
        flag: flag(
            "Distance attenuation of the lights: 1/(1 + 0.01·d²), d the distance to the light",
        ),
        keys: &[key(&['L'], Press::Next, "distance attenuation on / off")],
        shows: None,
        status: Some(two(
            12,
            |c| format!("attenuation {}", on_off(c.settings.attenuation)),
            |c| format!("att {}", on_off(c.settings.attenuation)),
            1,
            1,
        )),
        bench: Bench::None,
    },
    Opt {
        id: OptId::Specular,
        name: "specular",
        title: "specular",
        kind: Kind::Toggle,
        field: field!(specular: bool),
        flag: flag(
            "Blinn-Phong specular highlights (docs/specular.md): per pixel in Phong, per vertex in Gouraud, per facet in flat",
        ),
        keys: &[key(
            &['g'],
            Press::Next,
            "specular on/off; shininess ×2 ÷2; E environment",
        )],
        shows: None,
        // Highlights show only when on: the reference picture has none.
        status: Some(Status {
            shown: Some(|c| c.settings.specular),
            ..two(
                15,
                |c| format!("specular s={}", format_shininess(c.settings.shininess)),
                |c| format!("spec {}", format_shininess(c.settings.shininess)),
                9,
                3,
            )
        }),
        bench: Bench::Axis("specular"),
    },
    Opt {
        id: OptId::Shininess,
        name: "shininess",
        title: "shininess",
        kind: Kind::Number {
            parse: super::text::parse_shininess,
            step: Step {
                factor: 2.0,
                min: SHININESS_RANGE.0,
                max: SHININESS_RANGE.1,
                zero_below: None,
                wrap: false,
            },
            show: format_shininess,
            negative: false,
        },
        field: field!(shininess: f32),
        flag: Flag {
            value_name: Some("S"),
            ..flag("Specular exponent s of (N·H)^s: higher gives smaller, sharper highlights")
        },
        keys: &[also(&['y'], Press::Up), also(&['Y'], Press::Down)],
        shows: Some(Shows {
            when: |c| plan::specular_shows(c.settings, c.lights_on),
            why: "shows with specular on (g), a light on and fill display; unchanged",
        }),
        // Shown in the specular field.
        status: None,
        bench: Bench::None,
    },
    Opt {
        id: OptId::Environment,
        name: "environment",
        title: "environment",
        kind: Kind::Toggle,
        field: field!(environment: bool),
        flag: Flag {
            form: Form::Optional,
            ..flag(
                "Reflection of an environment, bent by the bump (docs/environment.md; Phong only): the built-in sky, or --environment-map. On by itself when a map is given",
            )
        },
        keys: &[also(&['E'], Press::Next)],
        shows: Some(Shows {
            when: |c| plan::environment_can_show(c.settings),
            why: "shows in Phong with fill display (m, d); unchanged",
        }),
        status: Some(Status {
            shown: Some(|c| plan::environment_shows(c.settings)),
            ..two(
                16,
                |c| {
                    format!(
                        "environment k={}",
                        format_shininess(c.settings.reflectivity)
                    )
                },
                |_| "env".into(),
                10,
                2,
            )
        }),
        bench: Bench::Axis("environment"),
    },
    Opt {
        id: OptId::Reflectivity,
        name: "reflectivity",
        title: "reflectivity",
        kind: Kind::Number {
            parse: super::text::parse_reflectivity,
            step: Step {
                factor: 1.0,
                min: 0.0,
                max: 1.0,
                zero_below: None,
                wrap: false,
            },
            show: format_shininess,
            negative: false,
        },
        field: field!(reflectivity: f32),
        flag: Flag {
            value_name: Some("K"),
            ..flag(
                "Share k of the reflection: colour = (1 − k)·lit + k·environment, k in {min}..={max}",
            )
        },
        keys: &[],
        shows: None,
        // Shown in the environment's field.
        status: None,
        bench: Bench::None,
    },
    Opt {
        id: OptId::Fov,
        name: "fov",
        title: "field of view",
        kind: Kind::Number {
            parse: |text| {
                let (min, max) = FOV_RANGE;
                let fov = parse_finite(text)?;
                if (min..=max).contains(&fov) {
                    Ok(fov)
                } else {
                    Err(format!(
                        "the field of view must be from {min} to {max} degrees, got '{text}'"
                    ))
                }
            },
            step: Step {
                factor: 1.125,
                min: FOV_RANGE.0,
                max: FOV_RANGE.1,
                zero_below: None,
                wrap: false,
            },
            show: |fov| format!("{}°", format_shininess(fov)),
            negative: false,
        },
        field: field!(fov: f32),
        flag: Flag {
            value_name: Some("DEGREES"),
            ..flag(
                "Vertical field of view of the camera in degrees, from {min} to {max} (the reference view: {default})",
            )
        },
        keys: &[
            key(&['w'], Press::Up, "field of view wider / narrower"),
            also(&['W'], Press::Down),
        ],
        shows: None,
        // Shown once it leaves the reference view.
        status: Some(Status {
            shown: Some(|c| c.settings.fov != DEFAULT_FOV),
            ..two(
                18,
                |c| format!("fov {}°", format_shininess(c.settings.fov)),
                |c| format!("fov {}", format_shininess(c.settings.fov)),
                13,
                5,
            )
        }),
        bench: Bench::None,
    },
    Opt {
        id: OptId::Up,
        name: "up",
        title: "up axis",
        kind: Kind::Choice {
            values: values::<UpAxis>,
        },
        field: field!(up: UpAxis),
        flag: flag(
            "The model's up axis: z stands Z-up files (most CAD and 3D-printing files) upright",
        ),
        keys: &[key(&['Z'], Press::Next, "up axis: Y / Z")],
        shows: None,
        // Shown only for Z-up.
        status: Some(Status {
            shown: Some(|c| c.settings.up == UpAxis::Z),
            ..same(19, |_| "Z up".into(), Some(4))
        }),
        bench: Bench::None,
    },
    Opt {
        id: OptId::ToneMap,
        name: "tone_map",
        title: "tone map",
        kind: Kind::Choice {
            values: values::<ToneMap>,
        },
        field: field!(tone_map: ToneMap),
        flag: flag(
            "Tone map of physically shaded models (glTF materials): Khronos PBR Neutral, ACES filmic, or none",
        ),
        keys: &[],
        shows: None,
        status: None,
        bench: Bench::None,
    },
    Opt {
        id: OptId::Exposure,
        name: "exposure",
        title: "exposure",
        kind: Kind::Number {
            parse: |text| {
                let e = parse_finite(text)?;
                if e > 0.0 {
                    Ok(e)
                } else {
                    Err(format!("the exposure must be above 0, got '{text}'"))
                }
            },
            step: Step {
                factor: 1.25,
                min: 0.01,
                max: 100.0,
                zero_below: None,
                wrap: false,
            },
            show: format_shininess,
            negative: false,
        },
        field: field!(exposure: f32),
        flag: Flag {
            value_name: Some("E"),
            ..flag(
                "Exposure: multiplies the light of physically shaded models before the tone map (1: as lit)",
            )
        },
        keys: &[],
        shows: None,
        status: None,
        bench: Bench::None,
    },
    Opt {
        id: OptId::EnvironmentTurn,
        name: "environment_turn",
        title: "environment turn",
        kind: Kind::Number {
            parse: |text| {
                let a = parse_finite(text)?;
                Ok(a.rem_euclid(360.0))
            },
            step: Step {
                factor: 30.0,
                min: 0.0,
                max: 360.0,
                zero_below: None,
                wrap: true,
            },
            show: |a| format!("{}°", format_shininess(a)),
            negative: true,
        },
        field: field!(environment_turn: f32),
        flag: Flag {
            value_name: Some("DEGREES"),
            ..flag(
                "Turn of the model view's environment about the vertical axis, in degrees (docs/shading.md, \"Image-based light\")",
            )
        },
        keys: &[key(
            &['J'],
            Press::Up,
            "turn the model's environment {step}° about the vertical",
        )],
        shows: Some(Shows {
            when: |c| plan::environment_can_show(c.settings),
            why: "shows on glTF materials in the model view, in Phong with fill display (m, d); unchanged",
        }),
        status: Some(Status {
            shown: Some(|c| c.settings.environment_turn != 0.0),
            ..same(
                20,
                |c| format!("env {}°", format_shininess(c.settings.environment_turn)),
                Some(6),
            )
        }),
        bench: Bench::None,
    },
    Opt {
        id: OptId::Backdrop,
        name: "backdrop",
        title: "backdrop",
        kind: Kind::Toggle,
        field: field!(backdrop: bool),
        flag: Flag {
            form: Form::Switch,
            ..flag(
                "Draw the model view's environment behind the model instead of the plain background (docs/shading.md, \"Image-based light\")",
            )
        },
        keys: &[key(
            &['B'],
            Press::Next,
            "the environment behind the model on / off",
        )],
        shows: Some(Shows {
            when: |c| c.settings.display == Display::Fill,
            why: "shows behind a model in the model view, with fill display (d); unchanged",
        }),
        status: Some(Status {
            shown: Some(|c| c.settings.backdrop),
            ..same(21, |_| "backdrop".into(), Some(6))
        }),
        bench: Bench::None,
    },
    Opt {
        id: OptId::IblDiffuse,
        name: "ibl_diffuse",
        title: "image-based diffuse light",
        kind: Kind::Choice {
            values: values::<IblDiffuse>,
        },
        field: field!(ibl_diffuse: IblDiffuse),
        flag: flag(
            "Diffuse light of the model view's environment on glTF materials: nine spherical harmonics, or an irradiance map integrated exactly (docs/shading.md, \"Image-based light\")",
        ),
        keys: &[],
        shows: None,
        status: None,
        bench: Bench::None,
    },
    Opt {
        id: OptId::IblSpecular,
        name: "ibl_specular",
        title: "image-based specular light",
        kind: Kind::Choice {
            values: values::<IblSpecular>,
        },
        field: field!(ibl_specular: IblSpecular),
        flag: flag(
            "Specular light of the model view's environment on glTF materials: prefiltered levels and the split-sum table, or the GGX lobe sampled per pixel (docs/shading.md, \"Image-based light\")",
        ),
        keys: &[],
        shows: None,
        status: None,
        bench: Bench::None,
    },
];

// Each entry at its id's place, so that [`get`] is an index: a table out
// of order does not compile.
const _: () = {
    let mut i = 0;
    while i < TABLE.len() {
        assert!(
            TABLE[i].id as usize == i,
            "an option's entry is not at its id's place"
        );
        assert!(
            OptId::ALL[i] as usize == i,
            "OptId::ALL is not in the ids' order"
        );
        i += 1;
    }
};

/// The entry of option `id`.
pub fn get(id: OptId) -> &'static Opt {
    &OPTIONS[id as usize]
}

/// The keys a help line shows: the first key of entry `opt`'s press `key`,
/// of each `Above` press after it in the table (up to the next line), then
/// the line's `others` ("+ -", "g y Y E", "d F u U").
pub fn help_keys(opt: usize, key: usize) -> String {
    let presses = OPTIONS.iter().flat_map(|o| o.keys.iter());
    let before: usize = OPTIONS[..opt].iter().map(|o| o.keys.len()).sum();
    let mut presses = presses.skip(before + key);
    let mut shown: Vec<String> = Vec::new();
    let others = match presses.next().map(|k| (k, &k.help)) {
        Some((k, KeyHelp::Line { others, .. })) => {
            shown.extend(k.keys.first().map(char::to_string));
            *others
        }
        _ => return String::new(),
    };
    for k in presses.take_while(|k| matches!(k.help, KeyHelp::Above)) {
        shown.extend(k.keys.first().map(char::to_string));
    }
    shown.extend(others.split_whitespace().map(String::from));
    shown.join(" ")
}

/// The texture field's value: on or off, or `none` on a model that has
/// no texture until the user chooses one.
fn texture_shown(c: &Ctx) -> &'static str {
    if c.texture_waits {
        "none"
    } else {
        on_off(c.settings.texture)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The keys the help line of `id`'s first press shows.
    fn line_keys(id: OptId) -> String {
        help_keys(id as usize, 0)
    }

    #[test]
    fn help_lines_show_the_keys_they_describe() {
        assert_eq!(line_keys(OptId::Shading), "m");
        assert_eq!(line_keys(OptId::BumpStrength), "+ -");
        assert_eq!(line_keys(OptId::LightVector), "v N");
        assert_eq!(line_keys(OptId::Display), "d F u U");
        assert_eq!(line_keys(OptId::Lights), "l 1 2 3 4");
        assert_eq!(line_keys(OptId::Specular), "g y Y E");
        assert_eq!(line_keys(OptId::Fov), "w W");
        // The up axis has its own line, no longer the field of view's.
        assert_eq!(line_keys(OptId::Up), "Z");
        // A key the line above describes shows no line of its own.
        assert_eq!(line_keys(OptId::TangentFrames), "");
    }

    #[test]
    fn help_texts_state_the_numbers_their_entries_hold() {
        let (min, max) = FOV_RANGE;
        let fov = get(OptId::Fov).flag_help();
        assert!(
            fov.contains(&format!(
                "from {min} to {max} (the reference view: {DEFAULT_FOV})"
            )),
            "{fov}"
        );
        assert!(!fov.contains('{'), "{fov}");
        let k = get(OptId::Reflectivity).flag_help();
        assert!(k.ends_with("k in 0..=1"), "{k}");
        let KeyHelp::Line { text, .. } = &get(OptId::EnvironmentTurn).keys[0].help else {
            panic!("the environment's turn has a help line");
        };
        let turn = get(OptId::EnvironmentTurn).fill(text);
        assert_eq!(turn, "turn the model's environment 30° about the vertical");
    }

    #[test]
    fn every_id_names_its_own_entry() {
        for id in OptId::ALL {
            assert_eq!(get(id).id, id);
        }
        assert_eq!(OPTIONS.len(), OptId::ALL.len());
    }
}
