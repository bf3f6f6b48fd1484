//! Text on a pixmap with the embedded DejaVu Sans font (licence: `assets/DejaVuSans-LICENSE.txt`).

use ab_glyph::{Font, FontRef, GlyphId, PxScale, ScaleFont, point};
use tiny_skia::Pixmap;

static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// The embedded font.
pub(crate) fn font() -> Option<FontRef<'static>> {
    FontRef::try_from_slice(DEJAVU_SANS).ok()
}

/// Width of `s` in pixels at `size`.
pub(crate) fn width(font: &FontRef<'_>, s: &str, size: f32) -> f32 {
    let f = font.as_scaled(PxScale::from(size));
    let mut prev: Option<GlyphId> = None;
    let mut w = 0.0;
    for c in s.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            w += f.kern(p, id);
        }
        w += f.h_advance(id);
        prev = Some(id);
    }
    w
}

/// Draws `s` with its baseline starting at (`x`, `y`), blending `rgb` by glyph coverage.
pub(crate) fn draw(
    pix: &mut Pixmap,
    font: &FontRef<'_>,
    s: &str,
    x: f32,
    y: f32,
    size: f32,
    rgb: [u8; 3],
) {
    let f = font.as_scaled(PxScale::from(size));
    let (w, h) = (pix.width() as i32, pix.height() as i32);
    let data = pix.data_mut();
    let mut caret = x;
    let mut prev: Option<GlyphId> = None;
    for c in s.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            caret += f.kern(p, id);
        }
        let glyph = id.with_scale_and_position(size, point(caret, y));
        caret += f.h_advance(id);
        prev = Some(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let b = outline.px_bounds();
        outline.draw(|gx, gy, cov| {
            let (px, py) = (b.min.x as i32 + gx as i32, b.min.y as i32 + gy as i32);
            if px < 0 || py < 0 || px >= w || py >= h {
                return;
            }
            let k = ((py * w + px) * 4) as usize;
            let a = cov.clamp(0.0, 1.0);
            for i in 0..3 {
                let old = f32::from(data[k + i]);
                data[k + i] = (old + (f32::from(rgb[i]) - old) * a).round() as u8;
            }
        });
    }
}
