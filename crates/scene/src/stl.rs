//! STL models, binary or ASCII.
//!
//! Which one is decided by size and content, not by the first word (binary
//! files from many CAD tools begin with `solid` too): a file whose length is
//! exactly 84 + 50 × the triangle count in its header is binary; otherwise
//! one that begins with `solid` is ASCII; otherwise it is binary and its
//! length must cover the triangles its header claims (checked before
//! anything is allocated, so a header claiming 4 G triangles costs nothing).
//!
//! Each facet's normal is used at its three corners, so edges stay hard as
//! STL means them (a zero or unusable normal is replaced by the one its
//! winding gives). Binary facet colours follow the two known conventions:
//! with `COLOR=` in the header (Materialise Magics) bit 15 clear marks a
//! facet colour, red in the low bits, the header's colour for the others;
//! otherwise (VisCAM, SolidView) bit 15 set marks a colour, blue in the low
//! bits. Facets without one are white when any facet has one.

use glam::Vec3;

use super::corners::{IndexedCorners, NO_INDEX, build_indexed, bytes_of};
use super::loaded_model::{LoadedModel, ModelMaps, ModelPart};
use super::model_error::ObjError;
use super::model_io::reserve;
use relief_core::budget::Reservation;

const HEADER: usize = 80;
const FACET: u64 = 50;

/// Reads an STL file; `name` (already sanitised) is used in messages.
pub fn parse(name: &str, bytes: &[u8]) -> Result<LoadedModel, ObjError> {
    relief_core::contain::contain(|| parse_unguarded(name, bytes)).unwrap_or_else(|cause| {
        Err(ObjError::Parse {
            name: name.to_string(),
            reason: format!("the reader failed on it ({cause})"),
        })
    })
}

fn parse_unguarded(name: &str, bytes: &[u8]) -> Result<LoadedModel, ObjError> {
    let claimed = (bytes.len() >= HEADER + 4)
        .then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64);
    let exact = claimed.is_some_and(|n| HEADER as u64 + 4 + n * FACET == bytes.len() as u64);
    let starts_solid = bytes.trim_ascii_start().starts_with(b"solid");
    let (facets, mut held) = if exact || !starts_solid {
        binary(name, bytes, claimed)?
    } else {
        ascii(name, bytes)?
    };
    let meshes = build_indexed(name, facets.corners, &[], &[true], &mut held)?;
    Ok(LoadedModel {
        parts: meshes
            .into_iter()
            .map(|(_, mesh)| ModelPart {
                mesh,
                material: None,
                own_maps: None,
                opacity_map: None,
                pbr_maps: Default::default(),
            })
            .collect(),
        maps: ModelMaps::default(),
        points: false,
        warnings: Vec::new(),
        z_up: true,
    })
}

fn vec3(b: &[u8]) -> Vec3 {
    let f = |i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    Vec3::new(f(0), f(4), f(8))
}

/// The facet's normal when usable, else its winding's.
fn facet_normal(given: Vec3, p: [Vec3; 3]) -> Option<Vec3> {
    given
        .try_normalize()
        .or_else(|| (p[1] - p[0]).cross(p[2] - p[0]).try_normalize())
}

/// The triangles as the builder reads them, filled as they are read: a
/// position per corner, one normal per facet for its three corners (none
/// when unusable: computed), a colour per corner when the file has any.
/// 84 bytes a triangle, 132 with colours; no corner-by-corner copy.
struct Facets {
    corners: IndexedCorners,
}

impl Facets {
    /// Bytes of `triangles` triangles, `colored` or not.
    fn bytes(triangles: u64, colored: bool) -> u64 {
        let corners = 3 * triangles;
        bytes_of::<Vec3>(corners)
            .saturating_add(bytes_of::<Vec3>(triangles))
            .saturating_add(bytes_of::<[u32; 3]>(corners))
            .saturating_add(if colored {
                bytes_of::<Option<Vec3>>(corners)
            } else {
                0
            })
    }

    /// Room for `triangles` triangles, reserved in a new reservation.
    fn reserve(
        name: &str,
        triangles: u64,
        colored: bool,
    ) -> Result<(Facets, Reservation), ObjError> {
        let held = reserve(name, "the triangles", Facets::bytes(triangles, colored))?;
        let n = triangles as usize;
        let corners = IndexedCorners {
            positions: Vec::with_capacity(3 * n),
            colors: if colored {
                Vec::with_capacity(3 * n)
            } else {
                Vec::new()
            },
            normals: Vec::with_capacity(n),
            corners: Vec::with_capacity(3 * n),
            ..IndexedCorners::default()
        };
        Ok((Facets { corners }, held))
    }

    fn push(&mut self, p: [Vec3; 3], normal: Option<Vec3>, color: Option<Vec3>) {
        let c = &mut self.corners;
        let n = normal.map_or(NO_INDEX, |n| {
            c.normals.push(n);
            (c.normals.len() - 1) as u32
        });
        for position in p {
            c.corners.push([c.positions.len() as u32, NO_INDEX, n]);
            c.positions.push(position);
        }
        if let Some(color) = color {
            c.colors.extend([Some(color); 3]);
        }
    }

