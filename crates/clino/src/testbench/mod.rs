//! Dynamic and static test analysis of inclinometers.
//!
//! Source: Liu, Cai, Yang, Zhang, "Testing of a MEMS Dynamic Inclinometer
//! Using the Stewart Platform", Sensors 2019 (sine fits, sensitivities eqs
//! 6–8 and 11, amplitude-frequency curves, cross-coupling), and Sapegin &
//! Strokach, "Micromechanical inclinometer" (the 10-minute static test).
//!
//! * [`sinefit`] — IEEE Std 1057 three- and four-parameter sine fits with trend removal;
//! * [`sensitivity`] — the paper's sensitivities and dB;
//! * [`conical`] — frequency response under the conical motion (simulated or recorded);
//! * [`orbit`] — cross-coupling under positional orbits;
//! * [`static_record`] — the rules a recording at rest passes first (shared by `allan` and `static`);
//! * [`static_test`] — drift and noise of a filter at rest;
//! * [`allan`] — overlapping Allan deviation, IEEE Std 952 readings and fitted noise terms with honest bounds;
//! * [`filters`] — the filter chosen by name for every run;
//! * [`plots`] — SVG/PNG plots of the results;
//! * [`recording`] — lab recordings (CSV) for `analyze`.
//!
//! ```
//! use clino::testbench::conical::{ConicalConfig, run_conical};
//! use clino::sim::ImuModel;
//! let cfg = ConicalConfig::new(5f64.to_radians(), vec![1.0], ImuModel::ideal(), "poisson");
//! let pts = run_conical(&cfg, &mut |_, _| {}).unwrap();
//! assert!(pts[0].tilt_x_db.unwrap().abs() < 0.05);
//! ```

pub mod allan;
pub mod conical;
pub mod filters;
pub mod orbit;
pub mod plots;
pub mod recording;
pub mod sensitivity;
pub mod sinefit;
pub mod static_record;
pub mod static_test;

mod demo;
pub use demo::demo_summary;
