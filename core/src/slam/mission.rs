//! `nvector-mission/1`: parsing and validation. OWNER: helper B.

use crate::error::InputError;
use serde_json::Value;

/// A validated mission.
#[derive(Debug, Clone)]
pub struct Mission {
    /// `name` field.
    pub name: String,
    /// N, the number of steps.
    pub steps: usize,
    /// Number of detections.
    pub detection_count: usize,
}

impl Mission {
    /// Parses and validates a mission; errors name the JSON path.
    pub fn from_value(v: &Value) -> Result<Mission, InputError> {
        let _ = v;
        Err(InputError::new("", "not implemented yet"))
    }

    /// Parses JSON text.
    pub fn from_json(text: &str) -> Result<Mission, InputError> {
        let v: Value = serde_json::from_str(text)
            .map_err(|e| InputError::new("", format!("invalid JSON: {e}")))?;
        Mission::from_value(&v)
    }
}
