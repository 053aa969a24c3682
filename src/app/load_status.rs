//! What the status line says while a model loads on its worker thread.

use std::time::Duration;

use relief_scene::load_progress::{LoadStep, ProgressNow};

/// A load under way, as the loop last read it.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadStatus {
    /// The file's name, sanitised.
    pub name: String,
    pub progress: ProgressNow,
    /// Since the load started.
    pub elapsed: Duration,
}

impl LoadStatus {
    /// One line: the file, the step and how far it is (a percentage when
    /// its size is known), the time so far, and how to stop it.
    pub fn text(&self) -> String {
        let ProgressNow { step, done, total } = self.progress;
        let how_far = match step {
            LoadStep::Starting => String::new(),
            LoadStep::Reading | LoadStep::Parsing if total > 0 => {
                format!(" {}% of {}", percent(done, total), megabytes(total, step))
            }
            LoadStep::Reading => format!(" {}", megabytes(done, step)),
            LoadStep::Parsing => String::new(),
            LoadStep::Building if total > 0 => format!(" {}%", percent(done, total)),
            LoadStep::Building => String::new(),
        };
        format!(
            "loading {}: {}{how_far} · {:.1} s (Esc cancels)",
            self.name,
            step.label(),
            self.elapsed.as_secs_f32()
        )
    }
}

/// `done` of `total` in whole percent, rounded down (100 only when done).
pub(super) fn percent(done: u64, total: u64) -> u64 {
    (u128::from(done.min(total)) * 100 / u128::from(total.max(1))) as u64
}

/// A size in MB (an OBJ's parse counts three passes over its bytes: the
/// file's size is a third of its units).
fn megabytes(units: u64, step: LoadStep) -> String {
    let bytes = match step {
        LoadStep::Parsing => units / 3,
        _ => units,
    };
    let mb = bytes as f64 / 1e6;
    if mb >= 10.0 {
        format!("{mb:.0} MB")
    } else {
        format!("{mb:.1} MB")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(step: LoadStep, done: u64, total: u64) -> String {
        LoadStatus {
            name: "big.obj".into(),
            progress: ProgressNow { step, done, total },
            elapsed: Duration::from_millis(1300),
        }
        .text()
    }

    #[test]
    fn each_step_says_what_it_knows() {
        assert_eq!(
            status(LoadStep::Reading, 26_250_000, 105_000_000),
            "loading big.obj: reading 25% of 105 MB · 1.3 s (Esc cancels)"
        );
        // Three passes over 9 MB: 4.5 MB of 27 counted units is 16 %.
        assert_eq!(
            status(LoadStep::Parsing, 4_500_000, 27_000_000),
            "loading big.obj: parsing 16% of 9.0 MB · 1.3 s (Esc cancels)"
        );
        assert_eq!(
            status(LoadStep::Parsing, 0, 0),
            "loading big.obj: parsing · 1.3 s (Esc cancels)"
        );
        assert_eq!(
            status(LoadStep::Building, 3, 6),
            "loading big.obj: building 50% · 1.3 s (Esc cancels)"
        );
        assert_eq!(
            status(LoadStep::Starting, 0, 0),
            "loading big.obj: starting · 1.3 s (Esc cancels)"
        );
    }

    #[test]
    fn percentages_round_down_and_stop_at_a_hundred() {
        assert_eq!(percent(999, 1000), 99);
        assert_eq!(percent(1000, 1000), 100);
        assert_eq!(percent(5000, 1000), 100);
        assert_eq!(percent(0, 0), 0);
    }
}
