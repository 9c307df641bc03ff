//! The `impact` command line.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::Context;
use clap::{Parser, Subcommand};
use impact::error::exit;
use impact::run::{run, RunOptions};
use impact::scene::{DeviceChoice, Scene};
use impact::ImpactError;

#[derive(Parser)]
#[command(
    name = "impact",
    version,
    about = "Contact-impact finite elements (Duan & Ye 2002)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Threads of the CPU work (the CPU kernels, setup, the implicit solves); results do not
    /// depend on it. Default: every core.
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene and write history.csv and summary.json.
    Run {
        /// The scene file (TOML), or an Abaqus/CalculiX deck (.inp) or LS-DYNA keyword file (.k).
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
        /// Replace the files of an earlier run in the output folder.
        #[arg(long, conflicts_with = "resume")]
        overwrite: bool,
        /// Continue the run in the output folder from its latest checkpoint, to the scene's
        /// end_time (the scene may differ from the first run's only in end_time and [output]).
        #[arg(long)]
        resume: bool,
        /// Fail (exit status 6) when the run completes with warnings.
        #[arg(long)]
        strict: bool,
    },
    /// Read, build and check a scene's model without running it: bodies, stable step,
    /// contact interfaces and their initial gaps, fixes, method and memory.
    Check {
        /// The scene file (TOML), or an Abaqus/CalculiX deck (.inp) or LS-DYNA keyword file (.k).
        scene: PathBuf,
        /// Where the kernels would run; overrides the scene's run.device.
        #[arg(long, value_parser = ["auto", "gpu", "cpu"])]
        device: Option<String>,
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
    /// Accuracy against speed on a problem with an exact answer: a grid of methods, devices,
    /// meshes and time steps; writes study.csv, study.svg/png, atlas.svg/png and atlas.md
    /// (crack_band: the energy a damaging element dissipates against its size; writes
    /// crack_band.csv and crack_band.svg/png).
    Study {
        /// two_bars, bar_on_wall, sliding_block or crack_band.
        problem: String,
        /// Output folder (default: results/study_<problem>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// A small grid (about a minute at most; CPU only unless --devices says otherwise).
        #[arg(long)]
        quick: bool,
        /// Devices to run on, comma-separated (default: cpu, and gpu when an adapter exists;
        /// --quick: cpu).
        #[arg(long, value_delimiter = ',')]
        devices: Vec<String>,
        /// Keep every run's own folder (history, summary, charts) under OUT/runs.
        #[arg(long)]
        keep_runs: bool,
        /// Replace an earlier study's files in OUT.
        #[arg(long)]
        overwrite: bool,
    },
    /// Write the scene an Abaqus/CalculiX deck (.inp) or LS-DYNA file (.k) runs as, its mesh kept in it:
    /// running the scene gives the deck's history.
    Convert {
        /// The deck.
        deck: PathBuf,
        /// The scene file to write (beside the deck, whose file its bodies name).
        #[arg(long)]
        to: PathBuf,
        /// Replace the scene file if it exists.
        #[arg(long)]
        overwrite: bool,
    },
    /// List the GPU adapters found, the one each device setting would use, and the limits
    /// and features that matter to the kernels.
    Info,
}

fn main() -> ExitCode {
    quiet_device_select();
    let code = match real_main() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", chain(&e));
            e.downcast_ref::<ImpactError>()
                .map_or(exit::OTHER, ImpactError::exit_code)
        }
    };
    quick_exit(code)
}

/// Ends the process with `code` once everything is written, without the C libraries' exit
/// handlers. Those tear down the GPU drivers' state while the drivers' own threads may still
/// run: on lavapipe one such race corrupted the heap at exit (an MPI rank then hung in Open
/// MPI's abort handler, after its run had completed and written its files). The devices are
/// closed and MPI is finalised before this (in `real_main`), and nothing of ours waits on an
/// exit handler.
fn quick_exit(code: u8) -> ! {
    use std::io::Write;
    let _ = std::io::stdout().flush();
    let _ = std::io::stderr().flush();
    // SAFETY: _exit ends the process; every file of the run is written and closed, the
    // standard streams flushed just above
    unsafe { libc::_exit(i32::from(code)) }
}

