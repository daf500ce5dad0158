//! The tools and stock a program describes, as a user meets them: `ger
//! render` cutting with the tool a Fusion 360 comment names (its slot
//! measured on the STL), the default tool in a millimetre machine, `ger
//! check` saying where each tool came from, CAMotics projects and
//! CutViewer's STOCK/BLOCK giving the stock, and the shared corpus's tool
//! comments read as their own text says.

mod support;

use std::path::Path;
use std::process::{Command, Output};

use serde_json::Value;

fn ger(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ger")).current_dir(dir).env("NO_COLOR", "1").args(args).output().unwrap()
}

fn ok(out: &Output) {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// A folder holding `files` (name, text), and no ger.toml.
fn folder(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    dir
}

/// A slot along X from X0 to X40 at Y0, 2 mm deep, posted as Fusion 360's
/// generic post writes a program, with `header` as its tool comment.
fn fusion_slot(header: &str) -> String {
    format!(
        "%\nO1001\n{header}\nG90 G94 G17\nG21\n\n(2D Contour1)\nT1 M6\nS10000 M3\nG54\nG0 X0 Y0\nZ5\n\
         G1 Z-2 F300\nX40 F600\nG0 Z5\nM5\nM30\n%\n"
    )
}

/// The top surface's vertices of a binary STL, as the mesh writes them: one at each cell's centre.
fn stl_vertices(path: &Path) -> Vec<[f64; 3]> {
    let bytes = std::fs::read(path).unwrap();
    let count = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * count);
    let f = |k: usize| f64::from(f32::from_le_bytes(bytes[k..k + 4].try_into().unwrap()));
    (0..count)
        .flat_map(|t| (0..3).map(move |v| 84 + 50 * t + 12 + 12 * v))
        .map(|k| [f(k), f(k + 4), f(k + 8)])
        .collect()
}

/// How wide the slot's floor is across Y at X = `x`, counted in cells of `cell`:
/// the cells whose centre is on the floor, `depth` down.
fn slot_width(vertices: &[[f64; 3]], x: f64, depth: f64, cell: f64) -> f64 {
    let mut ys: Vec<f64> = vertices
        .iter()
        .filter(|v| (v[0] - x).abs() < cell / 2.0 && (v[2] + depth).abs() < 1e-4)
        .map(|v| (v[1] / cell).round())
        .collect();
    ys.sort_by(f64::total_cmp);
    ys.dedup();
    ys.len() as f64 * cell
}

#[test]
fn render_cuts_with_the_tool_a_fusion_comment_names() {
    // A 1/8" endmill in a millimetre program, on ger's default inch machine: 3.175 mm is 0.125 in.
    let program = fusion_slot("(T1 D=3.175 CR=0. - ZMIN=-2. - flat end mill)");
    let dir = folder(&[("part.nc", &program)]);
    let cell: f64 = 0.002;
    ok(&ger(dir.path(), &["render", "--lenient", "part.nc", "-o", "part.stl", "--resolution", "0.002"]));
    let vertices = stl_vertices(&dir.path().join("part.stl"));
    // Mid-slot, 20 mm along; the floor 2 mm down.
    let (x, depth) = (20.0 / 25.4, 2.0 / 25.4);
    let x = (x / cell).floor() * cell + cell / 2.0;
    let width = slot_width(&vertices, x, depth, cell);
    assert!((width - 0.125).abs() <= cell, "slot {width} in wide, the comment's tool is 0.125 in");

    // The same program with no comment is cut by the default quarter-inch endmill.
    let dir = folder(&[("part.nc", &fusion_slot("(no tools here)"))]);
    ok(&ger(dir.path(), &["render", "--lenient", "part.nc", "-o", "part.stl", "--resolution", "0.002"]));
    let width = slot_width(&stl_vertices(&dir.path().join("part.stl")), x, depth, cell);
    assert!((width - 0.25).abs() <= cell, "slot {width} in wide, the default tool is 0.25 in");
}

