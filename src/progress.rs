//! The progress bar of long work on stderr, behind the `progress` feature.
//!
//! [`Bar`] is an indicatif bar with the `progress` feature (on in the default build, through
//! `cli`); without it (the core built with `--no-default-features`) it draws nothing, and
//! [`Bar::DRAWS`] is false so callers print plain progress lines instead (as they do when stderr
//! is not a terminal). Counting is safe from rayon workers.

/// A progress bar on stderr (see the module docs).
#[derive(Debug)]
pub struct Bar {
    #[cfg(feature = "progress")]
    bar: indicatif::ProgressBar,
}

impl Bar {
    /// Whether a bar is drawn at all in this build.
    pub const DRAWS: bool = cfg!(feature = "progress");

    /// A bar of `total` items, drawn on stderr.
    pub fn new(total: usize) -> Bar {
        #[cfg(feature = "progress")]
        {
            let bar = indicatif::ProgressBar::with_draw_target(
                Some(total as u64),
                indicatif::ProgressDrawTarget::stderr(),
            );
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} ({per_sec}, eta {eta})",
            ) {
                bar.set_style(style);
            }
            Bar { bar }
        }
        #[cfg(not(feature = "progress"))]
        {
            let _ = total;
            Bar {}
        }
    }

    /// A bar that draws nothing.
    pub fn hidden() -> Bar {
        Bar {
            #[cfg(feature = "progress")]
            bar: indicatif::ProgressBar::hidden(),
        }
    }

    /// `n` more items finished.
    pub fn inc(&self, n: u64) {
        #[cfg(feature = "progress")]
        self.bar.inc(n);
        #[cfg(not(feature = "progress"))]
        let _ = n;
    }

    /// The work failed: leave the bar where it stopped.
    pub fn abandon(&self) {
        #[cfg(feature = "progress")]
        self.bar.abandon();
    }

    /// The work finished: remove the bar.
    pub fn finish_and_clear(&self) {
        #[cfg(feature = "progress")]
        self.bar.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hidden_bar_counts_from_many_threads_without_drawing() {
        use rayon::prelude::*;
        let b = Bar::hidden();
        (0..1000).into_par_iter().for_each(|_| b.inc(1));
        b.finish_and_clear();
    }
}
