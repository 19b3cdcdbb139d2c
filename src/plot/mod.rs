//! Figures (plotters, PNG and SVG) from saved records ([architecture §6](crate::architecture)).
//!
//! The plot module reads records only — rows of the CSV files the other commands write, or the
//! same rows built in memory — and never calls the solvers. One file per figure kind:
//!
//! | figure | function | records |
//! |---|---|---|
//! | stability boundary surface in κ-τ-ω (3-D projection) | [`boundary3d::render`] | [`BoundaryRow`] |
//! | equal-area map of search directions by class and cause | [`direction_map::render`] | [`ReachRow`] (+ marked [`Direction`]s) |
//! | the ω = 0 section, boundary curve with the reachable part | [`section::render`] | [`BoundaryRow`] (+ [`ReachRow`]) |
//! | helix error e versus ‖S‖ (DER dynamics) | [`error_vs_s::render`] | [`Series`] |
//! | snap detection of a recorded run: e versus s, loading and unloading, s*, snap, return | [`detection::render`] | [`records::detect::SamplePoint`] |
//! | speed versus error of boundary methods (log-log) | [`speed_error::render`] | [`SpeedErrorRow`] |
//! | bifurcation type over the directions, with the hysteresis width and labelled runs | [`bifurcation_map::render`] | [`bifurcation_map::BifurcationRow`] |
//! | measured snap points (and mirror images) on the boundary: views along each axis, ω = 0 section | [`comparison::render`] | [`BoundaryRow`] + measured points |
//! | joint and motor angles versus s, with joint limits | [`trajectory::render`] | [`TrajectoryRow`] (+ [`JointLimit`]) |
//! | robot, rod and scene along a trajectory: strip, GIF (poses the robot model; see its docs) | [`render::render_trajectory`] | trajectory CSV + rig |
//! | rig layout: coverage heat map over the bench | [`layout_heatmap::render`] | [`layout_heatmap::Heatmap`] |
//! | rig layout: directions by placement | [`layout_directions::render`] | directions + placement |
//! | a campaign's sessions: runs by placement, moves between them | [`campaign_timeline::render`] | [`campaign_timeline::Bar`] |
//! | rig layout: coverage versus K | [`layout_coverage::render`] | [`layout_coverage::Point`] |
//!
//! The output format follows the file extension (`.png` or `.svg`, case-insensitive); anything
//! else is an [`Error::InvalidParameter`] naming the path. Files are written atomically (temp file
//! in the same directory, then rename). Text uses the embedded DejaVu Sans (see [`style`]), so
//! rendering needs no system fonts.
//!
//! ```
//! use helixreach::plot::{speed_error, SpeedErrorRow};
//! let rows = vec![SpeedErrorRow {
//!     method: "continuum".into(), resolution: "tol=1e-8".into(),
//!     time_per_direction_s: 2e-5, max_rel_err: 1e-9, median_rel_err: 1e-10,
//! }];
//! let out = std::env::temp_dir().join("helixreach-doc-speed.svg");
//! speed_error::render(&rows, &out).unwrap();
//! let svg = std::fs::read_to_string(&out).unwrap();
//! assert!(svg.contains("time per direction"));
//! ```
//!
//! [`Direction`]: crate::directions::Direction

pub mod bifurcation_map;
pub mod boundary3d;
pub mod campaign_timeline;
pub mod comparison;
pub mod detection;
pub mod direction_map;
pub mod error_vs_s;
pub mod layout_coverage;
pub mod layout_directions;
pub mod layout_heatmap;
/// The records (rows) figures are drawn from: [`crate::records`].
pub use crate::records;
pub mod render;
pub mod section;
pub mod speed_error;
pub mod style;
pub mod trajectory;

pub use records::{
    read_boundary, read_joint_limits, read_reach, read_series, read_speed_error, read_trajectory,
    BlockCause, BoundaryRow, JointLimit, ReachClass, ReachRow, Series, SeriesRow, SpeedErrorRow,
    TrajectoryRow,
};

