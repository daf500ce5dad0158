//! `ger lsp` as an editor speaks to it: the real binary over standard input
//! and output, with the protocol's own framing (Content-Length headers),
//! on a program in a temporary folder. Every range and text expected is
//! worked out by hand from the program below.

mod support;

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

/// How long a test waits for an answer: only a hang should take this long.
/// A debug build on a busy 2-core machine, compiling a wizard with a cold
/// compile cache while the other tests run Neovim and npm, once took over 60 s.
const PATIENCE: Duration = Duration::from_secs(180);

/// A mm machine with a 6 mm endmill as tool 1: nothing for the checks to say
/// about the program once its M02 is M30.
const CONFIG: &str = "units = \"mm\"\n[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6.0\n";

/// Line 8 (0-based 7) has the error, after a comment with a two-byte `Ø`:
/// `M02` starts at byte 11 of the line but at UTF-16 column 10.
const PROGRAM: &str = "\
G21 G90
M06 T1
M03 S10000
G00 X10 Y5 Z2
G01 Z-1 F100
G01 X20
M98 P100
(Ø6 mill) M02
O100
G91 G01 X5
G90
M99
";

/// A running `ger lsp`, whose messages a thread reads into a channel.
struct Server {
    child: Child,
    input: ChildStdin,
    messages: Receiver<Value>,
    next_id: i64,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Reads one framed message: headers to a blank line, then Content-Length bytes.
fn read_message(reader: &mut impl BufRead) -> Option<Value> {
    let mut length = None;
    loop {
        let mut header = String::new();
        if reader.read_line(&mut header).ok()? == 0 {
            return None;
        }
        let header = header.trim_end();
        if header.is_empty() {
            break;
        }
        if let Some(value) = header.strip_prefix("Content-Length: ") {
            length = Some(value.parse::<usize>().expect("a length"));
        }
    }
    let mut body = vec![0; length.expect("a Content-Length header")];
    reader.read_exact(&mut body).ok()?;
    Some(serde_json::from_slice(&body).expect("a JSON body"))
}

impl Server {
    fn start(dir: &Path) -> Server {
        Server::start_with(dir, &[])
    }

    /// `ger lsp --stdio` with more arguments.
    fn start_with(dir: &Path, args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
            .current_dir(dir)
            .args(["lsp", "--stdio"])
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap();
        let input = child.stdin.take().unwrap();
        let mut output = BufReader::new(child.stdout.take().unwrap());
        let (sender, messages) = mpsc::channel();
        std::thread::spawn(move || {
            while let Some(message) = read_message(&mut output) {
                if sender.send(message).is_err() {
                    break;
                }
            }
        });
        Server { child, input, messages, next_id: 1 }
    }

