//! `checkpoint.bin`: everything a run needs to continue bit for bit (`impact run --resume`),
//! with a hash of the scene it belongs to.
//!
//! The file is the bincode of [`Checkpoint`] followed by the CRC-32 of those bytes
//! (little-endian). A file whose checksum does not match is refused before anything is
//! restored: one flipped byte anywhere, or a truncated file, never resumes to another history.
//!
//! A checkpoint holds the integrator's state after a whole step, the run's tallies (iteration
//! counts, energies, the watch for warnings) and the VTU frames written so far. The scene's
//! hash leaves out `run.end_time` and `[output]`: a run may be continued to a later end time,
//! or with other output settings, and nothing else.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{ImpactError, Result};
pub use crate::integrate::SolverState;
use crate::scene::Scene;

/// The file name inside the run's folder.
pub(crate) const FILE: &str = "checkpoint.bin";

/// Bumped whenever the layout changes, or what the scene hash covers (a new scene key), so
/// that an older checkpoint is refused as such, not misread or taken for another scene's.
pub(crate) const FORMAT: u32 = 17;

/// What the time loop accumulates for the summary and the warnings.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Tally {
    pub steps: usize,
    pub iterations_total: usize,
    pub iterations_max: usize,
    pub unconverged_steps: usize,
    pub energy_initial: f64,
    pub energy_final: f64,
    pub energy_max: f64,
    /// The largest departure of the closed balance, total energy + friction work + impact
    /// loss of every contact, from the initial energy (the runs whose contacts measure their
    /// impact loss: explicit ones).
    pub balance_departure: Option<f64>,
    /// The first step whose contact iteration did not converge, and its time.
    pub first_unconverged: Option<(usize, f64)>,
    /// Each interface's largest normal force so far.
    pub peak_force: Vec<f64>,
    /// Each interface's deepest penetration so far, with its step and time.
    pub deepest: Vec<(f64, usize, f64)>,
    /// Each rigid body interface's largest step of relative motion so far, over half the
    /// rigid shape's thickness, with its step and time (`run::summary::count_motion`).
    pub fastest: Vec<(f64, usize, f64)>,
    /// The largest of each ply failure index so far (materials with strengths, engines that
    /// survey every step).
    pub failure_max: Option<[f64; 5]>,
    /// Where and when a ply failure index first reached 1.
    pub first_failure: Option<crate::output::failure_survey::FirstFailure>,
    /// The work the `[[load]]`s have done so far.
    #[serde(default)]
    pub external_work: f64,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    pub format: u32,
    pub scene_hash: u64,
    /// The scene's speed scale when the run began (the default tolerances follow it).
    pub speed_scale: f64,
    pub tally: Tally,
    /// VTU frames written up to this state: (time, file name), and the file names' stem.
    pub frames: Vec<(f64, String)>,
    pub frame_stem: String,
    pub solver: SolverState,
    /// Where the run computed: "cpu" (f64) or the GPU adapter's name (f32). A run resumes
    /// on the same kind, so that its history is one precision's.
    pub device: String,
}

impl Checkpoint {
    /// Writes `dir/checkpoint.bin` (through a temporary file and a rename, so a crash while
    /// writing leaves the previous checkpoint whole).
    pub fn write(&self, dir: &Path) -> Result<()> {
        let path = dir.join(FILE);
        let mut bytes = bincode::serialize(self).map_err(|e| ImpactError::Write {
            path: path.clone(),
            source: std::io::Error::other(e.to_string()),
        })?;
        let sum = crc32fast::hash(&bytes);
        bytes.extend_from_slice(&sum.to_le_bytes());
        crate::output::file::write_whole(&path, &bytes)
    }

    /// Reads `dir/checkpoint.bin` and checks that it belongs to `scene`.
    pub fn read(dir: &Path, scene: &Scene) -> Result<Checkpoint> {
        let path = dir.join(FILE);
        let refuse = |message: String| ImpactError::Resume {
            dir: dir.to_path_buf(),
            message,
        };
        let bytes = crate::limits::read_own(&path)
            .map_err(|e| refuse(format!("{}: {e}", path.display())))?;
        let payload =
            checked_payload(&bytes).map_err(|what| refuse(format!("{} {what}", path.display())))?;
        let c: Checkpoint = bincode::deserialize(payload).map_err(|e| {
            refuse(format!(
                "{} is not a checkpoint of this version of impact ({e})",
                path.display()
            ))
        })?;
        if c.scene_hash != scene_hash(scene) {
            return Err(refuse(format!(
                "the checkpoint belongs to another scene: {} differs from the run's scene in more than run.end_time and [output]",
                scene.path.display()
            )));
        }
        Ok(c)
    }
}

/// The bytes before the checksum, where the file's own format is this one's and the
/// checksum matches; otherwise what is wrong. The format (the first four bytes) is read
/// before the checksum, so that an older impact's checkpoint is named as such.
fn checked_payload(bytes: &[u8]) -> std::result::Result<&[u8], String> {
    let Some(format) = bytes.first_chunk::<4>().map(|b| u32::from_le_bytes(*b)) else {
        return Err(format!(
            "holds {} bytes: it is not a checkpoint",
            bytes.len()
        ));
    };
    if format != FORMAT {
        return Err(format!(
            "has format {format}, this impact reads {FORMAT} (or the file is damaged)"
        ));
    }
    let (payload, sum) = bytes
        .split_last_chunk::<4>()
        .filter(|(p, _)| p.len() >= 4)
        .ok_or_else(|| format!("holds {} bytes: it was cut short", bytes.len()))?;
    let (stored, computed) = (u32::from_le_bytes(*sum), crc32fast::hash(payload));
    if stored != computed {
        return Err(format!(
            "fails its checksum (stored {stored:08x}, computed {computed:08x}): it was damaged or cut short after it was written"
        ));
    }
    Ok(payload)
}

/// A hash of the scene without `run.end_time` and `[output]` (and without the paths of the
/// scene and its mesh files: the meshes' contents are in it).
pub fn scene_hash(scene: &Scene) -> u64 {
    let mut s = scene.clone();
    s.path = PathBuf::new();
    s.run.end_time = 0.0;
    s.output_dir = PathBuf::new();
    s.vtu_every = None;
    s.checkpoint_every = None;
    s.notices.clear();
    // a mesh file is known by its contents (in the hash), not by where it was read from
    for b in &mut s.bodies {
        if let crate::scene::BodyShape::Imported { path, .. } = &mut b.shape {
            *path = PathBuf::new();
        }
    }
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    let _ = write!(h, "{s:?}");
    h.0
}

/// FNV-1a over formatted text, without building the text.
struct Fnv(u64);

impl std::fmt::Write for Fnv {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for b in s.bytes() {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        Ok(())
    }
}
