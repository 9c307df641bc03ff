//! `history.csv`: one row per step (and a first row for t = 0), columns as
//! `scene-format.md` fixes them.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::{ImpactError, Result};
use crate::integrate::{ContactReport, Energies};
use crate::model::Model;

pub struct History {
    path: PathBuf,
    /// Interfaces with friction, whose `sliding` and `friction_work` close the row.
    frictional: Vec<usize>,
    out: BufWriter<File>,
    line: String,
}

/// The probe values of one node: displacement and velocity.
pub type ProbeValues = ([f64; 3], [f64; 3]);

impl History {
    /// Creates the file and writes the header.
    pub fn create(dir: &Path, model: &Model) -> Result<History> {
        let path = dir.join("history.csv");
        let file = File::create(&path).map_err(|source| ImpactError::Write {
            path: path.clone(),
            source,
        })?;
        let cols = column_names(model);
        let frictional: Vec<usize> = (0..model.interfaces.len())
            .filter(|&i| model.interfaces[i].friction > 0.0)
            .collect();
        let mut h = History {
            path,
            frictional,
            out: BufWriter::new(file),
            line: String::new(),
        };
        h.line = cols.join(",");
        h.flush_line()?;
        Ok(h)
    }

    fn flush_line(&mut self) -> Result<()> {
        self.line.push('\n');
        self.out
            .write_all(self.line.as_bytes())
            .map_err(|source| ImpactError::Write {
                path: self.path.clone(),
                source,
            })?;
        self.line.clear();
        Ok(())
    }

    /// Appends one row.
    pub fn row(
        &mut self,
        time: f64,
        step: usize,
        e: &Energies,
        bodies: &[[f64; 3]],
        contacts: &[ContactReport],
        probes: &[ProbeValues],
    ) -> Result<()> {
        use std::fmt::Write as _;
        let l = &mut self.line;
        let _ = write!(l, "{time},{step},{},{},{}", e.kinetic, e.strain, e.total());
        for v in bodies {
            let _ = write!(l, ",{},{},{}", v[0], v[1], v[2]);
        }
        for c in contacts {
            let _ = write!(
                l,
                ",{},{},{},{}",
                c.normal_force, c.tangential_force, c.active, c.max_penetration
            );
        }
        for (u, v) in probes {
            let _ = write!(l, ",{},{},{},{},{},{}", u[0], u[1], u[2], v[0], v[1], v[2]);
        }
        for &i in &self.frictional {
            let _ = write!(l, ",{},{}", contacts[i].sliding, contacts[i].friction_work);
        }
        self.flush_line()
    }

    /// Pushes buffered rows to disk (called on every exit path, so a diverged run keeps them).
    pub fn flush(&mut self) -> Result<()> {
        self.out.flush().map_err(|source| ImpactError::Write {
            path: self.path.clone(),
            source,
        })
    }
}

/// The history's columns for a model, in order.
pub fn column_names(model: &Model) -> Vec<String> {
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
    for itf in model.interfaces.iter().filter(|i| i.friction > 0.0) {
        for c in ["sliding", "friction_work"] {
            cols.push(format!("{}.{c}", itf.name));
        }
    }
    cols
}
