//! `Sector`: the landmark set of one range-and-bearing detection when the
//! robot's heading is uncertain (odometry2d), with the sensor at a point
//! fixed in the body frame.
//!
//! # The set
//!
//! With P the box of the robot position, T the heading interval, o the
//! sensor offset, r the range, β the bearing (optional) and C a box known
//! to hold the landmark:
//!
//! `A = {x ∈ C : ∃ p ∈ P, θ ∈ T, s = p + R(θ)·o, |x - s| ∈ r,
//!       [β: x - s points along θ + β]}`
//!
//! an annulus sector around the uncertain sensor point whose direction is
//! uncertain by T + β (an annulus when no bearing is measured).
//!
//! # Tests (each sound: `false` for "meets" and `true` for "disjoint" are
//! proofs)
//!
//! - [`Sector::contract_piece`]: the branch "landmark in box B": copies of
//!   P, T and B ∩ C contracted by [`OffsetDetection::contract`] (twice);
//!   `None` proves A ∩ B = ∅. Its heading is the sound heading contraction
//!   from "the landmark is in B" ([`Sector::heading_given`]).
//! - [`Sector::outer_box`]: the landmark part of `contract_piece(C)`.
//! - [`Sector::disjoint`]: outer boxes disjoint; or the annulus tests of
//!   [`crate::shapes::shape`] on the sensor boxes S = P + R(T)·o (every
//!   point of A is within r of a point of S); or, within a budget, a
//!   bisection of the common outer box in which every piece is excluded by
//!   one of the two sectors.
//!
//! An empty sector (empty P, T, range or C) is never called disjoint from
//! another: emptiness proves the mission infeasible, not two landmarks
//! distinct (an empty box proves nothing about distinctness).
//!
//! # Soundness
//!
//! `contract_piece` keeps every (p, θ, x) of the set with x ∈ B
//! ([`OffsetDetection::contract`] is sound), so `None` is a proof. A common
//! point of two sectors lies in both outer boxes, within r1 of S1 and r2
//! of S2, and in some piece of any bisection, which neither sector
//! excludes; so each disjointness argument is a proof. The interval sums
//! are rounded outwards.
//!
//! # Complexity
//!
//! O(1) per `contract_piece` / `meets`; O(budget) for `disjoint`.

use crate::interval::Interval;
use crate::odometry::sensor::OffsetDetection;
use crate::shapes::shape::distance_between;

/// The landmark set of one detection under an uncertain heading (see the
/// module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sector {
    /// P: the box of the robot position at the detection's step.
    pub centre: [Interval; 2],
    /// T: the heading at that step.
    pub heading: Interval,
    /// The measurement (range, bearing, sensor offset).
    pub detection: OffsetDetection,
    /// C: a box known to hold the landmark.
    pub cut: [Interval; 2],
}

/// The branch "landmark in a box": contracted copies of the position, the
/// heading and the landmark.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectorPiece {
    /// Contracted copy of P.
    pub p: [Interval; 2],
    /// Contracted copy of T: the heading given that the landmark is in the
    /// box.
    pub heading: Interval,
    /// Contracted copy of the box ∩ C.
    pub d: [Interval; 2],
}

fn box_meets(a: &[Interval; 2], b: &[Interval; 2]) -> bool {
    a[0].meets(b[0]) && a[1].meets(b[1])
}

impl Sector {
    /// A sector.
    pub fn new(
        centre: [Interval; 2],
        heading: Interval,
        detection: OffsetDetection,
        cut: [Interval; 2],
    ) -> Sector {
        Sector {
            centre,
            heading,
            detection,
            cut,
        }
    }

    /// Whether the sector is proved empty by its own domains (an empty
    /// centre, heading, range or cut).
    pub fn is_empty(&self) -> bool {
        self.centre
            .iter()
            .chain(self.cut.iter())
            .any(|x| x.is_empty())
            || self.heading.is_empty()
            || self
                .detection
                .range
                .intersect(Interval::new(0.0, f64::INFINITY))
                .is_empty()
            || self.detection.bearing.is_some_and(|b| b.is_empty())
    }

    /// The branch "landmark in `b`": P, T and b ∩ C contracted by the
    /// detection's constraint (two passes). `None` proves the sector does
    /// not meet `b`.
    pub fn contract_piece(&self, b: &[Interval; 2]) -> Option<SectorPiece> {
        let mut piece = SectorPiece {
            p: self.centre,
            heading: self.heading,
            d: [b[0].intersect(self.cut[0]), b[1].intersect(self.cut[1])],
        };
        for _ in 0..2 {
            if !self
                .detection
                .contract(&mut piece.p, &mut piece.heading, &mut piece.d)
            {
                return None;
            }
        }
        Some(piece)
    }

