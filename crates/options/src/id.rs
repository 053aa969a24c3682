//! The options' ids: a key, a message or a bench row names its option by
//! one of these, so a wrong id does not compile.

/// One option of the table ([`super::OPTIONS`]), in the table's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OptId {
    Shading,
    Normals,
    Texture,
    Colors,
    Bump,
    BumpStrength,
    Filter,
    Technique,
    LightVector,
    HeightDerivative,
    Aa,
    Display,
    TangentFrames,
    Lights,
    Attenuation,
    Specular,
    Shininess,
    Environment,
    Reflectivity,
    Fov,
    Up,
    ToneMap,
    Exposure,
    EnvironmentTurn,
    Backdrop,
    IblDiffuse,
    IblSpecular,
}

impl OptId {
    /// Every id, in the table's order. The table has one entry per id, at
    /// the id's place (checked when the crate compiles, see `table.rs`).
    pub const ALL: [OptId; 27] = [
        OptId::Shading,
        OptId::Normals,
        OptId::Texture,
        OptId::Colors,
        OptId::Bump,
        OptId::BumpStrength,
        OptId::Filter,
        OptId::Technique,
        OptId::LightVector,
        OptId::HeightDerivative,
        OptId::Aa,
        OptId::Display,
        OptId::TangentFrames,
        OptId::Lights,
        OptId::Attenuation,
        OptId::Specular,
        OptId::Shininess,
        OptId::Environment,
        OptId::Reflectivity,
        OptId::Fov,
        OptId::Up,
        OptId::ToneMap,
        OptId::Exposure,
        OptId::EnvironmentTurn,
        OptId::Backdrop,
        OptId::IblDiffuse,
        OptId::IblSpecular,
    ];
}
