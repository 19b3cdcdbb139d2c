//! `helixreach demo [--out DIR] [--quick] [--rig RIG] [--resume]`: the whole study on a rig.
//!
//! The stages are library functions ([`helixreach::experiment`]); this command parses the
//! arguments, runs them and renders the report: `report.md` and `report.json` with every headline
//! number and the settings that produced it. A failed stage is reported with its error in both
//! reports and on stderr, and the command exits non-zero. Progress goes to stderr.

use anyhow::Context;
use helixreach::experiment::{self, Log, RunOptions, Settings, StudyReport};
use serde_json::{json, Map, Value};
use std::fmt::Write as _;
use std::path::PathBuf;

/// Arguments of `helixreach demo`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "> helixreach demo --quick --out demo",
    "> helixreach demo --out figures"
))]
pub struct Args {
    /// Output directory for figures, CSVs and the report (`--out figures` regenerates the
    /// figures committed in `figures/`).
    #[arg(long, default_value = "helixreach-demo")]
    pub out: PathBuf,
    /// A small, fast run (about a minute): fewer directions, coarser rods.
    #[arg(long)]
    pub quick: bool,
    /// The rig: a rig file or the name of an embedded rig.
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
    /// Keep the reachability rows a previous run already wrote into `--out`.
    #[arg(long)]
    pub resume: bool,
}

/// Run `helixreach demo`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let log = Log::start().quiet(super::global().quiet);
    let settings = if args.quick {
        Settings::quick(&args.rig)
    } else {
        Settings::full(&args.rig)
    };
    log.say(
        "demo",
        format!(
            "{} run on rig `{}` with {} threads into {}",
            settings.mode,
            settings.rig,
            settings.threads,
            args.out.display()
        ),
    );
    let opts = RunOptions {
        out: args.out.clone(),
        resume: args.resume,
    };
    let report = experiment::run_with_log(&settings, &opts, &log)?;
    write_reports(&report, &args.out)?;
    log.say(
        "demo",
        format!(
            "finished in {:.1} s; report in {}",
            report.total_seconds,
            args.out.join("report.md").display()
        ),
    );
    let failed: Vec<String> = report
        .failed()
        .map(|s| format!("{}: {}", s.name, s.result.as_ref().err().map_or("", |e| e)))
        .collect();
    if !failed.is_empty() {
        anyhow::bail!(
            "{} of {} stages failed (see {}):\n  {}",
            failed.len(),
            report.stages.len(),
            args.out.join("report.md").display(),
            failed.join("\n  ")
        );
    }
    Ok(())
}

fn write_reports(run: &StudyReport, out: &std::path::Path) -> anyhow::Result<()> {
    let mut stages = Map::new();
    let mut failed = Vec::new();
    for s in &run.stages {
        let v = match &s.result {
            Ok(Value::Object(m)) => {
                let mut m = m.clone();
                m.insert("status".into(), json!("done"));
                m.insert("seconds".into(), json!(s.seconds));
                Value::Object(m)
            }
            Ok(other) => json!({ "status": "done", "seconds": s.seconds, "value": other }),
            Err(e) => {
                failed.push(json!({ "stage": s.name, "error": e }));
                json!({ "status": "failed", "error": e, "seconds": s.seconds })
            }
        };
        stages.insert(s.name.replace(' ', "_"), v);
    }
    let report = json!({
        "helixreach_version": env!("CARGO_PKG_VERSION"),
        "settings": run.settings,
        "total_seconds": run.total_seconds,
        "stages": stages,
        "figures": run.figures,
        "failed": failed,
    });
    let text = serde_json::to_string_pretty(&report)?;
    let write = |name: &str, text: &str| {
        let p = out.join(name);
        helixreach::io::write_atomic(&p, text.as_bytes())
            .with_context(|| format!("writing {}", p.display()))
    };
    write("report.json", &text)?;
    write("report.md", &markdown(run, &report))?;
    Ok(())
}

fn num(v: &Value) -> String {
    match v.as_f64() {
        // Where the report switches to exponent notation (a display range, not a tolerance).
        Some(x) if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) => format!("{x:.3e}"),
        Some(x) if x.fract() == 0.0 => format!("{x}"),
        Some(x) => format!("{x:.4}"),
        None => v.to_string(),
    }
}

fn markdown(run: &StudyReport, report: &Value) -> String {
    let mut md = String::new();
    let st = &run.settings;
    let _ = writeln!(md, "# helixreach demo report ({} run)\n", st.mode);
    let _ = writeln!(
        md,
        "Rig `{}`, {} threads, total {:.1} s. Every number below is also in `report.json`, \
         with the settings that produced it.\n",
        st.rig, st.threads, run.total_seconds
    );
    let _ = writeln!(md, "| stage | status | seconds |\n|---|---|---|");
    for s in &run.stages {
        let status = match &s.result {
            Ok(_) => "done".to_string(),
            Err(e) => format!("**FAILED** — {e}"),
        };
        let _ = writeln!(md, "| {} | {status} | {:.1} |", s.name, s.seconds);
    }
    for s in &run.stages {
        if let Ok(Value::Object(m)) = &s.result {
            let _ = writeln!(md, "\n## {}\n", s.name);
            for (k, v) in m {
                match v {
                    Value::Array(a) if a.iter().all(|x| x.is_object()) && !a.is_empty() => {
                        let keys: Vec<String> = a[0]
                            .as_object()
                            .map(|o| o.keys().cloned().collect())
                            .unwrap_or_default();
                        let _ = writeln!(
                            md,
                            "**{k}**\n\n| {} |\n|{}",
                            keys.join(" | "),
                            "---|".repeat(keys.len())
                        );
                        for x in a {
                            let cells: Vec<String> = keys.iter().map(|c| num(&x[c])).collect();
                            let _ = writeln!(md, "| {} |", cells.join(" | "));
                        }
                        md.push('\n');
                    }
                    Value::Array(a) => {
                        let items: Vec<String> = a
                            .iter()
                            .map(|x| x.as_str().map(str::to_string).unwrap_or_else(|| num(x)))
                            .collect();
                        let _ = writeln!(md, "- {k}: {}", items.join(", "));
                    }
                    _ => {
                        let _ = writeln!(md, "- {k}: {}", num(v));
                    }
                }
            }
        }
    }
    let _ = writeln!(md, "\n## Figures\n");
    for f in &run.figures {
        if f.ends_with(".png") {
            let _ = writeln!(md, "![{f}]({f})");
        }
    }
    let _ = writeln!(
        md,
        "\n## Settings\n\n```json\n{}\n```",
        serde_json::to_string_pretty(&report["settings"]).unwrap_or_default()
    );
    md
}
