//! Just enough HTTP/1.1 for the replay server: request line, headers, `Content-Length` and
//! chunked request bodies, `Expect: 100-continue`, keep-alive, and response heads.

use std::collections::BTreeMap;
use std::io::{self, BufRead, Read, Write};

use crate::RecordedRequest;

/// Longest request line, header line or chunk-size line, bytes.
const MAX_LINE_BYTES: u64 = 64 * 1024;
/// Most header lines in one request.
const MAX_HEADERS: usize = 256;
/// Largest request body, bytes (images in base64 are tens of MB).
const MAX_BODY_BYTES: usize = 1 << 30;

/// A parsed request and whether the connection stays open after its answer.
pub(crate) struct Incoming {
    pub request: RecordedRequest,
    pub keep_alive: bool,
}

fn bad(reason: impl Into<String>) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, reason.into())
}

/// One line without its line end; `None` at a clean end of stream.
fn read_line(reader: &mut impl BufRead) -> io::Result<Option<String>> {
    let mut line = Vec::new();
    let read = reader
        .by_ref()
        .take(MAX_LINE_BYTES)
        .read_until(b'\n', &mut line)?;
    if read == 0 {
        return Ok(None);
    }
    if line.last() != Some(&b'\n') {
        return Err(if read as u64 >= MAX_LINE_BYTES {
            bad("line too long")
        } else {
            io::Error::new(io::ErrorKind::UnexpectedEof, "connection closed mid-line")
        });
    }
    line.pop();
    if line.last() == Some(&b'\r') {
        line.pop();
    }
    Ok(Some(String::from_utf8_lossy(&line).into_owned()))
}

/// Reads the next request from `reader`; answers `100 Continue` on `writer` when asked to.
/// `Ok(None)` when the client closed the connection between requests.
pub(crate) fn read_request(
    reader: &mut impl BufRead,
    writer: &mut impl Write,
) -> io::Result<Option<Incoming>> {
    let request_line = loop {
        match read_line(reader)? {
            None => return Ok(None),
            Some(line) if line.trim().is_empty() => {}
            Some(line) => break line,
        }
    };
    let mut parts = request_line.split_whitespace();
    let (Some(method), Some(path), Some(version)) = (parts.next(), parts.next(), parts.next())
    else {
        return Err(bad(format!("malformed request line {request_line:?}")));
    };
    let http10 = version.eq_ignore_ascii_case("HTTP/1.0");
    let mut headers = BTreeMap::<String, String>::new();
    for _ in 0..=MAX_HEADERS {
        let line = read_line(reader)?
            .ok_or_else(|| io::Error::new(io::ErrorKind::UnexpectedEof, "closed in headers"))?;
        if line.is_empty() {
            return finish(reader, writer, method, path, http10, headers).map(Some);
        }
        let (name, value) = line
            .split_once(':')
            .ok_or_else(|| bad(format!("malformed header line {line:?}")))?;
        let name = name.trim().to_ascii_lowercase();
        let value = value.trim().to_owned();
        headers
            .entry(name)
            .and_modify(|existing| {
                existing.push_str(", ");
                existing.push_str(&value);
            })
            .or_insert(value);
    }
    Err(bad("too many header lines"))
}

fn finish(
    reader: &mut impl BufRead,
    writer: &mut impl Write,
    method: &str,
    path: &str,
    http10: bool,
    headers: BTreeMap<String, String>,
) -> io::Result<Incoming> {
    let header_has = |name: &str, token: &str| {
        headers.get(name).is_some_and(|value| {
            value
                .split(',')
                .any(|part| part.trim().eq_ignore_ascii_case(token))
        })
    };
    if header_has("expect", "100-continue") {
        writer.write_all(b"HTTP/1.1 100 Continue\r\n\r\n")?;
        writer.flush()?;
    }
    let body = if header_has("transfer-encoding", "chunked") {
        read_chunked(reader)?
    } else if let Some(length) = headers.get("content-length") {
        let length: usize = length
            .parse()
            .map_err(|_| bad(format!("Content-Length {length:?} is not a number")))?;
        if length > MAX_BODY_BYTES {
            return Err(bad(format!("body of {length} bytes is too large")));
        }
        let mut body = vec![0; length];
        reader.read_exact(&mut body)?;
        body
    } else {
        Vec::new()
    };
    let keep_alive = if http10 {
        header_has("connection", "keep-alive")
    } else {
        !header_has("connection", "close")
    };
    Ok(Incoming {
        request: RecordedRequest {
            method: method.to_owned(),
            path: path.to_owned(),
            headers,
            body,
        },
        keep_alive,
    })
}

