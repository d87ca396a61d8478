//! Validation tests of geosph: one test binary, one module per subject.
