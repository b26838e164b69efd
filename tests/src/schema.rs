//! A small JSON Schema (2020-12) validator for the OpenAPI document's
//! schemas: the keywords the document uses (`$ref` into the document,
//! `type`, `enum`, `const`, numeric bounds, `minItems` / `maxItems`,
//! `items`, `required`, `properties`, `additionalProperties`, `oneOf`,
//! `anyOf`, `allOf`). An unknown keyword is ignored, as JSON Schema says;
//! `pattern`, `format` and `propertyNames` are not checked.

use serde_json::Value;

/// The errors of `value` against `schema` (empty when it conforms); `doc`
/// resolves `$ref`s such as `#/components/schemas/Mission`.
pub fn validate(doc: &Value, schema: &Value, value: &Value) -> Vec<String> {
    let mut errors = Vec::new();
    check(doc, schema, value, "$", &mut errors);
    errors
}

fn type_matches(t: &str, v: &Value) -> bool {
    match t {
        "null" => v.is_null(),
        "boolean" => v.is_boolean(),
        "string" => v.is_string(),
        "array" => v.is_array(),
        "object" => v.is_object(),
        "number" => v.is_number(),
        "integer" => v.as_f64().is_some_and(|x| x.fract() == 0.0),
        _ => true,
    }
}

fn check(doc: &Value, schema: &Value, v: &Value, at: &str, errors: &mut Vec<String>) {
    let Some(s) = schema.as_object() else {
        if schema == &Value::Bool(false) {
            errors.push(format!("{at}: no value is allowed here"));
        }
        return;
    };
    if let Some(r) = s.get("$ref").and_then(Value::as_str) {
        match doc.pointer(r.trim_start_matches('#')) {
            Some(target) => check(doc, target, v, at, errors),
            None => errors.push(format!("{at}: dangling $ref {r}")),
        }
    }
    if let Some(t) = s.get("type") {
        let ok = match t {
            Value::String(t) => type_matches(t, v),
            Value::Array(ts) => ts
                .iter()
                .filter_map(Value::as_str)
                .any(|t| type_matches(t, v)),
            _ => true,
        };
        if !ok {
            errors.push(format!("{at}: {v} is not of type {t}"));
            return;
        }
    }
    if let Some(e) = s.get("enum").and_then(Value::as_array) {
        if !e.contains(v) {
            errors.push(format!(
                "{at}: {v} is not one of {}",
                Value::Array(e.clone())
            ));
        }
    }
    if let Some(c) = s.get("const") {
        if c != v {
            errors.push(format!("{at}: {v} is not {c}"));
        }
    }
    if let Some(x) = v.as_f64() {
        let bound = |k: &str| s.get(k).and_then(Value::as_f64);
        if bound("minimum").is_some_and(|m| x < m)
            || bound("maximum").is_some_and(|m| x > m)
            || bound("exclusiveMinimum").is_some_and(|m| x <= m)
            || bound("exclusiveMaximum").is_some_and(|m| x >= m)
        {
            errors.push(format!("{at}: {x} is out of bounds"));
        }
    }
    if let Some(a) = v.as_array() {
        let len = |k: &str| s.get(k).and_then(Value::as_u64);
        if len("minItems").is_some_and(|m| (a.len() as u64) < m)
            || len("maxItems").is_some_and(|m| (a.len() as u64) > m)
        {
            errors.push(format!("{at}: {} items is out of bounds", a.len()));
        }
        if let Some(items) = s.get("items") {
            for (i, x) in a.iter().enumerate() {
                check(doc, items, x, &format!("{at}[{i}]"), errors);
            }
        }
    }
    if let Some(o) = v.as_object() {
        for r in s
            .get("required")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            if let Some(r) = r.as_str() {
                if !o.contains_key(r) {
                    errors.push(format!("{at}: missing required `{r}`"));
                }
            }
        }
        let props = s.get("properties").and_then(Value::as_object);
        for (k, x) in o {
            match props.and_then(|p| p.get(k)) {
                Some(p) => check(doc, p, x, &format!("{at}.{k}"), errors),
                None => {
                    if let Some(extra) = s.get("additionalProperties") {
                        check(doc, extra, x, &format!("{at}.{k}"), errors);
                    }
                }
            }
        }
    }
    let branch_errors = |branches: &Vec<Value>| -> Vec<Vec<String>> {
        branches
            .iter()
            .map(|b| {
                let mut e = Vec::new();
                check(doc, b, v, at, &mut e);
                e
            })
            .collect()
    };
    if let Some(one) = s.get("oneOf").and_then(Value::as_array) {
        let results = branch_errors(one);
        let passing = results.iter().filter(|e| e.is_empty()).count();
        if passing != 1 {
            errors.push(format!(
                "{at}: {passing} branches of oneOf match {v} (exactly 1 must): {results:?}"
            ));
        }
    }
    if let Some(any) = s.get("anyOf").and_then(Value::as_array) {
        let results = branch_errors(any);
        if !results.iter().any(Vec::is_empty) {
            errors.push(format!("{at}: no branch of anyOf matches: {results:?}"));
        }
    }
    if let Some(all) = s.get("allOf").and_then(Value::as_array) {
        for e in branch_errors(all) {
            errors.extend(e);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn keywords_can_fail() {
        let doc = json!({"components": {"schemas": {"B": {"oneOf": [
            {"type": "number"}, {"type": "string", "enum": ["inf"]}]}}}});
        let s = json!({"type": "object", "required": ["a"], "additionalProperties": false,
            "properties": {"a": {"type": "array", "minItems": 2, "maxItems": 2,
                "items": {"$ref": "#/components/schemas/B"}},
                "n": {"type": ["integer", "null"], "minimum": 1}}});
        assert!(validate(&doc, &s, &json!({"a": [1, "inf"], "n": null})).is_empty());
        assert!(validate(&doc, &s, &json!({"a": [1, "inf"], "n": 3.0})).is_empty());
        for bad in [
            json!({"a": [1]}),
            json!({"a": [1, "x"]}),
            json!({"a": [1, 2], "n": 0}),
            json!({"a": [1, 2], "n": 1.5}),
            json!({"a": [1, 2], "z": 1}),
            json!({"n": 1}),
        ] {
            assert!(!validate(&doc, &s, &bad).is_empty(), "{bad}");
        }
    }
}
