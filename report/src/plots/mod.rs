//! PNG figures mirroring the paper's: Fig. 3 the 3-D trajectories of the laws, Fig. 4 the
//! position components against time, Fig. 5 the body rates ([`paper`]); the Monte Carlo
//! Fig. 6 ([`monte_carlo`]); the retarget comparison ([`retarget`]). [`style`] gives every
//! figure one look.
mod canvas;
pub mod monte_carlo;
pub mod paper;
pub mod requirement;
pub mod retarget;
pub mod style;

pub use paper::paper_figures;
