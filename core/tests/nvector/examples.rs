//! Worked examples of atmost_nvector whose expected results are derived by
//! hand (in the comments), not copied from a run.

use nvector_core::nvector::{atmost_nvector, Contractor, Status};
use nvector_core::{Interval, IntervalBox};

const ALL: [Contractor; 5] = [
    Contractor::Nvalue,
    Contractor::Projection,
    Contractor::Independent,
    Contractor::Best,
    Contractor::Exact,
];

fn b(axes: &[(f64, f64)]) -> IntervalBox {
    IntervalBox::new(
        &axes
            .iter()
            .map(|&(l, h)| Interval::new(l, h))
            .collect::<Vec<_>>(),
    )
}

fn gccat() -> Vec<IntervalBox> {
    vec![
        b(&[(1.0, 6.0), (2.0, 6.0)]),
        b(&[(3.0, 5.0), (6.0, 9.0)]),
        b(&[(4.0, 10.0), (1.0, 4.0)]),
        b(&[(5.0, 9.0), (3.0, 7.0)]),
        b(&[(9.0, 11.0), (0.0, 5.0)]),
    ]
}

#[test]
fn gccat_two_vectors_suffice() {
    // The catalogue's solution (5,6),(5,6),(9,3),(5,6),(9,3) uses 2 vectors.
    let solution = [[5.0, 6.0], [5.0, 6.0], [9.0, 3.0], [5.0, 6.0], [9.0, 3.0]];
    for mode in ALL {
        let mut boxes = gccat();
        let out = atmost_nvector(2, &mut boxes, mode).unwrap();
        assert!(!matches!(out.status, Status::Infeasible { .. }), "{mode:?}");
        for (bx, p) in boxes.iter().zip(&solution) {
            assert!(bx.contains(p), "{mode:?} removed the catalogue's solution");
        }
        assert!(
            out.min_distinct_lower <= 2 && out.min_distinct_upper >= 2,
            "{mode:?}"
        );
    }
    // C1 and C5 are disjoint, so at least 2; the catalogue's 2 is optimal.
    let out = atmost_nvector(2, &mut gccat(), Contractor::Exact).unwrap();
    assert_eq!((out.min_distinct_lower, out.min_distinct_upper), (2, 2));
}

#[test]
fn gccat_one_vector_is_infeasible() {
    // C1 = [1,6]x[2,6] and C5 = [9,11]x[0,5] are disjoint (x axis).
    for mode in ALL {
        let mut boxes = gccat();
        let out = atmost_nvector(1, &mut boxes, mode).unwrap();
        assert!(
            matches!(out.status, Status::Infeasible { .. }),
            "{mode:?}: {:?}",
            out.status
        );
        assert!(boxes.iter().all(|x| x.is_empty()));
    }
}

/// The paper's Figure 8 situation: k = 7, n = 3, on the first axis
/// x1 = [0,2], x2 = [1,3], x3 = [2,6], x4 = [5,7], x5 = [6,8], x6 = [7,12],
/// x7 = [11,13]. Left greedy by upper bound: points 2 (x1; x2, x3 stabbed),
/// 7 (x4; x5, x6 stabbed), 13 (x7): m = 3. Right greedy by lower bound:
/// 11 (x7; x6 stabbed), 6 (x5; x4, x3 stabbed), 1 (x2; x1 stabbed).
/// Kernels [1,2], [6,7], [11,13]. x1, x2 meet only the first: group {1,2}
/// -> [1,2]; x4, x5 only the second: group {4,5} -> [6,7]; x7 only the
/// third: {7} -> [11,13]; x3 = [2,6] and x6 = [7,12] meet two kernels and
/// keep their hulls. On the second axis everything overlaps (m = 1 < 3).
fn figure8() -> Vec<IntervalBox> {
    let x = [
        (0.0, 2.0),
        (1.0, 3.0),
        (2.0, 6.0),
        (5.0, 7.0),
        (6.0, 8.0),
        (7.0, 12.0),
        (11.0, 13.0),
    ];
    let y = [
        (0.0, 5.0),
        (3.0, 8.0),
        (0.0, 10.0),
        (0.0, 10.0),
        (0.0, 10.0),
        (0.0, 10.0),
        (0.0, 10.0),
    ];
    x.iter().zip(&y).map(|(&a, &c)| b(&[a, c])).collect()
}

