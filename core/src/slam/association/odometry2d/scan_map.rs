//! Scan registration against the closed-world map (odometry2d): the
//! detections of one scan are matched to a set M of groups proved pairwise
//! distinct by the distances between them, which the scan knows in the
//! robot's own frame whatever the heading; a detection that every
//! consistent matching sends to one group joins it.
//!
//! # Constraint
//!
//! atmost_nvector(n) over the detections; detections of one scan see
//! pairwise distinct landmarks; distinct landmarks are at least s apart
//! (`landmark_min_separation`); every detection sees a real landmark
//! (`max_outliers` = 0); the range-and-bearing constraint of each
//! detection from its sensor point `p + R(th) o`.
//!
//! # Math
//!
//! **The map.** Groups of two or more detections are taken tightest box first
//! into M when they are proved distinct from every group already in M:
//! their landmark boxes have no common point (the Euclidean distance
//! between the boxes has a positive lower bound), or a member of each sits
//! in one scan. M holds at most n groups, pairwise distinct landmarks.
//!
//! **The scan.** Detection a of a scan, at range r_a and bearing b_a from
//! the sensor point (offset o in the body frame), has its landmark at
//! `q_a = o + r_a (cos b_a, sin b_a)` in the robot frame; so for two
//! detections a, b of the scan `|l(a) - l(b)| = |q_a - q_b|` lies in the
//! interval D_ab computed from the measurements alone (a rotation keeps
//! distances; the pose is not read). For groups g, h of M with boxes
//! B_g, B_h, `|l(g) - l(h)|` lies in `D(B_g, B_h)`, the interval
//! evaluation of the Euclidean distance over the two boxes.
//!
//! **The matching.** Each detection a of the scan takes a value in
//! `dom(a)`: a group g of M whose box meets a's landmark box (a's own group
//! when that group is in M); and, when M has fewer than n groups, the
//! value "new" (a landmark of no group of M), kept only while `D(d(a),
//! B_g)` reaches s for every g of M. A matching assigns every detection a
//! value so that group values are injective over the scan (its landmarks
//! are pairwise distinct), `D_ab` meets `D(B_g, B_h)` for a -> g, b -> h,
//! and `D_ab` reaches s for a -> new, b -> h, and at most n - |M|
//! detections take "new" (the scan's landmarks are pairwise distinct and
//! only n - |M| landmarks are outside M). Every (a, v) is checked by a
//! depth-first search with forward checking for one matching using it
//! (each matching found marks all its pairs as supported); a value with no
//! matching is removed. A detection left with the single value g is in g.
//!
//! # Soundness
//!
//! The true matching a -> (the group of M seeing l(a), or new when none
//! does) satisfies every constraint: d(a) and B_g both hold l(a) = l(g),
//! so they meet; `|l(a) - l(b)|` is in D_ab (outward-rounded interval
//! arithmetic over the measurement intervals) and in `D(B_g, B_h)`; two
//! detections of one scan are distinct landmarks and so are two groups of
//! M, so group values are injective; a new landmark is distinct from every
//! landmark of M, hence at least s from it, and the scan's new landmarks
//! are pairwise distinct landmarks outside M's |M|, so at most n - |M|
//! of them. With |M| = n, the n groups hold
//! the n landmarks (closed world) and "new" is not a value. So the true
//! matching survives every removal, and a single value left is the true
//! one. The search gives up (proves nothing for the scan) beyond its node
//! budget; an empty domain proves the mission infeasible. Boxes read
//! during a pass hold their landmarks at every moment (contractions keep
//! every solution), so a map built earlier in the pass stays sound.
//!
//! # Complexity
//!
//! Building the map: O(k) for the groups, O(G n) for the greedy choice, O(n^2)
//! distances. Per scan of c detections: O(c n) domains, at most
//! `node_budget` search nodes of O(c) each. Memory O(k + n^2).

use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::slam::mission::Mission;
use crate::union_find::Uf;
use std::collections::BTreeSet;

/// Search nodes allowed for one scan before it proves nothing.
const NODE_BUDGET: usize = 20_000;

/// The "new landmark" value's bit (groups of M use bits 0..n, n <= 63).
const NEW: u32 = 63;

/// The closed-world map of a pass (module doc).
#[derive(Debug, Clone)]
pub struct ScanMap {
    /// A member of each group of M.
    reps: Vec<usize>,
    /// D(B_g, B_h), |M|² row-major, from the boxes when the map was built.
    dist: Vec<Interval>,
    /// How many detections of one scan may take "new": n - |M| (the
    /// landmarks outside M); 0: the closed world.
    new_max: usize,
    /// The minimum separation s (0: none stated).
    s: f64,
    /// The sensor offset (body frame).
    offset: [f64; 2],
}

/// The Euclidean distance between two 2-D boxes, as an interval.
fn box_distance(a: &IntervalBox, b: &IntervalBox) -> Interval {
    let dx = a[0] - b[0];
    let dy = a[1] - b[1];
    (dx.sqr() + dy.sqr()).sqrt()
}

