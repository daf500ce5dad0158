//! The 3D display: the cut stock lit and shaded from any direction, with
//! the fixtures that hold it and an optional toolpath drawn over it; and
//! the toolpath alone.
//!
//! An orthographic camera on a sphere around the part: azimuth turns it
//! about Z (0 looks from the front, -Y, towards +Y; 90 from the right),
//! elevation raises it (90 looks straight down). The mesh is the same as the
//! STL's, rasterised with a depth buffer at twice the resolution and averaged
//! down.

use super::mesh::{normal, Mesh};
use super::{Image, WHITE};
use ger_sim::{HeightField, Point, Segment, Solid};

/// Uncut stock.
pub const STOCK: [u8; 3] = [222, 194, 146];
/// Cut surfaces.
pub const CUT: [u8; 3] = [156, 184, 222];
pub const FEED: [u8; 3] = [20, 60, 200];
pub const RAPID: [u8; 3] = [225, 40, 30];
/// Fixtures (`[[fixtures]]`): what the tool must not touch.
pub const FIXTURE: [u8; 3] = [120, 200, 90];

/// Where the camera looks from, and the picture's size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Degrees about Z: 0 front, 90 right, 180 back, 270 left.
    pub azimuth: f64,
    /// Degrees above the XY plane, -90..=90.
    pub elevation: f64,
    /// 1 fits the part in the picture; 2 is twice as large.
    pub zoom: f64,
    pub width: u32,
    pub height: u32,
}

/// The named views: azimuth and elevation.
pub fn preset(name: &str) -> Option<(f64, f64)> {
    let iso = (1.0 / 2f64.sqrt()).atan().to_degrees();
    Some(match name {
        "iso" => (45.0, iso),
        "top" => (0.0, 90.0),
        "bottom" => (0.0, -90.0),
        "front" => (0.0, 0.0),
        "back" => (180.0, 0.0),
        "right" => (90.0, 0.0),
        "left" => (270.0, 0.0),
        _ => return None,
    })
}

pub const PRESETS: &str = "iso, top, bottom, front, back, right, left";

/// World to picture: x right, y down, and depth towards the viewer.
#[derive(Clone, Copy, Debug)]
pub struct Projection {
    right: Point,
    up: Point,
    toward: Point,
    scale: f64,
    offset: (f64, f64),
}

impl Projection {
    /// Fits the box `lo`..`hi` in the picture (with a margin), times the zoom.
    pub fn fit(camera: &Camera, lo: Point, hi: Point) -> Projection {
        let (az, el) = (camera.azimuth.to_radians(), camera.elevation.to_radians());
        let toward = Point::new(az.sin() * el.cos(), -az.cos() * el.cos(), el.sin());
        let right = Point::new(az.cos(), az.sin(), 0.0);
        let up = toward.cross(right);
        let mut p = Projection { right, up, toward, scale: 1.0, offset: (0.0, 0.0) };
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for k in 0..8 {
            let corner = Point::new(
                if k & 1 == 0 { lo[0] } else { hi[0] },
                if k & 2 == 0 { lo[1] } else { hi[1] },
                if k & 4 == 0 { lo[2] } else { hi[2] },
            );
            let (x, y) = (corner.dot(right), corner.dot(up));
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        let (w, h) = ((x1 - x0).max(1e-9), (y1 - y0).max(1e-9));
        p.scale = 0.92 * (camera.width as f64 / w).min(camera.height as f64 / h) * camera.zoom;
        let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        p.offset = (camera.width as f64 / 2.0 - cx * p.scale, camera.height as f64 / 2.0 + cy * p.scale);
        p
    }

    /// The same view, `factor` times the pixels.
    fn scaled(&self, factor: f64) -> Projection {
        Projection { scale: self.scale * factor, offset: (self.offset.0 * factor, self.offset.1 * factor), ..*self }
    }

    #[inline]
    pub fn project(&self, p: Point) -> (f64, f64, f64) {
        (
            self.offset.0 + p.dot(self.right) * self.scale,
            self.offset.1 - p.dot(self.up) * self.scale,
            p.dot(self.toward),
        )
    }
}

/// The lit stock and `fixtures`, `camera.width` x `camera.height`, and the projection used.
pub fn render(field: &HeightField, fixtures: &[Solid], camera: &Camera) -> (Image, Projection) {
    let stock = field.stock;
    let (mut lo, mut hi) = (stock.min, stock.max);
    for fixture in fixtures {
        let (a, b) = fixture.bounds();
        (lo, hi) = (lo.min(a), hi.max(b));
    }
    let projection = Projection::fit(camera, lo, hi);
    const SS: u32 = 2;
    let (w, h) = (camera.width * SS, camera.height * SS);
    let fine = projection.scaled(SS as f64);
    let mut colour = vec![WHITE; (w * h) as usize];
    let mut depth = vec![f32::NEG_INFINITY; (w * h) as usize];
    let light = {
        let l = 0.65 * fine.toward + 0.55 * fine.up - 0.35 * fine.right;
        l / l.length()
    };
    let cut_below = field.top() - (field.top() - field.bottom()) * 1e-6;
    let mut draw = |tri: [Point; 3], base: [u8; 3]| {
        let mut n = normal(tri[0], tri[1], tri[2]);
        if n.dot(fine.toward) < 0.0 {
            n = -n;
        }
        let lit = 0.3 + 0.7 * n.dot(light).max(0.0);
        let shade = base.map(|c| (c as f64 * lit).round().min(255.0) as u8);
        let p = tri.map(|v| fine.project(v));
        raster(&mut colour, &mut depth, w, h, p, shade);
    };
    let mesh = Mesh::new(field);
    mesh.for_each(|tri| {
        let n = normal(tri[0], tri[1], tri[2]);
        let cut = tri.iter().any(|p| p[2] < cut_below) && n[2].abs() > 1e-3 || tri.iter().all(|p| p[2] < cut_below);
        draw(tri, if cut { CUT } else { STOCK });
    });
    for fixture in fixtures {
        solid_triangles(fixture, |tri| draw(tri, FIXTURE));
    }
    // Average each SS x SS block.
    let mut image = Image::new(camera.width, camera.height, WHITE);
    for y in 0..camera.height {
        for x in 0..camera.width {
            let mut sum = [0u32; 3];
            for dy in 0..SS {
                for dx in 0..SS {
                    let c = colour[((y * SS + dy) * w + x * SS + dx) as usize];
                    for i in 0..3 {
                        sum[i] += c[i] as u32;
                    }
                }
            }
            image.pixels[(y * camera.width + x) as usize] = sum.map(|s| (s / (SS * SS)) as u8);
        }
    }
    (image, projection)
}

/// The faces of a fixture as triangles: a box's six, a cylinder's side and ends in 64 steps.
fn solid_triangles(solid: &Solid, mut each: impl FnMut([Point; 3])) {
    match *solid {
        Solid::Box { min, max } => {
            let corner = |k: usize| {
                Point::new(
                    if k & 1 == 0 { min[0] } else { max[0] },
                    if k & 2 == 0 { min[1] } else { max[1] },
                    if k & 4 == 0 { min[2] } else { max[2] },
                )
            };
            // Each face by its four corners, in order round it.
            for face in [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]] {
                let [a, b, c, d] = face.map(corner);
                each([a, b, c]);
                each([a, c, d]);
            }
        }
        Solid::Cylinder { centre, radius, bottom, top } => {
            const STEPS: usize = 64;
            let at = |k: usize, z: f64| {
                let angle = std::f64::consts::TAU * k as f64 / STEPS as f64;
                Point::new(centre[0] + radius * angle.cos(), centre[1] + radius * angle.sin(), z)
            };
            let (low, high) = (Point::new(centre[0], centre[1], bottom), Point::new(centre[0], centre[1], top));
            for k in 0..STEPS {
                let (a0, a1, b0, b1) = (at(k, bottom), at(k + 1, bottom), at(k, top), at(k + 1, top));
                each([a0, a1, b1]);
                each([a0, b1, b0]);
                each([low, a0, a1]);
                each([high, b0, b1]);
            }
        }
    }
}

