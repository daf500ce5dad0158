//! `ger view`'s server as the page uses it (the contract is
//! `host/docs/view-api.md`): the real binary on a copy of a program in a
//! temporary folder, spoken to in raw HTTP/1.1 over TCP.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A running `ger view`, killed when dropped.
struct Server {
    child: Child,
    port: u16,
    dir: tempfile::TempDir,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `ger view FILE --port 0 --wizards WIZARDS` in `dir`, once it has said where it serves.
fn start(dir: tempfile::TempDir, file: &str, wizards: &Path) -> Server {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
        .current_dir(dir.path())
        .args(["view", file, "--port", "0", "--wizards"])
        .arg(wizards)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let port = line
        .strip_prefix("ger view: http://127.0.0.1:")
        .and_then(|rest| rest.strip_suffix("/\n"))
        .and_then(|port| port.parse().ok())
        .unwrap_or_else(|| panic!("not the address line: {line:?}"));
    Server { child, port, dir }
}

struct Answer {
    status: u16,
    head: String,
    body: Vec<u8>,
}

impl Answer {
    fn json(&self) -> Value {
        serde_json::from_slice(&self.body)
            .unwrap_or_else(|err| panic!("{err}: {} {}", self.head, String::from_utf8_lossy(&self.body)))
    }

    fn error(&self) -> String {
        self.json()["error"].as_str().expect("errors are {\"error\": message}").to_string()
    }
}

impl Server {
    /// Sends `head` (the request line and headers, without the blank line) and `body`; reads the answer.
    fn raw(&self, head: &str, body: &[u8]) -> Answer {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        let mut request = format!("{head}\r\nConnection: close\r\n\r\n").into_bytes();
        request.extend_from_slice(body);
        // The server may answer (413) before it has read all of a body, and close.
        let _ = stream.write_all(&request);
        let mut bytes = Vec::new();
        let _ = stream.read_to_end(&mut bytes);
        let split = bytes.windows(4).position(|w| w == b"\r\n\r\n").expect("an answer with a head");
        let head = String::from_utf8(bytes[..split].to_vec()).unwrap();
        let status = head.split(' ').nth(1).and_then(|s| s.parse().ok()).expect("a status");
        assert!(!head.to_ascii_lowercase().contains("transfer-encoding: chunked"), "{head}");
        Answer { status, head, body: bytes[split + 4..].to_vec() }
    }

    fn request(&self, method: &str, path: &str, body: &[u8]) -> Answer {
        let head =
            format!("{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nContent-Length: {}", self.port, body.len());
        self.raw(&head, body)
    }

    fn get(&self, path: &str) -> Answer {
        self.request("GET", path, b"")
    }

    fn post(&self, path: &str, body: &str) -> Answer {
        self.request("POST", path, body.as_bytes())
    }

