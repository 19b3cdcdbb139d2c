//! The frames of a trajectory rendering (`render_frames.csv` next to `render_strip.png`, written
//! by `plot::render::render_trajectory`): one [`RenderFrameRecord`] per drawn frame with the
//! smallest clearance of each kind (self, scene, rod–arm: distance in metres and the two bodies),
//! empty when the frame has no pair of that kind.

use super::csv_out::{self, CsvRecord};
use crate::math::Real;

/// The smallest clearance of one kind at a frame.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ClearanceFields {
    /// Distance (m; 0 when touching or overlapping).
    #[serde(serialize_with = "csv_out::real")]
    pub m: Real,
    /// The first body.
    pub a: String,
    /// The second body.
    pub b: String,
}

/// Field adapter: a clearance as its three fields, or three empty fields.
fn clearance<S: serde::Serializer>(
    c: &Option<ClearanceFields>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde::Serialize;
    match c {
        Some(c) => c.serialize(s),
        None => ("", "", "").serialize(s),
    }
}

/// One drawn frame.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RenderFrameRecord {
    /// Frame number, 1-based, in strip order.
    pub frame: usize,
    /// Row index in the trajectory (0-based).
    pub row: usize,
    /// Line of the row in the trajectory file.
    pub line: usize,
    /// Time (s).
    #[serde(serialize_with = "csv_out::real")]
    pub t: Real,
    /// Distance along the ray.
    #[serde(serialize_with = "csv_out::real")]
    pub s: Real,
    /// Phase (`load`, …), empty when the file has none.
    pub phase: &'static str,
    /// The frame's caption.
    pub label: String,
    /// Arm against arm (`self_m,self_a,self_b`).
    #[serde(serialize_with = "clearance")]
    pub self_collision: Option<ClearanceFields>,
    /// Arm against a scene obstacle (`scene_m,scene_a,scene_b`).
    #[serde(serialize_with = "clearance")]
    pub scene: Option<ClearanceFields>,
    /// Rod against arm (`rod_arm_m,rod_arm_a,rod_arm_b`).
    #[serde(serialize_with = "clearance")]
    pub rod_arm: Option<ClearanceFields>,
}

impl CsvRecord for RenderFrameRecord {
    const HEADER: &'static [&'static str] = &[
        "frame",
        "row",
        "line",
        "t",
        "s",
        "phase",
        "label",
        "self_m",
        "self_a",
        "self_b",
        "scene_m",
        "scene_a",
        "scene_b",
        "rod_arm_m",
        "rod_arm_a",
        "rod_arm_b",
    ];
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv_out::{fields, to_csv};

    /// A missing clearance is three empty fields, a present one three; a caption with a comma is
    /// quoted and reads back whole.
    #[test]
    fn clearance_groups_are_three_fields_each() {
        let r = RenderFrameRecord {
            frame: 1,
            row: 0,
            line: 2,
            t: 0.0,
            s: 0.0,
            phase: "load",
            label: "s = 0, start".into(),
            self_collision: Some(ClearanceFields {
                m: 0.125,
                a: "right_l1".into(),
                b: "right_l4".into(),
            }),
            scene: None,
            rod_arm: Some(ClearanceFields {
                m: 0.0,
                a: "rod s=0.9".into(),
                b: "right_hand".into(),
            }),
        };
        let f = fields(&r).unwrap();
        assert_eq!(f.len(), RenderFrameRecord::HEADER.len());
        assert_eq!(
            &f[6..],
            [
                "s = 0, start",
                "0.125",
                "right_l1",
                "right_l4",
                "",
                "",
                "",
                "0",
                "rod s=0.9",
                "right_hand"
            ]
        );
        let text = to_csv(&[r]).unwrap();
        assert!(text.contains(",\"s = 0, start\","), "{text}");
    }

    /// The clearance columns follow the renderer's kinds, in its order and with its names.
    #[cfg(feature = "plots")]
    #[test]
    fn clearance_columns_follow_the_kinds() {
        use crate::plot::render::scene::ClearanceKind;
        for (j, k) in ClearanceKind::ALL.iter().enumerate() {
            let n = k.as_str().replace('-', "_");
            for (i, suffix) in ["m", "a", "b"].iter().enumerate() {
                assert_eq!(
                    RenderFrameRecord::HEADER[7 + 3 * j + i],
                    format!("{n}_{suffix}")
                );
            }
        }
    }
}