/// Mesa's Vulkan device-select layer looks for a desktop session to order the adapters, and
/// without one prints "XDG_RUNTIME_DIR is invalid or not set" on every GPU run. impact orders
/// the adapters itself, so the layer is turned off where there is no session (called first
/// in `main`, before any thread exists, as changing the environment requires).
fn quiet_device_select() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none()
        && std::env::var_os("NODEVICE_SELECT").is_none()
    {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// The error and its causes on one line, each cause once: a cause whose text its parent
/// already quotes (an OS error inside a message) is not repeated.
fn chain(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if !out.contains(&text) {
            if !out.is_empty() {
                out.push_str(": ");
            }
            out.push_str(&text);
        }
    }
    out
}

/// Sets a flag on SIGINT and SIGTERM; the run polls it between steps.
fn interrupt_flag() -> Option<Arc<AtomicBool>> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = flag.clone();
    ctrlc::set_handler(move || {
        if f.swap(true, Ordering::SeqCst) {
            // a second signal: stop now, without the checkpoint
            std::process::exit(i32::from(exit::INTERRUPTED));
        }
    })
    .ok()?;
    Some(flag)
}

/// The default threads of one of several MPI processes on a machine: the machine's cores
/// shared among them (every process taking every core would run P times as many threads
/// as cores).
fn rank_threads() -> Option<usize> {
    let local = impact::domain::launch::launched_local_size().filter(|&n| n > 1)?;
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    Some((cores / local).max(1))
}

fn parse_device(device: Option<String>) -> anyhow::Result<Option<DeviceChoice>> {
    device
        .map(|d| d.parse::<DeviceChoice>())
        .transpose()
        .map_err(anyhow::Error::msg)
}

/// The stack of the thread a command runs on (the main thread's usual size).
const COMMAND_STACK: usize = 8 << 20;

fn real_main() -> anyhow::Result<u8> {
    let cli = Cli::parse();
    let threads = cli.threads.map(usize::from).or_else(rank_threads);
    // The command runs on a worker of the CPU threads' pool, so that its serial parts share
    // the cores with the other workers alone: beside a main thread waiting on the pool, the
    // workers' spinning between parallel parts took the cores the serial parts needed (on
    // two cores the implicit steps ran 15-20% slower).
    let mut pool = rayon::ThreadPoolBuilder::new().stack_size(COMMAND_STACK);
    if let Some(n) = threads {
        pool = pool.num_threads(n);
    }
    let pool = pool.build().context("setting up the CPU threads")?;
    let code = pool.install(|| command(cli.command));
    close_devices();
    code
}

/// Closes the GPU devices the process opened, before it ends; a failure there comes after
/// the results are written and does not change them, so it is a warning.
fn close_devices() {
    if let Err(e) = impact::gpu::close_devices() {
        eprintln!("warning: closing the GPU devices: {e}");
    }
}

/// Runs one command of the command line.
fn command(command: Command) -> anyhow::Result<u8> {
    match command {
        Command::Study {
            problem,
            out,
            quick,
            devices,
            keep_runs,
            overwrite,
        } => study_command(&problem, out, quick, devices, (keep_runs, overwrite)),
        Command::Plot { dir, columns, name } => plot_command(&dir, columns, &name),
        Command::Run {
            scene,
            out,
            device,
            quiet,
            overwrite,
            resume,
            strict,
        } => run_command(&scene, out, device, quiet, overwrite, resume, strict),
        Command::Check { scene, device } => check_command(&scene, device),
        Command::Info => info_command(),
        Command::Convert {
            deck,
            to,
            overwrite,
        } => convert_command(&deck, &to, overwrite),
    }
}