    fn send(&mut self, message: Value) {
        let body = message.to_string();
        write!(self.input, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
        self.input.flush().unwrap();
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// Sends a request and waits for its answer (passing over notifications).
    fn request(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        let answer = self.wait(|m| m["id"] == json!(id));
        assert!(answer.get("error").is_none(), "{method}: {answer}");
        answer["result"].clone()
    }

    /// The next message `wanted` picks, within [`PATIENCE`].
    fn wait(&mut self, wanted: impl Fn(&Value) -> bool) -> Value {
        let deadline = Instant::now() + PATIENCE;
        loop {
            match self.messages.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
                Ok(message) if wanted(&message) => return message,
                Ok(_) => {}
                Err(RecvTimeoutError::Timeout) => panic!("no such message within {PATIENCE:?}"),
                Err(RecvTimeoutError::Disconnected) => panic!("ger lsp ended"),
            }
        }
    }

    /// The hover at `(line, character)` once it says `wanted`, within [`PATIENCE`].
    fn hover_until(&mut self, uri: &str, (line, character): (u32, u32), wanted: &str) -> String {
        let deadline = Instant::now() + PATIENCE;
        loop {
            let text = hover_text(&self.request("textDocument/hover", at(uri, line, character)));
            if text.contains(wanted) {
                return text;
            }
            assert!(Instant::now() < deadline, "no hover saying {wanted:?} within {PATIENCE:?}: {text}");
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// The diagnostics published for version `version` of the document.
    fn diagnostics(&mut self, version: i64) -> Vec<Value> {
        let message =
            self.wait(|m| m["method"] == "textDocument/publishDiagnostics" && m["params"]["version"] == json!(version));
        message["params"]["diagnostics"].as_array().unwrap().clone()
    }
}

fn range(start: (u32, u32), end: (u32, u32)) -> Value {
    json!({"start": {"line": start.0, "character": start.1}, "end": {"line": end.0, "character": end.1}})
}

fn at(uri: &str, line: u32, character: u32) -> Value {
    json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}})
}

fn hover_text(hover: &Value) -> String {
    hover["contents"]["value"].as_str().unwrap_or_else(|| panic!("no hover text: {hover}")).to_string()
}

#[test]
fn an_editor_session_over_stdio() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("ger.toml"), CONFIG).unwrap();
    let file = dir.path().join("part.nc");
    std::fs::write(&file, PROGRAM).unwrap();
    let uri = format!("file://{}", file.display());
    let mut server = Server::start(dir.path());

    let initialized = server.request("initialize", json!({"processId": null, "rootUri": null, "capabilities": {}}));
    let capabilities = &initialized["capabilities"];
    // 2: incremental text sync.
    assert_eq!(capabilities["textDocumentSync"]["change"], 2, "{capabilities}");
    for provider in ["hoverProvider", "definitionProvider", "documentSymbolProvider", "codeActionProvider"] {
        assert!(capabilities.get(provider).is_some(), "{provider}: {capabilities}");
    }
    server.notify("initialized", json!({}));
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "gcode", "version": 1, "text": PROGRAM}}),
    );

    // The one diagnostic: M02, refused in the strict dialect.
    let diagnostics = server.diagnostics(1);
    assert_eq!(diagnostics.len(), 1, "{diagnostics:#?}");
    let m02 = &diagnostics[0];
    assert_eq!(m02["range"], range((7, 10), (7, 13)));
    assert_eq!(m02["severity"], 1);
    let message = m02["message"].as_str().unwrap();
    assert!(message.starts_with("M02 is not accepted"), "{message}");
    assert!(message.contains("help: write M30 to end the program"), "{message}");

    // Its fix: M30 in its place.
    let actions = server.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": uri}, "range": m02["range"], "context": {"diagnostics": [m02]}}),
    );
    let edit = &actions[0]["edit"]["changes"][&uri][0];
    assert_eq!(edit["range"], range((7, 10), (7, 13)));
    assert_eq!(edit["newText"], "M30");
    assert_eq!(actions[0]["kind"], "quickfix");
    // Or, as the help says, the lenient dialect: first in ger.toml.
    let config_uri = format!("file://{}", dir.path().join("ger.toml").display());
    let edit = &actions[1]["edit"]["changes"][&config_uri][0];
    assert_eq!(edit["range"], range((0, 0), (0, 0)));
    assert_eq!(edit["newText"], "dialect = \"lenient\"\n");
    assert_eq!(actions.as_array().unwrap().len(), 2);

    // An incremental edit: "02" becomes "30". Nothing is left to say.
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 2},
               "contentChanges": [{"range": range((7, 11), (7, 13)), "text": "30"}]}),
    );
    assert_eq!(server.diagnostics(2), Vec::<Value>::new());

    // A code: the README's row for G01.
    let hover = server.request("textDocument/hover", at(&uri, 4, 1));
    let text = hover_text(&hover);
    assert!(text.contains("a feed move; a feed must be in force"), "{text}");
    assert_eq!(hover["range"], range((4, 0), (4, 3)));

    // A line: line 6 (0-based 5) ends at X20 Y5 Z-1, mm being the machine's unit.
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 5, 7)));
    assert!(text.contains("After line 6: **X20.000 Y5.000 Z-1.000** mm"), "{text}");
    // The call: O100 moves 5 on in G91, so X25.
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 6, 8)));
    assert!(text.contains("After line 7: **X25.000 Y5.000 Z-1.000** mm"), "{text}");
    assert!(text.contains("The planned run reaches line 7 at"), "{text}");
    // A line of O100 runs when it is called: its time is the call's, not its own.
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 9, 9)));
    assert!(text.contains("After line 10: **X25.000 Y5.000 Z-1.000** mm"), "{text}");
    assert!(!text.contains("planned run"), "{text}");
    // An axis word: its value, and its machine coordinate after the line.
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 3, 4)));
    assert!(text.contains("**X10**: 10.000 mm"), "{text}");
    assert!(text.contains("Machine **X10.000** mm after this line (absolute, G90)"), "{text}");

    // M98 P100 leads to O100, at line 9 (0-based 8).
    let definition = server.request("textDocument/definition", at(&uri, 6, 5));
    assert_eq!(definition["uri"], uri);
    assert_eq!(definition["range"], range((8, 0), (8, 4)));

    // O100's references: its definition and the one call, M98 P100 (from M98 to P100).
    let mut references = at(&uri, 8, 2);
    references["context"] = json!({"includeDeclaration": true});
    let references = server.request("textDocument/references", references);
    let ranges: Vec<&Value> = references.as_array().unwrap().iter().map(|r| &r["range"]).collect();
    assert_eq!(ranges, [&range((8, 0), (8, 4)), &range((6, 0), (6, 8))]);

    // Completion: the codes of the README's table, each with its form.
    let items = server.request("textDocument/completion", at(&uri, 5, 0));
    let g01 = items.as_array().unwrap().iter().find(|item| item["label"] == "G01").expect("G01 offered");
    assert_eq!(g01["detail"], "G01 [Xn] [Yn] [Zn] [Fn]");

    // One subprogram, from its O word to its M99.
    let symbols = server.request("textDocument/documentSymbol", json!({"textDocument": {"uri": uri}}));
    let symbols = symbols.as_array().unwrap();
    assert_eq!(symbols.len(), 1, "{symbols:#?}");
    assert_eq!(symbols[0]["name"], "O100");
    assert_eq!(symbols[0]["selectionRange"], range((8, 0), (8, 4)));
    assert_eq!(symbols[0]["range"], range((8, 0), (11, 3)));

    let shutdown = server.request("shutdown", Value::Null);
    assert_eq!(shutdown, Value::Null);
    server.notify("exit", Value::Null);
    let deadline = Instant::now() + Duration::from_secs(10);
    let status = loop {
        if let Some(status) = server.child.try_wait().unwrap() {
            break status;
        }
        assert!(Instant::now() < deadline, "ger lsp did not end after exit");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success(), "{status}");
}

