//! Studies: one experiment of the paper reproduced end to end as library code. A study
//! computes, returns its record (and the data behind its figures) and renders figures from the
//! saved files; it never prints. The binaries in `experiments/` only parse flags, call the
//! study, write its record and print.
//!
//! * [`paper_beam`] — the beam example of Sec. 4.2 (Eq. 30–37), number by number.
//! * [`solve`] — one scene file, one strategy, every metric (the `solve` binary).
//! * [`text`] — the number formats, aligned tables and wrapped notes of the printed reports.

pub mod cond_accuracy;
pub mod paper_beam;
pub mod solve;
pub mod text;
