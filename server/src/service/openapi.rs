//! The OpenAPI 3 document of the service, built from one table of
//! operations that the router is tested against
//! (server/tests/http_openapi.rs sends real requests and checks every
//! status and body against this document).

use serde_json::{json, Map, Value};

/// One documented operation: method, path, summary, request body schema,
/// responses (status, description, schema name or "").
pub struct Operation {
    /// HTTP method, lower case.
    pub method: &'static str,
    /// Path template.
    pub path: &'static str,
    /// Summary.
    pub summary: &'static str,
    /// Request body schema name ("" when none).
    pub request: &'static str,
    /// Responses.
    pub responses: &'static [(u16, &'static str, &'static str)],
}

const ERRORS: [(u16, &str, &str); 6] = [
    (400, "malformed request (JSON, query, multipart)", "Error"),
    (401, "missing or unknown API key", "Error"),
    (413, "request or mission too large", "Error"),
    (415, "unsupported content type", "Error"),
    (422, "invalid content, with the JSON path", "Error"),
    (503, "storage unavailable", "Error"),
];

/// Every operation of spec/api.md.
pub const OPERATIONS: &[Operation] = &[
    Operation {
        method: "post",
        path: "/api/v1/missions",
        summary: "Store a mission (JSON body or multipart `file`)",
        request: "Mission",
        responses: &[
            (201, "stored", "MissionSummary"),
            ERRORS[0],
            ERRORS[1],
            ERRORS[2],
            ERRORS[3],
            ERRORS[4],
            ERRORS[5],
        ],
    },
    Operation {
        method: "get",
        path: "/api/v1/missions",
        summary: "List missions (`limit`, `after`)",
        request: "",
        responses: &[
            (200, "a page of missions", "MissionList"),
            ERRORS[0],
            ERRORS[1],
            ERRORS[5],
        ],
    },
    Operation {
        method: "get",
        path: "/api/v1/missions/{id}",
        summary: "The mission as stored",
        request: "",
        responses: &[
            (200, "the mission", "Mission"),
            ERRORS[1],
            (404, "no such mission", "Error"),
            ERRORS[5],
        ],
    },
    Operation {
        method: "delete",
        path: "/api/v1/missions/{id}",
        summary: "Delete a mission and its jobs",
        request: "",
        responses: &[
            (204, "deleted", ""),
            ERRORS[1],
            (404, "no such mission", "Error"),
            ERRORS[5],
        ],
    },
    Operation {
        method: "post",
        path: "/api/v1/jobs",
        summary: "Queue a SLAM job",
        request: "JobRequest",
        responses: &[
            (202, "queued", "JobQueued"),
            ERRORS[0],
            ERRORS[1],
            (404, "no such mission", "Error"),
            ERRORS[4],
            (429, "queue full (Retry-After)", "Error"),
            ERRORS[5],
        ],
    },
    Operation {
        method: "get",
        path: "/api/v1/jobs/{id}",
        summary: "A job and its progress",
        request: "",
        responses: &[
            (200, "the job", "Job"),
            ERRORS[1],
            (404, "no such job", "Error"),
            ERRORS[5],
        ],
    },
    Operation {
        method: "delete",
        path: "/api/v1/jobs/{id}",
        summary: "Cancel a queued or running job",
        request: "",
        responses: &[
            (202, "cancelled", "JobQueued"),
            ERRORS[1],
            (404, "no such job", "Error"),
            (409, "the job has ended", "Error"),
            ERRORS[5],
        ],
    },
    Operation {
        method: "get",
        path: "/api/v1/jobs/{id}/events",
        summary: "Progress as Server-Sent Events until the job ends",
        request: "",
        responses: &[
            (
                200,
                "text/event-stream of Job objects (events `progress`, `end`)",
                "",
            ),
            ERRORS[1],
            (404, "no such job", "Error"),
        ],
    },
    Operation {
        method: "get",
        path: "/api/v1/jobs/{id}/result",
        summary: "The result (`format` = json, csv or svg)",
        request: "",
        responses: &[
            (200, "the result", "Result"),
            ERRORS[0],
            ERRORS[1],
            (404, "no such job", "Error"),
            (409, "the job is not done", "Error"),
            ERRORS[5],
        ],
    },
    Operation {
        method: "post",
        path: "/api/v1/contract",
        summary: "One atmost_nvector contraction (k <= 100000)",
        request: "ContractRequest",
        responses: &[
            (200, "the contraction", "ContractResponse"),
            ERRORS[0],
            ERRORS[1],
            ERRORS[2],
            ERRORS[4],
        ],
    },
    Operation {
        method: "post",
        path: "/api/v1/simulate",
        summary: "A simulated mission, returned and stored",
        request: "SimulateRequest",
        responses: &[
            (201, "stored", "Simulated"),
            ERRORS[0],
            ERRORS[1],
            ERRORS[2],
            ERRORS[4],
            ERRORS[5],
        ],
    },
    Operation {
        method: "get",
        path: "/healthz",
        summary: "Liveness",
        request: "",
        responses: &[(200, "alive", "")],
    },
    Operation {
        method: "get",
        path: "/readyz",
        summary: "Storage reachable",
        request: "",
        responses: &[(200, "ready", ""), ERRORS[5]],
    },
    Operation {
        method: "get",
        path: "/metrics",
        summary: "Prometheus text: jobs by state, job durations, requests",
        request: "",
        responses: &[(200, "metrics", ""), ERRORS[5]],
    },
    Operation {
        method: "get",
        path: "/api/v1/openapi.json",
        summary: "This document",
        request: "",
        responses: &[(200, "the OpenAPI document", "")],
    },
];

