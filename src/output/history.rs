//! `history.csv`: one row per step (and a first row for t = 0), columns as
//! `scene-format.md` fixes them. Counts are integers, every other value is in its shortest
//! round-trip form ([`shortest`]).

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{ImpactError, Result};
use crate::integrate::{ContactReport, Energies};
use crate::kernels::cohesive_forces::CohesiveReport;
use crate::model::Model;

pub struct History {
    path: PathBuf,
    /// Interfaces with friction, whose `sliding` and `friction_work` come after the probes.
    frictional: Vec<usize>,
    /// Interfaces whose primary side is a rigid body, whose force vectors come next.
    rigid: Vec<usize>,
    /// Rigid bodies that rotate, whose rotation vector and angular velocity come next.
    spinning: usize,
    /// Whether a material has ply strengths: the largest failure indices come next.
    failure: bool,
    /// Whether a material damages or a cohesive interface: the energy damage dissipated
    /// comes next.
    damage: bool,
    /// Whether a material damages: the plies' fibre and matrix modes' shares come next.
    plies: bool,
    /// Whether the model has loads (then the `external_work` column).
    loads: bool,
    /// The named fixes, whose reactions come next.
    reactions: usize,
    /// The cohesive interfaces, whose areas and energy close the row.
    cohesive: usize,
    /// The file (none on a rank that computes the rows and leaves the file to rank 0).
    file: Option<File>,
    /// Whole rows not yet written.
    pending: String,
    /// The file's length, which always ends on a whole row: a failed write is cut back to it.
    whole: u64,
    line: String,
}

pub use crate::integrate::state::ProbeValues;

/// A row's columns past the probes: each rotating rigid body's rotation and angular
/// velocity, the largest failure indices (where surveyed), each named fix's reaction and
/// each cohesive interface's report.
pub type RowExtras<'a> = (
    &'a [ProbeValues],
    Option<&'a [f64; 5]>,
    &'a [[f64; 3]],
    &'a [CohesiveReport],
);

/// Rows are written in batches of about this many bytes.
const BATCH: usize = 8 * 1024;

impl History {
    fn open(path: PathBuf, model: &Model, file: Option<File>, whole: u64) -> History {
        History {
            path,
            frictional: (0..model.interfaces.len())
                .filter(|&i| model.interfaces[i].law.is_frictional())
                .collect(),
            rigid: (0..model.interfaces.len())
                .filter(|&i| model.interfaces[i].is_rigid())
                .collect(),
            spinning: model.rigid.iter().filter(|b| b.rotates()).count(),
            failure: model.strengths.iter().any(Option::is_some),
            damage: has_damage(model),
            plies: model.damage_laws.iter().any(Option::is_some),
            loads: !model.loads.is_empty(),
            reactions: model.reactions.len(),
            cohesive: model.cohesive.len(),
            file,
            pending: String::new(),
            whole,
            line: String::new(),
        }
    }

    /// Creates the file and writes the header.
    pub fn create(dir: &Path, model: &Model) -> Result<History> {
        let path = dir.join("history.csv");
        let file = File::create(&path).map_err(|source| ImpactError::Write {
            path: path.clone(),
            source,
        })?;
        let mut h = History::open(path, model, Some(file), 0);
        h.line = column_names(model).join(",");
        h.flush_line()?;
        Ok(h)
    }

