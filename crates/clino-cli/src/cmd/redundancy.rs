//! `clino redundancy`: the nine-chain six-axis accelerometer with a gyro —
//! what can be restored, simulated faults, and diagnosis of recordings.

use anyhow::Context;
use clap::{Args as ClapArgs, Subcommand};
use clino::redundancy::{
    analysis,
    diagnose::{DiagnosisConfig, NoiseModel},
    fault_set::FaultSet,
    model::SixAxisAccelerometer,
    recording,
    simulate::{self, FaultKind, SimConfig, Simulator},
};
use std::path::PathBuf;

/// Arguments of `clino redundancy`.
#[derive(ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Which fault sets of 1–4 chains are restorable and isolable (vs the source's Table 1).
    Analyze {
        /// Print JSON (`restorable`, `isolable`: size "1".."4" → sets like "2389").
        #[arg(long)]
        json: bool,
    },
    /// Simulate a shaken cube with faulty chains: detection, diagnosis, restoration.
    Simulate {
        /// Faulty chains: chain numbers 1–9 separated by commas, e.g. 2,3,9.
        #[arg(long, value_name = "N,N,…")]
        faults: String,
        /// stuck | bias | drift | noise.
        #[arg(long, default_value = "bias")]
        fault_kind: String,
        /// Fault magnitude: bias N, drift N/s, noise σ N (default per kind: 0.02, 0.2, 0.004).
        #[arg(long)]
        magnitude: Option<f64>,
        /// Record length, s.
        #[arg(long, default_value_t = 1.0)]
        duration_s: f64,
        /// Fault onset, s.
        #[arg(long, default_value_t = 0.4)]
        onset_s: f64,
        /// Noise seed.
        #[arg(long, default_value_t = 7)]
        seed: u64,
        #[command(flatten)]
        diag: DiagArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
        /// Plot the x linear acceleration (truth, faulty, restored) to FILE.svg|png.
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Write the simulated recording (forces, gyro) as CSV for `diagnose`.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Simulate all 165 validation sets (1–3 chains and Table 1) and report rates and delays.
    Sweep {
        /// stuck | bias | drift | noise | all.
        #[arg(long, default_value = "all")]
        fault_kind: String,
        /// Record length per run, s.
        #[arg(long, default_value_t = 0.5)]
        duration_s: f64,
        /// Fault onset, s.
        #[arg(long, default_value_t = 0.2)]
        onset_s: f64,
        /// First noise seed (run i uses seed + i).
        #[arg(long, default_value_t = 7)]
        seed: u64,
        #[command(flatten)]
        diag: DiagArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Diagnose a recording: CSV with t_s, f1_N..f9_N, gyr_x_rad_s, gyr_y_rad_s, gyr_z_rad_s.
    Diagnose {
        /// The recording.
        recording: PathBuf,
        /// Cube mass, kg.
        #[arg(long, default_value_t = 0.1)]
        mass_kg: f64,
        /// Half the cube edge, m.
        #[arg(long, default_value_t = 0.012)]
        half_edge_m: f64,
        /// Chain stiffness, N/m: one value for all, or nine comma-separated.
        #[arg(long, default_value = "2e7")]
        stiffness_n_m: String,
        #[command(flatten)]
        diag: DiagArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
        /// Write the restored forces and body 6-D acceleration as CSV.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// Noise model and diagnosis settings shared by the subcommands.
#[derive(ClapArgs)]
struct DiagArgs {
    /// White noise of each chain force per sample, N.
    #[arg(long, default_value_t = 2.0e-4)]
    force_sigma_n: f64,
    /// White noise of each gyro axis per sample, rad/s.
    #[arg(long, default_value_t = 2.0e-3)]
    gyro_sigma_rad_s: f64,
    /// False-alarm probability per chi-square test.
    #[arg(long, default_value_t = 1e-6)]
    alpha: f64,
    /// Samples per residual block.
    #[arg(long, default_value_t = 10)]
    block_len: usize,
    /// Blocks per decision window.
    #[arg(long, default_value_t = 10)]
    window_blocks: usize,
}

impl DiagArgs {
    fn noise(&self) -> NoiseModel {
        NoiseModel {
            force_sigma_n: self.force_sigma_n,
            gyro_sigma_rad_s: self.gyro_sigma_rad_s,
        }
    }
    fn config(&self) -> DiagnosisConfig {
        DiagnosisConfig {
            block_len: self.block_len,
            window_blocks: self.window_blocks,
            false_alarm_prob: self.alpha,
            ..DiagnosisConfig::default()
        }
    }
}

fn parse_stiffness(s: &str) -> anyhow::Result<[f64; 9]> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .with_context(|| format!("--stiffness-n-m: '{x}' is not a number"))
        })
        .collect::<anyhow::Result<_>>()?;
    match v.len() {
        1 => Ok([v[0]; 9]),
        9 => Ok(std::array::from_fn(|i| v[i])),
        n => anyhow::bail!("--stiffness-n-m takes 1 or 9 values, got {n}"),
    }
}

