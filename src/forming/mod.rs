//! Axisymmetric rigid-viscoplastic "flow approach" sheet-forming solver (paper sections 2 and 5).
//!
//! Work in progress: see issue 4.
