//! The describing function's agreement with the exact simulation (the model document,
//! docs/MODEL.md, section 10): walls on rays through the origin with ray margins `s*` from
//! 1.05 to 2, on the paper's loop with an encoder and no friction; for each, whether the
//! describing function predicts a sustained limit cycle and whether the simulation's
//! protocol ends buzzing.
//!
//! `cargo run --release -p stabound --example buzz_agreement`

use stabound::buzz::{BuzzOptions, Quantization, buzz, describing_function};
use stabound::params::{Plant, Wall};

fn main() -> stabound::Result<()> {
    let q = Quantization::new(true, 0.0, 0.0, 0.0)?;
    let options = BuzzOptions::default();
    let (mut agree, mut total) = (0, 0);
    println!("delta,d,beta_over_alpha,s_star,df_buzz,df_amplitude,sim_buzz,sim_peak,sim_period");
    for &(delta, d) in &[(0.0, 1.0), (0.1, 1.0), (1.0, 1.0), (0.1, 0.0), (0.1, 2.0)] {
        let plant = Plant::new(delta, d)?;
        for &ratio in &[1.0, 3.0] {
            let base = Wall::new(0.1, 0.1 * ratio)?;
            let Some(s0) = describing_function(plant, &base)?.ray_margin else {
                continue;
            };
            for &target in &[1.05, 1.15, 1.3, 1.5, 2.0] {
                let f = s0 / target;
                let wall = Wall::new(base.alpha() * f, base.beta() * f)?;
                let df = describing_function(plant, &wall)?;
                let sim = buzz(plant, &wall, &q, &options)?;
                total += 1;
                if df.predicts_buzz() == sim.sustained() {
                    agree += 1;
                }
                println!(
                    "{delta},{d},{ratio},{:.4},{},{:.3},{},{},{}",
                    df.ray_margin.unwrap_or(f64::NAN),
                    df.predicts_buzz(),
                    df.amplitude_counts().unwrap_or(0.0),
                    sim.sustained(),
                    sim.peak_counts(),
                    sim.period_samples().map_or("-".into(), |p| p.to_string()),
                );
            }
        }
    }
    println!("agreement: {agree} of {total}");
    Ok(())
}
