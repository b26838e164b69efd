// Small DOM helpers shared by the page's features.

export const $ = (id) => document.getElementById(id);

export function el(tag, text, cls) {
  const e = document.createElement(tag);
  if (text !== undefined) e.textContent = text;
  if (cls) e.className = cls;
  return e;
}

/** A pointer event's position in a canvas's own pixels. */
export function canvasPoint(canvas, ev) {
  const r = canvas.getBoundingClientRect();
  return [(ev.clientX - r.left) * canvas.width / r.width, (ev.clientY - r.top) * canvas.height / r.height];
}

/**
 * Redraws at most once a frame; during a pan or zoom (`request(true)`) the
 * caller may move the previous picture, and a full redraw follows once the
 * movement stops (150 ms).
 */
export function scheduler(redraw) {
  let frame = 0, full = false, settle = 0;
  const request = (moving) => {
    if (!moving) full = true;
    if (!frame) frame = requestAnimationFrame(() => { frame = 0; const f = full; full = false; redraw(!f); });
    if (moving) { clearTimeout(settle); settle = setTimeout(() => request(false), 150); }
  };
  return request;
}
