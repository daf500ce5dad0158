//! The page's files, built into the binary so `ger view` needs nothing beside
//! it. The server knows only their paths and types, never their content.

/// URL path, content type, body.
pub(super) const ASSETS: &[(&str, &str, &str)] = &[
    ("/", "text/html; charset=utf-8", include_str!("assets/index.html")),
    ("/app.js", "text/javascript; charset=utf-8", include_str!("assets/app.js")),
    ("/style.css", "text/css; charset=utf-8", include_str!("assets/style.css")),
];
