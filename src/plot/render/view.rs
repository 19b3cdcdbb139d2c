//! Orthographic views: a right-handed screen basis `(right, up, toward)` in the robot base frame.
//!
//! A point `p` (base frame, metres) projects to the screen coordinates `(right·p, up·p)` (metres)
//! and has depth `toward·p` (larger = nearer the viewer). `right × up = toward` for every view.
//!
//! | view | viewer at | screen right | screen up |
//! |---|---|---|---|
//! | `front` | −y (beside the arm, sees it reach out along x) | +x | +z |
//! | `side` | +x (in front of the robot, behind the clamp) | +y | +z |
//! | `top` | +z | +x | +y |
//! | `iso` | direction (1, −1, 1)/√3 | (1, 1, 0)/√2 | z made orthogonal to the view direction |
//!
//! The three axis-aligned views label their axes with world coordinates; the `iso` view has no
//! world coordinate per screen axis and is drawn with a scale bar and an axis triad instead.

use crate::error::{Error, Result};
use crate::math::{Real, Vec3};

/// One orthographic view (see the module docs for the bases).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// Viewer at −y: screen (x, z).
    Front,
    /// Viewer at +x: screen (y, z).
    Side,
    /// Viewer at +z: screen (x, y).
    Top,
    /// Viewer along (1, −1, 1)/√3.
    Iso,
}

impl View {
    /// Every view, in the default strip order.
    pub const ALL: [View; 4] = [View::Front, View::Side, View::Top, View::Iso];

    /// The view's name (`front`, `side`, `top`, `iso`).
    pub fn as_str(&self) -> &'static str {
        match self {
            View::Front => "front",
            View::Side => "side",
            View::Top => "top",
            View::Iso => "iso",
        }
    }

    /// Parse one view name.
    pub fn parse(s: &str) -> Result<View> {
        match s.trim().to_ascii_lowercase().as_str() {
            "front" => Ok(View::Front),
            "side" => Ok(View::Side),
            "top" => Ok(View::Top),
            "iso" => Ok(View::Iso),
            other => Err(Error::invalid(
                "views",
                format!("`{other}`"),
                "each view must be one of front, side, top, iso",
            )),
        }
    }

    /// Parse a comma-separated list (`front,iso`): at least one view, no repeats.
    ///
    /// ```
    /// use helixreach::plot::render::View;
    /// assert_eq!(View::parse_list("front, iso").unwrap(), vec![View::Front, View::Iso]);
    /// assert!(View::parse_list("front,front").is_err());
    /// assert!(View::parse_list("back").unwrap_err().to_string().contains("back"));
    /// ```
    pub fn parse_list(s: &str) -> Result<Vec<View>> {
        let mut out = Vec::new();
        for part in s.split(',').filter(|p| !p.trim().is_empty()) {
            let v = View::parse(part)?;
            if out.contains(&v) {
                return Err(Error::invalid(
                    "views",
                    s,
                    format!("`{}` is listed twice", v.as_str()),
                ));
            }
            out.push(v);
        }
        if out.is_empty() {
            return Err(Error::invalid(
                "views",
                format!("`{s}`"),
                "name at least one view",
            ));
        }
        Ok(out)
    }

    /// The screen basis `(right, up, toward)` (unit, orthonormal, `right × up = toward`).
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        match self {
            View::Front => (Vec3::x(), Vec3::z(), -Vec3::y()),
            View::Side => (Vec3::y(), Vec3::z(), Vec3::x()),
            View::Top => (Vec3::x(), Vec3::y(), Vec3::z()),
            View::Iso => {
                let toward = Vec3::new(1.0, -1.0, 1.0).normalize();
                let up = (Vec3::z() - toward * toward.z).normalize();
                (up.cross(&toward), up, toward)
            }
        }
    }

    /// Screen coordinates `(right·p, up·p)` of `p` (metres).
    ///
    /// ```
    /// use helixreach::plot::render::View;
    /// use helixreach::math::Vec3;
    /// let p = Vec3::new(1.0, 2.0, 3.0);
    /// assert_eq!(View::Front.project(&p), [1.0, 3.0]);
    /// assert_eq!(View::Side.project(&p), [2.0, 3.0]);
    /// assert_eq!(View::Top.project(&p), [1.0, 2.0]);
    /// ```
    #[inline]
    pub fn project(&self, p: &Vec3) -> [Real; 2] {
        let (r, u, _) = self.basis();
        [r.dot(p), u.dot(p)]
    }

    /// Depth of `p` toward the viewer (m; larger = nearer).
    #[inline]
    pub fn depth(&self, p: &Vec3) -> Real {
        self.basis().2.dot(p)
    }

    /// World axis names of the screen axes (`None` for `iso`).
    pub fn axis_names(&self) -> Option<(&'static str, &'static str)> {
        match self {
            View::Front => Some(("x", "z")),
            View::Side => Some(("y", "z")),
            View::Top => Some(("x", "y")),
            View::Iso => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bases_are_right_handed_orthonormal() {
        for v in View::ALL {
            let (r, u, t) = v.basis();
            assert!((r.norm() - 1.0).abs() < 1e-15 && (u.norm() - 1.0).abs() < 1e-15);
            assert!(r.dot(&u).abs() < 1e-15);
            assert!((r.cross(&u) - t).norm() < 1e-15, "{v:?}");
        }
        let (r, _, _) = View::Iso.basis();
        assert!((r - Vec3::new(1.0, 1.0, 0.0).normalize()).norm() < 1e-15);
    }
}
