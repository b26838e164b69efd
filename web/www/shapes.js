// Detection shapes as polygons, for drawing (world coordinates, y up).
//
// A range detection j at step t allows the landmark positions
//   A(j) = {p + r u(phi) : p in P, r in range, phi in sector} ∩ C
// with P the box of p(t), u(phi) = (cos phi, sin phi), the sector the
// absolute angles heading + bearing (all angles without a bearing) and C the
// detection's box d(j) (core/src/shapes/shape.rs). Its drawing is the
// region between two convex polygons filled with the nonzero rule, the outer
// one counter-clockwise and the hole clockwise, so that many shapes go into
// one path (one fill per colour) and overlapping shapes add up to their
// union:
// - outer: the box grown by range.hi with rounded corners (every point within
//   range.hi of P), each quarter circle replaced by its circumscribed polygon;
// - hole: the points whose farthest distance to P is below range.lo, the
//   intersection of the four disks of radius range.lo around P's corners,
//   each arc replaced by its inscribed polygon;
// - with a sector narrower than pi: both cut by the cone widened by the box,
//   the convex hull of P ⊕ {0, L u(lo), L u(hi)} with L = range.hi / cos(half
//   the span) (the triangle holds the circular sector of radius range.hi);
// - both cut by C when C is finite.
// Each replacement only adds points, so the drawn region holds the true set
// (the browser test checks sampled true points): a drawing that never hides
// where the landmark may be. The annular sector widened by the box is drawn
// as (box ⊕ annulus) ∩ (box ⊕ cone), slightly larger than box ⊕ sector.
// Cost: O(ARC_STEPS) points per shape, no trigonometry beyond that.

/** Polygon points per quarter circle. */
export const ARC_STEPS = 6;

const TAU = 2 * Math.PI;

/** Appends the circumscribed polygon of the arc of radius r around (cx, cy) from angle t0 up to t1 (t1 > t0, at most a quarter turn). */
function arcOutside(pts, cx, cy, r, t0, t1) {
  const d = (t1 - t0) / ARC_STEPS, far = r / Math.cos(d / 2);
  pts.push(cx + r * Math.cos(t0), cy + r * Math.sin(t0));
  for (let k = 0; k < ARC_STEPS; k++) {
    const t = t0 + (k + 0.5) * d;
    pts.push(cx + far * Math.cos(t), cy + far * Math.sin(t));
  }
  pts.push(cx + r * Math.cos(t1), cy + r * Math.sin(t1));
}

/** Appends the inscribed polygon of the clockwise arc of radius r around (cx, cy) from point (ax, ay) towards (bx, by) (b itself left out). */
function arcInsideCw(pts, cx, cy, r, ax, ay, bx, by) {
  const t0 = Math.atan2(ay - cy, ax - cx);
  let d = Math.atan2(by - cy, bx - cx) - t0;
  while (d > 0) d -= TAU;
  while (d <= -TAU) d += TAU;
  for (let k = 0; k < ARC_STEPS; k++) {
    const t = t0 + (k * d) / ARC_STEPS;
    pts.push(cx + r * Math.cos(t), cy + r * Math.sin(t));
  }
}

/** Counter-clockwise outline of the points within r of box b. */
export function outerPolygon(b, r) {
  const pts = [];
  arcOutside(pts, b.x1, b.y0, r, -Math.PI / 2, 0);
  arcOutside(pts, b.x1, b.y1, r, 0, Math.PI / 2);
  arcOutside(pts, b.x0, b.y1, r, Math.PI / 2, Math.PI);
  arcOutside(pts, b.x0, b.y0, r, Math.PI, 1.5 * Math.PI);
  return pts;
}

/** Clockwise outline of the points whose farthest distance to box b is below r, or null when there is none. */
export function holePolygon(b, r) {
  const a = (b.x1 - b.x0) / 2, h = (b.y1 - b.y0) / 2;
  if (!(r * r > a * a + h * h)) return null;
  const cx = (b.x0 + b.x1) / 2, cy = (b.y0 + b.y1) / 2;
  const sa = Math.sqrt(r * r - a * a), sh = Math.sqrt(r * r - h * h);
  // Top, right, bottom and left points of the hole; each quadrant's arc is
  // centred on the opposite corner.
  const top = [cx, b.y0 + sa], right = [b.x0 + sh, cy], bottom = [cx, b.y1 - sa], left = [b.x1 - sh, cy];
  const pts = [];
  arcInsideCw(pts, b.x0, b.y0, r, ...top, ...right);
  arcInsideCw(pts, b.x0, b.y1, r, ...right, ...bottom);
  arcInsideCw(pts, b.x1, b.y1, r, ...bottom, ...left);
  arcInsideCw(pts, b.x1, b.y0, r, ...left, ...top);
  return pts;
}

