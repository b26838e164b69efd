//! The basic contractors of a SLAM mission, one per file: [`distance`]
//! (range), [`bearing`] (angle to the landmark) and [`motion_chain`]
//! (p(i+1) = p(i) + D(i)). They sit below both the detection shapes
//! ([`crate::shapes`]) and the SLAM pipeline ([`crate::slam`]), which use
//! them; they import only the interval types.

pub mod bearing;
pub mod distance;
pub mod motion_chain;