#[test]
fn the_default_tool_is_a_quarter_inch_in_a_millimetre_machine() {
    // No comment, no ger.toml, --units mm: the slot is 6.35 mm wide, not 0.25 mm.
    let dir = folder(&[("part.nc", &fusion_slot("(no tools here)"))]);
    let cell: f64 = 0.05;
    let args = ["render", "--lenient", "--units", "mm", "part.nc", "-o", "part.stl", "--resolution", "0.05"];
    ok(&ger(dir.path(), &args));
    let x = (20.0f64 / cell).floor() * cell + cell / 2.0;
    let width = slot_width(&stl_vertices(&dir.path().join("part.stl")), x, 2.0, cell);
    assert!((width - 6.35).abs() <= cell, "slot {width} mm wide");

    // And a ger.toml that gives only the unit changes nothing about that.
    std::fs::write(dir.path().join("ger.toml"), "units = \"mm\"\n").unwrap();
    ok(&ger(dir.path(), &["render", "--lenient", "part.nc", "-o", "part.stl", "--resolution", "0.05"]));
    let width = slot_width(&stl_vertices(&dir.path().join("part.stl")), x, 2.0, cell);
    assert!((width - 6.35).abs() <= cell, "slot {width} mm wide");
}

fn json_check(dir: &Path, args: &[&str]) -> (Value, Option<i32>) {
    let mut all = vec!["check", "--lenient", "--quiet", "--format", "json"];
    all.extend_from_slice(args);
    let out = ger(dir, &all);
    (serde_json::from_slice(&out.stdout).unwrap(), out.status.code())
}

#[test]
fn check_says_where_each_tool_came_from() {
    let program = fusion_slot("(T1 D=6. CR=0. - ZMIN=-2. - flat end mill)");
    let dir = folder(&[("part.nc", &program)]);
    let (report, status) = json_check(dir.path(), &["--units", "mm", "part.nc"]);
    assert_eq!(status, Some(0));
    assert_eq!(report["diagnostics"], serde_json::json!([]));
    let tool = &report["summary"]["tools"][0];
    assert_eq!(tool["source"], serde_json::json!({ "from": "comment", "line": 3 }));
    assert_eq!((tool["kind"].as_str(), tool["diameter"].as_f64()), (Some("endmill"), Some(6.0)));
    let text = ger(dir.path(), &["check", "--lenient", "--quiet", "--units", "mm", "part.nc"]);
    let stdout = String::from_utf8_lossy(&text.stdout);
    assert!(
        stdout.contains("tools     T1 47.000 mm over 2 moves: endmill 6.000 mm, from the program's comment at line 3"),
        "{stdout}"
    );

    // The config file's table wins over the comment.
    let config = "units = \"mm\"\n[[tools]]\nnumber = 1\nkind = \"ballmill\"\ndiameter = 2\n";
    std::fs::write(dir.path().join("ger.toml"), config).unwrap();
    let (report, _) = json_check(dir.path(), &["part.nc"]);
    let tool = &report["summary"]["tools"][0];
    assert_eq!(tool["kind"], "ballmill");
    assert_eq!(tool["source"], serde_json::json!({ "from": "config", "file": "ger.toml" }), "{tool}");
}

#[test]
fn check_warns_once_when_it_falls_back_to_the_default_tool() {
    // Two cuts, both with the undescribed tool 1: one warning, at the first move.
    let program = "G21\nM03 S1000\nG00 X0 Y0 Z5\nG01 Z-1 F100\nX10\nG00 Z5\nX0 Y10\nG01 Z-1\nX10\nG00 Z5\nM05\nM30\n";
    let dir = folder(&[("part.ngc", program)]);
    let (report, status) = json_check(dir.path(), &["--units", "mm", "part.ngc"]);
    assert_eq!(status, Some(0), "a warning");
    let diagnostics = report["diagnostics"].as_array().unwrap();
    assert_eq!(diagnostics.len(), 1, "{diagnostics:#?}");
    assert_eq!((diagnostics[0]["rule"].as_str(), diagnostics[0]["line"].as_u64()), (Some("default-tool"), Some(3)));
    assert!(diagnostics[0]["message"].as_str().unwrap().contains("quarter-inch endmill (6.350 mm)"));
    assert_eq!(report["summary"]["tools"][0]["source"], serde_json::json!({ "from": "default" }));
    assert_eq!(report["summary"]["problems"], serde_json::json!({ "default-tool": 1 }));
    // --allow default-tool: nothing to say; --deny warnings: a failure.
    let (report, status) = json_check(dir.path(), &["--units", "mm", "--allow", "default-tool", "part.ngc"]);
    assert_eq!((status, report["diagnostics"].as_array().map(Vec::len)), (Some(0), Some(0)));
    let (_, status) = json_check(dir.path(), &["--units", "mm", "--deny", "warnings", "part.ngc"]);
    assert_eq!(status, Some(1));
}

