//! Snapshots of the experiment before it runs: the robot's collision capsules, the motor, the
//! rod's exact helix, the clamp and the scene, in orthographic views along a planned trajectory,
//! with the smallest clearances (self, scene, rod–arm) named and drawn.
//!
//! Unlike the other figures of [`crate::plot`], this one poses a model: forward kinematics of
//! the rig's robot and the collision model's distance queries (and, for the default frame
//! choice, the continuum s* of the trajectory's direction).
//!
//! | item | what |
//! |---|---|
//! | [`Scene`] | a rig ready to draw (robot model, collision model, obstacles, clamp) |
//! | [`Scene::snapshot`] | one [`Configuration`] (joints, helix, azimuth) posed: bodies, rod, clearances |
//! | [`render_scene`] | one snapshot, its views side by side (PNG or SVG) — e.g. a rig placement |
//! | [`render_strip`] | several snapshots as columns, views stacked, common scale (PNG or SVG) |
//! | [`render_gif`] | an animated GIF, one frame per snapshot, steady camera |
//! | [`render_trajectory`] | trajectory CSV + rig → strip (PNG, SVG), GIF, per-frame clearance CSV |
//! | [`view`] | the orthographic views and their bases |
//! | [`input`] | reading and checking the trajectory CSV, choosing frames |
//! | [`draw`] | layout (one world → pixel map, [`Layout::pixel`]) and drawing |
//! | [`palette`] | a frame's colours reduced to a GIF palette |
//!
//! # GIF
//! Frames are drawn into RGB buffers on the bitmap backend, reduced to a ≤ 256-colour palette
//! ([`palette::reduce`]: the most frequent colours, exact — the frames are flat fills) and
//! LZW-compressed in parallel, in chunks, then written in order with the `gif` crate (the crate
//! plotters' own `gif_backend` is built on) to a temp file renamed over the target when complete.
//! plotters' `gif_backend` draws, quantizes (NeuQuant, ≈ 25× the time of the rest of a frame
//! here) and writes sequentially, straight to the target path, so it is not used.
//!
//! ```
//! use helixreach::plot::render::{render_scene, Configuration, RenderOptions, Scene, View};
//! let rig = helixreach::planning::rig::Rig::load("sawyer-seed").unwrap();
//! let scene = Scene::new(&rig).unwrap();
//! let q = vec![-0.857, -0.873, -1.819, -0.034, 1.860, 2.434, -2.200];
//! let snap = scene.snapshot(&Configuration { q, kto: [2.0, 3.0, 0.0], azimuth: 0.0 }).unwrap();
//! let out = std::env::temp_dir().join("helixreach-doc-render.svg");
//! let opts = RenderOptions { views: vec![View::Front, View::Iso], ..Default::default() };
//! render_scene(&scene, &snap, &opts, &out).unwrap();
//! assert!(std::fs::read_to_string(&out).unwrap().contains("rod-arm"));
//! ```

pub mod draw;
pub mod input;
pub mod palette;
pub mod scene;
pub mod view;

pub use draw::{Arrangement, Layout, RenderOptions};
pub use input::{FrameChoice, FrameSelection, Phase, Row};
pub use scene::{
    closest_points, Body, Clearance, ClearanceKind, Configuration, Part, Scene, Snapshot, Solid,
};
pub use view::View;

use crate::error::{Error, Result};
use crate::math::Real;
use crate::par::Par;
use crate::planning::rig::Rig;
use crate::plot::{DrawResult, Figure};
use crate::records::render::{ClearanceFields, RenderFrameRecord};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::io::Write as _;
use std::path::{Path, PathBuf};

struct Sheet<'a> {
    scene: &'a Scene,
    snaps: &'a [Snapshot],
    layout: Layout,
    opts: &'a RenderOptions,
}

impl Figure for Sheet<'_> {
    fn size(&self) -> (u32, u32) {
        self.layout.size()
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        draw::draw_sheet(root, self.scene, self.snaps, &self.layout, self.opts)
    }
}

/// Draw one snapshot, its views side by side, into `out` (`.png` or `.svg`, atomically).
pub fn render_scene(
    scene: &Scene,
    snap: &Snapshot,
    opts: &RenderOptions,
    out: &Path,
) -> Result<()> {
    let snaps = std::slice::from_ref(snap);
    let layout = Layout::new(snaps, opts, Arrangement::Row)?;
    crate::plot::save(
        &Sheet {
            scene,
            snaps,
            layout,
            opts,
        },
        out,
    )
}

