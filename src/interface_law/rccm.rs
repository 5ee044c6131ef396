//! The RCCM adhesion law. Filled by the rccm lane (a stub until then: plain contact).
use super::{InterfaceLaw, InterfaceOutputs, InterfacePoint, PointFriction, PointModification, PointSolution};
use crate::scene::RccmSpec;

/// The RCCM law (stub).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rccm {
    /// The scene's parameters.
    pub spec: RccmSpec,
}

impl Rccm {
    /// The law of `spec`.
    pub fn new(spec: &RccmSpec) -> Self {
        Rccm { spec: *spec }
    }
}

impl InterfaceLaw for Rccm {
    fn name(&self) -> &'static str {
        "rccm"
    }
    fn has_memory(&self) -> bool {
        true
    }
    fn initial(&self) -> Vec<f64> {
        Vec::new()
    }
    fn modification(
        &self,
        _: &InterfacePoint,
        friction: PointFriction,
        _: &[f64],
        _: Option<&PointSolution>,
    ) -> PointModification {
        PointModification::plain(friction)
    }
    fn update(&self, _: &InterfacePoint, committed: &[f64], _: &PointSolution, _: f64) -> Vec<f64> {
        committed.to_vec()
    }
    fn residual(&self, _: &InterfacePoint, _: &[f64], _: &[f64], _: &PointSolution, _: f64) -> f64 {
        0.0
    }
    fn outputs(&self, _: &[f64]) -> InterfaceOutputs {
        InterfaceOutputs::default()
    }
}
