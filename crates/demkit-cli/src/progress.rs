//! The progress bar drawn on stderr during long runs (none with --quiet or off a terminal).

use demkit::methods::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// A progress bar that may be hidden.
pub struct Bar {
    bar: Option<ProgressBar>,
}

impl Bar {
    /// A bar on stderr unless `quiet` or stderr is not a terminal.
    pub fn new(quiet: bool, label: &str) -> Self {
        if quiet || !std::io::stderr().is_terminal() {
            return Bar { bar: None };
        }
        let bar = ProgressBar::with_draw_target(Some(1), ProgressDrawTarget::stderr());
        if let Ok(style) =
            ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} {msg} ({elapsed})")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_prefix(label.to_string());
        Bar { bar: Some(bar) }
    }

    /// Updates the bar after an iteration.
    pub fn update(&self, p: Progress) {
        if let Some(b) = &self.bar {
            b.set_length(p.max_iter as u64);
            b.set_position(p.iteration as u64);
            b.set_message(format!("error {:.3e}", p.error));
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