/// Starts `ger lsp` in a temporary folder with `config` as its ger.toml and
/// `program` as part.nc, opened (version 1); the folder goes with the server.
fn open(config: &str, program: &str) -> (tempfile::TempDir, Server, String) {
    open_with(config, program, &[], Value::Null).0
}

/// As [`open`], with more arguments for `ger lsp` and the editor's
/// initializationOptions; also what the server answered to `initialize`.
fn open_with(
    config: &str,
    program: &str,
    args: &[&str],
    options: Value,
) -> ((tempfile::TempDir, Server, String), Value) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("ger.toml"), config).unwrap();
    let file = dir.path().join("part.nc");
    std::fs::write(&file, program).unwrap();
    let uri = format!("file://{}", file.display());
    let mut server = Server::start_with(dir.path(), args);
    let initialized = server.request(
        "initialize",
        json!({"processId": null, "rootUri": null, "capabilities": {}, "initializationOptions": options}),
    );
    server.notify("initialized", json!({}));
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "gcode", "version": 1, "text": program}}),
    );
    ((dir, server, uri), initialized)
}

/// An inch program on a mm machine whose G54 is at machine X100.
#[test]
fn hover_gives_words_in_machine_units_and_lines_their_place_and_time() {
    let config = "units = \"mm\"\n[offsets]\nG54 = [100.0, 0.0, 0.0]\n\
                  [[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6.0\n";
    let program = "G20 G90 G54\nG01 X1. F100\nG91 X-1.\nM30\n";
    let (_dir, mut server, uri) = open(config, program);
    server.diagnostics(1);

    // X1. in inches is 25.4 mm, from program zero at X100: machine X125.4.
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 1, 5)));
    assert!(text.contains("**X1.** is **25.400 mm** on this machine (the program is in inches here, G20)"), "{text}");
    assert!(
        text.contains("Machine **X125.400** mm after this line (absolute, G90, from program zero at machine X100.000 Y0.000 Z0.000)"),
        "{text}"
    );
    // G91 X-1.: 25.4 mm back, to machine X100.
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 2, 5)));
    assert!(text.contains("**X-1.** is **-25.400 mm** on this machine"), "{text}");
    assert!(text.contains("Machine **X100.000** mm after this line (relative, G91)"), "{text}");
    // F is not a length: no value in mm (the line's place is still said).
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 1, 9)));
    assert!(!text.contains("**F100**"), "{text}");

    // The planned time, on grbl-default (X: 500 mm/s²). F100 in/min is
    // 42.333 mm/s; each move starts and ends at rest (the second turns back),
    // so takes d/v + v/a: 125.4 mm in 2.9622 + 0.0847 = 3.0469 s, 25.4 mm
    // in 0.6 + 0.0847 = 0.6847 s. Line 3 is reached at 3.05 s of 3.73 s.
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 2, 8)));
    assert!(text.contains("After line 3: **X100.000 Y0.000 Z0.000** mm, in machine coordinates"), "{text}");
    assert!(text.contains("The planned run reaches line 3 at **3.0 s** of 3.7 s, on grbl-default"), "{text}");
    // On the line's first word, a code: the same after the code's meaning.
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 1, 0)));
    assert!(text.contains("After line 2: **X125.400 Y0.000 Z0.000** mm"), "{text}");
    assert!(text.contains("reaches line 2 at **0.0 s** of 3.7 s"), "{text}");
}

