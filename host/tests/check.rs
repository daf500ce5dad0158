//! `ger check` as a user runs it: the JSON report against its documented
//! schema (`host/docs/check.schema.json`), exit statuses, and no finding on any
//! program meant to be clean.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `ger check ARGS FILE` in FILE's folder, with FILE's `.toml` beside it if there is one.
fn check(program: &Path, args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ger"));
    command.current_dir(program.parent().unwrap()).env("NO_COLOR", "1").arg("check").arg("--quiet").args(args);
    let config = program.with_extension("toml");
    if config.exists() {
        command.arg("--config").arg(config.file_name().unwrap());
    }
    command.arg(program.file_name().unwrap()).output().unwrap()
}

fn json(program: &str, args: &[&str]) -> (Value, Option<i32>) {
    let mut all = vec!["--format", "json"];
    all.extend_from_slice(args);
    let output = check(&root().join(program), &all);
    assert!(output.stderr.is_empty(), "{}", String::from_utf8_lossy(&output.stderr));
    (serde_json::from_slice(&output.stdout).expect("the report is JSON"), output.status.code())
}

fn schema() -> jsonschema::Validator {
    let text = std::fs::read_to_string(root().join("host/docs/check.schema.json")).unwrap();
    jsonschema::validator_for(&serde_json::from_str(&text).unwrap()).expect("the schema is a valid JSON Schema")
}

fn assert_valid(validator: &jsonschema::Validator, report: &Value) {
    let errors: Vec<String> =
        validator.iter_errors(report).map(|e| format!("{} at {}", e, e.instance_path())).collect();
    assert!(errors.is_empty(), "{errors:#?}\n{report:#}");
}

