//! Helpers shared by the property tests (each test file that needs them
//! declares `mod common;`).

// Each test crate uses a part of them.
#![allow(dead_code)]

/// The simulator's splitmix64 generator, with the draws the instances need
/// (proptest draws the seed).
pub struct Rng(nvector_core::slam::simulate::Rng);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(nvector_core::slam::simulate::Rng::new(seed))
    }
    pub fn next(&mut self) -> u64 {
        self.0.next_u64()
    }
    pub fn unit(&mut self) -> f64 {
        self.0.unit()
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}
