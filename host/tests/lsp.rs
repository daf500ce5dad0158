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
        let mut child = Command::new(env!("CARGO_BIN_EXE_ger"))
            .current_dir(dir)
            .args(["lsp", "--stdio"])
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

    /// The next message `wanted` picks, within 60 s (a debug build on a busy machine).
    fn wait(&mut self, wanted: impl Fn(&Value) -> bool) -> Value {
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            match self.messages.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
                Ok(message) if wanted(&message) => return message,
                Ok(_) => {}
                Err(RecvTimeoutError::Timeout) => panic!("no such message within 60 s"),
                Err(RecvTimeoutError::Disconnected) => panic!("ger lsp ended"),
            }
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
    // An axis word: its machine coordinate after the line.
    let text = hover_text(&server.request("textDocument/hover", at(&uri, 3, 4)));
    assert!(text.contains("**X** after this line: 10.000 mm"), "{text}");

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
