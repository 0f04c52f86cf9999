//! Per-scene image tolerances: `fixtures/reference/tolerances.ron`, a RON map
//! from scene name (the file stem in `fixtures/scenes/`) to a
//! [`Tolerance`]. A scene that is not listed must match its reference exactly.
//!
//! ```ron
//! {
//!     // Why this scene may differ, and by how much.
//!     "phong": (max_rmse: 0.05, max_pixel: 1, pixel_threshold: 0, max_fraction_over: 0.001),
//! }
//! ```

use crate::imgdiff::Tolerance;
use std::collections::BTreeMap;
use std::path::Path;

/// Scene name → tolerance.
pub type Tolerances = BTreeMap<String, Tolerance>;

/// Parses the tolerance file's text; `path` names it in messages.
///
/// # Errors
/// `path:line:col: message` for malformed RON or an unknown field, and a
/// message naming the scene for a value out of range (negative, not finite,
/// or a fraction above 1).
pub fn parse(text: &str, path: &Path) -> Result<Tolerances, String> {
    let map: Tolerances = ron::from_str(text).map_err(|e| {
        format!(
            "{}:{}:{}: {}",
            path.display(),
            e.position.line,
            e.position.col,
            e.code
        )
    })?;
    for (name, t) in &map {
        let bad = |what: &str| Err(format!("{}: scene \"{name}\": {what}", path.display()));
        if !(t.max_rmse >= 0.0 && t.max_rmse.is_finite()) {
            return bad("max_rmse must be a finite number ≥ 0");
        }
        if !(0.0..=1.0).contains(&t.max_fraction_over) {
            return bad("max_fraction_over is a fraction of the pixels, from 0 to 1");
        }
    }
    Ok(map)
}

/// Reads the tolerance file; a missing file means "every scene exact".
///
/// # Errors
/// As [`parse`], or when the file exists but cannot be read.
pub fn load(path: &Path) -> Result<Tolerances, String> {
    match std::fs::read_to_string(path) {
        Ok(text) => parse(&text, path),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Tolerances::new()),
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

/// The tolerance of a scene: its entry, or exact.
pub fn of(map: &Tolerances, scene: &str) -> Tolerance {
    map.get(scene).copied().unwrap_or_default()
}

/// Entries naming no scene (a renamed or deleted scene leaves them stale).
pub fn unknown<'a>(map: &'a Tolerances, scenes: &[String]) -> Vec<&'a str> {
    map.keys()
        .filter(|k| !scenes.contains(k))
        .map(String::as_str)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(text: &str) -> Result<Tolerances, String> {
        parse(text, Path::new("tol.ron"))
    }

    #[test]
    fn entries_parse_and_missing_fields_are_exact() {
        let m = p(r#"{
            // a comment
            "phong": (max_rmse: 0.05, max_pixel: 1, max_fraction_over: 0.001),
            "mirror_glass": Tolerance(pixel_threshold: 2),
        }"#)
        .unwrap();
        assert_eq!(m.len(), 2);
        let t = of(&m, "phong");
        assert_eq!(
            (
                t.max_rmse,
                t.max_pixel,
                t.pixel_threshold,
                t.max_fraction_over
            ),
            (0.05, 1, 0, 0.001)
        );
        assert_eq!(of(&m, "mirror_glass").pixel_threshold, 2);
        assert_eq!(of(&m, "not_listed"), Tolerance::default());
    }

    #[test]
    fn empty_map_is_fine() {
        assert!(p("{}").unwrap().is_empty());
    }

    #[test]
    fn unknown_fields_and_bad_values_are_errors_with_a_place() {
        let e = p("{\n  \"a\": (max_rsme: 1.0),\n}").unwrap_err();
        assert!(e.starts_with("tol.ron:2:"), "{e}");
        assert!(e.contains("max_rsme"), "{e}");
        assert!(p(r#"{"a": (max_rmse: -1.0)}"#)
            .unwrap_err()
            .contains("\"a\""));
        assert!(p(r#"{"a": (max_fraction_over: 2.0)}"#).is_err());
        assert!(p(r#"{"a": (max_pixel: 300)}"#).is_err());
        assert!(p(r#"{"a": (max_rmse: 1.0)"#).is_err());
    }

    #[test]
    fn stale_entries_are_found() {
        let m = p(r#"{"gone": (), "here": ()}"#).unwrap();
        assert_eq!(unknown(&m, &["here".to_string()]), vec!["gone"]);
    }
}
