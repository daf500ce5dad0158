//! A CAMotics project (`NAME.camotics`, JSON): its tools by number, each in
//! its own unit, and its workpiece: a box, or "automatic" (the box of the
//! cut plus a margin in percent). CAMotics keeps the workpiece's bounds in
//! millimetres whatever the project's unit; so are the tools here once read.

use std::collections::BTreeMap;

use serde::Deserialize;

use crate::config::{Tool, ToolKind};

/// What ger takes from a project: lengths in millimetres.
#[derive(Clone, Debug, PartialEq)]
pub struct Project {
    pub tools: Vec<Tool>,
    pub workpiece: Option<Workpiece>,
    /// The programs it simulates, as the project names them.
    pub files: Vec<String>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Workpiece {
    /// In program coordinates.
    Bounds {
        min: [f64; 3],
        max: [f64; 3],
    },
    Automatic {
        margin_percent: f64,
    },
}

#[derive(Deserialize)]
struct File {
    /// "metric" or "imperial": the unit of a tool that does not give its own.
    units: Option<String>,
    #[serde(default)]
    tools: BTreeMap<String, FileTool>,
    workpiece: Option<FileWorkpiece>,
    #[serde(default)]
    files: Vec<String>,
}

#[derive(Deserialize)]
struct FileTool {
    units: Option<String>,
    shape: Option<String>,
    length: Option<f64>,
    diameter: Option<f64>,
    snub_diameter: Option<f64>,
}

#[derive(Deserialize)]
struct FileWorkpiece {
    #[serde(default)]
    automatic: bool,
    #[serde(default)]
    margin: f64,
    bounds: Option<FileBounds>,
}

#[derive(Deserialize)]
struct FileBounds {
    min: [f64; 3],
    max: [f64; 3],
}

/// A project ger cannot use, and where in it the mistake is.
#[derive(Debug, thiserror::Error)]
pub enum ProjectError {
    /// Not JSON, or not the shape of a project (serde_json's message says the line and column).
    #[error("{0}")]
    Json(serde_json::Error),
    #[error("units must be \"metric\" or \"imperial\", not \"{0}\"")]
    Units(String),
    #[error("tool \"{0}\": a tool's key must be its number")]
    ToolKey(String),
    #[error("tool {number}: {problem}")]
    Tool { number: u32, problem: Box<ProjectError> },
    #[error("diameter and length must be above zero")]
    Size,
    #[error("unknown shape \"{0}\"")]
    Shape(String),
    #[error("workpiece: the margin must be zero or more")]
    Margin,
    #[error("workpiece: its bounds must have max above min on every axis")]
    Bounds,
}

/// Millimetres per unit of a project's "units".
fn millimetres(units: Option<&str>) -> Result<f64, ProjectError> {
    match units.unwrap_or("metric") {
        "metric" => Ok(1.0),
        "imperial" => Ok(25.4),
        other => Err(ProjectError::Units(other.to_string())),
    }
}

/// Reads a project's text; a mistake is reported with its line and column, or the tool it is in.
pub fn parse(text: &str) -> Result<Project, ProjectError> {
    let file: File = serde_json::from_str(text).map_err(ProjectError::Json)?;
    let project_scale = millimetres(file.units.as_deref())?;
    let mut tools = Vec::new();
    for (key, entry) in &file.tools {
        let number: u32 = key.parse().map_err(|_| ProjectError::ToolKey(key.clone()))?;
        let fail = |problem| ProjectError::Tool { number, problem: Box::new(problem) };
        let scale = match &entry.units {
            Some(units) => millimetres(Some(units)).map_err(fail)?,
            None => project_scale,
        };
        // CAMotics' own defaults: 2 x 10 mm, or 1/8 x 1 in.
        let imperial = scale != 1.0;
        let diameter = entry.diameter.map_or(if imperial { 3.175 } else { 2.0 }, |d| d * scale);
        let length = entry.length.map_or(if imperial { 25.4 } else { 10.0 }, |l| l * scale);
        if !(diameter > 0.0 && diameter.is_finite() && length > 0.0 && length.is_finite()) {
            return Err(fail(ProjectError::Size));
        }
        let radius = diameter / 2.0;
        let (kind, tip_angle) = match entry.shape.as_deref().unwrap_or("cylindrical") {
            "cylindrical" => (ToolKind::Endmill, None),
            // A spheroid's end is round like a ball's, if not as deep.
            "ballnose" | "spheroid" => (ToolKind::Ballmill, None),
            // A cone `length` high with `diameter` across its top.
            "conical" => (ToolKind::Drill, Some(2.0 * radius.atan2(length).to_degrees())),
            // A cone cut off at `snub_diameter`: taken to its point, with the same sides.
            "snubnose" => {
                let snub = entry.snub_diameter.map_or(0.0, |d| d * scale).clamp(0.0, diameter);
                (ToolKind::Drill, Some(2.0 * (radius - snub / 2.0).atan2(length).to_degrees()))
            }
            other => return Err(fail(ProjectError::Shape(other.to_string()))),
        };
        let tip_angle = tip_angle.filter(|a| *a > 0.0);
        let flute_length = Some(length);
        tools.push(Tool { flute_length, tip_angle, ..Tool::new(number, kind, diameter) });
    }
    let workpiece = match file.workpiece {
        Some(w) if w.automatic => {
            if !(w.margin >= 0.0 && w.margin.is_finite()) {
                return Err(ProjectError::Margin);
            }
            Some(Workpiece::Automatic { margin_percent: w.margin })
        }
        Some(FileWorkpiece { bounds: Some(FileBounds { min, max }), .. }) => {
            if !(0..3).all(|i| min[i].is_finite() && max[i].is_finite() && max[i] > min[i]) {
                return Err(ProjectError::Bounds);
            }
            Some(Workpiece::Bounds { min, max })
        }
        _ => None,
    };
    Ok(Project { tools, workpiece, files: file.files })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cameo_bear_and_tiger() {
        // The projects of CAMotics' examples, as they ship.
        let cameo = parse(
            r#"{ "units": "metric", "resolution-mode": "high", "resolution": 0.365095,
                 "tools": { "1": { "units": "metric", "shape": "ballnose", "length": 10, "diameter": 2, "description": "" } },
                 "workpiece": { "automatic": false, "margin": 5,
                                "bounds": { "min": [-83.6, -104.153, -7], "max": [83.6, 103.747, 0] } },
                 "files": ["cameo.nc"] }"#,
        )
        .unwrap();
        assert_eq!(cameo.tools, [Tool { flute_length: Some(10.0), ..Tool::new(1, ToolKind::Ballmill, 2.0) }]);
        assert_eq!(
            cameo.workpiece,
            Some(Workpiece::Bounds { min: [-83.6, -104.153, -7.0], max: [83.6, 103.747, 0.0] })
        );
        assert_eq!(cameo.files, ["cameo.nc"]);

        // An imperial tool in a metric project: 1/8 in.
        let bear = parse(
            r#"{ "units": "metric",
                 "tools": { "1": { "units": "imperial", "shape": "ballnose", "length": 1, "diameter": 0.125 } },
                 "workpiece": { "automatic": false, "margin": 0, "bounds": { "min": [0, 0, -20], "max": [80, 80, 0] } } }"#,
        )
        .unwrap();
        assert_eq!((bear.tools[0].diameter, bear.tools[0].flute_length), (3.175, Some(25.4)));

