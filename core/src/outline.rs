//! Outlines for drawing: polygons that ENCLOSE a detection shape
//! ([`Shape`]: an annulus or annular sector around an uncertain centre, cut
//! by a box) and the exact boundary of a landmark region (a union of boxes),
//! in the first two axes (x, y).
//!
//! # Which way, and why
//!
//! Every outline encloses its set: a drawn shape never hides a point where
//! the landmark may be. A reader takes an empty part of the picture as "the
//! landmark is not there", so the drawing may only err on the side of more
//! ink, as the contractors only err on the side of larger boxes. The
//! property tests below plant points of the true set and check they are
//! inside; they also check that what must be out (the centre of a ring's
//! hole, a point behind a sector) stays out, so that the outline is not
//! trivially large.
//!
//! # The shape's outline (`shape_outline`)
//!
//! With P the centre box (x, y), r = [lo, hi] the range, the sector
//! S = heading + bearing (absolute angles; all angles without a bearing)
//! and C the cut box, the shape is
//! `A = {p + t u(φ) : p ∈ P, t ∈ r, φ ∈ S} ∩ C`, u(φ) = (cos φ, sin φ).
//! It is drawn as the region between two polygons filled with the nonzero
//! rule: `outer` counter-clockwise, `hole` clockwise (null when there is
//! none), so that shapes can share one path and overlap as a union:
//! - outer ⊇ P ⊕ disk(hi): the box grown by hi with rounded corners, each
//!   quarter circle replaced by its circumscribed polygon (tangent points at
//!   the ends, `ARC_STEPS` vertices at radius hi / cos(δ/2) in between);
//! - hole ⊆ {x : max_{p∈P} |x - p| < lo}: the intersection of the four disks
//!   of radius lo around P's corners, each arc replaced by its inscribed
//!   polygon (chords lie inside a disk, and the hole is convex);
//! - with a sector narrower than π, both are clipped by the cone P ⊕ T with
//!   T the triangle {0, L u(S.lo), L u(S.hi)}, L = hi / cos(width(S)/2): T
//!   holds the circular sector of radius hi, so P ⊕ T holds P ⊕ sector;
//! - both clipped by C (Sutherland–Hodgman, convex clip polygons).
//!
//! Filled: (outer \ hole) ∩ cone ∩ C ⊇ A. In 3-D the horizontal distance is
//! at least sqrt(lo² - dz²) with dz the largest depth difference between P
//! and C, which replaces lo (hi stays: the horizontal distance is at most the
//! distance).
//!
//! Rounding: the polygon's vertices go through a few rounded operations
//! (cos, sin, products, the clipping's intersection points), each with a
//! relative error near 2^-53; the outer radii are grown and the hole's
//! radius shrunk by `SLACK` (1e-9) times the picture's scale, far above that
//! error and far below a pixel, so the enclosure holds in floating point.
//! The angles use libm (same bits native and wasm).
//!
//! # The region's outline (`union_outline`)
//!
//! The boundary of the union of boxes, as closed loops (outer boundaries
//! counter-clockwise, holes clockwise): the box bounds are compressed into a
//! grid, the covered cells marked with a 2-D difference array, and the edges
//! between covered and uncovered cells chained into loops. Every vertex is
//! one of the boxes' own bounds, so the outline is exact: no rounding.
//!
//! # Complexity
//!
//! `shape_outline`: O(ARC_STEPS) vertices and time per shape, no allocation
//! sized by an input number. `union_outline`: O(n log n + g²) for n boxes
//! and a grid of g ≤ 2n lines per axis; above `MAX_UNION_BOXES` boxes it
//! returns the boxes' own rectangles (still an enclosure), so that the grid
//! stays under 4 · MAX_UNION_BOXES² cells.

use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::shapes::shape::Shape;

/// Polygon vertices per quarter circle (between the two tangent points).
pub const ARC_STEPS: usize = 6;

/// Relative slack of the outer radii and the hole's radius (see the module
/// doc, "Rounding").
pub const SLACK: f64 = 1e-9;

/// Most boxes whose union is traced exactly (see the module doc).
pub const MAX_UNION_BOXES: usize = 1000;

