//! `ger view`'s check of a request's head (`ger_view::guard::Guard::admit`),
//! on heads read from any bytes the way hyper reads them (httparse into
//! http's types). A head hyper could not read is answered by hyper, not
//! ger, so it is skipped.
#![no_main]

use ger_view::guard::Guard;
use http::header::HOST;
use http::{HeaderName, HeaderValue, Request, Version};
use libfuzzer_sys::fuzz_target;

const PORT: u16 = 8274;

fuzz_target!(|bytes: &[u8]| {
    let Some(request) = head(bytes) else { return };
    let admitted = Guard::new(PORT).admit(&request);
    if admitted.is_ok() {
        // Whatever else it allows, the guard lets through only requests for this server.
        let hosts: Vec<_> = request.headers().get_all(HOST).iter().collect();
        assert!(
            matches!(hosts[..], [host] if host == "127.0.0.1:8274" || host == "localhost:8274"),
            "admitted with Host {hosts:?}"
        );
    }
});

fn head(bytes: &[u8]) -> Option<Request<()>> {
    let mut headers = [httparse::EMPTY_HEADER; 64];
    let mut parsed = httparse::Request::new(&mut headers);
    if !parsed.parse(bytes).ok()?.is_complete() {
        return None;
    }
    let mut request = Request::builder().method(parsed.method?).uri(parsed.path?).version(if parsed.version? == 1 {
        Version::HTTP_11
    } else {
        Version::HTTP_10
    });
    for header in parsed.headers.iter() {
        let name = HeaderName::from_bytes(header.name.as_bytes()).ok()?;
        request = request.header(name, HeaderValue::from_bytes(header.value).ok()?);
    }
    request.body(()).ok()
}
