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
    /// Draw history columns of a run against time: DIR/NAME.svg and DIR/NAME.png.
    Plot {
        /// A run's output folder (it holds history.csv).
        dir: PathBuf,
        /// Columns to draw, comma-separated (default: every contact's normal force).
        #[arg(long, value_delimiter = ',')]
        columns: Vec<String>,
        /// File name of the chart, without extension.
        #[arg(long, default_value = "plot")]
        name: String,
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
        Command::Plot { dir, columns, name } => {
            use impact::output::plot::{chart, Table};
            let table = Table::read(&dir.join("history.csv"))
                .with_context(|| format!("reading the history of {}", dir.display()))?;
            let columns = if columns.is_empty() {
                table
                    .columns
                    .iter()
                    .filter(|c| c.ends_with(".normal_force"))
                    .cloned()
                    .collect()
            } else {
                columns
            };
            if let Some(bad) = columns.iter().find(|c| !table.columns.contains(c)) {
                anyhow::bail!(
                    "{}: no column \"{bad}\" (the columns are: {})",
                    dir.join("history.csv").display(),
                    table.columns.join(", ")
                );
            }
            if columns.is_empty() {
                anyhow::bail!(
                    "{}: no columns to draw; name them with --columns a,b",
                    dir.display()
                );
            }
            chart(&table, &columns.join(", "), &columns).write(&dir, &name)?;
            println!(
                "{}: {} and {}",
                columns.join(", "),
                dir.join(format!("{name}.svg")).display(),
                dir.join(format!("{name}.png")).display()
            );
            Ok(())
        }
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
