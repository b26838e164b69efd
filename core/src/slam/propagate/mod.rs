//! Propagation to the fixpoint: the physics-guided rounds of the paper's
//! section 6 ([`rounds`]: dead reckoning, then rounds of a forward and a
//! backward pass along the motion chain ([`passes`]) with each detection
//! contracted when a pass reaches its step ([`detections`]), and the
//! association step ([`crate::slam::association::step`])), and
//! [`fixpoint`], which runs them or the robust propagation
//! ([`crate::slam::robust`]) when detections may be false.

mod detections;
pub mod fixpoint;
mod passes;
mod propagation;
pub mod rounds;