    /// Reopens the history of a run to continue it: keeps the header and the first `rows`
    /// rows (the state a checkpoint holds, the last at `time`) and appends after them. The
    /// header must be the model's, and those rows whole rows of numbers ending at the
    /// checkpoint's step and time; otherwise the file is left as it is.
    pub fn resume(dir: &Path, model: &Model, rows: usize, time: f64) -> Result<History> {
        let path = dir.join("history.csv");
        let read_err = |source| ImpactError::Read {
            path: path.clone(),
            source,
        };
        let text = crate::limits::read_own_text(&path).map_err(read_err)?;
        let header = column_names(model).join(",");
        let bad = |what: String| ImpactError::Resume {
            dir: dir.to_path_buf(),
            message: format!("{}: {what}", path.display()),
        };
        if text.lines().next() != Some(header.as_str()) {
            return Err(bad("its columns are not this model's".into()));
        }
        // the byte offset after the header and `rows` rows
        let keep = text
            .match_indices('\n')
            .nth(rows)
            .map(|(i, _)| i + 1)
            .ok_or_else(|| bad(format!("it holds fewer than the checkpoint's {rows} rows")))?;
        let fields = header.split(',').count();
        check_rows(&text[header.len() + 1..keep], fields, (rows - 1, time)).map_err(bad)?;
        let write_err = |source| ImpactError::Write {
            path: path.clone(),
            source,
        };
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .open(&path)
            .map_err(read_err)?;
        file.set_len(keep as u64).map_err(write_err)?;
        std::io::Seek::seek(&mut file, std::io::SeekFrom::End(0)).map_err(write_err)?;
        Ok(History::open(path, model, Some(file), keep as u64))
    }

    /// A history that writes nothing: the one of a rank other than the first in a
    /// decomposed run, which computes every row's sums with the others but leaves the file
    /// to rank 0.
    pub fn discard(model: &Model) -> History {
        History::open(PathBuf::from("history.csv"), model, None, 0)
    }

    fn flush_line(&mut self) -> Result<()> {
        self.line.push('\n');
        if self.file.is_some() {
            self.pending.push_str(&self.line);
        }
        self.line.clear();
        match self.pending.len() >= BATCH {
            true => self.flush(),
            false => Ok(()),
        }
    }

    /// Appends one row; `spins` holds each rotating rigid body's rotation vector and angular
    /// velocity, `reactions` each named fix's, `cohesive` each cohesive interface's report.
    pub fn row(
        &mut self,
        time: f64,
        step: usize,
        e: &Energies,
        (bodies, contacts, probes): (&[[f64; 3]], &[ContactReport], &[ProbeValues]),
        (spins, failure, reactions, cohesive): RowExtras,
    ) -> Result<()> {
        use std::fmt::Write as _;
        let l = &mut self.line;
        fn num(l: &mut String, x: f64) {
            l.push(',');
            shortest(x, l);
        }
        shortest(time, l);
        let _ = write!(l, ",{step}");
        for x in [e.kinetic, e.strain, e.total()] {
            num(l, x);
        }
        for v in bodies {
            for &x in v {
                num(l, x);
            }
        }
        for c in contacts {
            num(l, c.normal_force);
            num(l, c.tangential_force);
            let _ = write!(l, ",{}", c.active);
            num(l, c.max_penetration);
        }
        for (u, v) in probes {
            for &x in u.iter().chain(v) {
                num(l, x);
            }
        }
        for &i in &self.frictional {
            let _ = write!(l, ",{}", contacts[i].sliding);
            num(l, contacts[i].friction_work);
        }
        for c in contacts {
            num(l, c.impact_loss);
        }
        for &i in &self.rigid {
            for x in contacts[i].force {
                num(l, x);
            }
        }
        for k in 0..self.spinning {
            // NaN where the engine does not rotate bodies (none runs such a model)
            let (r, w) = spins
                .get(k)
                .copied()
                .unwrap_or(([f64::NAN; 3], [f64::NAN; 3]));
            for &x in r.iter().chain(&w) {
                num(l, x);
            }
        }
        if self.failure {
            // NaN where the engine does not survey every step (scene-format.md)
            for x in failure.copied().unwrap_or([f64::NAN; 5]) {
                num(l, x);
            }
        }
        if self.damage {
            num(l, e.damage);
        }
        if self.plies {
            num(l, e.plies.fibre);
            num(l, e.plies.matrix());
        }
        for k in 0..self.reactions {
            // NaN where the engine gives no reactions (scene-format.md)
            for x in reactions.get(k).copied().unwrap_or([f64::NAN; 3]) {
                num(l, x);
            }
        }
        for k in 0..self.cohesive {
            let c = cohesive.get(k).copied().unwrap_or(CohesiveReport {
                delaminated_area: f64::NAN,
                damaged_area: f64::NAN,
                energy: f64::NAN,
            });
            for x in [c.delaminated_area, c.damaged_area, c.energy] {
                num(l, x);
            }
        }
        if self.loads {
            num(l, e.load_work);
        }
        self.flush_line()
    }

