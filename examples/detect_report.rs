//! The snap detector on the seed's 58 recorded runs, against the authors' labels.
//!
//! Reads `SEED/observations/observations_labels.csv`, `SEED/trajectories.csv` (each run's
//! clamp) and the unpacked observation files (`tar -xJf SEED/observations/observations.tar.xz
//! -C DIR`). For each run: the detection with the run's clamp (and, with `--fit-clamp`, with the
//! clamp fitted from the joints), beside `s_authors` (the authors' post-processing) and
//! `s_snap_ref` / `s_return_ref` (an independent detection). Prints one line per run and the
//! agreement statistics; `--samples OUT_DIR` writes each run's per-sample CSV.
//!
//! Run: `cargo run --release --example detect_report -- SEED DIR [--fit-clamp] [--samples OUT_DIR]`

use helixreach::detect::{DetectOptions, Detector};
use helixreach::directions::Direction;
use helixreach::io::{parse_field, CsvInput};
use helixreach::math::Real;
use helixreach::planning::rig::Rig;
use helixreach::records::clamp_runs::read_seed_runs;
use helixreach::records::csv_out;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

struct Label {
    file: String,
    dir: Direction,
    s_authors: Real,
    authors_type: String,
    s_snap_ref: Option<Real>,
    s_return_ref: Option<Real>,
}