/// A point (x, y).
pub type Point = [f64; 2];

/// The outline of one shape: the region between `outer` (counter-clockwise)
/// and `hole` (clockwise), filled with the nonzero rule.
#[derive(Debug, Clone, PartialEq)]
pub struct Outline {
    /// Counter-clockwise polygon enclosing the shape.
    pub outer: Vec<Point>,
    /// Clockwise polygon inside the shape's hole (none when lo is too small
    /// for a hole, or the hole is cut away).
    pub hole: Option<Vec<Point>>,
}

const PI: f64 = core::f64::consts::PI;

/// The outline of a shape in its first two axes, or `None` when nothing can
/// be drawn: an empty shape, a centre or range that is unbounded, a shape
/// with fewer than 2 axes, or a shape cut away entirely.
pub fn shape_outline(s: &Shape) -> Option<Outline> {
    if s.dim() < 2 || s.is_empty() {
        return None;
    }
    let (px, py) = (s.centre[0], s.centre[1]);
    let hi = s.range.hi();
    if !(px.is_bounded() && py.is_bounded() && hi.is_finite()) {
        return None;
    }
    let lo = horizontal_lo(s);
    let scale = 1.0 + hi + px.mag().max(py.mag());
    let slack = SLACK * scale;
    let b = Rect {
        x0: px.lo(),
        x1: px.hi(),
        y0: py.lo(),
        y1: py.hi(),
    };
    let mut outer = outer_polygon(&b, hi + slack);
    let mut hole = if lo > slack {
        hole_polygon(&b, lo - slack)
    } else {
        None
    };
    if let Some((heading, bearing)) = s.bearing {
        let sector = heading.add_outward(bearing);
        if sector.is_bounded() && sector.width() < PI - 1e-6 {
            let cone = cone_polygon(&b, sector, hi, slack);
            outer = clip_convex(&outer, &cone);
            hole = hole.map(|h| clip_convex(&h, &cone));
        }
    }
    let c = Rect {
        x0: s.cut[0].lo(),
        x1: s.cut[0].hi(),
        y0: s.cut[1].lo(),
        y1: s.cut[1].hi(),
    };
    outer = clip_rect(&outer, &c);
    hole = hole.map(|h| clip_rect(&h, &c));
    if outer.len() < 3 {
        return None;
    }
    Some(Outline {
        outer,
        hole: hole.filter(|h| h.len() >= 3),
    })
}

/// The smallest horizontal distance the range allows: lo in 2-D; in 3-D
/// sqrt(lo² - dz²) (0 when dz ≥ lo or dz is unbounded), dz the largest
/// depth difference between the centre and the cut, rounded down.
fn horizontal_lo(s: &Shape) -> f64 {
    let lo = s.range.lo().max(0.0);
    if s.dim() < 3 {
        return lo;
    }
    let dz = s.centre[2].sub(s.cut[2]).abs().hi();
    if !dz.is_finite() {
        return 0.0;
    }
    let d2 = Interval::point(lo)
        .sqr()
        .sub(Interval::point(dz).sqr())
        .lo();
    if d2 > 0.0 {
        Interval::point(d2).sqrt().lo()
    } else {
        0.0
    }
}

/// An axis-aligned rectangle (bounds may be infinite for a cut).
struct Rect {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
}

/// Appends the circumscribed polygon of the arc of radius r around c from
/// angle t0 to t1 (a quarter turn): the two tangent points and `ARC_STEPS`
/// points at radius r / cos(δ/2) between them.
fn arc_outside(pts: &mut Vec<Point>, c: Point, r: f64, t0: f64, t1: f64) {
    let d = (t1 - t0) / ARC_STEPS as f64;
    let far = r / libm::cos(d / 2.0) * (1.0 + SLACK);
    pts.push([c[0] + r * libm::cos(t0), c[1] + r * libm::sin(t0)]);
    for k in 0..ARC_STEPS {
        let t = t0 + (k as f64 + 0.5) * d;
        pts.push([c[0] + far * libm::cos(t), c[1] + far * libm::sin(t)]);
    }
    pts.push([c[0] + r * libm::cos(t1), c[1] + r * libm::sin(t1)]);
}

