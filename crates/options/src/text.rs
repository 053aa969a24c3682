//! How option values are read from the command line and written in the
//! status line and the key messages.

/// A finite number (no NaN, no infinity).
pub fn parse_finite(text: &str) -> Result<f32, String> {
    let value: f32 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("'{text}' is not a finite number"))
    }
}

/// A bump strength: finite and not negative.
pub fn parse_strength(text: &str) -> Result<f32, String> {
    let k = parse_finite(text)?;
    if k < 0.0 {
        return Err(format!("bump strength must be 0 or more, got {k}"));
    }
    Ok(k)
}

/// A specular exponent: finite and > 0.
pub fn parse_shininess(text: &str) -> Result<f32, String> {
    let s = parse_finite(text)?;
    if s > 0.0 {
        Ok(s)
    } else {
        Err(format!("the shininess must be above 0, got '{text}'"))
    }
}

/// A reflectivity: finite, in 0..=1.
pub fn parse_reflectivity(text: &str) -> Result<f32, String> {
    let k = parse_finite(text)?;
    if (0.0..=1.0).contains(&k) {
        Ok(k)
    } else {
        Err(format!("the reflectivity must be in 0..=1, got '{text}'"))
    }
}

pub fn on_off(b: bool) -> &'static str {
    if b { "on" } else { "off" }
}

/// The bump strength with at most four decimals, no trailing zeros.
pub fn format_strength(k: f32) -> String {
    let s = format!("{k:.4}");
    let s = s.trim_end_matches('0');
    s.strip_suffix('.').unwrap_or(s).to_string()
}

/// The specular exponent (or a reflectivity) without needless decimals.
pub fn format_shininess(s: f32) -> String {
    format!("{}", (s * 100.0).round() / 100.0)
}
