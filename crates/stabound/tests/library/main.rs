//! Tests of the `stabound` library against independent computations: eigenvalues against
//! polynomial roots, the exact boundary against bisection, alpha_max against brute force,
//! the paper's published values, golden figure data, extremes and properties of the public API.

mod amax_bruteforce;
mod amax_direct;
mod amax_properties;
mod amax_sweep;
mod amax_vs_boundary;
mod boundary_exact;
mod boundary_tolerance;
mod butterworth;
mod buzz;
mod certificate_amax;
mod certificate_boundary;
mod certificate_element_boxes;
mod certificate_elements;
mod certificate_sets;
mod certified_table;
mod circle_roots;
mod core_model;
mod dampers;
mod elements;
mod extremes;
#[cfg(feature = "svg")]
mod figures_drawing;
#[cfg(feature = "svg")]
mod figures_golden;
#[cfg(feature = "svg")]
mod figures_paper;
mod loop_amax;
mod loop_boundary;
mod marginal_below;
mod passivity_delay;
mod passivity_quantized;
mod request;
mod robust_proof;
mod robust_proof_elements;
mod robust_props;
mod robust_sets;
mod safety;
#[cfg(feature = "scene")]
mod scene_check;
#[cfg(feature = "scene")]
mod scene_elements;
mod step_elements;
mod stiff;
mod table_lookup;
mod verdicts;
