//! What every run says at its end: rows solved, failed and skipped per method, with the first
//! error of each ([`Tally`]), and the failure that ends a run with exit status 4 — a method
//! that failed on every scene it ran on ([`Tally::all_failed`], [`crate::Error::MethodFailed`]).
//!
//! A row's outcome comes from its `warnings` cell, the studies' one convention: `error: …`
//! is a failure, `skipped: …` a row not run (by configuration), anything else a solve (its
//! warnings are not failures).

use serde::{Deserialize, Serialize};

/// The rows of one method.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MethodTally {
    /// The method's name.
    pub method: String,
    /// Rows solved (with or without warnings).
    pub solved: usize,
    /// Rows whose solve or metrics failed (`warnings` starts with `error:`).
    pub failed: usize,
    /// Rows not run by configuration (`warnings` starts with `skipped:`).
    pub skipped: usize,
    /// The first failure's message (without `error: `).
    pub first_error: Option<String>,
}

/// The per-method tally of a run, methods in order of first appearance.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Tally(pub Vec<MethodTally>);

impl Tally {
    /// Counts one row of `method` from its `warnings` cell.
    pub fn add(&mut self, method: &str, warnings: &str) {
        let i = match self.0.iter().position(|t| t.method == method) {
            Some(i) => i,
            None => {
                self.0.push(MethodTally {
                    method: method.to_string(),
                    ..MethodTally::default()
                });
                self.0.len() - 1
            }
        };
        let t = &mut self.0[i];
        if let Some(e) = warnings.strip_prefix("error: ") {
            t.failed += 1;
            if t.first_error.is_none() {
                t.first_error = Some(e.to_string());
            }
        } else if warnings.starts_with("skipped:") {
            t.skipped += 1;
        } else {
            t.solved += 1;
        }
    }

    /// The number of rows counted.
    pub fn rows(&self) -> usize {
        self.0.iter().map(|t| t.solved + t.failed + t.skipped).sum()
    }

    /// The methods that failed on every row they ran (skipped rows aside), with their first
    /// error: `barrier (12 of 12 rows: <first error>)`, `;`-separated; `None` where every
    /// method solved at least one row it ran.
    pub fn all_failed(&self) -> Option<String> {
        let failed: Vec<String> = self
            .0
            .iter()
            .filter(|t| t.failed > 0 && t.solved == 0)
            .map(|t| {
                format!(
                    "{} ({} of {} rows: {})",
                    t.method,
                    t.failed,
                    t.failed,
                    t.first_error.as_deref().unwrap_or("no message")
                )
            })
            .collect();
        (!failed.is_empty()).then(|| failed.join("; "))
    }

    /// The summary printed at the end of a run: one line per method (solved / failed /
    /// skipped and the first error, clipped to `width` characters).
    pub fn text(&self, width: usize) -> String {
        let rows: Vec<Vec<String>> = self
            .0
            .iter()
            .map(|t| {
                let e = t.first_error.as_deref().unwrap_or("");
                let e = if e.chars().count() > width {
                    format!("{}…", e.chars().take(width).collect::<String>())
                } else {
                    e.to_string()
                };
                vec![
                    t.method.clone(),
                    t.solved.to_string(),
                    t.failed.to_string(),
                    t.skipped.to_string(),
                    e,
                ]
            })
            .collect();
        super::text::table(
            &["method", "solved", "failed", "skipped", "first error"],
            &rows,
            &[false, true, true, true, false],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcomes_come_from_the_warnings_cell() {
        let mut t = Tally::default();
        t.add("barrier", "error: Newton did not converge");
        t.add("lagrange", "");
        t.add("barrier", "error: second");
        t.add(
            "optimal",
            "skipped: optimal runs on the families [\"beam\"] only",
        );
        t.add("lagrange", "cond2 of the system matrix is 1e12: …");
        assert_eq!(t.rows(), 5);
        assert_eq!(t.0[0].failed, 2);
        assert_eq!(
            t.0[0].first_error.as_deref(),
            Some("Newton did not converge")
        );
        assert_eq!(t.0[1].solved, 2);
        assert_eq!(t.0[2].skipped, 1);
        // barrier failed every row it ran; optimal ran none (skipped is not a failure).
        let msg = t.all_failed().unwrap();
        assert!(msg.starts_with("barrier (2 of 2 rows: Newton"), "{msg}");
        assert!(!msg.contains("optimal") && !msg.contains("lagrange"));
        t.add("barrier", "");
        assert_eq!(t.all_failed(), None);
        assert!(t.text(40).lines().count() >= 4);
    }
}
