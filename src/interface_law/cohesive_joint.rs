//! The cohesive–frictional joint. Filled by the joint lane (a stub until then: plain contact).
use super::{InterfaceLaw, InterfaceOutputs, InterfacePoint, PointFriction, PointModification, PointSolution};
use crate::scene::CohesiveJointSpec;

/// The cohesive joint (stub).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CohesiveJoint {
    /// The scene's parameters.
    pub spec: CohesiveJointSpec,
}

impl CohesiveJoint {
    /// The law of `spec`.
    pub fn new(spec: &CohesiveJointSpec) -> Self {
        CohesiveJoint { spec: *spec }
    }
}

impl InterfaceLaw for CohesiveJoint {
    fn name(&self) -> &'static str {
        "cohesive_joint"
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
