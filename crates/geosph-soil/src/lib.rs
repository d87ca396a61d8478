//! Constitutive core of the geosph soil model, usable without SPH.
//!
//! Conventions: stress σ is the Cauchy stress with **tension positive**, always a symmetric
//! 3×3 [`Tensor3`](geosph_core::Tensor3), also in 2D (plane strain: ε_zz = 0, σ_zz evolves).
//! Soil-mechanics measures are compression positive: p = −I₁/3, q = √(3 J₂).
//!
//! Modules:
//! - [`invariants`]: I₁, the deviator s, J₂, p and q.
//! - [`kinematics`]: strain rate and spin from a D×D velocity gradient, embedded in 3×3, and
//!   the Jaumann co-rotational term σ·ωᵀ + ω·σ (Bui et al. 2008).
//! - [`material`]: validated soil parameters ([`SoilMaterial`]), elastic constants
//!   ([`ElasticConstants`]: G, K, λ, Hooke's law) and the Drucker–Prager constants matched to
//!   Mohr–Coulomb in plane strain ([`DruckerPragerConstants`]: α_φ, k_c, α_ψ).
//! - [`constitutive`]: the [`Constitutive`] trait (σ_n, Δε, Δω → σ_{n+1}, Δε̄ᵖ), its result
//!   [`StressUpdate`], the scene-level [`ConstitutiveConfig`] and the enum [`SoilModel`] it
//!   builds.
//! - [`elastic`]: [`LinearElastic`] (hypoelastic, Jaumann rate).
//! - [`drucker_prager`]: [`DruckerPragerBui2008`], elastic–perfectly plastic Drucker–Prager
//!   with associated or non-associated flow, integrated by [`ReturnAlgorithm::Bui2008`]
//!   (continuum tangent + tension cracking + stress scaling) or
//!   [`ReturnAlgorithm::ConsistentReturn`] (closest-point return to the cone or its apex).
//! - [`element`]: the single-material-point element-test driver (simple shear, oedometer,
//!   drained triaxial compression, any velocity gradient) returning the (p, q) stress path,
//!   with CSV output.
#![warn(missing_docs)]

pub mod constitutive;
pub mod drucker_prager;
pub mod elastic;
pub mod element;
pub mod invariants;
pub mod kinematics;
pub mod material;
pub mod sph;

pub use constitutive::{Constitutive, ConstitutiveConfig, Response, SoilModel, StressUpdate};
pub use drucker_prager::{DruckerPragerBui2008, ReturnAlgorithm};
pub use elastic::LinearElastic;
pub use element::{
    ElementTest, ElementTestError, LoadingPath, PathPoint, run_element_test, write_csv,
};
pub use material::{DruckerPragerConstants, ElasticConstants, MaterialError, SoilMaterial};
pub use sph::{GeostaticReport, SoilBuild, SoilConfig, SoilError, build_soil};
