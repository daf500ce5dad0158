//! `ger compare` as a user runs it: the JSON report against its schema
//! (`host/docs/compare.schema.json`), the text, the heat map, the exit
//! status and a broken design. The part against geometry written by hand is
//! ger-engine's test; here the design is the STL of a program ger renders.

use std::path::Path;
use std::process::{Command, Output};

fn ger(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ger")).current_dir(dir).env("NO_COLOR", "1").args(args).output().unwrap()
}

const CONFIG: &str = "units = \"mm\"\n[stock]\nsize = [100, 50, 20]\norigin = [0, 0, 20]\n\
                      [[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 10\nflute_length = 20\n";
/// A 10 mm slot 5 deep along Y25 through the block.
const SLOT: &str = "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG01 Z-5 F500\nX110\nG00 Z5\nM30\n";
/// The same, and 0.3 mm deeper from X50 to X70 (lines 7 and 8).
const DEEP: &str = "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG01 Z-5 F500\nX110\nG00 X50 Z1\nG01 Z-5.3\nX70\nG00 Z5\nM30\n";

#[test]
fn a_gouge_is_reported_with_its_lines_as_text_json_and_a_heat_map() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    std::fs::write(path.join("ger.toml"), CONFIG).unwrap();
    std::fs::write(path.join("slot.ngc"), SLOT).unwrap();
    std::fs::write(path.join("deep.ngc"), DEEP).unwrap();
    let out = ger(path, &["render", "slot.ngc", "-o", "slot.stl", "--resolution", "0.5", "-q"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));

    let out = ger(path, &["compare", "slot.ngc", "slot.stl", "--resolution", "0.5", "-q"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("slot.ngc against slot.stl: within the tolerance\n"), "{text}");

    let args =
        ["compare", "deep.ngc", "slot.stl", "--resolution", "0.5", "-q", "--format", "json", "--heat-map", "heat.png"];
    let out = ger(path, &args);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/compare.schema.json")).unwrap();
    let schema = jsonschema::validator_for(&serde_json::from_str(&text).unwrap()).unwrap();
    let errors: Vec<String> = schema.iter_errors(&report).map(|e| format!("{e} at {}", e.instance_path())).collect();
    assert!(errors.is_empty(), "{errors:?}\n{report:#}");
    let gouge = &report["gouge"];
    assert!((gouge["worst"].as_f64().unwrap() - 0.3).abs() < 1e-5, "{report:#}");
    assert_eq!(gouge["lines"], serde_json::json!([7, 8]));
    assert_eq!(report["left"]["area"], 0.0);
    // The heat map: red where gouged (the stadium, about 279 of 5000 mm²), green elsewhere on the part.
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path.join("heat.png")).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let pixels: Vec<&[u8]> = buf[..info.buffer_size()].chunks(3).collect();
    let red = pixels.iter().filter(|c| **c == [215, 40, 35]).count() as f64;
    let green = pixels.iter().filter(|c| **c == [70, 170, 80]).count() as f64;
    let share = red / (red + green);
    assert!((share - 279.0 / 5000.0).abs() < 0.01, "red {red} green {green}");
}

#[test]
fn check_with_a_design_adds_the_comparison_and_fails_on_a_gouge() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    std::fs::write(path.join("ger.toml"), CONFIG).unwrap();
    std::fs::write(path.join("slot.ngc"), SLOT).unwrap();
    std::fs::write(path.join("deep.ngc"), DEEP).unwrap();
    assert!(ger(path, &["render", "slot.ngc", "-o", "slot.stl", "--resolution", "0.5", "-q"]).status.success());
    let out = ger(path, &["check", "deep.ngc", "--design", "slot.stl", "--resolution", "0.5", "-q"]);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("  gouged    0.300 mm deepest") && text.contains("cut by lines 7, 8"), "{text}");
    let args = ["check", "deep.ngc", "--design", "slot.stl", "--resolution", "0.5", "-q", "--format", "json"];
    let report: serde_json::Value = serde_json::from_slice(&ger(path, &args).stdout).unwrap();
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/check.schema.json")).unwrap();
    let schema = jsonschema::validator_for(&serde_json::from_str(&text).unwrap()).unwrap();
    let errors: Vec<String> = schema.iter_errors(&report).map(|e| format!("{e} at {}", e.instance_path())).collect();
    assert!(errors.is_empty(), "{errors:?}\n{report:#}");
    assert_eq!(report["design"]["gouge"]["lines"], serde_json::json!([7, 8]));
    // The slot itself is within the tolerance: exit 0.
    assert_eq!(
        ger(path, &["check", "slot.ngc", "--design", "slot.stl", "--resolution", "0.5", "-q"]).status.code(),
        Some(0)
    );
}

#[test]
fn a_design_that_is_not_a_solid_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    std::fs::write(path.join("ger.toml"), CONFIG).unwrap();
    std::fs::write(path.join("slot.ngc"), SLOT).unwrap();
    // One triangle: no edge has a neighbour.
    let open = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid x\n";
    std::fs::write(path.join("open.stl"), open).unwrap();
    let out = ger(path, &["compare", "slot.ngc", "open.stl", "-q"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("bad design open.stl: the mesh is not a closed surface"), "{err}");
}

/// The slot roughed 4 mm deep of its 5.
const ROUGH: &str = "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG01 Z-4 F500\nX110\nG00 Z5\nM30\n";
/// Its finishing: a rapid down into the roughed slot (line 4), the last millimetre, and 0.3 mm too
/// deep from X50 to X70 (lines 8 and 9).
const FINISH_DEEP: &str =
    "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG00 Z-3\nG01 Z-5 F500\nX110\nG00 X50 Z1\nG01 Z-5.3\nX70\nG00 Z5\nM30\n";
