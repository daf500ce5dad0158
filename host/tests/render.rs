//! `ger render` and `ger pulses` through the binary: pictures tested by their
//! properties, the STL by watertightness and volume, pulses by hand-counted
//! steps, and the bad inputs by exit status and message.

use std::collections::HashMap;
use std::path::Path;
use std::process::{Command, Output};

fn ger(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ger")).current_dir(dir).args(args).output().unwrap()
}

fn setup(program: &str, config: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("part.ngc"), program).unwrap();
    std::fs::write(dir.path().join("ger.toml"), config).unwrap();
    dir
}

/// Two pockets 0.1 and 0.3 deep in a 2 x 1 x 0.5 block, quarter-inch endmill.
const POCKETS: &str = "G20\nG00 Z0.1\nX0.5 Y0.5\nG01 Z-0.1 F10\nG02 X0.5 Y0.5 I0.1 J0\nG00 Z0.1\n\
                       X1.5 Y0.5\nG01 Z-0.3\nG02 X1.5 Y0.5 I0.1 J0\nG00 Z0.1\nM30\n";
const BLOCK: &str = "[stock]\nsize = [2, 1, 0.5]\norigin = [0, 0, 0.5]\n";

struct Png {
    width: u32,
    height: u32,
    pixels: Vec<[u8; 3]>,
}

impl Png {
    fn read(path: &Path) -> Png {
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        let pixels = buf[..info.buffer_size()].chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        Png { width: info.width, height: info.height, pixels }
    }

    fn at(&self, x: u32, y: u32) -> [u8; 3] {
        self.pixels[(y * self.width + x) as usize]
    }
}

fn luma(c: [u8; 3]) -> f64 {
    0.299 * c[0] as f64 + 0.587 * c[1] as f64 + 0.114 * c[2] as f64
}

