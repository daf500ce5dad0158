//! `ger view`'s HTTP side, as `host/docs/view-api.md` describes it: the page's
//! files, the snapshot as JSON and binary, server-sent events, and the
//! requests that change the session. Every bad request gets a 4xx answer
//! with a JSON message; nothing a client sends stops the server.

use std::convert::Infallible;
use std::sync::Arc;
use std::time::Duration;

use axum::body::{Body, Bytes};
use axum::extract::rejection::{BytesRejection, QueryRejection};
use axum::extract::{DefaultBodyLimit, Query, Request, State};
use axum::http::header::{CONTENT_LENGTH, CONTENT_TYPE};
use axum::http::{Method, StatusCode};
use axum::middleware::{self, Next};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use futures_util::Stream;
use hyper::server::conn::http1;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use serde::Deserialize;
use serde_json::{json, Value};

use crate::assets::ASSETS;
use crate::guard::Guard;
use crate::session::{Notice, Refusal, Session, Snapshot};

/// The largest body a request may have: a program of a few million lines.
pub(crate) const BODY_LIMIT: usize = 64 << 20;
/// How long a connection may take to send a request's head, or stay idle
/// between requests: then it is closed, so that slow or silent clients cannot
/// hold connections open.
const HEAD_TIMEOUT: Duration = Duration::from_secs(5);

type Shared = State<Arc<Session>>;

/// An answer other than 200: its status and `{"error": message}`.
struct ApiError(StatusCode, String);

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (self.0, Json(json!({ "error": self.1 }))).into_response()
    }
}

fn refuse(status: StatusCode, message: impl Into<String>) -> ApiError {
    ApiError(status, message.into())
}

/// Serves the session on `listener` (bound to 127.0.0.1:`port`) until the process ends.
pub(crate) async fn serve(listener: std::net::TcpListener, session: Arc<Session>, port: u16) -> std::io::Result<()> {
    let listener = tokio::net::TcpListener::from_std(listener)?;
    let mut router = Router::new()
        .route("/api/state", get(state))
        .route("/api/heights", get(heights))
        .route("/api/verdicts", get(verdicts))
        .route("/api/path", get(path))
        .route("/api/events", get(events))
        .route("/api/files", get(files))
        .route("/api/source", post(source))
        .route("/api/save", post(save))
        .route("/api/reload", post(reload))
        .route("/api/open", post(open));
    for &(path, content_type, body) in ASSETS {
        router = router.route(path, get(move || async move { ([(CONTENT_TYPE, content_type)], body) }));
    }
    let app = router
        .fallback(|| async { refuse(StatusCode::NOT_FOUND, "no such page or request") })
        .method_not_allowed_fallback(|method: Method| async move {
            refuse(StatusCode::METHOD_NOT_ALLOWED, format!("this path does not take {method}"))
        })
        .layer(DefaultBodyLimit::max(BODY_LIMIT))
        .layer(middleware::from_fn_with_state(Arc::new(Guard::new(port)), guard))
        .with_state(session);
    loop {
        let stream = match listener.accept().await {
            Ok((stream, _)) => stream,
            // Out of file descriptors, or the like: wait for connections being served to end.
            Err(_) => {
                tokio::time::sleep(Duration::from_millis(100)).await;
                continue;
            }
        };
        let service = TowerToHyperService::new(app.clone());
        tokio::spawn(async move {
            let connection = http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(HEAD_TIMEOUT)
                .serve_connection(TokioIo::new(stream), service);
            // A connection that fails (closed, timed out, not HTTP) ends alone.
            let _ = connection.await;
        });
    }
}

async fn guard(State(guard): State<Arc<Guard>>, request: Request, next: Next) -> Response {
    match guard.admit(&request) {
        Ok(()) => next.run(request).await,
        Err((status, message)) => refuse(status, message).into_response(),
    }
}

/// Runs `work` (file I/O, a directory walk) off the server's threads.
async fn blocking<T: Send + 'static>(work: impl FnOnce() -> T + Send + 'static) -> Result<T, ApiError> {
    tokio::task::spawn_blocking(work).await.map_err(|err| refuse(StatusCode::INTERNAL_SERVER_ERROR, err.to_string()))
}

fn version(version: u64) -> Json<Value> {
    Json(json!({ "version": version }))
}

async fn state(State(session): Shared) -> Response {
    let (snapshot, busy) = session.latest();
    let (head, rest) = snapshot.state(busy);
    let length = head.len() + rest.len();
    // Two parts, so a large snapshot is not copied for each request.
    let body = Body::from_stream(futures_util::stream::iter([Ok::<_, Infallible>(head), Ok(rest)]));
    ([(CONTENT_TYPE, "application/json".to_string()), (CONTENT_LENGTH, length.to_string())], body).into_response()
}

#[derive(Deserialize)]
struct Wanted {
    version: u64,
}

