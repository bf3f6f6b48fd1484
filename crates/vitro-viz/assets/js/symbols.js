// Entity symbols after APP-6 / MIL-STD-2525: the frame shape and fill say the side
// (friendly: blue rectangle, or circle in the air; hostile: red diamond; neutral: green square;
// unknown: yellow quatrefoil), the icon inside says the type.

export const SIDES = ['friendly', 'hostile', 'neutral', 'unknown'];

export const FILL = { friendly: '#80e0ff', hostile: '#ff8080', neutral: '#aaffaa', unknown: '#ffff80' };
export const STROKE = { friendly: '#00557a', hostile: '#a00000', neutral: '#1d6b1d', unknown: '#8a7a00' };

const AIR = new Set(['procerus', 'vidar', 'skeldar', 'ctol', 'vtol', 'uav', 'aircraft', 'helicopter', 'drone']);
const FIXED_WING = new Set(['procerus', 'ctol']);
const ROTARY_WING = new Set(['vidar', 'skeldar', 'vtol', 'helicopter']);

/** True for entity types drawn as aircraft. */
export function isAir(kind) {
  return AIR.has(kind);
}

/** What each known type is called in the legend. */
export const KIND_NAMES = {
  truck: 'cargo truck',
  car: 'car',
  ugv: 'UGV (MDARS ground robot)',
  trooper: 'trooper',
  vip: 'VIP (to evacuate)',
  hvt: 'high-value target',
  procerus: 'fixed-wing UAV (Procerus)',
  vidar: 'helicopter UAV (Vidar)',
  skeldar: 'helicopter UAV (Skeldar)',
  ctol: 'fixed-wing UAV',
  vtol: 'helicopter UAV',
};

function framePath(ctx, side, air, s) {
  ctx.beginPath();
  if (side === 'hostile') {
    ctx.moveTo(0, -s * 1.15);
    ctx.lineTo(s * 1.15, 0);
    ctx.lineTo(0, s * 1.15);
    ctx.lineTo(-s * 1.15, 0);
    ctx.closePath();
  } else if (side === 'neutral') {
    ctx.rect(-s * 0.9, -s * 0.9, s * 1.8, s * 1.8);
  } else if (side === 'unknown') {
    // four lobes meeting at (±r, ±r)
    const r = s * 0.6;
    ctx.arc(0, -r, r, Math.PI, Math.PI * 2);
    ctx.arc(r, 0, r, Math.PI * 1.5, Math.PI * 2.5);
    ctx.arc(0, r, r, 0, Math.PI);
    ctx.arc(-r, 0, r, Math.PI * 0.5, Math.PI * 1.5);
    ctx.closePath();
  } else if (air) {
    ctx.arc(0, 0, s, 0, Math.PI * 2);
  } else {
    ctx.rect(-s * 1.3, -s * 0.85, s * 2.6, s * 1.7);
  }
}

function icon(ctx, kind, side, s) {
  if (FIXED_WING.has(kind)) kind = 'ctol';
  if (ROTARY_WING.has(kind)) kind = 'vtol';
  const w = side === 'friendly' && !isAir(kind) ? s * 1.3 : s * 0.7;
  const h = side === 'friendly' && !isAir(kind) ? s * 0.85 : s * 0.7;
  ctx.beginPath();
  switch (kind) {
    case 'none':
      return;
    case 'trooper': // infantry: crossed diagonals
      ctx.moveTo(-w, -h);
      ctx.lineTo(w, h);
      ctx.moveTo(w, -h);
      ctx.lineTo(-w, h);
      ctx.stroke();
      return;
    case 'car':
    case 'truck':
    case 'ugv': {
      // wheeled vehicle: a chassis line on two wheels
      const r = s * 0.17;
      ctx.moveTo(-s * 0.55, s * 0.2);
      ctx.lineTo(s * 0.55, s * 0.2);
      ctx.stroke();
      for (const x of [-s * 0.35, s * 0.35]) {
        ctx.beginPath();
        ctx.arc(x, s * 0.2 + r + 1, r, 0, Math.PI * 2);
        ctx.stroke();
      }
      if (kind === 'truck') ctx.strokeRect(-s * 0.45, -s * 0.35, s * 0.9, s * 0.5);
      if (kind === 'ugv') text(ctx, 'R', -s * 0.12, s * 0.65);
      return;
    }
    case 'ctol': // fixed-wing UAV: a flattened V
      ctx.moveTo(-s * 0.7, -s * 0.2);
      ctx.lineTo(0, s * 0.25);
      ctx.lineTo(s * 0.7, -s * 0.2);
      ctx.lineTo(0, s * 0.05);
      ctx.closePath();
      ctx.fill();
      return;
    case 'vtol': // rotary wing: a bow tie
      ctx.moveTo(-s * 0.6, -s * 0.35);
      ctx.lineTo(s * 0.6, s * 0.35);
      ctx.lineTo(s * 0.6, -s * 0.35);
      ctx.lineTo(-s * 0.6, s * 0.35);
      ctx.closePath();
      ctx.fill();
      return;
    case 'vip':
      text(ctx, 'VIP', 0, 0.55 * s);
      return;
    case 'hvt':
      text(ctx, 'HVT', 0, 0.55 * s);
      return;
    default:
      text(ctx, (kind || '?').slice(0, 3).toUpperCase(), 0, 0.55 * s);
  }
}

