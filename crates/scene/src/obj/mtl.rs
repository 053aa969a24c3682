//! Wavefront MTL material libraries, read into one plain description per
//! `newmtl`: what relief can show of a material, and nothing that needs the
//! scene (textures are paths here; loading them is the caller's choice).
//!
//! Read: `Kd`, `Ks`, `Ns`, `d` (opacity) or `Tr` (transparency, 1 − d),
//! `map_Kd`, `map_Ks`, `map_d`, `bump`/`map_Bump`/`map_bump` (a height map,
//! its `-bm` multiplier kept), `norm` (a tangent-space normal map) and the
//! PBR extension's `Pr`, `Pm`, `map_Pr` and `map_Pm` (roughness, metallic).
//! Keywords are matched without regard to case. A map line's options
//! (`-bm 2`, `-s 1 1 1`, `-clamp on`, …) come before the file name, which
//! is the rest of the line: it may hold spaces, be quoted, and use `\`.
//! Texture paths are resolved relative to the MTL, matching names without
//! regard to case when the exact one is missing. Everything else (`Ka`,
//! `illum`, `Ni`, the extension's sheen and clearcoat, …) is skipped. A line that cannot be read
//! is a warning naming the file and line; the rest of the library is kept.

use std::path::Path;

use glam::Vec3;

use crate::model_io::resolve_beside;
use relief_core::sanitize::clean;

use crate::loaded_model::{MaterialDesc, TexturePath};

/// Map options and how many numbers (or words) follow each.
const OPTIONS: &[(&str, usize, usize)] = &[
    ("-blendu", 1, 1),
    ("-blendv", 1, 1),
    ("-bm", 1, 1),
    ("-boost", 1, 1),
    ("-cc", 1, 1),
    ("-clamp", 1, 1),
    ("-imfchan", 1, 1),
    ("-mm", 1, 2),
    ("-o", 1, 3),
    ("-s", 1, 3),
    ("-t", 1, 3),
    ("-texres", 1, 1),
    ("-type", 1, 1),
];

/// A map line's text after its keyword: the options read, the `-bm`
/// multiplier, and the file name (the rest of the line, unquoted).
fn map_statement(rest: &str) -> Result<(String, Option<f32>), String> {
    let mut rest = rest.trim();
    let mut bm = None;
    loop {
        let word = rest.split_whitespace().next().unwrap_or("");
        let Some(&(option, min, max)) = OPTIONS.iter().find(|(o, ..)| *o == word) else {
            break;
        };
        rest = rest[word.len()..].trim_start();
        let mut taken = 0;
        while taken < max {
            let next = rest.split_whitespace().next().unwrap_or("");
            let numeric = next.parse::<f32>().is_ok();
            // Options with one value take a word (`on`, `r`, `sphere`);
            // those with several take numbers only.
            if next.is_empty() || (max > 1 && taken >= min && !numeric) {
                break;
            }
            if option == "-bm" {
                let value = next
                    .parse::<f32>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| format!("-bm {} is not a finite number", quote(next)))?;
                bm = Some(value);
            }
            rest = rest[next.len()..].trim_start();
            taken += 1;
        }
        if taken < min {
            return Err(format!("option {option} needs a value"));
        }
    }
    let file = rest.trim();
    let file = file
        .strip_prefix('"')
        .and_then(|f| f.strip_suffix('"'))
        .unwrap_or(file);
    if file.is_empty() {
        return Err("no file name".into());
    }
    Ok((file.to_string(), bm))
}

fn quote(word: &str) -> String {
    let s: String = clean(word).chars().take(24).collect();
    format!("'{s}'")
}

fn color(rest: &str) -> Result<Vec3, String> {
    let n: Vec<f32> = rest
        .split_whitespace()
        .map(|w| w.parse::<f32>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("{} is not a colour", quote(rest.trim())))?;
    match n.as_slice() {
        // One number is a grey.
        [g] => Ok(Vec3::splat(*g)),
        [r, g, b] => Ok(Vec3::new(*r, *g, *b)),
        _ => Err(format!("{} is not a colour", quote(rest.trim()))),
    }
}

fn scalar(rest: &str) -> Result<f32, String> {
    rest.split_whitespace()
        .next()
        .and_then(|w| w.parse::<f32>().ok())
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("{} is not a number", quote(rest.trim())))
}

/// Reads an MTL library (`text`, any 8-bit encoding) found in `dir`;
/// `name` (already sanitised) names it in warnings. Returns the materials
/// and the warnings.
pub fn parse(name: &str, text: &[u8], dir: &Path) -> (Vec<MaterialDesc>, Vec<String>) {
    let text = String::from_utf8_lossy(text);
    let mut materials: Vec<MaterialDesc> = Vec::new();
    let mut warnings = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        let (keyword, rest) = match line.split_once(|c: char| c.is_ascii_whitespace()) {
            Some((k, r)) => (k, r.trim()),
            None => (line, ""),
        };
        if keyword.is_empty() {
            continue;
        }
        let keyword = keyword.to_ascii_lowercase();
        if keyword == "newmtl" {
            materials.push(MaterialDesc::named(rest.to_string()));
            continue;
        }
        let Some(m) = materials.last_mut() else {
            continue;
        };
        let result = apply_statement(m, &keyword, rest, dir);
        if let Err(problem) = result {
            warnings.push(format!(
                "material library {name}, line {}: {problem} (line skipped)",
                number + 1
            ));
        }
    }
    for m in &materials {
        warn_of_missing_maps(name, m, &mut warnings);
    }
    (materials, warnings)
}