fn ok(out: &Output) {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn the_top_view_is_darker_where_deeper_and_empty_around_the_stock() {
    let dir = setup(POCKETS, BLOCK);
    ok(&ger(dir.path(), &["render", "part.ngc", "-o", "top.png", "--size", "400x300"]));
    let png = Png::read(&dir.path().join("top.png"));
    assert_eq!((png.width, png.height), (400, 300));
    for (x, y) in [(0, 0), (399, 0), (0, 299), (5, 150)] {
        assert_eq!(png.at(x, y), [255, 255, 255], "background at {x},{y}");
    }
    // The stock is placed as `top::placement` says: 2 x 1 in, 16 px padding, 120 px legend, 44 px footer.
    let scale = ((400.0 - 32.0 - 120.0) / 2.0f64).min((300.0 - 32.0 - 44.0) / 1.0);
    let left = 16.0 + ((400.0 - 32.0 - 120.0) as i64 - (2.0 * scale).round() as i64) as f64 / 2.0;
    let top = 16.0 + ((300.0 - 32.0 - 44.0) as i64 - scale.round() as i64) as f64 / 2.0;
    let pixel = |x: f64, y: f64| png.at((left + x * scale) as u32, (top + (1.0 - y) * scale) as u32);
    let uncut = luma(pixel(1.0, 0.9));
    let shallow = luma(pixel(0.5, 0.5));
    let deep = luma(pixel(1.5, 0.5));
    assert!(uncut > shallow + 10.0 && shallow > deep + 10.0, "{uncut} {shallow} {deep}");
}

#[test]
fn the_3d_view_shows_the_part_on_an_empty_background_with_the_toolpath_over_it() {
    let dir = setup(POCKETS, BLOCK);
    ok(&ger(dir.path(), &["render", "part.ngc", "-o", "iso.png", "--size", "320x240", "--view", "iso"]));
    let png = Png::read(&dir.path().join("iso.png"));
    assert_eq!((png.width, png.height), (320, 240));
    assert_eq!(png.at(0, 0), [255, 255, 255]);
    assert_eq!(png.at(319, 239), [255, 255, 255]);
    let lit = png.pixels.iter().filter(|c| **c != [255, 255, 255]).count();
    assert!(lit > 320 * 240 / 5, "the part fills the picture: {lit}");
    // Lit from above: the top faces are brighter than the front wall.
    ok(&ger(dir.path(), &["render", "part.ngc", "-o", "path.png", "--size", "320x240", "--with-toolpath"]));
    let png = Png::read(&dir.path().join("path.png"));
    let blue = png.pixels.iter().filter(|c| c[2] > 150 && c[0] < 60).count();
    let red = png.pixels.iter().filter(|c| c[0] > 200 && c[1] < 80).count();
    assert!(blue > 50 && red > 20, "blue {blue} red {red}");
}

#[test]
fn the_3d_view_draws_the_fixtures_in_their_own_colour() {
    let green = |png: &Png| {
        png.pixels.iter().filter(|c| c[1] as i32 > c[0] as i32 + 30 && c[1] as i32 > c[2] as i32 + 30).count()
    };
    let dir = setup(POCKETS, BLOCK);
    ok(&ger(
        dir.path(),
        &["render", "part.ngc", "-o", "plain.png", "--size", "320x240", "--view", "top", "--format", "3d"],
    ));
    assert_eq!(green(&Png::read(&dir.path().join("plain.png"))), 0, "nothing green without fixtures");
    // A jaw 0.4 x 1 in beside the 2 x 1 in block: seen from above, about a seventh of the picture's width.
    let jaw = "[[fixtures]]\nname = \"jaw\"\nmin = [2.2, 0, -0.5]\nmax = [2.6, 1, 0.2]\n";
    std::fs::write(dir.path().join("ger.toml"), format!("{BLOCK}{jaw}")).unwrap();
    ok(&ger(
        dir.path(),
        &["render", "part.ngc", "-o", "jaw.png", "--size", "320x240", "--view", "top", "--format", "3d"],
    ));
    let png = Png::read(&dir.path().join("jaw.png"));
    let (jaw, all) = (green(&png), png.pixels.iter().filter(|c| **c != [255, 255, 255]).count());
    let share = jaw as f64 / all as f64;
    assert!((0.10..0.20).contains(&share), "the jaw is {jaw} of {all} drawn pixels");
}

#[test]
fn the_top_view_takes_in_the_fixtures_and_draws_them_over_the_part() {
    let green = |png: &Png| {
        png.pixels.iter().filter(|c| c[1] as i32 > c[0] as i32 + 30 && c[1] as i32 > c[2] as i32 + 30).count()
    };
    let dir = setup(POCKETS, BLOCK);
    ok(&ger(dir.path(), &["render", "part.ngc", "-o", "plain.png", "--size", "400x300"]));
    assert_eq!(green(&Png::read(&dir.path().join("plain.png"))), 0, "nothing green without fixtures");
    // The jaw 0.4 x 1 in beside the 2 x 1 in block: the picture takes in 2.6 x 1 in, a jaw of 0.4 of it.
    let jaw = "[[fixtures]]\nname = \"jaw\"\nmin = [2.2, 0, -0.5]\nmax = [2.6, 1, 0.2]\n";
    std::fs::write(dir.path().join("ger.toml"), format!("{BLOCK}{jaw}")).unwrap();
    ok(&ger(dir.path(), &["render", "part.ngc", "-o", "jaw.png", "--size", "400x300"]));
    let png = Png::read(&dir.path().join("jaw.png"));
    // Placed as `top::placement` places 2.6 x 1 in: 16 px padding, 120 px legend, 44 px footer.
    let scale = ((400.0 - 32.0 - 120.0) / 2.6f64).min((300.0 - 32.0 - 44.0) / 1.0);
    let (width, height) = ((2.6 * scale).round(), scale.round());
    let share = green(&png) as f64 / (width * height);
    assert!((share - 0.4 / 2.6).abs() < 0.01, "the jaw is {share} of the picture");
    // The part is drawn narrower, the stock's left edge where the picture's is.
    let left = 16.0 + ((400.0 - 32.0 - 120.0) as i64 - width as i64) as f64 / 2.0;
    let top = 16.0 + ((300.0 - 32.0 - 44.0) as i64 - height as i64) as f64 / 2.0;
    let pixel = |x: f64, y: f64| png.at((left + x * scale) as u32, (top + (1.0 - y) * scale) as u32);
    let (uncut, deep, jaw) = (luma(pixel(1.0, 0.9)), luma(pixel(1.5, 0.5)), pixel(2.4, 0.5));
    assert!(uncut > deep + 20.0, "{uncut} {deep}");
    assert!(jaw[1] as i32 > jaw[0] as i32 + 30 && jaw[1] as i32 > jaw[2] as i32 + 30, "{jaw:?}");
    assert_eq!(png.at((left - 2.0) as u32, (top + 0.5 * scale) as u32), [255, 255, 255]);
}

#[test]
fn the_toolpath_alone_has_rapids_and_feeds_in_their_colours() {
    let dir = setup(POCKETS, BLOCK);
    ok(&ger(dir.path(), &["render", "part.ngc", "-o", "tp.png", "--toolpath", "--view", "top", "--size", "200x100"]));
    let png = Png::read(&dir.path().join("tp.png"));
    let blue = png.pixels.iter().filter(|c| **c == [20, 60, 200]).count();
    let red = png.pixels.iter().filter(|c| **c == [225, 40, 30]).count();
    let white = png.pixels.iter().filter(|c| **c == [255, 255, 255]).count();
    assert!(blue > 30 && red > 10 && white + blue + red == png.pixels.len(), "{blue} {red} {white}");
}

/// The triangles of a binary STL.
fn read_stl(path: &Path) -> Vec<[[f32; 3]; 3]> {
    let bytes = std::fs::read(path).unwrap();
    let count = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * count);
    let f = |k: usize| f32::from_le_bytes(bytes[k..k + 4].try_into().unwrap());
    (0..count)
        .map(|t| {
            let base = 84 + 50 * t + 12;
            std::array::from_fn(|v| std::array::from_fn(|a| f(base + 12 * v + 4 * a)))
        })
        .collect()
}