    /// Whether the sector may meet `b` (`false` is a proof that it does not).
    pub fn meets(&self, b: &[Interval; 2]) -> bool {
        self.contract_piece(b).is_some()
    }

    /// The heading interval given that the landmark lies in `b`: a sound
    /// contraction of T (empty when the sector does not meet `b`). The
    /// union over the boxes of a cover of A of these intervals holds every
    /// heading of the detection's solutions.
    pub fn heading_given(&self, b: &[Interval; 2]) -> Interval {
        self.contract_piece(b)
            .map_or(Interval::EMPTY, |piece| piece.heading)
    }

    /// A box holding the sector (empty axes when it is proved empty).
    pub fn outer_box(&self) -> [Interval; 2] {
        self.contract_piece(&self.cut)
            .map_or([Interval::EMPTY; 2], |piece| piece.d)
    }

    /// The box of the sensor point: P + R(T)·o.
    pub fn sensor_box(&self) -> [Interval; 2] {
        self.detection.sensor_box(&self.centre, self.heading)
    }

    /// A proof that the two sectors share no point (`false`: not proved);
    /// at most `budget` pieces of bisection (see the module doc).
    pub fn disjoint(&self, other: &Sector, budget: usize) -> bool {
        if self.is_empty() || other.is_empty() {
            return false;
        }
        let (ha, hb) = (self.outer_box(), other.outer_box());
        if ha.iter().chain(hb.iter()).any(|x| x.is_empty()) {
            // Proved empty by contraction: not a proof of distinctness.
            return false;
        }
        if !box_meets(&ha, &hb) {
            return true;
        }
        let (sa, sb) = (self.sensor_box(), other.sensor_box());
        let dd = distance_between(&sa, &sb);
        let r1 = self
            .detection
            .range
            .intersect(Interval::new(0.0, f64::INFINITY));
        let r2 = other
            .detection
            .range
            .intersect(Interval::new(0.0, f64::INFINITY));
        if !dd.is_empty()
            && ((r1 + r2).hi() < dd.lo() || (dd + r1).hi() < r2.lo() || (dd + r2).hi() < r1.lo())
        {
            return true;
        }
        let start = [ha[0].intersect(hb[0]), ha[1].intersect(hb[1])];
        let mut stack = vec![start];
        let mut seen = 0usize;
        while let Some(x) = stack.pop() {
            let (pa, pb) = match (self.contract_piece(&x), other.contract_piece(&x)) {
                (Some(pa), Some(pb)) => (pa, pb),
                _ => continue,
            };
            seen += 1;
            if seen > budget {
                return false;
            }
            let y = [pa.d[0].intersect(pb.d[0]), pa.d[1].intersect(pb.d[1])];
            if y[0].is_empty() || y[1].is_empty() {
                continue;
            }
            let axis = if y[0].width() >= y[1].width() { 0 } else { 1 };
            let m = y[axis].mid();
            let (mut l, mut r) = (y, y);
            l[axis] = Interval::new(y[axis].lo(), m);
            r[axis] = Interval::new(m, y[axis].hi());
            if l == y || r == y {
                // Cannot split further (a point or an ulp wide): not proved.
                return false;
            }
            stack.push(r);
            stack.push(l);
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sector(h: Interval, beta: f64) -> Sector {
        Sector::new(
            [Interval::centered(0.0, 0.05); 2],
            h,
            OffsetDetection::new(
                Interval::centered(3.0, 0.05),
                Some(Interval::centered(beta, 0.02)),
                [0.2, 0.0],
            ),
            [Interval::ENTIRE; 2],
        )
    }

    #[test]
    fn port_and_starboard_are_disjoint_unless_the_heading_is_lost() {
        let h = Interval::centered(0.0, 0.1);
        let (a, b) = (sector(h, 1.5), sector(h, -1.5));
        assert!(a.disjoint(&b, 200) && b.disjoint(&a, 200));
        // Heading uncertain by more than pi: the sectors overlap.
        let h = Interval::new(-2.0, 2.0);
        assert!(!sector(h, 1.5).disjoint(&sector(h, -1.5), 200));
    }

    #[test]
    fn a_box_gives_the_heading() {
        // Heading lost in [-4, 4]; the landmark is known near (0.2, 3),
        // seen at bearing ~ pi/2 from the laser: the heading is ~0.
        let s = sector(Interval::new(-4.0, 4.0), std::f64::consts::FRAC_PI_2);
        let h = s.heading_given(&[Interval::centered(0.2, 0.1), Interval::centered(3.0, 0.1)]);
        assert!(h.contains(0.0) && h.width() < 0.3, "{h:?}");
        assert!(!s.meets(&[Interval::centered(0.2, 0.1), Interval::centered(30.0, 0.1)]));
    }
}
