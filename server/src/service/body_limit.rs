//! The request body limit (`--max-body`), answered so that every client
//! can read it.
//!
//! A body over the limit gets the 413 `body_too_large` error. Answering it
//! while the client is still sending and then closing the connection makes
//! the kernel reset it: a client that writes its whole body before reading
//! (Python's `urllib`, many scripts) sees a broken pipe and never the 413.
//! So the rest of an oversized body is read and dropped first (up to
//! [`DRAIN_CAP`] bytes within [`DRAIN_TIME`]; past that the answer is sent
//! and the connection closed, as before). Nothing over the limit is kept in
//! memory: the limit is checked before each chunk is stored.
//!
//! - A `Content-Length` over the limit: answered at once, after draining;
//!   with `Expect: 100-continue` the client has sent nothing yet, so no
//!   drain (the body is never asked for).
//! - A body of unknown length (chunked): read up to the limit, then handed
//!   on in one piece; past the limit, drained and answered 413.
//! - A declared length within the limit: handed on as it is (hyper holds
//!   the client to its `Content-Length`; `DefaultBodyLimit` stays behind
//!   this as the extractors' own guard).

use super::{AppError, AppState};
use axum::body::{Body, Bytes};
use axum::extract::{Request, State};
use axum::http::{header, HeaderValue, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use futures_util::StreamExt;
use std::time::Duration;

/// The most bytes of an oversized body read (and dropped) before the 413.
pub const DRAIN_CAP: u64 = 1 << 30;
/// The longest time spent draining an oversized body.
pub const DRAIN_TIME: Duration = Duration::from_secs(30);

/// The middleware: see the module's documentation.
pub(super) async fn limit_body(
    State(state): State<AppState>,
    req: Request,
    next: Next,
) -> Response {
    let max = state.config.max_body;
    let declared = req
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    let chunked = req
        .headers()
        .get(header::TRANSFER_ENCODING)
        .is_some_and(|v| v.as_bytes().eq_ignore_ascii_case(b"chunked"));
    match declared {
        Some(n) if n > max as u64 => {
            let expects = req
                .headers()
                .get(header::EXPECT)
                .is_some_and(|v| v.as_bytes().eq_ignore_ascii_case(b"100-continue"));
            let drained = expects || drain(req.into_body()).await;
            too_large(
                format!(
                    "the request body of {n} bytes is above this service's limit of {max} bytes"
                ),
                drained,
            )
        }
        Some(_) => next.run(req).await,
        None if !chunked => next.run(req).await,
        None => {
            let (parts, body) = req.into_parts();
            let mut stream = body.into_data_stream();
            let mut kept: Vec<u8> = Vec::new();
            while let Some(chunk) = stream.next().await {
                let Ok(chunk) = chunk else {
                    return AppError::new(
                        StatusCode::BAD_REQUEST,
                        "invalid_body",
                        "the request body could not be read to its end",
                    )
                    .into_response();
                };
                if kept.len() + chunk.len() > max {
                    let drained = drain_stream(stream).await;
                    return too_large(
                        format!("the request body is above this service's limit of {max} bytes"),
                        drained,
                    );
                }
                kept.extend_from_slice(&chunk);
            }
            let req = Request::from_parts(parts, Body::from(Bytes::from(kept)));
            next.run(req).await
        }
    }
}

/// The 413 answer; `Connection: close` when the body was not read to its
/// end (the connection cannot carry another request).
fn too_large(message: String, drained: bool) -> Response {
    let mut resp =
        AppError::new(StatusCode::PAYLOAD_TOO_LARGE, "body_too_large", message).into_response();
    if !drained {
        resp.headers_mut()
            .insert(header::CONNECTION, HeaderValue::from_static("close"));
    }
    resp
}

/// Reads and drops a body; true when it was read to its end within the
/// caps.
async fn drain(body: Body) -> bool {
    drain_stream(body.into_data_stream()).await
}

async fn drain_stream(mut stream: axum::body::BodyDataStream) -> bool {
    let read = async {
        let mut total: u64 = 0;
        while let Some(chunk) = stream.next().await {
            let Ok(chunk) = chunk else { return false };
            total += chunk.len() as u64;
            if total > DRAIN_CAP {
                return false;
            }
        }
        true
    };
    tokio::time::timeout(DRAIN_TIME, read)
        .await
        .unwrap_or(false)
}