/// The same finishing, exact.
const FINISH: &str = "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG00 Z-3\nG01 Z-5 F500\nX110\nG00 Z5\nM30\n";

fn job_folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    for (name, text) in [
        ("ger.toml", CONFIG),
        ("slot.ngc", SLOT),
        ("rough.ngc", ROUGH),
        ("finish.ngc", FINISH),
        ("deep.ngc", FINISH_DEEP),
        ("slot_deep.ngc", DEEP),
    ] {
        std::fs::write(path.join(name), text).unwrap();
    }
    let out = ger(path, &["render", "slot.ngc", "-o", "slot.stl", "--resolution", "0.5", "-q"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    dir
}

#[test]
fn a_job_is_compared_on_the_part_its_programs_leave_together() {
    let dir = job_folder();
    let path = dir.path();
    let out = ger(path, &["compare", "rough.ngc", "finish.ngc", "slot.stl", "--resolution", "0.5", "-q"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("rough.ngc, then finish.ngc against slot.stl: within the tolerance\n"), "{text}");

    // The roughing alone leaves the last millimetre of the slot: 10 x 100 mm.
    let out = ger(path, &["compare", "rough.ngc", "slot.stl", "--resolution", "0.5", "-q"]);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("  left      1.000 mm highest") && text.contains("1000.000 mm³"), "{text}");

    let args = ["compare", "rough.ngc", "deep.ngc", "slot.stl", "--resolution", "0.5", "-q", "--format", "json"];
    let out = ger(path, &args);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/compare.schema.json")).unwrap();
    let schema = jsonschema::validator_for(&serde_json::from_str(&text).unwrap()).unwrap();
    let errors: Vec<String> = schema.iter_errors(&report).map(|e| format!("{e} at {}", e.instance_path())).collect();
    assert!(errors.is_empty(), "{errors:?}\n{report:#}");
    assert_eq!(report["files"], serde_json::json!(["rough.ngc", "deep.ngc"]));
    assert!((report["gouge"]["worst"].as_f64().unwrap() - 0.3).abs() < 1e-5, "{report:#}");
    assert_eq!(report["gouge"]["cut_by"], serde_json::json!([{ "file": "deep.ngc", "lines": [8, 9] }]));
    let out = ger(path, &["compare", "rough.ngc", "deep.ngc", "slot.stl", "--resolution", "0.5", "-q"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("; cut by deep.ngc lines 8, 9\n"), "{text}");
}

/// `ger check ARGS --design slot.stl` in `path` at a 0.5 mm grid: its exit status and its report.
fn check_against_slot(path: &Path, args: &[&str]) -> (Option<i32>, String) {
    let mut all = vec!["check"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--design", "slot.stl", "--resolution", "0.5", "-q"]);
    let out = ger(path, &all);
    (out.status.code(), String::from_utf8(out.stdout).unwrap())
}

#[test]
fn check_of_a_job_with_a_design_judges_the_part_the_whole_job_leaves() {
    let dir = job_folder();
    let path = dir.path();
    let check = |args: &[&str]| check_against_slot(path, args);
    // The finishing program's rapid goes into the roughed slot's air: clean, and the part is the design.
    let (status, text) = check(&["rough.ngc", "finish.ngc"]);
    assert_eq!(status, Some(0), "{text}");
    assert!(
        text.contains("job rough.ngc, then finish.ngc: no problems found\n  gouged    none\n  left      none\n"),
        "{text}"
    );
    let (status, text) = check(&["rough.ngc", "deep.ngc"]);
    assert_eq!(status, Some(1), "{text}");
    assert!(text.contains("job rough.ngc, then deep.ngc: 1 error (gouged below the design)\n"), "{text}");
    assert!(text.contains("; cut by deep.ngc lines 8, 9\n"), "{text}");
    let (_, text) = check(&["rough.ngc", "deep.ngc", "--format", "json"]);
    let report: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!((report["errors"].as_u64(), report["warnings"].as_u64()), (Some(1), Some(0)), "{report:#}");
    assert_eq!(report["design"]["gouge"]["cut_by"][0]["lines"], serde_json::json!([8, 9]));
}

#[test]
fn with_a_design_the_summary_counts_what_the_exit_status_counts() {
    let dir = job_folder();
    let path = dir.path();
    let check = |args: &[&str]| check_against_slot(path, args);
    // A gouge with no other finding: an error, not "no problems found".
    let (status, text) = check(&["slot_deep.ngc"]);
    assert_eq!(status, Some(1), "{text}");
    assert!(text.starts_with("slot_deep.ngc: 1 error (gouged below the design)\n"), "{text}");
    let (_, json) = check(&["slot_deep.ngc", "--format", "json"]);
    let report: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(report["errors"].as_u64(), Some(1), "{report:#}");
    // Material left is a warning (exit 0), an error under --deny warnings (exit 1).
    let (status, text) = check(&["rough.ngc"]);
    assert_eq!(status, Some(0), "{text}");
    assert!(text.starts_with("rough.ngc: 1 warning (material left on the design)\n"), "{text}");
    let (status, text) = check(&["rough.ngc", "--deny", "warnings"]);
    assert_eq!(status, Some(1), "{text}");
    assert!(text.starts_with("rough.ngc: 1 error (material left on the design)\n"), "{text}");
    // Within the tolerance: clean, exit 0.
    let (status, text) = check(&["slot.ngc"]);
    assert_eq!(status, Some(0), "{text}");
    assert!(text.starts_with("slot.ngc: no problems found\n"), "{text}");
}
