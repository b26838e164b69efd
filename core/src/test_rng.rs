//! What core's unit tests share: a small deterministic generator (the
//! MMIX linear congruential generator), so that each test's cases are the
//! same on every run and every platform (the fingerprint of a text is
//! `rng::fnv1a`).

/// The generator state.
pub struct Lcg(u64);

impl Lcg {
    /// A generator from its seed.
    pub fn new(seed: u64) -> Lcg {
        Lcg(seed)
    }

    /// 53 pseudo-random bits.
    pub fn bits(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 11
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.bits() as f64 / (1u64 << 53) as f64
    }
}