        let tiger = parse(
            r#"{ "tools": { "1": { "units": "metric", "shape": "cylindrical", "length": 20, "diameter": 2.5 } },
                 "workpiece": { "automatic": false, "margin": 0, "bounds": { "min": [-2, -1, -32], "max": [92, 89, 0] } } }"#,
        )
        .unwrap();
        assert_eq!(tiger.tools[0].kind, ToolKind::Endmill);
        assert_eq!(tiger.workpiece, Some(Workpiece::Bounds { min: [-2.0, -1.0, -32.0], max: [92.0, 89.0, 0.0] }));
    }

    #[test]
    fn cones_get_the_angle_of_their_height_and_diameter() {
        // wave.camotics' tool 1: 12.5 mm across 15.088835 mm up, tan(22.5°) = 6.25 / 15.088835.
        let wave =
            parse(r#"{ "tools": { "1": { "shape": "conical", "length": 15.088835, "diameter": 12.5 } } }"#).unwrap();
        let angle = wave.tools[0].tip_angle.unwrap();
        assert!((angle - 45.0).abs() < 1e-4, "{angle}");
        // slant_test's snub nose: 4 mm across, 2 mm flat, 5.5 mm up: sides at atan(1 / 5.5) from the axis.
        let snub =
            parse(r#"{ "tools": { "1": { "shape": "snubnose", "length": 5.5, "diameter": 4, "snub_diameter": 2 } } }"#)
                .unwrap();
        let expected = 2.0 * (1.0f64 / 5.5).atan().to_degrees();
        assert!((snub.tools[0].tip_angle.unwrap() - expected).abs() < 1e-9);
    }

    #[test]
    fn an_automatic_workpiece_is_a_margin_in_percent() {
        let project = parse(
            r#"{ "workpiece": { "automatic": true, "margin": 5, "bounds": { "min": [0,0,0], "max": [1,1,1] } } }"#,
        )
        .unwrap();
        assert_eq!(project.workpiece, Some(Workpiece::Automatic { margin_percent: 5.0 }));
        assert_eq!(parse("{}").unwrap(), Project { tools: Vec::new(), workpiece: None, files: Vec::new() });
    }

    #[test]
    fn mistakes_say_where() {
        for (text, words) in [
            ("{ \"tools\": { \"1\": { \"diameter\": 2 } ", "line 1 column"),
            (r#"{ "tools": { "one": { "diameter": 2 } } }"#, "tool \"one\""),
            (r#"{ "tools": { "3": { "diameter": -2 } } }"#, "tool 3: diameter"),
            (r#"{ "tools": { "3": { "shape": "star" } } }"#, "tool 3: unknown shape \"star\""),
            (r#"{ "tools": { "3": { "units": "cubits" } } }"#, "tool 3: units"),
            (r#"{ "workpiece": { "bounds": { "min": [0, 0, 0], "max": [1, 0, 1] } } }"#, "max above min"),
            (r#"{ "tools": [1, 2] }"#, "line 1"),
        ] {
            let err = parse(text).unwrap_err().to_string();
            assert!(err.contains(words), "{text}: {err}");
        }
    }
}
