//! The `impact` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::{Parser, Subcommand};
use impact::run::{run, RunOptions};
use impact::scene::{DeviceChoice, Scene};

#[derive(Parser)]
#[command(
    name = "impact",
    version,
    about = "Contact-impact finite elements (Duan & Ye 2002)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene and write history.csv and summary.json.
    Run {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Output folder (default: the scene's output.dir, or results/<scene stem>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Where the kernels run; overrides the scene's run.device.
        #[arg(long, value_parser = ["auto", "gpu", "cpu"])]
        device: Option<String>,
        /// No progress lines.
        #[arg(long)]
        quiet: bool,
    },
    /// List the GPU adapters found, the one each device setting would use, and the limits
    /// and features that matter to the kernels.
    Info,
}

fn main() -> ExitCode {
    match real_main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn real_main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Run {
            scene,
            out,
            device,
            quiet,
        } => {
            let sc = Scene::load(&scene)?;
            let device = device
                .map(|d| d.parse::<DeviceChoice>())
                .transpose()
                .map_err(anyhow::Error::msg)?;
            let opts = RunOptions { out, device, quiet };
            let dir = impact::run::output_dir(&sc, &opts);
            let s = run(&sc, &opts).with_context(|| format!("running {}", scene.display()))?;
            println!(
                "{}: {} steps in {:.2} s on {} ({} iterations, at most {} per step); energy {:.6e} -> {:.6e}; results in {}",
                scene.display(),
                s.steps,
                s.wall_seconds,
                s.device,
                s.iterations_total,
                s.iterations_max,
                s.energy_initial,
                s.energy_final,
                dir.display()
            );
            Ok(())
        }
        Command::Info => {
            print!("{}", impact::gpu::context::info_report()?);
            Ok(())
        }
    }
}