#[test]
fn figure8_groups_on_the_first_axis() {
    let mut boxes = figure8();
    let out = atmost_nvector(3, &mut boxes, Contractor::Nvalue).unwrap();
    assert_eq!(out.status, Status::Contracted);
    let xs: Vec<(f64, f64)> = boxes.iter().map(|x| (x[0].lo(), x[0].hi())).collect();
    assert_eq!(
        xs,
        vec![
            (1.0, 2.0),
            (1.0, 2.0),
            (2.0, 6.0),
            (6.0, 7.0),
            (6.0, 7.0),
            (7.0, 12.0),
            (11.0, 13.0)
        ]
    );
    assert_eq!(
        out.groups,
        vec![vec![0, 1], vec![2], vec![3, 4], vec![5], vec![6]]
    );
    // nvalue leaves the second axis alone (it needs only 1 value there).
    assert_eq!(boxes[0][1], Interval::new(0.0, 5.0));
    assert_eq!(boxes[1][1], Interval::new(3.0, 8.0));
}

#[test]
fn figure8_projection_intersects_whole_boxes() {
    // x1 and x2 are the same vector: their second axes meet in [3,5].
    let mut boxes = figure8();
    let out = atmost_nvector(3, &mut boxes, Contractor::Projection).unwrap();
    assert_eq!(boxes[0], b(&[(1.0, 2.0), (3.0, 5.0)]));
    assert_eq!(boxes[1], b(&[(1.0, 2.0), (3.0, 5.0)]));
    assert_eq!(out.groups[0], vec![0, 1]);
    assert_eq!((out.min_distinct_lower, out.min_distinct_upper), (3, 3));
}

#[test]
fn independent_separates_what_projections_cannot() {
    // Three landmarks: A = [0,1]x[0,1], B = [4,5]x[2,3], C = [2,3]x[4,5]
    // (pairwise disjoint, n = 3). The x-kernels are [0,1], [2,3], [4,5] and
    // so are the y-kernels. F = [0.5,2.5]^2 straddles the first two kernels
    // on both axes, so per-axis reasoning neither groups nor shrinks it. In
    // 2-D, F misses B (x: 2.5 < 4) and C (y: 2.5 < 4): it meets only A, so it
    // is A's vector: F and A both become F ∩ A = [0.5,1]^2.
    let boxes0 = vec![
        b(&[(0.0, 1.0), (0.0, 1.0)]),
        b(&[(4.0, 5.0), (2.0, 3.0)]),
        b(&[(2.0, 3.0), (4.0, 5.0)]),
        b(&[(0.5, 2.5), (0.5, 2.5)]),
    ];
    let mut proj = boxes0.clone();
    let out = atmost_nvector(3, &mut proj, Contractor::Projection).unwrap();
    assert_eq!(out.status, Status::Unchanged);
    assert_eq!(proj, boxes0);
    let mut ind = boxes0.clone();
    let out = atmost_nvector(3, &mut ind, Contractor::Independent).unwrap();
    assert_eq!(ind[3], b(&[(0.5, 1.0), (0.5, 1.0)]));
    assert_eq!(ind[0], b(&[(0.5, 1.0), (0.5, 1.0)]));
    assert_eq!(out.groups, vec![vec![0, 3], vec![1], vec![2]]);
}

#[test]
fn single_box_and_slack_n_prune_nothing() {
    for mode in ALL {
        let mut one = vec![b(&[(0.0, 1.0), (2.0, 3.0)])];
        let out = atmost_nvector(1, &mut one, mode).unwrap();
        assert_eq!(out.status, Status::Unchanged, "{mode:?}");
        assert_eq!(out.groups, vec![vec![0]]);
        assert_eq!((out.min_distinct_lower, out.min_distinct_upper), (1, 1));
        // n >= k: every box can take its own vector.
        let mut boxes = gccat();
        let out = atmost_nvector(5, &mut boxes, mode).unwrap();
        assert_eq!(out.status, Status::Unchanged, "{mode:?}");
        assert_eq!(boxes, gccat());
    }
}

#[test]
fn exact_refuses_more_than_40_boxes() {
    let mut boxes: Vec<IntervalBox> = (0..41)
        .map(|i| b(&[(f64::from(i), f64::from(i) + 0.5)]))
        .collect();
    let err = atmost_nvector(41, &mut boxes, Contractor::Exact).unwrap_err();
    assert!(err.message.contains("at most 40"), "{err}");
}

#[test]
fn three_disjoint_boxes_with_n_2_are_infeasible() {
    for mode in ALL {
        let mut boxes = vec![b(&[(0.0, 1.0)]), b(&[(2.0, 3.0)]), b(&[(4.0, 5.0)])];
        let out = atmost_nvector(2, &mut boxes, mode).unwrap();
        match out.status {
            Status::Infeasible { reason } => assert!(reason.contains("n = 2"), "{reason}"),
            s => panic!("{mode:?}: {s:?}"),
        }
    }
}
