//! The cohesive–frictional joint. Filled by the joint lane.
