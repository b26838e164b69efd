"""Schemathesis hooks for the fuzz run of `make test` (scripts/fuzz.sh).

JSON Schema cannot say every rule of the spec's formats: an interval's
bounds in order, one dimension for every box, per-step arrays of `steps`
entries, and so on. The OpenAPI document lists those rules in the
descriptions of the schemas they constrain; this module implements them a
second time, in Python, from docs/formats.md (not from the Rust code), and
the check `rules_oracle` holds the service to them for every request the
fuzzer generates as schema-valid on POST /api/v1/missions,
POST /api/v1/contract and POST /api/v1/tdoa:

- schema-valid and within the rules -> must be accepted (201 / 200);
- schema-valid but breaking a rule  -> must be refused with 422 naming a
  JSON path.

Schemathesis's own `positive_data_acceptance` is off for these three
operations (it would count the second case as a wrongful refusal); every
other check stays on, `negative_data_rejection` included (schema-invalid
requests must be refused everywhere).

The one refusal of valid work is a resource limit: the `exact` contractor's
work budget and the contract endpoint's time limit answer 422 with code
`work_limit`; the check accepts it and counts it (printed at the end).
"""

import atexit
import json
import math
import sys

import schemathesis

# CPython 3.11's ast module leaks its recursion counter when a deep parse
# hits the recursion limit (python/cpython#106905); hypothesis parses
# lambda sources while it describes strategies, and one fuzz run died of
# it ("AST constructor recursion depth mismatch", a runtime error of the
# fuzzer, not of the service). A higher limit keeps that parse below it.
sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))

INF = math.inf
DIMENSIONS = {"unicycle2d": 2, "auv3d": 3, "odometry2d": 2}
CHANNELS = {
    "unicycle2d": ["speed", "heading"],
    "odometry2d": ["speed", "turn_rate"],
    "auv3d": ["roll", "pitch", "yaw", "vx", "vy", "vz"],
}
STATS = {"valid": 0, "rule_broken": 0, "work_limit": 0}

# The fields of the request bodies the oracle judges (the three operations
# above and every schema they reach), each named here once its rules from
# docs/formats.md are in this module, or once it is known to have none the
# schema does not state. scripts/fuzz.sh refuses to fuzz a document with a
# field missing here (`unruled`): a field added to the formats without its
# rules here would have the oracle count its refusals as wrongful, at
# random, in whichever run the fuzzer first draws it (the CI run of
# 2026-11-25 failed that way on `heading_drift`).
RULED = {
    "Mission": {
        "format", "name", "model", "steps", "dt", "inputs", "motion_error",
        "initial_position", "final_position", "initial_heading",
        "final_heading", "heading_error", "heading_drift", "motion_drift",
        "sensor_offset",
        "detections", "landmark_count", "landmark_region",
        "landmark_min_separation", "max_outliers", "truth", "meta",
    },
    "Inputs": {"speed", "heading", "turn_rate", "roll", "pitch", "yaw", "vx", "vy", "vz"},
    "Detection": {"step", "range", "bearing", "depth", "landmark", "region", "scan"},
    "DriftWindow": {"steps", "error", "exempt_above"},
    "Truth": {"positions", "landmarks", "matching", "headings"},
    "MissionUpload": {"file"},
    "ContractRequest": {"format", "boxes", "n", "contractor"},
    "TdoaDoc": {
        "format", "name", "propagation_speed", "receivers", "pulses",
        "emitter_count", "emitter_region", "max_outliers", "truth", "meta",
    },
    "ReceiverDoc": {"position", "clock_bias"},
    "PulseDoc": {"arrivals", "emitter", "region", "altitude", "distance_from"},
    "ArrivalDoc": {"receiver", "time"},
    "DistanceFromDoc": {"point", "range"},
    "TdoaTruthDoc": {"emitters", "matching", "positions"},
}
JUDGED = ("/api/v1/missions", "/api/v1/contract", "/api/v1/tdoa")


def unruled(doc):
    """The `schema.property` names of the judged request bodies (and every
    schema they reach through $ref) that RULED does not list."""
    schemas = doc["components"]["schemas"]
    seen, todo, missing = set(), [], []

    def refs(node):
        if isinstance(node, dict):
            ref = node.get("$ref")
            if isinstance(ref, str) and ref.startswith("#/components/schemas/"):
                todo.append(ref.rsplit("/", 1)[1])
            for v in node.values():
                refs(v)
        elif isinstance(node, list):
            for v in node:
                refs(v)

    for path in JUDGED:
        refs(doc["paths"][path]["post"]["requestBody"])
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        schema = schemas[name]
        for prop in schema.get("properties", {}):
            if prop not in RULED.get(name, ()):
                missing.append(f"{name}.{prop}")
        refs(schema)
    return sorted(missing)


