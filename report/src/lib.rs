//! What the results of the lander mission look like to a reader: the PNG figures of a
//! scenario's flights, a divert and a Monte Carlo campaign ([`plots`]), and the one
//! self-contained HTML page of a results directory ([`html`]). Draws what `lander` flew and
//! `campaign` summarised; runs nothing itself.
#![forbid(unsafe_code)]
// std's transcendental functions compute the figures' axes, ticks and trajectories here,
// outside any FMU (the workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]

pub mod html;
pub mod plots;