use crate::error::{Error, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Output format of a figure, chosen by the file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Raster PNG (bitmap backend).
    Png,
    /// Vector SVG (text kept as `<text>` elements).
    Svg,
}

impl Format {
    /// The format of `path` from its extension (`png` or `svg`, any case).
    ///
    /// ```
    /// use helixreach::plot::Format;
    /// use std::path::Path;
    /// assert_eq!(Format::from_path(Path::new("a/b.SVG")).unwrap(), Format::Svg);
    /// assert!(Format::from_path(Path::new("b.pdf")).is_err());
    /// ```
    pub fn from_path(path: &Path) -> Result<Format> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("svg") => Ok(Format::Svg),
            _ => Err(Error::invalid(
                "out",
                path.display(),
                "the figure file must end in .png or .svg",
            )),
        }
    }
}

/// Result of drawing on a backend.
pub(crate) type DrawResult<DB> =
    std::result::Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// The house legend: a white, grey-bordered box of the series labels at `pos`.
pub(crate) fn draw_legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    pos: SeriesLabelPosition,
) -> DrawResult<DB>
where
    DB: DrawingBackend + 'a,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(pos)
        .label_font((style::FAMILY, style::LEGEND))
        .background_style(WHITE.mix(0.9))
        .border_style(style::GREY)
        .margin(12)
        .draw()
}

/// The house axes of a linear chart: axis titles, tick labels by [`style::fmt_tick`], light grey
/// major grid, no minor grid.
pub(crate) fn draw_axes<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    x_desc: &str,
    y_desc: &str,
) -> DrawResult<DB> {
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .axis_desc_style((style::FAMILY, style::AXIS))
        .label_style((style::FAMILY, style::TICK))
        .x_label_formatter(&style::fmt_tick)
        .y_label_formatter(&style::fmt_tick)
        .bold_line_style(style::LIGHT_GREY)
        .light_line_style(TRANSPARENT)
        .draw()
}

/// A figure ready to draw: validated data and layout, independent of the backend.
pub(crate) trait Figure {
    /// Size in pixels (width, height).
    fn size(&self) -> (u32, u32);
    /// Draw on a white root area of [`Figure::size`].
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB>;
}

/// Render `fig` into `out` (format by extension), atomically.
pub(crate) fn save<F: Figure>(fig: &F, out: &Path) -> Result<()> {
    let format = Format::from_path(out)?;
    style::init_fonts();
    let draw_err = |e: String| Error::File {
        path: out.to_path_buf(),
        reason: format!("drawing the figure failed: {e}"),
    };
    match format {
        Format::Svg => {
            let mut text = String::new();
            {
                let root = SVGBackend::with_string(&mut text, fig.size()).into_drawing_area();
                root.fill(&WHITE).map_err(|e| draw_err(e.to_string()))?;
                fig.draw(&root).map_err(|e| draw_err(e.to_string()))?;
                root.present().map_err(|e| draw_err(e.to_string()))?;
            }
            crate::io::write_atomic(out, text.as_bytes())
        }
        Format::Png => {
            // Drawn into memory and encoded here; the one writer puts the bytes in place.
            let (w, h) = fig.size();
            let mut rgb = vec![0u8; w as usize * h as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
                root.fill(&WHITE).map_err(|e| draw_err(e.to_string()))?;
                fig.draw(&root).map_err(|e| draw_err(e.to_string()))?;
                root.present().map_err(|e| draw_err(e.to_string()))?;
            }
            let bytes = encode_png(&rgb, w, h).map_err(|e| draw_err(e.to_string()))?;
            crate::io::write_atomic(out, &bytes)
        }
    }
}

/// PNG bytes of an RGB buffer (row-major, 3 bytes per pixel).
pub(crate) fn encode_png(
    rgb: &[u8],
    w: u32,
    h: u32,
) -> std::result::Result<Vec<u8>, png::EncodingError> {
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header()?;
        writer.write_image_data(rgb)?;
    }
    Ok(bytes)
}
