//! The page `ger view` serves, compiled into the binary. The files are
//! hand-written (no framework, no build step); what they ask of the server is
//! host/docs/view-api.md.

/// URL path, content type, body.
pub(crate) const ASSETS: &[(&str, &str, &str)] = &[
    ("/", "text/html; charset=utf-8", include_str!("assets/index.html")),
    ("/app.js", "text/javascript; charset=utf-8", include_str!("assets/app.js")),
    ("/style.css", "text/css; charset=utf-8", include_str!("assets/style.css")),
];
