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
//! - with a sector narrower than π, both are clipped by P ⊕ K with K the
//!   infinite cone of directions S (which holds the sector): for a box P
//!   and a convex cone K, P ⊕ K is the intersection of the half-planes
//!   n · x <= max_{p∈P} n · p over the outward normals n of K's two edges
//!   and the axis directions between them (the box's support function is
//!   linear between axis directions). An axis direction is used only when
//!   it is inside K's dual cone by a margin, so that rounding never adds a
//!   cut (leaving one out only makes the region larger), and every
//!   half-plane is moved out by the slack;
//! - both clipped by the cut box C (Sutherland–Hodgman half-planes).
//!
//! Filled: (outer \ hole) ∩ (P ⊕ K) ∩ C ⊇ A. In 3-D the horizontal distance is
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
//! # The region's outline (`union_boundary`)
//!
//! The boundary of the union of boxes, as segments: each side of each box,
//! minus the parts where another box covers the strip just outside it.
//! Every coordinate is one of the boxes' own bounds (comparisons only), so
//! the boundary is exact: no rounding. (The page fills the union itself
//! from the boxes, and strokes these segments.)
//!
//! # Complexity
//!
//! `shape_outline`: O(ARC_STEPS) vertices and time per shape, no allocation
//! sized by an input number. `union_boundary`: O(n² · s) for n boxes, s
//! the pieces a side is cut into (at most n + 1); above `MAX_UNION_BOXES`
//! boxes it declines (`None`, O(n)).

use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::shapes::shape::Shape;

/// Polygon vertices per quarter circle (between the two tangent points).
pub const ARC_STEPS: usize = 6;

/// Relative slack of the outer radii and the hole's radius (see the module
/// doc, "Rounding").
pub const SLACK: f64 = 1e-9;

/// Most boxes whose union is traced exactly (see the module doc).
pub const MAX_UNION_BOXES: usize = 2000;

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
            let (planes, count) = cone_half_planes(&b, sector, slack);
            for &(n, c) in &planes[..count] {
                outer = clip_half(&outer, n, c);
                hole = hole.map(|h| clip_half(&h, n, c));
            }
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

/// The cone P ⊕ K (module doc) as half-planes n · x <= c: the outward
/// normals of C's two edges, and the axis directions between them (where
/// the box's support function bends), each at the box's support value plus
/// the slack.
fn cone_half_planes(b: &Rect, sector: Interval, slack: f64) -> ([(Point, f64); 6], usize) {
    let (lo, hi) = (sector.lo(), sector.hi());
    let (ul, uh) = (
        [libm::cos(lo), libm::sin(lo)],
        [libm::cos(hi), libm::sin(hi)],
    );
    let mut normals = [[0.0; 2]; 6];
    normals[0] = [ul[1], -ul[0]];
    normals[1] = [-uh[1], uh[0]];
    let mut n = 2;
    for e in [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]] {
        // In the dual cone (e · u < 0 for both edges), with a margin so that
        // rounding never lets in a normal that would cut too much.
        if e[0] * ul[0] + e[1] * ul[1] < -1e-9 && e[0] * uh[0] + e[1] * uh[1] < -1e-9 {
            normals[n] = e;
            n += 1;
        }
    }
    let mut planes = [([0.0; 2], 0.0); 6];
    for k in 0..n {
        let m = normals[k];
        let mut support = f64::NEG_INFINITY;
        for p in [[b.x0, b.y0], [b.x1, b.y0], [b.x1, b.y1], [b.x0, b.y1]] {
            support = support.max(m[0] * p[0] + m[1] * p[1]);
        }
        planes[k] = (m, support + slack);
    }
    (planes, n)
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