/// A 20 mm slot 1 mm deep along X at Y5, with no tool change and no comment.
const PLAIN_SLOT: &str = "G21\nG00 X0 Y5 Z5\nG01 Z-1 F100\nX20\nG00 Z5\nM30\n";

/// The box an STL's vertices span.
fn stl_box(path: &Path) -> ([f64; 3], [f64; 3]) {
    stl_vertices(path).iter().fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), v| {
        (std::array::from_fn(|i| lo[i].min(v[i])), std::array::from_fn(|i| hi[i].max(v[i])))
    })
}

fn assert_box(got: ([f64; 3], [f64; 3]), want: ([f64; 3], [f64; 3])) {
    for i in 0..3 {
        assert!((got.0[i] - want.0[i]).abs() < 1e-3 && (got.1[i] - want.1[i]).abs() < 1e-3, "{got:?} vs {want:?}");
    }
}

#[test]
fn a_camotics_project_beside_the_program_gives_its_tools_and_workpiece() {
    // As CAMotics' tiger.camotics is written: a 2.5 mm cylindrical tool, a workpiece box.
    let project = r#"{
      "units": "metric",
      "tools": { "1": { "units": "metric", "shape": "cylindrical", "length": 20, "diameter": 2.5, "description": "" } },
      "workpiece": { "automatic": false, "margin": 0, "bounds": { "min": [-2, -1, -6], "max": [30, 12, 0] } },
      "files": ["part.nc"]
    }"#;
    let dir = folder(&[("part.nc", PLAIN_SLOT), ("part.camotics", project)]);
    let (report, _) = json_check(dir.path(), &["--units", "mm", "part.nc"]);
    let tool = &report["summary"]["tools"][0];
    assert_eq!(tool["source"], serde_json::json!({ "from": "camotics", "file": "part.camotics" }));
    assert_eq!(tool["diameter"], 2.5);
    // The part is the workpiece's box: the STL spans it.
    ok(&ger(dir.path(), &["render", "--units", "mm", "part.nc", "-o", "part.stl", "--resolution", "0.25"]));
    assert_box(stl_box(&dir.path().join("part.stl")), ([-2.0, -1.0, -6.0], [30.0, 12.0, 0.0]));

    // Another name: found by the project's list of files.
    std::fs::rename(dir.path().join("part.camotics"), dir.path().join("job.camotics")).unwrap();
    let (report, _) = json_check(dir.path(), &["--units", "mm", "part.nc"]);
    assert_eq!(report["summary"]["tools"][0]["source"]["file"], "job.camotics");

    // A broken project of the program's own name is an error that says where.
    std::fs::write(dir.path().join("part.camotics"), "{ \"tools\": ").unwrap();
    let out = ger(dir.path(), &["check", "--units", "mm", "part.nc"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("bad CAMotics project part.camotics: EOF while parsing a value at line 1 column 11"),
        "{stderr}"
    );
}

#[test]
fn an_automatic_camotics_workpiece_is_the_cut_plus_its_margin_in_percent() {
    let project =
        r#"{ "tools": { "1": { "diameter": 2, "length": 10 } }, "workpiece": { "automatic": true, "margin": 10 } }"#;
    let dir = folder(&[("part.nc", PLAIN_SLOT), ("part.camotics", project)]);
    ok(&ger(dir.path(), &["render", "--units", "mm", "part.nc", "-o", "part.stl", "--resolution", "0.1"]));
    // The cut: X -1 to 21, Y 4 to 6, Z -1 to 0, which CAMotics deepens by 2 mm (it is under 2 mm);
    // then 10% of 22 x 2 x 3 mm on each side, and below.
    assert_box(stl_box(&dir.path().join("part.stl")), ([-3.2, 3.8, -3.3], [23.2, 6.2, 0.0]));
}

