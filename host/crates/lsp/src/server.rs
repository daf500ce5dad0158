//! The protocol: documents opened, edited and closed; diagnostics published
//! by the worker; hover, definition, symbols, code actions and completion
//! answered on the protocol's thread from the last finished analysis.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use crossbeam_channel::Sender;
use lsp_server::{Connection, ErrorCode, Message, Notification, ProtocolError, Request, RequestId, Response};
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, Notification as _, PublishDiagnostics,
};
use lsp_types::request::{
    CodeActionRequest, Completion, DocumentSymbolRequest, GotoDefinition, HoverRequest, InlayHintRequest, References,
    Request as _,
};
use lsp_types::{
    CodeActionKind, CodeActionParams, CodeActionProviderCapability, CompletionItem, CompletionItemKind,
    CompletionOptions, CompletionParams, CompletionResponse, DocumentSymbol, DocumentSymbolParams,
    DocumentSymbolResponse, Documentation, GotoDefinitionParams, GotoDefinitionResponse, Hover, HoverContents,
    HoverParams, HoverProviderCapability, InitializeParams, InlayHint, InlayHintLabel, InlayHintParams,
    InlayHintTooltip, Location, MarkupContent, MarkupKind, OneOf, Position, PublishDiagnosticsParams, Range,
    ReferenceParams, ServerCapabilities, ServerInfo, SymbolKind, TextDocumentSyncCapability, TextDocumentSyncKind,
    TextDocumentSyncOptions, Url,
};
use ropey::Rope;
use serde::de::DeserializeOwned;

use crate::analysis::{analyse, Analysis};
use crate::codes::{self, codes};
use crate::outline::{covers, line_tokens, Block};
use crate::text::{Document, LineText};
use crate::watch::{self, Folders, Follower, Watched};
use crate::{actions, hover, Options, WizardInfo};
use ger_engine::core::diag::Span;
use ger_engine::core::lex::TokenKind;
use ger_engine::core::statement::{Dialect, Distance};
use ger_engine::core::wizard::key as wizard_key;

/// Why the server stopped before the editor said `exit`.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("the editor broke the protocol: {0}")]
    Protocol(#[from] ProtocolError),
    #[error("cannot {what}: {cause}")]
    Io { what: &'static str, cause: std::io::Error },
}

/// How long the text must rest after an edit before it is analysed.
const DEBOUNCE: Duration = Duration::from_millis(200);

/// Serves the protocol on standard input and output until the editor says `exit`.
pub fn serve_stdio(options: Options) -> Result<(), Error> {
    let (connection, io_threads) = Connection::stdio();
    serve(connection, options)?;
    io_threads.join().map_err(|cause| Error::Io { what: "use the standard streams", cause })
}

/// Serves the protocol on `connection` until the editor says `exit`.
pub fn serve(connection: Connection, options: Options) -> Result<(), Error> {
    let (id, params) = connection.initialize_start()?;
    // What the editor says about itself changes nothing; what it asks of ger,
    // in its initializationOptions, may: `{"inlayHints": true}`.
    let asked = serde_json::from_value::<InitializeParams>(params).ok().and_then(|p| p.initialization_options);
    let inlay_hints = asked.as_ref().and_then(|o| o.get("inlayHints")?.as_bool()).unwrap_or(false);
    let capabilities = ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Options(TextDocumentSyncOptions {
            open_close: Some(true),
            change: Some(TextDocumentSyncKind::INCREMENTAL),
            ..TextDocumentSyncOptions::default()
        })),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        code_action_provider: Some(CodeActionProviderCapability::Options(lsp_types::CodeActionOptions {
            code_action_kinds: Some(vec![CodeActionKind::QUICKFIX]),
            ..lsp_types::CodeActionOptions::default()
        })),
        completion_provider: Some(CompletionOptions::default()),
        inlay_hint_provider: inlay_hints.then_some(OneOf::Left(true)),
        ..ServerCapabilities::default()
    };
    let initialize = serde_json::json!({
        "capabilities": capabilities,
        "serverInfo": ServerInfo { name: "ger".to_string(), version: Some(env!("CARGO_PKG_VERSION").to_string()) },
    });
    connection.initialize_finish(id, initialize)?;

    let (folders, events) = Folders::new().unzip();
    let shared = Arc::new(Shared {
        folders: Mutex::new(folders),
        options,
        documents: Mutex::new(HashMap::new()),
        wake: Condvar::new(),
        analyses: Mutex::new(HashMap::new()),
        catalogs: Mutex::new(HashMap::new()),
        sender: connection.sender.clone(),
        inlay_hints,
        generations: AtomicU64::new(0),
        stopping: AtomicBool::new(false),
    });
    let worker = {
        let shared = shared.clone();
        std::thread::Builder::new()
            .name("ger lsp analysis".to_string())
            .spawn(move || shared.work())
            .map_err(|cause| Error::Io { what: "start the analysis thread", cause })?
    };
    let watcher = match events {
        Some(events) => {
            let shared = shared.clone();
            let thread = std::thread::Builder::new()
                .name("ger lsp watcher".to_string())
                .spawn(move || watch::follow(&*shared, &events))
                .map_err(|cause| Error::Io { what: "start the watching thread", cause })?;
            Some(thread)
        }
        None => None,
    };
    let served = serve_messages(&connection, &shared);
    shared.stopping.store(true, Ordering::SeqCst);
    shared.wake.notify_all();
    let _ = worker.join();
    if let Some(watcher) = watcher {
        let _ = watcher.join();
    }
    served
}

