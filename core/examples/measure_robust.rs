//! Measurements of the robust propagation's stages on mission files (with
//! truth: `nvector simulate` or `nvector import` output), printed one line
//! per file; not checks (the tests are core/tests/slam/robust/):
//!
//! ```text
//! cargo run --release -p nvector-core --example measure_robust -- packing a.json b.json
//! cargo run --release -p nvector-core --example measure_robust -- cliques a.json
//! NVECTOR_CLIQUE_LIMITS=ahead,per_detection,nodes,nodes_each \
//!   cargo run --release -p nvector-core --example measure_robust -- free-conflicts a.json
//! ```
//!
//! `packing`: what the conflict packing finds (BENCHMARKS.md, the conflict
//! packing on branch `qten`); `cliques`: the free conflicts and the packing,
//! with the time taken; `free-conflicts`: what the free conflicts prove on
//! large missions (docs/outliers.md, "Free conflicts on CMU Plaza 1").

// A tool run by hand: it reads files and the clock, which core itself never
// does.
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::model::Model;
use nvector_core::slam::robust::cliques::clique_conflicts;
use nvector_core::slam::robust::conflicts::{pack, Packing};
use nvector_core::slam::types::{Association, SolveOptions};
use std::sync::atomic::AtomicBool;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((what, paths)) = args.split_first() else {
        eprintln!("usage: measure_robust packing|cliques|free-conflicts MISSION.json...");
        std::process::exit(2);
    };
    match what.as_str() {
        "packing" => packing(paths),
        "cliques" => cliques(paths),
        "free-conflicts" => free_conflicts(paths),
        other => {
            eprintln!("unknown measurement {other:?}: packing, cliques or free-conflicts");
            std::process::exit(2);
        }
    }
}

/// Detections in (step, index) order.
fn order_of(m: &Mission) -> Vec<usize> {
    let mut order: Vec<usize> = (0..m.detections.len()).collect();
    order.sort_by_key(|&j| (m.detections[j].step, j));
    order
}

/// What the packing finds on each file.
fn packing(paths: &[String]) {
    let options = SolveOptions {
        association: Association::NVector(Contractor::Best),
        ..SolveOptions::default()
    };
    let cancel = AtomicBool::new(false);
    for path in paths {
        let text = std::fs::read_to_string(path).unwrap();
        let m = Mission::from_json(&text).unwrap();
        let truth = m.truth.as_ref().unwrap().matching.clone();
        let k = m.detections.len();
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by_key(|&j| (m.detections[j].step, j));
        let r = pack(
            &m,
            m.max_outliers,
            &vec![false; k],
            &order,
            &options,
            &cancel,
        );
        match r {
            Packing::Proved {
                proved_false,
                conflicts,
                positions,
                solves,
                ..
            } => {
                let sizes: Vec<String> = conflicts
                    .iter()
                    .map(|c| {
                        let ph = c.iter().filter(|&&j| truth[j].is_none()).count();
                        format!("{}({}ph)", c.len(), ph)
                    })
                    .collect();
                let pf: Vec<bool> = proved_false
                    .iter()
                    .enumerate()
                    .filter(|(_, &f)| f)
                    .map(|(j, _)| truth[j].is_none())
                    .collect();
                println!(
                    "{path}: k {k} q {} unresolved {} [{}] proved false {} (phantoms {}) positions {} solves {solves}",
                    m.max_outliers,
                    conflicts.len(),
                    sizes.join(" "),
                    pf.len(),
                    pf.iter().filter(|&&b| b).count(),
                    positions.is_some(),
                );
            }
            other => println!("{path}: {other:?}"),
        }
    }
}

/// The cliques per phantom and what the packing proves, with the time
/// the packing took.
fn cliques(paths: &[String]) {
    let options = SolveOptions {
        association: Association::NVector(Contractor::Best),
        ..SolveOptions::default()
    };
    let cancel = AtomicBool::new(false);
    for path in paths {
        let m = Mission::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
        let truth = m.truth.as_ref().unwrap().matching.clone();
        let k = m.detections.len();
        let order = order_of(&m);
        let cliques = clique_conflicts(&m, &Model::new(&m), &vec![true; k], &order);
        let mut with = vec![0usize; k];
        for c in &cliques {
            for &j in c {
                with[j] += 1;
            }
        }
        let phantoms: Vec<usize> = (0..k).filter(|&j| truth[j].is_none()).collect();
        let per: Vec<usize> = phantoms.iter().map(|&j| with[j]).collect();
        let t0 = std::time::Instant::now();
        let r = pack(
            &m,
            m.max_outliers,
            &vec![false; k],
            &order,
            &options,
            &cancel,
        );
        let secs = t0.elapsed().as_secs_f64();
        let summary = match r {
            Packing::Proved {
                proved_false,
                solves,
                ..
            } => format!(
                "proved false {} (phantoms {}) solves {solves}",
                proved_false.iter().filter(|&&f| f).count(),
                phantoms.iter().filter(|&&j| proved_false[j]).count()
            ),
            other => format!("{other:?}"),
        };
        println!(
            "{path}: k {k} cliques {} per phantom {per:?}; {summary} {secs:.1} s",
            cliques.len()
        );
    }
}

