//! Wizards end to end through the library: real components from `wizards/`
//! and `tests/wizards/guests/`, built on first use, run by the wasmtime
//! runtime inside the real pipeline. Expectations come from geometry and
//! from what each test wizard is written to do, not from recorded output.

use std::path::{Path, PathBuf};
use std::time::Duration;

use ger_core::config::Config;
use ger_core::emit::Emitter;
use ger_core::passes::{translate, Event, Library, Options, LAST_STAGE};
use ger_wasm::{Limits, WasmWizards};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
}

/// The program's output lines and its diagnostics.
fn run(dir: &str, config: &Config, program: &str) -> (Vec<String>, Vec<String>) {
    run_limited(dir, config, Limits::default(), program)
}

/// The same, with wizard calls limited by `limits`; each diagnostic with its
/// help and the calls it ran in.
fn run_limited(dir: &str, config: &Config, limits: Limits, program: &str) -> (Vec<String>, Vec<String>) {
    let mut wizards = WasmWizards::new(&repo(dir), config, limits, Some(Box::new(|_: &str| {})));
    let emitter = Emitter::new(4, false);
    let options = Options { config, stage: LAST_STAGE, wizards: &mut wizards };
    let (mut lines, mut diagnostics) = (Vec::new(), Vec::new());
    for event in translate(program.as_bytes(), Library::empty(), options) {
        match event {
            Event::Statement(s) => lines.push(emitter.line(&s)),
            Event::Diagnostic(d) => {
                diagnostics.push(format!("{d}\n{}\n{}", d.help.clone().unwrap_or_default(), d.call_chain().join("\n")))
            }
        }
    }
    (lines, diagnostics)
}

fn mm(tools: &str) -> Config {
    Config::from_toml(&format!("units = \"mm\"\n{tools}")).unwrap()
}

/// A move as (G code, start, end), tracking position over the output.
fn moves(lines: &[String]) -> Vec<(u32, [f64; 3], [f64; 3])> {
    let mut at = [0.0; 3];
    let mut mode = 0;
    let mut out = Vec::new();
    for line in lines {
        let mut to = at;
        let mut moved = false;
        for word in line.split_whitespace() {
            let (letter, value) = word.split_at(1);
            let Ok(value) = value.parse::<f64>() else { continue };
            match letter {
                "G" if value < 4.0 => mode = value as u32,
                "X" | "Y" | "Z" => {
                    to["XYZ".find(letter).unwrap()] = value;
                    moved = true;
                }
                _ => {}
            }
        }
        if moved {
            out.push((mode, at, to));
            at = to;
        }
    }
    out
}

/// The centre of each line's arc (absolute), or `None` for a line that is no arc.
fn arc_centres(lines: &[String]) -> Vec<Option<[f64; 2]>> {
    let mut at = [0.0; 2];
    let mut out = Vec::new();
    for line in lines {
        let word = |letter: char| {
            line.split_whitespace().find(|w| w.starts_with(letter)).and_then(|w| w[1..].parse::<f64>().ok())
        };
        let moved = ['X', 'Y', 'Z'].iter().any(|&l| word(l).is_some());
        let centre = word('I').zip(word('J')).map(|(i, j)| [at[0] + i, at[1] + j]);
        if moved {
            out.push(centre);
        }
        at = [word('X').unwrap_or(at[0]), word('Y').unwrap_or(at[1])];
    }
    out
}

fn distance_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 == 0.0 { 0.0 } else { (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0) };
    ((p[0] - a[0] - t * dx).powi(2) + (p[1] - a[1] - t * dy).powi(2)).sqrt()
}

#[test]
fn pocket_stays_inside_covers_the_floor_and_never_goes_too_deep() {
    let (x0, y0, length, width, depth, d) = (10.0, -5.0, 75.0, 30.0, 10.0, 6.0);
    let config = mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6.0\n");
    let program = format!("G21 G90\nG00 X{x0} Y{y0} Z0\nF300\nPocket {length} {width} {depth} 4\nM30\n");
    let (lines, diagnostics) = run("wizards", &config, &program);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let moves = moves(&lines);
    let r = d / 2.0;
    let eps = 1e-3;
    let (xa, xb, ya, yb) = (x0 + r, x0 + length - r, y0 + r, y0 + width - r);
    for (mode, a, b) in &moves {
        assert!(a[2] >= -depth - eps && b[2] >= -depth - eps, "below DEPTH: {a:?} -> {b:?}");
        if *mode == 1 {
            for p in [a, b] {
                assert!(p[0] >= xa - eps && p[0] <= xb + eps && p[1] >= ya - eps && p[1] <= yb + eps, "{p:?}");
            }
        }
    }
    // Rasterize the tool along the feed moves at full depth: every point of
    // the pocket a round tool can reach (within r of the inset rectangle)
    // must be cut; only the corners' fillets are left.
    let floor: Vec<_> = moves
        .iter()
        .filter(|(mode, a, b)| *mode == 1 && (a[2] + depth).abs() < eps && (b[2] + depth).abs() < eps)
        .map(|(_, a, b)| ([a[0], a[1]], [b[0], b[1]]))
        .collect();
    assert!(!floor.is_empty(), "nothing cut at full depth");
    let step = 0.2;
    let (mut checked, mut missed) = (0, Vec::new());
    for i in 0..=(length / step) as usize {
        for j in 0..=(width / step) as usize {
            let p = [x0 + i as f64 * step, y0 + j as f64 * step];
            let nearest = [p[0].clamp(xa, xb), p[1].clamp(ya, yb)];
            if distance_to_segment(p, nearest, nearest) > r - eps {
                continue; // a corner fillet: no round tool reaches it
            }
            checked += 1;
            if !floor.iter().any(|(a, b)| distance_to_segment(p, *a, *b) <= r + eps) {
                missed.push(p);
            }
        }
    }
    assert!(checked > 50_000, "{checked}");
    assert!(missed.is_empty(), "{} points not cut, e.g. {:?}", missed.len(), &missed[..missed.len().min(5)]);
    // Three levels of at most 4: 4, 8, 10, each cut level.
    let levels: std::collections::BTreeSet<i64> =
        moves.iter().filter(|m| m.0 == 1 && m.1[2] == m.2[2]).map(|m| (m.2[2] * 1000.0).round() as i64).collect();
    assert_eq!(levels.into_iter().collect::<Vec<_>>(), [-10_000, -8_000, -4_000]);
    // Down to each by ramps in the middle, never steeper than 3 degrees
    // (a chord is no longer than its arc), never straight down.
    for (mode, a, b) in moves.iter().filter(|m| m.0 == 1 && m.1[2] != m.2[2]) {
        let run = (b[0] - a[0]).hypot(b[1] - a[1]);
        // Written to 4 decimals: each end may be 0.00005 off.
        let rounding = 1e-4 / run;
        assert!(run > 0.0 && (a[2] - b[2]) / run <= 3f64.to_radians().tan() + rounding, "G0{mode} {a:?} -> {b:?}");
        let middle = y0 + width / 2.0;
        assert!((a[1] - middle).abs() <= r && (b[1] - middle).abs() <= r, "not in the middle: {a:?} -> {b:?}");
    }
}