fn serve_messages(connection: &Connection, shared: &Shared) -> Result<(), Error> {
    for message in &connection.receiver {
        match message {
            Message::Request(request) => {
                if connection.handle_shutdown(&request)? {
                    return Ok(());
                }
                let response = shared.answer(request);
                if connection.sender.send(response.into()).is_err() {
                    // The writer is gone: so is the editor.
                    return Ok(());
                }
            }
            Message::Notification(notification) => shared.notified(notification),
            Message::Response(_) => {}
        }
    }
    Ok(())
}

/// An open document, and the analysis it waits for.
struct Open {
    document: Document,
    path: PathBuf,
    /// The generation of its newest text: an analysis of an older one is stale.
    generation: Arc<AtomicU64>,
    /// When to analyse it, if its text has not been analysed yet.
    due: Option<Instant>,
}

/// What the protocol's thread and the worker share.
struct Shared {
    options: Options,
    documents: Mutex<HashMap<Url, Open>>,
    /// Told when a document is due, or the server stops.
    wake: Condvar,
    analyses: Mutex<HashMap<Url, Arc<Analysis>>>,
    /// The wizards of each folder, described once.
    catalogs: Mutex<HashMap<PathBuf, Arc<Vec<WizardInfo>>>>,
    sender: Sender<Message>,
    /// Whether the editor asked for inlay hints.
    inlay_hints: bool,
    /// The folders watched (none without a watcher).
    folders: Mutex<Option<Folders>>,
    generations: AtomicU64,
    stopping: AtomicBool,
}

/// A job for the worker.
struct Job {
    uri: Url,
    path: PathBuf,
    text: Rope,
    version: i32,
    generation: u64,
    newest: Arc<AtomicU64>,
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    // Every change under these locks is one assignment: a panic leaves them consistent.
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

fn params<P: DeserializeOwned>(value: serde_json::Value) -> Option<P> {
    serde_json::from_value(value).ok()
}

impl Shared {
    fn notified(&self, notification: Notification) {
        match notification.method.as_str() {
            DidOpenTextDocument::METHOD => {
                let Some(p) = params::<lsp_types::DidOpenTextDocumentParams>(notification.params) else { return };
                let item = p.text_document;
                // An unsaved buffer has no path: it is analysed as if in the working folder.
                let path = item.uri.to_file_path().unwrap_or_else(|()| PathBuf::from(item.uri.path()));
                let open = Open {
                    document: Document::new(&item.text, item.version),
                    path,
                    generation: Arc::new(AtomicU64::new(0)),
                    due: None,
                };
                lock(&self.documents).insert(item.uri.clone(), open);
                self.changed(&item.uri, Instant::now());
            }
            DidChangeTextDocument::METHOD => {
                let Some(p) = params::<lsp_types::DidChangeTextDocumentParams>(notification.params) else { return };
                let uri = p.text_document.uri;
                if let Some(open) = lock(&self.documents).get_mut(&uri) {
                    open.document.change(p.content_changes, p.text_document.version);
                }
                self.changed(&uri, Instant::now() + DEBOUNCE);
            }
            DidCloseTextDocument::METHOD => {
                let Some(p) = params::<lsp_types::DidCloseTextDocumentParams>(notification.params) else { return };
                let uri = p.text_document.uri;
                if let Some(open) = lock(&self.documents).remove(&uri) {
                    open.generation.store(u64::MAX, Ordering::SeqCst);
                }
                lock(&self.analyses).remove(&uri);
                self.publish(uri, Vec::new(), None);
            }
            _ => {}
        }
    }

