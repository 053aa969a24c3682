//! A texture: its base level, the mip chain and normal map built from it
//! on first use, and the memory budget it holds.

use std::sync::atomic::{AtomicU64, Ordering};

use super::level::Level;
use super::normal_map::NormalMap;
use super::texels::{Fetch, Texels};
use crate::with_fetch;
use std::sync::{Arc, Mutex, OnceLock};

/// A colour + height texture and, built on first use, its mip chain.
#[derive(Debug)]
pub struct Texture {
    /// Where it came from, for the status line (already sanitised).
    pub name: String,
    base: Level,
    /// Every height equal: the bump stage has nothing to show.
    flat_height: bool,
    /// Level 0 is a copy-free view of `base` only conceptually: `mips` holds
    /// levels 1.. and is built the first time a minified pixel asks for it.
    mips: OnceLock<Vec<Level>>,
    /// The dot3 normal map, built on first use for one slope scale and
    /// rebuilt only when the scale changes.
    normal_map: Mutex<Option<Arc<NormalMap>>>,
    /// Normal maps built so far (for the frame counters and tests).
    normal_map_builds: AtomicU64,
    /// The memory budget held for the worst case of everything above (for
    /// textures read from files).
    reservation: Option<relief_core::budget::Reservation>,
}

impl Texture {
    pub fn new(name: impl Into<String>, base: Level) -> Self {
        let first = base.texels.first().map_or(0.0, |t| t[3]);
        let flat_height =
            with_fetch!(&base.texels, t => (0..t.len()).all(|i| t.height(i) == first));
        Texture {
            name: name.into(),
            base,
            flat_height,
            mips: OnceLock::new(),
            normal_map: Mutex::new(None),
            normal_map_builds: AtomicU64::new(0),
            reservation: None,
        }
    }

    /// The texture read with these wrap modes (a model's sampler), its
    /// mip chain and normal map made from then on with them.
    pub fn with_wrap(mut self, wrap: super::wrap::Wrap) -> Self {
        self.base.wrap = wrap;
        self.mips = OnceLock::new();
        self.normal_map = Mutex::new(None);
        self
    }

    /// The texture holding `reservation` until it is dropped.
    pub fn holding(mut self, reservation: relief_core::budget::Reservation) -> Self {
        self.reservation = Some(reservation);
        self
    }

    /// Bytes held against the memory budget for this texture (0 for one
    /// made in memory).
    pub fn reserved_bytes(&self) -> u64 {
        self.reservation.as_ref().map_or(0, |r| r.bytes())
    }

    /// From 8-bit RGBA rows, **top row first** (as images are stored).
    pub fn from_rgba8(name: impl Into<String>, width: usize, height: usize, rgba: &[u8]) -> Self {
        Texture::new(name, Level::from_rgba8_top_down(width, height, rgba))
    }

    pub fn into_arc(self) -> Arc<Texture> {
        Arc::new(self)
    }

    /// This texture with every height 0 (a glTF colour map, whose alpha is
    /// opacity), converted in place at its precision: its reservation
    /// still covers it.
    pub fn without_height(mut self) -> Self {
        let texels = std::mem::replace(&mut self.base.texels, Texels::F32(Vec::new()));
        self.base.texels = texels.without_height();
        self.flat_height = true;
        self.mips = OnceLock::new();
        self.normal_map = Mutex::new(None);
        self
    }

    /// This texture held against the budget for its base level and mip
    /// chain only: for a map whose texels are read as they are (a model's
    /// colour, normal or metallic-roughness picture), never made into a
    /// normal map from its heights.
    pub fn read_as_map(mut self) -> Self {
        let texels = self.base.texels.len() as f64;
        let mip = match self.base.texels.mip_kind() {
            super::texels::MipKind::F32 => 16.0,
            super::texels::MipKind::Rgba16 => 8.0,
            super::texels::MipKind::Xyz16 => 6.0,
        } / 3.0;
        let needed = (texels * (self.base.texels.bytes_per_texel() as f64 + mip)).ceil() as u64;
        if let Some(held) = &mut self.reservation {
            held.shrink(held.bytes().saturating_sub(needed));
        }
        self
    }

    /// The full-resolution level, moved out (for a map read one level only).
    pub fn into_base(self) -> Level {
        self.base
    }

    /// The full-resolution level.
    pub fn base(&self) -> &Level {
        &self.base
    }

    pub fn width(&self) -> usize {
        self.base.width
    }

    pub fn height(&self) -> usize {
        self.base.height
    }

    /// True when the height map is constant, so bump mapping cannot change a pixel.
    pub fn height_is_flat(&self) -> bool {
        self.flat_height
    }

    /// True once the mip chain has been built (tests use it to show that
    /// nothing builds it while no pixel is minified).
    pub fn mips_built(&self) -> bool {
        self.mips.get().is_some()
    }

    /// Levels 1.. of the mip chain, built once on first call.
    pub fn mip_levels(&self) -> &[Level] {
        self.mips.get_or_init(|| self.base.build_chain())
    }

    /// Level `i` of the chain (0 = base), clamped to the smallest level.
    #[inline]
    pub fn level(&self, i: usize) -> &Level {
        if i == 0 {
            return &self.base;
        }
        let chain = self.mip_levels();
        if chain.is_empty() {
            &self.base
        } else {
            &chain[(i - 1).min(chain.len() - 1)]
        }
    }

    /// Number of levels including the base.
    pub fn level_count(&self) -> usize {
        1 + self.mip_levels().len()
    }

    /// The normal map for slope scale `scale` (see [`NormalMap::build`]),
    /// built on first use and kept until another scale is asked for. The flag
    /// says whether this call built it (for the frame's counters).
    pub fn normal_map(&self, scale: f32) -> (Arc<NormalMap>, bool) {
        let mut slot = self
            .normal_map
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(map) = slot.as_ref()
            && map.scale.to_bits() == NormalMap::effective_scale(scale).to_bits()
        {
            return (Arc::clone(map), false);
        }
        let map = Arc::new(NormalMap::build(&self.base, scale));
        *slot = Some(Arc::clone(&map));
        self.normal_map_builds.fetch_add(1, Ordering::Relaxed);
        (map, true)
    }

    /// How many normal maps this texture has built.
    pub fn normal_map_builds(&self) -> u64 {
        self.normal_map_builds.load(Ordering::Relaxed)
    }
}