#[test]
fn the_json_report_has_its_documented_shape() {
    let validator = schema();

    // Findings in a subprogram called twice: each names its call.
    let (report, status) = json("tests/check/in_subprogram.ngc", &[]);
    assert_valid(&validator, &report);
    assert_eq!(status, Some(1));
    assert_eq!(report["errors"], 2);
    assert_eq!(report["warnings"], 0);
    let diagnostics = report["diagnostics"].as_array().unwrap();
    for (d, call_line) in diagnostics.iter().zip([5, 7]) {
        assert_eq!(d["rule"], "rapid-into-stock");
        assert_eq!((d["line"].as_u64(), d["column"].as_u64(), d["length"].as_u64()), (Some(11), Some(1), Some(7)));
        assert_eq!(d["calls"], serde_json::json!([{ "name": "O10", "line": call_line, "column": 1 }]));
    }
    assert_eq!(report["summary"]["problems"], serde_json::json!({ "rapid-into-stock": 2 }));
    assert_eq!(report["summary"]["units"], "mm");
    // The planned time: on grbl-default (no [machine.motion]), by tool, and by call.
    let planned = &report["summary"]["planned"];
    assert_eq!(planned["profile"]["preset"], "grbl-default");
    assert_eq!(planned["profile"]["configured"], false);
    assert_eq!(planned["profile"]["max_rate"], serde_json::json!([5000.0, 5000.0, 1000.0]));
    let total = planned["seconds"].as_f64().unwrap();
    assert_eq!(planned["tools"].as_array().unwrap().len(), 1);
    assert_eq!(planned["tools"][0]["seconds"].as_f64(), Some(total));
    let calls = planned["calls"].as_array().unwrap();
    assert_eq!(calls.len(), 2, "{calls:?}");
    for (call, line) in calls.iter().zip([5, 7]) {
        assert_eq!(
            (call["name"].as_str(), call["line"].as_u64(), call["column"].as_u64()),
            (Some("O10"), Some(line), Some(1))
        );
    }
    // The first call feeds 20 mm at 200 mm/min (6 s) and rapids 4 mm on Z;
    // the second is already at Y30: its rapids alone, well under a second.
    let (first, second) = (calls[0]["seconds"].as_f64().unwrap(), calls[1]["seconds"].as_f64().unwrap());
    assert!(first > 6.0 && first < 7.0 && second < 1.0 && first + second < total, "{first} {second} of {total}");

    // A clean program: no diagnostics, and the summary's figures (worked out
    // in tests/check/plunge_clean.ngc: 3 + 30 + 3 + 30 + sqrt(30^2 + 3^2) at F100).
    let (report, status) = json("tests/check/plunge_clean.ngc", &[]);
    assert_valid(&validator, &report);
    assert_eq!(status, Some(0));
    assert_eq!(report["diagnostics"], serde_json::json!([]));
    let cutting = report["summary"]["cutting_distance"].as_f64().unwrap();
    let expected = 4.0 + 30.0 + 3.0 + 30.0 + (900.0f64 + 9.0).sqrt();
    assert!((cutting - expected).abs() < 1e-9, "{cutting} vs {expected}");
    assert_eq!(report["summary"]["tools"][0]["number"], 1);
    assert_eq!(report["summary"]["codes"]["G01"], 5);

    // A problem the translation found has no rule; --deny warnings makes warnings errors.
    let (report, _) = json("tests/check/feed_zero.ngc", &[]);
    assert_valid(&validator, &report);
    assert_eq!(report["diagnostics"][0]["rule"], Value::Null);
    assert_eq!(report["diagnostics"][0]["column"], 9);
    let (report, status) = json("tests/check/plunge.ngc", &["--deny", "warnings"]);
    assert_valid(&validator, &report);
    assert_eq!(
        (status, report["errors"].as_u64(), report["diagnostics"][0]["severity"].as_str()),
        (Some(1), Some(1), Some("error"))
    );
    let (report, status) = json("tests/check/plunge.ngc", &[]);
    assert_eq!((status, report["warnings"].as_u64()), (Some(0), Some(1)));

    // A holder's collision, and the tool assembly as the table gives it.
    let (report, status) = json("tests/check/holder_collision.ngc", &[]);
    assert_valid(&validator, &report);
    assert_eq!((status, report["errors"].as_u64()), (Some(1), Some(3)));
    assert_eq!(
        (report["diagnostics"][0]["rule"].as_str(), report["diagnostics"][0]["line"].as_u64()),
        (Some("collision"), Some(26))
    );
    let tools = &report["summary"]["tools"];
    assert_eq!(tools[1]["number"], 1);
    assert_eq!((tools[1]["stick_out"].as_f64(), tools[1]["unchecked"].is_null()), (Some(22.0), true));
    assert_eq!(tools[1]["holder"], serde_json::json!([[30.0, 30.0, 40.0]]));
    assert_eq!(tools[0]["unchecked"], "holder not configured: only the shank is checked");
    let (report, _) = json("tests/check/fixture.ngc", &[]);
    assert_valid(&validator, &report);
    assert_eq!(
        (report["diagnostics"][0]["rule"].as_str(), report["diagnostics"][0]["line"].as_u64()),
        (Some("fixture"), Some(6))
    );

    // A job: each program's report, in order, and the job's counts; the
    // finishing program alone has a rapid into the stock, after its roughing none.
    let (report, status) = json("tests/check/job.ngc", &["job_roughing.nc"]);
    let programs = report["programs"].as_array().unwrap();
    assert_eq!(status, Some(0));
    assert_eq!(
        programs.iter().map(|p| p["file"].as_str().unwrap()).collect::<Vec<_>>(),
        ["job_roughing.nc", "job.ngc"]
    );
    for program in programs {
        assert_valid(&validator, program);
    }
    assert_eq!((report["errors"].as_u64(), report["warnings"].as_u64()), (Some(0), Some(0)));
    let (report, status) = json("tests/check/job_alone.ngc", &[]);
    assert_eq!((status, report["diagnostics"][0]["rule"].as_str()), (Some(1), Some("rapid-into-stock")));

    // Each tool says what it is and where it came from: the config file, a comment, the default.
    let (report, _) = json("tests/check/default_tool_clean.ngc", &[]);
    assert_valid(&validator, &report);
    let tool = &report["summary"]["tools"][0];
    assert_eq!((tool["kind"].as_str(), tool["diameter"].as_f64()), (Some("endmill"), Some(6.0)));
    assert_eq!(tool["source"], serde_json::json!({ "from": "comment", "line": 2 }));
    let (report, status) = json("tests/check/default_tool.ngc", &[]);
    assert_valid(&validator, &report);
    assert_eq!((status, report["diagnostics"][0]["rule"].as_str()), (Some(0), Some("default-tool")));
    assert_eq!(report["summary"]["tools"][0]["source"], serde_json::json!({ "from": "default" }));
    let (report, _) = json("tests/check/plunge.ngc", &[]);
    assert_eq!(report["summary"]["tools"][0]["source"], serde_json::json!({ "from": "config", "file": "plunge.toml" }));

    // The schema is not a formality: a report with a field renamed fails it.
    let mut broken = report.clone();
    let summary = broken["summary"].as_object_mut().unwrap();
    let time = summary.remove("run_time_seconds").unwrap();
    summary.insert("run_time".to_string(), time);
    assert!(!validator.is_valid(&broken));
}