class Broken(Exception):
    """A rule of the spec is broken (the message says which)."""


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def absent(obj, key):
    """An optional field: absent or null."""
    return obj.get(key) is None


def bound(v, path):
    if is_number(v):
        return float(v)
    if v in ("inf", "+inf"):
        return INF
    if v == "-inf":
        return -INF
    raise Broken(f"{path}: not a bound")


def interval(v, path):
    """An interval [lo, hi] with lo <= hi holding a real number, or x."""
    if is_number(v):
        return (float(v), float(v))
    if not isinstance(v, list) or len(v) != 2:
        raise Broken(f"{path}: not an interval")
    lo, hi = bound(v[0], path), bound(v[1], path)
    if lo > hi:
        raise Broken(f"{path}: lower bound above upper bound")
    if lo == hi and math.isinf(lo):
        raise Broken(f"{path}: holds no real number")
    return (lo, hi)


def box(v, path, dim=None):
    if not isinstance(v, list) or not v:
        raise Broken(f"{path}: not a box")
    if dim is not None and len(v) != dim:
        raise Broken(f"{path}: dimension {len(v)}, expected {dim}")
    for i, x in enumerate(v):
        interval(x, f"{path}[{i}]")
    return len(v)


def per_step(v, path, steps):
    if isinstance(v, list) and len(v) != steps:
        raise Broken(f"{path}: {len(v)} entries, expected {steps}")


def channel(v, path, steps):
    if "value" in v:
        per_step(v["value"], f"{path}.value", steps)
        if not isinstance(v["value"], list):
            raise Broken(f"{path}.value: not an array")
        per_step(v["error"], f"{path}.error", steps)
    else:
        lo, hi = v["lo"], v["hi"]
        per_step(lo, f"{path}.lo", steps)
        per_step(hi, f"{path}.hi", steps)
        for i, (a, b) in enumerate(zip(lo, hi)):
            a, b = bound(a, f"{path}.lo[{i}]"), bound(b, f"{path}.hi[{i}]")
            if a > b:
                raise Broken(f"{path}.lo[{i}]: above hi")
            if a == INF:
                raise Broken(f"{path}.lo[{i}]: inf holds no real number")
            if b == -INF:
                raise Broken(f"{path}.hi[{i}]: -inf holds no real number")


def mission_rules(m):
    """Raises Broken when a schema-valid mission breaks a rule of
    docs/formats.md that the schema cannot state."""
    model = m["model"]
    dim = DIMENSIONS[model]
    steps = m["steps"]
    box(m["initial_position"], "initial_position", dim)
    for key in ("final_position", "landmark_region"):
        if not absent(m, key):
            box(m[key], key, dim)
    inputs = m["inputs"]
    for name in inputs:
        if name not in CHANNELS[model]:
            raise Broken(f"inputs.{name}: not a channel of {model}")
    for name in CHANNELS[model]:
        if name not in inputs:
            raise Broken(f"inputs.{name}: missing")
        channel(inputs[name], f"inputs.{name}", steps)
    if not absent(m, "motion_error"):
        per_step(m["motion_error"], "motion_error", steps)
    heading_rules(m, model, steps)
    n = m.get("landmark_count")
    for i, d in enumerate(m["detections"]):
        p = f"detections[{i}]"
        if d["step"] > steps:
            raise Broken(f"{p}.step: above steps")
        interval(d["range"], f"{p}.range")
        if not absent(d, "bearing"):
            interval(d["bearing"], f"{p}.bearing")
        if not absent(d, "region"):
            box(d["region"], f"{p}.region", dim)
        if not absent(d, "depth"):
            if model != "auv3d":
                raise Broken(f"{p}.depth: auv3d only")
            interval(d["depth"], f"{p}.depth")
        if not absent(d, "landmark") and n is not None and d["landmark"] >= n:
            raise Broken(f"{p}.landmark: not below landmark_count")
    truth = m.get("truth")
    if truth is not None:
        if len(truth["positions"]) != steps + 1:
            raise Broken("truth.positions: not steps + 1 points")
        # An entry of truth.positions may be null (not known at that step).
        for key in ("positions", "landmarks"):
            for i, point in enumerate(truth[key]):
                if point is None and key == "positions":
                    continue
                if point is None or len(point) != dim:
                    raise Broken(f"truth.{key}[{i}]: dimension")
        if len(truth["matching"]) != len(m["detections"]):
            raise Broken("truth.matching: not one per detection")
        for i, x in enumerate(truth["matching"]):
            if x is not None and x >= len(truth["landmarks"]):
                raise Broken(f"truth.matching[{i}]: no such landmark")
        if not absent(truth, "headings"):
            if model != "odometry2d":
                raise Broken("truth.headings: odometry2d only")
            if len(truth["headings"]) != steps + 1:
                raise Broken("truth.headings: not steps + 1 entries")