/// `impact study`: the accuracy-against-speed study of a problem.
fn study_command(
    problem: &str,
    out: Option<PathBuf>,
    quick: bool,
    devices: Vec<String>,
    (keep_runs, overwrite): (bool, bool),
) -> anyhow::Result<u8> {
    use impact::study::{study, Problem};
    let p = Problem::parse(problem);
    if p.is_none() && problem != "crack_band" {
        eprintln!(
            "error: unknown problem \"{problem}\" (the problems are: {}, crack_band)",
            Problem::NAMES
        );
        return Ok(exit::USAGE);
    }
    let out = out.unwrap_or_else(|| PathBuf::from(format!("results/study_{problem}")));
    if let Some(bad) = devices
        .iter()
        .find(|d| !matches!(d.as_str(), "cpu" | "gpu"))
    {
        eprintln!("error: --devices: unknown device \"{bad}\" (the devices are cpu and gpu)");
        return Ok(exit::USAGE);
    }
    let devices: Vec<String> = if !devices.is_empty() {
        devices
    } else if quick || impact::gpu::GpuContext::new().is_err() {
        vec!["cpu".into()]
    } else {
        vec!["cpu".into(), "gpu".into()]
    };
    let devices: Vec<&str> = devices.iter().map(String::as_str).collect();
    // held until the study ends: a second study into the folder is refused
    let _lock = impact::study::folder::claim(&out, overwrite)?;
    let Some(p) = p else {
        return crack_band_command(&out, quick, &devices, keep_runs);
    };
    let rows = study(p, &out, quick, &devices, keep_runs, &mut |r| {
        eprintln!(
            "{} {} {} el, c dt/h {}: force error {:.3e}, {:.3} s, {}",
            r.method.name(),
            r.device,
            r.elements,
            r.courant,
            r.errors.force,
            r.wall_seconds,
            r.status
        );
    })?;
    println!(
        "{} runs; {} written",
        rows.len(),
        [
            "study.csv",
            "study.svg",
            "study.png",
            "atlas.svg",
            "atlas.png",
            "atlas.md"
        ]
        .map(|f| out.join(f).display().to_string())
        .join(", ")
    );
    Ok(exit::SUCCESS)
}

/// `impact study crack_band`: the energy a damaging element dissipates against its size.
fn crack_band_command(
    out: &Path,
    quick: bool,
    devices: &[&str],
    keep_runs: bool,
) -> anyhow::Result<u8> {
    let rows = impact::study::crack_band::study(out, quick, devices, keep_runs, &mut |r| {
        eprintln!(
            "{} {} h {} mm: dissipated {:.4e}, G A {:.4e} (ratio {:.4}), snap-back width {:.3} mm, {:.3} s",
            r.mode,
            r.device,
            r.size,
            r.dissipated,
            r.exact,
            r.dissipated / r.exact,
            r.snap_back_width,
            r.wall_seconds
        );
    })?;
    println!(
        "{} runs; {} written",
        rows.len(),
        ["crack_band.csv", "crack_band.svg", "crack_band.png"]
            .map(|f| out.join(f).display().to_string())
            .join(", ")
    );
    Ok(exit::SUCCESS)
}

/// `impact plot`: history columns as an SVG and a PNG chart.
fn plot_command(dir: &Path, columns: Vec<String>, name: &str) -> anyhow::Result<u8> {
    use impact::output::plot::{chart, Table};
    if let Some(why) = chart_name_refused(name) {
        eprintln!("error: --name {name:?}: {why}");
        return Ok(exit::USAGE);
    }
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
    // a column the history lacks is a usage error, like a bad flag
    if let Some(bad) = columns.iter().find(|c| !table.columns.contains(c)) {
        eprintln!(
            "error: --columns: {} has no column \"{bad}\" (the columns are: {})",
            dir.join("history.csv").display(),
            table.columns.join(", ")
        );
        return Ok(exit::USAGE);
    }
    if columns.is_empty() {
        eprintln!(
            "error: {}: no contact force columns to draw; name columns with --columns a,b",
            dir.display()
        );
        return Ok(exit::USAGE);
    }
    chart(&table, &columns.join(", "), &columns).write(dir, name)?;
    println!(
        "{}: {} and {}",
        columns.join(", "),
        dir.join(format!("{name}.svg")).display(),
        dir.join(format!("{name}.png")).display()
    );
    Ok(exit::SUCCESS)
}