    /// Pushes the rows held back to disk (called on every exit path, so a diverged run keeps
    /// them). A write that fails part way is cut back, so the file ends on a whole row.
    pub fn flush(&mut self) -> Result<()> {
        let Some(file) = self.file.as_mut() else {
            return Ok(());
        };
        if let Err(source) = file.write_all(self.pending.as_bytes()) {
            let _ = file.set_len(self.whole);
            let _ = std::io::Seek::seek(file, std::io::SeekFrom::End(0));
            return Err(ImpactError::Write {
                path: self.path.clone(),
                source,
            });
        }
        self.whole += self.pending.len() as u64;
        self.pending.clear();
        Ok(())
    }
}

impl Drop for History {
    /// A history dropped on any path (an early return, a panic) still writes the rows it
    /// holds back.
    fn drop(&mut self) {
        let _ = self.flush();
    }
}

/// The rows a resumed history keeps: each of `fields` numbers, the last one that of step
/// `step` at `time` (the same bits).
fn check_rows(
    text: &str,
    fields: usize,
    (step, time): (usize, f64),
) -> std::result::Result<(), String> {
    let mut last = None;
    for (i, line) in text.lines().enumerate() {
        let values: Vec<&str> = line.split(',').collect();
        if values.len() != fields || values.iter().any(|v| v.parse::<f64>().is_err()) {
            return Err(format!(
                "row {} is not {fields} numbers (the file was changed or cut after the run wrote it)",
                i + 1
            ));
        }
        last = Some((values[0].to_string(), values[1].to_string()));
    }
    let mut expected = String::new();
    shortest(time, &mut expected);
    match last {
        Some((t, s)) if t == expected && s == step.to_string() => Ok(()),
        Some((t, s)) => Err(format!(
            "its row {} is step {s} at t = {t}, the checkpoint's is step {step} at t = {expected}",
            step + 1
        )),
        None => Err("it holds no rows".into()),
    }
}

/// Appends `x` in the shortest text that `str::parse::<f64>` reads back to the same bits:
/// Rust's shortest round-trip digits, written plain (`0.25`, `-3`, `100`) or with an exponent
/// (`1e-300`, `1.5e20`, `1e3`), whichever is shorter, plain on a tie. `NaN`, `inf` and `-inf`
/// as `Display` writes them. A finite `x` takes at most 24 characters: 17 digits at most, so
/// `-d.ddddddddddddddddde-ddd`.
pub fn shortest(x: f64, out: &mut String) {
    use std::fmt::Write as _;
    let start = out.len();
    if !x.is_finite() {
        let _ = write!(out, "{x}");
        return;
    }
    // `{:e}` and `{}` write the same shortest digits; the exponent says how long the plain
    // form would be, so it need not be written (for 1e-300 it has 302 characters)
    let _ = write!(out, "{x:e}");
    let exp_form = &out[start..];
    let (mantissa, exponent) = exp_form
        .split_once('e')
        .expect("LowerExp writes an exponent");
    let k: i64 = exponent
        .parse()
        .expect("LowerExp writes an integer exponent");
    let digits = mantissa.bytes().filter(u8::is_ascii_digit).count() as i64;
    let sign = i64::from(x.is_sign_negative());
    let plain = sign
        + if k < 0 {
            // 0.000ddd
            2 + (-k - 1) + digits
        } else if digits <= k + 1 {
            // ddd000, no decimal point
            k + 1
        } else {
            // dd.ddd
            digits + 1
        };
    if plain <= exp_form.len() as i64 {
        out.truncate(start);
        let _ = write!(out, "{x}");
    }
}

