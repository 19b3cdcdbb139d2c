//! The whole study from Rust: the stages `helixreach demo` runs, as library calls.
//!
//! ```sh
//! cargo run --release --example study -- [quick|full] [OUT_DIR]
//! ```

use helixreach::experiment::{self, RunOptions, Settings};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mode = args.next().unwrap_or_else(|| "quick".into());
    let out = args.next().unwrap_or_else(|| "target/study".into());
    let settings = match mode.as_str() {
        "full" => Settings::full("sawyer-seed"),
        _ => Settings::quick("sawyer-seed"),
    };
    let report = experiment::run(&settings, &RunOptions::new(&out))?;
    if let Some(reach) = &report.reach {
        println!(
            "testable: {:.1} % with roll fixed, {:.1} % with roll motor",
            100.0 * reach.roll_fixed.fraction_testable,
            100.0 * reach.roll_motor.fraction_testable
        );
    }
    for stage in report.failed() {
        eprintln!("{} failed: {:?}", stage.name, stage.result);
    }
    if report.all_done() {
        Ok(())
    } else {
        Err("a stage failed".into())
    }
}
