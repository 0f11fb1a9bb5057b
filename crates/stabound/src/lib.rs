//! # stabound
//!
//! Exact stability boundaries for haptic rendering: a damped mass sampled every `T` seconds,
//! touching a virtual spring-damper wall whose force arrives after a delay. Stability depends
//! on four normalized numbers: stiffness `alpha`, virtual damping `beta`, physical damping
//! `delta` and delay `d` (Hulin, Preusche and Hirzinger, "Stability Boundary for Haptic
//! Rendering: Influence of Physical Damping", IROS 2006).
//!
//! ```
//! use stabound::params::{Plant, Wall};
//! use stabound::stability::{Checker, Options, Verdict};
//!
//! // A device with physical damping delta = 0.5 and one sample of delay.
//! let plant = Plant::new(0.5, 1.0)?;
//! let checker = Checker::new(&plant, Options::default())?;
//! // A soft, well-damped wall is stable; a very stiff one is not.
//! assert_eq!(checker.verdict(&Wall::new(0.1, 0.3)?)?, Verdict::Stable);
//! assert_eq!(checker.verdict(&Wall::new(5.0, 0.3)?)?, Verdict::Unstable);
//! // Roots and spectral radius, when they are wanted:
//! let analysis = checker.analyze(&Wall::new(0.1, 0.3)?)?;
//! assert!(analysis.spectral_radius < 1.0);
//! # Ok::<(), stabound::Error>(())
//! ```
//!
//! The data flow reads as the modules do: [`params`] (validated inputs, physical units) ->
//! [`model`] (exact discretization, state matrix) -> [`poly`] (characteristic polynomial
//! `q = Q0 + alpha QA + beta QB`) -> [`stability`] (Schur-Cohn, eigenvalues) -> [`boundary`]
//! (stability boundaries: exact D-decomposition and a grid-and-bisection engine) and
//! [`amax`] (maximum stable stiffness, by direct search). [`search`] gives exact
//! one-dimensional stable sets (stiffness at fixed damping and the reverse); [`scene`] checks
//! the walls of a scene file with them.
//! [`sim`] simulates step responses of the sampled loop (between samples too);
//! [`passivity`] computes the passive region for any whole-sample delay and velocity filter
//! and compares it with the stable region; [`figures`] builds the data and drawings of the
//! paper's figures. [`filter`] and [`elements`] describe a real device's loop (velocity
//! filter, operator hand, compliant transmission, actuator lag) and test walls on it.
//!
//! ## Features
//!
//! | feature | default | what it adds |
//! | --- | --- | --- |
//! | `serde` | yes | `Serialize`/`Deserialize` for parameters and results (validated on the way in) |
//! | `scene` | yes | [`scene`]: scene files in TOML or JSON (implies `serde`) |
//! | `svg` | yes | [`plot`] and [`figures`]: SVG drawings and the paper's figures |
//! | `raster` | no | PNG output of the drawings ([`plot::render`]; resvg, tiny-skia, embedded DejaVu Sans) |
//! | `pdf` | no | PDF output of the drawings ([`plot::render`]; svg2pdf, embedded DejaVu Sans) |
//!
//! `default-features = false` leaves the numerics, engines and CSV/JSON/C/Rust export.
#![warn(missing_docs)]

pub mod amax;
pub mod boundary;
pub mod buzz;
pub mod cancel;
pub mod certificate;
mod curve;
mod devices;
pub mod elements;
mod enclosure;
pub mod error;
pub mod export;
#[cfg(feature = "svg")]
pub mod figures;
pub mod filter;
mod geometry;
mod golden;
mod inputs;
pub mod model;
mod ordered;
pub mod params;
pub mod passivity;
#[cfg(feature = "svg")]
pub mod plot;
pub mod poly;
pub mod request;
pub mod robust;
mod roots;
#[cfg(feature = "scene")]
pub mod scene;
pub mod search;
mod shown;
pub mod sim;
pub mod stability;

pub use amax::{Amax, AmaxOptions, alpha_max};
pub use cancel::Cancel;
pub use elements::Loop;
pub use error::{Error, Result};
pub use filter::{FilterKind, VelocityFilter};
pub use params::{Delay, Device, Normalized, Plant, Wall};
pub use stability::{Analysis, Checker, Verdict};
