//! Models that produce contact problems: the 1-DOF spring of Fig. 1 (Eq. 10–17) and 2D
//! Euler–Bernoulli beams/frames (Eq. 30), including the paper's 3-element beam, and the 5-point
//! membrane stiffness; Q4 elasticity ([`elasticity`]), its flat punch turned onto an inclined
//! plane and its rigid cylinder's rows along nodal normals ([`inclined`]: contact rows with two
//! terms), an axis-aligned block pressed on an inclined plane with its supports unrotated
//! ([`incline_block`]: two-term rows that a diagonal preconditioner cannot absorb), two elastic
//! bodies with node-to-segment and mortar rows ([`two_body`]: the contact
//! patch test; [`cylinder`]: an elastic cylinder on a block) and scenes that scale to 10⁶ DOFs
//! ([`scalable`], the run-time studies' input). Seeded random scenes of these models are
//! the `generate` module's (above the strategies: some families are calibrated by a solve).
pub mod beam;
mod contact_forces;
pub mod cylinder;
pub mod elasticity;
pub mod incline_block;
pub mod inclined;
pub mod membrane;
pub mod scalable;
pub mod solid;
pub mod spring;
pub mod two_body;
