//! `clino stewart ik|fk`: Stewart-platform kinematics of single poses.

use clino::report::text::stewart as text;
use clino::sim::stewart::{Geometry, Pose};
use serde_json::json;

/// Arguments of `clino stewart`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(clap::Subcommand)]
enum Cmd {
    /// Inverse kinematics: leg lengths (m) of a pose given about the home point.
    Ik(IkArgs),
    /// Forward kinematics: the pose of six leg lengths (m).
    Fk(FkArgs),
}

#[derive(clap::Args)]
struct IkArgs {
    /// Offset along x from home, mm.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    x_mm: f64,
    /// Offset along y, mm.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    y_mm: f64,
    /// Offset along z, mm.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    z_mm: f64,
    /// Roll (z-y-x), degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    roll_deg: f64,
    /// Pitch, degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pitch_deg: f64,
    /// Yaw, degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    yaw_deg: f64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
struct FkArgs {
    /// Six leg lengths, m (comma separated).
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_hyphen_values = true
    )]
    legs_m: Vec<f64>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// Run `clino stewart`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let g = Geometry::typical();
    match a.cmd {
        Cmd::Ik(p) => ik(&g, p),
        Cmd::Fk(f) => fk(&g, f),
    }
}

fn ik(g: &Geometry, p: IkArgs) -> anyhow::Result<()> {
    let pose = Pose::from_deg(
        [p.x_mm * 1e-3, p.y_mm * 1e-3, p.z_mm * 1e-3],
        [p.roll_deg, p.pitch_deg, p.yaw_deg],
        g.home_height_m,
    );
    let legs = g.inverse(&pose)?;
    if p.json {
        println!(
            "{}",
            json!({ "legs_m": legs, "condition": g.condition(&pose) })
        );
    } else {
        print!("{}", text::ik(&legs));
    }
    Ok(())
}

fn fk(g: &Geometry, f: FkArgs) -> anyhow::Result<()> {
    anyhow::ensure!(f.legs_m.len() == 6, "give exactly six leg lengths");
    let l: [f64; 6] = core::array::from_fn(|i| f.legs_m[i]);
    let sol = g.forward(&l, &g.home())?;
    if f.json {
        let (r, p, y) = sol.pose.attitude.euler_angles();
        let off = sol.pose.pos_m - g.home().pos_m;
        println!(
            "{}",
            json!({
                "x_mm": off.x * 1e3, "y_mm": off.y * 1e3, "z_mm": off.z * 1e3,
                "roll_deg": r.to_degrees(), "pitch_deg": p.to_degrees(), "yaw_deg": y.to_degrees(),
                "iterations": sol.iterations, "residual_m": sol.residual_m, "condition": sol.condition,
            })
        );
    } else {
        print!("{}", text::fk(&g.home(), &sol));
    }
    Ok(())
}
