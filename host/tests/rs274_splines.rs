//! Differential test of the lenient dialect's splines (G5, G5.1, G5.2/G5.3)
//! against LinuxCNC, on the programs in `tests/differential/splines/`.
//!
//! `rs274 -g` prints a curve as `NURBS_FEED(n, ...)`, without its points, so
//! it is asked only to accept each program and to draw as many curves as the
//! program has G5, G5.1 and G5.3 lines. The path comes from LinuxCNC's
//! preview: the `gcode` Python module AXIS draws with, on the same
//! interpreter (`preview.py` beside the programs), which follows each curve
//! with straight feeds whose ends lie on it. Line by line, every point of the
//! preview must lie within ger's spline tolerance of ger's path, and ger's
//! path (its arcs followed finely) within that tolerance of the preview's,
//! allowing for how far the preview's chords cut inside the curve.
//!
//! Both come with Debian's `linuxcnc-uspace` (the module for Debian's own
//! `/usr/bin/python3`). Where they are missing the test says so and passes,
//! except under CI, where a missing peer is a failure.

mod support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use support::rs274::{self, Kind, Machine, Moves};

const TIME_LIMIT: Duration = Duration::from_secs(20);

/// ger's default spline tolerance on a millimetre machine (tests/differential/ger.toml).
const TOLERANCE_MM: f64 = 0.02;
const PYTHON: &str = "/usr/bin/python3";

type Point = [f64; 2];

/// One move of a path in the XY plane: an arc has its centre and turn.
#[derive(Clone, Copy, Debug)]
struct Piece {
    start: Point,
    end: Point,
    arc: Option<(Point, bool)>,
}