#[test]
fn pocket_rounds_its_corners_enters_by_helix_and_climbs_in_either_unit() {
    // (unit, tool, call, the pocket's corner, size and depth, a cell)
    let cases = [
        ("mm", "endmill\"\ndiameter = 6", "Pocket 40 30 6 3 3 3.6 8 0.3 \"helix\"", 8.0, [40.0, 30.0, 6.0], 0.1),
        ("mm", "ballmill\"\ndiameter = 4", "Pocket 40 30 6 2 3 2 5", 5.0, [40.0, 30.0, 6.0], 0.1),
        ("inch", "endmill\"\ndiameter = 0.25", "Pocket 2 1.5 0.3 0.1 3 0.15 0.4 0.01", 0.4, [2.0, 1.5, 0.3], 0.004),
    ];
    for (unit, tool, call, corner, [length, width, depth], cell) in cases {
        let (x0, y0) = (10.0 * cell, 10.0 * cell);
        let g = if unit == "mm" { 21 } else { 20 };
        let program =
            format!("G{g} G90\nM06 T1\nM03 S12000\nG00 X{x0} Y{y0} Z1\nG01 Z0 F100\n{call}\nG00 Z1\nM05\nM30\n");
        let config = format!(
            "units = \"{unit}\"\n[stock]\nsize = [{}, {}, {}]\n[[tools]]\nnumber = 1\nkind = \"{tool}\n\
             flute_length = {}\n",
            length + 20.0 * cell,
            width + 20.0 * cell,
            2.0 * depth,
            2.0 * depth
        );
        // Climb milling with M03 inside a pocket is counter-clockwise: its
        // rounded corners and its helix are G03 arcs, never G02.
        let (lines, _) = run("wizards", &Config::from_toml(&config).unwrap(), &program);
        assert!(lines.iter().any(|l| l.starts_with("G03")) && !lines.iter().any(|l| l.starts_with("G02")), "{call}");
        // With an allowance, the finishing ring is joined at the middle of the
        // bottom wall by arcs tangent to it (their centres straight above that
        // point), from and back to the outermost rough ring's line, the
        // allowance further in: once in and once out at every level.
        let allowance: f64 = call.split_whitespace().nth(8).map_or(0.0, |a| a.parse().unwrap());
        if allowance > 0.0 {
            let r = if unit == "mm" { 3.0 } else { 0.125 };
            let (bottom, rough) = ([x0 + length / 2.0, y0 + r], y0 + r + allowance);
            let at = |p: [f64; 3], q: [f64; 2]| (p[0] - q[0]).abs() < 1e-4 && (p[1] - q[1]).abs() < 1e-4;
            let arcs = moves(&lines).into_iter().zip(arc_centres(&lines)).filter(|((mode, a, b), centre)| {
                let tangent = centre.is_some_and(|c| (c[0] - bottom[0]).abs() < 1e-4 && c[1] > bottom[1]);
                *mode == 3 && tangent && (at(*a, bottom) || at(*b, bottom))
            });
            let on_rough = |p: [f64; 3]| (p[1] - rough).abs() < 1e-4;
            let ends: Vec<(bool, bool)> =
                arcs.map(|((_, a, b), _)| (on_rough(a) && at(b, bottom), at(a, bottom) && on_rough(b))).collect();
            let levels = (depth / if unit == "mm" { 3.0 } else { 0.1 }).round() as usize;
            assert_eq!(ends, [(true, false), (false, true)].repeat(levels), "{call}");
        }
        // No plunge, no rapid into the stock, nothing ger warns of.
        let (status, report) = denied_check(&program, &config);
        assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])), "{call}");
        let field = simulated(&program, &config, cell);
        let at = |dx: f64, dy: f64| height_at(&field, x0 + dx, y0 + dy);
        let tolerance = 2.0 * cell;
        // Nothing below DEPTH, and DEPTH reached; a flat endmill's floor is
        // flat there in the middle (a ball's is scalloped between rings);
        // just outside the walls, uncut.
        let lowest = (0..field.nx).flat_map(|i| (0..field.ny).map(move |j| (i, j))).map(|(i, j)| field.get(i, j));
        assert!((lowest.fold(f64::INFINITY, f64::min) + depth).abs() < 1e-6, "{call}: not cut to DEPTH");
        if tool.starts_with("endmill") {
            assert!((at(length / 2.0, width / 2.0) + depth).abs() < 1e-6, "{call}: {}", at(length / 2.0, width / 2.0));
        }
        for (dx, dy) in [(-tolerance, width / 2.0), (length + tolerance, width / 2.0), (length / 2.0, -tolerance)] {
            assert_eq!(at(dx, dy), 0.0, "{call}: cut outside the wall at {dx}, {dy}");
        }
        for (dx, dy) in [(tolerance, width / 2.0), (length - tolerance, width / 2.0), (length / 2.0, width - tolerance)]
        {
            assert!(at(dx, dy) < -depth / 2.0, "{call}: the wall at {dx}, {dy} is not cut: {}", at(dx, dy));
        }
        // A corner of radius `corner`: beyond its arc uncut, inside it cut.
        // Along the diagonal, the arc is corner (1 - 1/√2) in from the corner.
        let arc = corner * (1.0 - std::f64::consts::FRAC_1_SQRT_2);
        assert_eq!(at(arc - tolerance, arc - tolerance), 0.0, "{call}: the corner is not rounded to {corner}");
        assert!(at(arc + tolerance, arc + tolerance) < 0.0, "{call}: the corner's arc is not cut");
    }
    // What the tool cannot do is an error at the call, not bad G-code.
    let config = mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n");
    for (call, words) in [
        ("Pocket 40 30 6 3 3 6", "would leave ribs"),
        ("Pocket 40 30 6 3 3 3 20", "more than half"),
        ("Pocket 10 10 6 3 3 3 0 2.5", "wider than the pocket"),
        ("Pocket 6.001 6.001 6", "too tight"),
        ("Pocket 40 30 6 3 3 3 0 0 \"spiral\"", "ramp"),
    ] {
        let (_, diagnostics) = run("wizards", &config, &format!("G21 G90\nM06 T1\nG00 X0 Y0 Z0\nF100\n{call}\nM30\n"));
        assert!(diagnostics.len() == 1 && diagnostics[0].contains(words), "{call}: {diagnostics:?}");
    }
    // A corner tighter than the tool is cut at the tool's radius, with a warning.
    let (_, diagnostics) =
        run("wizards", &config, "G21 G90\nM06 T1\nG00 X0 Y0 Z0\nF100\nPocket 40 30 6 3 3 3 1\nM30\n");
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert!(diagnostics[0]
        .starts_with("5:1: warning: wizard `Pocket`: corners of radius 1 are cut to the tool's radius, 3"));
}

/// `ger check --deny warnings --format json` of `program` with `config`: its status and report.
fn denied_check(program: &str, config: &str) -> (Option<i32>, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("part.ngc"), program).unwrap();
    std::fs::write(dir.path().join("ger.toml"), config).unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        // Building what is not built yet (a fresh clone), as `ger check` does.
        .args(["check", "--deny", "warnings", "--quiet", "--format", "json", "--wizards"])
        .arg(repo("wizards"))
        .arg("part.ngc")
        .current_dir(dir.path())
        .output()
        .unwrap();
    let report = serde_json::from_slice(&output.stdout)
        .unwrap_or_else(|_| panic!("{}", String::from_utf8_lossy(&output.stderr)));
    (output.status.code(), report)
}

#[test]
fn circle_pocket_helixes_down_and_cuts_its_circle_to_the_wall() {
    let (cx, cy, diameter, depth) = (40.0, 30.0, 30.0, 8.0);
    for (tool, d, allowance) in [("endmill", 6.0, 0.0), ("ballmill", 4.0, 0.0), ("endmill", 6.0, 0.4)] {
        let tools = format!("[[tools]]\nnumber = 1\nkind = \"{tool}\"\ndiameter = {d}\nflute_length = 20\n");
        let program = format!(
            "G21 G90\nM06 T1\nM03 S12000\nG00 X{cx} Y{cy} Z5\nG01 Z0 F300\nCirclePocket {diameter} {depth} 4 3 {allowance}\n\
             G00 Z5\nM05\nM30\n"
        );
        let (lines, diagnostics) = run("wizards", &mm(&tools), &program);
        assert!(diagnostics.is_empty(), "{diagnostics:?}");
        // Radially, every point of the floor is within the tool's radius of a circle cut at full depth.
        let r = d / 2.0;
        let mut at_floor = Vec::new();
        let wall = diameter / 2.0;
        let path = moves(&lines);
        for ((mode, a, b), centre) in path.iter().zip(arc_centres(&lines)) {
            let (Some(centre), true) = (centre, *mode == 3 && (b[2] + depth).abs() < 1e-9) else { continue };
            let radius = (a[0] - centre[0]).hypot(a[1] - centre[1]);
            if (centre[0] - cx).abs() < 1e-4 && (centre[1] - cy).abs() < 1e-4 {
                at_floor.push(radius);
            } else {
                // A lead: inside the wall's circle, tangent to it from within
                // (its centre its radius in from the wall's path), one end on it.
                let from_axis = (centre[0] - cx).hypot(centre[1] - cy);
                assert!(allowance > 0.0 && (from_axis + radius - (wall - r)).abs() < 1e-4, "{tool}: {a:?} -> {b:?}");
                let on_wall = |p: &[f64; 3]| ((p[0] - cx).hypot(p[1] - cy) - (wall - r)).abs() < 1e-4;
                assert!(on_wall(a) != on_wall(b), "{tool}: a lead from {a:?} to {b:?}");
            }
        }
        assert!(at_floor.iter().all(|radius| radius + r <= wall + 1e-9), "{at_floor:?} cut past the wall");
        assert!(at_floor.iter().any(|radius| (radius + r - wall).abs() < 1e-9), "{at_floor:?}: no pass at the wall");
        if allowance > 0.0 {
            // The rings stop the allowance short of the wall, the finishing pass does not.
            let rough: Vec<&f64> = at_floor.iter().filter(|radius| (*radius + r - wall).abs() > 1e-9).collect();
            assert!(rough.iter().any(|radius| (*radius + r + allowance - wall).abs() < 1e-9), "{at_floor:?}");
        }
        for step in 0..=300 {
            let rho = wall * f64::from(step) / 300.0;
            let near = |radius: &f64| (rho - radius).abs() <= r || rho <= r - radius;
            assert!(at_floor.iter().any(near), "radius {rho} is not cut ({at_floor:?})");
        }
        // The simulated part: the circle's box, to the cell, at DEPTH, with no warning.
        let (status, report) = denied_check(&program, &format!("units = \"mm\"\n{tools}"));
        assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])), "{tool}");
        let cut = &report["summary"]["cut_box"];
        let cell = 0.1;
        for (axis, centre) in [(0, cx), (1, cy)] {
            let (lo, hi) = (cut["min"][axis].as_f64().unwrap(), cut["max"][axis].as_f64().unwrap());
            assert!((lo - (centre - wall)).abs() < cell && (hi - (centre + wall)).abs() < cell, "{tool}: {cut}");
        }
        assert!((cut["min"][2].as_f64().unwrap() + depth).abs() < cell, "{tool}: {cut}");
    }
    // A pocket hardly wider than the tool leaves no room for a helix: an error at the call.
    let (_, diagnostics) = run(
        "wizards",
        &mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n"),
        "G21 G90\nM06 T1\nG00 X0 Y0 Z0\nF100\nCirclePocket 6.2 2\nM30\n",
    );
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert!(
        diagnostics[0].starts_with("5:1: error") && diagnostics[0].contains("no room to helix down"),
        "{diagnostics:?}"
    );
    for (call, words) in [
        ("CirclePocket 30 8 4 3 4", "more than a ring's stepover"),
        ("CirclePocket 7 2 1 3 0.5", "leaves the rings no room"),
    ] {
        let (_, diagnostics) = run(
            "wizards",
            &mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n"),
            &format!("G21 G90\nM06 T1\nG00 X0 Y0 Z0\nF100\n{call}\nM30\n"),
        );
        assert!(diagnostics.len() == 1 && diagnostics[0].contains(words), "{call}: {diagnostics:?}");
    }
}

