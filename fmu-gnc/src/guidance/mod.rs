//! Guidance (paper Sec. III): the acceleration the lander must produce, sampled at the
//! guidance rate, and the thrust magnitude that realises it.
pub mod polynomial;
pub mod pv;
pub mod retarget;
pub mod sequencer;
pub mod terminal;
pub mod thrust;