def drift_rules(m, field, odometry):
    """heading_drift or motion_drift: odometry2d only (even an empty list
    is refused for the other models: the field itself is odometry2d's);
    each window's steps >= 1 and error >= 0; exempt_above optional, >= 0,
    at most 8 distinct values over the windows (one prefix array or exempt
    sum each in the solver)."""
    if absent(m, field):
        return
    if not odometry:
        raise Broken(f"{field}: odometry2d only")
    for i, w in enumerate(m[field]):
        if w["steps"] < 1:
            raise Broken(f"{field}[{i}].steps: below 1")
        if w["error"] < 0:
            raise Broken(f"{field}[{i}].error: negative")
    levels = set()
    for i, w in enumerate(m[field]):
        if absent(w, "exempt_above"):
            continue
        if w["exempt_above"] < 0:
            raise Broken(f"{field}[{i}].exempt_above: negative")
        levels.add(w["exempt_above"])
        if len(levels) > 8:
            raise Broken(f"{field}[{i}].exempt_above: a ninth distinct value")


def heading_rules(m, model, steps):
    """odometry2d's headings (initial_heading required, final_heading,
    heading_error, heading_drift and motion_drift optional, refused for
    the other models) and
    sensor_offset (2-D models only)."""
    odometry = model == "odometry2d"
    if odometry and absent(m, "initial_heading"):
        raise Broken("initial_heading: missing (odometry2d)")
    for key in ("initial_heading", "final_heading"):
        if not absent(m, key):
            if not odometry:
                raise Broken(f"{key}: odometry2d only")
            interval(m[key], key)
    if not absent(m, "heading_error"):
        if not odometry:
            raise Broken("heading_error: odometry2d only")
        per_step(m["heading_error"], "heading_error", steps)
    for field in ("heading_drift", "motion_drift"):
        drift_rules(m, field, odometry)
    if not absent(m, "sensor_offset") and DIMENSIONS[model] != 2:
        raise Broken("sensor_offset: 2-D models only")


def contract_rules(r):
    boxes = r["boxes"]
    dim = box(boxes[0], "boxes[0]")
    for i, b in enumerate(boxes[1:], 1):
        box(b, f"boxes[{i}]", dim)
    if r.get("contractor") == "exact" and len(boxes) > 40:
        raise Broken("boxes: exact takes at most 40 boxes")