/// The history's columns for a model, in order.
pub(crate) fn column_names(model: &Model) -> Vec<String> {
    let mut cols: Vec<String> = [
        "time",
        "step",
        "kinetic_energy",
        "strain_energy",
        "total_energy",
    ]
    .map(String::from)
    .to_vec();
    for b in &model.body_names {
        for c in ["vx", "vy", "vz"] {
            cols.push(format!("{b}.{c}"));
        }
    }
    for itf in &model.interfaces {
        for c in [
            "normal_force",
            "tangential_force",
            "active",
            "max_penetration",
        ] {
            cols.push(format!("{}.{c}", itf.name));
        }
    }
    for p in &model.probes {
        for c in ["ux", "uy", "uz", "vx", "vy", "vz"] {
            cols.push(format!("{}.{c}", p.name));
        }
    }
    // columns beyond scene-format.md go last, so the fixed ones keep their places
    for itf in model.interfaces.iter().filter(|i| i.law.is_frictional()) {
        for c in ["sliding", "friction_work"] {
            cols.push(format!("{}.{c}", itf.name));
        }
    }
    // the energy each contact's normal impulses took (NaN where not measured)
    for itf in &model.interfaces {
        cols.push(format!("{}.impact_loss", itf.name));
    }
    // the force on each rigid body by each of its contacts
    for itf in model.interfaces.iter().filter(|i| i.is_rigid()) {
        for c in ["fx", "fy", "fz"] {
            cols.push(format!("{}.{c}", itf.name));
        }
    }
    // the rotation vector and angular velocity of each rigid body that rotates
    for b in model.rigid.iter().filter(|b| b.rotates()) {
        for c in ["rx", "ry", "rz", "wx", "wy", "wz"] {
            cols.push(format!("{}.{c}", b.name));
        }
    }
    // the largest of each ply failure index over the model
    if model.strengths.iter().any(Option::is_some) {
        for c in crate::material::failure::INDICES {
            cols.push(format!("failure_index.{c}"));
        }
    }
    // the energy the plies' damage and the cohesive interfaces dissipated so far
    if has_damage(model) {
        cols.push("damage_energy".into());
    }
    // of it, what the plies' fibre and matrix modes dissipated
    if model.damage_laws.iter().any(Option::is_some) {
        cols.push("damage_energy.fibre".into());
        cols.push("damage_energy.matrix".into());
    }
    // the reaction of each named fix
    for r in &model.reactions {
        for c in ["fx", "fy", "fz"] {
            cols.push(format!("{}.{c}", r.name));
        }
    }
    // each cohesive interface's separated and damaged areas and its dissipation
    for c in &model.cohesive {
        for k in ["delaminated_area", "damaged_area", "energy"] {
            cols.push(format!("{}.{k}", c.name));
        }
    }
    // the work the loads did so far (in the total energy's potential)
    if !model.loads.is_empty() {
        cols.push("external_work".into());
    }
    cols
}

