//! The 2D display: the stock seen from above, each cell shaded by its depth
//! of cut (light: uncut, dark: deepest), with a depth legend and a scale bar.

use super::{font, label, mix, round_length, Image, BLACK, WHITE};
use ger_sim::HeightField;

/// Uncut stock.
pub const SURFACE: [u8; 3] = [238, 226, 198];
/// The deepest cut.
pub const DEEPEST: [u8; 3] = [28, 36, 84];

const PAD: i64 = 16;
const LEGEND: i64 = 120;
const FOOTER: i64 = 44;

/// The colour of a cut `depth` below the top, of `max` in all.
pub fn shade(depth: f64, max: f64) -> [u8; 3] {
    if depth <= 0.0 || max <= 0.0 {
        return SURFACE;
    }
    // Any cut at all is visibly darker than the surface.
    mix(SURFACE, DEEPEST, 0.12 + 0.88 * depth / max)
}

/// Where the stock is drawn: its top-left pixel and pixels per unit.
#[derive(Clone, Copy, Debug)]
pub struct Placement {
    pub left: i64,
    pub top: i64,
    pub width: i64,
    pub height: i64,
    pub scale: f64,
}

pub fn placement(field: &HeightField, width: u32, height: u32) -> Placement {
    let size = field.stock.size();
    let room_w = (width as i64 - 2 * PAD - LEGEND).max(8) as f64;
    let room_h = (height as i64 - 2 * PAD - FOOTER).max(8) as f64;
    let scale = (room_w / size[0]).min(room_h / size[1]);
    let (w, h) = ((size[0] * scale).round() as i64, (size[1] * scale).round() as i64);
    Placement {
        left: PAD + (room_w as i64 - w) / 2,
        top: PAD + (room_h as i64 - h) / 2,
        width: w.max(1),
        height: h.max(1),
        scale,
    }
}

/// The top view, `width` x `height` pixels; `unit` labels the legend ("mm", "in").
pub fn render(field: &HeightField, width: u32, height: u32, unit: &str) -> Image {
    let mut image = Image::new(width, height, WHITE);
    let place = placement(field, width, height);
    let top = field.top();
    let max = top - field.lowest();
    for py in 0..place.height {
        // Y up: the picture's first row is the stock's far edge.
        let j = (((place.height - 1 - py) as f64 + 0.5) / place.height as f64 * field.ny as f64) as usize;
        for px in 0..place.width {
            let i = ((px as f64 + 0.5) / place.width as f64 * field.nx as f64) as usize;
            let depth = top - field.get(i.min(field.nx - 1), j.min(field.ny - 1));
            image.set(place.left + px, place.top + py, shade(depth, max));
        }
    }
    legend(&mut image, max, unit);
    scale_bar(&mut image, &place, unit);
    image
}

/// The depth ramp at the right: 0 at the top, the deepest cut at the bottom.
fn legend(image: &mut Image, max: f64, unit: &str) {
    let x = image.width as i64 - LEGEND + 8;
    let (y0, h) = (PAD + 20, (image.height as i64 - 2 * PAD - FOOTER - 40).clamp(20, 400));
    font::draw(image, x, PAD, "Z", 2, BLACK);
    for k in 0..h {
        let depth = max * k as f64 / (h - 1) as f64;
        image.fill_rect(x, y0 + k, 18, 1, shade(depth, max));
    }
    for (depth, y) in [(0.0, y0), (max / 2.0, y0 + h / 2), (max, y0 + h - 1)] {
        image.fill_rect(x + 18, y, 5, 1, BLACK);
        font::draw(image, x + 26, y - 7, &label(-significant(depth, 3)), 2, BLACK);
    }
    font::draw(image, x + 26, y0 + h + 10, unit, 2, BLACK);
}

/// `x` to `digits` significant digits.
fn significant(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let p = 10f64.powi(x.abs().log10().floor() as i32 + 1 - digits);
    (x / p).round() * p
}

/// A bar of a round length under the stock, with its length.
fn scale_bar(image: &mut Image, place: &Placement, unit: &str) {
    let length = round_length(place.width as f64 / place.scale / 3.0);
    let pixels = (length * place.scale).round() as i64;
    let (x, y) = (place.left, place.top + place.height + 14);
    image.fill_rect(x, y, pixels, 4, BLACK);
    image.fill_rect(x, y - 4, 2, 12, BLACK);
    image.fill_rect(x + pixels - 2, y - 4, 2, 12, BLACK);
    font::draw(image, x + pixels + 8, y - 5, &format!("{} {unit}", label(length)), 2, BLACK);
}