/// The published diagnostics' messages, for a failing assertion to show.
fn messages(diagnostics: &[Value]) -> Vec<&str> {
    diagnostics.iter().map(|d| d["message"].as_str().unwrap_or("")).collect()
}

#[test]
fn a_change_to_ger_toml_checks_the_open_programs_again() {
    // M02 is refused in the strict dialect and taken in the lenient one.
    let program = "G21\nG00 X1\nM02\n";
    let (dir, mut server, _uri) = open(CONFIG, program);
    let m02 = |diagnostics: &[Value]| diagnostics.iter().any(|d| d["range"] == range((2, 0), (2, 3)));
    let before = server.diagnostics(1);
    assert!(m02(&before), "{:?}", messages(&before));
    // No edit: only the file on disk changes, as another editor would save it.
    std::fs::write(dir.path().join("ger.toml"), format!("dialect = \"lenient\"\n{CONFIG}")).unwrap();
    let after = server.diagnostics(1);
    assert!(!m02(&after), "{:?}", messages(&after));
}

#[test]
fn inlay_hints_show_where_relative_and_polar_moves_go_when_asked_for() {
    // From X10 Y10: G91 X5 to X15 Y10, Y-3 to X15 Y7; polar (G16) X10 Y90:
    // 10 mm at 90 degrees, to X15 Y17. The absolute moves get no hint.
    let program = "G21 G90\nG00 X10 Y10\nG91 G01 X5 F100\nY-3\nG16\nX10 Y90\nG15 G90\nG01 X0 Y0\nM30\n";
    let whole = json!({"start": {"line": 0, "character": 0}, "end": {"line": 9, "character": 0}});
    let ((_dir, mut server, uri), initialized) = open_with(CONFIG, program, &[], json!({"inlayHints": true}));
    assert_eq!(initialized["capabilities"]["inlayHintProvider"], true, "{initialized}");
    server.diagnostics(1);
    let hints = server.request("textDocument/inlayHint", json!({"textDocument": {"uri": uri}, "range": whole}));
    let hints: Vec<(u64, u64, &str)> = hints
        .as_array()
        .unwrap()
        .iter()
        .map(|h| {
            (
                h["position"]["line"].as_u64().unwrap(),
                h["position"]["character"].as_u64().unwrap(),
                h["label"].as_str().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        hints,
        [
            (2, 15, "→ X15.000 Y10.000 Z0.000 mm"),
            (3, 3, "→ X15.000 Y7.000 Z0.000 mm"),
            (5, 7, "→ X15.000 Y17.000 Z0.000 mm")
        ]
    );
    // Only the lines asked for.
    let line_four = json!({"start": {"line": 3, "character": 0}, "end": {"line": 3, "character": 4}});
    let hints = server.request("textDocument/inlayHint", json!({"textDocument": {"uri": uri}, "range": line_four}));
    assert_eq!(hints.as_array().unwrap().len(), 1, "{hints}");

    // Off unless asked for: no capability, and nothing if asked all the same.
    let ((_dir, mut server, uri), initialized) = open_with(CONFIG, program, &[], Value::Null);
    assert!(initialized["capabilities"].get("inlayHintProvider").is_none(), "{initialized}");
    server.diagnostics(1);
    let hints = server.request("textDocument/inlayHint", json!({"textDocument": {"uri": uri}, "range": whole}));
    assert_eq!(hints, json!([]));
}

fn repo(path: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
}

/// The shipped wizards the example calls (Pocket, BoltCircle), built if need
/// be by `ger run`, as the other tests that run the example have them.
fn built_wizards() {
    let run = Command::new(env!("CARGO_BIN_EXE_ger"))
        .args(["run", "--wizards"])
        .arg(repo("wizards"))
        .arg(repo("host/examples/pocket.ngc"))
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
}

/// What BoltCircle's `describe()` says, as its source writes it.
const BOLT_CIRCLE_SUMMARY: &str = "drills holes evenly spaced on a circle around the current position";
const BOLT_CIRCLE_USAGE: &str = "BoltCircle COUNT DIAMETER DEPTH [ANGLE] [PECK] [BREAK]";

#[test]
fn a_shipped_wizard_is_described_completed_followed_and_run() {
    built_wizards();
    // Over X50 Y40 at Z5, BoltCircle drills 4 holes on a 20 mm circle, 1 deep,
    // and ends over the centre at the Z it started from (its source says so).
    let program = "G21 G90\nM06 T1\nM03 S10000\nG00 X50 Y40 Z5\nF100\nBoltCircle 4 20 1\nM30\n";
    let wizards = repo("wizards").display().to_string();
    let ((_dir, mut server, uri), _) = open_with(CONFIG, program, &["--no-build", "--wizards", &wizards], Value::Null);
    let diagnostics = server.diagnostics(1);
    assert!(!diagnostics.iter().any(|d| d["range"]["start"]["line"] == 5), "{:?}", messages(&diagnostics));

    // The folder's wizards are described once its first analysis is published.
    let text = server.hover_until(&uri, (5, 3), BOLT_CIRCLE_SUMMARY);
    assert!(text.contains("**BoltCircle** (wizard)"), "{text}");
    assert!(text.contains(BOLT_CIRCLE_SUMMARY), "{text}");
    assert!(text.contains(&format!("`{BOLT_CIRCLE_USAGE}`")), "{text}");
    assert!(text.contains("- `DIAMETER`: diameter of the circle through the holes' centres"), "{text}");
    assert!(text.contains("- `ANGLE` (optional)"), "{text}");
    assert!(text.contains("After line 6: **X50.000 Y40.000 Z5.000** mm"), "{text}");

    let items = server.request("textDocument/completion", at(&uri, 6, 0));
    let item = items.as_array().unwrap().iter().find(|i| i["label"] == "BoltCircle").expect("BoltCircle offered");
    assert_eq!(item["detail"], BOLT_CIRCLE_USAGE);

    let definition = server.request("textDocument/definition", at(&uri, 5, 3));
    let source = repo("wizards/boltcircle/src/lib.rs").canonicalize().unwrap();
    let found = definition["uri"].as_str().unwrap().strip_prefix("file://").unwrap().to_string();
    assert_eq!(Path::new(&found).canonicalize().unwrap(), source);
}

#[test]
fn a_wizard_added_to_the_folder_is_used_without_an_edit() {
    built_wizards();
    let program = "G21 G90\nM06 T1\nM03 S10000\nG00 X50 Y40 Z5\nF100\nBc 4 20 1\nM30\n";
    let ((dir, mut server, uri), _) = open_with(CONFIG, program, &["--wizards", "wizards"], Value::Null);
    let wizards = dir.path().join("wizards");
    std::fs::create_dir(&wizards).unwrap();
    let call = |diagnostics: &[Value]| diagnostics.iter().any(|d| d["range"]["start"]["line"] == 5);
    let before = server.diagnostics(1);
    assert!(call(&before), "{:?}", messages(&before));
    // BoltCircle, under the name the program calls.
    std::fs::copy(repo("wizards/boltcircle.wasm"), wizards.join("bc.wasm")).unwrap();
    let after = server.diagnostics(1);
    assert!(!call(&after), "{:?}", messages(&after));
    // Described again: its hover says what it does.
    server.hover_until(&uri, (5, 1), BOLT_CIRCLE_SUMMARY);
}

/// What the Neovim test's script asks Neovim, through its own LSP client:
/// the diagnostics it received for the program, then a hover on `G01`.
const NVIM_SCRIPT: &str = r#"
local dir, ger, out = os.getenv("GER_DIR"), os.getenv("GER_BIN"), os.getenv("GER_OUT")
local client = vim.lsp.start_client({ name = "ger", cmd = { ger, "lsp", "--stdio" }, root_dir = dir })
vim.cmd("edit " .. dir .. "/part.nc")
vim.lsp.buf_attach_client(0, client)
local result = { diagnostics = {} }
vim.wait(60000, function() return #vim.diagnostic.get(0) > 0 end, 50)
for _, d in ipairs(vim.diagnostic.get(0)) do
  table.insert(result.diagnostics, { lnum = d.lnum, col = d.col, end_col = d.end_col, severity = d.severity, message = d.message })
end
local params = { textDocument = { uri = vim.uri_from_bufnr(0) }, position = { line = 4, character = 1 } }
local answers = vim.lsp.buf_request_sync(0, "textDocument/hover", params, 20000) or {}
for _, answer in pairs(answers) do
  if answer.result then result.hover = answer.result.contents.value end
end
vim.fn.writefile({ vim.fn.json_encode(result) }, out)
vim.lsp.stop_client(client)
vim.cmd("qa!")
"#;

#[test]
fn neovim_shows_the_diagnostics_and_the_hover() {
    let Ok(nvim) = which("nvim") else {
        return support::peer_missing("Neovim (nvim) is not installed: `apt-get install neovim`");
    };
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("ger.toml"), CONFIG).unwrap();
    std::fs::write(dir.path().join("part.nc"), PROGRAM).unwrap();
    std::fs::write(dir.path().join("test.lua"), NVIM_SCRIPT).unwrap();
    let out = dir.path().join("result.json");
    let mut command = Command::new(nvim);
    command
        .current_dir(dir.path())
        .args(["--headless", "-u", "NONE", "-i", "NONE", "-c", "luafile test.lua"])
        .env("GER_DIR", dir.path())
        .env("GER_BIN", env!("CARGO_BIN_EXE_ger"))
        .env("GER_OUT", &out)
        .stdin(Stdio::null());
    let finished = support::process::run(&mut command, Duration::from_secs(120));
    let result = std::fs::read_to_string(&out)
        .unwrap_or_else(|err| panic!("Neovim wrote no result ({err}): {}{}", finished.stdout, finished.stderr));
    let result: Value = serde_json::from_str(&result).unwrap();
    let diagnostics = result["diagnostics"].as_array().unwrap();
    assert_eq!(diagnostics.len(), 1, "{result:#}");
    // Neovim counts bytes: the M02 after "(Ø6 mill) " (11 bytes) on line 8 (0-based 7).
    let m02 = &diagnostics[0];
    assert_eq!((m02["lnum"].as_u64(), m02["col"].as_u64(), m02["end_col"].as_u64()), (Some(7), Some(11), Some(14)));
    // 1: vim.diagnostic.severity.ERROR.
    assert_eq!(m02["severity"], 1);
    assert!(m02["message"].as_str().unwrap().starts_with("M02 is not accepted"), "{m02}");
    let hover = result["hover"].as_str().unwrap_or_else(|| panic!("no hover: {result:#}"));
    assert!(hover.contains("a feed move; a feed must be in force"), "{hover}");
}

/// The program `name` in PATH.
fn which(name: &str) -> Result<std::path::PathBuf, ()> {
    let path = std::env::var_os("PATH").ok_or(())?;
    std::env::split_paths(&path).map(|dir| dir.join(name)).find(|file| file.is_file()).ok_or(())
}

#[test]
fn the_vscode_extension_packages() {
    let Ok(npm) = which("npm") else {
        return support::peer_missing("npm is not installed: the VS Code extension was not built");
    };
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../editors/vscode");
    let npm_run = |args: &[&str]| {
        let finished =
            support::process::run(Command::new(&npm).current_dir(&folder).args(args), Duration::from_secs(600));
        assert_eq!(finished.code, Some(0), "npm {args:?}: {}{}", finished.stdout, finished.stderr);
    };
    // .ci/setup.d installs the packages from the lock file; a developer's first run does too.
    if !folder.join("node_modules").is_dir() {
        npm_run(&["ci", "--no-audit", "--no-fund"]);
    }
    npm_run(&["run", "compile"]);
    let out = tempfile::tempdir().unwrap();
    let vsix = out.path().join("ger.vsix");
    let vsix_arg = vsix.display().to_string();
    npm_run(&["exec", "--", "vsce", "package", "--allow-missing-repository", "--out", &vsix_arg]);
    // A .vsix is a zip, whose directory names its files uncompressed.
    let bytes = std::fs::read(&vsix).unwrap();
    assert!(bytes.starts_with(b"PK"), "not a zip");
    for name in
        ["extension/package.json", "extension/out/extension.js", "extension/node_modules/vscode-languageclient/"]
    {
        assert!(bytes.windows(name.len()).any(|w| w == name.as_bytes()), "{name} is not in the package");
    }
}

/// The program the README's picture of Neovim shows: inches on a mm machine
/// whose G54 is at X100, and a feed on a rapid, which is refused.
const PICTURED: &str = "\
(a bracket, in inches)
G20 G90 G54
M06 T1
M03 S10000
G00 X0 Y0 Z0.1 F50
G01 Z-0.1 F20
G01 X2. F30
G91 Y1.
G90 X0
G00 Z0.5
M30
";

/// The README's setup for Neovim 0.7: the Lua block that starts with `first`.
fn readme_lua(first: &str) -> String {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap();
    let start = readme.find(&format!("```lua\n{first}")).expect("the README's Neovim 0.7 setup") + "```lua\n".len();
    let end = readme[start..].find("```").unwrap() + start;
    readme[start..end].to_string()
}

/// What Neovim is told in the picture's terminal after the README's setup
/// (with `ger` the one built): the hover on `X2.` (line 7) once the
/// diagnostics are in, then a file written to say the screen is ready.
const PICTURE_INIT: &str = r#"
vim.o.number = true
vim.o.signcolumn = "yes"
vim.o.laststatus = 0
vim.o.ruler = false
vim.o.showmode = false
vim.cmd("highlight NormalFloat ctermbg=236 ctermfg=252")
vim.cmd("highlight FloatBorder ctermbg=236 ctermfg=244")
vim.cmd("highlight DiagnosticVirtualTextError ctermfg=203")
vim.cmd("highlight LineNr ctermfg=242")
vim.cmd("highlight SignColumn ctermbg=NONE")
vim.lsp.handlers["textDocument/hover"] = vim.lsp.with(vim.lsp.handlers.hover, { border = "rounded", max_width = 84 })
local function wait_then(condition, action, tries)
  if condition() or tries == 0 then return action() end
  vim.defer_fn(function() wait_then(condition, action, tries - 1) end, 100)
end
vim.api.nvim_create_autocmd("VimEnter", { callback = function()
  wait_then(function() return #vim.diagnostic.get(0) > 0 end, function()
    vim.api.nvim_win_set_cursor(0, { 7, 5 })
    vim.lsp.buf.hover()
    vim.defer_fn(function() vim.fn.writefile({ "ready" }, os.getenv("GER_READY")) end, 1500)
  end, 600)
end })
"#;

/// The 256 colours of an xterm, as CSS.
fn xterm_colour(n: u8) -> String {
    const BASIC: [&str; 16] = [
        "#1d1f21", "#cc6666", "#b5bd68", "#f0c674", "#81a2be", "#b294bb", "#8abeb7", "#c5c8c6", "#666666", "#d54e53",
        "#b9ca4a", "#e7c547", "#7aa6da", "#c397d8", "#70c0b1", "#eaeaea",
    ];
    match n {
        0..=15 => BASIC[n as usize].to_string(),
        16..=231 => {
            let level = |v: u8| if v == 0 { 0 } else { 55 + 40 * v as u32 };
            let n = n - 16;
            format!("rgb({},{},{})", level(n / 36), level(n / 6 % 6), level(n % 6))
        }
        232..=255 => {
            let grey = 8 + 10 * (n as u32 - 232);
            format!("rgb({grey},{grey},{grey})")
        }
    }
}

/// A terminal's screen as tmux's `capture-pane -e` gives it (text and SGR
/// escapes) as an HTML page of one `pre`, each run of cells in its colours.
fn screen_html(screen: &str) -> String {
    let (background, foreground) = ("#1d1f21".to_string(), "#c5c8c6".to_string());
    let mut html = format!(
        "<!doctype html><meta charset=utf-8><style>body{{margin:0;background:{background}}}\
         pre{{margin:0;padding:8px;font:14px/17px 'DejaVu Sans Mono',monospace;color:{foreground}}}</style><pre>"
    );
    let (mut fg, mut bg, mut bold, mut reverse): (Option<String>, Option<String>, bool, bool) =
        (None, None, false, false);
    let mut open = false;
    let mut chars = screen.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '\x1b' && chars.peek() == Some(&'[') {
            chars.next();
            let mut code = String::new();
            for c in chars.by_ref() {
                if c.is_ascii_alphabetic() {
                    break;
                }
                code.push(c);
            }
            let numbers: Vec<u32> = code.split(';').map(|n| n.parse().unwrap_or(0)).collect();
            let mut i = 0;
            while i < numbers.len() {
                match numbers[i] {
                    0 => (fg, bg, bold, reverse) = (None, None, false, false),
                    1 => bold = true,
                    7 => reverse = true,
                    22 => bold = false,
                    27 => reverse = false,
                    n @ 30..=37 => fg = Some(xterm_colour(n as u8 - 30)),
                    n @ 90..=97 => fg = Some(xterm_colour(n as u8 - 90 + 8)),
                    n @ 40..=47 => bg = Some(xterm_colour(n as u8 - 40)),
                    n @ 100..=107 => bg = Some(xterm_colour(n as u8 - 100 + 8)),
                    39 => fg = None,
                    49 => bg = None,
                    n @ (38 | 48) if numbers.get(i + 1) == Some(&5) => {
                        let colour = Some(xterm_colour(numbers.get(i + 2).copied().unwrap_or(0) as u8));
                        if n == 38 {
                            fg = colour
                        } else {
                            bg = colour
                        }
                        i += 2;
                    }
                    n @ (38 | 48) if numbers.get(i + 1) == Some(&2) => {
                        let rgb = |k: usize| numbers.get(i + k).copied().unwrap_or(0);
                        let colour = Some(format!("rgb({},{},{})", rgb(2), rgb(3), rgb(4)));
                        if n == 38 {
                            fg = colour
                        } else {
                            bg = colour
                        }
                        i += 4;
                    }
                    _ => {}
                }
                i += 1;
            }
            if open {
                html.push_str("</span>");
            }
            let (mut f, mut b) = (fg.clone().unwrap_or(foreground.clone()), bg.clone().unwrap_or(background.clone()));
            if reverse {
                std::mem::swap(&mut f, &mut b);
            }
            let weight = if bold { "font-weight:bold;" } else { "" };
            html.push_str(&format!("<span style=\"color:{f};background:{b};{weight}\">"));
            open = true;
            continue;
        }
        match c {
            '<' => html.push_str("&lt;"),
            '>' => html.push_str("&gt;"),
            '&' => html.push_str("&amp;"),
            c => html.push(c),
        }
    }
    if open {
        html.push_str("</span>");
    }
    html.push_str("</pre>");
    html
}

/// Neovim in a terminal (tmux), as a user sees it: the diagnostic at the
/// rapid's F and the hover on `X2.` (2 in = 50.8 mm, from G54's X100: X150.8).
/// The screen is drawn as a picture by Chromium: `UPDATE_SCREENSHOT=1`
/// writes it to `host/docs/lsp-neovim.png`, the one the README shows.
#[test]
fn neovim_in_a_terminal_shows_the_diagnostic_and_the_hover() {
    let chromium =
        std::env::var_os("GER_CHROMIUM").map_or_else(|| std::path::PathBuf::from("/usr/bin/chromium"), Into::into);
    let (Ok(_), Ok(tmux), true) = (which("nvim"), which("tmux"), chromium.is_file()) else {
        return support::peer_missing(
            "Neovim, tmux or Chromium is missing: the picture of ger in Neovim was NOT taken",
        );
    };
    let dir = tempfile::tempdir().unwrap();
    let config = "units = \"mm\"\n[offsets]\nG54 = [100.0, 0.0, 0.0]\n[[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6.0\n";
    std::fs::write(dir.path().join("ger.toml"), config).unwrap();
    std::fs::write(dir.path().join("bracket.nc"), PICTURED).unwrap();
    let setup = readme_lua("-- Neovim 0.7 (tested)");
    let ger = format!("{:?}, \"lsp\"", env!("CARGO_BIN_EXE_ger"));
    assert!(setup.contains("\"ger\", \"lsp\""), "{setup}");
    std::fs::write(dir.path().join("init.lua"), setup.replace("\"ger\", \"lsp\"", &ger) + PICTURE_INIT).unwrap();
    let ready = dir.path().join("ready");
    let session = format!("ger-lsp-{}", std::process::id());
    let socket = dir.path().join("tmux.sock");
    let tmux_command = |args: &[&str]| {
        let mut command = Command::new(&tmux);
        command.arg("-S").arg(&socket).args(args);
        command
    };
    let shell = format!(
        "cd {dir} && TERM=xterm-256color GER_READY={ready} nvim -u init.lua -i NONE bracket.nc",
        dir = dir.path().display(),
        ready = ready.display()
    );
    let started =
        tmux_command(&["-f", "/dev/null", "new-session", "-d", "-s", &session, "-x", "100", "-y", "20", &shell])
            .status()
            .unwrap();
    assert!(started.success(), "tmux did not start");
    let deadline = Instant::now() + Duration::from_secs(90);
    while !ready.exists() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(100));
    }
    let captured = tmux_command(&["capture-pane", "-p", "-e", "-t", &session]).output().unwrap();
    let _ = tmux_command(&["kill-server"]).status();
    let screen = String::from_utf8_lossy(&captured.stdout).into_owned();
    assert!(ready.exists(), "Neovim was not ready within 90 s:\n{screen}");
    let plain: String = {
        let mut plain = String::new();
        let mut chars = screen.chars();
        while let Some(c) = chars.next() {
            if c == '\x1b' {
                chars.by_ref().find(|c| c.is_ascii_alphabetic());
            } else {
                plain.push(c);
            }
        }
        plain
    };
    // What the server said, as Neovim shows it: the F refused, and the hover.
    assert!(plain.contains("F is not allowed on a G00"), "{plain}");
    assert!(plain.contains("50.800 mm"), "{plain}");
    assert!(plain.contains("X150.800"), "{plain}");

    let html = dir.path().join("screen.html");
    std::fs::write(&html, screen_html(&screen)).unwrap();
    let picture = if std::env::var("UPDATE_SCREENSHOT").is_ok_and(|v| v == "1") {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/lsp-neovim.png")
    } else {
        Path::new(env!("CARGO_TARGET_TMPDIR")).join("lsp-neovim.png")
    };
    let shot = support::process::run(
        Command::new(&chromium)
            .args(["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--window-size=860,356"])
            .arg(format!("--screenshot={}", picture.display()))
            .arg(format!("file://{}", html.display())),
        Duration::from_secs(120),
    );
    assert_eq!(shot.code, Some(0), "{}{}", shot.stdout, shot.stderr);
    assert!(std::fs::read(&picture).unwrap().starts_with(b"\x89PNG"), "no picture at {}", picture.display());
}
