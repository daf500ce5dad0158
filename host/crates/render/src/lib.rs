//! Pictures and meshes of a simulated part: the 2D top view shaded by depth
//! ([`top`]), a lit 3D view with an optional toolpath ([`view`]), the
//! toolpath alone, a watertight binary STL ([`mesh`]), and the toolpath as
//! straight pieces for a viewer to draw ([`pieces`]). Everything here
//! takes a height field or segments and writes to any `Write`; `cli` picks
//! the files.

pub mod font;
pub mod mesh;
pub mod pieces;
pub mod top;
pub mod view;

use std::io::{self, Write};

/// An RGB picture.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[u8; 3]>,
}

pub const WHITE: [u8; 3] = [255, 255, 255];
pub const BLACK: [u8; 3] = [0, 0, 0];

impl Image {
    pub fn new(width: u32, height: u32, background: [u8; 3]) -> Image {
        Image { width, height, pixels: vec![background; width as usize * height as usize] }
    }

    pub fn get(&self, x: u32, y: u32) -> [u8; 3] {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// Sets a pixel; outside the picture, nothing.
    #[inline]
    pub fn set(&mut self, x: i64, y: i64, colour: [u8; 3]) {
        if x >= 0 && y >= 0 && (x as u32) < self.width && (y as u32) < self.height {
            self.pixels[y as usize * self.width as usize + x as usize] = colour;
        }
    }

    pub fn fill_rect(&mut self, x: i64, y: i64, w: i64, h: i64, colour: [u8; 3]) {
        for yy in y..y + h {
            for xx in x..x + w {
                self.set(xx, yy, colour);
            }
        }
    }

    /// A one-pixel line between two points (DDA).
    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), colour: [u8; 3]) {
        let steps = (b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil().clamp(1.0, 1e5) as usize;
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            self.set((a.0 + t * (b.0 - a.0)).round() as i64, (a.1 + t * (b.1 - a.1)).round() as i64, colour);
        }
    }

    /// Writes the picture as a PNG.
    pub fn write_png(&self, out: impl Write) -> io::Result<()> {
        let mut encoder = png::Encoder::new(out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(io::Error::other)?;
        writer.write_image_data(self.pixels.as_flattened()).map_err(io::Error::other)?;
        writer.finish().map_err(io::Error::other)
    }
}

/// A colour between `a` (t = 0) and `b` (t = 1).
pub fn mix(a: [u8; 3], b: [u8; 3], t: f64) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0);
    std::array::from_fn(|i| (a[i] as f64 + t * (b[i] as f64 - a[i] as f64)).round() as u8)
}

/// A colour's brightness (Rec. 601 luma), for tests and legends.
pub fn luma(c: [u8; 3]) -> f64 {
    0.299 * c[0] as f64 + 0.587 * c[1] as f64 + 0.114 * c[2] as f64
}

/// A round length near `x`: 1, 2 or 5 times a power of ten, at most `x`.
pub fn round_length(x: f64) -> f64 {
    if x <= 0.0 || !x.is_finite() {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0].into_iter().map(|m| m * p).find(|v| *v <= x).unwrap_or(p)
}

/// A length for a label: up to 4 significant decimals, no trailing zeros.
pub fn label(x: f64) -> String {
    let text = format!("{x:.4}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_string()
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_lengths_and_labels() {
        assert_eq!(round_length(37.0), 20.0);
        assert_eq!(round_length(0.6), 0.5);
        assert_eq!(round_length(1.0), 1.0);
        assert_eq!(label(2.5), "2.5");
        assert_eq!(label(10.0), "10");
        assert_eq!(label(-0.00001), "0");
    }

    #[test]
    fn pngs_decode_to_the_same_pixels() {
        let mut image = Image::new(7, 5, WHITE);
        image.line((0.0, 0.0), (6.0, 4.0), BLACK);
        let mut bytes = Vec::new();
        image.write_png(&mut bytes).unwrap();
        let decoded = decode(&bytes);
        assert_eq!(decoded, image);
    }

    /// A PNG back to an image (RGB only): for tests.
    pub fn decode(bytes: &[u8]) -> Image {
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        let pixels = buf[..info.buffer_size()].chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        Image { width: info.width, height: info.height, pixels }
    }
}