/// `impact run`: runs a scene and prints its outcome.
#[allow(clippy::too_many_arguments)]
fn run_command(
    scene: &Path,
    out: Option<PathBuf>,
    device: Option<String>,
    quiet: bool,
    overwrite: bool,
    resume: bool,
    strict: bool,
) -> anyhow::Result<u8> {
    let sc = Scene::load(scene)?;
    let opts = RunOptions {
        out,
        device: parse_device(device)?,
        quiet,
        overwrite,
        resume,
        // every rank of a decomposed run has one: the ranks agree on it each step
        interrupt: interrupt_flag(),
    };
    let dir = impact::run::output_dir(&sc, &opts);
    let (s, first) = run_scene(&sc, opts)?;
    if !first {
        return Ok(exit::SUCCESS);
    }
    println!(
        "{}: {} steps in {:.2} s{} on {} ({} contact iterations, at most {} in a step); energy {:.6e} -> {:.6e}{}; {}; results in {}",
        scene.display(),
        s.steps,
        s.wall_seconds,
        s.device_seconds
            .map_or(String::new(), |d| format!(" ({d:.2} s on the device)")),
        s.device,
        s.iterations_total,
        s.iterations_max,
        s.energy_initial,
        s.energy_final,
        balance_text(&s),
        s.status,
        dir.display()
    );
    for w in &s.warnings {
        eprintln!("warning: {}: {}", w.kind, w.message);
    }
    Ok(if strict && !s.warnings.is_empty() {
        eprintln!(
            "error: --strict: the run completed with {} warning(s)",
            s.warnings.len()
        );
        exit::WARNINGS_STRICT
    } else {
        exit::SUCCESS
    })
}

/// Runs the scene on this process, or, started by `mpirun -n P` with P > 1, decomposed over
/// the P ranks. Returns the summary and whether this process is the first (which reports).
#[cfg(feature = "mpi")]
fn run_scene(sc: &Scene, opts: RunOptions) -> anyhow::Result<(impact::output::Summary, bool)> {
    use impact::domain::mpi::MpiRanks;
    use impact::domain::Ranks;
    use mpi::traits::Communicator;
    if !impact::domain::launch::launched() {
        return Ok((run(sc, &opts)?, true));
    }
    let universe = mpi::initialize().context("initialising MPI")?;
    let world = universe.world();
    if world.size() == 1 {
        let ran = run(sc, &opts);
        close_devices();
        return Ok((ran?, true));
    }
    let ranks = MpiRanks::new(world);
    let ran = impact::run::run_ranks(sc, &opts, &ranks);
    // the devices close before `MPI_Finalize` (when `universe` drops)
    close_devices();
    match ran {
        Ok(s) => Ok((s, ranks.rank() == 0)),
        // an error every rank meets alike ends every rank; rank 0 says why
        Err(e) if same_on_every_rank(&e) => match ranks.rank() {
            0 => Err(e.into()),
            _ => Ok((Default::default(), false)),
        },
        // an error on some ranks only would leave the others waiting: say it, end the job
        Err(e) => {
            eprintln!("error (rank {}): {e}", ranks.rank());
            world_abort(&universe, e.exit_code())
        }
    }
}

/// Whether every rank of a decomposed run meets error `e` alike and stops on its own: the
/// scene's values (checked the same on every rank), what a decomposed run refuses, a
/// checkpoint that does not fit the run (checked the same on every rank), a failure in a
/// stage the ranks agree on (the output folder, reading a checkpoint, the resumed start, a
/// checkpoint's write), a diverged run (the energy it is judged by is summed over the
/// ranks, the same bits on each) and an interrupted one (the ranks agree on the signal
/// after each step). Rank 0 then writes what a stopped run leaves before it ends.
#[cfg(feature = "mpi")]
fn same_on_every_rank(e: &ImpactError) -> bool {
    use ImpactError::*;
    matches!(
        e,
        SceneValue { .. }
            | Unsupported { .. }
            | OutputExists { .. }
            | Resume { .. }
            | Agreed(_)
            | Diverged { .. }
            | Interrupted { .. }
            | Ranks(_)
    )
}

/// Ends every process of the MPI job with `code` (`MPI_Abort`).
#[cfg(feature = "mpi")]
fn world_abort(universe: &mpi::environment::Universe, code: u8) -> ! {
    use mpi::traits::Communicator;
    universe.world().abort(i32::from(code))
}

/// The run line's balance, where the summary has one: its largest departure, the contacts'
/// losses counted, as a share of the initial energy.
fn balance_text(s: &impact::output::Summary) -> String {
    match s.energy_balance {
        Some(b) if s.energy_initial > 0.0 => {
            format!(" (balance within {:.2}%)", 100.0 * b / s.energy_initial)
        }
        _ => String::new(),
    }
}

