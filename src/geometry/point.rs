//! The contact kinematics of one secondary node against a primary face.

/// No candidate face: the query is open (far from the primary surface).
pub const NO_FACE: u32 = u32::MAX;

/// The contact kinematics of one secondary node.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactPoint {
    /// Index into `ContactQueries::faces`, or [`NO_FACE`].
    pub face: u32,
    pub xi: [f64; 2],
    /// Outward unit normal of the primary face at xi.
    pub normal: [f64; 3],
    /// Penetration (> 0) or separation (< 0) along the normal.
    pub gap: f64,
    /// Rate of penetration (> 0 approaching).
    pub gap_rate: f64,
}

impl Default for ContactPoint {
    fn default() -> Self {
        ContactPoint {
            face: NO_FACE,
            xi: [0.0; 2],
            normal: [0.0; 3],
            gap: f64::NEG_INFINITY,
            gap_rate: 0.0,
        }
    }
}