function text(ctx, t, y, size) {
  ctx.font = `bold ${Math.max(7, size)}px system-ui, sans-serif`;
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  ctx.fillText(t, 0, y);
}

/**
 * Draws one entity's symbol centred at (x, y), screen pixels.
 * heading: radians counter-clockwise from east (screen y grows down); null for none.
 */
export function drawSymbol(ctx, x, y, s, side, kind, heading = null, status = 'active') {
  const air = isAir(kind);
  ctx.save();
  ctx.translate(x, y);
  const gone = status === 'down' || status === 'captured' || status === 'dead' || status === 'destroyed';
  if (status === 'aboard' || status === 'extracted') ctx.globalAlpha = 0.45;
  if (heading != null && !gone) {
    const len = s * 2.3;
    const dx = Math.cos(heading) * len;
    const dy = -Math.sin(heading) * len;
    ctx.strokeStyle = '#111';
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    ctx.moveTo(0, 0);
    ctx.lineTo(dx, dy);
    const a = Math.atan2(dy, dx);
    ctx.lineTo(dx - 5 * Math.cos(a - 0.45), dy - 5 * Math.sin(a - 0.45));
    ctx.moveTo(dx, dy);
    ctx.lineTo(dx - 5 * Math.cos(a + 0.45), dy - 5 * Math.sin(a + 0.45));
    ctx.stroke();
  }
  // APP-6: a dashed frame for what is not confirmed (here: not yet detected by the team)
  const unseen = status === 'undetected';
  if (unseen) ctx.globalAlpha = 0.6;
  framePath(ctx, side, air, s);
  ctx.fillStyle = FILL[side] || FILL.unknown;
  ctx.fill();
  ctx.lineWidth = 1.4;
  ctx.strokeStyle = '#000';
  if (unseen) ctx.setLineDash([3, 2]);
  ctx.stroke();
  ctx.setLineDash([]);
  ctx.fillStyle = '#000';
  ctx.strokeStyle = '#000';
  ctx.lineWidth = 1.1;
  icon(ctx, kind, side, s);
  if (gone) {
    ctx.strokeStyle = '#000';
    ctx.lineWidth = 2.2;
    ctx.beginPath();
    ctx.moveTo(-s * 1.2, -s * 1.2);
    ctx.lineTo(s * 1.2, s * 1.2);
    ctx.moveTo(s * 1.2, -s * 1.2);
    ctx.lineTo(-s * 1.2, s * 1.2);
    ctx.stroke();
  }
  ctx.restore();
}

/** A small canvas with one symbol, for the legend and the inspector. */
export function symbolCanvas(side, kind, size = 22, status = 'active') {
  const c = document.createElement('canvas');
  const dpr = window.devicePixelRatio || 1;
  c.width = Math.round(size * 1.6 * dpr);
  c.height = Math.round(size * dpr);
  c.style.width = `${size * 1.6}px`;
  c.style.height = `${size}px`;
  const ctx = c.getContext('2d');
  ctx.scale(dpr, dpr);
  drawSymbol(ctx, size * 0.8, size / 2, size * 0.36, side, kind, null, status);
  return c;
}