/// Whether two groups are proved distinct: disjoint boxes or a common scan.
fn distinct(
    a: &IntervalBox,
    b: &IntervalBox,
    scans_a: &BTreeSet<u64>,
    scans_b: &BTreeSet<u64>,
) -> bool {
    box_distance(a, b).lo() > 0.0 || scans_a.intersection(scans_b).next().is_some()
}

impl ScanMap {
    /// The map of the current groups (`uf`) and landmark boxes `det`
    /// (2-D); None when there is nothing to register against (n = 0, n > 63,
    /// or not 2-D).
    pub fn new(mission: &Mission, det: &[IntervalBox], uf: &mut Uf, n: usize) -> Option<ScanMap> {
        if n == 0 || n > 62 || det.first().is_none_or(|b| b.dim() != 2) {
            return None;
        }
        let groups = uf.groups();
        let mut cand: Vec<(f64, usize, BTreeSet<u64>)> = groups
            .iter()
            .filter(|g| !det[g[0]].is_empty())
            .map(|g| {
                // Inserted one by one: `collect` into a set sorts first
                // (std's stable sort, its own copy in the page's wasm).
                let mut scans = BTreeSet::new();
                scans.extend(g.iter().filter_map(|&j| mission.detections[j].scan));
                (det[g[0]].diameter(), g[0], scans)
            })
            .filter(|c| c.0.is_finite())
            .collect();
        crate::sort::stable_by(&mut cand, |a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut chosen: Vec<(usize, BTreeSet<u64>)> = Vec::new();
        for (_, r, scans) in cand {
            if chosen.len() == n {
                break;
            }
            if chosen
                .iter()
                .all(|(c, cs)| distinct(&det[r], &det[*c], &scans, cs))
            {
                chosen.push((r, scans));
            }
        }
        let reps: Vec<usize> = chosen.into_iter().map(|c| c.0).collect();
        let m = reps.len();
        let mut dist = vec![Interval::ENTIRE; m * m];
        for (x, &g) in reps.iter().enumerate() {
            for (y, &h) in reps.iter().enumerate() {
                dist[x * m + y] = box_distance(&det[g], &det[h]);
            }
        }
        Some(ScanMap {
            reps,
            dist,
            new_max: n - m,
            s: mission.landmark_min_separation.max(0.0),
            offset: mission.sensor_offset.unwrap_or([0.0, 0.0]),
        })
    }

    /// How many groups the map holds.
    pub fn len(&self) -> usize {
        self.reps.len()
    }

    /// Whether the map holds no group.
    pub fn is_empty(&self) -> bool {
        self.reps.is_empty()
    }

    /// The robot-frame landmark point of detection `j` (module doc);
    /// None without a bearing.
    fn frame_point(&self, mission: &Mission, j: usize) -> Option<[Interval; 2]> {
        let d = &mission.detections[j];
        let b = d.bearing?;
        let r = d.range.intersect(Interval::new(0.0, f64::INFINITY));
        if r.is_empty() || b.is_empty() {
            return None;
        }
        Some([
            Interval::point(self.offset[0]) + r * b.cos(),
            Interval::point(self.offset[1]) + r * b.sin(),
        ])
    }

    /// Matches the detections `scan` (one scan: pairwise distinct
    /// landmarks) against the map; returns the unions (detection, a member
    /// of its group) it proves. Err: no matching at all (infeasible).
    pub fn settle(
        &self,
        mission: &Mission,
        det: &[IntervalBox],
        uf: &mut Uf,
        scan: &[usize],
    ) -> Result<Vec<(usize, usize)>, String> {
        let m = self.reps.len();
        let roots: Vec<usize> = self.reps.iter().map(|&r| uf.find(r)).collect();
        let mut vars = Vec::new();
        let mut doms = Vec::new();
        let mut points = Vec::new();
        let mut open_left = false;
        for &a in scan {
            let Some(q) = self.frame_point(mission, a) else {
                continue;
            };
            let ra = uf.find(a);
            let mut dom = 0u64;
            if let Some(x) = roots.iter().position(|&r| r == ra) {
                dom |= 1 << x;
            } else {
                open_left = true;
                for (x, &r) in roots.iter().enumerate() {
                    if det[a].meets(&det[r]) {
                        dom |= 1 << x;
                    }
                }
                let far = roots
                    .iter()
                    .all(|&r| box_distance(&det[a], &det[r]).hi() >= self.s);
                if self.new_max > 0 && far {
                    dom |= 1 << NEW;
                }
            }
            vars.push(a);
            doms.push(dom);
            points.push(q);
        }
        if !open_left {
            return Ok(Vec::new());
        }
        let c = vars.len();
        let dab = pair_distances(&points);
        let search = Search {
            m,
            s: self.s,
            dist: &self.dist,
            dab: &dab,
            c,
            nodes: 0,
            new_max: self.new_max,
        };
        let Some(kept) = search.supported(&doms) else {
            return Ok(Vec::new());
        };
        let mut unions = Vec::new();
        for (&a, &dom) in vars.iter().zip(&kept) {
            if dom == 0 {
                return Err(format!(
                    "detection {a} (step {}): no matching of its scan onto the {m} groups proved distinct fits the distances",
                    mission.detections[a].step
                ));
            }
            if dom.count_ones() == 1 && dom != 1 << NEW {
                let g = dom.trailing_zeros() as usize;
                if uf.find(a) != roots[g] {
                    unions.push((a, roots[g]));
                }
            }
        }
        Ok(unions)
    }
}

/// `|q_x - q_y|` for every ordered pair of the scan's robot-frame points
/// (c² intervals, row-major; the diagonal unused).
fn pair_distances(points: &[[Interval; 2]]) -> Vec<Interval> {
    let c = points.len();
    let mut dab = vec![Interval::ENTIRE; c * c];
    for x in 0..c {
        for y in 0..c {
            if x != y {
                let dx = points[x][0] - points[y][0];
                let dy = points[x][1] - points[y][1];
                dab[x * c + y] = (dx.sqr() + dy.sqr()).sqrt();
            }
        }
    }
    dab
}

/// The matching search of one scan (module doc).
struct Search<'a> {
    m: usize,
    s: f64,
    dist: &'a [Interval],
    dab: &'a [Interval],
    c: usize,
    nodes: usize,
    /// Most detections taking "new" in one matching.
    new_max: usize,
}