/// Snapshot `N` of `?version=N`, if it is the latest.
fn wanted(session: &Session, query: Result<Query<Wanted>, QueryRejection>) -> Result<Arc<Snapshot>, ApiError> {
    let Ok(Query(Wanted { version })) = query else {
        return Err(refuse(StatusCode::BAD_REQUEST, "say which snapshot: ?version=N"));
    };
    let (snapshot, _) = session.latest();
    match version.cmp(&snapshot.version) {
        std::cmp::Ordering::Equal => Ok(snapshot),
        std::cmp::Ordering::Less => Err(refuse(
            StatusCode::GONE,
            format!("snapshot {version} has been replaced by {}: fetch /api/state again", snapshot.version),
        )),
        std::cmp::Ordering::Greater => {
            Err(refuse(StatusCode::BAD_REQUEST, format!("there is no snapshot {version} yet")))
        }
    }
}

fn binary(bytes: Bytes) -> Response {
    ([(CONTENT_TYPE, "application/octet-stream")], bytes).into_response()
}

async fn heights(State(session): Shared, query: Result<Query<Wanted>, QueryRejection>) -> Result<Response, ApiError> {
    Ok(binary(wanted(&session, query)?.heights.clone()))
}

async fn verdicts(State(session): Shared, query: Result<Query<Wanted>, QueryRejection>) -> Result<Response, ApiError> {
    Ok(binary(wanted(&session, query)?.verdicts.clone()))
}

async fn path(State(session): Shared, query: Result<Query<Wanted>, QueryRejection>) -> Result<Response, ApiError> {
    Ok(binary(wanted(&session, query)?.path.clone()))
}

/// `busy` and `snapshot` events, starting with where things stand now. A
/// client that falls behind gets the latest: only that one matters.
async fn events(State(session): Shared) -> Sse<impl Stream<Item = Result<Event, Infallible>>> {
    let stream = futures_util::stream::unfold((session.notices(), true), |(mut notices, first)| async move {
        if !first && notices.changed().await.is_err() {
            return None;
        }
        let (name, version) = match *notices.borrow_and_update() {
            Notice::Busy(version) => ("busy", version),
            Notice::Ready(version) => ("snapshot", version),
        };
        let event = Event::default().event(name).data(format!("{{\"version\":{version}}}"));
        Some((Ok(event), (notices, false)))
    });
    Sse::new(stream).keep_alive(KeepAlive::default())
}

async fn files(State(session): Shared) -> Result<Json<Value>, ApiError> {
    let folder = session.folder.display().to_string();
    let files = blocking(move || session.files()).await?;
    Ok(Json(json!({ "folder": folder, "files": files })))
}

/// The body as the program's text.
fn text(body: Result<Bytes, BytesRejection>) -> Result<String, ApiError> {
    let bytes = body.map_err(|rejection| match rejection.status() {
        StatusCode::PAYLOAD_TOO_LARGE => refuse(StatusCode::PAYLOAD_TOO_LARGE, "the body is over 64 MiB"),
        status => refuse(status, rejection.body_text()),
    })?;
    String::from_utf8(Vec::from(bytes)).map_err(|_| refuse(StatusCode::BAD_REQUEST, "the body is not UTF-8 text"))
}

async fn source(State(session): Shared, body: Result<Bytes, BytesRejection>) -> Result<Json<Value>, ApiError> {
    let text = text(body)?;
    Ok(version(session.edit(text)))
}

fn failed(err: impl std::fmt::Display) -> ApiError {
    refuse(StatusCode::INTERNAL_SERVER_ERROR, err.to_string())
}

async fn save(State(session): Shared, body: Result<Bytes, BytesRejection>) -> Result<Json<Value>, ApiError> {
    let text = text(body)?;
    Ok(version(blocking(move || session.save(text)).await?.map_err(failed)?))
}

async fn reload(State(session): Shared) -> Result<Json<Value>, ApiError> {
    Ok(version(blocking(move || session.reload()).await?.map_err(failed)?))
}

#[derive(Deserialize)]
struct Open {
    path: String,
}

async fn open(State(session): Shared, body: Result<Bytes, BytesRejection>) -> Result<Json<Value>, ApiError> {
    let Open { path } = serde_json::from_str(&text(body)?).map_err(|err| {
        refuse(StatusCode::BAD_REQUEST, format!("expected {{\"path\": \"name.ngc\"}} relative to the folder: {err}"))
    })?;
    let asked = path.clone();
    let opened = blocking(move || session.open(&asked)).await?;
    opened.map(version).map_err(|refusal| match refusal {
        Refusal::Outside => refuse(StatusCode::FORBIDDEN, format!("{path} is outside the program's folder")),
        Refusal::Missing => refuse(StatusCode::NOT_FOUND, format!("there is no file {path} in the program's folder")),
        Refusal::TooLarge => refuse(StatusCode::PAYLOAD_TOO_LARGE, format!("{path} is over 64 MiB")),
        Refusal::NotText => refuse(StatusCode::BAD_REQUEST, format!("{path} is not UTF-8 text")),
    })
}