/// Sets what statement `keyword rest` of an MTL library in `dir` says of
/// material `m`; an unknown keyword is ignored.
fn apply_statement(
    m: &mut MaterialDesc,
    keyword: &str,
    rest: &str,
    dir: &Path,
) -> Result<(), String> {
    let texture = |rest: &str| -> Result<(TexturePath, Option<f32>), String> {
        let (written, bm) = map_statement(rest)?;
        let file = resolve_beside(dir, &written);
        Ok((TexturePath { written, file }, bm))
    };
    match keyword {
        "kd" => m.diffuse = Some(color(rest)?),
        "ks" => m.specular = Some(color(rest)?),
        "ns" => m.shininess = Some(scalar(rest)?),
        "d" => m.opacity = Some(scalar(rest)?.clamp(0.0, 1.0)),
        "tr" => m.opacity = Some(1.0 - scalar(rest)?.clamp(0.0, 1.0)),
        "map_kd" => m.diffuse_map = Some(texture(rest)?.0),
        "map_ks" => m.specular_map = Some(texture(rest)?.0),
        "map_d" => m.opacity_map = Some(texture(rest)?.0),
        "bump" | "map_bump" => {
            let (path, bm) = texture(rest)?;
            m.bump_map = Some(path);
            m.bump_multiplier = bm.unwrap_or(1.0);
        }
        "norm" => m.normal_map = Some(texture(rest)?.0),
        "pr" => m.roughness = Some(scalar(rest)?.clamp(0.0, 1.0)),
        "pm" => m.metallic = Some(scalar(rest)?.clamp(0.0, 1.0)),
        "map_pr" => m.roughness_map = Some(texture(rest)?.0),
        "map_pm" => m.metallic_map = Some(texture(rest)?.0),
        _ => {}
    }
    Ok(())
}

/// One warning per map of material `m` whose file was not found.
fn warn_of_missing_maps(name: &str, m: &MaterialDesc, warnings: &mut Vec<String>) {
    for (what, map) in [
        ("map_Kd", &m.diffuse_map),
        ("map_Ks", &m.specular_map),
        ("map_d", &m.opacity_map),
        ("bump", &m.bump_map),
        ("norm", &m.normal_map),
        ("map_Pr", &m.roughness_map),
        ("map_Pm", &m.metallic_map),
    ] {
        if let Some(TexturePath {
            written,
            file: None,
        }) = map
        {
            warnings.push(format!(
                "material library {name}: {what} {} of material {} not found",
                quote(written),
                quote(&m.name)
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pbr_extension_is_read() {
        let text = b"newmtl steel\nKd 0.5 0.5 0.5\nPr 0.25\nPM 2\nmap_Pr -bm 1 rough.png\nmap_Pm metal.png\n";
        let (m, warnings) = parse("lib.mtl", text, Path::new("/nonexistent-dir"));
        assert_eq!(m.len(), 1);
        assert_eq!((m[0].roughness, m[0].metallic), (Some(0.25), Some(1.0)));
        assert_eq!(m[0].roughness_map.as_ref().unwrap().written, "rough.png");
        assert_eq!(m[0].metallic_map.as_ref().unwrap().written, "metal.png");
        // Both maps are missing there: a warning each.
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert!(warnings[0].contains("map_Pr"), "{warnings:?}");
    }

    #[test]
    fn options_come_before_a_file_name_with_spaces() {
        assert_eq!(
            map_statement("-bm 2 -s 1 1 1 -clamp on my bump.png"),
            Ok(("my bump.png".into(), Some(2.0)))
        );
        assert_eq!(map_statement("\"a b.png\""), Ok(("a b.png".into(), None)));
        assert_eq!(
            map_statement("-o 0.5 tex.png"),
            Ok(("tex.png".into(), None))
        );
        assert!(map_statement("-bm").is_err());
        assert!(map_statement("-bm x f.png").is_err());
    }

    #[test]
    fn materials_are_read_case_insensitively() {
        let text = b"newmtl a\nKD 1 0.5 0\nTr 0.25\nNs 10\nnewmtl b\nkd 0.5\nd 0.5\n";
        let (m, w) = parse("x.mtl", text, Path::new("."));
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(m.len(), 2);
        assert_eq!(m[0].diffuse, Some(Vec3::new(1.0, 0.5, 0.0)));
        assert_eq!(m[0].opacity, Some(0.75));
        assert_eq!(m[0].shininess, Some(10.0));
        assert_eq!(m[1].diffuse, Some(Vec3::splat(0.5)));
        assert_eq!(m[1].opacity, Some(0.5));
    }

    #[test]
    fn a_bad_line_is_a_warning_with_its_line() {
        let (m, w) = parse("x.mtl", b"newmtl a\nKd red\nKs 1 1 1\n", Path::new("."));
        assert_eq!(m[0].specular, Some(Vec3::ONE));
        assert_eq!(m[0].diffuse, None);
        assert_eq!(w.len(), 1);
        assert!(w[0].starts_with("material library x.mtl, line 2:"), "{w:?}");
    }
}