/// Runs the scene on this process; started by an MPI launcher with more than one process,
/// says that this build has no MPI (every process would run the whole scene).
#[cfg(not(feature = "mpi"))]
fn run_scene(sc: &Scene, opts: RunOptions) -> anyhow::Result<(impact::output::Summary, bool)> {
    if let Some(n) = impact::domain::launch::launched_size().filter(|&n| n > 1) {
        anyhow::bail!(
            "started as one of {n} MPI processes, but this build of impact has no MPI: build it with `cargo build --release --features mpi` (docs/mpi.md)"
        );
    }
    Ok((run(sc, &opts)?, true))
}

/// `impact check`: builds and checks the model, and prints its report.
fn check_command(scene: &Path, device: Option<String>) -> anyhow::Result<u8> {
    let sc = Scene::load(scene)?;
    let device = parse_device(device)?.unwrap_or(sc.run.device);
    let mut clock = impact::output::summary::SetupClock::start();
    let setup = impact::setup::prepare(&sc, device, &mut |l| eprintln!("{l}"), &mut clock)?;
    print!("{}", impact::report::model_report(&sc, &setup)?);
    Ok(exit::SUCCESS)
}

/// `impact info`: threads, adapters and limits.
fn info_command() -> anyhow::Result<u8> {
    println!(
        "CPU threads: {} ({} cores; --threads N sets it)",
        rayon::current_num_threads(),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    print!("{}", impact::gpu::context::info_report()?);
    Ok(exit::SUCCESS)
}

/// Why `impact plot` may not write a chart named `name`, if it may not: an empty or hidden
/// name, a character that is not a letter, digit, `_`, `-` or `.`, or the name of a chart the
/// run writes itself (`plot` would replace it).
fn chart_name_refused(name: &str) -> Option<String> {
    if name.is_empty() || name.starts_with('.') {
        return Some(
            "a chart's name is not empty and does not start with `.` (a hidden file)".into(),
        );
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')))
    {
        return Some(format!(
            "holds {c:?}: a chart's name is made of ASCII letters, digits, `_`, `-` and `.`"
        ));
    }
    let own = ["forces", "energies", "delamination"].contains(&name)
        || name.starts_with("exact_")
        || name.ends_with("_force_displacement");
    own.then(|| {
        "the run writes a chart of that name itself (forces, energies, delamination, exact_*, *_force_displacement): choose another".into()
    })
}

/// `impact convert`: the deck's scene written to `to`, and the deck's notice.
fn convert_command(
    deck: &std::path::Path,
    to: &std::path::Path,
    overwrite: bool,
) -> anyhow::Result<u8> {
    let usage = |path: &std::path::Path, message: String| ImpactError::Usage {
        path: path.to_path_buf(),
        message,
    };
    if !impact::scene::from_deck::is_deck(deck) {
        return Err(usage(deck, "not a deck: impact converts Abaqus/CalculiX decks (.inp) and LS-DYNA keyword files (.k)".into()).into());
    }
    let converted = impact::scene::from_deck::convert(deck)?;
    let folder = |p: &std::path::Path| -> std::path::PathBuf {
        let d = p.parent().filter(|d| !d.as_os_str().is_empty());
        d.unwrap_or(std::path::Path::new(".")).to_path_buf()
    };
    if folder(deck).canonicalize().ok() != folder(to).canonicalize().ok() {
        let message = format!(
            "write the scene in the deck's folder ({}), whose file its bodies name",
            folder(deck).display()
        );
        return Err(usage(to, message).into());
    }
    // the deck and its includes are never written over, whatever name reaches them
    let target = to.canonicalize().ok();
    if let Some(f) =
        (converted.files.iter()).find(|f| target.is_some() && f.canonicalize().ok() == target)
    {
        let message = format!(
            "is the deck or a file it reads ({}): write the scene to another file",
            f.display()
        );
        return Err(usage(to, message).into());
    }
    if to.exists() && !overwrite {
        return Err(usage(to, "exists: pass --overwrite to replace it".into()).into());
    }
    // the scene must be one impact reads
    impact::scene::Scene::parse(&converted.toml, to).map_err(|e| converted.locate(e))?;
    std::fs::write(to, &converted.toml).map_err(|source| ImpactError::Write {
        path: to.to_path_buf(),
        source,
    })?;
    if let Some(n) = converted.notice {
        eprintln!("notice: {n}");
    }
    Ok(0)
}
