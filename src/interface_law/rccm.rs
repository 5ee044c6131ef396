//! The RCCM adhesion law. Filled by the rccm lane.
