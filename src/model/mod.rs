//! Models that produce contact problems: the 1-DOF spring of Fig. 1 (Eq. 10–17) and 2D
//! Euler–Bernoulli beams/frames (Eq. 30), including the paper's 3-element beam, and the 5-point
//! membrane stiffness.
pub mod beam;
pub mod membrane;
pub mod spring;