#[test]
fn drill_grid_drills_every_hole_in_pecks_and_never_rapids_into_the_material() {
    let tools = "[[tools]]\nnumber = 1\nkind = \"drill\"\ndiameter = 3\nflute_length = 20\n";
    // 3 columns 10 apart towards +X, 2 rows 8 apart towards -Y, 5 deep in pecks of at most 2.
    let program = "G21 G90\nM06 T1\nM03 S3000\nG00 X20 Y30 Z1\nF120\nDrillGrid 3 2 10 -8 6 2\nG00 Z5\nM05\nM30\n";
    let calls = [
        ("DrillGrid 3 2 10 -8 6 2", 3, 2.0),
        ("DrillGrid 3 2 10 -8 6 2 0.3", 3, 2.0),
        ("DrillGrid 3 2 10 -8 6", 1, 5.0),
    ];
    for (call, pecks, most) in calls {
        let program = program.replace("DrillGrid 3 2 10 -8 6 2", call);
        let (lines, diagnostics) = run("wizards", &mm(tools), &program);
        assert!(diagnostics.is_empty(), "{diagnostics:?}");
        let moves = moves(&lines);
        // Each hole's bottom, in the order drilled: rows back and forth from the first hole.
        let bottoms: Vec<[f64; 2]> =
            moves.iter().filter(|m| m.0 == 1 && (m.2[2] + 5.0).abs() < 1e-9).map(|m| [m.2[0], m.2[1]]).collect();
        assert_eq!(
            bottoms,
            [[20.0, 30.0], [30.0, 30.0], [40.0, 30.0], [40.0, 22.0], [30.0, 22.0], [20.0, 22.0]],
            "{call}"
        );
        // Straight down, every hole in `pecks` feeds.
        let feeds: Vec<_> = moves.iter().filter(|m| m.0 == 1).collect();
        assert_eq!(feeds.len(), 6 * pecks, "{call}: {feeds:?}");
        assert!(feeds.iter().all(|m| m.1[0] == m.2[0] && m.1[1] == m.2[1]), "{call}");
        // A rapid goes down only into a hole already cut deeper; a feed takes at most a peck of new material.
        let mut deepest = std::collections::HashMap::new();
        for (mode, a, b) in &moves {
            let key = ((b[0] * 1000.0).round() as i64, (b[1] * 1000.0).round() as i64);
            let reached = deepest.entry(key).or_insert(0.0f64);
            if *mode == 0 && b[2] < a[2] {
                assert!(b[2] > *reached, "{call}: a rapid to Z{} into material at {key:?} (cut to Z{reached})", b[2]);
            }
            if *mode == 1 {
                assert!(*reached - b[2] <= most + 1e-9, "{call}: a feed to Z{} from Z{reached}", b[2]);
            }
            *reached = reached.min(b[2]);
        }
        let (status, report) = denied_check(&program, &format!("units = \"mm\"\n{tools}"));
        assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])), "{call}");
        let cut = &report["summary"]["cut_box"];
        let near = |value: &serde_json::Value, expected: f64| (value.as_f64().unwrap() - expected).abs() < 0.1;
        assert!(near(&cut["min"][0], 18.5) && near(&cut["max"][0], 41.5), "{call}: {cut}");
        assert!(near(&cut["min"][1], 20.5) && near(&cut["max"][1], 31.5), "{call}: {cut}");
    }
    // BREAK without PECK, and a break as long as the peck, are errors at the call.
    for (call, words) in [("Drill 5 0 0.2", "must be"), ("Drill 5 1 1", "less than the peck")] {
        let (_, diagnostics) =
            run("wizards", &mm(tools), &format!("G21 G90\nM06 T1\nG00 X0 Y0 Z1\nF100\n{call}\nM30\n"));
        assert!(diagnostics.len() == 1 && diagnostics[0].contains(words), "{call}: {diagnostics:?}");
    }
}

/// The part `program` cuts in the machine of `config`, simulated at `cell`.
fn simulated(program: &str, config: &str, cell: f64) -> ger_sim::field::HeightField {
    let config = Config::from_toml(config).unwrap();
    let wizards = WasmWizards::new(&repo("wizards"), &config, Limits::default(), None);
    let source = ger_engine::Source::text("part.ngc", ".", program);
    let mut part = ger_engine::Program::new(source, config).with_wizards(Box::new(wizards));
    let (stock, report) = part.stock(&mut ger_engine::Silent);
    assert_eq!(report.errors(), 0);
    let resolution = ger_engine::Resolution { cell: Some(cell), ..Default::default() };
    let simulation = part.simulation(stock, resolution).unwrap();
    let (field, report) = part.simulate(simulation, &mut ger_engine::Silent);
    assert_eq!(report.errors(), 0);
    field
}

/// The height of the cell of `field` at `x`, `y`.
fn height_at(field: &ger_sim::field::HeightField, x: f64, y: f64) -> f64 {
    let (i, j) = ((x - field.stock.min[0]) / field.cell, (y - field.stock.min[1]) / field.cell_y());
    let (i, j) = (i.floor() as usize, j.floor() as usize);
    let centre = field.centre(i, j);
    assert!((centre[0] - x).abs() <= field.cell && (centre[1] - y).abs() <= field.cell_y(), "{centre:?} for {x}, {y}");
    field.get(i, j)
}

#[test]
fn profile_cuts_a_groove_round_the_outside_or_the_inside_and_nothing_else() {
    let config = "units = \"mm\"\n[stock]\nsize = [120, 100, 10]\norigin = [0, 0, 10]\n\
                  [[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n";
    let program =
        |call: &str| format!("G21 G90\nM06 T1\nM03 S12000\nG00 X20 Y20 Z5\nG00 Z0\nF600\n{call}\nG00 Z5\nM05\nM30\n");
    // A 60 x 40 rectangle from X20 Y20, 6 deep, with a 6 mm endmill: (point, cut or not).
    let outside: &[([f64; 2], bool)] = &[
        ([50.0, 40.0], false), // the part
        ([20.5, 40.0], false), // just inside its left edge
        ([17.0, 40.0], true),  // the groove's middle
        ([13.5, 40.0], false), // past the groove
        ([18.0, 18.0], true),  // round the sharp corner: 2.8 from it
        ([15.5, 15.5], false), // 6.4 from it
        ([83.0, 50.0], true),  // the right edge's groove
        ([50.0, 63.0], true),  // the top's
    ];
    // Inside, with corners of radius 10: a ring 6 wide inside the wall; the middle stays.
    let c = 30.0 - 9.0 * std::f64::consts::FRAC_1_SQRT_2;
    let inside: &[([f64; 2], bool)] = &[
        ([50.0, 40.0], false), // the island
        ([23.0, 40.0], true),  // the ring
        ([19.5, 40.0], false), // outside the hole
        ([21.0, 21.0], false), // the rounded corner keeps this
        ([c, c], true),        // 9 from the corner's centre: in the hole's corner
        ([77.0, 30.0], true),
    ];
    for (call, points) in [("Profile 60 40 6", outside), ("Profile 60 40 6 \"inside\" 10", inside)] {
        let (status, report) = denied_check(&program(call), config);
        assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])), "{call}");
        let field = simulated(&program(call), config, 0.2);
        for (point, cut) in points {
            let height = height_at(&field, point[0], point[1]);
            let expected = if *cut { -6.0 } else { 0.0 };
            assert!((height - expected).abs() < 1e-6, "{call}: Z{height} at {point:?}");
        }
    }
    // A circle: CORNER half the sides, entered by a helix.
    let (status, report) = denied_check(&program("Profile 40 40 6 \"inside\" 20"), config);
    assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])));
    let field = simulated(&program("Profile 40 40 6 \"inside\" 20"), config, 0.2);
    for (point, cut) in [([40.0, 40.0], false), ([40.0, 23.0], true), ([57.0, 40.0], true), ([22.0, 22.0], false)] {
        let height = height_at(&field, point[0], point[1]);
        assert!((height - if cut { -6.0 } else { 0.0 }).abs() < 1e-6, "circle: Z{height} at {point:?}");
    }
    // Two tabs, in two levels of 3: the path round the 60 x 40 rectangle
    // (corner radius 3, the tool's) is 200 + 6π long and starts in the middle
    // of its bottom side, at (50, 17), clockwise. The tabs' centres are a
    // quarter and three quarters of it along: 30 to the corner, 3π/2 round
    // it and 20 up the left side, at (17, 40), and so at (83, 40) on the
    // right. Their bridges, 12 wide (twice the tool) and 1.5 high (a quarter
    // of 6), stay at Z-4.5; beyond a bridge's end and its 45° ramp the groove
    // is at Z-6.
    let call = "Profile 60 40 6 \"outside\" 0 3 2";
    let (status, report) = denied_check(&program(call), config);
    assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])), "{call}");
    let field = simulated(&program(call), config, 0.2);
    let tabbed = [
        ([17.0, 40.0], -4.5),
        ([17.0, 36.0], -4.5),
        ([17.0, 44.0], -4.5),
        ([17.0, 52.0], -6.0),
        ([17.0, 28.0], -6.0),
        ([83.0, 40.0], -4.5),
        ([83.0, 28.0], -6.0),
        ([50.0, 17.0], -6.0),
        ([50.0, 40.0], 0.0),
    ];
    for (point, expected) in tabbed {
        let height = height_at(&field, point[0], point[1]);
        assert!((height - expected).abs() < 1e-6, "{call}: Z{height} at {point:?}, not {expected}");
    }
    // The same with 0.5 left by the levels for a finishing pass: the edge
    // is where it was, the tabs too, and the pass is joined to the groove
    // by two arcs of the tool's radius tangent to the edge's path at
    // (50, 17) (their centre 3 below it), from and back to the groove's
    // path 0.5 further out: one lap at full depth, as the flutes are not
    // known to be shorter.
    let call = "Profile 60 40 6 \"outside\" 0 3 2 12 1.5 0.5";
    let (status, report) = denied_check(&program(call), config);
    assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])), "{call}");
    let field = simulated(&program(call), config, 0.2);
    let edges = [([20.3, 40.0], 0.0), ([19.7, 30.0], -6.0), ([50.0, 20.3], 0.0), ([50.0, 19.7], -6.0)];
    for (point, expected) in tabbed.into_iter().chain(edges) {
        let height = height_at(&field, point[0], point[1]);
        assert!((height - expected).abs() < 1e-6, "{call}: Z{height} at {point:?}, not {expected}");
    }
    let (lines, _) = run("wizards", &Config::from_toml(config).unwrap(), &program(call));
    let leads: Vec<([f64; 3], [f64; 3])> = moves(&lines)
        .into_iter()
        .zip(arc_centres(&lines))
        .filter(|(_, centre)| centre.is_some_and(|c| (c[0] - 50.0).abs() < 1e-4 && (c[1] - 14.0).abs() < 1e-4))
        .map(|((mode, a, b), _)| {
            assert_eq!(mode, 3, "{call}: a lead on the left of a clockwise path turns counter-clockwise");
            (a, b)
        })
        .collect();
    assert_eq!(leads.len(), 2, "{call}: {leads:?}");
    // Afterwards the tool is back where the call was (the program's own Z5 follows).
    assert_eq!(moves(&lines).last().map(|m| m.1), Some([20.0, 20.0, 0.0]), "{call}");
    let ((a, b), (c, d)) = (leads[0], leads[1]);
    let on = |p: [f64; 3], y: f64| (p[1] - y).abs() < 1e-4 && (p[2] + 6.0).abs() < 1e-9;
    assert!(on(a, 16.5) && on(b, 17.0) && a[0] > 50.0 && (b[0] - 50.0).abs() < 1e-4, "{call}: lead-in {a:?} -> {b:?}");
    assert!(on(c, 17.0) && on(d, 16.5) && d[0] < 50.0, "{call}: lead-out {c:?} -> {d:?}");
    // Inside, with flutes 4 long: the pass is cut in two levels of 3, each led in and out.
    let short = config.replace("diameter = 6\n", "diameter = 6\nflute_length = 4\n");
    let call = "Profile 60 40 6 \"inside\" 10 3 0 12 1.5 0.5";
    let (lines, diagnostics) = run("wizards", &Config::from_toml(&short).unwrap(), &program(call));
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    // Inside, counter-clockwise from the bottom's middle (50, 23): the leads' centre is 3 above it.
    let leads = arc_centres(&lines)
        .iter()
        .filter(|c| c.is_some_and(|c| (c[0] - 50.0).abs() < 1e-4 && (c[1] - 26.0).abs() < 1e-4))
        .count();
    assert_eq!(leads, 4, "{call}");
    let field = simulated(&program(call), &short, 0.2);
    for (point, expected) in [([23.0, 40.0], -6.0), ([20.3, 40.0], -6.0), ([19.7, 40.0], 0.0), ([50.0, 40.0], 0.0)] {
        let height = height_at(&field, point[0], point[1]);
        assert!((height - expected).abs() < 1e-6, "{call}: Z{height} at {point:?}, not {expected}");
    }
    // What cannot be cut is an error at the call.
    let (_, diagnostics) = run(
        "wizards",
        &mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n"),
        &program("Profile 5 40 2 \"inside\""),
    );
    assert!(diagnostics.len() == 1 && diagnostics[0].contains("does not fit inside"), "{diagnostics:?}");
    let (_, diagnostics) = run(
        "wizards",
        &mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n"),
        &program("Profile 60 40 6 \"round\""),
    );
    assert!(diagnostics.len() == 1 && diagnostics[0].contains("\"outside\" or \"inside\""), "{diagnostics:?}");
    let (_, diagnostics) = run(
        "wizards",
        &mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n"),
        &program("Profile 20 20 6 \"outside\" 0 3 6"),
    );
    assert!(diagnostics.len() == 1 && diagnostics[0].contains("do not fit"), "{diagnostics:?}");
    for (call, words) in [
        ("Profile 60 40 6 \"outside\" 0 3 0 12 1.5 3.5", "at most the tool's radius"),
        ("Profile 7 40 6 \"inside\" 0 3 0 12 1.5 0.6", "with 0.6 allowance a side does not fit"),
    ] {
        let (_, diagnostics) =
            run("wizards", &mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n"), &program(call));
        assert!(diagnostics.len() == 1 && diagnostics[0].contains(words), "{call}: {diagnostics:?}");
    }
}

