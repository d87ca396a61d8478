//! The geosph soil model: a constitutive core usable without SPH, and its SPH coupling.
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
//! - [`constitutive`]: the [`Constitutive`] trait (σ_n, Δε, Δω → σ_{n+1}, Δε̄ᵖ) and its
//!   result [`StressUpdate`].
//! - [`model`]: the scene-level [`ConstitutiveConfig`] and the enum [`SoilModel`] it builds.
//! - [`elastic`]: [`LinearElastic`] (hypoelastic, Jaumann rate).
//! - [`drucker_prager`]: [`DruckerPragerBui2008`], elastic–perfectly plastic Drucker–Prager
//!   with associated or non-associated flow, integrated by [`ReturnAlgorithm::Bui2008`]
//!   (continuum tangent + tension cracking + stress scaling) or
//!   [`ReturnAlgorithm::ConsistentReturn`] (closest-point return to the cone or its apex).
//! - [`element`]: the single-material-point element-test driver (simple shear, oedometer,
//!   drained triaxial compression, any velocity gradient) returning the (p, q) stress path,
//!   with CSV output.
//! - `sph` (feature `sph`, off by default): the SPH coupling — soil particles, soil walls, the
//!   geostatic stage and the solver the runner steps (`build_soil` from a scene's
//!   `SoilConfig`), on the shared SPH layer of `geosph-sph`. Without it the crate is the
//!   constitutive core alone and depends on no SPH code.
//!
//! The Drucker–Prager return map on one stress, without SPH:
//!
//! ```
//! use geosph_core::Tensor3;
//! use geosph_soil::{Constitutive, DruckerPragerBui2008, ReturnAlgorithm, Response, SoilMaterial};
//!
//! // The aluminium bars of Bui et al. (2008): E = 0.84 MPa, ν = 0.3, φ = 19.8°, c = 0, ψ = 0.
//! let bars = SoilMaterial::new(0.84e6, 0.3, 19.8, 0.0, 0.0).unwrap();
//! let model = DruckerPragerBui2008::new(bars, ReturnAlgorithm::ConsistentReturn).unwrap();
//! // Isotropic compression of 1 kPa, then a large shear strain increment.
//! let stress = Tensor3::identity() * -1e3;
//! let mut shear = Tensor3::zeros();
//! shear[(0, 1)] = 1e-2;
//! shear[(1, 0)] = 1e-2;
//! let update = model.update(&stress, &shear, &Tensor3::zeros());
//! assert_eq!(update.response, Response::Cone);
//! // Back on the yield surface f = √J₂ + α_φ I₁ − k_c = 0, with plastic strain.
//! assert!(model.yield_function(&update.stress).unwrap().abs() < 1e-9);
//! assert!(update.equivalent_plastic_strain_increment > 0.0);
//! ```
#![warn(missing_docs)]

pub mod constitutive;
pub mod drucker_prager;
pub mod elastic;
pub mod element;
pub mod invariants;
pub mod kinematics;
pub mod material;
pub mod model;
#[cfg(feature = "sph")]
pub mod sph;

pub use constitutive::{Constitutive, Response, StressUpdate};
pub use drucker_prager::{DruckerPragerBui2008, ReturnAlgorithm};
pub use elastic::LinearElastic;
pub use element::{
    ElementTest, ElementTestError, LoadingPath, PathPoint, run_element_test, write_csv,
};
pub use material::{
    ConeMatch, DruckerPragerConstants, ElasticConstants, MaterialError, SoilMaterial,
};
pub use model::{ConstitutiveConfig, SoilModel};
#[cfg(feature = "sph")]
pub use sph::{
    FactorOfSafety, GeostaticReport, SoilConfig, SoilError, StrengthReductionConfig, build_soil,
    factor_of_safety,
};
