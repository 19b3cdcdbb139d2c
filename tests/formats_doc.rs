//! `docs/FORMATS.md` explains every column the tool writes: each column of each CSV record type
//! appears there in a code span, literally (`s_star`, or in a list `dir_kappa, dir_tau, dir_omega`)
//! or through a prefix pattern (`dir_*`, `scene_*`). A column added to a record without its
//! explanation fails here.

use helixreach::records::csv_out::CsvRecord;
use helixreach::records::{
    bifurcation::BifurcationRecord, boundary::BoundaryRecord, centerline::CenterlineRecord,
    check::CheckRowRecord, compare::ComparisonRecord, detect::DetectRunRecord,
    detect::DetectSampleRecord, helix_points::HelixPointMatrixRecord,
    helix_points::HelixPointRecord, layout::AssignmentRecord, layout::CandidateRecord,
    layout::CoverageRecord, layout::PlacementRecord, layout::RayRecord, reach::ReachRecord,
    render::RenderFrameRecord, series::PhasedSeriesRecord,
};

/// The words of every code span of `doc`, split at commas and spaces.
fn code_words(doc: &str) -> Vec<String> {
    doc.split('`')
        .skip(1)
        .step_by(2)
        .flat_map(|span| span.split([',', ' ']))
        .filter(|w| !w.is_empty())
        .map(str::to_string)
        .collect()
}

#[test]
fn every_output_column_is_explained() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/FORMATS.md");
    let doc = std::fs::read_to_string(path).unwrap();
    let words = code_words(&doc);
    let explained = |col: &str| {
        words.iter().any(|w| {
            w == col
                || w.strip_suffix('*')
                    .is_some_and(|p| !p.is_empty() && col.starts_with(p))
        })
    };
    let headers: [(&str, &[&str]); 17] = [
        ("boundary", BoundaryRecord::HEADER),
        ("reach", ReachRecord::HEADER),
        ("bifurcation", BifurcationRecord::HEADER),
        ("compare", ComparisonRecord::HEADER),
        ("simulate", PhasedSeriesRecord::HEADER),
        ("simulate --centerline", CenterlineRecord::HEADER),
        ("check", CheckRowRecord::HEADER),
        ("detect samples", DetectSampleRecord::HEADER),
        ("detect --runs", DetectRunRecord::HEADER),
        ("layout rays", RayRecord::HEADER),
        ("layout candidates", CandidateRecord::HEADER),
        ("layout placements", PlacementRecord::HEADER),
        ("layout assignment", AssignmentRecord::HEADER),
        ("layout coverage", CoverageRecord::HEADER),
        ("render frames", RenderFrameRecord::HEADER),
        ("helix --points", HelixPointRecord::HEADER),
        ("helix --points --matrix", HelixPointMatrixRecord::HEADER),
    ];
    let missing: Vec<String> = headers
        .iter()
        .flat_map(|(kind, cols)| {
            cols.iter()
                .filter(|c| !explained(c))
                .map(move |c| format!("{kind}: {c}"))
        })
        .collect();
    assert!(
        missing.is_empty(),
        "columns not explained in docs/FORMATS.md: {missing:?}"
    );
}
