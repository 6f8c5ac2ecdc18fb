//! penalty-lab (crate docs written below).
pub mod conditioning;
pub mod error;
pub mod linalg;
pub mod metrics;
pub mod model;
pub mod plot;
pub mod scene;
pub mod strategy;
pub mod system;
pub use error::{Error, Result};
