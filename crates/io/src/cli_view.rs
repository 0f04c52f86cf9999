//! The command line's view and depth overrides: `--camera` picks a camera
//! of a glTF model by name; `--eye`, `--look-at`, `--up`, `--fov`,
//! `--aperture`, `--focus-distance` and `--max-depth` then replace the scene's (or the framed model's) camera
//! and settings, checked as a scene file's would be.

use crate::error::{Error, Result};
use crate::schema::MAX_DEPTH;
use crate::LoadedScene;
use clap::Args;
use gridrt_bbox::{Real, Vec3};
use gridrt_tracer::{Projection, ThinLens};

/// Camera and depth overrides of `gridrt render`.
#[derive(Debug, Clone, Default, Args)]
pub struct ViewArgs {
    /// A camera of the glTF model rendered on its own, by name (unnamed
    /// cameras are `camera N`, N the camera's index in the file).
    #[arg(long, value_name = "NAME")]
    pub camera: Option<String>,
    /// Camera position `X,Y,Z` (overrides the scene's camera).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<[f64; 3]>,
    /// The point the camera looks at, `X,Y,Z`.
    #[arg(long = "look-at", value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub look_at: Option<[f64; 3]>,
    /// The camera's up direction, `X,Y,Z` (not parallel to the view).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub up: Option<[f64; 3]>,
    /// Vertical field of view in degrees, between 0 and 180 (exclusive);
    /// the camera becomes a perspective one.
    #[arg(long, value_name = "DEG")]
    pub fov: Option<f64>,
    /// Longest chain of reflection and refraction bounces after the camera
    /// ray, 0 to 64 (overrides the scene's `max_depth`).
    #[arg(long = "max-depth", value_name = "N")]
    pub max_depth: Option<u32>,
    /// Radius of the camera's thin lens in world units (depth of field);
    /// 0 is a pinhole. Needs a focus distance (`--focus-distance`, or the
    /// scene camera's `focus_distance`).
    #[arg(long, value_name = "R")]
    pub aperture: Option<f64>,
    /// Distance from the eye to the plane in focus, along the view
    /// direction (> 0).
    #[arg(long = "focus-distance", value_name = "D")]
    pub focus_distance: Option<f64>,
}

/// Parses `X,Y,Z` (three finite numbers separated by commas).
fn parse_vec3(s: &str) -> std::result::Result<[f64; 3], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| format!("`{s}` is not three numbers X,Y,Z"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok([x, y, z]),
        [_, _, _] => Err(format!("`{s}` has a non-finite number")),
        _ => Err(format!("`{s}` is not three numbers X,Y,Z")),
    }
}

/// `[f64; 3]` as a `Vec3`, finite in `Real`.
fn vec3(arg: &str, v: [f64; 3]) -> Result<Vec3> {
    let p = Vec3::new(v[0] as Real, v[1] as Real, v[2] as Real);
    if p.is_finite() {
        Ok(p)
    } else {
        Err(Error::arg(
            arg,
            "the value is too large for the build's precision",
        ))
    }
}