/** Sutherland–Hodgman: the part of polygon pts where nx x + ny y <= c. */
function clipHalf(pts, nx, ny, c) {
  const out = [];
  const n = pts.length / 2;
  if (n === 0) return out;
  let px = pts[2 * n - 2], py = pts[2 * n - 1];
  let pin = nx * px + ny * py <= c;
  for (let i = 0; i < n; i++) {
    const x = pts[2 * i], y = pts[2 * i + 1];
    const inside = nx * x + ny * y <= c;
    if (inside !== pin) {
      const fp = nx * px + ny * py - c, fx = nx * x + ny * y - c;
      const t = fp / (fp - fx);
      out.push(px + t * (x - px), py + t * (y - py));
    }
    if (inside) out.push(x, y);
    px = x; py = y; pin = inside;
  }
  return out;
}

/** Clips a polygon by a convex counter-clockwise polygon. */
function clipConvex(pts, clip) {
  const n = clip.length / 2;
  for (let i = 0; i < n && pts.length; i++) {
    const ax = clip[2 * i], ay = clip[2 * i + 1];
    const bx = clip[(2 * i + 2) % clip.length], by = clip[(2 * i + 3) % clip.length];
    // Inside is to the left of a -> b: (b - a) x (p - a) >= 0.
    const ex = bx - ax, ey = by - ay;
    pts = clipHalf(pts, ey, -ex, ey * ax - ex * ay);
  }
  return pts;
}

/** Clips a polygon by a rectangle. */
function clipRect(pts, r) {
  pts = clipHalf(pts, -1, 0, -r.x0);
  pts = clipHalf(pts, 1, 0, r.x1);
  pts = clipHalf(pts, 0, -1, -r.y0);
  return clipHalf(pts, 0, 1, r.y1);
}

/** Counter-clockwise convex hull of a flat point list (monotone chain). */
function convexHull(flat) {
  const p = [];
  for (let i = 0; i < flat.length; i += 2) p.push([flat[i], flat[i + 1]]);
  p.sort((u, v) => u[0] - v[0] || u[1] - v[1]);
  const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  const half = (list) => {
    const h = [];
    for (const q of list) {
      while (h.length >= 2 && cross(h[h.length - 2], h[h.length - 1], q) <= 0) h.pop();
      h.push(q);
    }
    h.pop();
    return h;
  };
  return [...half(p), ...half(p.slice().reverse())].flat();
}

/** The cone of directions [lo, hi] (span below pi) from box b, cut at distance r: a convex counter-clockwise polygon. */
export function conePolygon(b, lo, hi, r) {
  const far = (r / Math.cos((hi - lo) / 2)) * (1 + 1e-9) + 1e-9;
  const dirs = [[0, 0], [far * Math.cos(lo), far * Math.sin(lo)], [far * Math.cos(hi), far * Math.sin(hi)]];
  const pts = [];
  for (const [x, y] of [[b.x0, b.y0], [b.x1, b.y0], [b.x1, b.y1], [b.x0, b.y1]]) {
    for (const [dx, dy] of dirs) pts.push(x + dx, y + dy);
  }
  return convexHull(pts);
}

/**
 * The polygons of one detection's shape: `{outer, hole}` (flat [x, y, ...]
 * lists, hole null when there is none), or null when nothing is drawn (an
 * unbounded box or range, or a shape cut away entirely).
 * @param {{x0:number,x1:number,y0:number,y1:number}} P the box of the position
 * @param {[number, number]} range
 * @param {{x0:number,x1:number,y0:number,y1:number}|null} cut the detection's box
 * @param {[number, number]|null} sector absolute angles (heading + bearing)
 */
export function shapePolygons(P, range, cut, sector) {
  const [lo, hi] = range;
  if (!P || !Number.isFinite(hi) || !(hi >= 0)) return null;
  let outer = outerPolygon(P, hi);
  let hole = lo > 0 ? holePolygon(P, lo) : null;
  if (sector && sector[1] - sector[0] < Math.PI - 1e-6) {
    const cone = conePolygon(P, sector[0], sector[1], hi);
    outer = clipConvex(outer, cone);
    if (hole) hole = clipConvex(hole, cone);
  }
  if (cut) {
    outer = clipRect(outer, cut);
    if (hole) hole = clipRect(hole, cut);
  }
  if (outer.length < 6) return null;
  return { outer, hole: hole && hole.length >= 6 ? hole : null };
}

/**
 * Appends a closed polygon to `parts`, the pieces of an SVG path string
 * (`new Path2D(parts.join(' '))`: one call into the browser for thousands of
 * polygons instead of one per vertex, about ten times faster in Chromium).
 * Numbers keep every digit (no rounding that could move a vertex inwards).
 */
export function addPolygon(parts, pts) {
  parts.push(`M${pts[0]} ${pts[1]}`);
  for (let i = 2; i < pts.length; i += 2) parts.push(`L${pts[i]} ${pts[i + 1]}`);
  parts.push('Z');
}