    /// The snapshot once it is at least `version` and nothing newer is being made.
    fn state_at(&self, version: u64) -> Value {
        let started = Instant::now();
        loop {
            let answer = self.get("/api/state");
            assert_eq!(answer.status, 200);
            let state = answer.json();
            if state["version"].as_u64().unwrap() >= version && state["busy"] == false {
                return state;
            }
            // The first snapshot may build the example's wizards.
            assert!(started.elapsed() < Duration::from_secs(600), "no snapshot {version}: {state:#}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// The snapshot once `done` holds of it.
    fn state_when(&self, done: impl Fn(&Value) -> bool) -> Value {
        let started = Instant::now();
        loop {
            let state = self.state_at(1);
            if done(&state) {
                return state;
            }
            assert!(started.elapsed() < Duration::from_secs(10), "never came: {state:#}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    fn file(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }
}

/// A copy of `host/examples/`'s pocket program and its machine in a folder of its own.
fn pocket_folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for name in ["pocket.ngc", "ger.toml"] {
        std::fs::copy(root().join("host/examples").join(name), dir.path().join(name)).unwrap();
    }
    dir
}

fn pocket() -> Server {
    start(pocket_folder(), "pocket.ngc", &root().join("wizards"))
}

fn lines(state: &Value) -> Vec<String> {
    state["output"]["text"].as_str().unwrap().lines().map(str::to_string).collect()
}

fn f32s(bytes: &[u8]) -> Vec<f32> {
    bytes.chunks_exact(4).map(|c| f32::from_le_bytes(c.try_into().unwrap())).collect()
}

#[test]
fn the_pocket_example_translated_simulated_edited_and_saved() {
    let server = pocket();
    let state = server.state_at(1);
    let version = state["version"].as_u64().unwrap();
    assert_eq!(
        (state["file"].as_str(), state["saved"].as_bool(), state["conflict"].as_bool()),
        (Some("pocket.ngc"), Some(true), Some(false))
    );
    assert_eq!(state["source"], std::fs::read_to_string(server.file("pocket.ngc")).unwrap());

    // The output is `ger run`'s, line for line.
    let run = Command::new(env!("CARGO_BIN_EXE_ger"))
        .current_dir(server.dir.path())
        .args(["run", "pocket.ngc", "--wizards"])
        .arg(root().join("wizards"))
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let output = lines(&state);
    assert_eq!(output, String::from_utf8(run.stdout).unwrap().lines().collect::<Vec<_>>());
    assert!(state["diagnostics"].as_array().unwrap().is_empty(), "{:#}", state["diagnostics"]);

    // Each output line's source: the preamble none, N<line> its line, a wizard's lines the call.
    let sources: Vec<u64> =
        state["output"]["source_lines"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
    assert_eq!(sources.len(), output.len());
    assert_eq!(&sources[..4], [0, 0, 0, 0]);
    let pocket_call = 10;
    for (line, source) in output.iter().zip(&sources).skip(4) {
        let n: u64 = line[1..line.find(' ').unwrap()].parse().unwrap();
        assert!(n == *source || *source == pocket_call || *source == 16, "{line} from line {source}");
    }
    assert!(sources.iter().filter(|&&s| s == pocket_call).count() > 20, "the pocket is many moves");

    // The part: a 75 x 30 pocket 10 deep at X10 Y10, in a stock whose top is Z0.
    let part = &state["part"];
    let (nx, ny) = (part["nx"].as_u64().unwrap() as usize, part["ny"].as_u64().unwrap() as usize);
    assert_eq!(part["top"], 0.0);
    assert_eq!(part["units"], "mm");
    let heights = server.get(&format!("/api/heights?version={version}"));
    assert_eq!(heights.status, 200);
    assert!(heights.head.contains("application/octet-stream"), "{}", heights.head);
    assert_eq!(heights.body.len(), nx * ny * 4);
    let heights = f32s(&heights.body);
    let cell = |x: f64, y: f64| {
        let i = ((x - part["x0"].as_f64().unwrap()) / part["cell_x"].as_f64().unwrap()) as usize;
        let j = ((y - part["y0"].as_f64().unwrap()) / part["cell_y"].as_f64().unwrap()) as usize;
        heights[j * nx + i]
    };
    assert!((cell(47.5, 25.0) + 10.0).abs() < 0.05, "the pocket's floor: {}", cell(47.5, 25.0));
    assert!((cell(20.0, 35.0) + 10.0).abs() < 0.05, "the pocket's floor: {}", cell(20.0, 35.0));
    assert_eq!(cell(47.5, 42.0), 0.0, "beside the pocket: uncut");
    assert!(heights.iter().filter(|&&z| z < -1.0).count() > nx * ny / 10);

    // The toolpath: from machine zero, G00 Z5, G00 X10 Y10, G01 Z0 (lines 6 to 8).
    let path = server.get(&format!("/api/path?version={version}"));
    assert_eq!(path.status, 200);
    assert_eq!(path.body.len() as u64, state["path"]["pieces"].as_u64().unwrap() * 32);
    assert_eq!(state["path"]["decimated"], false);
    let piece = |k: usize| {
        let record = &path.body[k * 32..(k + 1) * 32];
        let floats = f32s(&record[..24]);
        let words: Vec<u32> = record[24..].chunks(4).map(|c| u32::from_le_bytes(c.try_into().unwrap())).collect();
        (floats, words[0] as usize, words[1])
    };
    let expected = [
        ([0.0, 0.0, 0.0, 0.0, 0.0, 5.0], 6, 0),
        ([0.0, 0.0, 5.0, 10.0, 10.0, 5.0], 7, 0),
        ([10.0, 10.0, 5.0, 10.0, 10.0, 0.0], 8, 1),
    ];
    for (k, (ends, line, kind)) in expected.into_iter().enumerate() {
        let (floats, output_line, got_kind) = piece(k);
        assert_eq!((floats.as_slice(), got_kind), (ends.as_slice(), kind), "piece {k}");
        assert_eq!(sources[output_line], line, "piece {k} is from {}", output[output_line]);
        assert!(output[output_line].starts_with(&format!("N{line} G0")), "{}", output[output_line]);
    }
    assert_eq!(state["path"]["min"], serde_json::json!([0.0, 0.0, -10.0]));

    // The planned run time is `ger check`'s; each line is reached in program order, the
    // first move (line 6) at once, the pocket (line 10) before the second tool (line 12).
    let check = Command::new(env!("CARGO_BIN_EXE_ger"))
        .current_dir(server.dir.path())
        .args(["check", "pocket.ngc", "--quiet", "--format", "json", "--wizards"])
        .arg(root().join("wizards"))
        .output()
        .unwrap();
    let report: serde_json::Value = serde_json::from_slice(&check.stdout).unwrap();
    let planned = report["summary"]["planned"]["seconds"].as_f64().unwrap();
    let run_time = &state["run_time"];
    assert_eq!(run_time["seconds"].as_f64(), Some((planned * 100.0).round() / 100.0));
    assert_eq!((run_time["preset"].as_str(), run_time["configured"].as_bool()), (Some("grbl-default"), Some(false)));
    let times: Vec<f64> = run_time["lines"].as_array().unwrap().iter().map(|t| t.as_f64().unwrap()).collect();
    assert_eq!(times.len(), 19, "{times:?}");
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    assert_eq!(&times[..6], [0.0; 6]);
    assert!(times[9] > 0.0 && times[10] - times[9] > 10.0 && times[11] < times[18], "{times:?}");
    assert_eq!(times[18], run_time["seconds"].as_f64().unwrap());

    // An edit: a shallower pocket, not saved.
    let text = state["source"].as_str().unwrap().replace("Pocket 75 30 10 3", "Pocket 75 30 4 2");
    let answer = server.post("/api/source", &text);
    assert_eq!(answer.status, 200);
    let edited_version = answer.json()["version"].as_u64().unwrap();
    assert!(edited_version > version);
    let edited = server.state_at(edited_version);
    assert_eq!((edited["source"].as_str(), edited["saved"].as_bool()), (Some(text.as_str()), Some(false)));
    let edited_output = edited["output"]["text"].as_str().unwrap();
    assert!(edited_output.contains("Z-4.000") && !edited_output.contains("Z-10.000"), "{edited_output}");
    assert_eq!(edited["path"]["min"][2], -4.0);
    // The old snapshot's data is gone.
    assert_eq!(server.get(&format!("/api/heights?version={version}")).status, 410);

    // Saved: the file has the text, and our own write is no conflict. It keeps its mode.
    #[cfg(unix)]
    let mode = {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(server.file("pocket.ngc"), std::fs::Permissions::from_mode(0o640)).unwrap();
        || std::fs::metadata(server.file("pocket.ngc")).unwrap().permissions().mode() & 0o7777
    };
    let answer = server.post("/api/save", &text);
    assert_eq!(answer.status, 200, "{}", answer.error());
    let saved_version = answer.json()["version"].as_u64().unwrap();
    assert_eq!(std::fs::read_to_string(server.file("pocket.ngc")).unwrap(), text);
    #[cfg(unix)]
    assert_eq!(mode(), 0o640);
    let saved = server.state_at(saved_version);
    assert_eq!((saved["saved"].as_bool(), saved["conflict"].as_bool()), (Some(true), Some(false)));
    std::thread::sleep(Duration::from_millis(700));
    let later = server.state_at(saved_version);
    assert_eq!((later["saved"].as_bool(), later["conflict"].as_bool()), (Some(true), Some(false)), "{later:#}");

    // Changed on disk by someone else: the page follows.
    let external = text.replace("Pocket 75 30 4 2", "Pocket 75 30 6 3");
    std::fs::write(server.file("pocket.ngc"), &external).unwrap();
    let followed = server.state_when(|s| s["source"] == external.as_str());
    assert_eq!((followed["saved"].as_bool(), followed["conflict"].as_bool()), (Some(true), Some(false)));
    assert!(followed["output"]["text"].as_str().unwrap().contains("Z-6.000"));

    // Changed on disk while the page has unsaved edits: a conflict, the page's text kept.
    let mine = external.replace("G00 Z5\nM05", "G00 Z6\nM05");
    server.post("/api/source", &mine);
    std::fs::write(server.file("pocket.ngc"), &text).unwrap();
    let conflict = server.state_when(|s| s["conflict"] == true);
    assert_eq!((conflict["source"].as_str(), conflict["saved"].as_bool()), (Some(mine.as_str()), Some(false)));
    // Reloading takes the file's text.
    let reloaded = server.post("/api/reload", "").json()["version"].as_u64().unwrap();
    let reloaded = server.state_at(reloaded);
    assert_eq!(reloaded["source"], text.as_str());
    assert_eq!((reloaded["saved"].as_bool(), reloaded["conflict"].as_bool()), (Some(true), Some(false)));

    // A bad line: its diagnostic at its line and column (G07 is the 8th byte of line 6).
    let bad = text.replace("G00 Z5\nG00 X10", "G00 Z5 G07\nG00 X10");
    let version = server.post("/api/source", &bad).json()["version"].as_u64().unwrap();
    let state = server.state_at(version);
    let diagnostics = state["diagnostics"].as_array().unwrap();
    assert_eq!(diagnostics.len(), 1, "{diagnostics:#?}");
    let d = &diagnostics[0];
    assert_eq!(d["severity"], "error");
    assert_eq!((d["line"].as_u64(), d["column"].as_u64()), (Some(6), Some(8)), "{d:#}");
    assert_eq!((d["end_line"].as_u64(), d["end_column"].as_u64()), (Some(6), Some(11)), "{d:#}");
    assert_eq!(d["check"], Value::Null);
}

/// A program with no wizards in a folder with a subfolder, a symlink out, and a file beside it.
fn simple() -> Server {
    let dir = tempfile::tempdir().unwrap();
    let program = "G21 G90\nM03 S1000\nG00 Z5\nG00 X0 Y0\nG01 Z-1 F100\nG01 X10\nG00 Z5\nM30\n";
    std::fs::write(dir.path().join("a.ngc"), program).unwrap();
    std::fs::write(
        dir.path().join("ger.toml"),
        "units = \"mm\"\n[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 2.0\n",
    )
    .unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::fs::write(dir.path().join("sub/b.nc"), "G21\n(moves nothing)\nM30\n").unwrap();
    std::fs::write(dir.path().join("notes.txt"), "not G-code").unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink("/etc/hostname", dir.path().join("out.ngc")).unwrap();
    start(dir, "a.ngc", &root().join("wizards"))
}

#[test]
fn bad_requests_get_their_4xx_and_the_server_carries_on() {
    let server = simple();
    let first = server.state_at(1)["version"].as_u64().unwrap();
    let port = server.port;
    let expect = |answer: Answer, status: u16, words: &str| {
        assert_eq!(answer.status, status, "{}", String::from_utf8_lossy(&answer.body));
        let error = answer.error();
        assert!(error.contains(words), "{status}: {error:?} does not say {words:?}");
    };

    expect(server.get("/nope"), 404, "no such");
    expect(server.get("/api/state/x"), 404, "no such");
    expect(server.post("/api/state", ""), 405, "POST");
    expect(server.get("/api/source"), 405, "GET");
    expect(server.post("/", ""), 405, "POST");

    // Over 64 MiB.
    let big = vec![b'('; (64 << 20) + 1];
    expect(server.request("POST", "/api/source", &big), 413, "64 MiB");

    // DNS rebinding and other sites' pages.
    expect(server.raw("GET /api/state HTTP/1.1\r\nHost: evil.example:80", b""), 403, "Host");
    expect(server.raw(&format!("GET /api/state HTTP/1.1\r\nHost: 127.0.0.1:{}", port + 1), b""), 403, "Host");
    expect(server.raw("GET /api/state HTTP/1.1", b""), 403, "Host");
    // Two Host headers: which one a proxy on the way read cannot be known.
    let twice = format!("GET /api/state HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nHost: evil.example");
    expect(server.raw(&twice, b""), 400, "one Host");
    // An absolute-form target names the host that counts, whatever the Host header says.
    let absolute = |host: &str| format!("GET http://{host}/api/state HTTP/1.1\r\nHost: 127.0.0.1:{port}");
    expect(server.raw(&absolute("evil.example"), b""), 403, "evil.example");
    expect(server.raw(&absolute(&format!("127.0.0.1:{}", port + 1)), b""), 403, "not 127.0.0.1");
    assert_eq!(server.raw(&absolute(&format!("localhost:{port}")), b"").status, 200);
    let from = |origin: &str| {
        let head =
            format!("POST /api/source HTTP/1.1\r\nHost: localhost:{port}\r\nOrigin: {origin}\r\nContent-Length: 6\r\n");
        server.raw(head.trim_end(), b"G00 X1")
    };
    expect(from("http://evil.example"), 403, "another site");
    expect(from(&format!("http://127.0.0.1:{port}")), 403, "another site");
    assert_eq!(from(&format!("http://localhost:{port}")).status, 200);

    // Opening outside the folder.
    let open = |path: &str| server.post("/api/open", &serde_json::json!({ "path": path }).to_string());
    expect(open("../a.ngc"), 403, "outside");
    expect(open("sub/../../a.ngc"), 403, "outside");
    expect(open("/etc/hostname"), 403, "outside");
    #[cfg(unix)]
    expect(open("out.ngc"), 403, "outside");
    expect(open("missing.ngc"), 404, "no file");
    expect(open("sub"), 404, "no file");
    expect(server.post("/api/open", "sub/b.nc"), 400, "path");
    expect(server.post("/api/open", "{\"file\": \"sub/b.nc\"}"), 400, "path");
    expect(server.request("POST", "/api/source", b"G00 X\xff"), 400, "UTF-8");

    // Versions.
    let version = server.post("/api/source", "G21\nG00 X2\nM30\n").json()["version"].as_u64().unwrap();
    let state = server.state_at(version);
    let now = state["version"].as_u64().unwrap();
    expect(server.get(&format!("/api/path?version={first}")), 410, "replaced");
    expect(server.get("/api/path"), 400, "version");
    expect(server.get("/api/heights?version=x"), 400, "version");
    expect(server.get(&format!("/api/heights?version={}", now + 5)), 400, "no snapshot");

    // Not HTTP/1.1; headers over 64 KiB.
    expect(server.raw(&format!("GET /api/state HTTP/1.0\r\nHost: 127.0.0.1:{port}"), b""), 400, "HTTP/1.1");
    let long = format!("GET /api/state HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nX-Long: {}", "a".repeat(70 << 10));
    assert_eq!(server.raw(&long, b"").status, 431);

    // Still serving.
    assert_eq!(server.get("/api/state").status, 200);
    let page = server.get("/");
    assert_eq!(page.status, 200);
    assert!(page.head.contains("text/html"), "{}", page.head);
    assert_eq!(server.get("/app.js").status, 200);
    assert_eq!(server.get("/style.css").status, 200);

    // The folder's G-code files, and opening one of them.
    let files = server.get("/api/files").json();
    assert_eq!(files["files"], serde_json::json!(["a.ngc", "sub/b.nc"]));
    let answer = open("sub/b.nc");
    assert_eq!(answer.status, 200);
    let opened = server.state_at(answer.json()["version"].as_u64().unwrap());
    assert_eq!(
        (opened["file"].as_str(), opened["source"].as_str()),
        (Some("sub/b.nc"), Some("G21\n(moves nothing)\nM30\n"))
    );
    // No move: no stock to know, no part.
    assert_eq!(opened["part"], Value::Null);
}

#[test]
fn events_tell_when_a_snapshot_is_made() {
    let server = simple();
    server.state_at(1);
    let mut stream = TcpStream::connect(("127.0.0.1", server.port)).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    write!(stream, "GET /api/events HTTP/1.1\r\nHost: 127.0.0.1:{}\r\n\r\n", server.port).unwrap();
    let mut seen = String::new();
    let mut read_until = |wanted: &str| {
        let mut buffer = [0u8; 4096];
        while !seen.contains(wanted) {
            let n = stream.read(&mut buffer).unwrap();
            assert!(n > 0, "the stream ended: {seen}");
            seen.push_str(&String::from_utf8_lossy(&buffer[..n]));
        }
    };
    read_until("event: snapshot\ndata: {\"version\":1}");
    let version = server.post("/api/source", "G21\nG00 X3\nM30\n").json()["version"].as_u64().unwrap();
    read_until(&format!("event: snapshot\ndata: {{\"version\":{version}}}"));
}

#[test]
fn a_wizard_changed_on_disk_is_used_at_once() {
    // The example's wizards, built if need be (by `ger run`, as any test that runs the example does)...
    let run = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["run", "--wizards"])
        .arg(root().join("wizards"))
        .arg(root().join("host/examples/pocket.ngc"))
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    // ...and copied to a folder of their own.
    let dir = pocket_folder();
    let wizards = dir.path().join("wizards");
    std::fs::create_dir(&wizards).unwrap();
    for name in ["pocket.wasm", "boltcircle.wasm"] {
        std::fs::copy(root().join("wizards").join(name), wizards.join(name)).unwrap();
    }
    let server = start(dir, "pocket.ngc", &wizards);
    assert_eq!(server.state_at(1)["diagnostics"], serde_json::json!([]));

    // Pocket gone: its call is an error.
    let pocket = std::fs::read(wizards.join("pocket.wasm")).unwrap();
    std::fs::remove_file(wizards.join("pocket.wasm")).unwrap();
    let missing = server.state_when(|s| !s["diagnostics"].as_array().unwrap().is_empty());
    let d = &missing["diagnostics"][0];
    assert_eq!((d["line"].as_u64(), d["severity"].as_str()), (Some(10), Some("error")), "{d:#}");
    assert!(d["message"].as_str().unwrap().contains("Pocket"), "{d:#}");

    // Back: the call works again.
    std::fs::write(wizards.join("pocket.wasm"), pocket).unwrap();
    server.state_when(|s| s["diagnostics"] == serde_json::json!([]));
}

#[test]
fn a_connection_that_never_finishes_its_head_is_closed() {
    let server = simple();
    server.state_at(1);
    let mut stream = TcpStream::connect(("127.0.0.1", server.port)).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    write!(stream, "GET /api/state HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nX-Slow: a", server.port).unwrap();
    let started = Instant::now();
    // The server closes it without an answer (a read of 0), well before our own minute is up.
    let mut bytes = Vec::new();
    let read = stream.read_to_end(&mut bytes);
    assert!(read.is_ok(), "not closed by the server: {read:?} after {:?}", started.elapsed());
    assert!(started.elapsed() >= Duration::from_secs(4), "closed at once, not after its 5 s: {:?}", started.elapsed());
    // And it still serves others.
    assert_eq!(server.get("/api/state").status, 200);
}

#[test]
fn the_snapshot_gives_the_fixtures_in_machine_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("a.ngc"),
        "G21 G90\nM03 S1000\nG00 Z5\nG00 X0 Y0\nG01 Z-1 F100\nG01 X10\nG00 Z5\nM30\n",
    )
    .unwrap();
    // G54 is 100, 50, -20 from machine zero: the jaw, in program coordinates, moves by it; the bolt does not.
    let toml = "units = \"mm\"\n[offsets]\nG54 = [100, 50, -20]\n[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 2.0\n\
                [[fixtures]]\nname = \"jaw\"\nmin = [-10, 0, -5]\nmax = [-5, 20, 3]\n\
                [[fixtures]]\nname = \"bolt\"\ncentre = [30, 40, 0]\ndiameter = 8\nheight = 6\ncoordinates = \"machine\"\n";
    std::fs::write(dir.path().join("ger.toml"), toml).unwrap();
    let server = start(dir, "a.ngc", &root().join("wizards"));
    let state = server.state_when(|s| s["busy"] == false && !s["part"].is_null());
    assert_eq!(
        state["fixtures"],
        serde_json::json!([
            { "name": "jaw", "shape": "box", "min": [90.0, 50.0, -25.0], "max": [95.0, 70.0, -17.0] },
            { "name": "bolt", "shape": "cylinder", "min": [26.0, 36.0, 0.0], "max": [34.0, 44.0, 6.0] },
        ]),
        "{state:#}"
    );
}

#[test]
fn a_job_is_viewed_on_the_part_it_leaves_with_its_design_as_a_layer() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let config = "units = \"mm\"\n[stock]\nsize = [100, 50, 20]\norigin = [0, 0, 20]\n\
                  [[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 10\nflute_length = 20\n";
    // The slot 5 deep along Y25; roughed 4 deep, then finished with a rapid down into the roughed
    // slot (line 4) and 0.3 mm too deep from X50 to X70.
    let slot = "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG01 Z-5 F500\nX110\nG00 Z5\nM30\n";
    let rough = "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG01 Z-4 F500\nX110\nG00 Z5\nM30\n";
    let finish =
        "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG00 Z-3\nG01 Z-5 F500\nX110\nG00 X50 Z1\nG01 Z-5.3\nX70\nG00 Z5\nM30\n";
    for (name, text) in [("ger.toml", config), ("slot.ngc", slot), ("rough.ngc", rough), ("finish.ngc", finish)] {
        std::fs::write(path.join(name), text).unwrap();
    }
    let render = Command::new(env!("CARGO_BIN_EXE_ger"))
        .current_dir(path)
        .args(["render", "slot.ngc", "-o", "slot.stl", "--resolution", "0.5", "-q"])
        .status()
        .unwrap();
    assert!(render.success());
    let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
        .current_dir(path)
        .args(["view", "rough.ngc", "finish.ngc", "--design", "slot.stl", "--resolution", "0.5", "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let port = line.trim().rsplit(':').next().unwrap().trim_end_matches('/').parse().unwrap();
    let server = Server { child, port, dir };

    // Viewing the roughing: the part is the job's, gouged 0.3 mm over a stadium 20 x 10 with round ends.
    let state = server.state_when(|s| !s["design"].is_null());
    assert_eq!(state["job"], serde_json::json!(["rough.ngc", "finish.ngc"]));
    let design = &state["design"];
    assert_eq!(design["file"], "slot.stl");
    assert!((design["gouge"]["worst"].as_f64().unwrap() - 0.3).abs() < 1e-5, "{design:#}");
    assert_eq!(design["left"]["area"], 0.0, "{design:#}");
    let (nx, ny) = (state["part"]["nx"].as_u64().unwrap() as usize, state["part"]["ny"].as_u64().unwrap() as usize);
    let verdicts = server.get(&format!("/api/verdicts?version={}", state["version"])).body;
    assert_eq!(verdicts.len(), nx * ny);
    // 2 is gouged: the stadium's 279 mm² in cells of 0.25 mm².
    let gouged = verdicts.iter().filter(|v| **v == 2).count() as f64 * 0.25;
    let area = 200.0 + 25.0 * std::f64::consts::PI;
    assert!((gouged - area).abs() / area < 0.03, "{gouged} mm² gouged");

    // Viewing the finishing program: checked on what the roughing left, its rapid is into air.
    let answer = server.post("/api/open", r#"{"path": "finish.ngc"}"#);
    assert_eq!(answer.status, 200);
    let state = server.state_when(|s| s["file"] == "finish.ngc" && !s["design"].is_null());
    let checks: Vec<&Value> = state["diagnostics"].as_array().unwrap().iter().map(|d| &d["check"]).collect();
    assert!(checks.is_empty(), "{:#}", state["diagnostics"]);
    assert!((state["design"]["gouge"]["worst"].as_f64().unwrap() - 0.3).abs() < 1e-5);
}