fn read_chunked(reader: &mut impl BufRead) -> io::Result<Vec<u8>> {
    let mut body = Vec::new();
    loop {
        let line = read_line(reader)?
            .ok_or_else(|| io::Error::new(io::ErrorKind::UnexpectedEof, "closed in chunk"))?;
        let size_text = line.split(';').next().unwrap_or_default().trim();
        let size = usize::from_str_radix(size_text, 16)
            .map_err(|_| bad(format!("malformed chunk size {line:?}")))?;
        if size == 0 {
            // Trailer fields up to the empty line.
            while let Some(trailer) = read_line(reader)? {
                if trailer.is_empty() {
                    break;
                }
            }
            return Ok(body);
        }
        if body.len().saturating_add(size) > MAX_BODY_BYTES {
            return Err(bad("chunked body is too large"));
        }
        let start = body.len();
        body.resize(start + size, 0);
        reader.read_exact(&mut body[start..])?;
        match read_line(reader)? {
            Some(rest) if rest.is_empty() => {}
            _ => return Err(bad("chunk not followed by CRLF")),
        }
    }
}

/// The status line and headers of a response whose body has `content_length` bytes.
pub(crate) fn response_head(
    status: u16,
    headers: &BTreeMap<String, String>,
    json_content_type: bool,
    content_length: usize,
    keep_alive: bool,
) -> Vec<u8> {
    let mut head = format!("HTTP/1.1 {status} {}\r\n", reason(status));
    for (name, value) in headers {
        if name.eq_ignore_ascii_case("content-length") || name.eq_ignore_ascii_case("connection") {
            continue;
        }
        head.push_str(&format!("{name}: {value}\r\n"));
    }
    if json_content_type {
        head.push_str("Content-Type: application/json\r\n");
    }
    head.push_str(&format!("Content-Length: {content_length}\r\n"));
    head.push_str(if keep_alive {
        "Connection: keep-alive\r\n\r\n"
    } else {
        "Connection: close\r\n\r\n"
    });
    head.into_bytes()
}

/// Reason phrase of the common statuses.
fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        201 => "Created",
        204 => "No Content",
        400 => "Bad Request",
        401 => "Unauthorized",
        403 => "Forbidden",
        404 => "Not Found",
        408 => "Request Timeout",
        413 => "Payload Too Large",
        422 => "Unprocessable Entity",
        429 => "Too Many Requests",
        500 => "Internal Server Error",
        501 => "Not Implemented",
        502 => "Bad Gateway",
        503 => "Service Unavailable",
        504 => "Gateway Timeout",
        _ => "Status",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(raw: &[u8]) -> io::Result<Option<Incoming>> {
        let mut reader = io::BufReader::new(raw);
        let mut sink = Vec::new();
        read_request(&mut reader, &mut sink)
    }

    #[test]
    fn chunked_body_with_extension_and_trailer_is_joined() {
        let raw = b"POST /x HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n3;ext=1\r\nabc\r\na\r\n0123456789\r\n0\r\nX-T: 1\r\n\r\n";
        let incoming = parse(raw).unwrap().unwrap();
        assert_eq!(incoming.request.body, b"abc0123456789");
        assert!(incoming.keep_alive);
    }

    #[test]
    fn http10_closes_unless_asked_and_duplicate_headers_join() {
        let raw = b"GET /a?b=1 HTTP/1.0\r\nX-A: 1\r\nx-a: 2\r\n\r\n";
        let incoming = parse(raw).unwrap().unwrap();
        assert!(!incoming.keep_alive);
        assert_eq!(incoming.request.path, "/a?b=1");
        assert_eq!(incoming.request.headers["x-a"], "1, 2");
    }

    #[test]
    fn malformed_request_line_and_short_body_are_errors() {
        assert!(parse(b"GARBAGE\r\n\r\n").is_err());
        assert!(parse(b"POST / HTTP/1.1\r\nContent-Length: 10\r\n\r\nabc").is_err());
        assert!(parse(b"").unwrap().is_none());
    }
}
