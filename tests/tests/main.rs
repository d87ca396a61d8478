//! Validation tests of geosph: one test binary, one module per subject.
mod blow_up;
mod checkpoint;
mod corrections;
mod dam_break;
mod determinism;
mod escape;
mod factor_of_safety;
mod geometry;
mod hostile_scenes;
mod incompressible;
mod kernels;
mod neighbours;
mod output_integrity;
mod soil_element;
mod soil_sph;
mod wall_pressure;
mod wcsph;