impl Search<'_> {
    /// Whether detection x -> value u and y -> value v fit together.
    fn fits(&self, x: usize, u: u32, y: usize, v: u32) -> bool {
        let d = self.dab[x * self.c + y];
        match (u == NEW, v == NEW) {
            (true, true) => true,
            (true, false) | (false, true) => d.hi() >= self.s,
            (false, false) => u != v && d.meets(self.dist[u as usize * self.m + v as usize]),
        }
    }

    /// The values of each domain that some matching uses; None: the node
    /// budget ran out (nothing proved).
    fn supported(mut self, doms: &[u64]) -> Option<Vec<u64>> {
        let mut seen = vec![0u64; self.c];
        let mut assign = vec![0u32; self.c];
        for x in 0..self.c {
            let mut rest = doms[x] & !seen[x];
            while rest != 0 {
                let v = rest.trailing_zeros();
                rest &= rest - 1;
                if seen[x] & (1 << v) != 0 {
                    continue;
                }
                let mut d = doms.to_vec();
                d[x] = 1 << v;
                if self.solve(&mut d, &mut assign, 0)? {
                    for (y, &w) in assign.iter().enumerate() {
                        seen[y] |= 1 << w;
                    }
                }
            }
        }
        Some(seen)
    }

    /// Forward checking of x -> u: every other unassigned domain keeps the
    /// values that fit with it (not "new" when `no_new`); false when one
    /// empties.
    fn forward(&self, d: &mut [u64], x: usize, u: u32, no_new: bool) -> bool {
        for (y, dy) in d.iter_mut().enumerate() {
            if y == x || *dy & (1 << 62) != 0 {
                continue;
            }
            let mut keep = 0u64;
            let mut vs = *dy;
            if no_new {
                vs &= !(1 << NEW);
            }
            while vs != 0 {
                let v = vs.trailing_zeros();
                vs &= vs - 1;
                if self.fits(x, u, y, v) {
                    keep |= 1 << v;
                }
            }
            *dy = keep;
            if keep == 0 {
                return false;
            }
        }
        true
    }

    /// Depth-first search with forward checking over `d` (`news`: the
    /// detections assigned "new" so far); on success `assign` holds a
    /// matching. None: out of budget.
    fn solve(&mut self, d: &mut [u64], assign: &mut [u32], news: usize) -> Option<bool> {
        self.nodes += 1;
        if self.nodes > NODE_BUDGET {
            return None;
        }
        // The unassigned variable with the fewest values (a variable is
        // assigned when its value is recorded: `assign` past `done`).
        let mut best: Option<usize> = None;
        for x in 0..self.c {
            if d[x] & (1 << 62) != 0 {
                continue;
            }
            if best.is_none_or(|b| d[x].count_ones() < d[b].count_ones()) {
                best = Some(x);
            }
        }
        let Some(x) = best else {
            return Some(true);
        };
        let mut rest = d[x];
        while rest != 0 {
            let u = rest.trailing_zeros();
            rest &= rest - 1;
            let saved = d.to_vec();
            let news = news + usize::from(u == NEW);
            let ok = news <= self.new_max && self.forward(d, x, u, news == self.new_max);
            if ok {
                assign[x] = u;
                d[x] = (1 << 62) | (1 << u);
                if self.solve(d, assign, news)? {
                    return Some(true);
                }
            }
            d.copy_from_slice(&saved);
        }
        Some(false)
    }
}