#[test]
fn usage_mistakes_exit_with_2() {
    let program = root().join("tests/check/plunge.ngc");
    for args in [&["--allow", "rapids"][..], &["--format", "xml"], &["--deny", "errors"], &["--resolution", "0"]] {
        let output = check(&program, args);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
        assert!(!output.stderr.is_empty());
    }
}

/// Translation tests that move the tool through where a block of stock would
/// be (the stock being, by default, the box the program cuts with its top at
/// Z0): each is a real finding, kept as it is because the case tests something else.
const NOT_CLEAN: &[(&str, &str)] = &[
    ("tests/translate/offsets.ngc", "rapids to Z0 under a G55 whose Z is -0.5"),
    ("tests/translate/polar.ngc", "returns to Z0 with a rapid through the polar cut"),
    ("tests/lenient/home_and_machine_moves.ngc", "G53 rapids to machine Z-1 through the cut"),
    ("tests/lenient/canned_cycles.ngc", "drills with tool 1, a quarter-inch endmill"),
    ("tests/lenient/real_world_blocks.ngc", "plunges the endmill 0.25 in, a Haas drilling block"),
    ("tests/lenient/no_effect_spindle_tool.ngc", "loads tool 2, which its tool table does not have"),
    ("tests/lenient/tapping_and_other_planes.ngc", "taps and drills with tool 1, a quarter-inch endmill"),
];

/// Every example, and every case whose translation is clean, checks clean. A
/// case that never starts a spindle is a translation test (written without
/// M03): it is checked with `--allow spindle-off`, which `tests/check` covers.
#[test]
fn programs_meant_to_be_clean_have_no_findings() {
    let mut programs = Vec::new();
    collect(&root().join("host/examples"), &mut programs);
    collect(&root().join("tests"), &mut programs);
    programs.sort();
    let mut checked = 0;
    let mut failures = Vec::new();
    for program in programs {
        let relative = program.strip_prefix(root()).unwrap().to_string_lossy().to_string();
        let expected_err = std::fs::read_to_string(program.with_extension("err")).unwrap_or_default();
        if !expected_err.is_empty()
            || relative.starts_with("tests/differential")
            || relative.starts_with("tests/corpus")
        {
            continue;
        }
        let case_args = std::fs::read_to_string(program.with_extension("args")).unwrap_or_default();
        let mut args: Vec<String> = Vec::new();
        let words: Vec<&str> = case_args.split_whitespace().collect();
        for (i, word) in words.iter().enumerate() {
            match *word {
                "--lenient" => args.push(word.to_string()),
                "--units" | "--wizards" | "--stock-from" => args.extend([word.to_string(), words[i + 1].to_string()]),
                // A job's programs before this one (tests/check/job.ngc).
                more if more.ends_with(".nc") => args.push(more.to_string()),
                _ => {}
            }
        }
        if relative.starts_with("host/examples") {
            args.extend(["--wizards".to_string(), root().join("wizards").display().to_string()]);
        }
        let text = std::fs::read_to_string(&program).unwrap();
        if !starts_spindle(&text) {
            args.extend(["--allow".to_string(), "spindle-off".to_string()]);
        }
        // A case with no tool table is cut with the default tool, which is a
        // warning of its own (tests/check/default_tool.ngc): not what these test.
        let config = [program.with_extension("toml"), program.with_file_name("ger.toml")]
            .iter()
            .find_map(|path| std::fs::read_to_string(path).ok())
            .unwrap_or_default();
        if !config.contains("[[tools]]") {
            args.extend(["--allow".to_string(), "default-tool".to_string()]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let output = check(&program, &args);
        let stderr = String::from_utf8_lossy(&output.stderr).to_string();
        let excluded = NOT_CLEAN.iter().any(|(path, _)| *path == relative);
        match (excluded, stderr.is_empty() && output.status.success()) {
            (false, false) => failures.push(format!("{relative} {args:?}:\n{stderr}")),
            (true, true) => failures.push(format!("{relative} is listed as not clean, but checks clean: unlist it")),
            _ => checked += 1,
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked >= 40, "only {checked} programs checked");
}

fn starts_spindle(text: &str) -> bool {
    text.split(|c: char| !c.is_ascii_alphanumeric())
        .any(|word| matches!(word.to_ascii_uppercase().as_str(), "M3" | "M03" | "M4" | "M04"))
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            collect(&path, out);
        } else if path.extension().is_some_and(|e| e == "ngc") {
            out.push(path);
        }
    }
}