def tdoa_rules(t):
    """Raises Broken when a schema-valid nvector-tdoa/1 problem breaks a
    rule of docs/formats.md ("TDOA passive location") that the schema
    cannot state."""
    lo, _ = interval(t["propagation_speed"], "propagation_speed")
    if lo <= 0:
        raise Broken("propagation_speed: not positive")
    receivers = t["receivers"]
    for i, r in enumerate(receivers):
        box(r["position"], f"receivers[{i}].position", 3)
        if not absent(r, "clock_bias"):
            interval(r["clock_bias"], f"receivers[{i}].clock_bias")
    n = t.get("emitter_count")
    if n is not None and not 1 <= n <= 1 << 20:
        raise Broken("emitter_count: not in 1..=2^20")
    pulses = t["pulses"]
    ids = n if n is not None else max(len(pulses), 1)
    arrivals = 0
    for k, p in enumerate(pulses):
        at = f"pulses[{k}]"
        for a, arr in enumerate(p["arrivals"]):
            if arr["receiver"] >= len(receivers):
                raise Broken(f"{at}.arrivals[{a}].receiver: no such receiver")
            interval(arr["time"], f"{at}.arrivals[{a}].time")
            arrivals += 1
        if not absent(p, "emitter") and p["emitter"] >= ids:
            raise Broken(f"{at}.emitter: not below emitter_count")
        if not absent(p, "distance_from"):
            d = p["distance_from"]
            box(d["point"], f"{at}.distance_from.point", 3)
            interval(d["range"], f"{at}.distance_from.range")
        if not absent(p, "altitude"):
            interval(p["altitude"], f"{at}.altitude")
        if not absent(p, "region"):
            box(p["region"], f"{at}.region", 3)
    q = t.get("max_outliers")
    if q is not None and q > 4294967295:
        raise Broken("max_outliers: above u32::MAX")
    if not absent(t, "emitter_region"):
        box(t["emitter_region"], "emitter_region", 3)
    if not absent(t, "meta") and not isinstance(t["meta"], dict):
        raise Broken("meta: not an object")
    truth = t.get("truth")
    if truth is not None:
        positions = truth.get("positions")
        if positions is not None:
            if len(positions) != len(pulses):
                raise Broken("truth.positions: not one per pulse")
            for i, x in enumerate(positions):
                if x is not None and len(x) != 3:
                    raise Broken(f"truth.positions[{i}]: not 3 coordinates")
        emitters = truth.get("emitters") or []
        for i, x in enumerate(emitters):
            if len(x) != 3:
                raise Broken(f"truth.emitters[{i}]: not 3 coordinates")
        matching = truth.get("matching")
        if matching is not None:
            if len(matching) != len(pulses):
                raise Broken("truth.matching: not one per pulse")
            for i, x in enumerate(matching):
                if x is not None and x >= max(len(emitters), len(pulses)):
                    raise Broken(f"truth.matching[{i}]: no such emitter")


def mission_of(case):
    body = case.body
    if isinstance(body, (bytes, str)):
        try:
            body = json.loads(body)
        except ValueError:
            return None
    if case.media_type and case.media_type.startswith("multipart/"):
        body = body.get("file") if isinstance(body, dict) else None
        if isinstance(body, (bytes, str)):
            try:
                body = json.loads(body)
            except ValueError:
                return None
    return body if isinstance(body, dict) else None


RULES = {
    ("POST", "/api/v1/missions"): (mission_rules, 201),
    ("POST", "/api/v1/contract"): (contract_rules, 200),
    ("POST", "/api/v1/tdoa"): (tdoa_rules, 202),
}


@schemathesis.check
def rules_oracle(ctx, response, case):
    """Schema-valid requests: accepted when they keep the spec's rules,
    refused with 422 and a JSON path when they break one."""
    key = (case.operation.method.upper(), case.operation.path)
    if key not in RULES:
        return None
    meta = case.meta
    if meta is None or not meta.generation.mode.is_positive:
        return None
    body = mission_of(case)
    if body is None:
        return None
    rules, success = RULES[key]
    try:
        rules(body)
    except Broken as broken:
        STATS["rule_broken"] += 1
        if response.status_code != 422:
            raise AssertionError(
                f"a request breaking a rule ({broken}) was answered "
                f"{response.status_code}, expected 422"
            )
        err = response.json().get("error", {})
        if not err.get("path"):
            raise AssertionError(f"422 without a JSON path: {err}")
        return None
    except (KeyError, TypeError, IndexError) as e:
        # The body does not have the schema's shape: not a positive case
        # this oracle can judge (schemathesis checks the schema itself).
        print(f"rules_oracle: skipped a body it cannot read ({e!r})", file=sys.stderr)
        return None
    if response.status_code == 422:
        err = response.json().get("error", {})
        if err.get("code") == "work_limit":
            STATS["work_limit"] += 1
            return None
        raise AssertionError(
            f"a request valid by the schema and the spec's rules was refused: {err}"
        )
    if response.status_code not in (success, 401, 429):
        raise AssertionError(
            f"a valid request was answered {response.status_code}, expected {success}"
        )
    STATS["valid"] += 1
    return None


@atexit.register
def _report():
    # Not when the module was only imported for `unruled` (scripts/fuzz.sh).
    if "schemathesis.cli" not in sys.modules and not any(STATS.values()):
        return
    print(
        "rules_oracle: {valid} valid bodies accepted, {rule_broken} rule-breaking "
        "bodies refused with 422, {work_limit} work_limit answers".format(**STATS),
        file=sys.stderr,
    )
