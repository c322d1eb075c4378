//! A progress bar that appears only on runs longer than about a second,
//! and only when stderr is a terminal.

use guideway::report::StepProgress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

const SHOW_AFTER: Duration = Duration::from_secs(1);
const TICKS: u64 = 1000;

pub(super) struct Progress {
    enabled: bool,
    started: Instant,
    bar: Option<ProgressBar>,
}

impl Progress {
    pub fn new(quiet: bool) -> Progress {
        Progress {
            enabled: !quiet && std::io::stderr().is_terminal(),
            started: Instant::now(),
            bar: None,
        }
    }

    /// The step callback of a run: the bar moved, and a stop asked for
    /// once Ctrl-C set `interrupted`.
    pub fn on_step<'a>(
        &'a mut self,
        interrupted: &'a AtomicBool,
    ) -> impl FnMut(StepProgress) -> ControlFlow<()> + 'a {
        move |step| {
            self.update(step);
            if interrupted.load(Ordering::SeqCst) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        }
    }

    pub fn update(&mut self, progress: StepProgress) {
        if !self.enabled {
            return;
        }
        if self.bar.is_none() {
            if self.started.elapsed() < SHOW_AFTER {
                return;
            }
            let bar = ProgressBar::with_draw_target(Some(TICKS), ProgressDrawTarget::stderr());
            bar.set_style(
                ProgressStyle::with_template(
                    "{elapsed_precise} [{wide_bar}] {percent:>3}%  t = {msg} s  eta {eta}",
                )
                .expect("the template is valid")
                .progress_chars("=> "),
            );
            self.bar = Some(bar);
        }
        if let Some(bar) = &self.bar {
            bar.set_position((progress.fraction * TICKS as f64) as u64);
            bar.set_message(format!("{:.4}", progress.time));
        }
    }

    pub fn finish(self) {
        if let Some(bar) = self.bar {
            bar.finish_and_clear();
        }
    }
}