fn labels(path: &Path) -> anyhow::Result<Vec<Label>> {
    let mut t = CsvInput::open(path)?;
    let c: Vec<usize> = [
        "observation_file",
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "s_authors",
        "authors_type",
        "s_snap_ref",
        "s_return_ref",
    ]
    .iter()
    .map(|n| t.column(n, ""))
    .collect::<Result<_, _>>()?;
    let mut out = Vec::new();
    for (k, rec) in t.reader.records().enumerate() {
        let rec = rec?;
        let line = k + 2;
        let num = |i: usize, n: &str| parse_field(path, line, &rec, c[i], n);
        let opt = |i: usize| rec.get(c[i]).and_then(|x| x.parse::<Real>().ok());
        out.push(Label {
            file: rec.get(c[0]).unwrap_or("").to_string(),
            dir: Direction::new(num(1, "k")?, num(2, "t")?, num(3, "w")?)?,
            s_authors: num(4, "s_authors")?,
            authors_type: rec.get(c[5]).unwrap_or("").to_string(),
            s_snap_ref: opt(6),
            s_return_ref: opt(7),
        });
    }
    Ok(out)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(seed), Some(dir)) = (args.first(), args.get(1)) else {
        anyhow::bail!(
            "usage: detect_report SEED DIR [--fit-clamp] [--samples OUT_DIR] (see the module docs)"
        );
    };
    let (seed, dir) = (PathBuf::from(seed), PathBuf::from(dir));
    let fit_clamp = args.iter().any(|a| a == "--fit-clamp");
    let samples_dir = args
        .iter()
        .position(|a| a == "--samples")
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from);
    let labels = labels(&seed.join("observations/observations_labels.csv"))?;
    let runs = read_seed_runs(&seed.join("trajectories.csv"))?;
    let det = Detector::new(Rig::load("sawyer-seed")?, DetectOptions::default())?;
    let t0 = std::time::Instant::now();
    let results: Vec<_> = labels
        .par_iter()
        .map(|l| {
            let run = runs
                .iter()
                .find(|r| format!("test_{}", r.file) == l.file)
                .expect("every labelled run is in trajectories.csv");
            let clamp = (!fit_clamp).then_some(run.clamp);
            let c0 = helixreach::cpu_time::thread_cpu_seconds().unwrap_or(0.0);
            let r = det
                .read(&dir.join(&l.file))
                .and_then(|obs| det.detect(&obs, &l.dir, clamp));
            let cpu = helixreach::cpu_time::thread_cpu_seconds().unwrap_or(0.0) - c0;
            if let (Ok(d), Some(out)) = (&r, &samples_dir) {
                let text = csv_out::to_csv(&d.sample_records()).unwrap();
                std::fs::create_dir_all(out).unwrap();
                std::fs::write(out.join(l.file.replace(".txt", ".csv")), text).unwrap();
            }
            (r, run.clamp, cpu)
        })
        .collect();
    let wall = t0.elapsed();
    println!("file,authors_type,s_authors,s_snap_ref,s_return_ref,s_det,s_ret,reason,confidence,sigma,fit_rms_mm,clamp_err_mm,s_rev,s_pred");
    let (mut rel_a, mut rel_r, mut rel_ret) = (Vec::new(), Vec::new(), Vec::new());
    let (mut agree_ref, mut n_ref_cls) = (0, 0);
    let mut cpus = Vec::new();
    for (l, (r, clamp, cpu)) in labels.iter().zip(&results) {
        cpus.push(*cpu);
        match r {
            Err(e) => println!("{},ERROR {e}", l.file),
            Ok(d) => {
                let o = &d.outcome;
                let ce = (d.clamp - helixreach::math::Vec3::from(*clamp)).norm() * 1e3;
                println!(
                    "{},{},{},{},{},{},{},{},{},{:.4},{:.2},{:.2},{:.4},{:.4}",
                    l.file,
                    l.authors_type,
                    l.s_authors,
                    l.s_snap_ref.map_or(String::new(), |x| x.to_string()),
                    l.s_return_ref.map_or(String::new(), |x| x.to_string()),
                    o.s_snap.map_or(String::new(), |x| format!("{x:.5}")),
                    o.s_return.map_or(String::new(), |x| format!("{x:.5}")),
                    o.reason.as_str(),
                    o.confidence.as_str(),
                    d.extrinsics.sigma,
                    d.extrinsics.rms * 1e3,
                    ce,
                    d.s_reversal,
                    d.s_predicted
                );
                if l.authors_type == "subcritical" {
                    if let Some(s) = o.s_snap {
                        rel_a.push((s - l.s_authors).abs() / l.s_authors);
                    } else {
                        rel_a.push(Real::INFINITY);
                    }
                }
                if let (Some(s), Some(r)) = (o.s_snap, l.s_snap_ref) {
                    rel_r.push((s - r).abs() / r);
                }
                if let (Some(s), Some(r)) = (o.s_return, l.s_return_ref) {
                    rel_ret.push((s - r).abs() / r);
                }
                n_ref_cls += 1;
                if o.s_snap.is_some() == l.s_snap_ref.is_some() {
                    agree_ref += 1;
                }
            }
        }
    }
    let stats = |v: &[Real]| {
        let f: Vec<Real> = v.iter().copied().filter(|x| x.is_finite()).collect();
        let within = v.iter().filter(|x| **x <= 0.02).count();
        (
            f.iter().sum::<Real>() / f.len().max(1) as Real,
            f.iter().copied().fold(0.0, Real::max),
            within,
            v.len(),
        )
    };
    let a = stats(&rel_a);
    let r = stats(&rel_r);
    eprintln!(
        "vs s_authors (subcritical runs): within 2 %: {}/{}; mean {:.4}, max {:.4} (over detected)",
        a.2, a.3, a.0, a.1
    );
    eprintln!(
        "vs s_snap_ref (both detected): within 2 %: {}/{}; mean {:.4}, max {:.4}",
        r.2, r.3, r.0, r.1
    );
    let q = stats(&rel_ret);
    eprintln!(
        "s_return vs s_return_ref (both found): {} runs; mean {:.4}, max {:.4}; within 5 %: {}",
        q.3,
        q.0,
        q.1,
        rel_ret.iter().filter(|x| **x <= 0.05).count()
    );
    eprintln!("detected-or-not agreement with s_snap_ref: {agree_ref}/{n_ref_cls}");
    cpus.sort_by(Real::total_cmp);
    eprintln!(
        "wall {:.2} s; CPU per run (read + detect): median {:.1} ms, max {:.1} ms, total {:.2} s",
        wall.as_secs_f64(),
        cpus[cpus.len() / 2] * 1e3,
        cpus[cpus.len() - 1] * 1e3,
        cpus.iter().sum::<Real>()
    );
    Ok(())
}