#[test]
fn face_leaves_the_whole_rectangle_flat_at_its_depth() {
    // A 60 x 40 stock faced 1.5 deep in levels of 0.5 with a 12 mm endmill.
    let config = "units = \"mm\"\n[stock]\nsize = [60, 40, 10]\norigin = [0, 0, 10]\n\
                  [[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 12\n";
    let program = "G21 G90\nM06 T1\nM03 S12000\nG00 X0 Y0 Z5\nG00 Z0\nF600\nFace 60 40 1.5 0.5\nG00 Z5\nM05\nM30\n";
    let (status, report) = denied_check(program, config);
    assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])));
    // The simulated part, cell by cell: everything at Z-1.5.
    let field = simulated(program, config, 0.25);
    let mut heights = Vec::new();
    for i in 0..field.nx {
        for j in 0..field.ny {
            heights.push(field.get(i, j));
        }
    }
    let (low, high) = heights.iter().fold((f64::MAX, f64::MIN), |(lo, hi), h| (lo.min(*h), hi.max(*h)));
    assert!((low + 1.5).abs() < 1e-6 && (high + 1.5).abs() < 1e-6, "heights from {low} to {high}");
}

#[test]
fn thread_mill_climbs_one_pitch_a_turn_to_the_major_diameter() {
    // An M12 x 1.75 tapped hole 10 deep, bored first to 10.2 (its minor diameter is 10.106),
    // threaded in 2 passes with an 8 mm cutter.
    let config = "units = \"mm\"\n[stock]\nsize = [60, 60, 20]\norigin = [0, 0, 20]\n\
                  [[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n\
                  [[tools]]\nnumber = 2\nkind = \"endmill\"\ndiameter = 8\nflute_length = 20\n";
    let program = "G21 G90\nM06 T1\nM03 S12000\nG00 X30 Y30 Z5\nG00 Z0\nF300\nCirclePocket 10.2 12 3\n\
                   M06 T2\nG00 X30 Y30 Z0\nF200\nThreadMill 12 1.75 10 \"inside\" 2\nG00 Z5\nM05\nM30\n";
    let (lines, diagnostics) = run("wizards", &Config::from_toml(config).unwrap(), program);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let threading: Vec<&String> = lines.iter().skip_while(|l| !l.contains("T2")).collect();
    let word = |line: &str, letter: char| {
        line.split_whitespace().find(|w| w.starts_with(letter)).and_then(|w| w[1..].parse::<f64>().ok())
    };
    // The helices: counter-clockwise full turns with Z, each a pitch above the one before.
    let helices: Vec<(f64, f64)> = threading
        .iter()
        .filter(|l| l.starts_with("G03") && word(l, 'Z').is_some())
        .map(|l| (word(l, 'I').unwrap().abs(), word(l, 'Z').unwrap()))
        .collect();
    assert_eq!(helices.len(), 2 * 6, "{helices:?}");
    for pass in helices.chunks(6) {
        let mut below = -10.0;
        for (_, z) in pass {
            assert!((z - below - 1.75).abs() < 1e-3, "{pass:?}");
            below = *z;
        }
        assert!(pass[5].1 >= 0.0, "the thread stops short of the top: {pass:?}");
    }
    // The last pass's radius puts the cutter's edge on the major diameter: 6 - 4 = 2;
    // the first is a half of the thread depth (5/8 of 0.866 x 1.75 = 0.947) short of it.
    let (first, last) = (helices[0].0, helices[6].0);
    assert!((last - 2.0).abs() < 1e-3 && (first - (2.0 - 0.947 / 2.0)).abs() < 1e-3, "{first} {last}");
    let (status, report) = denied_check(program, config);
    assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])));
    let cut = &report["summary"]["cut_box"];
    let near = |value: &serde_json::Value, expected: f64| (value.as_f64().unwrap() - expected).abs() < 0.1;
    assert!(near(&cut["min"][0], 24.0) && near(&cut["max"][0], 36.0), "the major diameter: {cut}");
    // Outside, an M20 x 2 bolt: clockwise turns, the edge on the minor diameter,
    // 17/24 of 0.866 x 2 = 1.227 in from the major: 10 - 1.227 + 4 = 12.773.
    let (lines, diagnostics) = run(
        "wizards",
        &Config::from_toml(config).unwrap(),
        "G21 G90\nM06 T2\nG00 X0 Y0 Z0\nF100\nThreadMill 20 2 8 \"outside\"\nM30\n",
    );
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let helices: Vec<(f64, f64)> = lines
        .iter()
        .filter(|l| l.starts_with("G02") && word(l, 'Z').is_some())
        .map(|l| (word(l, 'I').unwrap().abs(), word(l, 'Z').unwrap()))
        .collect();
    let zs: Vec<f64> = helices.iter().map(|h| h.1).collect();
    assert_eq!(zs, [-6.0, -4.0, -2.0, 0.0], "{helices:?}");
    assert!(helices.iter().all(|h| (h.0 - 12.773).abs() < 1e-3), "{helices:?}");
    // A cutter that cannot fit the bore is an error at the call.
    let (_, diagnostics) = run(
        "wizards",
        &Config::from_toml(config).unwrap(),
        "G21 G90\nM06 T2\nG00 X0 Y0 Z0\nF100\nThreadMill 6 1 5\nM30\n",
    );
    assert!(diagnostics.len() == 1 && diagnostics[0].contains("too big for an M6 x 1 thread"), "{diagnostics:?}");
}

