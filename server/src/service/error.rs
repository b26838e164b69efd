//! The service's one error type: every failure becomes the spec's JSON
//! error body `{"error": {"code", "message", "path"}}` with a 4xx status
//! for the caller's faults and 5xx only for the service's own.

use super::store;
use axum::body::Bytes;
use axum::extract::{FromRequest, Request};
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde::Serialize;
use serde_json::Value;
use utoipa::{IntoResponses, ToSchema};

/// A client or service error, as the spec's JSON error body.
#[derive(Debug)]
pub struct AppError {
    pub(super) status: StatusCode,
    pub(super) code: &'static str,
    pub(super) message: String,
    pub(super) path: String,
    pub(super) retry_after: Option<u64>,
}

impl AppError {
    pub(super) fn new(
        status: StatusCode,
        code: &'static str,
        message: impl Into<String>,
    ) -> AppError {
        AppError {
            status,
            code,
            message: message.into(),
            path: String::new(),
            retry_after: None,
        }
    }

    pub(super) fn at(mut self, path: impl Into<String>) -> AppError {
        self.path = path.into();
        self
    }

    pub(super) fn not_found(what: &str) -> AppError {
        AppError::new(
            StatusCode::NOT_FOUND,
            "not_found",
            format!("no such {what}"),
        )
    }

    pub(super) fn bad(code: &'static str, e: nvector_core::InputError) -> AppError {
        AppError::new(StatusCode::UNPROCESSABLE_ENTITY, code, e.message).at(e.path)
    }
}

impl From<store::StoreError> for AppError {
    fn from(e: store::StoreError) -> Self {
        tracing::error!("{e}");
        AppError::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "storage_unavailable",
            "the storage is unavailable, try again",
        )
    }
}

/// The error body of every 4xx and 5xx answer (docs/api.md).
#[derive(Serialize, ToSchema)]
#[schema(example = json!({"error": {"code": "invalid_mission", "message": "lower bound 5 is above upper bound 4", "path": "detections[3].range"}}))]
pub struct ErrorBody {
    /// What went wrong.
    pub error: ErrorDetail,
}

/// The error itself.
#[derive(Serialize, ToSchema)]
pub struct ErrorDetail {
    /// A stable, machine-readable code (`invalid_json`, `invalid_mission`,
    /// `not_found`, `queue_full`, `work_limit`, ...).
    pub code: &'static str,
    /// What is wrong, for a person.
    pub message: String,
    /// The JSON path (or query parameter) of the bad value; "" when none.
    pub path: String,
}

// The error answers that several operations share, each one response
// for `#[utoipa::path(responses(...))]` (beside the operation's own
// tuples): one wording per answer in the OpenAPI document.