    /// The document's text changed: what runs on an older one stops, and
    /// it is analysed at `due`.
    fn changed(&self, uri: &Url, due: Instant) {
        let generation = self.generations.fetch_add(1, Ordering::SeqCst) + 1;
        if let Some(open) = lock(&self.documents).get_mut(uri) {
            open.generation.store(generation, Ordering::SeqCst);
            open.due = Some(due);
        }
        self.wake.notify_all();
    }

    fn publish(&self, uri: Url, diagnostics: Vec<lsp_types::Diagnostic>, version: Option<i32>) {
        let params = PublishDiagnosticsParams { uri, diagnostics, version };
        // The editor gone, nobody is left to tell.
        let _ = self.sender.send(Notification::new(PublishDiagnostics::METHOD.to_string(), params).into());
    }

    /// The worker: analyses each document when it is due, until the server stops.
    fn work(&self) {
        while let Some(job) = self.next_job() {
            let stale =
                || self.stopping.load(Ordering::Relaxed) || job.newest.load(Ordering::Relaxed) != job.generation;
            // Watched before they are read: a change after the read is seen.
            self.watch(&self.watched_of(&job.uri));
            // Made here, not under the documents' lock: the text is the job's own.
            let text: Arc<str> = Arc::from(String::from(&job.text));
            let Some(analysis) = analyse(&self.options, &job.uri, &job.path, text, &stale) else {
                continue;
            };
            let wizards = self.options.wizards_dir(job.path.parent().unwrap_or(std::path::Path::new("/")));
            let diagnostics = analysis.diagnostics.clone();
            let replaced;
            {
                // Stored and published under the documents' lock, so a close cannot come between.
                let documents = lock(&self.documents);
                if stale() || !documents.contains_key(&job.uri) {
                    continue;
                }
                replaced = lock(&self.analyses).insert(job.uri.clone(), Arc::new(analysis));
                self.publish(job.uri, diagnostics, Some(job.version));
            }
            // Freed after the locks: the positions of a large program take a while.
            drop(replaced);
            if !lock(&self.catalogs).contains_key(&wizards) {
                let catalog = Arc::new((self.options.catalog)(&wizards));
                lock(&self.catalogs).insert(wizards, catalog);
            }
        }
    }

    /// The next document due, once it is (`None` when the server stops).
    fn next_job(&self) -> Option<Job> {
        let mut documents = lock(&self.documents);
        loop {
            if self.stopping.load(Ordering::SeqCst) {
                return None;
            }
            let next = documents.iter().filter_map(|(uri, open)| Some((open.due?, uri))).min_by_key(|(due, _)| *due);
            let Some((due, uri)) = next else {
                documents = self.wake.wait(documents).unwrap_or_else(|p| p.into_inner());
                continue;
            };
            let now = Instant::now();
            if due > now {
                documents = self.wake.wait_timeout(documents, due - now).unwrap_or_else(|p| p.into_inner()).0;
                continue;
            }
            let uri = uri.clone();
            let open = documents.get_mut(&uri).expect("just found");
            open.due = None;
            return Some(Job {
                uri,
                path: open.path.clone(),
                text: open.document.snapshot(),
                version: open.document.version,
                generation: open.generation.load(Ordering::SeqCst),
                newest: open.generation.clone(),
            });
        }
    }

    /// The wizards folder of the program `uri` names.
    fn wizards_dir_of(&self, uri: &Url) -> PathBuf {
        let path = uri.to_file_path().unwrap_or_default();
        self.options.wizards_dir(path.parent().unwrap_or(std::path::Path::new("/")))
    }