/// Draw snapshots as a strip (one column per snapshot, the views stacked, common scale) into
/// `out` (`.png` or `.svg`, atomically). At most [`input::MAX_STRIP_FRAMES`] snapshots.
pub fn render_strip(
    scene: &Scene,
    snaps: &[Snapshot],
    opts: &RenderOptions,
    out: &Path,
) -> Result<()> {
    if snaps.len() > input::MAX_STRIP_FRAMES {
        return Err(Error::invalid(
            "frames",
            snaps.len(),
            format!("a strip holds at most {} frames", input::MAX_STRIP_FRAMES),
        ));
    }
    let layout = Layout::new(snaps, opts, Arrangement::Strip)?;
    crate::plot::save(
        &Sheet {
            scene,
            snaps,
            layout,
            opts,
        },
        out,
    )
}

/// Draw `snap` with `layout` (normally [`Arrangement::Row`]) into an RGB buffer of
/// [`Layout::size`] (row-major, 3 bytes per pixel): one GIF frame before quantization.
pub fn render_rgb(
    scene: &Scene,
    snap: &Snapshot,
    layout: &Layout,
    opts: &RenderOptions,
) -> Result<Vec<u8>> {
    crate::plot::style::init_fonts();
    let (w, h) = layout.size();
    let mut buf = vec![255u8; w as usize * h as usize * 3];
    let drawn = (|| {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        draw::draw_sheet(&root, scene, std::slice::from_ref(snap), layout, opts)
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())
    })();
    drawn.map_err(|e| Error::invalid("frame", "", format!("drawing failed: {e}")))?;
    Ok(buf)
}

/// Frames per parallel chunk of [`render_gif`] (bounds the memory held at once).
const GIF_CHUNK: usize = 8;

/// Write an animated GIF (looping), one frame per snapshot (views side by side, one steady
/// scale and centre for all frames), `delay_ms` per frame, into `out` (atomically). Progress
/// every tenth of the frames on stderr when `progress`. At most [`input::MAX_GIF_FRAMES`].
/// Frames are drawn in parallel on `par`, written in order.
pub fn render_gif(
    par: Par,
    scene: &Scene,
    snaps: &[Snapshot],
    opts: &RenderOptions,
    delay_ms: u32,
    out: &Path,
    progress: bool,
) -> Result<()> {
    if snaps.is_empty() || snaps.len() > input::MAX_GIF_FRAMES {
        return Err(Error::invalid(
            "gif frames",
            snaps.len(),
            format!("must be between 1 and {}", input::MAX_GIF_FRAMES),
        ));
    }
    if !(10..=10_000).contains(&delay_ms) {
        return Err(Error::invalid(
            "gif delay (ms)",
            delay_ms,
            "must be between 10 and 10000",
        ));
    }
    crate::plot::style::init_fonts();
    let layout = Layout::new(snaps, opts, Arrangement::Row)?;
    let (w, h) = layout.size();
    if w > u16::MAX as u32 || h > u16::MAX as u32 {
        return Err(Error::invalid(
            "gif size",
            format!("{w}×{h}"),
            "must fit 65535 px",
        ));
    }
    let io = |source| Error::Io {
        path: out.to_path_buf(),
        source,
    };
    let enc_err = |e: gif::EncodingError| Error::File {
        path: out.to_path_buf(),
        reason: format!("GIF encoding failed: {e}"),
    };
    // Encoded into memory; the one writer puts the bytes in place.
    let mut bytes = Vec::new();
    let result = (|| -> Result<()> {
        let mut enc = gif::Encoder::new(&mut bytes, w as u16, h as u16, &[]).map_err(enc_err)?;
        enc.set_repeat(gif::Repeat::Infinite).map_err(enc_err)?;
        let delay = (delay_ms as Real / 10.0).round() as u16;
        let mut done = 0;
        for chunk in snaps.chunks(GIF_CHUNK) {
            let frames: Vec<Result<gif::Frame<'static>>> = par.map(chunk, |s| {
                let rgb = render_rgb(scene, s, &layout, opts)?;
                let (pal, idx) = palette::reduce(&rgb);
                let mut f = gif::Frame::from_palette_pixels(w as u16, h as u16, idx, pal, None);
                f.delay = delay;
                // LZW-compress here, in parallel; the writer only copies the bytes.
                f.make_lzw_pre_encoded();
                Ok(f)
            })?;
            for f in frames {
                let f = f.map_err(|e| Error::File {
                    path: out.to_path_buf(),
                    reason: e.to_string(),
                })?;
                enc.write_lzw_pre_encoded_frame(&f).map_err(enc_err)?;
                done += 1;
                if progress && (done % (snaps.len() / 10).max(1) == 0 || done == snaps.len()) {
                    eprintln!("render: GIF frame {done}/{}", snaps.len());
                }
            }
        }
        let inner = enc.into_inner().map_err(io)?;
        inner.flush().map_err(io)?;
        Ok(())
    })();
    result?;
    crate::io::write_atomic(out, &bytes)
}