#[test]
fn the_stl_is_watertight_and_holds_the_stock_less_the_cut() {
    let dir = setup(POCKETS, BLOCK);
    ok(&ger(dir.path(), &["render", "part.ngc", "-o", "part.stl", "--resolution", "0.01"]));
    let triangles = read_stl(&dir.path().join("part.stl"));
    // Every edge is in exactly two triangles, once in each direction.
    let key = |p: [f32; 3]| p.map(f32::to_bits);
    let mut edges: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
    for t in &triangles {
        for k in 0..3 {
            let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
            *edges.entry((a, b)).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "edge {a:?}-{b:?} used {n} times in one direction");
        assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a:?}-{b:?} has no twin");
    }
    // Volume by the divergence theorem: the block less two discs of radius 0.225.
    let volume: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|p| p.map(f64::from));
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum();
    let want = 2.0 * 1.0 * 0.5 - std::f64::consts::PI * 0.225f64.powi(2) * (0.1 + 0.3);
    assert!((volume / want - 1.0).abs() < 0.01, "{volume} vs {want}");
}

fn stl_volume(path: &Path) -> f64 {
    read_stl(path)
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|p| p.map(f64::from));
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum()
}

#[test]
fn a_job_renders_the_part_all_its_programs_cut() {
    // The two pockets of POCKETS as two programs, one after the other, on one block.
    let first = "G20\nG00 Z0.1\nX0.5 Y0.5\nG01 Z-0.1 F10\nG02 X0.5 Y0.5 I0.1 J0\nG00 Z0.1\nM30\n";
    let second = "G20\nG00 Z0.1\nX1.5 Y0.5\nG01 Z-0.3 F10\nG02 X1.5 Y0.5 I0.1 J0\nG00 Z0.1\nM30\n";
    let dir = setup(first, BLOCK);
    std::fs::write(dir.path().join("second.ngc"), second).unwrap();
    ok(&ger(dir.path(), &["render", "part.ngc", "second.ngc", "-o", "job.stl", "--resolution", "0.01"]));
    let volume = stl_volume(&dir.path().join("job.stl"));
    let want = 2.0 * 1.0 * 0.5 - std::f64::consts::PI * 0.225f64.powi(2) * (0.1 + 0.3);
    assert!((volume / want - 1.0).abs() < 0.01, "{volume} vs {want}");
}

