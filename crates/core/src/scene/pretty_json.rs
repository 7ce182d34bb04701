//! Human-readable JSON: objects indented one key per line, arrays of numbers (coordinates,
//! faces) on one line, arrays of such arrays one element per line.

use std::fmt::Write as _;

use serde_json::Value;

/// Pretty-prints `value` with two-space indentation and compact numeric arrays (ends with a
/// newline).
pub fn to_pretty(value: &Value) -> String {
    let mut out = String::new();
    write_value(value, 0, &mut out);
    out.push('\n');
    out
}

fn is_scalar(v: &Value) -> bool {
    !matches!(v, Value::Array(_) | Value::Object(_))
}

fn write_value(value: &Value, depth: usize, out: &mut String) {
    let pad = "  ".repeat(depth + 1);
    let close = "  ".repeat(depth);
    match value {
        Value::Object(map) if !map.is_empty() => {
            out.push_str("{\n");
            for (i, (key, v)) in map.iter().enumerate() {
                write!(out, "{pad}{}: ", Value::String(key.clone())).ok();
                write_value(v, depth + 1, out);
                out.push_str(if i + 1 < map.len() { ",\n" } else { "\n" });
            }
            write!(out, "{close}}}").ok();
        }
        Value::Array(items) if !items.is_empty() && !items.iter().all(is_scalar) => {
            out.push_str("[\n");
            for (i, v) in items.iter().enumerate() {
                out.push_str(&pad);
                write_value(v, depth + 1, out);
                out.push_str(if i + 1 < items.len() { ",\n" } else { "\n" });
            }
            write!(out, "{close}]").ok();
        }
        Value::Array(items) => {
            out.push('[');
            for (i, v) in items.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                out.push_str(&v.to_string());
            }
            out.push(']');
        }
        other => out.push_str(&other.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact_numeric_arrays_and_round_trip() {
        let v: Value = serde_json::json!({"a": [[1.0, 2.5, -3.0], [4, 5, 6]], "b": {"c": "x", "d": []}, "e": {}});
        let text = to_pretty(&v);
        assert!(text.contains("    [1.0, 2.5, -3.0],\n"), "{text}");
        assert_eq!(serde_json::from_str::<Value>(&text).unwrap(), v);
    }
}
