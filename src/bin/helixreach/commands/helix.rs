//! `helixreach helix`: the end pose of the rod for one helix (JSON), or for every row of a CSV
//! (CSV, 17 significant digits), in the command line's one pose format `x,y,z,qw,qx,qy,qz`
//! (`--matrix`: the frames as rotation matrices). Thin glue over [`helixreach::helix`].

use anyhow::Context;
use helixreach::helix::{twist_ratio, EndPose, Helix, DEFAULT_NU};
use helixreach::math::Real;
use helixreach::records::csv_out::{CsvRecord, CsvStream};
use helixreach::records::helix_points::{HelixPointMatrixRecord, HelixPointRecord};
use helixreach::robot::{pose_to_xyz_wxyz, Frame};
use helixreach::Error;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Arguments of `helixreach helix`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach helix --kappa 2 --tau 1 --omega 0.5",
    "$ printf 'kappa,tau,omega\\n1,0,0\\n2,1,0.5\\n' > points.csv",
    "$ helixreach helix --points points.csv",
    "$ helixreach helix --points points.csv --matrix"
))]
#[command(group(clap::ArgGroup::new("input").required(true).args(["kappa", "points"])))]
pub struct Args {
    /// Curvature κ ≥ 0 (nondimensional, L = 1).
    #[arg(long, allow_negative_numbers = true, requires_all = ["tau", "omega"])]
    kappa: Option<Real>,
    /// Torsion τ (nondimensional).
    #[arg(long, allow_negative_numbers = true, requires = "kappa")]
    tau: Option<Real>,
    /// Twisting moment ω (nondimensional).
    #[arg(long, allow_negative_numbers = true, requires = "kappa")]
    omega: Option<Real>,
    /// Poisson's ratio ν ∈ (−1, 0.5]; the motor angle is ω/c with c = 1/(1+ν).
    #[arg(long, default_value_t = DEFAULT_NU, allow_negative_numbers = true)]
    nu: Real,
    /// Rod length L (> 0); positions come out in its unit.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    length: Real,
    /// CSV file with header `kappa,tau,omega` (other columns ignored): one end pose per row,
    /// written as CSV to stdout.
    #[arg(long, conflicts_with_all = ["kappa", "tau", "omega"])]
    points: Option<PathBuf>,
    /// Give the end frames as rotation matrices (`r00 … r22`, row-major; JSON: rows) instead of
    /// quaternions `qw,qx,qy,qz`.
    #[arg(long)]
    matrix: bool,
}

/// Run `helixreach helix`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let c = twist_ratio(args.nu)?;
    if !(args.length.is_finite() && args.length > 0.0) {
        return Err(Error::invalid("length", args.length, "must be finite and > 0").into());
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    match (&args.points, args.kappa, args.tau, args.omega) {
        (Some(path), ..) => points(path, args.length, c, args.matrix, &mut out)?,
        (None, Some(k), Some(t), Some(w)) => {
            let h = Helix::new(k, t, w)?;
            let pose = h.end_pose(args.length, args.nu)?;
            let json = pose_json(&h, &pose, args.nu, c, args.length, args.matrix);
            serde_json::to_writer_pretty(&mut out, &json)?;
            writeln!(out)?;
        }
        _ => anyhow::bail!("give --kappa, --tau and --omega, or --points FILE.csv"),
    }
    out.flush().context("writing to stdout")?;
    Ok(())
}

fn rows(m: &helixreach::math::Mat3) -> [[Real; 3]; 3] {
    [0, 1, 2].map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]])
}

/// `x, y, z, qw, qx, qy, qz` of the frame `rot` at the end.
fn xyz_wxyz(p: &EndPose, rot: &helixreach::math::Mat3) -> [Real; 7] {
    pose_to_xyz_wxyz(&Frame {
        rot: *rot,
        pos: p.position,
    })
}

fn pose_json(
    h: &Helix,
    p: &EndPose,
    nu: Real,
    c: Real,
    length: Real,
    matrix: bool,
) -> serde_json::Value {
    let mut v = serde_json::json!({
        "inputs": {
            "kappa": h.kappa(), "tau": h.tau(), "omega": h.omega(),
            "nu": nu, "c": c, "length": length,
        },
        "frame": "clamp frame: origin at the clamped end, z = initial tangent, x = initial normal N0",
        "position": [p.position.x, p.position.y, p.position.z],
        "motor_angle": p.motor_angle,
    });
    if matrix {
        v["material_rows"] = serde_json::json!(rows(&p.material));
        v["transported_rows"] = serde_json::json!(rows(&p.transported));
    } else {
        v["material_wxyz"] = serde_json::json!(xyz_wxyz(p, &p.material)[3..]);
        v["transported_wxyz"] = serde_json::json!(xyz_wxyz(p, &p.transported)[3..]);
    }
    v
}

fn points(
    path: &Path,
    length: Real,
    c: Real,
    matrix: bool,
    out: &mut impl Write,
) -> anyhow::Result<()> {
    let mut table = helixreach::io::CsvInput::open(path)?;
    let col = |name: &str| table.column(name, "header must contain kappa,tau,omega");
    let cols = [col("kappa")?, col("tau")?, col("omega")?];
    let header = if matrix {
        HelixPointMatrixRecord::HEADER
    } else {
        HelixPointRecord::HEADER
    };
    let mut stream = CsvStream::new(out, header)?;
    let mut n_rows = 0usize;
    for (k, rec) in table.reader.records().enumerate() {
        let line = k + 2;
        let bad = |field: &str, reason: String| helixreach::io::bad_line(path, line, field, reason);
        let rec = rec.map_err(|e| bad("record", e.to_string()))?;
        let line = helixreach::io::line_of(&rec, line);
        let bad = |field: &str, reason: String| helixreach::io::bad_line(path, line, field, reason);
        let mut v = [0.0; 3];
        for (j, name) in ["kappa", "tau", "omega"].iter().enumerate() {
            v[j] = helixreach::io::parse_field(path, line, &rec, cols[j], name)?;
        }
        let h = Helix::new(v[0], v[1], v[2]).map_err(|e| {
            let field = match &e {
                Error::InvalidParameter { field, .. } => field.clone(),
                _ => "helix".to_string(),
            };
            bad(&field, e.to_string())
        })?;
        let p = h.end_pose_unchecked(length, c);
        if matrix {
            stream.write(&HelixPointMatrixRecord {
                kappa: v[0],
                tau: v[1],
                omega: v[2],
                position: [p.position.x, p.position.y, p.position.z],
                r: std::array::from_fn(|k| p.material[(k / 3, k % 3)]),
                motor_angle: p.motor_angle,
            })?;
        } else {
            stream.write(&HelixPointRecord {
                kappa: v[0],
                tau: v[1],
                omega: v[2],
                pose: xyz_wxyz(&p, &p.material),
                motor_angle: p.motor_angle,
            })?;
        }
        n_rows += 1;
    }
    if n_rows == 0 {
        return Err(table.file_error("no rows after the header".into()).into());
    }
    stream.finish()?;
    Ok(())
}