#[test]
fn a_program_that_cuts_nothing_still_renders_the_stock() {
    let dir = setup("G20\nG00 X1 Y1 Z1\nM30\n", "");
    ok(&ger(dir.path(), &["render", "part.ngc", "-o", "empty.png", "--size", "200x150"]));
    let png = Png::read(&dir.path().join("empty.png"));
    assert!(png.pixels.contains(&[238, 226, 198]), "uncut stock is drawn");
}

#[test]
fn a_missing_tool_is_an_error_at_its_m06_and_writes_nothing() {
    let dir = setup("G20\nM06 T9\nG01 X1 Z-0.1 F10\nM30\n", "");
    let out = ger(dir.path(), &["render", "part.ngc", "-o", "x.png"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("tool 9 is not in the tool table") && stderr.contains(":2:1"), "{stderr}");
    assert!(!dir.path().join("x.png").exists());
}

#[test]
fn too_fine_a_resolution_is_refused_naming_the_finest_that_fits() {
    let dir = setup(POCKETS, BLOCK);
    let out = ger(dir.path(), &["render", "part.ngc", "-o", "x.stl", "--resolution", "0.0001", "--memory-limit", "16"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("the finest that fits is --resolution 0.000"), "{stderr}");
    let finest: f64 = stderr.split("--resolution ").nth(1).unwrap().split_whitespace().next().unwrap().parse().unwrap();
    ok(&ger(
        dir.path(),
        &["render", "part.ngc", "-o", "x.stl", "--resolution", &finest.to_string(), "--memory-limit", "16"],
    ));
}

#[test]
fn bad_view_parameters_are_usage_errors() {
    let dir = setup(POCKETS, BLOCK);
    for args in [
        &["--elevation", "95"][..],
        &["--zoom", "0"],
        &["--view", "sideways"],
        &["--azimuth", "nan"],
        &["--size", "10x10"],
        &["--resolution", "-1"],
    ] {
        let mut all = vec!["render", "part.ngc", "-o", "v.png"];
        all.extend_from_slice(args);
        let out = ger(dir.path(), &all);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    }
    let out = ger(dir.path(), &["render", "part.ngc", "-o", "v.stl", "--view", "top"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn pulses_count_the_steps_by_hand() {
    // At 10 steps per inch: Z down 0.3 (3 ticks), then X 1, Y 0.5 (10 ticks, Y on every other).
    let dir = setup("G20\nG01 Z-0.3 F10\nX1 Y0.5\nM30\n", "");
    let out = ger(dir.path(), &["pulses", "part.ngc", "--steps-per-unit", "10"]);
    ok(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    let ticks: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(ticks.len(), 13, "{text}");
    assert_eq!(ticks[0], "1\t2\t0 0 1\t1 1 0");
    assert_eq!(ticks[3], "4\t3\t1 1 0\t1 1 0");
    assert_eq!(ticks[4], "5\t3\t1 0 0\t1 1 0");
    assert!(text.ends_with("# 13 ticks; steps X 10 Y 5 Z 3; at X 10 Y 5 Z -3 (steps)\n"), "{text}");
    let out = ger(dir.path(), &["pulses", "part.ngc", "--steps-per-unit", "10", "--limit", "2"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.lines().filter(|l| !l.starts_with('#')).count(), 2);
    assert!(text.ends_with("# 2 ticks; steps X 0 Y 0 Z 2; at X 0 Y 0 Z -2 (steps)\n"), "{text}");
}
