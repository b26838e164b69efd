//! SLAM measures of `nvector bench` (sweep, paper scenario, AUV). OWNER: helper B.

/// Runs the SLAM measures, handing each JSON line to `emit`.
pub fn run(_quick: bool, _only: Option<&str>, _emit: &mut dyn FnMut(serde_json::Value)) {}
