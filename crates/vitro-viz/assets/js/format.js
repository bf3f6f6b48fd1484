// Formatting of times, numbers and positions for the page.

/** Simulated nanoseconds as h:mm:ss.s */
export function clock(tNs) {
  const t = Number(tNs) / 1e9;
  const h = Math.floor(t / 3600);
  const m = Math.floor((t % 3600) / 60);
  const s = t % 60;
  return `${h}:${String(m).padStart(2, '0')}:${s.toFixed(1).padStart(4, '0')}`;
}

/**
 * The calendar time (UTC) of simulated nanoseconds tNs after a start in Unix milliseconds
 * (the scene's start_unix_ms): "2024-06-01 06:00:12 UTC". Empty without a start.
 */
export function wallClock(startMs, tNs) {
  if (startMs == null) return '';
  const d = new Date(Number(startMs) + Math.floor(Number(tNs) / 1e6));
  if (Number.isNaN(d.getTime())) return '';
  return `${d.toISOString().slice(0, 19).replace('T', ' ')} UTC`;
}

/** A speed factor as text: 0.5×, 2×, 1000×. */
export function speed(x) {
  if (x == null) return 'max';
  return `${x < 1 ? x.toFixed(x < 0.2 ? 2 : 1) : Math.round(x * 100) / 100}×`;
}

/** A number with a sensible number of digits. */
export function num(v) {
  if (v == null || Number.isNaN(v)) return '–';
  const a = Math.abs(v);
  if (a !== 0 && (a >= 1e6 || a < 1e-3)) return v.toExponential(2);
  if (Number.isInteger(v)) return String(v);
  return v.toFixed(a >= 100 ? 0 : a >= 10 ? 1 : 2);
}

/** A world position as text. */
export function pos(p) {
  return `${p[0].toFixed(1)}, ${p[1].toFixed(1)}, ${p[2].toFixed(1)} m`;
}

/** Escapes text for HTML. */
export function esc(s) {
  return String(s).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' }[c]));
}

/** Heading in radians counter-clockwise from east, as a compass bearing in degrees. */
export function bearing(rad) {
  const deg = (90 - (rad * 180) / Math.PI) % 360;
  return `${Math.round((deg + 360) % 360)}°`;
}
