//! The whole per-sample loop in one place: what a device, a live stream or a
//! script does with clino. Reads the embedded 22 s of BROAD trial 07 and
//! prints the tilt once a second.
//!
//! ```sh
//! cargo run --release -p clino --example pipeline
//! ```

use clino::core::filter::{FilterKind, FilterSpec};
use clino::core::pipeline::Pipeline;
use clino::io::{ImuCsvReader, ReadOptions};

fn main() -> clino::Result<()> {
    // 1. the filter and its parameters (every one has a unit; see `clino fuse --help`)
    let mut spec = FilterSpec::default_for(FilterKind::Dynamic);
    spec.set("bandwidth", "0.15").expect("a valid value");
    // 2. the pipeline: calibration and lever arm are optional stages
    let mut pipeline = Pipeline::new(spec).with_lever_arm(None);
    // 3. samples from any source: here a recording
    let text = clino::demo::BROAD_EXCERPT;
    let mut reader = ImuCsvReader::new(
        text.as_bytes(),
        "broad_07_excerpt.csv",
        &ReadOptions::default(),
    )?;
    let mut next_print = 0.0;
    while let Some(row) = reader.next_row()? {
        // 4. one call per sample
        let out = pipeline.update(&row.sample);
        if let Some(tilt) = out.tilt()
            && row.sample.t_s >= next_print
        {
            println!(
                "t = {:6.2} s  roll {:7.2}°  pitch {:7.2}°  inclination {:6.2}°  ({})",
                row.sample.t_s,
                tilt.roll_rad.to_degrees(),
                tilt.pitch_rad.to_degrees(),
                tilt.inclination_rad.to_degrees(),
                out.status.as_str()
            );
            next_print = row.sample.t_s + 1.0;
        }
    }
    let c = pipeline.counts();
    println!(
        "{} samples: {} fused, {} dropouts, {} saturated",
        c.samples, c.fused, c.dropouts, c.saturated
    );
    Ok(())
}