    fn is_empty(&self) -> bool {
        self.corners.corners.is_empty()
    }
}

/// 5-bit channels of a 15-bit colour, low bits first.
fn channels(bits: u16) -> [f32; 3] {
    [0, 5, 10].map(|s| ((bits >> s) & 31) as f32 / 31.0)
}

fn binary(
    name: &str,
    bytes: &[u8],
    claimed: Option<u64>,
) -> Result<(Facets, Reservation), ObjError> {
    let at = |offset: u64, problem: String| ObjError::Byte {
        name: name.to_string(),
        offset,
        problem,
    };
    let Some(count) = claimed else {
        return Err(at(
            0,
            format!(
                "a binary STL needs an 84-byte header, the file has {} bytes",
                bytes.len()
            ),
        ));
    };
    let need = HEADER as u64 + 4 + count * FACET;
    if need > bytes.len() as u64 {
        return Err(at(
            80,
            format!(
                "the header claims {count} triangles ({need} bytes) but the file has {} bytes",
                bytes.len()
            ),
        ));
    }
    if count == 0 {
        return Err(ObjError::Empty {
            name: name.to_string(),
        });
    }
    // Materialise: the header's colour, and facets with bit 15 clear coloured.
    let header = &bytes[..HEADER];
    let magics = header.windows(6).position(|w| w == b"COLOR=").map(|i| {
        let c = header.get(i + 6..i + 9).unwrap_or(&[255, 255, 255]);
        Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) / 255.0
    });
    let records = || bytes[HEADER + 4..need as usize].chunks_exact(FACET as usize);
    // Any colour makes the uncoloured facets white: known before reading.
    let any_color = magics.is_some() || records().any(|f| f[49] & 0x80 != 0);
    let (mut facets, held) = Facets::reserve(name, count, any_color)?;
    for (i, facet) in records().enumerate() {
        let offset = (HEADER + 4) as u64 + i as u64 * FACET;
        let p = [vec3(&facet[12..]), vec3(&facet[24..]), vec3(&facet[36..])];
        if let Some(k) = p.iter().position(|v| !v.is_finite()) {
            return Err(at(
                offset + 12 + 12 * k as u64,
                format!("triangle {}: a position is not a finite number", i + 1),
            ));
        }
        let given = vec3(facet);
        let normal = facet_normal(if given.is_finite() { given } else { Vec3::ZERO }, p);
        let attribute = u16::from_le_bytes([facet[48], facet[49]]);
        let color = match magics {
            Some(_) if attribute & 0x8000 == 0 => Some(Vec3::from_array(channels(attribute))),
            Some(default) => Some(default),
            None if attribute & 0x8000 != 0 => {
                let [b, g, r] = channels(attribute);
                Some(Vec3::new(r, g, b))
            }
            None => None,
        };
        facets.push(p, normal, color.or(any_color.then_some(Vec3::ONE)));
    }
    Ok((facets, held))
}

fn ascii(name: &str, bytes: &[u8]) -> Result<(Facets, Reservation), ObjError> {
    let text = String::from_utf8_lossy(bytes);
    // A facet of n vertices is a fan of n - 2 triangles: counted first, to
    // reserve them.
    let (mut triangles, mut vertices) = (0u64, 0u64);
    for line in text.lines() {
        match line.split_whitespace().next() {
            Some("facet") => vertices = 0,
            Some("vertex") => vertices += 1,
            Some("endfacet") => triangles += vertices.saturating_sub(2),
            _ => {}
        }
    }
    let (mut facets, held) = Facets::reserve(name, triangles, false)?;
    let mut normal = Vec3::ZERO;
    let mut polygon: Vec<Vec3> = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let at = |problem: String| ObjError::Line {
            name: name.to_string(),
            line: number + 1,
            problem,
        };
        let mut words = line.split_whitespace();
        let keyword = words.next().unwrap_or("");
        let three = |words: &mut std::str::SplitWhitespace, what: &str| {
            let n: Vec<f32> = words
                .take(3)
                .map(|w| w.parse::<f32>().ok().filter(|x| x.is_finite()))
                .collect::<Option<_>>()
                .filter(|n: &Vec<f32>| n.len() == 3)
                .ok_or_else(|| at(format!("{what} needs three finite numbers")))?;
            Ok::<Vec3, ObjError>(Vec3::new(n[0], n[1], n[2]))
        };
        match keyword {
            "facet" => {
                polygon.clear();
                normal = match words.next() {
                    Some("normal") => three(&mut words, "facet normal")?,
                    _ => Vec3::ZERO,
                };
            }
            "vertex" => {
                let p = three(&mut words, "vertex")?;
                if polygon.len() >= super::corners::MAX_FACE_CORNERS {
                    return Err(at("too many vertices in one facet".into()));
                }
                polygon.push(p);
            }
            "endfacet" => {
                for k in 1..polygon.len().saturating_sub(1) {
                    let p = [polygon[0], polygon[k], polygon[k + 1]];
                    facets.push(p, facet_normal(normal, p), None);
                }
                polygon.clear();
            }
            _ => {}
        }
    }
    if facets.is_empty() {
        return Err(ObjError::Empty {
            name: name.to_string(),
        });
    }
    Ok((facets, held))
}