    fn answer(&self, request: Request) -> Response {
        let id = request.id.clone();
        let result = match request.method.as_str() {
            HoverRequest::METHOD => self.with(request, |s, p: HoverParams| serde_json::to_value(s.hover(p))),
            GotoDefinition::METHOD => {
                self.with(request, |s, p: GotoDefinitionParams| serde_json::to_value(s.definition(p)))
            }
            References::METHOD => self.with(request, |s, p: ReferenceParams| serde_json::to_value(s.references(p))),
            DocumentSymbolRequest::METHOD => {
                self.with(request, |s, p: DocumentSymbolParams| serde_json::to_value(s.symbols(p)))
            }
            CodeActionRequest::METHOD => self.with(request, |s, p: CodeActionParams| {
                let uri = &p.text_document.uri;
                serde_json::to_value(actions::code_actions(uri, &s.config_of(uri), &p.context.diagnostics))
            }),
            Completion::METHOD => self.with(request, |s, p: CompletionParams| serde_json::to_value(s.completion(p))),
            InlayHintRequest::METHOD => {
                self.with(request, |s, p: InlayHintParams| serde_json::to_value(s.inlay_hints(p).unwrap_or_default()))
            }
            method => return method_not_found(id, method),
        };
        match result {
            Some(Ok(value)) => Response { id, result: Some(value), error: None },
            _ => Response::new_err(id, ErrorCode::InvalidParams as i32, "invalid parameters".to_string()),
        }
    }

    fn with<P: DeserializeOwned>(
        &self,
        request: Request,
        answer: impl FnOnce(&Shared, P) -> serde_json::Result<serde_json::Value>,
    ) -> Option<serde_json::Result<serde_json::Value>> {
        Some(answer(self, params(request.params)?))
    }

    /// The config file of the program `uri` names: the one given, or `ger.toml` beside it.
    fn config_of(&self, uri: &Url) -> PathBuf {
        let path = uri.to_file_path().unwrap_or_default();
        let beside = || path.with_file_name("ger.toml");
        self.options.settings.config.clone().unwrap_or_else(beside)
    }

    fn analysis(&self, uri: &Url) -> Option<Arc<Analysis>> {
        lock(&self.analyses).get(uri).cloned()
    }

    fn catalog(&self, uri: &Url) -> Arc<Vec<WizardInfo>> {
        lock(&self.catalogs).get(&self.wizards_dir_of(uri)).cloned().unwrap_or_default()
    }

    /// What the program `uri` names reads besides its text.
    fn watched_of(&self, uri: &Url) -> Watched {
        let path = uri.to_file_path().unwrap_or_default();
        let folder = path.parent().unwrap_or(std::path::Path::new("/"));
        Watched::new(&self.config_of(uri), folder, &self.wizards_dir_of(uri))
    }

    /// What is under the cursor: the code's meaning, the wizard's usage, a
    /// length's value in the machine's unit and an axis's machine
    /// coordinate; and where the tool is after the line, and when.
    fn hover(&self, p: HoverParams) -> Option<Hover> {
        let uri = &p.text_document_position_params.text_document.uri;
        let position = p.text_document_position_params.position;
        let analysis = self.analysis(uri);
        let dialect = analysis.as_ref().map_or(Dialect::Strict, |a| a.dialect);
        let (tokens, at, range) = {
            let documents = lock(&self.documents);
            let document = &documents.get(uri)?.document;
            let (line, col, line_text) = document.cursor(position);
            let tokens = line_tokens(&line_text, line, dialect);
            let at = tokens.iter().position(|(token, _)| covers(token, col));
            let range = at.map(|i| document.range(line, tokens[i].0.span.col, tokens[i].0.span.len));
            (tokens, at, range)
        };
        let line = position.line.saturating_add(1);
        let mut sections = Vec::new();
        match at.map(|i| (&tokens[i].0.kind, tokens[i].1.as_str())) {
            Some((TokenKind::Word { letter: letter @ ('G' | 'M'), value }, _)) => {
                let code = codes::name(*letter, *value);
                let rows = codes().rows(&code);
                if rows.is_empty() {
                    sections.push(format!("**{code}**: not a code ger knows"));
                }
                sections.extend(rows.iter().map(|row| row.markdown()));
            }
            Some((TokenKind::Word { letter, value }, written)) => {
                if let Some(analysis) = &analysis {
                    let g10 = tokens.iter().any(|(t, _)| t.kind == TokenKind::Word { letter: 'G', value: 10.0 });
                    let word = hover::Word { letter: *letter, value: *value, written, line, on_g10: g10 };
                    sections.extend(hover::word_text(&word, analysis));
                }
            }
            Some((TokenKind::Ident(name), _)) => sections.push(hover::wizard_hover(name, &self.catalog(uri))),
            _ => {}
        }
        if let Some(analysis) = &analysis {
            sections.push(hover::line_text(line, analysis));
        }
        (!sections.is_empty()).then(|| Hover {
            contents: HoverContents::Markup(MarkupContent {
                kind: MarkupKind::Markdown,
                value: sections.join("\n\n---\n\n"),
            }),
            range,
        })
    }