#[test]
fn cutviewers_stock_block_gives_the_stock() {
    // As Carbide Create writes it: a 100 x 100 x 1 mm sheet, program zero on its top lower-left corner.
    let program = format!(
        "(STOCK/BLOCK,100.00, 100.00, 1.00,0.00, 0.00, 1.00)\n(TOOL/MILL,3.17, 0.00, 0.00, 0.00)\n{PLAIN_SLOT}"
    );
    let dir = folder(&[("part.nc", &program)]);
    ok(&ger(dir.path(), &["render", "--units", "mm", "part.nc", "-o", "part.stl", "--resolution", "0.5"]));
    assert_box(stl_box(&dir.path().join("part.stl")), ([0.0, 0.0, -1.0], [100.0, 100.0, 0.0]));
}

/// The corpus's Fusion 360 tool comments, read by splitting their text, against what the scan made of them.
#[test]
fn the_corpus_tool_comments_are_read_as_written() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpus");
    if !corpus.join("INDEX.tsv").exists() {
        support::peer_missing(&format!("the corpus is not at {}: its tool comments were NOT read", corpus.display()));
        return;
    }
    let index = std::fs::read_to_string(corpus.join("INDEX.tsv")).unwrap();
    let (mut files, mut compared) = (0, 0);
    for line in index.lines().skip(1) {
        let fields: Vec<&str> = line.split('\t').collect();
        if fields.len() < 8 || fields[7] != "gcode" {
            continue;
        }
        let Ok(text) = std::fs::read_to_string(corpus.join(fields[0])) else { continue };
        let scan = ger_core::tools::scan(text.as_bytes(), ger_core::statement::Dialect::Lenient);
        files += 1;
        // Every "(Tn D=d ..." line: tool n has diameter d, at the first line that describes n.
        let mut seen = std::collections::BTreeSet::new();
        for (number, line) in text.lines().enumerate() {
            let Some(comment) = line.trim().strip_prefix("(T") else { continue };
            let mut words = comment.split_whitespace();
            let Some(tool) = words.next().and_then(|n| n.parse::<u32>().ok()) else { continue };
            let Some(diameter) = words.next().and_then(|w| w.strip_prefix("D=")).and_then(|d| d.parse::<f64>().ok())
            else {
                continue;
            };
            if !seen.insert(tool) {
                continue;
            }
            let entry = &scan.tools[&tool];
            assert_eq!((entry.described.diameter, entry.line), (diameter, number as u32 + 1), "{}: {line}", fields[0]);
            compared += 1;
        }
    }
    assert!(files > 300 && compared > 150, "{files} files, {compared} comments");

    // Every CAMotics project of the corpus reads, and the three the README quotes give what they say.
    for entry in std::fs::read_dir(corpus.join("camotics-examples")).unwrap() {
        let folder = entry.unwrap().path();
        for file in std::fs::read_dir(&folder).unwrap().map(|f| f.unwrap().path()) {
            if file.extension().is_some_and(|e| e == "camotics") {
                let project = ger_core::tools::camotics::parse(&std::fs::read_to_string(&file).unwrap());
                assert!(project.is_ok(), "{}: {:?}", file.display(), project.err());
            }
        }
    }
    let read = |name: &str| {
        let path = corpus.join(format!("camotics-examples/{name}/{name}.camotics"));
        ger_core::tools::camotics::parse(&std::fs::read_to_string(path).unwrap()).unwrap()
    };
    use ger_core::config::ToolKind::*;
    for (name, kind, diameter) in [("cameo", Ballmill, 2.0), ("bear", Ballmill, 3.175), ("tiger", Endmill, 2.5)] {
        let tool = &read(name).tools[0];
        assert_eq!((tool.number, tool.kind, tool.diameter), (1, kind, diameter), "{name}");
    }
}
