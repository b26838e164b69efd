//! The local frames (core/src/shapes/frames.rs) on missions planted with
//! their truth on the boundary (tests/common/planted.rs): for groups that
//! are true (detections of one landmark joined at random), each piece's
//! paving holds the exact `L - p(s)` of its group's landmark relative to
//! the position of its frame's step (checked with rationals: it is not a
//! float), the pieces build without error, and every pair the frames prove
//! distinct sees two different landmarks. The chain sums come with or
//! without the detection steps marked; the tuning is drawn at random
//! (pieces of a few steps, small gaps, few boxes), and the frames run twice
//! (the second time on their cache, after more groups were joined).
//!
//! `PROPTEST_CASES` sets the number of cases (common::config).

use num_rational::BigRational;
use nvector_core::shapes::chain_sums::ChainSums;
use nvector_core::shapes::distinct::Uf;
use nvector_core::shapes::frames::{FrameOptions, Frames};
use nvector_core::slam::association::sightings;
use nvector_core::slam::model::Model;
use proptest::prelude::*;

use crate::common;
use common::planted::{self, PlantedMission};
use common::{holds, rat, Rng};

/// Runs the frames on a planted mission (module doc); returns the number
/// of pairs proved.
fn check_frames(pm: &PlantedMission, rng: &mut Rng) -> Result<usize, String> {
    let m = &pm.mission;
    let model = Model::new(m);
    let dim = model.dim;
    let k = m.detections.len();
    let steps: Vec<usize> = m.detections.iter().map(|d| d.step).collect();
    let sums = if rng.chance(0.5) {
        ChainSums::new(&model.disp, dim).with_steps(&steps)
    } else {
        ChainSums::new(&model.disp, dim)
    };
    let mut order: Vec<usize> = (0..k).collect();
    order.sort_by_key(|&j| (steps[j], j));
    let opts = FrameOptions {
        piece_steps: 1 + rng.below(40),
        max_gap: 1 + rng.below(60),
        max_boxes: 2 + rng.below(40),
        refine_shapes: 1 + rng.below(12),
        anchor_gap: 1 + rng.below(20),
        // The pieces built and tested on 1 to 3 threads: the pairs must
        // hold the same.
        threads: 1 + rng.below(3),
    };
    let mut uf = Uf::new(k);
    let mut frames = Frames::default();
    let mut proved = 0;
    for round in 0..2 {
        // Join true pairs at random (more in the second round).
        for a in 0..k {
            for b in a + 1..k {
                if pm.matching[a].is_some()
                    && pm.matching[a] == pm.matching[b]
                    && rng.chance(0.3 + 0.3 * round as f64)
                {
                    uf.union(a, b);
                }
            }
        }
        let mut out = Vec::new();
        frames
            .pairs(
                &sightings(m),
                &order,
                dim,
                &sums,
                &model.heading_at,
                &mut uf,
                &opts,
                &mut out,
            )
            .map_err(|e| format!("true groups called infeasible: {e} ({opts:?})"))?;
        for &(a, b) in &out {
            let (la, lb) = (pm.matching[a as usize], pm.matching[b as usize]);
            if la == lb {
                return Err(format!(
                    "detections {a} and {b} of landmark {la:?} proved distinct ({opts:?})"
                ));
            }
        }
        proved += out.len();
        for (member, s, _, paving) in frames.every_piece() {
            let l = &pm.landmarks[pm.matching[member].expect("a true group")];
            let rel: Vec<BigRational> = (0..dim)
                .map(|a| rat(l[a]) - rat(pm.positions[s][a]))
                .collect();
            let inside = paving
                .boxes()
                .iter()
                .any(|b| (0..dim).all(|a| holds(b[a], &rel[a])));
            if !inside {
                return Err(format!(
                    "the piece of detection {member} in the frame of step {s} lost L - p(s) = {:?}: {:?} ({opts:?})",
                    (0..dim).map(|a| l[a] - pm.positions[s][a]).collect::<Vec<_>>(),
                    paving.boxes()
                ));
            }
        }
    }
    Ok(proved)
}

proptest! {
    #![proptest_config(common::config(200))]

    /// Module doc.
    #[test]
    fn frames_keep_a_truth_on_the_boundary(seed in any::<u64>(), three in any::<bool>()) {
        let mut rng = Rng::new(seed);
        let mut o = planted::Options::random(&mut rng, if three { 3 } else { 2 });
        o.steps = 5 + rng.below(80);
        o.detect = o.detect.max(0.3);
        let pm = planted::mission(&mut rng, &o);
        check_frames(&pm, &mut rng).map_err(|e| TestCaseError::fail(format!("seed {seed}: {e}\n{}", pm.value)))?;
    }
}

/// The planted missions give the frames something to prove: over fixed
/// seeds, they prove distinct pairs.
#[test]
fn frames_prove_pairs_on_planted_missions() {
    let mut proved = 0;
    for seed in 0..60u64 {
        let mut rng = Rng::new(seed);
        let mut o = planted::Options::random(&mut rng, 2 + (seed % 2) as usize);
        o.steps = 5 + rng.below(80);
        o.detect = o.detect.max(0.3);
        let pm = planted::mission(&mut rng, &o);
        proved += check_frames(&pm, &mut rng).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
    }
    eprintln!("PROVED {proved}");
    assert!(proved >= 50, "{proved} pairs proved");
}
