//! Helix end poses at given points (`helixreach helix --points FILE` on stdout): one
//! [`HelixPointRecord`] per input row (`--matrix`: [`HelixPointMatrixRecord`]), every number as
//! `{:.16e}` (17 significant digits). The pose is in the clamp frame (z the initial tangent, x
//! the initial normal), in the command line's one pose format `x,y,z,qw,qx,qy,qz` (the material
//! frame at the end); with `--matrix` the frame as `r00 … r22`, row-major; `motor_angle` is the
//! end's twist.

use super::csv_out::{self, CsvRecord};
use crate::math::Real;

/// The end pose of one helix in the command line's pose format (`x,y,z,qw,qx,qy,qz`, the
/// material frame's unit quaternion, scalar first, `qw ≥ 0`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct HelixPointRecord {
    /// κ.
    #[serde(serialize_with = "csv_out::real_e16")]
    pub kappa: Real,
    /// τ.
    #[serde(serialize_with = "csv_out::real_e16")]
    pub tau: Real,
    /// ω.
    #[serde(serialize_with = "csv_out::real_e16")]
    pub omega: Real,
    /// End position and material frame: `x, y, z` (units of the length given), `qw, qx, qy, qz`.
    #[serde(serialize_with = "e16_list")]
    pub pose: [Real; 7],
    /// Twist of the end (rad).
    #[serde(serialize_with = "csv_out::real_e16")]
    pub motor_angle: Real,
}

impl CsvRecord for HelixPointRecord {
    const HEADER: &'static [&'static str] = &[
        "kappa",
        "tau",
        "omega",
        "x",
        "y",
        "z",
        "qw",
        "qx",
        "qy",
        "qz",
        "motor_angle",
    ];
}

/// The end pose of one helix with the material frame as a matrix (`helix --matrix`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct HelixPointMatrixRecord {
    /// κ.
    #[serde(serialize_with = "csv_out::real_e16")]
    pub kappa: Real,
    /// τ.
    #[serde(serialize_with = "csv_out::real_e16")]
    pub tau: Real,
    /// ω.
    #[serde(serialize_with = "csv_out::real_e16")]
    pub omega: Real,
    /// End position `x, y, z` (units of the length given).
    #[serde(serialize_with = "e16_list")]
    pub position: [Real; 3],
    /// Material frame at the end, row-major (`r00 … r22`; columns m1, m2, t).
    #[serde(serialize_with = "e16_list")]
    pub r: [Real; 9],
    /// Twist of the end (rad).
    #[serde(serialize_with = "csv_out::real_e16")]
    pub motor_angle: Real,
}

impl CsvRecord for HelixPointMatrixRecord {
    const HEADER: &'static [&'static str] = &[
        "kappa",
        "tau",
        "omega",
        "x",
        "y",
        "z",
        "r00",
        "r01",
        "r02",
        "r10",
        "r11",
        "r12",
        "r20",
        "r21",
        "r22",
        "motor_angle",
    ];
}

fn e16_list<S: serde::Serializer>(v: &[Real], s: S) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::SerializeTuple;
    let mut t = s.serialize_tuple(v.len())?;
    for x in v {
        t.serialize_element(&format!("{x:.16e}"))?;
    }
    t.end()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv_out::{fields, CsvStream};

    /// Every field as `{:.16e}`, streamed under the header, in both shapes.
    #[test]
    fn every_field_in_e16() {
        let r = HelixPointRecord {
            kappa: 1.0,
            tau: 0.0,
            omega: -0.5,
            pose: [1.0 / 3.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0],
            motor_angle: 0.25,
        };
        let f = fields(&r).unwrap();
        assert_eq!(f.len(), HelixPointRecord::HEADER.len());
        assert_eq!(f[3], format!("{:.16e}", 1.0 / 3.0));
        assert_eq!(f[6], "1.0000000000000000e0");
        let mut s = CsvStream::new(Vec::new(), HelixPointRecord::HEADER).unwrap();
        s.write(&r).unwrap();
        let text = String::from_utf8(s.finish().unwrap()).unwrap();
        assert!(text.starts_with("kappa,tau,omega,x,y,z,qw,qx,qy,qz,motor_angle\n"));
        assert_eq!(text.lines().nth(1).unwrap(), f.join(","));
        let m = HelixPointMatrixRecord {
            kappa: 1.0,
            tau: 0.0,
            omega: -0.5,
            position: [1.0 / 3.0, 0.0, 2.0],
            r: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            motor_angle: 0.25,
        };
        let f = fields(&m).unwrap();
        assert_eq!(f.len(), HelixPointMatrixRecord::HEADER.len());
        assert_eq!(f[6], "1.0000000000000000e0");
    }
}
