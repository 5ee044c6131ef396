//! The thin elastic layer (imperfect interface). Filled by the core lane.
