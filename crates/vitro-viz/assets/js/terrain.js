// Ground heights from the scene's heightmap (no three.js here: the 2D map uses it too).

/** Ground height at world (x, y): bilinear in the heightmap, clamped at its edges. */
export function groundAt(t, x, y) {
  if (!t || !t.z.length) return 0;
  if (t.nx < 2 || t.ny < 2) return t.z[0];
  const fx = Math.min(t.nx - 1, Math.max(0, (x - t.origin[0]) / t.cell));
  const fy = Math.min(t.ny - 1, Math.max(0, (y - t.origin[1]) / t.cell));
  const i = Math.min(t.nx - 2, Math.floor(fx));
  const j = Math.min(t.ny - 2, Math.floor(fy));
  const u = fx - i;
  const v = fy - j;
  const z = (a, b) => t.z[b * t.nx + a];
  return (1 - v) * ((1 - u) * z(i, j) + u * z(i + 1, j)) + v * ((1 - u) * z(i, j + 1) + u * z(i + 1, j + 1));
}

/** Height of a point above the ground under it, metres. */
export function aboveGround(t, p) {
  return p[2] - groundAt(t, p[0], p[1]);
}
