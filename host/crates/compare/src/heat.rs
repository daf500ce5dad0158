//! The comparison as a picture: the part from above, each cell coloured by
//! its verdict (red gouged, green within the tolerance, blue material
//! left), with a legend and a scale as `ger render`'s top view has.

use ger_render::top::placement;
use ger_render::{font, label, Image, BLACK, WHITE};
use ger_sim::HeightField;

use crate::Verdict;

pub const GOUGED: [u8; 3] = [215, 40, 35];
pub const WITHIN: [u8; 3] = [70, 170, 80];
pub const LEFT: [u8; 3] = [40, 90, 210];
/// Cells the design does not cover.
pub const UNJUDGED: [u8; 3] = [225, 225, 225];

/// `width` x `height` pixels of `verdicts` (row-major over `field`'s grid);
/// `tolerance` and `unit` label the legend.
pub fn heat_map(
    field: &HeightField,
    verdicts: &[Verdict],
    tolerance: f64,
    width: u32,
    height: u32,
    unit: &str,
) -> Image {
    let mut image = Image::new(width, height, WHITE);
    let place = placement(field, width, height);
    for py in 0..place.height {
        // Y up: the picture's first row is the stock's far edge.
        let j = (((place.height - 1 - py) as f64 + 0.5) / place.height as f64 * field.ny as f64) as usize;
        for px in 0..place.width {
            let i = ((px as f64 + 0.5) / place.width as f64 * field.nx as f64) as usize;
            let colour = match verdicts[j.min(field.ny - 1) * field.nx + i.min(field.nx - 1)] {
                Verdict::Unjudged => UNJUDGED,
                Verdict::Within => WITHIN,
                Verdict::Gouged => GOUGED,
                Verdict::Left => LEFT,
            };
            image.set(place.left + px, place.top + py, colour);
        }
    }
    let t = label(tolerance);
    let x = image.width as i64 - 112;
    for (k, (colour, text)) in
        [(GOUGED, format!("< -{t}")), (WITHIN, format!("+-{t}")), (LEFT, format!("> +{t}"))].iter().enumerate()
    {
        let y = 24 + 28 * k as i64;
        image.fill_rect(x, y, 18, 18, *colour);
        font::draw(&mut image, x + 26, y + 2, text, 2, BLACK);
    }
    font::draw(&mut image, x + 26, 24 + 28 * 3, unit, 2, BLACK);
    image
}
