//! The 2D display: the stock seen from above, each cell shaded by its depth
//! of cut (light: uncut, dark: deepest), the fixtures over it in their own
//! colour, with a depth legend and a scale bar.

use super::view::FIXTURE;
use super::{font, label, mix, round_length, Image, BLACK, WHITE};
use ger_sim::{HeightField, Solid};

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
    placement_of([size[0], size[1]], width, height)
}

/// Where a box `size` across (X, Y) is drawn.
fn placement_of(size: [f64; 2], width: u32, height: u32) -> Placement {
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

/// The top view, `width` x `height` pixels, of the part and the `fixtures`
/// over it (the picture takes in both); `unit` labels the legend ("mm", "in").
pub fn render(field: &HeightField, fixtures: &[Solid], width: u32, height: u32, unit: &str) -> Image {
    let mut image = Image::new(width, height, WHITE);
    let stock = field.stock;
    let (mut lo, mut hi) = ([stock.min[0], stock.min[1]], [stock.max[0], stock.max[1]]);
    for fixture in fixtures {
        let (a, b) = fixture.bounds();
        (lo, hi) = ([lo[0].min(a[0]), lo[1].min(a[1])], [hi[0].max(b[0]), hi[1].max(b[1])]);
    }
    let place = placement_of([hi[0] - lo[0], hi[1] - lo[1]], width, height);
    // The point of the drawn box at the centre of pixel (px, py) of the placement; Y up.
    let at = |px: i64, py: i64| {
        let u = (px as f64 + 0.5) / place.width as f64;
        let v = ((place.height - 1 - py) as f64 + 0.5) / place.height as f64;
        (lo[0] + u * (hi[0] - lo[0]), lo[1] + v * (hi[1] - lo[1]))
    };
    let top = field.top();
    let max = top - field.lowest();
    let size = stock.size();
    for py in 0..place.height {
        for px in 0..place.width {
            let (x, y) = at(px, py);
            let (u, v) = ((x - stock.min[0]) / size[0], (y - stock.min[1]) / size[1]);
            if !(0.0..1.0).contains(&u) || !(0.0..1.0).contains(&v) {
                continue;
            }
            let (i, j) = ((u * field.nx as f64) as usize, (v * field.ny as f64) as usize);
            let depth = top - field.get(i.min(field.nx - 1), j.min(field.ny - 1));
            image.set(place.left + px, place.top + py, shade(depth, max));
        }
    }
    // Fixtures over the part, two thirds opaque (what they hold shows through), with a darker rim.
    let rim = FIXTURE.map(|c| c / 2);
    for py in 0..place.height {
        for px in 0..place.width {
            let inside = |px, py| {
                let (x, y) = at(px, py);
                fixtures.iter().any(|f| f.covers(x, y))
            };
            if !inside(px, py) {
                continue;
            }
            let edge = [(-1, 0), (1, 0), (0, -1), (0, 1)].iter().any(|&(dx, dy)| !inside(px + dx, py + dy));
            let (x, y) = (place.left + px, place.top + py);
            let under = image.get(x as u32, y as u32);
            image.set(x, y, if edge { rim } else { mix(under, FIXTURE, 0.65) });
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
