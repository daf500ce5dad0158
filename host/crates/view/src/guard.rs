//! What `ger view`'s server lets through, judged from a request's head
//! alone (it needs only the `http` crate's types). Public so that the fuzz
//! target `view_request` (host/fuzz) calls it on heads it reads from any bytes.

use http::header::{HOST, ORIGIN};
use http::{Method, Request, StatusCode, Version};

/// The most header bytes a request may have.
const HEADER_LIMIT: usize = 64 << 10;

/// What a request must say of where it is going and where it comes from.
pub struct Guard {
    /// The `Host` headers the page is reached by.
    hosts: [String; 2],
}

impl Guard {
    /// The guard of a server on 127.0.0.1:`port`.
    pub fn new(port: u16) -> Guard {
        Guard { hosts: [format!("127.0.0.1:{port}"), format!("localhost:{port}")] }
    }

    /// Refuses what no page of ours sends, with the status and message of the
    /// answer. A foreign `Host` is a DNS-rebinding attack (another site's
    /// script reaching us under its own name); a foreign `Origin` on a change
    /// is another site's page posting to us. A request without `Origin` is not
    /// from a browser page (browsers always send one on a POST), so it is let
    /// through like curl.
    pub fn admit<B>(&self, request: &Request<B>) -> Result<(), (StatusCode, String)> {
        let refuse = |status, message: &str| Err((status, message.to_string()));
        if request.version() != Version::HTTP_11 {
            return refuse(StatusCode::BAD_REQUEST, "ger view speaks HTTP/1.1 only");
        }
        let headers = request.headers();
        let size: usize = headers.iter().map(|(name, value)| name.as_str().len() + value.len() + 4).sum();
        if size > HEADER_LIMIT {
            return refuse(StatusCode::REQUEST_HEADER_FIELDS_TOO_LARGE, "the headers are over 64 KiB");
        }
        let mut hosts = headers.get_all(HOST).iter();
        let host = hosts.next().and_then(|h| h.to_str().ok()).unwrap_or_default();
        if hosts.next().is_some() {
            // RFC 9112, 3.2: which one a proxy on the way read is anyone's guess.
            return refuse(StatusCode::BAD_REQUEST, "a request has one Host header, not several");
        }
        let ours = |name: &str| self.hosts.iter().any(|h| h == name);
        if !ours(host) {
            return refuse(StatusCode::FORBIDDEN, &format!("the Host must be {} or {}", self.hosts[0], self.hosts[1]));
        }
        // An absolute-form target (`GET http://host/path`) names the host that counts (RFC 9112, 3.2.2).
        if let Some(authority) = request.uri().authority() {
            if !ours(authority.as_str()) {
                let message = format!("the request is for {authority}, not {} or {}", self.hosts[0], self.hosts[1]);
                return refuse(StatusCode::FORBIDDEN, &message);
            }
        }
        if !matches!(*request.method(), Method::GET | Method::HEAD) {
            if let Some(origin) = headers.get(ORIGIN) {
                if origin.as_bytes() != format!("http://{host}").as_bytes() {
                    return refuse(StatusCode::FORBIDDEN, "a request from another site's page");
                }
            }
        }
        Ok(())
    }
}