/// 401: the key is missing or unknown.
#[derive(IntoResponses)]
#[response(status = 401, description = "Missing or unknown API key")]
pub struct Unauthorized(#[allow(dead_code)] ErrorBody);

/// 503: the storage did not answer.
#[derive(IntoResponses)]
#[response(status = 503, description = "Storage unavailable")]
pub struct StorageUnavailable(#[allow(dead_code)] ErrorBody);

/// 400: the body is not JSON.
#[derive(IntoResponses)]
#[response(status = 400, description = "Malformed JSON")]
pub struct MalformedJson(#[allow(dead_code)] ErrorBody);

/// 404: no job of this key has this id.
#[derive(IntoResponses)]
#[response(status = 404, description = "No such job")]
pub struct NoSuchJob(#[allow(dead_code)] ErrorBody);

/// 404: no mission of this key has this id.
#[derive(IntoResponses)]
#[response(status = 404, description = "No such mission")]
pub struct NoSuchMission(#[allow(dead_code)] ErrorBody);

/// 413: the body is above the service's limit.
#[derive(IntoResponses)]
#[response(status = 413, description = "Request body too large")]
pub struct BodyTooLarge(#[allow(dead_code)] ErrorBody);

/// 422: a field is invalid, named by its path.
#[derive(IntoResponses)]
#[response(status = 422, description = "Invalid field, with its path")]
pub struct InvalidField(#[allow(dead_code)] ErrorBody);

/// 429: the queue is full.
#[derive(IntoResponses)]
#[response(status = 429, description = "Too many queued jobs (Retry-After)")]
pub struct QueueFull(#[allow(dead_code)] ErrorBody);

impl IntoResponse for AppError {
    fn into_response(self) -> Response {
        let body = ErrorBody {
            error: ErrorDetail {
                code: self.code,
                message: self.message,
                path: self.path,
            },
        };
        let mut r = (self.status, Json(body)).into_response();
        if let Some(s) = self.retry_after {
            r.headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from(s));
        }
        if self.status == StatusCode::UNAUTHORIZED {
            // RFC 9110, 15.5.2: a 401 names the scheme it wants.
            r.headers_mut().insert(
                header::WWW_AUTHENTICATE,
                HeaderValue::from_static("Bearer realm=\"nvector\""),
            );
        }
        r
    }
}

pub(super) type ApiResult<T> = Result<T, AppError>;

/// The answers the framework gives on its own under `/api/` (405 for a
/// method a route does not have; 400 for a path segment
/// that is not UTF-8; 404 past the routes) carry the spec's JSON error
/// body too, as every 4xx and 5xx must. A JSON answer passes untouched;
/// the other headers are kept; the framework's text, if any, becomes the
/// message.
pub(super) async fn json_errors(req: Request, next: axum::middleware::Next) -> Response {
    let api = req.uri().path().starts_with("/api/");
    let method = req.method().clone();
    let resp = next.run(req).await;
    let status = resp.status();
    if !api || !(status.is_client_error() || status.is_server_error()) {
        return resp;
    }
    let json = resp
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|t| t.starts_with("application/json"));
    if json {
        return resp;
    }
    let (parts, body) = resp.into_parts();
    let text = axum::body::to_bytes(body, 16 * 1024)
        .await
        .unwrap_or_default();
    let text = String::from_utf8_lossy(&text).trim().to_string();
    let (code, message) = match status {
        // axum adds the `Allow` header to a 405 outside this layer.
        StatusCode::METHOD_NOT_ALLOWED => (
            "method_not_allowed",
            format!("method {method} is not allowed here (the Allow header lists those that are)"),
        ),
        StatusCode::NOT_FOUND => ("not_found", "no such endpoint".to_string()),
        StatusCode::URI_TOO_LONG => ("uri_too_long", "the URI is too long".to_string()),
        s if s.is_server_error() => ("internal", "the service failed; this is a bug".to_string()),
        s => (
            "bad_request",
            if text.is_empty() {
                s.canonical_reason().unwrap_or("bad request").to_string()
            } else {
                text
            },
        ),
    };
    // axum's path rejection names the segment: "Invalid URL: ... in `id`".
    let path = message
        .split_once("in `")
        .and_then(|(_, rest)| rest.split_once('`'))
        .map_or(String::new(), |(name, _)| name.to_string());
    let mut r = AppError::new(status, code, message)
        .at(path)
        .into_response();
    for (name, value) in &parts.headers {
        if name != header::CONTENT_TYPE && name != header::CONTENT_LENGTH {
            r.headers_mut().insert(name.clone(), value.clone());
        }
    }
    r
}

/// A JSON body; a syntax error (a NaN or Infinity literal, a number out
/// of range, a truncated body) is a 400 whose `path` names the value being
/// read there (`nvector_core::format::syntax_path`), and so is a key
/// repeated in one object outside `meta` (a `Value` keeps the last one
/// silently, while the CLI's typed read refuses a repeated field).
pub(super) fn parse_json(bytes: &[u8]) -> ApiResult<Value> {
    let v = parse_json_value(bytes)?;
    if let Some(path) = std::str::from_utf8(bytes)
        .ok()
        .and_then(nvector_core::format::duplicate_key)
    {
        return Err(AppError::new(
            StatusCode::BAD_REQUEST,
            "invalid_json",
            format!("duplicate key `{path}`: a key may appear once in an object"),
        )
        .at(path));
    }
    Ok(v)
}

/// A JSON text read as a `Value`, syntax errors as in [`parse_json`], repeated
/// keys not checked: for the service's own stored texts (results).
pub(super) fn parse_json_value(bytes: &[u8]) -> ApiResult<Value> {
    serde_json::from_slice(bytes).map_err(|e| {
        let path = std::str::from_utf8(bytes).map_or(String::new(), |text| {
            nvector_core::format::syntax_path(text, e.line(), e.column())
        });
        AppError::new(
            StatusCode::BAD_REQUEST,
            "invalid_json",
            format!("invalid JSON: {e}"),
        )
        .at(path)
    })
}

/// A request body type read by [`Body`]: its error code for a body that is
/// JSON but not this type (422).
pub(super) trait RequestBody: serde::de::DeserializeOwned {
    /// `invalid_job`, `invalid_request`, ...
    const CODE: &'static str;
}

/// A JSON body read as `T` by core's format reader (the JSON path of the
/// bad value in every error): 413 past the body limit, 400 for text that is
/// not JSON, 422 naming the path for JSON that is not a `T` (an object of
/// `T`'s fields only).
pub(super) struct Body<T>(pub T);

impl<S: Send + Sync, T: RequestBody> FromRequest<S> for Body<T> {
    type Rejection = AppError;

    async fn from_request(req: Request, state: &S) -> ApiResult<Body<T>> {
        let bytes = Bytes::from_request(req, state).await.map_err(|e| {
            AppError::new(
                StatusCode::PAYLOAD_TOO_LARGE,
                "body_too_large",
                e.body_text(),
            )
        })?;
        let text = match std::str::from_utf8(&bytes) {
            Ok(t) if serde_json::from_str::<serde::de::IgnoredAny>(t).is_ok() => t,
            _ => {
                return Err(parse_json(&bytes).err().unwrap_or_else(|| {
                    AppError::new(StatusCode::BAD_REQUEST, "invalid_json", "invalid JSON")
                }))
            }
        };
        nvector_core::format::from_str::<nvector_core::format::Object<T>>(text)
            .map(|o| Body(o.0))
            .map_err(|e| AppError::bad(T::CODE, e))
    }
}