    /// The subprogram a call names, or the source of the wizard a call runs.
    fn definition(&self, p: GotoDefinitionParams) -> Option<GotoDefinitionResponse> {
        let uri = &p.text_document_position_params.text_document.uri;
        let position = p.text_document_position_params.position;
        let analysis = self.analysis(uri)?;
        let documents = lock(&self.documents);
        let document = &documents.get(uri)?.document;
        let (line, col, _) = document.cursor(position);
        if let Some(name) = analysis.outline.wizard_at(line, col) {
            let key = wizard_key(name);
            let catalog = self.catalog(uri);
            let source = catalog.iter().find(|w| wizard_key(&w.name) == key)?.source.clone()?;
            let uri = Url::from_file_path(source).ok()?;
            return Some(GotoDefinitionResponse::Scalar(Location { uri, range: Range::default() }));
        }
        let call = analysis.outline.call_at(line, col)?;
        let block = analysis.outline.definition(&call.label)?;
        let start = block.start;
        let range = document.range(start.line, start.col, start.len);
        Some(GotoDefinitionResponse::Scalar(Location { uri: uri.clone(), range }))
    }

    /// The calls of the subprogram called or defined at the cursor (and its
    /// definition, if the editor asks for it).
    fn references(&self, p: ReferenceParams) -> Option<Vec<Location>> {
        let uri = &p.text_document_position.text_document.uri;
        let position = p.text_document_position.position;
        let analysis = self.analysis(uri)?;
        let documents = lock(&self.documents);
        let document = &documents.get(uri)?.document;
        let (line, col, _) = document.cursor(position);
        let outline = &analysis.outline;
        let label = match outline.call_at(line, col) {
            Some(call) => call.label.clone(),
            None => outline.blocks.iter().find(|b| b.start.line == line)?.label.clone()?,
        };
        let location = |span: Span| Location { uri: uri.clone(), range: document.range(span.line, span.col, span.len) };
        let definition = outline.definition(&label).filter(|_| p.context.include_declaration);
        let calls = outline.calls.iter().filter(|call| call.label == label);
        Some(definition.map(|b| b.start).into_iter().chain(calls.map(|call| call.span)).map(location).collect())
    }

    /// The subprograms and O-word blocks, nested as they are.
    fn symbols(&self, p: DocumentSymbolParams) -> Option<DocumentSymbolResponse> {
        let uri = &p.text_document.uri;
        let analysis = self.analysis(uri)?;
        let documents = lock(&self.documents);
        let document = &documents.get(uri)?.document;
        let blocks = &analysis.outline.blocks;
        let symbol = |block: &Block| {
            let start = block.start;
            let selection = document.range(start.line, start.col, start.len);
            let last = document.line(block.end_line.saturating_sub(1) as usize);
            let end =
                Position { line: block.end_line.saturating_sub(1), character: last.encode_utf16().count() as u32 };
            #[allow(deprecated)] // `deprecated` is a field every literal must name.
            DocumentSymbol {
                name: block.name.clone(),
                detail: None,
                kind: if block.label.is_some() { SymbolKind::FUNCTION } else { SymbolKind::NAMESPACE },
                tags: None,
                deprecated: None,
                range: Range { start: selection.start, end: end.max(selection.end) },
                selection_range: selection,
                children: None,
            }
        };
        // Blocks come in order of their start, a parent before its children:
        // build from the last, handing each to its parent.
        let mut built: Vec<Option<DocumentSymbol>> = blocks.iter().map(|b| Some(symbol(b))).collect();
        for i in (0..blocks.len()).rev() {
            if let Some(parent) = blocks[i].parent {
                let child = built[i].take().expect("each block is taken once, by its parent");
                built[parent]
                    .as_mut()
                    .expect("a parent comes before")
                    .children
                    .get_or_insert_with(Vec::new)
                    .insert(0, child);
            }
        }
        Some(DocumentSymbolResponse::Nested(built.into_iter().flatten().collect()))
    }