/// What [`render_trajectory`] draws and writes.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryRender {
    /// Frames of the strip.
    pub frames: FrameSelection,
    /// Drawing options of the strip (the title is filled in when empty).
    pub strip: RenderOptions,
    /// Frames of the GIF (evenly in time); `None` = no GIF.
    pub gif_frames: Option<usize>,
    /// Drawing options of the GIF frames.
    pub gif: RenderOptions,
    /// GIF frame delay (ms).
    pub gif_delay_ms: u32,
    /// Azimuth when the trajectory neither has an `azimuth` column nor rod ends to recover it.
    pub azimuth: Real,
    /// Progress on stderr.
    pub progress: bool,
    /// The parallelism of the snapshots and the GIF frames.
    pub par: Par,
}

impl Default for TrajectoryRender {
    fn default() -> Self {
        TrajectoryRender {
            frames: FrameSelection::Default { s_star: None },
            strip: RenderOptions::default(),
            gif_frames: None,
            gif: RenderOptions {
                panel: (330, 320),
                ..RenderOptions::default()
            },
            gif_delay_ms: 100,
            azimuth: 0.0,
            progress: false,
            par: Par::all(),
        }
    }
}

/// What [`render_trajectory`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSummary {
    /// The strip (PNG).
    pub strip_png: PathBuf,
    /// The strip (SVG).
    pub strip_svg: PathBuf,
    /// Per-frame clearances (CSV).
    pub frames_csv: PathBuf,
    /// The GIF, when asked.
    pub gif: Option<PathBuf>,
    /// The frames of the strip.
    pub frames: Vec<FrameChoice>,
    /// The azimuth used (rad).
    pub azimuth: Real,
    /// Smallest clearance of each kind over the strip's frames (m), in [`ClearanceKind::ALL`]
    /// order (`None` when nothing of that kind is checked).
    pub min_clearance: [Option<Real>; 3],
}

/// The snapshot of row `r`, titled.
fn row_snapshot(
    scene: &Scene,
    rows: &[Row],
    i: usize,
    azimuth: Real,
    label: &str,
) -> Result<Snapshot> {
    let r = &rows[i];
    let mut snap = scene.snapshot(&Configuration {
        q: r.q.clone(),
        kto: r.kto,
        azimuth,
    })?;
    let phase = r
        .phase
        .map_or(String::new(), |p| format!(", {}", p.as_str()));
    snap.title = vec![
        label.to_string(),
        format!("line {}: t = {:.1} s, s = {:.3}{phase}", r.line, r.t, r.s),
        format!(
            "κ, τ, ω = {:.2}, {:.2}, {:.2}",
            r.kto[0], r.kto[1], r.kto[2]
        ),
    ];
    Ok(snap)
}