impl ViewArgs {
    /// Applies the overrides to `scene`.
    ///
    /// # Errors
    /// [`Error::Arg`] naming the flag when the named camera does not exist,
    /// the view is degenerate (eye on
    /// the look-at point, up parallel to the view), the field of view is
    /// not in (0, 180) or the depth is over 64.
    // The lens fields are `Real`: their conversion to f64 does nothing in
    // the f64 build.
    #[allow(clippy::useless_conversion)]
    pub fn apply(&self, loaded: &mut LoadedScene) -> Result<()> {
        if let Some(name) = &self.camera {
            let Some((_, cam)) = loaded.cameras.iter().find(|(n, _)| n == name) else {
                let have: Vec<&str> = loaded.cameras.iter().map(|(n, _)| n.as_str()).collect();
                return Err(Error::arg(
                    "--camera",
                    if have.is_empty() {
                        format!("{} has no cameras", loaded.source.display())
                    } else {
                        format!(
                            "{} has no camera \"{name}\"; its cameras are: {}",
                            loaded.source.display(),
                            have.join(", ")
                        )
                    },
                ));
            };
            loaded.scene.camera = cam.clone();
            loaded.framed_camera = false;
        }
        let scene = &mut loaded.scene;
        let cam = &mut scene.camera;
        if let Some(e) = self.eye {
            cam.eye = vec3("--eye", e)?;
        }
        if let Some(l) = self.look_at {
            cam.look_at = vec3("--look-at", l)?;
        }
        if let Some(u) = self.up {
            cam.up = vec3("--up", u)?;
        }
        let flag = if self.look_at.is_some() {
            "--look-at"
        } else {
            "--eye"
        };
        let view = (cam.look_at - cam.eye)
            .try_normalize()
            .ok_or_else(|| Error::arg(flag, "the camera's eye and look-at point coincide"))?;
        if self.eye.is_some() || self.look_at.is_some() || self.up.is_some() {
            let side = cam.up.try_normalize().map(|u| u.cross(view).length());
            if !side.is_some_and(|s| s > 1e-6) {
                return Err(Error::arg(
                    if self.up.is_some() { "--up" } else { flag },
                    "the up direction is zero or parallel to the view direction: give another --up",
                ));
            }
        }
        if let Some(f) = self.fov {
            if !(f > 0.0 && f < 180.0) {
                return Err(Error::arg(
                    "--fov",
                    format!("{f} is not a field of view: use degrees between 0 and 180"),
                ));
            }
            cam.projection = Projection::Perspective {
                vfov_deg: f as Real,
            };
        }
        if self.aperture.is_some() || self.focus_distance.is_some() {
            let radius = self
                .aperture
                .unwrap_or_else(|| cam.lens.map_or(0.0, |l| f64::from(l.radius)));
            if !(radius >= 0.0 && radius.is_finite()) {
                return Err(Error::arg(
                    "--aperture",
                    format!("{radius} is not a lens radius: use a number >= 0 (0 is a pinhole)"),
                ));
            }
            let focus = self
                .focus_distance
                .or_else(|| cam.lens.map(|l| f64::from(l.focus_distance)));
            if let Some(f) = focus {
                if !(f > 0.0 && f.is_finite()) {
                    return Err(Error::arg(
                        "--focus-distance",
                        format!("{f} is not a distance to the plane in focus: use a number > 0"),
                    ));
                }
            }
            cam.lens = match (radius > 0.0, focus) {
                (false, _) => None,
                (true, Some(f)) => Some(ThinLens {
                    radius: radius as Real,
                    focus_distance: f as Real,
                }),
                (true, None) => return Err(Error::arg(
                    "--aperture",
                    "a lens radius > 0 needs --focus-distance (the distance to the plane in focus)",
                )),
            };
        }
        if let Some(d) = self.max_depth {
            if d > MAX_DEPTH {
                return Err(Error::arg(
                    "--max-depth",
                    format!("{d} is too large: use 0 to {MAX_DEPTH}"),
                ));
            }
            scene.settings.max_depth = d;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_parse_and_bad_ones_say_why() {
        assert_eq!(parse_vec3("1,-2.5, 3e2"), Ok([1.0, -2.5, 300.0]));
        assert!(parse_vec3("1,2").unwrap_err().contains("three numbers"));
        assert!(parse_vec3("1,2,x").is_err());
        assert!(parse_vec3("1,2,inf").unwrap_err().contains("non-finite"));
    }

    #[test]
    fn overrides_replace_the_camera_and_depth_and_check_them() {
        let mut s = crate::default_scene().unwrap();
        let v = ViewArgs {
            eye: Some([0.0, 1.0, 5.0]),
            look_at: Some([0.0, 1.0, 0.0]),
            fov: Some(30.0),
            max_depth: Some(2),
            ..ViewArgs::default()
        };
        v.apply(&mut s).unwrap();
        assert_eq!(s.scene.camera.eye, Vec3::new(0.0, 1.0, 5.0));
        assert_eq!(
            s.scene.camera.projection,
            Projection::Perspective { vfov_deg: 30.0 }
        );
        assert_eq!(s.scene.settings.max_depth, 2);
        let bad = |v: ViewArgs| v.apply(&mut s.clone()).unwrap_err().to_string();
        let same = ViewArgs {
            eye: Some([0.0, 1.0, 0.0]),
            ..ViewArgs::default()
        };
        assert!(bad(same).contains("coincide"));
        let up = ViewArgs {
            up: Some([0.0, 0.0, 1.0]),
            ..ViewArgs::default()
        };
        assert!(bad(up).contains("--up"));
        let fov = ViewArgs {
            fov: Some(180.0),
            ..ViewArgs::default()
        };
        assert!(bad(fov).contains("--fov"));
        let depth = ViewArgs {
            max_depth: Some(65),
            ..ViewArgs::default()
        };
        assert!(bad(depth).contains("--max-depth"));
        let lens = ViewArgs {
            aperture: Some(0.1),
            focus_distance: Some(4.0),
            ..ViewArgs::default()
        };
        let mut t = s.clone();
        lens.apply(&mut t).unwrap();
        assert_eq!(
            t.scene.camera.lens,
            Some(ThinLens {
                radius: 0.1,
                focus_distance: 4.0
            })
        );
        let no_focus = ViewArgs {
            aperture: Some(0.1),
            ..ViewArgs::default()
        };
        assert!(bad(no_focus).contains("--focus-distance"));
        let negative = ViewArgs {
            aperture: Some(-1.0),
            focus_distance: Some(4.0),
            ..ViewArgs::default()
        };
        assert!(bad(negative).contains("--aperture"));
        let zero_focus = ViewArgs {
            aperture: Some(0.1),
            focus_distance: Some(0.0),
            ..ViewArgs::default()
        };
        assert!(bad(zero_focus).contains("--focus-distance"));
        let named = ViewArgs {
            camera: Some("top".into()),
            ..ViewArgs::default()
        };
        assert!(bad(named.clone()).contains("has no cameras"));
        let mut top = s.scene.camera.clone();
        top.eye = Vec3::new(0.0, 9.0, 0.1);
        s.cameras = vec![("side".into(), s.scene.camera.clone()), ("top".into(), top)];
        named.apply(&mut s).unwrap();
        assert_eq!(s.scene.camera.eye, Vec3::new(0.0, 9.0, 0.1));
        s.cameras.truncate(1);
        let e = named.apply(&mut s.clone()).unwrap_err().to_string();
        assert!(e.contains("its cameras are: side"), "{e}");
    }
}