    /// At the end of each line in the range whose move is relative (G91)
    /// or polar (G16), where the tool is after it, in machine coordinates;
    /// nothing unless the editor asked for inlay hints.
    fn inlay_hints(&self, p: InlayHintParams) -> Option<Vec<InlayHint>> {
        if !self.inlay_hints {
            return None;
        }
        let uri = &p.text_document.uri;
        let analysis = self.analysis(uri)?;
        let documents = lock(&self.documents);
        let document = &documents.get(uri)?.document;
        let moves = analysis.moves_between(p.range.start.line.saturating_add(1), p.range.end.line.saturating_add(1));
        let hints = moves.iter().filter_map(|&(line, at)| {
            let state = analysis.state_at(line)?;
            if state.distance != Distance::Incremental && !state.polar {
                return None;
            }
            let end = document.line(line as usize - 1).encode_utf16().count() as u32;
            Some(InlayHint {
                position: Position { line: line - 1, character: end },
                label: InlayHintLabel::String(format!(
                    "→ {} {}",
                    hover::place(at, analysis.units),
                    analysis.units.abbreviation()
                )),
                kind: None,
                text_edits: None,
                tooltip: Some(InlayHintTooltip::String(
                    "where the tool is after this line, in machine coordinates".to_string(),
                )),
                padding_left: Some(true),
                padding_right: None,
                data: None,
            })
        });
        Some(hints.collect())
    }

    /// The codes of the README's table and the wizards of the program's folder.
    fn completion(&self, p: CompletionParams) -> CompletionResponse {
        let mut items: Vec<CompletionItem> = codes()
            .all()
            .map(|(code, rows)| CompletionItem {
                label: code.to_string(),
                kind: Some(CompletionItemKind::KEYWORD),
                detail: rows.first().map(|row| row.form.replace('`', "")),
                documentation: Some(markdown(rows.iter().map(|row| row.markdown()).collect::<Vec<_>>().join("\n\n"))),
                ..CompletionItem::default()
            })
            .collect();
        items.extend(self.catalog(&p.text_document_position.text_document.uri).iter().map(|wizard| CompletionItem {
            label: wizard.name.clone(),
            kind: Some(CompletionItemKind::FUNCTION),
            detail: Some(wizard.usage.clone()),
            documentation: Some(markdown(hover::wizard_text(wizard))),
            ..CompletionItem::default()
        }));
        CompletionResponse::Array(items)
    }
}

impl Follower for Shared {
    fn watched(&self) -> Vec<Watched> {
        let open: Vec<Url> = lock(&self.documents).keys().cloned().collect();
        open.iter().map(|uri| self.watched_of(uri)).collect()
    }

    fn watch(&self, program: &Watched) -> Vec<PathBuf> {
        lock(&self.folders).as_mut().map(|folders| folders.add(program)).unwrap_or_default()
    }

    /// A file a program's analysis reads changed: the program is analysed
    /// again at once (its text has not changed: the same version is
    /// published again), and a wizards folder whose `.wasm` changed is
    /// described again after it.
    fn files_changed(&self, paths: &[PathBuf]) {
        let open: Vec<Url> = lock(&self.documents).keys().cloned().collect();
        for uri in open {
            let watched = self.watched_of(&uri);
            if paths.iter().any(|path| watched.reads(path)) {
                lock(&self.catalogs).remove(&self.wizards_dir_of(&uri));
                self.changed(&uri, Instant::now());
            }
        }
    }

    fn stopping(&self) -> bool {
        self.stopping.load(Ordering::SeqCst)
    }
}

fn method_not_found(id: RequestId, method: &str) -> Response {
    Response::new_err(id, ErrorCode::MethodNotFound as i32, format!("ger lsp does not answer {method}"))
}

fn markdown(value: String) -> Documentation {
    Documentation::MarkupContent(MarkupContent { kind: MarkupKind::Markdown, value })
}
