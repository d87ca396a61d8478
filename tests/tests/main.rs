//! Validation tests of geosph: one test binary, one module per subject.
mod corrections;
mod kernels;
mod neighbours;