fn object(required: &[&str], props: Value) -> Value {
    json!({"type": "object", "required": required, "properties": props})
}

/// Schemas: the required top-level properties of each body.
pub fn schemas() -> Value {
    json!({
        "Error": object(&["error"], json!({"error": object(&["code", "message", "path"], json!({
            "code": {"type": "string"}, "message": {"type": "string"}, "path": {"type": "string"}}))})),
        "Mission": object(&["format", "model", "dt", "steps", "initial_position", "inputs", "detections"], json!({"format": {"type": "string", "enum": ["nvector-mission/1"]}})),
        "MissionSummary": object(&["id", "name", "steps", "detections"], json!({"id": {"type": "string"}, "name": {"type": "string"}, "steps": {"type": "integer"}, "detections": {"type": "integer"}})),
        "MissionList": object(&["missions", "next"], json!({"missions": {"type": "array", "items": {"$ref": "#/components/schemas/MissionSummary"}}})),
        "JobRequest": object(&["mission"], json!({"mission": {"type": "string"}, "contractor": {"type": "string", "enum": ["none", "nvalue", "projection", "independent", "best"]}, "max_rounds": {"type": "integer"}, "time_limit_s": {"type": "number"}})),
        "JobQueued": object(&["id", "state"], json!({"id": {"type": "string"}, "state": {"type": "string"}})),
        "Job": object(&["id", "mission", "state", "progress"], json!({"state": {"type": "string", "enum": ["queued", "running", "done", "failed", "cancelled"]},
            "progress": object(&["round", "max_trajectory_diameter", "fraction"], json!({})),
            "error": {"type": "string"}, "attempts": {"type": "integer", "description": "times a worker claimed the job (1 unless re-queued)"},
            "runner": {"type": "string", "description": "id of the nvector process that runs or ran the job"}})),
        "Result": object(&["format", "mission", "status", "trajectory", "detections", "landmarks", "matching", "metrics"], json!({"format": {"type": "string", "enum": ["nvector-result/1"]}})),
        "ContractRequest": object(&["format", "n", "boxes"], json!({"format": {"type": "string", "enum": ["nvector-contract/1"]}})),
        "ContractResponse": object(&["format", "status", "boxes", "groups", "min_distinct", "stats"], json!({"format": {"type": "string", "enum": ["nvector-contract-result/1"]}})),
        "SimulateRequest": object(&["scenario"], json!({"scenario": {"type": "string", "enum": ["paper", "auv"]}, "seed": {"type": "integer"}, "steps": {"type": "integer"}, "landmarks": {"type": "integer"}, "operator": {"type": "boolean"}, "noise": {"type": "number"}})),
        "Simulated": object(&["id", "name", "steps", "detections", "mission"], json!({})),
    })
}

/// The whole document.
pub fn document() -> Value {
    let mut paths = Map::new();
    for op in OPERATIONS {
        let entry = paths
            .entry(op.path.to_string())
            .or_insert_with(|| json!({}));
        let mut responses = Map::new();
        for (status, desc, schema) in op.responses {
            let mut r = json!({"description": desc});
            if !schema.is_empty() {
                r["content"] = json!({"application/json": {"schema": {"$ref": format!("#/components/schemas/{schema}")}}});
            }
            responses.insert(status.to_string(), r);
        }
        let mut o = json!({"summary": op.summary, "responses": responses});
        if op.path.contains("{id}") {
            o["parameters"] = json!([{"name": "id", "in": "path", "required": true, "schema": {"type": "string"}}]);
        }
        if !op.request.is_empty() {
            o["requestBody"] = json!({"required": true, "content": {"application/json": {"schema": {"$ref": format!("#/components/schemas/{}", op.request)}}}});
        }
        entry[op.method] = o;
    }
    json!({
        "openapi": "3.0.3",
        "info": {"title": "nvector", "version": env!("CARGO_PKG_VERSION"),
                 "description": "Guaranteed interval SLAM with the nvector global constraint (spec/api.md)."},
        "paths": paths,
        "components": {
            "schemas": schemas(),
            "securitySchemes": {"apiKey": {"type": "http", "scheme": "bearer"}}
        }
    })
}
