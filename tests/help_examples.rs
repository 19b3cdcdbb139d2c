//! Every subcommand's `--help` ends with an `Examples` section, and its examples work.
//!
//! A line starting `  $ ` is runnable: it runs in seconds (tiny sizes) in an empty directory,
//! after the `$ ` lines before it in the same `--help` (a later line may read what an earlier one
//! wrote). Each runs here with `sh -c`, the built `helixreach` first on `PATH`, in a fresh
//! temporary directory per subcommand, and must exit 0. A line starting `  > ` is shown only and
//! not run: it takes minutes (a full sweep, the demo) or needs files of the user's (recorded
//! runs); it is still parsed, so a flag it names must exist (`--help` of that command lists it).

use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_helixreach");

/// Subcommands whose every example needs the user's files or minutes of work.
const NOT_RUNNABLE: [&str; 2] = ["detect", "demo"];

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

fn help(args: &[&str]) -> String {
    let o = run(Path::new("."), args);
    assert!(o.status.success(), "{args:?}");
    String::from_utf8(o.stdout).unwrap()
}

/// The subcommands `helixreach --help` lists (not `help`).
fn subcommands() -> Vec<String> {
    let top = help(&["--help"]);
    let list: Vec<String> = top
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect();
    assert!(list.len() >= 19, "{list:?}");
    list
}

/// The example lines of a `--help` text: (`runnable`, command line).
fn examples(text: &str) -> Vec<(bool, String)> {
    let mut lines = text.lines().skip_while(|l| !l.starts_with("Examples"));
    assert!(lines.next().is_some(), "no Examples section in\n{text}");
    lines
        .take_while(|l| !l.trim().is_empty())
        .map(|l| {
            if let Some(c) = l.strip_prefix("  $ ") {
                (true, c.to_string())
            } else if let Some(c) = l.strip_prefix("  > ") {
                (false, c.to_string())
            } else {
                panic!("an example line starts with `  $ ` or `  > `: {l:?}")
            }
        })
        .collect()
}

/// The long flags a `helixreach CMD …` example line names.
fn flags_of(line: &str) -> Vec<&str> {
    line.split_whitespace()
        .filter(|w| w.starts_with("--"))
        .map(|w| w.split('=').next().unwrap_or(w))
        .collect()
}

#[test]
fn every_subcommand_has_examples_and_they_run() {
    let path = format!(
        "{}:{}",
        Path::new(BIN).parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut ran = 0;
    for cmd in subcommands() {
        let text = help(&[&cmd, "--help"]);
        let ex = examples(&text);
        let own = format!("helixreach {cmd} ");
        assert!(
            ex.iter().any(|(_, l)| l.starts_with(&own)),
            "{cmd}: no example of `helixreach {cmd}`"
        );
        if !NOT_RUNNABLE.contains(&cmd.as_str()) {
            assert!(
                ex.iter().any(|(r, l)| *r && l.starts_with(&own)),
                "{cmd}: no runnable example of itself"
            );
        }
        // A shown-only line still names only flags that exist.
        for (_, line) in ex.iter().filter(|(r, l)| !r && l.starts_with(&own)) {
            for f in flags_of(line) {
                assert!(
                    text.contains(&format!("{f} ")) || text.contains(&format!("{f}\n")),
                    "{cmd}: `{line}` names {f}, which `helixreach {cmd} --help` does not list"
                );
            }
        }
        let dir = tempfile::tempdir().unwrap();
        for (_, line) in ex.iter().filter(|(r, _)| *r) {
            let o = Command::new("sh")
                .current_dir(dir.path())
                .env("PATH", &path)
                .args(["-c", line])
                .output()
                .unwrap();
            assert!(
                o.status.success(),
                "{cmd}: `{line}` exited {:?}:\n{}",
                o.status.code(),
                String::from_utf8_lossy(&o.stderr)
            );
            ran += 1;
        }
    }
    assert!(ran >= 30, "{ran} example lines ran");
}

/// The parser of this test against a section that breaks its rules.
#[test]
#[should_panic(expected = "starts with")]
fn a_line_without_a_marker_is_refused() {
    examples("Examples (…):\n  $ helixreach rod\n  helixreach rod --preset nitinol\n");
}
