//! JSON output ([`to_json_value`]): serde's, with negative zero written as `0.0`.
//!
//! An IEEE `−0.0` (e.g. the energy of a spring that was never stretched, `−½ k · 0²`, or a
//! product with a negative factor that rounds to zero) is the same number as `0.0`, but
//! serde writes it as `-0.0`, which reads like a small negative value. Every JSON object
//! hopsim writes (`--json`, `--summary`) goes through [`to_json_value`].

use serde::Serialize;
use serde_json::{Number, Value};

/// `value` as a JSON value whose floating-point zeros are all `0.0` (never `-0.0`).
pub fn to_json_value<T: Serialize + ?Sized>(value: &T) -> serde_json::Result<Value> {
    let mut json = serde_json::to_value(value)?;
    normalise_zeros(&mut json);
    Ok(json)
}

/// `value` as pretty-printed JSON, with [`to_json_value`]'s zeros.
pub fn to_json_string_pretty<T: Serialize + ?Sized>(value: &T) -> serde_json::Result<String> {
    serde_json::to_string_pretty(&to_json_value(value)?)
}

/// Replaces every `-0.0` in `json` by `0.0`.
fn normalise_zeros(json: &mut Value) {
    match json {
        Value::Number(n) if n.is_f64() && n.as_f64() == Some(0.0) => {
            *n = Number::from_f64(0.0).unwrap_or_else(|| Number::from(0));
        }
        Value::Array(items) => items.iter_mut().for_each(normalise_zeros),
        Value::Object(map) => map.values_mut().for_each(normalise_zeros),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Energies {
        spring: f64,
        kinetic: f64,
        history: Vec<f64>,
        count: i64,
    }

    #[test]
    fn negative_zero_is_written_as_zero() {
        let e = Energies {
            spring: -0.0,
            kinetic: -1.5,
            history: vec![-0.0, 0.0, -1e-300],
            count: 0,
        };
        // serde alone writes the sign of zero.
        assert!(serde_json::to_string(&e).unwrap().contains("-0.0"));
        let text = to_json_string_pretty(&e).unwrap();
        assert!(!text.contains("-0.0"), "{text}");
        let v = to_json_value(&e).unwrap();
        assert_eq!(v["spring"].as_f64().map(f64::is_sign_positive), Some(true));
        // Other numbers are unchanged: negatives, tiny values, integers.
        assert_eq!(v["kinetic"], -1.5);
        assert_eq!(v["history"][2], -1e-300);
        assert_eq!(v["count"], 0);
    }
}