/// The distance of two 2-D points.
fn dist(p: &[f64], q: &[f64]) -> f64 {
    let (dx, dy) = (p[0] - q[0], p[1] - q[1]);
    (dx * dx + dy * dy).sqrt()
}

/// Whether detection j of `m` is false by the truth: no landmark (a
/// planted range), or its true distance outside its range interval (a
/// tight band's outlier). Range-only, 2-D.
fn false_by_truth(m: &Mission, j: usize) -> bool {
    let t = m.truth.as_ref().unwrap();
    let d = &m.detections[j];
    let Some(l) = t.matching[j] else {
        return true;
    };
    let (p, q) = (&t.positions[d.step], &t.landmarks[l]);
    let r = dist(p, q);
    r < d.range.lo() || r > d.range.hi()
}

/// What the free conflicts prove on large missions (CMU Plaza 1 with
/// planted false ranges or a tight band: docs/outliers.md, "Free conflicts
/// on CMU Plaza 1"): the cliques found with the limits
/// `NVECTOR_CLIQUE_LIMITS=ahead,per_detection,nodes,nodes_each`, how many
/// false detections they hold, their components, the sum of the
/// components' minimum hitting sets against q, and what `forced` proves.
fn free_conflicts(paths: &[String]) {
    use nvector_core::slam::robust::cliques::{clique_conflicts_with, Limits};
    use nvector_core::slam::robust::hitting::{components, forced, minimum, Forced, Hit};
    let mut limits = Limits::default();
    if let Ok(l) = std::env::var("NVECTOR_CLIQUE_LIMITS") {
        let v: Vec<u64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        (limits.ahead, limits.per_detection) = (v[0] as usize, v[1] as usize);
        (limits.nodes, limits.nodes_each) = (v[2], v[3]);
    }
    for path in paths {
        let m = Mission::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
        let k = m.detections.len();
        let t0 = std::time::Instant::now();
        let cliques =
            clique_conflicts_with(&m, &Model::new(&m), &vec![true; k], &order_of(&m), &limits);
        let secs = t0.elapsed().as_secs_f64();
        let bad: Vec<usize> = (0..k).filter(|&j| false_by_truth(&m, j)).collect();
        // False ranges that hold some landmark's true distance: the truth
        // keeping them is a solution (never refutable).
        let t = m.truth.as_ref().unwrap();
        let fit = bad
            .iter()
            .filter(|&&j| {
                let d = &m.detections[j];
                let p = &t.positions[d.step];
                t.landmarks.iter().any(|l| {
                    let r = dist(p, l);
                    d.range.lo() <= r && r <= d.range.hi()
                })
            })
            .count();
        let held = bad
            .iter()
            .filter(|&&j| cliques.iter().any(|c| c.contains(&j)))
            .count();
        let (mut sum, mut margins) = (0, Vec::new());
        for comp in components(&cliques) {
            let fam: Vec<Vec<usize>> = comp.iter().map(|&i| cliques[i].clone()).collect();
            let mut w = 5_000_000;
            let Hit::Found(h) = minimum(&fam, &[], m.max_outliers, &mut w) else {
                continue;
            };
            sum += h.len();
            let mut best = 0;
            for &x in &h {
                let mut ban = vec![false; k];
                ban[x] = true;
                let mut w = 5_000_000;
                if let Hit::Found(h2) = minimum(&fam, &ban, m.max_outliers, &mut w) {
                    best = best.max(h2.len() - h.len());
                }
            }
            margins.push(best);
        }
        let (mut fam, mut b, mut proved) = (cliques.clone(), m.max_outliers, 0);
        let mut work = 20_000_000;
        while let Forced::Members(xs) = forced(&fam, b, &mut work) {
            if xs.is_empty() {
                break;
            }
            assert!(xs.iter().all(|&j| false_by_truth(&m, j)), "{path}: {xs:?}");
            (b, proved) = (b - xs.len(), proved + xs.len());
            fam.retain(|c| !c.iter().any(|j| xs.contains(j)));
        }
        println!(
            "{path}: {limits:?}: k {k}, q {}, false by the truth {} ({fit} fitting a landmark), {} cliques in {secs:.2} s, holding {held} of them; \
             components' minimum hitting sets sum to {sum} (slack {}), best margin per component {margins:?}; proved false {proved}",
            m.max_outliers,
            bad.len(),
            cliques.len(),
            m.max_outliers.saturating_sub(sum)
        );
    }
}
