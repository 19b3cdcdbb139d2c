//! Helix end poses at given points (`helixreach helix --points FILE` on stdout): one
//! [`HelixPointRecord`] per input row, every number as `{:.16e}` (17 significant digits).
//! The pose is in the clamp frame (z the initial tangent, x the initial normal); `r` is the
//! material frame at the end, row-major; `motor_angle` the end's twist.

use super::csv_out::{self, CsvRecord};
use crate::math::Real;

/// The end pose of one helix.
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
    /// End position x (units of the length given).
    #[serde(serialize_with = "csv_out::real_e16")]
    pub px: Real,
    /// End position y.
    #[serde(serialize_with = "csv_out::real_e16")]
    pub py: Real,
    /// End position z.
    #[serde(serialize_with = "csv_out::real_e16")]
    pub pz: Real,
    /// Material frame at the end, row-major (`r00 … r22`).
    #[serde(serialize_with = "rows_e16")]
    pub r: [[Real; 3]; 3],
    /// Twist of the end (rad).
    #[serde(serialize_with = "csv_out::real_e16")]
    pub motor_angle: Real,
}

fn rows_e16<S: serde::Serializer>(
    r: &[[Real; 3]; 3],
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::SerializeTuple;
    let mut t = s.serialize_tuple(9)?;
    for x in r.iter().flatten() {
        t.serialize_element(&format!("{x:.16e}"))?;
    }
    t.end()
}

impl CsvRecord for HelixPointRecord {
    const HEADER: &'static [&'static str] = &[
        "kappa",
        "tau",
        "omega",
        "px",
        "py",
        "pz",
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv_out::{fields, CsvStream};

    /// Sixteen fields as `{:.16e}`, streamed under the header.
    #[test]
    fn sixteen_fields_in_e16() {
        let r = HelixPointRecord {
            kappa: 1.0,
            tau: 0.0,
            omega: -0.5,
            px: 1.0 / 3.0,
            py: 0.0,
            pz: 2.0,
            r: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            motor_angle: 0.25,
        };
        let f = fields(&r).unwrap();
        assert_eq!(f.len(), HelixPointRecord::HEADER.len());
        assert_eq!(f[3], format!("{:.16e}", 1.0 / 3.0));
        assert_eq!(f[6], "1.0000000000000000e0");
        let mut s = CsvStream::new(Vec::new(), HelixPointRecord::HEADER).unwrap();
        s.write(&r).unwrap();
        let text = String::from_utf8(s.finish().unwrap()).unwrap();
        assert!(text.starts_with("kappa,tau,omega,px,py,pz,r00,"));
        assert_eq!(text.lines().nth(1).unwrap(), f.join(","));
    }
}
