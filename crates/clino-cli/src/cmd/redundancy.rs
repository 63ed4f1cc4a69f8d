//! `clino redundancy`: the nine-chain six-axis accelerometer with a gyro —
//! what can be restored, simulated faults, and diagnosis of recordings.

use super::print_result;
use anyhow::Context;
use clap::{Args as ClapArgs, Subcommand, ValueEnum};
use clino::redundancy::{
    analysis,
    diagnose::{DiagnosisConfig, NoiseModel},
    fault_set::FaultSet,
    model::SixAxisAccelerometer,
    recording,
    simulate::{self, FaultKind, SimConfig, Simulator},
};
use clino::report::text::redundancy as text;
use std::path::{Path, PathBuf};

/// Arguments of `clino redundancy`.
#[derive(ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

/// How a faulty chain misbehaves.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum KindArg {
    /// Output frozen at its value at the onset.
    Stuck,
    /// Constant offset (N).
    Bias,
    /// Offset growing linearly (N/s).
    Drift,
    /// Extra white noise (σ, N).
    Noise,
}

impl From<KindArg> for FaultKind {
    fn from(k: KindArg) -> Self {
        match k {
            KindArg::Stuck => FaultKind::Stuck,
            KindArg::Bias => FaultKind::Bias,
            KindArg::Drift => FaultKind::Drift,
            KindArg::Noise => FaultKind::Noise,
        }
    }
}

/// The fault kinds of a sweep.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum SweepKindArg {
    /// Output frozen at its value at the onset.
    Stuck,
    /// Constant offset (N).
    Bias,
    /// Offset growing linearly (N/s).
    Drift,
    /// Extra white noise (σ, N).
    Noise,
    /// Every kind, one after the other.
    All,
}

impl SweepKindArg {
    fn kinds(self) -> Vec<FaultKind> {
        let one = |k: KindArg| vec![FaultKind::from(k)];
        match self {
            SweepKindArg::Stuck => one(KindArg::Stuck),
            SweepKindArg::Bias => one(KindArg::Bias),
            SweepKindArg::Drift => one(KindArg::Drift),
            SweepKindArg::Noise => one(KindArg::Noise),
            SweepKindArg::All => FaultKind::ALL.to_vec(),
        }
    }
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
    Simulate(SimulateArgs),
    /// Simulate all 165 validation sets (1–3 chains and Table 1) and report rates and delays.
    Sweep(SweepArgs),
    /// Diagnose a recording: CSV with t_s, f1_N..f9_N, gyr_x_rad_s, gyr_y_rad_s, gyr_z_rad_s.
    Diagnose(DiagnoseArgs),
}

#[derive(ClapArgs)]
struct SimulateArgs {
    /// Faulty chains: chain numbers 1–9 separated by commas, e.g. 2,3,9.
    #[arg(long, value_name = "N,N,…")]
    faults: String,
    /// How the faulty chains misbehave.
    #[arg(long, value_enum, default_value = "bias", ignore_case = true)]
    fault_kind: KindArg,
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
    // Print JSON; --plot draws the x linear acceleration (truth, faulty, restored).
    #[command(flatten)]
    output: super::OutputArgs,
    /// Write the simulated recording (forces, gyro) as CSV for `diagnose`.
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(ClapArgs)]
struct SweepArgs {
    /// Fault kind, or all.
    #[arg(long, value_enum, default_value = "all", ignore_case = true)]
    fault_kind: SweepKindArg,
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
}

#[derive(ClapArgs)]
struct DiagnoseArgs {
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

fn create(p: &Path) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
    let f = std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?;
    Ok(std::io::BufWriter::new(f))
}

/// Run `clino redundancy`.
pub fn run(a: Args) -> anyhow::Result<()> {
    match a.command {
        Command::Analyze { json } => {
            let an = analysis::analyze(&SixAxisAccelerometer::reference(), 4);
            print_result(json, &an, || text::analysis(&an))
        }
        Command::Simulate(s) => simulate(s),
        Command::Sweep(s) => sweep(s),
        Command::Diagnose(d) => diagnose(d),
    }
}

fn simulate(a: SimulateArgs) -> anyhow::Result<()> {
    let set = FaultSet::parse(&a.faults)?;
    let cfg = SimConfig {
        duration_s: a.duration_s,
        onset_s: a.onset_s,
        magnitude: a.magnitude,
        seed: a.seed,
        noise: a.diag.noise(),
        diagnosis: a.diag.config(),
        ..SimConfig::default()
    };
    let sim = Simulator::new(&SixAxisAccelerometer::reference(), &cfg)?;
    let o = sim.run(set, a.fault_kind.into(), a.seed)?;
    if let Some(p) = &a.output.plot {
        o.plot(p)?;
    }
    if let Some(p) = &a.out {
        recording::write_csv(create(p)?, &o.recording)?;
    }
    print_result(a.output.json, &o.report, || text::simulation(&o.report))?;
    for w in &o.report.warnings {
        eprintln!("clino: warning: {w}");
    }
    Ok(())
}

fn sweep(a: SweepArgs) -> anyhow::Result<()> {
    let cfg = SimConfig {
        duration_s: a.duration_s,
        onset_s: a.onset_s,
        seed: a.seed,
        noise: a.diag.noise(),
        diagnosis: a.diag.config(),
        ..SimConfig::default()
    };
    let sim = Simulator::new(&SixAxisAccelerometer::reference(), &cfg)?;
    let sets = simulate::validation_sets();
    let kinds = a.fault_kind.kinds();
    let bar = indicatif::ProgressBar::new((sets.len() * kinds.len()) as u64);
    let summaries = simulate::sweep_kinds(&sim, &sets, &kinds, &mut |_, _| bar.inc(1))?;
    bar.finish_and_clear();
    print_result(a.json, &summaries, || text::sweep(&summaries))
}

fn diagnose(a: DiagnoseArgs) -> anyhow::Result<()> {
    let acc =
        SixAxisAccelerometer::new(a.mass_kg, a.half_edge_m, parse_stiffness(&a.stiffness_n_m)?)?;
    let rec = recording::read_csv(&a.recording)?;
    let d = recording::diagnose_recording(&acc, &a.diag.noise(), &a.diag.config(), &rec)?;
    if let Some(p) = &a.out {
        let restored = recording::restore_recording(&acc, &a.diag.noise(), &rec, &d, 10)?;
        recording::write_restored_csv(create(p)?, &restored)?;
    }
    print_result(a.json, &d, || {
        text::diagnosis(&a.recording, &d, &rec.ignored_columns)
    })
}
