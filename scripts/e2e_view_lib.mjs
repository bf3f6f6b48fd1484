// Helpers of scripts/e2e_view.mjs: waiting on the page, reading its clock, judging pixels.

/** Waits until `fn(arg)` holds in the page. */
export function waitFor(page, fn, timeout, arg) {
  return page.waitForFunction(fn, arg, { timeout, polling: 50 });
}

/** The clock as the page shows it: simulated ns, events fired, and the text. */
export function clockOf(page) {
  return page.evaluate(() => {
    const clock = document.getElementById('clock');
    return {
      t: Number(clock.dataset.tNs),
      events: Number(document.getElementById('events').dataset.events),
      text: clock.textContent,
    };
  });
}

/**
 * True if a PNG screenshot (optionally only the `clip` box of it) is a picture, not a blank:
 * many distinct colours (quantised to 4 bits a channel) and no colour covering most of it.
 * The PNG is decoded by the browser itself.
 */
export async function checkNotBlank(page, png, label, clip = null) {
  const stats = await page.evaluate(
    async ({ b64, clip }) => {
      const img = new Image();
      img.src = `data:image/png;base64,${b64}`;
      await img.decode();
      const box = clip || { x: 0, y: 0, width: img.width, height: img.height };
      const c = document.createElement('canvas');
      c.width = Math.round(box.width);
      c.height = Math.round(box.height);
      const ctx = c.getContext('2d');
      ctx.drawImage(img, box.x, box.y, box.width, box.height, 0, 0, c.width, c.height);
      const d = ctx.getImageData(0, 0, c.width, c.height).data;
      const counts = new Map();
      for (let i = 0; i < d.length; i += 4) {
        const k = ((d[i] >> 4) << 8) | ((d[i + 1] >> 4) << 4) | (d[i + 2] >> 4);
        counts.set(k, (counts.get(k) || 0) + 1);
      }
      const top = Math.max(...counts.values());
      return { colours: counts.size, topShare: top / (d.length / 4), width: c.width, height: c.height };
    },
    { b64: png.toString('base64'), clip },
  );
  console.log(
    `       ${label}: ${stats.width}x${stats.height} px, ${stats.colours} colours, the commonest covers ${(100 * stats.topShare).toFixed(0)}%`,
  );
  return stats.colours >= 48 && stats.topShare < 0.8;
}