#[test]
fn engrave_cuts_its_strokes_inside_the_text_box_at_its_depth() {
    let tools = "[[tools]]\nnumber = 1\nkind = \"ballmill\"\ndiameter = 1\n";
    let program = |call: &str| format!("G21 G90\nM06 T1\nM03 S18000\nG00 X20 Y10 Z0\nF400\n{call}\nG00 Z5\nM05\nM30\n");
    let feeds = |call: &str| {
        let (lines, diagnostics) = run("wizards", &mm(tools), &program(call));
        assert!(diagnostics.is_empty(), "{call}: {diagnostics:?}");
        moves(&lines[lines.iter().position(|l| l.contains("Engrave")).unwrap_or(0)..])
            .into_iter()
            .filter(|m| m.0 == 1)
            .collect::<Vec<_>>()
    };
    // An L 10 high: down its stem and along its foot, 4/6 of the height wide.
    let l: Vec<[f64; 3]> = feeds("Engrave \"L\" 10 0.3").iter().map(|m| m.2).collect();
    let expected = [[20.0, 20.0, -0.3], [20.0, 10.0, -0.3], [20.0 + 40.0 / 6.0, 10.0, -0.3]];
    assert_eq!(l.len(), 3, "{l:?}");
    for (got, want) in l.iter().zip(expected) {
        assert!((0..3).all(|k| (got[k] - want[k]).abs() < 1e-3), "{l:?}");
    }
    // Six characters advance 10 each (4/6 of 10 wide, a third of 10 apart): 56.667 wide.
    let width = 60.0 - 10.0 / 3.0;
    for (call, left) in
        [("Engrave \"GER 42\" 10 0.3", 20.0), ("Engrave \"GER 42\" 10 0.3 \"centre\"", 20.0 - width / 2.0)]
    {
        let cuts = feeds(call);
        assert!(cuts.len() > 20, "{call}");
        for (_, _, b) in &cuts {
            let eps = 1e-3; // the output's rounding
            assert!((b[2] + 0.3).abs() < eps, "{call}: a feed to {b:?}, not at the depth");
            assert!(
                b[0] >= left - eps && b[0] <= left + width + eps && b[1] >= 10.0 - eps && b[1] <= 20.0 + eps,
                "{call}: {b:?}"
            );
        }
        let xs: Vec<f64> = cuts.iter().map(|m| m.2[0]).collect();
        let (lo, hi) = xs.iter().fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(*x), hi.max(*x)));
        assert!((lo - left).abs() < 1e-3 && (hi - (left + width)).abs() < 1e-3, "{call}: {lo} to {hi}");
    }
    let (status, report) = denied_check(&program("Engrave \"GER 42\" 10 0.3"), &format!("units = \"mm\"\n{tools}"));
    assert_eq!((status, &report["diagnostics"]), (Some(0), &serde_json::json!([])));
    let cut = &report["summary"]["cut_box"];
    assert!((cut["min"][2].as_f64().unwrap() + 0.3).abs() < 0.05, "{cut}");
    // Every glyph of the font cuts; one it lacks is an error at the call that names it.
    assert!(feeds("Engrave \"ABCDEFGHIJKLMNOPQRSTUVWXYZ 0123456789 -+.,:/# abc\" 5").len() > 100);
    let (_, diagnostics) = run("wizards", &mm(tools), &program("Engrave \"Café\" 5"));
    assert!(diagnostics.len() == 1 && diagnostics[0].contains("the font has no `\\u{e9}`"), "{diagnostics:?}");
}

#[test]
fn every_wizards_example_passes_the_check_with_warnings_denied_and_is_pictured() {
    // The README's example, then one for each wizard that ships (the
    // README shows each, rendered by host/docs/wizards/render.sh).
    let mut programs = vec![repo("host/examples/pocket.ngc")];
    let readme = std::fs::read_to_string(repo("README.md")).unwrap();
    let mut shipped: Vec<String> = std::fs::read_dir(repo("wizards"))
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.is_dir() && !path.ends_with("target"))
        .map(|path| path.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    shipped.sort();
    for name in &shipped {
        // Each in millimetres on a metric machine, and written again in
        // inches for an inch machine (`inch/`, with its own tools).
        for folder in ["host/examples/wizards", "host/examples/wizards/inch"] {
            let program = repo(&format!("{folder}/{name}.ngc"));
            assert!(program.exists(), "the wizard {name} has no example in {folder}");
            programs.push(program);
        }
        let picture = format!("host/docs/wizards/{name}.png");
        assert!(repo(&picture).exists() && readme.contains(&picture), "{picture} is missing or not in the README");
    }
    for program in programs {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
            .args(["check", "--deny", "warnings", "--quiet", "--wizards"])
            .arg(repo("wizards"))
            .arg(&program)
            .env("NO_COLOR", "1")
            .output()
            .unwrap();
        let (out, err) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
        assert!(output.status.success(), "{}: {out}{err}", program.display());
        assert!(!err.contains("warning") && !out.contains("warning"), "{}: {out}{err}", program.display());
    }
}

#[test]
fn pocket_refuses_a_tool_wider_than_the_pocket_and_keeps_incremental_mode() {
    let config = mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 12.0\n");
    let (_, diagnostics) = run("wizards", &config, "G21\nF100\nPocket 20 10 3\nM30\n");
    assert_eq!(diagnostics.len(), 1);
    assert!(
        diagnostics[0]
            .starts_with("3:1: error: wizard `Pocket`: the tool (T1, diameter 12) is wider than the pocket (20 x 10)"),
        "{diagnostics:?}"
    );
    assert!(diagnostics[0].contains("usage: Pocket LENGTH WIDTH DEPTH [STEPDOWN]"), "{diagnostics:?}");

    let config = mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 2.0\n");
    let (lines, diagnostics) = run("wizards", &config, "G21 G91\nF100\nPocket 4 4 1\nX5\nM30\n");
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    // Pocket leaves the tool where it found it (X0), in G91: X5 is 5 from
    // there, in the G00 that Pocket's last move left modal.
    assert_eq!(lines[lines.len() - 2], "G00 X5.0000");
}

#[test]
fn a_wizard_sees_the_machine_state_at_its_call() {
    let tools = "[[tools]]\nnumber = 2\nkind = \"drill\"\ndiameter = 0.25\nflute_length = 1.0\ntip_angle = 118.0\n";
    let config = Config::from_toml(&format!("units = \"inch\"\n{tools}")).unwrap();
    let program = "G21\nG52 X25.4\nM06 T2\nG00 X10 Y5 Z2\nM03 S1200\nG18 G91\nF250\nEcho\nM30\n";
    let (_, diagnostics) = run("tests/wizards/guests", &config, program);
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    let seen = &diagnostics[0];
    assert!(seen.starts_with("8:1: error: wizard `Echo`: State { units: Mm, position: ["), "{seen}");
    for part in [
        "distance: Incremental",
        "plane: ZX",
        "feed: Some(250.0",
        "spindle: Clockwise(Some(1200.0))",
        "tool: Some(Tool { number: 2, kind: Drill, diameter: 6.35",
        "flute_length: Some(25.4",
        "tip_angle: Some(118.0)",
        "tool_number: 2",
        "line: 8",
        "find_tool(2) = Some(Tool { number: 2, kind: Drill, diameter: 6.35",
        "find_tool(9) = None",
    ] {
        assert!(seen.contains(part), "{part} not in {seen}");
    }
    let position = &seen[seen.find("position: [").unwrap() + 11..];
    let position: Vec<f64> = position[..position.find(']').unwrap()].split(", ").map(|v| v.parse().unwrap()).collect();
    for (got, expected) in position.iter().zip([10.0, 5.0, 2.0]) {
        assert!((got - expected).abs() < 1e-9, "{position:?}");
    }
}

#[test]
fn hostile_wizards_get_clear_diagnostics_and_ger_keeps_working() {
    let program = "G21 G90 G01 F100\nSpin\nHog\nSnoop\nCrash\nChatter\nGarbage\nRecurse\nNest 1\nM30\n";
    // The first run builds the guests from source (a minute on a fresh
    // machine); what is timed below is the calls alone.
    run("tests/wizards/guests", &mm(""), program);
    let started = std::time::Instant::now();
    let (lines, diagnostics) = run("tests/wizards/guests", &mm(""), program);
    let expected = [
        ("2:1: error: wizard `Spin` did not finish within 1 s and was stopped", ""),
        ("3:1: error: wizard `Hog` needed more than 64 MiB of memory and was stopped", "memory allocation"),
        ("4:1: error: wizard `Snoop` panicked", "open /etc/passwd"),
        ("5:1: error: wizard `Crash` panicked", "boom: the wizard gave up"),
        ("6:1: error: wizard `Chatter` wrote more than 64 KiB of output and was stopped", "its stdout (last 12 of"),
        ("7:1: error: wizard `Garbage` returned a bad statement (#2): `%` is not a G-code letter (A-Z)", ""),
        ("8:1: error: wizard calls nest deeper than 16: `Recurse` recurses without end", ""),
    ];
    assert_eq!(diagnostics.len(), expected.len(), "{diagnostics:#?}");
    for (diagnostic, (start, detail)) in diagnostics.iter().zip(expected) {
        assert!(diagnostic.starts_with(start), "{diagnostic}\nshould start with {start}");
        assert!(diagnostic.contains(detail), "{diagnostic}\nshould contain {detail}");
    }
    // The file was not read: the sandbox has no directories.
    assert!(diagnostics[2].contains("No such file or directory") && !diagnostics[2].contains("root:"));
    // Crash's stdout is shown too.
    assert!(diagnostics[3].contains("its stdout:\n  about to give up"), "{}", diagnostics[3]);
    // After all that, a good wizard still runs, and the program goes on.
    assert!(lines.ends_with(&["G01 X1.0000".into(), "G01 X0.0000".into(), "M30".into()]), "{lines:?}");
    // Spin's 1 s is the only long wait: nothing hung (a generous bound, for a loaded machine).
    assert!(started.elapsed().as_secs() < 60, "{:?}", started.elapsed());
}

#[test]
fn limits_are_the_runtimes_to_set() {
    let limits = Limits { time: std::time::Duration::from_millis(200), memory: 8 << 20, ..Limits::default() };
    let config = mm("");
    // Build the two guests first (slow on a fresh machine): only the calls are timed.
    run("tests/wizards/guests", &config, "Spin\nHog\n");
    let mut wizards = WasmWizards::new(&repo("tests/wizards/guests"), &config, limits, Some(Box::new(|_: &str| {})));
    let options = Options { config: &config, stage: LAST_STAGE, wizards: &mut wizards };
    let started = std::time::Instant::now();
    let diagnostics: Vec<String> = translate("Spin\nHog\n".as_bytes(), Library::empty(), options)
        .filter_map(|e| match e {
            Event::Diagnostic(d) => Some(d.message),
            Event::Statement(_) => None,
        })
        .collect();
    assert_eq!(
        diagnostics,
        [
            "wizard `Spin` did not finish within 0.2 s and was stopped",
            "wizard `Hog` needed more than 8 MiB of memory and was stopped"
        ]
    );
    assert!(started.elapsed().as_millis() < 5_000, "{:?}", started.elapsed());
}

#[test]
fn a_missing_wizard_lists_the_ones_there_are() {
    let (_, diagnostics) = run("tests/wizards/guests", &mm(""), "Pocket 1 2 3\n");
    assert!(diagnostics[0].starts_with("1:1: error: no wizard named `Pocket` in "), "{diagnostics:?}");
    assert!(diagnostics[0].contains("chatter, crash, echo"), "{diagnostics:?}");
}