/// The boundary of the union of the boxes' first two axes, as segments
/// `[a, b]` (axis-aligned; none inside the union, every boundary point on
/// one). Boxes that are empty, unbounded or of fewer than 2 axes are left
/// out. `None` above [`MAX_UNION_BOXES`] boxes (every box's sides would
/// draw a grid, not an outline: the caller draws the union's fill alone).
pub fn union_boundary(boxes: &[IntervalBox]) -> Option<Vec<[Point; 2]>> {
    let mut rects: Vec<[f64; 4]> = Vec::with_capacity(boxes.len());
    for b in boxes {
        if b.dim() >= 2 && !b.is_empty() && b[0].is_bounded() && b[1].is_bounded() {
            rects.push([b[0].lo(), b[0].hi(), b[1].lo(), b[1].hi()]);
        }
    }
    if rects.len() > MAX_UNION_BOXES {
        return None;
    }
    let mut out = Vec::new();
    let (mut pieces, mut next) = (Vec::new(), Vec::new());
    for r in &rects {
        // Each side: the axis its line crosses (0: x = c, 1: y = c), c,
        // whether the strip that must be uncovered is below (or left of) it,
        // and its span along the line.
        for (axis, c, below, lo, hi) in [
            (0, r[0], true, r[2], r[3]),
            (0, r[1], false, r[2], r[3]),
            (1, r[2], true, r[0], r[1]),
            (1, r[3], false, r[0], r[1]),
        ] {
            pieces.clear();
            pieces.push([lo, hi]);
            for q in &rects {
                let (a0, a1, s0, s1) = if axis == 0 {
                    (q[0], q[1], q[2], q[3])
                } else {
                    (q[2], q[3], q[0], q[1])
                };
                // q covers the open strip beside the side along [s0, s1].
                let beside = if below {
                    a0 < c && c <= a1
                } else {
                    a0 <= c && c < a1
                };
                if beside {
                    next.clear();
                    for &[p0, p1] in &pieces {
                        if p0 < p1.min(s0) {
                            next.push([p0, p1.min(s0)]);
                        }
                        if p0.max(s1) < p1 {
                            next.push([p0.max(s1), p1]);
                        }
                    }
                    std::mem::swap(&mut pieces, &mut next);
                }
            }
            for &[p0, p1] in &pieces {
                if p0 < p1 {
                    out.push(if axis == 0 {
                        [[c, p0], [c, p1]]
                    } else {
                        [[p0, c], [p1, c]]
                    });
                }
            }
        }
    }
    Some(out)
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

    /// The union's boundary is the boundary: on random boxes snapped to a
    /// coarse grid (shared sides, holes, touching corners, flat boxes),
    /// every segment has the union on exactly one side, and between every
    /// two neighbouring probe points of which one is covered and the other
    /// not, a segment passes.
    #[test]
    fn union_boundary_is_the_boundary_of_the_union() {
        let mut rng = Lcg::new(5);
        for case in 0..400 {
            let n = 1 + (rng.bits() % 12) as usize;
            let boxes: Vec<IntervalBox> = (0..n)
                .map(|_| {
                    let mut g = || (rng.bits() % 10) as f64;
                    let (a, b, c, d) = (g(), g(), g(), g());
                    // Flat boxes (a line: drawn, but no side of it is
                    // covered) are checked below, apart.
                    let (b, d) = (
                        if a == b { a + 1.0 } else { b },
                        if c == d { c + 1.0 } else { d },
                    );
                    IntervalBox::new(&[iv(a.min(b), a.max(b)), iv(c.min(d), c.max(d))])
                })
                .collect();
            let covered = |q: Point| boxes.iter().any(|b| b.contains(&q));
            let segs = union_boundary(&boxes).unwrap();
            for s in &segs {
                let m = [(s[0][0] + s[1][0]) / 2.0, (s[0][1] + s[1][1]) / 2.0];
                let (l, r) = if s[0][0] == s[1][0] {
                    ([m[0] - 0.01, m[1]], [m[0] + 0.01, m[1]])
                } else {
                    ([m[0], m[1] - 0.01], [m[0], m[1] + 0.01])
                };
                assert!(
                    covered(l) != covered(r),
                    "case {case}: {s:?} is not on the boundary of {boxes:?}"
                );
            }
            // Probes at half-integers: neighbours one apart straddle a grid line.
            for i in -1..10 {
                for j in -1..10 {
                    let q = [i as f64 + 0.5, j as f64 + 0.5];
                    let (qx, qy) = ([q[0] + 1.0, q[1]], [q[0], q[1] + 1.0]);
                    if covered(q) != covered(qx) {
                        let x = q[0] + 0.5;
                        assert!(
                            segs.iter().any(|s| s[0][0] == x
                                && s[1][0] == x
                                && s[0][1].min(s[1][1]) < q[1]
                                && q[1] < s[0][1].max(s[1][1])),
                            "case {case}: no boundary between {q:?} and {qx:?}"
                        );
                    }
                    if covered(q) != covered(qy) {
                        let y = q[1] + 0.5;
                        assert!(
                            segs.iter().any(|s| s[0][1] == y
                                && s[1][1] == y
                                && s[0][0].min(s[1][0]) < q[0]
                                && q[0] < s[0][0].max(s[1][0])),
                            "case {case}: no boundary between {q:?} and {qy:?}"
                        );
                    }
                }
            }
        }
        assert_eq!(union_boundary(&[]), Some(vec![]));
        assert_eq!(union_boundary(&[IntervalBox::entire(2)]), Some(vec![]));
        let many = vec![IntervalBox::new(&[iv(0.0, 1.0), iv(0.0, 1.0)]); MAX_UNION_BOXES + 1];
        assert_eq!(union_boundary(&many), None);
        // A flat box is a line, drawn on both its sides; a point is not drawn.
        let flat = union_boundary(&[IntervalBox::new(&[iv(0.0, 2.0), iv(1.0, 1.0)])]);
        assert_eq!(flat, Some(vec![[[0.0, 1.0], [2.0, 1.0]]; 2]));
        assert_eq!(
            union_boundary(&[IntervalBox::point(&[1.0, 1.0])]),
            Some(vec![])
        );
    }
}
