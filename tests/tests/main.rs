//! Validation tests of geosph: one test binary, one module per subject.
mod corrections;
mod dam_break;
mod incompressible;
mod kernels;
mod neighbours;
mod soil_element;
mod wcsph;