fn ger(args: &[&str], stdin: &str, target_dir: &Path) -> (String, String, i32) {
    use std::io::Write;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(args)
        .env("NO_COLOR", "1")
        // Share compiled dependencies with the test wizards' builds.
        .env("CARGO_TARGET_DIR", target_dir)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(stdin.as_bytes()).unwrap();
    let output = child.wait_with_output().unwrap();
    let text = |b: Vec<u8>| String::from_utf8(b).unwrap();
    (text(output.stdout), text(output.stderr), output.status.code().unwrap_or(-1))
}

#[test]
fn a_wizard_may_not_be_named_like_a_macro_keyword() {
    // `While 3` and `Sin 30` read as macro B and an expression, never as calls.
    let dir = tempfile::tempdir().unwrap();
    let wizards = dir.path().to_str().unwrap();
    let target = repo("tests/wizards/guests/target/cargo");
    for name in ["While", "Goto", "Sin", "Round"] {
        let (_, err, status) = ger(&["wizard", "new", name, "--wizards", wizards], "", &target);
        assert_eq!(status, 1, "{name}");
        assert!(err.contains(&format!("`{name}` cannot be a wizard's name")), "{err}");
        assert!(!dir.path().join(name.to_ascii_lowercase()).exists());
    }
    // One made by hand is neither built nor listed as callable.
    std::fs::create_dir(dir.path().join("round")).unwrap();
    std::fs::write(dir.path().join("round/app.py"), "").unwrap();
    let (_, err, status) = ger(&["wizard", "build", "round", "--wizards", wizards], "", &target);
    assert_eq!((status, err.contains("`round` cannot be a wizard's name")), (1, true), "{err}");
    let (out, _, status) = ger(&["wizard", "list", "--no-build", "--wizards", wizards], "", &target);
    assert_eq!(status, 1);
    assert!(out.contains("named like a macro keyword: no program can call it"), "{out}");
}

#[test]
fn a_new_wizard_builds_and_runs_unchanged_and_is_listed() {
    let dir = tempfile::tempdir().unwrap();
    let wizards = dir.path().to_str().unwrap();
    let target = repo("tests/wizards/guests/target/cargo");
    let (out, err, status) = ger(&["wizard", "new", "Square", "--wizards", wizards], "", &target);
    assert_eq!(status, 0, "{out}{err}");
    assert!(out.contains("created") && dir.path().join("square/src/lib.rs").is_file(), "{out}");
    let (_, err, status) = ger(&["wizard", "new", "Sq1", "--wizards", wizards], "", &target);
    assert_eq!(status, 1);
    assert!(err.contains("`Sq1` cannot be a wizard's name"), "{err}");

    // `ger run` builds it (its .wasm is missing) and runs it.
    let program = "G21 G90\nG00 X0 Y0 Z0\nF100\nSquare 10 1\nM30\n";
    let (out, err, status) =
        ger(&["run", "--units", "mm", "--no-line-numbers", "--wizards", wizards, "-"], program, &target);
    assert_eq!(status, 0, "{err}");
    let body: Vec<&str> = out.lines().skip_while(|l| !l.starts_with("G00 X0")).skip(1).collect();
    assert_eq!(
        body,
        ["G01 Z-1.000 F100.000", "G01 X10.000", "G01 Y10.000", "G01 X0.000", "G01 Y0.000", "G00 Z0.000", "M30"]
    );

    let (out, err, status) = ger(&["wizard", "list", "--wizards", wizards], "", &target);
    assert_eq!(status, 0, "{err}");
    assert!(out.starts_with("Square SIDE DEPTH"), "{out}");
    assert!(out.contains("(square, Rust)") && out.contains("SIDE         side of the square"), "{out}");

    // --no-build: a missing .wasm is an error that says how to build it.
    std::fs::remove_file(dir.path().join("square.wasm")).unwrap();
    let (_, err, status) = ger(&["check", "--no-build", "--wizards", wizards, "-"], program, &target);
    assert_eq!(status, 1);
    assert!(err.contains("wizard `Square` is not built") && err.contains("ger wizard build"), "{err}");
}

#[test]
fn the_examples_in_other_languages_build_from_the_default_folder() {
    // As the README has a new user do it: in the repository, with `--wizards`
    // left at its default, a relative path (jco once resolved it twice).
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["wizard", "build", "circle", "slot"])
        .current_dir(repo("."))
        .env("NO_COLOR", "1")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{err}");
    for built in ["built wizards/circle.wasm", "built wizards/slot.wasm"] {
        assert!(err.contains(built), "{err}");
    }
    // Circle, on the JavaScript SDK: a helix round the groove (radius 5: a
    // turn is 10π, at 3° it may drop 1.647, so 1 deep is one turn), then a
    // level turn; never straight down.
    let endmill = mm("[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 4\n");
    let (lines, diagnostics) = run("wizards", &endmill, "G21 G90\nM06 T1\nG00 X0 Y0 Z0\nF100\nCircle 5 1\nM30\n");
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let arcs: Vec<&String> = lines.iter().filter(|l| l.starts_with("G03")).collect();
    assert_eq!(arcs.len(), 2, "{lines:?}");
    assert!(arcs[0].contains("X5.0000 Y0.0000 Z-1.0000 I-5.0000 J0.0000"), "{lines:?}");
    assert!(!lines.iter().any(|l| l.starts_with("G01") && l.contains('Z')), "{lines:?}");
    // The SDK's argument checks, in JavaScript: the count, and the parameter by name.
    for (call, words) in [
        ("Circle 5", "Circle takes 2 arguments, not 1 (usage: Circle RADIUS DEPTH)"),
        ("Circle 5 \"deep\"", "DEPTH (argument 2) must be a number, not the text \"deep\""),
    ] {
        let (_, diagnostics) = run("wizards", &endmill, &format!("G21 G90\nM06 T1\nF100\n{call}\nM30\n"));
        assert!(diagnostics.len() == 1 && diagnostics[0].contains(words), "{call}: {diagnostics:?}");
    }
}

#[test]
fn a_new_wizard_in_python_or_javascript_builds_and_runs_as_the_rust_one_does() {
    let dir = tempfile::tempdir().unwrap();
    let wizards = dir.path().to_str().unwrap();
    // The toolchains (componentize-py, jco) the shipped wizards' builds installed, not a second copy.
    std::os::unix::fs::symlink(repo("wizards/target"), dir.path().join("target")).unwrap();
    let target = repo("tests/wizards/guests/target/cargo");
    for (name, lang, file, language) in
        [("Square", "python", "app.py", "Python"), ("Cube", "js", "wizard.js", "JavaScript")]
    {
        let (out, err, status) = ger(&["wizard", "new", name, "--lang", lang, "--wizards", wizards], "", &target);
        assert_eq!(status, 0, "{out}{err}");
        let folder = dir.path().join(name.to_ascii_lowercase());
        assert!(out.contains(&format!("edit {file}")) && folder.join(file).is_file(), "{out}");
        let program = format!("G21 G90\nG00 X0 Y0 Z0\nF100\n{name} 10 1\nM30\n");
        let (out, err, status) =
            ger(&["run", "--units", "mm", "--no-line-numbers", "--wizards", wizards, "-"], &program, &target);
        assert_eq!(status, 0, "{lang}: {err}");
        let body: Vec<&str> = out.lines().skip_while(|l| !l.starts_with("G00 X0")).skip(1).collect();
        assert_eq!(
            body,
            ["G01 Z-1.000 F100.000", "G01 X10.000", "G01 Y10.000", "G01 X0.000", "G01 Y0.000", "G00 Z0.000", "M30"],
            "{lang}"
        );
        let (out, err, status) = ger(&["wizard", "list", "--wizards", wizards], "", &target);
        assert_eq!(status, 0, "{err}");
        let listed = format!("({}, {language})", name.to_ascii_lowercase());
        assert!(out.contains(&format!("{name} SIDE DEPTH")) && out.contains(&listed), "{out}");
        // Its argument errors name the parameter, as the SDK's do.
        let (_, err, status) =
            ger(&["run", "--units", "mm", "--wizards", wizards, "-"], &program.replace(" 10 1", " 10 -1"), &target);
        assert_eq!(status, 1);
        assert!(err.contains("DEPTH (argument 2) must be greater than 0"), "{lang}: {err}");
    }
}

#[test]
fn watch_translates_again_when_the_program_or_a_wizard_changes() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().unwrap();
    let wizards = dir.path().join("wizards");
    std::fs::create_dir(&wizards).unwrap();
    // Built by an earlier use if need be.
    run("wizards", &mm(""), "BoltCircle 1 1 1\nPocket 1 1 1\n");
    // `Ww` is BoltCircle at first, then Pocket: the same call, another wizard.
    std::fs::copy(repo("wizards/boltcircle.wasm"), wizards.join("ww.wasm")).unwrap();
    let program = dir.path().join("p.ngc");
    std::fs::write(&program, "G21\nF100\nWw 10 20 1\nM30\n").unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["run", "--units", "mm", "--no-line-numbers", "--watch", "--wizards"])
        .arg(&wizards)
        .arg(&program)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let stdout = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(stdout).lines() {
            if tx.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    let one_run = || -> Vec<String> {
        let mut lines = Vec::new();
        while let Ok(line) = rx.recv_timeout(std::time::Duration::from_secs(30)) {
            let done = line == "M30";
            lines.push(line);
            if done {
                break;
            }
        }
        lines
    };
    // A slow machine may split one save's events across two runs: a run
    // that says again what the last one said is not the change awaited.
    let next_run = |last: &[String]| -> Vec<String> {
        loop {
            let lines = one_run();
            if lines.is_empty() || lines != last {
                return lines;
            }
        }
    };
    // Ten holes on a circle of diameter 20, the first at angle 0.
    let first = next_run(&[]);
    assert!(first.contains(&"G00 X10.000 Y0.000".to_string()), "{first:?}");
    std::fs::write(&program, "G21\nF100\nX3\nWw 10 20 1\nM30\n").unwrap();
    let second = next_run(&first);
    assert!(second.contains(&"G00 X13.000 Y0.000".to_string()), "{second:?}");
    // Pocket 10 x 20 x 1: feeds across XY (its rings), which BoltCircle never makes.
    // Later than the run's own writes, which the watcher lets pass.
    std::thread::sleep(std::time::Duration::from_millis(500));
    std::fs::copy(repo("wizards/pocket.wasm"), wizards.join("ww.wasm")).unwrap();
    let third = next_run(&second);
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(third.iter().any(|l| l.starts_with("G01 X") && l.contains(" Y")), "{third:?}");
    assert!(!third.contains(&"G00 X13.000 Y0.000".to_string()), "{third:?}");
}