/// Counter-clockwise polygon holding every point within r of the box.
fn outer_polygon(b: &Rect, r: f64) -> Vec<Point> {
    let mut pts = Vec::with_capacity(4 * (ARC_STEPS + 2));
    arc_outside(&mut pts, [b.x1, b.y0], r, -PI / 2.0, 0.0);
    arc_outside(&mut pts, [b.x1, b.y1], r, 0.0, PI / 2.0);
    arc_outside(&mut pts, [b.x0, b.y1], r, PI / 2.0, PI);
    arc_outside(&mut pts, [b.x0, b.y0], r, PI, 1.5 * PI);
    pts
}

/// Appends the inscribed polygon of the clockwise arc of radius r around c
/// from point a towards point e (e itself left out).
fn arc_inside_cw(pts: &mut Vec<Point>, c: Point, r: f64, a: Point, e: Point) {
    let t0 = libm::atan2(a[1] - c[1], a[0] - c[0]);
    let mut d = libm::atan2(e[1] - c[1], e[0] - c[0]) - t0;
    while d > 0.0 {
        d -= 2.0 * PI;
    }
    while d <= -2.0 * PI {
        d += 2.0 * PI;
    }
    for k in 0..ARC_STEPS {
        let t = t0 + (k as f64) * d / ARC_STEPS as f64;
        pts.push([c[0] + r * libm::cos(t), c[1] + r * libm::sin(t)]);
    }
}

/// Clockwise polygon inside the points whose farthest distance to the box
/// is below r (the intersection of the disks of radius r around its
/// corners), or `None` when that set is empty.
fn hole_polygon(b: &Rect, r: f64) -> Option<Vec<Point>> {
    let a = (b.x1 - b.x0) / 2.0;
    let h = (b.y1 - b.y0) / 2.0;
    // Shrunk a little more so that the square roots' rounding stays inside.
    let r = r * (1.0 - SLACK);
    if r * r <= (a * a + h * h) * (1.0 + 1e-12) {
        return None;
    }
    let (cx, cy) = ((b.x0 + b.x1) / 2.0, (b.y0 + b.y1) / 2.0);
    let sa = (r * r - a * a).sqrt();
    let sh = (r * r - h * h).sqrt();
    // The hole's top, right, bottom and left points; each quadrant's arc is
    // centred on the opposite corner.
    let top = [cx, b.y0 + sa];
    let right = [b.x0 + sh, cy];
    let bottom = [cx, b.y1 - sa];
    let left = [b.x1 - sh, cy];
    let mut pts = Vec::with_capacity(4 * ARC_STEPS);
    arc_inside_cw(&mut pts, [b.x0, b.y0], r, top, right);
    arc_inside_cw(&mut pts, [b.x0, b.y1], r, right, bottom);
    arc_inside_cw(&mut pts, [b.x1, b.y1], r, bottom, left);
    arc_inside_cw(&mut pts, [b.x1, b.y0], r, left, top);
    Some(pts)
}

/// The cone P ⊕ T (module doc) as a counter-clockwise convex polygon.
fn cone_polygon(b: &Rect, sector: Interval, r: f64, slack: f64) -> Vec<Point> {
    let far = r / libm::cos(sector.width() / 2.0) * (1.0 + SLACK) + slack;
    let dirs = [
        [0.0, 0.0],
        [far * libm::cos(sector.lo()), far * libm::sin(sector.lo())],
        [far * libm::cos(sector.hi()), far * libm::sin(sector.hi())],
    ];
    let mut pts = Vec::with_capacity(12);
    for c in [[b.x0, b.y0], [b.x1, b.y0], [b.x1, b.y1], [b.x0, b.y1]] {
        for d in dirs {
            pts.push([c[0] + d[0], c[1] + d[1]]);
        }
    }
    convex_hull(pts)
}