fn raster(colour: &mut [[u8; 3]], depth: &mut [f32], w: u32, h: u32, p: [(f64, f64, f64); 3], shade: [u8; 3]) {
    let [(x0, y0, z0), (x1, y1, z1), (x2, y2, z2)] = p;
    let area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    if area.abs() < 1e-12 {
        return;
    }
    let xmin = x0.min(x1).min(x2).floor().max(0.0) as i64;
    let xmax = (x0.max(x1).max(x2).ceil() as i64).min(w as i64 - 1);
    let ymin = y0.min(y1).min(y2).floor().max(0.0) as i64;
    let ymax = (y0.max(y1).max(y2).ceil() as i64).min(h as i64 - 1);
    for py in ymin..=ymax {
        let cy = py as f64 + 0.5;
        for px in xmin..=xmax {
            let cx = px as f64 + 0.5;
            let w0 = ((x2 - x1) * (cy - y1) - (y2 - y1) * (cx - x1)) / area;
            let w1 = ((x0 - x2) * (cy - y2) - (y0 - y2) * (cx - x2)) / area;
            let w2 = 1.0 - w0 - w1;
            if w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9 {
                continue;
            }
            let z = (w0 * z0 + w1 * z1 + w2 * z2) as f32;
            let k = (py as u32 * w + px as u32) as usize;
            if z > depth[k] {
                depth[k] = z;
                colour[k] = shade;
            }
        }
    }
}

/// Draws toolpath segments over a picture: feeds blue, rapids red.
pub struct PathPainter<'i> {
    image: &'i mut Image,
    projection: Projection,
}

impl<'i> PathPainter<'i> {
    pub fn new(image: &'i mut Image, projection: Projection) -> PathPainter<'i> {
        PathPainter { image, projection }
    }

    pub fn add(&mut self, segment: &Segment, rapid: bool) {
        let colour = if rapid { RAPID } else { FEED };
        // Arcs in pieces of at most half a pixel's error.
        let n = segment.pieces(0.5 / self.projection.scale);
        let mut a = self.projection.project(segment.from());
        for k in 1..=n {
            let b = self.projection.project(segment.at(k as f64 / n as f64));
            if rapid && (k % 2 == 0 && n > 1) {
                a = b;
                continue;
            }
            self.image.line((a.0, a.1), (b.0, b.1), colour);
            a = b;
        }
    }
}

/// An empty picture for the toolpath alone, fitted to the path's box.
pub fn blank(camera: &Camera, lo: Point, hi: Point) -> (Image, Projection) {
    (Image::new(camera.width, camera.height, WHITE), Projection::fit(camera, lo, hi))
}
