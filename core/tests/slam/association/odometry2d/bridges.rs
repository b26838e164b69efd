//! Track bridges (core/src/slam/association/odometry2d/tracks.rs, "Bridges") on
//! planted woods worlds (random trajectories among identical landmarks,
//! bounds around the truth; the robot circles, so the headings run beyond
//! ±pi, and the bearings are wrapped into (-pi, pi]): every union the
//! track rule makes, bridges included, joins two detections of one true
//! landmark, and the bridges join tracks the window alone leaves apart
//! (a rule that bridges nothing passes the first check).

use nvector_core::slam::association::odometry2d::tracks::{track_unions, TrackOptions};
use nvector_core::slam::mission::Mission;
use nvector_core::slam::model::Model;
use nvector_core::slam::simulate::odometry_scenario::{simulate_woods, WoodsOptions};
use nvector_core::union_find::Uf;

fn groups(uf: &mut Uf) -> usize {
    (0..uf.len()).filter(|&j| uf.find(j) == j).count()
}

#[test]
fn bridges_only_join_detections_of_one_landmark() {
    let mut fewer = 0;
    for seed in 1..=12u64 {
        let opts = WoodsOptions {
            seed: 100 + seed,
            steps: Some(600 + (seed as usize % 3) * 200),
            landmarks: Some(8 + (seed as usize % 10)),
            operator: false,
        };
        let mission = Mission::from_value(&simulate_woods(&opts)).expect("a woods mission");
        let truth = mission.truth.as_ref().expect("truth").matching.clone();
        let model = Model::new(&mission);
        let chain = model.odometry.as_ref().expect("odometry2d");
        let k = mission.detections.len();
        let mut uf = Uf::new(k);
        let u = track_unions(&mission, chain, &mut uf, TrackOptions::default());
        for (a, b) in u {
            assert!(truth[a].is_some(), "seed {seed}: {a} has no true landmark");
            assert_eq!(truth[a], truth[b], "seed {seed}: joined {a} and {b}");
        }
        let with = groups(&mut uf);
        let mut alone = Uf::new(k);
        let no_bridges = TrackOptions {
            bridge_steps: 0,
            ..TrackOptions::default()
        };
        track_unions(&mission, chain, &mut alone, no_bridges);
        let without = groups(&mut alone);
        assert!(
            with <= without,
            "seed {seed}: {with} groups with bridges, {without} without"
        );
        if with < without {
            fewer += 1;
        }
    }
    assert!(
        fewer >= 6,
        "the bridges joined tracks on only {fewer} of 12 worlds"
    );
}