/// Whether the model dissipates energy by damage: a material that damages, or a cohesive
/// interface.
fn has_damage(model: &Model) -> bool {
    model.damage_laws.iter().any(Option::is_some) || !model.cohesive.is_empty()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(x: f64) -> String {
        let mut s = String::new();
        shortest(x, &mut s);
        s
    }

    /// xorshift64*: a fixed sequence, so a failure replays.
    fn bit_patterns(n: usize) -> impl Iterator<Item = u64> {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        (0..n).map(move |_| {
            s ^= s >> 12;
            s ^= s << 25;
            s ^= s >> 27;
            s.wrapping_mul(0x2545_f491_4f6c_dd1d)
        })
    }

    #[test]
    fn examples() {
        for (x, t) in [
            (0.25, "0.25"),
            (1e-300, "1e-300"),
            (1.5e20, "1.5e20"),
            (0.0, "0"),
            (-0.0, "-0"),
            (-3.0, "-3"),
            (100.0, "100"),
            (1000.0, "1e3"),
            (0.01, "0.01"),
            (0.001, "1e-3"),
            (0.1 + 0.2, "0.30000000000000004"),
            (5e-324, "5e-324"),
            (f64::MAX, "1.7976931348623157e308"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(text(x), t, "{x:e}");
        }
        // the non-finite texts are Display's, as before, and parse back
        assert_eq!(text(f64::NAN), format!("{}", f64::NAN));
        assert!(text(f64::NAN).parse::<f64>().unwrap().is_nan());
        assert_eq!(text(f64::INFINITY).parse::<f64>(), Ok(f64::INFINITY));
        assert_eq!(
            text(f64::NEG_INFINITY).parse::<f64>(),
            Ok(f64::NEG_INFINITY)
        );
    }

    /// Random bit patterns (every exponent, subnormals included), the subnormal and huge ends,
    /// and powers of ten: each text parses back to the same bits, is the shorter of the plain
    /// and exponent forms, and has at most 24 characters.
    #[test]
    fn round_trip_and_length() {
        let subnormal = bit_patterns(20_000).map(|b| b & 0x800f_ffff_ffff_ffff);
        let tiny_and_huge = bit_patterns(20_000).map(|b| b ^ 0x7fe0_0000_0000_0000);
        let decimal = (-330..=310).flat_map(|k| {
            let p = 10f64.powi(k);
            [p, -p, 1.5 * p, 123_456_789.0 * p, p / 3.0]
        });
        let mut longest = 0;
        for x in bit_patterns(200_000)
            .chain(subnormal)
            .chain(tiny_and_huge)
            .map(f64::from_bits)
            .chain(decimal)
            .filter(|x| x.is_finite())
        {
            let t = text(x);
            let back: f64 = t.parse().unwrap_or_else(|e| panic!("{t}: {e}"));
            assert_eq!(back.to_bits(), x.to_bits(), "{t}");
            let (plain, exp) = (format!("{x}"), format!("{x:e}"));
            let expected = if plain.len() <= exp.len() { plain } else { exp };
            assert_eq!(t, expected);
            longest = longest.max(t.len());
        }
        // 24 is reached: a negative 17-digit number with a three-digit negative exponent
        assert_eq!(longest, 24);
    }

    /// A row's fields are these texts; integers (step, active, sliding) stay integers; the
    /// plies' fibre and matrix shares follow the damage energy; a named fix the engine gives
    /// no reaction for is NaN.
    #[test]
    fn row_fields() {
        let dir = std::env::temp_dir().join(format!("impact_history_row_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("history.csv");
        let mut h = History {
            path: path.clone(),
            frictional: vec![0],
            rigid: Vec::new(),
            spinning: 0,
            failure: false,
            damage: true,
            plies: true,
            loads: false,
            reactions: 1,
            cohesive: 0,
            file: Some(File::create(&path).unwrap()),
            pending: String::new(),
            whole: 0,
            line: String::new(),
        };
        let e = Energies {
            kinetic: 0.25,
            strain: 1e-300,
            damage: 2.5,
            plies: crate::material::damage::Dissipation {
                total: 2.0,
                fibre: 0.5,
            },
            ..Default::default()
        };
        let c = ContactReport {
            normal_force: 1.5e20,
            active: 12,
            sliding: 3,
            friction_work: f64::NAN,
            impact_loss: 0.125,
            ..Default::default()
        };
        let rows = (&[[1.0, -0.0, f64::INFINITY]][..], &[c][..], &[][..]);
        h.row(1e-3, 7, &e, rows, (&[], None, &[], &[])).unwrap();
        h.flush().unwrap();
        let written = std::fs::read_to_string(&path).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        let total = text(e.total());
        assert_eq!(
            written,
            format!(
                "1e-3,7,0.25,1e-300,{total},1,-0,inf,1.5e20,0,12,0,3,NaN,0.125,2.5,0.5,1.5,NaN,NaN,NaN\n"
            )
        );
    }
}