#[test]
fn a_wizard_that_logs_too_much_is_stopped_at_its_limit() {
    // Babble logs 100 lines of 1 MiB: the host would keep them all.
    let (lines, diagnostics) = run("tests/wizards/guests", &mm(""), "G21 G90 G01 F100\nBabble\nNest 0\n");
    assert_eq!(diagnostics.len(), 1, "{diagnostics:#?}");
    let diagnostic = &diagnostics[0];
    assert!(
        diagnostic.starts_with("2:1: error: wizard `Babble` logged more than 64 KiB and was stopped"),
        "{diagnostic}"
    );
    // What it logged before is shown, each line cut to 200 characters.
    assert!(diagnostic.contains("its log:\n  babble babble"), "{}", &diagnostic[..diagnostic.len().min(500)]);
    assert!(diagnostic.len() < 1000, "{} bytes", diagnostic.len());
    assert_eq!(lines, ["G01 X0.0000 F100.0000"]);
}

#[test]
fn a_wizards_long_messages_and_names_are_cut_with_a_note() {
    let (_, diagnostics) = run("tests/wizards/guests", &mm(""), "Rant 0\nRant 1\nRant 2\n");
    assert_eq!(diagnostics.len(), 3, "{:#?}", diagnostics.iter().map(|d| d.len()).collect::<Vec<_>>());
    // A failure's message: 10 MiB of "no", of which the first 1,000 characters are shown.
    let message =
        format!("1:1: error: wizard `Rant`: {}... ({} more bytes cut)\n", "no".repeat(500), (10 << 20) - 1000);
    assert!(diagnostics[0].starts_with(&message), "{}", &diagnostics[0][..2000.min(diagnostics[0].len())]);
    assert!(diagnostics[0].contains("usage: Rant KIND"), "{}", diagnostics[0]);
    // A call of a 9 MiB name makes a line longer than the lexer reads; the line is shown cut.
    let line = format!("`{}... ({} more bytes cut)`", &"Yes".repeat(334)[..1000], (9 << 20) - 1000);
    let message =
        format!("2:1: error: wizard `Rant` returned a bad statement (#1, {line}): this line is longer than 1 MiB");
    assert!(diagnostics[1].starts_with(&message), "{}", &diagnostics[1][..2000.min(diagnostics[1].len())]);
    // A call of a 99,999-letter name is read, and is no wizard: its name is cut to 64 characters.
    let name = format!("{}... ({} more bytes cut)", &"Yes".repeat(22)[..64], 99_999 - 64);
    assert!(diagnostics[2].starts_with(&format!("3:1: error: no wizard named `{name}` in ")), "{}", diagnostics[2]);
    assert!(diagnostics[2].ends_with("in wizard `Rant` called at line 3"), "{}", diagnostics[2]);
    for diagnostic in &diagnostics {
        assert!(diagnostic.len() < 3000, "{} bytes", diagnostic.len());
    }
}

#[test]
fn all_the_calls_of_a_program_share_one_time_limit() {
    let config = mm("");
    run("tests/wizards/guests", &config, "Fan 0 0\n"); // built before the clock starts
                                                       // Spin never returns: each call takes all the time it may.
    let limits = Limits { time: Duration::from_millis(400), program_time: Duration::from_secs(1), ..Limits::default() };
    let started = std::time::Instant::now();
    let (_, diagnostics) = run_limited("tests/wizards/guests", &config, limits.clone(), "Spin\nSpin\nSpin\nSpin\n");
    let messages: Vec<&str> = diagnostics.iter().map(|d| d.lines().next().unwrap()).collect();
    assert_eq!(
        messages,
        [
            "1:1: error: wizard `Spin` did not finish within 0.4 s and was stopped",
            "2:1: error: wizard `Spin` did not finish within 0.4 s and was stopped",
            "3:1: error: wizard `Spin` was stopped: the wizard calls of this program had run for 1 s, \
             all the time they have together",
            "4:1: error: wizard `Spin` was not run: the wizard calls of this program have used all of their 1 s",
        ]
    );
    assert!(diagnostics[3].contains("--wizard-total-time"), "{}", diagnostics[3]);
    assert!(started.elapsed() < Duration::from_secs(10), "{:?}", started.elapsed());

    // Fan 10 15 makes 10^15 quick calls, nested: they count towards the same limit.
    let started = std::time::Instant::now();
    let (lines, diagnostics) = run_limited("tests/wizards/guests", &config, limits.clone(), "G01 F100\nFan 10 15\n");
    let elapsed = started.elapsed();
    assert!(!diagnostics.is_empty() && diagnostics.len() <= 15 * 10, "{} diagnostics", diagnostics.len());
    for diagnostic in &diagnostics {
        assert!(
            diagnostic.starts_with("2:1: error: wizard `Fan` was not run: the wizard calls of this program have used")
                || diagnostic.starts_with("2:1: error: wizard `Fan` was stopped: the wizard calls of this program had"),
            "{diagnostic}"
        );
    }
    assert!(lines.len() > 15, "{} lines: the calls ran until the limit", lines.len());
    assert!(elapsed < Duration::from_secs(20), "{elapsed:?}");

    // A new translation has the whole time again.
    let mut wizards = WasmWizards::new(&repo("tests/wizards/guests"), &config, limits, None);
    for _ in 0..2 {
        let options = Options { config: &config, stage: LAST_STAGE, wizards: &mut wizards };
        let messages: Vec<String> = translate("Spin\n".as_bytes(), Library::empty(), options)
            .filter_map(|e| if let Event::Diagnostic(d) = e { Some(d.message) } else { None })
            .collect();
        assert_eq!(messages, ["wizard `Spin` did not finish within 0.4 s and was stopped"]);
    }
}

#[test]
fn all_the_calls_of_a_program_share_one_statement_limit() {
    // Fan 10 3: each call returns its move and, above the last level, 10
    // calls, so 11 statements; the last level's calls return 1. Depth first,
    // the root and four Fan 10 2 subtrees (221 statements each) return 895;
    // the fifth Fan 10 2 and four of its Fan 10 1 subtrees (21 each) bring
    // that to 990, and its fifth Fan 10 1 would make it 1001. That call and
    // every one after it (five Fan 10 1, five Fan 10 2) fail.
    let limits = Limits { program_statements: 1000, ..Limits::default() };
    let (lines, diagnostics) =
        run_limited("tests/wizards/guests", &mm(""), limits, "G21 G90 G01 F100\nFan 10 3\nM30\n");
    let message = "2:1: error: wizard `Fan` returned 11 statements, which takes the wizard calls of this program \
                   past the 1000 statements they may return together";
    assert_eq!(diagnostics.len(), 11, "{diagnostics:#?}");
    assert!(diagnostics.iter().all(|d| d.starts_with(message)), "{diagnostics:#?}");
    // The calls that ran: the root, 4 x (1 + 10 x 11), then 1 + 4 x 11, each one move.
    assert_eq!(lines.iter().filter(|l| l.starts_with("G01 X")).count(), 1 + 4 * 111 + 1 + 4 * 11);
}

#[test]
fn m99_and_o_in_a_wizards_output_are_errors_at_the_call() {
    // On Fanuc or Haas an M99 in the main program rewinds and runs it again.
    let (lines, diagnostics) = run("tests/wizards/guests", &mm(""), "G21 G90 G01 F100\nRewind 0\nRewind 1\nX9\nM30\n");
    assert_eq!(diagnostics.len(), 2, "{diagnostics:#?}");
    assert!(diagnostics[0].starts_with("2:1: error: M99 in the output of wizard `Rewind`\n"), "{}", diagnostics[0]);
    assert!(
        diagnostics[0].contains("Fanuc or Haas") && diagnostics[0].ends_with("in wizard `Rewind` called at line 2")
    );
    assert!(
        diagnostics[1]
            .starts_with("3:1: error: O100 in the output of wizard `Rewind`: a wizard cannot define a subprogram\n"),
        "{}",
        diagnostics[1]
    );
    // What came before the M99 ran; the rest of each call's output (X2; X3,
    // M99 and M98 P100) is dropped, and the program goes on.
    assert_eq!(lines, ["G01 X1.0000 F100.0000", "G01 X9.0000", "M30"]);
}

#[test]
fn a_wizards_random_numbers_depend_only_on_the_call() {
    // O1 runs twice from the same place: the same call, with the same state.
    let program = "O1000\nO1\nG00 X0 Y0\nRandom\nM99\nG21 G90 G01 F100\nM98 P1 L2\nG00 X5\nRandom\nM30\n";
    // Where each of Random's moves went: X from its hash map's keys, Y from wasi:random.
    let targets = |lines: Vec<String>| -> Vec<(String, String)> {
        let word = |line: &str, axis: char| line.split(' ').find(|w| w.starts_with(axis)).unwrap().to_string();
        lines.iter().filter(|l| l.starts_with("G01")).map(|l| (word(l, 'X'), word(l, 'Y'))).collect()
    };
    let (first, diagnostics) = run("tests/wizards/guests", &mm(""), program);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let first = targets(first);
    assert_eq!(first.len(), 3, "{first:?}");
    assert_eq!(first[0], first[1], "the same call twice");
    // Another state is another call: other numbers.
    assert!(first[0].0 != first[2].0 && first[0].1 != first[2].1, "{first:?}");
    // A second run (a new runtime) gives the same numbers.
    let (second, _) = run("tests/wizards/guests", &mm(""), program);
    assert_eq!(targets(second), first);
}

#[test]
fn a_wizard_never_sees_what_an_earlier_call_left() {
    // `Remember N` moves to X = N plus the marks of earlier calls it finds in
    // its statics and heap: each call must find none.
    let calls: String = (1..=5).map(|n| format!("Remember {n}\n")).collect();
    let (lines, diagnostics) = run("tests/wizards/guests", &mm(""), &format!("G21 G90 G01 F100\n{calls}M30\n"));
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let xs: Vec<f64> = moves(&lines).iter().map(|(_, _, to)| to[0]).collect();
    assert_eq!(xs, [1.0, 2.0, 3.0, 4.0, 5.0], "a call found an earlier call's marks: {lines:?}");
}