/// Run `clino redundancy`.
pub fn run(a: Args) -> anyhow::Result<()> {
    match a.command {
        Command::Analyze { json } => {
            let an = analysis::analyze(&SixAxisAccelerometer::reference(), 4);
            if json {
                println!("{}", serde_json::to_string_pretty(&an)?);
            } else {
                print!("{}", an.summary());
                for k in ["1", "2", "3", "4"] {
                    let not_iso: Vec<&String> = an.restorable[k]
                        .iter()
                        .filter(|s| !an.isolable[k].contains(s))
                        .collect();
                    if !not_iso.is_empty() {
                        println!(
                            "size {k}: restorable but not isolable ({}): {}",
                            not_iso.len(),
                            not_iso
                                .iter()
                                .map(|s| s.as_str())
                                .collect::<Vec<_>>()
                                .join(" ")
                        );
                    }
                }
            }
        }
        Command::Simulate {
            faults,
            fault_kind,
            magnitude,
            duration_s,
            onset_s,
            seed,
            diag,
            json,
            plot,
            out,
        } => {
            let set = FaultSet::parse(&faults)?;
            let kind = FaultKind::parse(&fault_kind)?;
            let cfg = SimConfig {
                duration_s,
                onset_s,
                magnitude,
                seed,
                noise: diag.noise(),
                diagnosis: diag.config(),
                ..SimConfig::default()
            };
            let sim = Simulator::new(&SixAxisAccelerometer::reference(), &cfg)?;
            let o = sim.run(set, kind, seed)?;
            if let Some(p) = &plot {
                o.plot(p)?;
            }
            if let Some(p) = &out {
                let f = std::fs::File::create(p)
                    .with_context(|| format!("creating {}", p.display()))?;
                recording::write_csv(std::io::BufWriter::new(f), &o.recording)?;
            }
            let r = &o.report;
            if json {
                println!("{}", serde_json::to_string_pretty(r)?);
            } else {
                let ms =
                    |v: Option<f64>| v.map_or("—".to_string(), |x| format!("{:.1} ms", x * 1e3));
                let pct =
                    |v: Option<f64>| v.map_or("—".to_string(), |x| format!("{:.3} %", x * 100.0));
                let list = |l: &str| {
                    FaultSet::from_label(l).map_or_else(|_| l.to_string(), |s| s.to_list())
                };
                println!(
                    "faults {} ({}, magnitude {}) from {} s",
                    set.to_list(),
                    r.fault_kind.name(),
                    r.fault_magnitude,
                    r.onset_s
                );
                println!(
                    "diagnosed {} (source scheme: {})",
                    list(&r.diagnosed),
                    list(&r.diagnosed_source)
                );
                println!(
                    "detection delay {}, isolation delay {}",
                    ms(r.detection_delay_s),
                    ms(r.isolation_delay_s)
                );
                println!(
                    "false alarms {} of {} windows before the fault",
                    r.false_alarm_windows, r.pre_onset_windows
                );
                let restored = match &r.restored_with {
                    Some(l) if *l == r.faults => "restored".to_string(),
                    Some(l) => format!("restored with the wrong chains {}", list(l)),
                    None => "not restored".to_string(),
                };
                println!(
                    "linear acceleration max relative error: faulty {}, {restored} {}, fault-free {}",
                    pct(Some(r.faulty_linear_acc_max_rel_error)),
                    pct(r.restored_linear_acc_max_rel_error),
                    pct(Some(r.fault_free_linear_acc_max_rel_error))
                );
            }
            for w in &r.warnings {
                eprintln!("clino: warning: {w}");
            }
        }
        Command::Sweep {
            fault_kind,
            duration_s,
            onset_s,
            seed,
            diag,
            json,
        } => {
            let kinds: Vec<FaultKind> = if fault_kind == "all" {
                FaultKind::ALL.to_vec()
            } else {
                vec![FaultKind::parse(&fault_kind)?]
            };
            let cfg = SimConfig {
                duration_s,
                onset_s,
                seed,
                noise: diag.noise(),
                diagnosis: diag.config(),
                ..SimConfig::default()
            };
            let sim = Simulator::new(&SixAxisAccelerometer::reference(), &cfg)?;
            let sets = simulate::validation_sets();
            let bar = indicatif::ProgressBar::new((sets.len() * kinds.len()) as u64);
            let mut summaries = Vec::new();
            for kind in kinds {
                let (s, _) = simulate::sweep(&sim, &sets, kind, &mut |_, _| bar.inc(1))?;
                summaries.push(s);
            }
            bar.finish_and_clear();
            if json {
                println!("{}", serde_json::to_string_pretty(&summaries)?);
            } else {
                println!(
                    "kind   runs  detected  false-alarm  delay mean/max (ms)  isolated  source  agree  source-wrong  max restored err (set)"
                );
                for s in &summaries {
                    println!(
                        "{:<6} {:>4}  {:>7.1}%  {:>10.2e}  {:>8.1} / {:<8.1}  {:>8}  {:>6}  {:>5}  {:>12}  {:>8.3} % ({})",
                        s.fault_kind.name(),
                        s.runs,
                        100.0 * s.detection_rate,
                        s.false_alarm_rate,
                        1e3 * s.mean_detection_delay_s,
                        1e3 * s.max_detection_delay_s,
                        s.isolated,
                        s.isolated_source,
                        s.agree,
                        s.source_wrong_set,
                        100.0 * s.max_restored_linear_acc_rel_error,
                        s.worst_restored_set
                    );
                    if !s.misdiagnosed.is_empty() {
                        println!("       misdiagnosed: {}", s.misdiagnosed.join(" "));
                    }
                }
            }
        }
        Command::Diagnose {
            recording: path,
            mass_kg,
            half_edge_m,
            stiffness_n_m,
            diag,
            json,
            out,
        } => {
            let acc =
                SixAxisAccelerometer::new(mass_kg, half_edge_m, parse_stiffness(&stiffness_n_m)?)?;
            let rec = recording::read_csv(&path)?;
            let d = recording::diagnose_recording(&acc, &diag.noise(), &diag.config(), &rec)?;
            if let Some(p) = &out {
                let restored = recording::restore_recording(&acc, &diag.noise(), &rec, &d, 10)?;
                let f = std::fs::File::create(p)
                    .with_context(|| format!("creating {}", p.display()))?;
                recording::write_restored_csv(std::io::BufWriter::new(f), &restored)?;
            }
            if json {
                println!("{}", serde_json::to_string_pretty(&d)?);
            } else {
                println!(
                    "{}: {} samples, step {:.6} s, {} decisions",
                    path.display(),
                    d.samples,
                    d.step_s,
                    d.windows
                );
                match d.first_alarm_s {
                    None => println!("no fault detected"),
                    Some(t) => println!(
                        "first alarm at {t:.4} s; diagnosed {} (source scheme: {})",
                        d.diagnosed, d.diagnosed_source
                    ),
                }
                for s in &d.segments {
                    println!(
                        "  {:>9.4} – {:>9.4} s  general {:<12} source {}",
                        s.from_s, s.to_s, s.general, s.source
                    );
                }
                if !rec.ignored_columns.is_empty() {
                    println!("ignored columns: {}", rec.ignored_columns.join(", "));
                }
            }
        }
    }
    Ok(())
}