/// Trajectory CSV + rig → `out_dir/render_strip.png`, `render_strip.svg`, `render_frames.csv`
/// and (when asked) `render.gif`. The trajectory is read and checked against the rig (see
/// [`input`]); every file is written atomically.
pub fn render_trajectory(
    rig: &Rig,
    trajectory: &Path,
    opts: &TrajectoryRender,
    out_dir: &Path,
) -> Result<RenderSummary> {
    let scene = Scene::new(rig)?;
    let names: Vec<String> = scene
        .model()
        .joints()
        .iter()
        .map(|j| j.name.clone())
        .collect();
    let robot = format!(
        "{} ({} → {})",
        scene.model().name(),
        scene.model().root_link(),
        scene.model().tip_link()
    );
    let rows = input::read_trajectory(trajectory, &names, &robot)?;
    if let Some(n) = opts.gif_frames {
        if n == 0 || n > input::MAX_GIF_FRAMES {
            return Err(Error::invalid(
                "gif frames",
                n,
                format!("must be between 1 and {}", input::MAX_GIF_FRAMES),
            ));
        }
    }
    let azimuth = input::resolve_azimuth(&scene, &rows, opts.azimuth)?;
    input::check_rows(&scene, &rows, azimuth, trajectory)?;
    let frames = input::select_frames(&rows, opts.frames)?;
    let numbered: Vec<(usize, &input::FrameChoice)> = frames.iter().enumerate().collect();
    let snaps = opts
        .par
        .map(&numbered, |&(k, f)| {
            row_snapshot(
                &scene,
                &rows,
                f.row,
                azimuth,
                &format!("#{} {}", k + 1, f.label),
            )
        })?
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
    let mut strip_opts = opts.strip.clone();
    if strip_opts.title.is_empty() {
        strip_opts.title = format!(
            "{} on rig {}: {} frames, azimuth {:.3} rad",
            trajectory.file_name().unwrap_or_default().to_string_lossy(),
            rig.name,
            snaps.len(),
            // Rounded so round-off never prints as "-0.000".
            (azimuth * 1e3).round() / 1e3 + 0.0
        );
    }
    std::fs::create_dir_all(out_dir).map_err(|source| Error::Io {
        path: out_dir.to_path_buf(),
        source,
    })?;
    let strip_png = out_dir.join("render_strip.png");
    let strip_svg = out_dir.join("render_strip.svg");
    render_strip(&scene, &snaps, &strip_opts, &strip_png)?;
    render_strip(&scene, &snaps, &strip_opts, &strip_svg)?;

    // Per-frame clearances.
    let mut records = Vec::with_capacity(frames.len());
    let mut min_clearance = [None; 3];
    for (k, (f, s)) in frames.iter().zip(&snaps).enumerate() {
        let r = &rows[f.row];
        let mut by_kind = ClearanceKind::ALL.iter().enumerate().map(|(j, kind)| {
            s.clearance(*kind).map(|c| {
                min_clearance[j] =
                    Some(min_clearance[j].map_or(c.distance, |m: Real| m.min(c.distance)));
                ClearanceFields {
                    m: c.distance,
                    a: c.a.clone(),
                    b: c.b.clone(),
                }
            })
        });
        records.push(RenderFrameRecord {
            frame: k + 1,
            row: f.row,
            line: r.line,
            t: r.t,
            s: r.s,
            phase: r.phase.map_or("", |p| p.as_str()),
            label: f.label.clone(),
            self_collision: by_kind.next().flatten(),
            scene: by_kind.next().flatten(),
            rod_arm: by_kind.next().flatten(),
        });
    }
    let csv = crate::records::csv_out::to_csv(&records)?;
    let frames_csv = out_dir.join("render_frames.csv");
    crate::io::write_atomic(&frames_csv, csv.as_bytes())?;

    let gif = match opts.gif_frames {
        Some(n) => {
            let idx = input::even_rows(&rows, n);
            let snaps = opts
                .par
                .map(&idx, |&i| {
                    let r = &rows[i];
                    row_snapshot(&scene, &rows, i, azimuth, &format!("t = {:.1} s", r.t))
                })?
                .into_iter()
                .collect::<Result<Vec<_>>>()?;
            let mut gif_opts = opts.gif.clone();
            if gif_opts.title.is_empty() {
                gif_opts.title = strip_opts.title.replace(
                    &format!("{} frames", frames.len()),
                    &format!("{} frames", snaps.len()),
                );
            }
            let path = out_dir.join("render.gif");
            render_gif(
                opts.par,
                &scene,
                &snaps,
                &gif_opts,
                opts.gif_delay_ms,
                &path,
                opts.progress,
            )?;
            Some(path)
        }
        None => None,
    };
    Ok(RenderSummary {
        strip_png,
        strip_svg,
        frames_csv,
        gif,
        frames,
        azimuth,
        min_clearance,
    })
}