#[test]
fn ger_splines_follow_linuxcnc() {
    let preview_works = Command::new(PYTHON).args(["-c", "import gcode"]).output().is_ok_and(|o| o.status.success());
    if !rs274::available() || !preview_works {
        let message = "rs274 and LinuxCNC's gcode module for /usr/bin/python3 (Debian package linuxcnc-uspace) \
                       are not installed: the spline differential test did NOT run";
        support::peer_missing(message);
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/differential");
    let mut programs: Vec<PathBuf> = std::fs::read_dir(dir.join("splines"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ngc"))
        .collect();
    programs.sort();
    assert!(programs.len() >= 2, "the spline programs are missing");
    let mut failures = Vec::new();
    for program in &programs {
        let scratch = tempfile::tempdir().unwrap();
        // LinuxCNC's preview reads a parameter file and writes its offsets
        // back into it: it gets a fresh, empty one.
        let var = |name: &str| {
            let path = scratch.path().join(name);
            std::fs::write(&path, "").unwrap();
            path
        };
        let curves = rs274_curves(program);
        let expected = curve_lines(program);
        let name = program.file_name().unwrap().to_string_lossy().to_string();
        if curves != expected {
            failures.push(format!("{name}: rs274 drew {curves} curves, the program has {expected}"));
            continue;
        }
        let ger = ger_path(program, &dir.join("ger.toml"));
        let preview = preview_path(program, &var("preview.var"));
        match compare(&ger, &preview) {
            Ok(lines) => eprintln!("{name}: {curves} curves, {lines} lines agree"),
            Err(problem) => failures.push(format!("{name}: {problem}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// How many G5, G5.1 and G5.3 lines the program has: each draws one curve.
fn curve_lines(program: &Path) -> usize {
    let text = std::fs::read_to_string(program).unwrap();
    let code = |word: &str| matches!(word.to_ascii_uppercase().as_str(), "G5" | "G05" | "G5.1" | "G05.1" | "G5.3");
    text.lines().filter(|line| !line.starts_with('(') && line.split_whitespace().any(code)).count()
}

/// How many curves rs274 draws; it must accept the program.
fn rs274_curves(program: &Path) -> usize {
    let moves = rs274::moves(program, &Machine::default(), TIME_LIMIT)
        .unwrap_or_else(|refusal| panic!("rs274 refuses {}: {refusal:?}", program.display()));
    moves.iter().filter(|m| m.kind == Kind::Spline).count()
}

/// ger's moves in the XY plane, by the program line they come from.
fn ger_path(program: &Path, config: &Path) -> BTreeMap<u32, Vec<Piece>> {
    let output = Command::new(env!("CARGO_BIN_EXE_ger"))
        .arg("run")
        .arg("--lenient")
        .arg("--config")
        .arg(config)
        .arg(program)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "ger failed on {}:\n{}",
        program.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    let mut path: BTreeMap<u32, Vec<Piece>> = BTreeMap::new();
    for m in Moves::from_ger(&String::from_utf8(output.stdout).unwrap()).iter() {
        let (Some(start), Some(end), Some(line)) = (m.start, m.end, m.line) else { continue };
        let arc = match m.kind {
            Kind::Arc { centre, turn } => Some(([centre[0], centre[1]], turn > 0)),
            Kind::Rapid | Kind::Feed => None,
            _ => continue,
        };
        let (start, end) = ([start[0], start[1]], [end[0], end[1]]);
        if end != start {
            path.entry(line).or_default().push(Piece { start, end, arc });
        }
    }
    path
}

/// The preview's move ends in the XY plane, by program line, as pieces.
fn preview_path(program: &Path, var: &Path) -> BTreeMap<u32, Vec<Piece>> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/differential/splines/preview.py");
    let output = Command::new(PYTHON).arg(script).arg(program).arg(var).output().unwrap();
    assert!(output.status.success(), "LinuxCNC's preview failed:\n{}", String::from_utf8_lossy(&output.stderr));
    let mut path: BTreeMap<u32, Vec<Piece>> = BTreeMap::new();
    let mut at = [0.0, 0.0];
    for line in String::from_utf8(output.stdout).unwrap().lines() {
        let fields: Vec<f64> = line.split_whitespace().map(|f| f.parse().unwrap()).collect();
        let end = [fields[1], fields[2]];
        if distance(end, at) > 1e-9 {
            path.entry(fields[0] as u32).or_default().push(Piece { start: at, end, arc: None });
        }
        at = end;
    }
    path
}

/// Whether the two paths agree line by line; the number of lines compared.
fn compare(ger: &BTreeMap<u32, Vec<Piece>>, preview: &BTreeMap<u32, Vec<Piece>>) -> Result<usize, String> {
    let lines = |path: &BTreeMap<u32, Vec<Piece>>| path.keys().copied().collect::<Vec<_>>();
    if lines(ger) != lines(preview) {
        return Err(format!("ger moves on lines {:?}, LinuxCNC on {:?}", lines(ger), lines(preview)));
    }
    for (line, ours) in ger {
        let theirs = &preview[line];
        // The preview's points are on the curve: each within the tolerance of ger's path.
        for piece in theirs {
            let off = distance_to_path(piece.end, ours);
            if off > TOLERANCE_MM + 1e-6 {
                return Err(format!("line {line}: LinuxCNC's point {:?} is {off:.4} mm from ger's path", piece.end));
            }
        }
        // ger's path against the preview's chords, which cut inside the curve by their sagitta.
        let allowance = TOLERANCE_MM + chord_sagitta(theirs) + 1e-6;
        for piece in ours {
            for k in 0..=16 {
                let p = point_on(piece, f64::from(k) / 16.0);
                let off = distance_to_path(p, theirs);
                if off > allowance {
                    return Err(format!(
                        "line {line}: ger's point {p:?} is {off:.4} mm from LinuxCNC's path (allowed {allowance:.4})"
                    ));
                }
            }
        }
    }
    Ok(ger.len())
}

/// How far a polyline's chords may lie inside the curve through its points:
/// the sagitta of the circle through each three points in a row, over one chord.
fn chord_sagitta(polyline: &[Piece]) -> f64 {
    polyline
        .windows(2)
        .map(|pair| {
            let (a, b, c) = (pair[0].start, pair[0].end, pair[1].end);
            let (ab, bc, ca) = (distance(a, b), distance(b, c), distance(c, a));
            let cross = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
            if cross < 1e-12 {
                return 0.0;
            }
            let radius = ab * bc * ca / (2.0 * cross);
            let chord = ab.max(bc);
            radius - (radius * radius - chord * chord / 4.0).max(0.0).sqrt()
        })
        .fold(0.0, f64::max)
}

fn distance(a: Point, b: Point) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn distance_to_path(p: Point, path: &[Piece]) -> f64 {
    path.iter().map(|piece| distance_to_piece(p, piece)).fold(f64::INFINITY, f64::min)
}

/// The angle turned from the start of an arc to `p`, in its own sense, 0 to 2π.
fn turned(piece: &Piece, centre: Point, ccw: bool, p: Point) -> f64 {
    let angle = |q: Point| (q[1] - centre[1]).atan2(q[0] - centre[0]);
    let turn = (angle(p) - angle(piece.start)) * if ccw { 1.0 } else { -1.0 };
    turn.rem_euclid(std::f64::consts::TAU)
}

fn distance_to_piece(p: Point, piece: &Piece) -> f64 {
    match piece.arc {
        None => {
            let (a, b) = (piece.start, piece.end);
            let ab = [b[0] - a[0], b[1] - a[1]];
            let t = (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / (ab[0] * ab[0] + ab[1] * ab[1])).clamp(0.0, 1.0);
            distance(p, [a[0] + t * ab[0], a[1] + t * ab[1]])
        }
        Some((centre, ccw)) => {
            if turned(piece, centre, ccw, p) <= turned(piece, centre, ccw, piece.end) {
                (distance(p, centre) - distance(piece.start, centre)).abs()
            } else {
                distance(p, piece.start).min(distance(p, piece.end))
            }
        }
    }
}

fn point_on(piece: &Piece, f: f64) -> Point {
    match piece.arc {
        None => {
            [piece.start[0] + f * (piece.end[0] - piece.start[0]), piece.start[1] + f * (piece.end[1] - piece.start[1])]
        }
        Some((centre, ccw)) => {
            let sweep = turned(piece, centre, ccw, piece.end);
            let angle = (piece.start[1] - centre[1]).atan2(piece.start[0] - centre[0])
                + if ccw { f * sweep } else { -f * sweep };
            let r = distance(piece.start, centre);
            [centre[0] + r * angle.cos(), centre[1] + r * angle.sin()]
        }
    }
}
