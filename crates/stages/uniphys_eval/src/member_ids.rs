//! Normalisation of member ids to strings (reference 16.2): a set with any invalid id is invalid.

use std::collections::BTreeSet;

use serde_json::Value;

use crate::error::EvalError;

/// A set of normalised member ids.
pub type IdSet = BTreeSet<String>;

/// Normalises one id to a string: integers, integral floats (`3.0` → `"3"`) and stripped
/// non-empty strings; anything else (bools, null, fractional floats, arrays, objects) is invalid.
///
/// # Errors
/// [`EvalError::InvalidId`] for an id that cannot be normalised.
pub fn normalise_id(id: &Value) -> Result<String, EvalError> {
    let invalid = || EvalError::InvalidId(id.to_string());
    match id {
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                Ok(i.to_string())
            } else if let Some(u) = n.as_u64() {
                Ok(u.to_string())
            } else {
                match n.as_f64() {
                    Some(f) if f.is_finite() && f.fract() == 0.0 => Ok(format!("{f:.0}")),
                    _ => Err(invalid()),
                }
            }
        }
        Value::String(s) => {
            let t = s.trim();
            if t.is_empty() {
                Err(invalid())
            } else {
                Ok(t.to_owned())
            }
        }
        _ => Err(invalid()),
    }
}

/// Normalises a JSON list of ids to a set; a non-list or any invalid id makes the whole set
/// invalid.
///
/// # Errors
/// [`EvalError::InvalidId`] for a non-list value or the first id that cannot be normalised.
pub fn normalise_id_set(ids: &Value) -> Result<IdSet, EvalError> {
    match ids {
        Value::Array(items) => items.iter().map(normalise_id).collect(),
        other => Err(EvalError::InvalidId(other.to_string())),
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    #[test]
    fn ids_normalise_ints_integral_floats_and_stripped_strings() {
        assert_eq!(normalise_id(&json!(3)).ok(), Some("3".to_owned()));
        assert_eq!(normalise_id(&json!(-2)).ok(), Some("-2".to_owned()));
        assert_eq!(normalise_id(&json!(4.0)).ok(), Some("4".to_owned()));
        assert_eq!(
            normalise_id(&json!("  door ")).ok(),
            Some("door".to_owned())
        );
    }

    #[test]
    fn bools_null_fractional_floats_and_blank_strings_are_invalid_ids() {
        for bad in [
            json!(true),
            json!(null),
            json!(1.5),
            json!("   "),
            json!([1]),
            json!({}),
        ] {
            assert!(normalise_id(&bad).is_err(), "{bad} should be invalid");
        }
    }

    #[test]
    fn one_invalid_id_invalidates_the_whole_set() {
        assert!(normalise_id_set(&json!([1, "2", false])).is_err());
        assert!(normalise_id_set(&json!("1")).is_err());
        let set = normalise_id_set(&json!([1, 1.0, " 1 ", "a"])).expect("valid");
        assert_eq!(set.len(), 2);
    }
}