#[test]
fn a_wizard_built_against_the_first_contract_runs_unchanged() {
    let tools = "[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\n\
                 [[tools]]\nnumber = 2\nkind = \"endmill\"\ndiameter = 3\nflute_length = 12\n";
    let (lines, diagnostics) = run("tests/wizards/guests", &mm(tools), "G21 G90 G01 F100\nLegacy 2\nM30\n");
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let ends: Vec<[f64; 3]> = moves(&lines).iter().map(|(_, _, to)| *to).collect();
    assert_eq!(ends, [[3.0, 12.0, 0.0]], "{lines:?}");
    // It is a component of ger:wizard@0.1.0, asking for that version's host.
    let wasm = std::fs::read(repo("tests/wizards/guests/legacy.wasm")).unwrap();
    let has = |text: &str| wasm.windows(text.len()).any(|w| w == text.as_bytes());
    assert!(has("ger:wizard/host@0.1.0") && !has("ger:wizard/host@0.2.0"));
}

#[test]
fn a_wizard_is_told_the_stock_the_tools_and_the_unit_and_may_warn() {
    let config = "units = \"mm\"\n[stock]\nsize = [100, 60, 20]\n\
                  [[tools]]\nnumber = 7\nkind = \"endmill\"\ndiameter = 6\n\
                  [[tools]]\nnumber = 3\nkind = \"drill\"\ndiameter = 3\n";
    let config = Config::from_toml(config).unwrap();
    // An inch program on a millimetre machine: Survey's numbers are in inches,
    // and ger writes them in millimetres.
    let (lines, diagnostics) = run("tests/wizards/guests", &config, "G20 G90 G01 F10\nSurvey\nM30\n");
    let ends: Vec<[f64; 3]> = moves(&lines).iter().map(|(_, _, to)| *to).collect();
    // The stock's far corner (program zero on its top lower-left corner),
    // then 2 tools, the largest T7, and 1 for a millimetre machine (in inches).
    assert_eq!(ends, [[100.0, 60.0, -20.0], [50.8, 177.8, 25.4]], "{lines:?}");
    let shown: Vec<&str> = diagnostics.iter().map(|d| d.lines().next().unwrap()).collect();
    assert_eq!(shown, ["2:1: warning: wizard `Survey`: warning 1", "2:1: warning: wizard `Survey`: warning 2"]);
    // Past 16 a call, warnings are counted.
    let (_, diagnostics) = run("tests/wizards/guests", &config, "G20 G90 G01 F10\nSurvey 20\nM30\n");
    assert_eq!(diagnostics.len(), 17, "{diagnostics:?}");
    assert!(diagnostics[16].starts_with("2:1: warning: wizard `Survey` gave 4 more warnings, not shown"));
    // With no stock size, there is none to tell.
    let (_, diagnostics) = run("tests/wizards/guests", &mm(""), "Survey\nM30\n");
    assert!(diagnostics[0].contains("wizard `Survey`: no stock"), "{diagnostics:?}");
}

#[test]
fn the_total_time_is_an_option() {
    let target = repo("tests/wizards/guests/target/cargo");
    run("tests/wizards/guests", &mm(""), "Spin\n");
    let wizards = repo("tests/wizards/guests");
    let args =
        ["run", "--wizard-time", "0.3", "--wizard-total-time", "0.5", "--wizards", wizards.to_str().unwrap(), "-"];
    let (_, err, status) = ger(&args, "Spin\nSpin\nSpin\n", &target);
    assert_eq!(status, 1);
    assert!(err.contains("error: wizard `Spin` did not finish within 0.3 s"), "{err}");
    assert!(
        err.contains("error: wizard `Spin` was stopped: the wizard calls of this program had run for 0.5 s"),
        "{err}"
    );
    assert!(err.contains("error: wizard `Spin` was not run"), "{err}");
}

/// `ger run` of `program` with the wizards in `wizards` and the cache key
/// under `cache_home` (as `XDG_CACHE_HOME`).
fn ger_cached(wizards: &Path, cache_home: &Path, program: &str) -> (String, String, i32) {
    use std::io::Write;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["run", "--units", "mm", "--no-line-numbers", "--no-build", "--wizards"])
        .arg(wizards)
        .arg("-")
        .env("NO_COLOR", "1")
        .env("XDG_CACHE_HOME", cache_home)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(program.as_bytes()).unwrap();
    let output = child.wait_with_output().unwrap();
    let text = |b: Vec<u8>| String::from_utf8_lossy(&b).into_owned();
    // A signal (SIGILL from bad native code) has no exit code.
    (text(output.stdout), text(output.stderr), output.status.code().unwrap_or(-1))
}

/// The bytes of section `name` of the ELF file inside `bytes` (a compiled component).
fn elf_section(bytes: &[u8], name: &str) -> std::ops::Range<usize> {
    let start = bytes.windows(4).position(|w| w == b"\x7fELF").expect("an ELF file");
    let elf = &bytes[start..];
    let at = |offset: usize, size: usize| {
        elf[offset..offset + size].iter().rev().fold(0usize, |n, &b| n << 8 | usize::from(b))
        // little-endian
    };
    let (table, entry_size, count, names) = (at(0x28, 8), at(0x3a, 2), at(0x3c, 2), at(0x3e, 2));
    let header = |i: usize| table + i * entry_size;
    let strings = at(header(names) + 0x18, 8);
    (0..count)
        .find_map(|i| {
            let text = &elf[strings + at(header(i), 4)..];
            let found = &text[..text.iter().position(|&b| b == 0)?];
            let offset = start + at(header(i) + 0x18, 8);
            (found == name.as_bytes()).then(|| offset..offset + at(header(i) + 0x20, 8))
        })
        .expect("the section")
}

#[cfg(unix)]
#[test]
fn the_compile_cache_runs_only_what_this_users_ger_compiled_from_that_wasm() {
    use std::os::unix::fs::MetadataExt;
    run("tests/wizards/guests", &mm(""), "Nest 0\nEcho\n"); // built if need be
    let temp = tempfile::tempdir().unwrap();
    let wizards = temp.path().join("wizards");
    std::fs::create_dir(&wizards).unwrap();
    for name in ["nest.wasm", "echo.wasm"] {
        std::fs::copy(repo("tests/wizards/guests").join(name), wizards.join(name)).unwrap();
    }
    let (key_a, key_b) = (temp.path().join("a"), temp.path().join("b"));
    let cache = wizards.join("target/ger/cache");
    let entries = || -> Vec<PathBuf> {
        let Ok(read) = std::fs::read_dir(&cache) else { return Vec::new() };
        read.map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "cwasm")).collect()
    };
    let program = "G21 G90 G01 F100\nNest 1\nM30\n";
    // Nest 1 moves to X1, then X0, and nothing else does.
    let nest_ran = |key: &Path| {
        let (out, err, status) = ger_cached(&wizards, key, program);
        assert_eq!(status, 0, "{err}");
        let moves: Vec<&str> = out.lines().filter(|l| l.starts_with("G01 X")).collect();
        assert_eq!(moves.len(), 2, "{out}");
        assert!(moves[0].starts_with("G01 X1.000") && moves[1] == "G01 X0.000", "{out}");
    };
    let inode = |path: &Path| std::fs::metadata(path).unwrap().ino();

    nest_ran(&key_a);
    let [nest] = &entries()[..] else { panic!("{:?}", entries()) };
    let nest = nest.clone();
    let (_, err, _) = ger_cached(&wizards, &key_a, "Echo\n");
    assert!(err.contains("error: wizard `Echo`: State {"), "{err}");
    let echo = entries().into_iter().find(|p| *p != nest).expect("Echo's entry");
    // A good entry is used as it is: not written again.
    let good = inode(&nest);
    nest_ran(&key_a);
    assert_eq!(inode(&nest), good);

    // Each bad entry is compiled again and overwritten; the new one is then used.
    let compiled_again = |bad: &[u8], key: &Path| {
        std::fs::write(&nest, bad).unwrap();
        nest_ran(key);
        assert_ne!(std::fs::read(&nest).unwrap(), bad);
        let rewritten = inode(&nest);
        nest_ran(key);
        assert_eq!(inode(&nest), rewritten, "the new entry verifies");
    };
    let entry = std::fs::read(&nest).unwrap();
    // Another wizard's entry under this one's name (it would run as Echo).
    compiled_again(&std::fs::read(&echo).unwrap(), &key_a);
    // Native code changed: its code section filled with ud2 (it would crash with SIGILL).
    let mut changed = entry.clone();
    let text = elf_section(&changed, ".text");
    for (i, byte) in changed[text].iter_mut().enumerate() {
        *byte = [0x0f, 0x0b][i % 2];
    }
    compiled_again(&changed, &key_a);
    // Cut short: to half, and to less than a signature.
    compiled_again(&entry[..entry.len() / 2], &key_a);
    compiled_again(&entry[..10], &key_a);
    // Signed with another user's key.
    compiled_again(&entry, &key_b);

    // A link to a file elsewhere is replaced, not written through; a FIFO (which
    // would block a reader for ever) is replaced too.
    let outside = temp.path().join("outside");
    std::fs::write(&outside, "not ger's").unwrap();
    std::fs::remove_file(&nest).unwrap();
    std::os::unix::fs::symlink(&outside, &nest).unwrap();
    nest_ran(&key_a);
    assert_eq!(std::fs::read_to_string(&outside).unwrap(), "not ger's");
    assert!(std::fs::symlink_metadata(&nest).unwrap().is_file());
    std::fs::remove_file(&nest).unwrap();
    let made = std::process::Command::new("mkfifo").arg(&nest).status().unwrap();
    assert!(made.success());
    nest_ran(&key_a);
    assert!(std::fs::symlink_metadata(&nest).unwrap().is_file());

    // Where no key can be made (its folder would be under a file), nothing is cached.
    std::fs::remove_dir_all(&cache).unwrap();
    let blocked = temp.path().join("file");
    std::fs::write(&blocked, "").unwrap();
    nest_ran(&blocked);
    assert!(entries().is_empty(), "{:?}", entries());
}