/// Counter-clockwise convex hull (monotone chain).
fn convex_hull(mut p: Vec<Point>) -> Vec<Point> {
    p.sort_by(|u, v| u[0].total_cmp(&v[0]).then(u[1].total_cmp(&v[1])));
    let cross = |o: Point, a: Point, b: Point| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let half = |list: &mut dyn Iterator<Item = Point>| {
        let mut h: Vec<Point> = Vec::new();
        for q in list {
            while h.len() >= 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
        h
    };
    let mut lower = half(&mut p.iter().copied());
    let upper = half(&mut p.iter().rev().copied());
    lower.extend(upper);
    lower
}

/// Sutherland–Hodgman: the part of the polygon where n · x <= c.
fn clip_half(pts: &[Point], n: Point, c: f64) -> Vec<Point> {
    let mut out = Vec::with_capacity(pts.len() + 2);
    let Some(&last) = pts.last() else {
        return out;
    };
    let f = |q: Point| n[0] * q[0] + n[1] * q[1] - c;
    let (mut p, mut fp) = (last, f(last));
    for &q in pts {
        let fq = f(q);
        if (fq <= 0.0) != (fp <= 0.0) {
            let t = fp / (fp - fq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
        if fq <= 0.0 {
            out.push(q);
        }
        (p, fp) = (q, fq);
    }
    out
}

/// Clips a polygon by a convex counter-clockwise polygon.
fn clip_convex(pts: &[Point], clip: &[Point]) -> Vec<Point> {
    let mut out = pts.to_vec();
    for (i, &a) in clip.iter().enumerate() {
        let b = clip[(i + 1) % clip.len()];
        // Inside is to the left of a -> b: (b - a) × (x - a) >= 0.
        let e = [b[0] - a[0], b[1] - a[1]];
        out = clip_half(&out, [e[1], -e[0]], e[1] * a[0] - e[0] * a[1]);
        if out.is_empty() {
            break;
        }
    }
    out
}

/// Clips a polygon by a rectangle (infinite sides cut nothing).
fn clip_rect(pts: &[Point], r: &Rect) -> Vec<Point> {
    let mut out = pts.to_vec();
    for (n, c) in [
        ([-1.0, 0.0], -r.x0),
        ([1.0, 0.0], r.x1),
        ([0.0, -1.0], -r.y0),
        ([0.0, 1.0], r.y1),
    ] {
        if c.is_finite() {
            out = clip_half(&out, n, c);
        } else if c < 0.0 {
            return Vec::new();
        }
    }
    out
}

/// The boundary of the union of the boxes' first two axes as closed loops
/// (outer boundaries counter-clockwise, holes clockwise; nonzero fill gives
/// the union). Boxes that are empty, unbounded or of fewer than 2 axes are
/// left out. Above [`MAX_UNION_BOXES`] boxes, each box's rectangle (an
/// enclosure of the union, not its boundary).
pub fn union_outline(boxes: &[IntervalBox]) -> Vec<Vec<Point>> {
    let rects: Vec<[f64; 4]> = boxes
        .iter()
        .filter(|b| b.dim() >= 2 && !b.is_empty() && b[0].is_bounded() && b[1].is_bounded())
        .map(|b| [b[0].lo(), b[0].hi(), b[1].lo(), b[1].hi()])
        .collect();
    if rects.len() > MAX_UNION_BOXES {
        return rects
            .iter()
            .map(|r| vec![[r[0], r[2]], [r[1], r[2]], [r[1], r[3]], [r[0], r[3]]])
            .collect();
    }
    let axis = |k: usize| {
        let mut v: Vec<f64> = rects.iter().flat_map(|r| [r[k], r[k + 1]]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let (xs, ys) = (axis(0), axis(2));
    if xs.len() < 2 || ys.len() < 2 {
        return Vec::new();
    }
    let (nx, ny) = (xs.len() - 1, ys.len() - 1);
    let at = |v: &[f64], x: f64| v.partition_point(|&u| u < x);
    // 2-D difference array over the cells, then prefix sums: covered > 0.
    let mut diff = vec![0i32; (nx + 1) * (ny + 1)];
    for r in &rects {
        let (i0, i1, j0, j1) = (at(&xs, r[0]), at(&xs, r[1]), at(&ys, r[2]), at(&ys, r[3]));
        if i0 == i1 || j0 == j1 {
            continue; // a degenerate box covers no cell
        }
        diff[j0 * (nx + 1) + i0] += 1;
        diff[j0 * (nx + 1) + i1] -= 1;
        diff[j1 * (nx + 1) + i0] -= 1;
        diff[j1 * (nx + 1) + i1] += 1;
    }
    let mut covered = vec![false; nx * ny];
    let mut row = vec![0i32; nx + 1];
    for j in 0..ny {
        let mut run = 0;
        for i in 0..nx {
            row[i] += diff[j * (nx + 1) + i];
            run += row[i];
            covered[j * nx + i] = run > 0;
        }
    }
    let cov = |i: isize, j: isize| {
        i >= 0
            && j >= 0
            && (i as usize) < nx
            && (j as usize) < ny
            && covered[j as usize * nx + i as usize]
    };
    // Directed boundary edges with the covered cell on their left, between
    // grid vertices (i, j).
    let mut edges: Vec<([usize; 2], [usize; 2])> = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            if !covered[j * nx + i] {
                continue;
            }
            let (ii, jj) = (i as isize, j as isize);
            if !cov(ii, jj - 1) {
                edges.push(([i, j], [i + 1, j]));
            }
            if !cov(ii + 1, jj) {
                edges.push(([i + 1, j], [i + 1, j + 1]));
            }
            if !cov(ii, jj + 1) {
                edges.push(([i + 1, j + 1], [i, j + 1]));
            }
            if !cov(ii - 1, jj) {
                edges.push(([i, j + 1], [i, j]));
            }
        }
    }
    // Chain them: edges sorted by their start, each used once.
    let mut order: Vec<usize> = (0..edges.len()).collect();
    order.sort_by_key(|&e| edges[e].0);
    let mut used = vec![false; edges.len()];
    let mut loops = Vec::new();
    for first in 0..edges.len() {
        if used[first] {
            continue;
        }
        let mut grid_pts: Vec<[usize; 2]> = Vec::new();
        let mut e = first;
        loop {
            used[e] = true;
            grid_pts.push(edges[e].0);
            let end = edges[e].1;
            let k = order.partition_point(|&o| edges[o].0 < end);
            match order[k..]
                .iter()
                .take_while(|&&o| edges[o].0 == end)
                .find(|&&o| !used[o])
            {
                Some(&next) => e = next,
                None => break,
            }
        }
        loops.push(simplify(&grid_pts, &xs, &ys));
    }
    loops
}

/// Grid vertices -> points, without the vertices in the middle of a
/// straight run.
fn simplify(g: &[[usize; 2]], xs: &[f64], ys: &[f64]) -> Vec<Point> {
    let n = g.len();
    (0..n)
        .filter(|&k| {
            let (a, b, c) = (g[(k + n - 1) % n], g[k], g[(k + 1) % n]);
            !((a[0] == b[0] && b[0] == c[0]) || (a[1] == b[1] && b[1] == c[1]))
        })
        .map(|k| [xs[g[k][0]], ys[g[k][1]]])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    /// Winding number of the polygon around q.
    fn winding(poly: &[Point], q: Point) -> i32 {
        let mut w = 0;
        for (i, &a) in poly.iter().enumerate() {
            let b = poly[(i + 1) % poly.len()];
            let side = (b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1]);
            if a[1] <= q[1] {
                if b[1] > q[1] && side > 0.0 {
                    w += 1;
                }
            } else if b[1] <= q[1] && side < 0.0 {
                w -= 1;
            }
        }
        w
    }

    /// Whether the outline, filled with the nonzero rule, covers q.
    fn filled(o: &Outline, q: Point) -> bool {
        winding(&o.outer, q) + o.hole.as_ref().map_or(0, |h| winding(h, q)) != 0
    }

    fn iv(lo: f64, hi: f64) -> Interval {
        Interval::new(lo, hi)
    }

    /// Shapes with planted points: random boxes (zero width included),
    /// ranges, sectors and cuts, at small and huge offsets; every point
    /// p + t u(φ) with p ∈ P, t ∈ r, φ ∈ S that lies in C is inside the
    /// filled outline. The outline is not trivial: the centre of P is out
    /// when there is a hole, and a point behind P opposite a narrow sector
    /// is out.
    #[test]
    fn the_outline_encloses_planted_points_of_the_shape() {
        let mut rng = Lcg::new(17);
        let (mut points, mut holes, mut cones) = (0, 0, 0);
        for case in 0..4000 {
            let offset = [0.0, 1e3, -1e6, 4e7][case % 4];
            let mut u = || rng.unit();
            let x0 = offset + u() * 20.0 - 10.0;
            let y0 = -offset + u() * 20.0 - 10.0;
            let (w, h) = if case % 7 == 0 {
                (0.0, 0.0)
            } else {
                (u() * u() * 8.0, u() * u() * 8.0)
            };
            let lo = u() * 15.0;
            let hi = lo + u() * 3.0;
            let a = u() * 12.0 - 6.0;
            let sector = if u() < 0.5 {
                None
            } else {
                Some(iv(a, a + u() * 3.3))
            };
            let (cx0, cy0) = (x0 + u() * 30.0 - 20.0, y0 + u() * 30.0 - 20.0);
            let cut = if u() < 0.5 {
                IntervalBox::entire(2)
            } else {
                IntervalBox::new(&[iv(cx0, cx0 + u() * 25.0), iv(cy0, cy0 + u() * 25.0)])
            };
            let centre = IntervalBox::new(&[iv(x0, x0 + w), iv(y0, y0 + h)]);
            let s = Shape::new(
                centre,
                iv(lo, hi),
                sector.map(|s| (Interval::point(0.0), s)),
                cut.clone(),
            );
            let o = shape_outline(&s);
            for _ in 0..30 {
                let p = [x0 + rng.unit() * w, y0 + rng.unit() * h];
                let t = lo + rng.unit() * (hi - lo);
                let phi = match sector {
                    Some(s) => s.lo() + rng.unit() * s.width(),
                    None => rng.unit() * 2.0 * PI,
                };
                let q = [p[0] + t * libm::cos(phi), p[1] + t * libm::sin(phi)];
                if !cut.contains(&q) {
                    continue;
                }
                points += 1;
                let o = o
                    .as_ref()
                    .unwrap_or_else(|| panic!("case {case}: no outline for a shape holding {q:?}"));
                assert!(
                    filled(o, q),
                    "case {case}: {q:?} of the shape is outside its outline"
                );
            }
            let m = [x0 + w / 2.0, y0 + h / 2.0];
            if let Some(o) = &o {
                // (with a sector, m is the cone's apex: on the boundary)
                if o.hole.is_some() && sector.is_none() && cut.contains(&m) {
                    holes += 1;
                    assert!(!filled(o, m), "case {case}: the hole is drawn filled");
                }
                if let Some(sec) = sector.filter(|s| s.width() < 3.0) {
                    let back = sec.mid() + PI;
                    let d = libm::hypot(w, h) / 2.0 + 1.0;
                    let q = [m[0] + d * libm::cos(back), m[1] + d * libm::sin(back)];
                    if cut.contains(&q) {
                        cones += 1;
                        assert!(
                            !filled(o, q),
                            "case {case}: the sector is drawn behind its box"
                        );
                    }
                }
            }
        }
        assert!(
            points > 40_000 && holes > 100 && cones > 100,
            "{points} {holes} {cones}"
        );
    }

    /// 3-D: the horizontal projection of a spherical shell cut in depth;
    /// points at the planted depth project inside the outline.
    #[test]
    fn a_3d_shell_projects_inside_its_outline() {
        let mut rng = Lcg::new(3);
        for case in 0..2000 {
            let mut u = || rng.unit();
            let (x0, y0, z0) = (u() * 10.0, u() * 10.0, u() * 5.0);
            let (w, h, dz) = (u() * 2.0, u() * 2.0, u() * 2.0);
            let lo = 3.0 + u() * 10.0;
            let hi = lo + u() * 2.0;
            let (cz0, cz1) = (z0 + u() * 6.0 - 3.0, z0 + 3.0 + u() * 3.0);
            let s = Shape::new(
                IntervalBox::new(&[iv(x0, x0 + w), iv(y0, y0 + h), iv(z0, z0 + dz)]),
                iv(lo, hi),
                None,
                IntervalBox::new(&[Interval::ENTIRE, Interval::ENTIRE, iv(cz0, cz1)]),
            );
            let o = shape_outline(&s).expect("a bounded shell has an outline");
            for _ in 0..20 {
                let p = [
                    x0 + rng.unit() * w,
                    y0 + rng.unit() * h,
                    z0 + rng.unit() * dz,
                ];
                let z = cz0 + rng.unit() * (cz1 - cz0);
                let t = lo + rng.unit() * (hi - lo);
                let vz = z - p[2];
                if vz.abs() > t {
                    continue;
                }
                let hr = (t * t - vz * vz).sqrt();
                let phi = rng.unit() * 2.0 * PI;
                let q = [p[0] + hr * libm::cos(phi), p[1] + hr * libm::sin(phi)];
                assert!(filled(&o, q), "case {case}: {q:?} outside");
            }
        }
    }

    /// Nothing is drawn for what cannot be drawn, and nothing panics:
    /// unbounded centres and ranges, empty shapes, huge and zero values.
    #[test]
    fn unbounded_empty_huge_and_zero_shapes() {
        let c = IntervalBox::new(&[iv(0.0, 1.0), iv(0.0, 1.0)]);
        let e = IntervalBox::entire(2);
        let unbounded = Shape::new(IntervalBox::entire(2), iv(1.0, 2.0), None, e.clone());
        assert_eq!(shape_outline(&unbounded), None);
        let far = Shape::new(c.clone(), iv(1.0, f64::INFINITY), None, e.clone());
        assert_eq!(shape_outline(&far), None);
        let empty = Shape::new(IntervalBox::empty(2), iv(1.0, 2.0), None, e.clone());
        assert_eq!(shape_outline(&empty), None);
        let away = Shape::new(
            c.clone(),
            iv(1.0, 2.0),
            None,
            IntervalBox::new(&[iv(50.0, 60.0), iv(50.0, 60.0)]),
        );
        assert_eq!(shape_outline(&away), None);
        let point = Shape::new(
            IntervalBox::point(&[0.0, 0.0]),
            iv(0.0, 0.0),
            None,
            e.clone(),
        );
        let o = shape_outline(&point).expect("a point is drawn");
        assert!(filled(&o, [0.0, 0.0]) && o.hole.is_none());
        let huge = Shape::new(
            IntervalBox::new(&[iv(-1e300, 1e300), iv(0.0, 1.0)]),
            iv(1e300, 1.5e300),
            Some((Interval::ENTIRE, iv(0.0, 1.0))),
            e,
        );
        if let Some(o) = shape_outline(&huge) {
            assert!(o.outer.iter().all(|p| !p[0].is_nan() && !p[1].is_nan()));
        }
    }

    /// The union's outline is the union: on random boxes snapped to a coarse
    /// grid (shared edges, holes, touching corners), every probe point off
    /// the grid lines is covered by the nonzero fill of the loops exactly
    /// when a box holds it.
    #[test]
    fn union_outline_is_the_union_of_the_boxes() {
        let mut rng = Lcg::new(5);
        for case in 0..400 {
            let n = 1 + (rng.bits() % 12) as usize;
            let boxes: Vec<IntervalBox> = (0..n)
                .map(|_| {
                    let g = |rng: &mut Lcg| (rng.bits() % 10) as f64;
                    let (a, b, c, d) = (g(&mut rng), g(&mut rng), g(&mut rng), g(&mut rng));
                    IntervalBox::new(&[iv(a.min(b), a.max(b)), iv(c.min(d), c.max(d))])
                })
                .collect();
            let loops = union_outline(&boxes);
            for i in 0..20 {
                for j in 0..20 {
                    let q = [i as f64 * 0.5 + 0.25 - 0.5, j as f64 * 0.5 + 0.25 - 0.5];
                    let inside = boxes.iter().any(|b| b.contains(&q));
                    let w: i32 = loops.iter().map(|l| winding(l, q)).sum();
                    assert_eq!(w != 0, inside, "case {case}: {q:?}, boxes {boxes:?}");
                    assert!((0..=1).contains(&w), "case {case}: winding {w}");
                }
            }
        }
        assert!(union_outline(&[]).is_empty());
        assert!(union_outline(&[IntervalBox::entire(2)]).is_empty());
    }
}
