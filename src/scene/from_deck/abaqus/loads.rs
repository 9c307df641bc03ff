//! The loads of an Abaqus/CalculiX deck: `*CLOAD` (nodal forces on node sets or nodes),
//! `*DLOAD` with `Pn` (a pressure on side n of elements) and `*AMPLITUDE` (tabular, in the
//! step's time), as the scene's `[[load]]`s. Without `AMPLITUDE=` a load of a dynamic step
//! acts at once and holds (CalculiX and Abaqus); `*STEP, AMPLITUDE=RAMP` ramps it over the
//! step.

use super::{Block, Gathered, On, Reader};
use crate::error::Result;
use crate::mesh::abaqus::{pressure_side, pressure_surface, word};
use crate::mesh::BodyParts;
use crate::scene::from_deck::{DeckBody, DeckLoad, LoadOn};

/// A `*CLOAD` line: node set (or node number), dof (0-2), value, amplitude, line.
pub(super) struct NodalLoad {
    set: String,
    dof: usize,
    value: f64,
    amplitude: Option<String>,
    line: usize,
}

/// A `*DLOAD` pressure line: element set (or element number), side, value, amplitude, line.
pub(super) struct PressureLoad {
    target: String,
    side: usize,
    value: f64,
    amplitude: Option<String>,
    line: usize,
}

/// The parameters of `*AMPLITUDE` read.
const AMPLITUDE_READ: [&str; 4] = ["NAME", "TIME", "VALUE", "DEFINITION"];

impl Reader<'_> {
    /// `*AMPLITUDE, NAME=...`: (time, value) pairs, up to four a line.
    pub(super) fn amplitude(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let name = b
            .get("NAME")
            .ok_or_else(|| self.src.err(b.line, "*AMPLITUDE needs NAME="))?;
        if let Some(p) = b
            .params
            .keys()
            .find(|p| !AMPLITUDE_READ.contains(&p.as_str()))
        {
            return Err(self.src.err(b.line, format!("*AMPLITUDE, {p}: impact reads NAME, TIME, VALUE=RELATIVE and DEFINITION=TABULAR")));
        }
        let is = |key: &str, allowed: &[&str]| {
            b.get(key)
                .is_none_or(|v| allowed.contains(&word(v).as_str()))
        };
        if !is("DEFINITION", &["TABULAR"]) || !is("VALUE", &["RELATIVE"]) {
            return Err(self.src.err(b.line, "*AMPLITUDE: impact reads tabular amplitudes of relative values (DEFINITION=TABULAR, VALUE=RELATIVE)"));
        }
        if !is("TIME", &["STEPTIME", "TOTALTIME"]) {
            return Err(self.src.err(b.line, "*AMPLITUDE, TIME=: impact reads STEP TIME and TOTAL TIME (the same in its one step)"));
        }
        let mut values = Vec::new();
        for (f, l) in &b.data {
            for (i, x) in f.iter().enumerate().filter(|(_, x)| !x.is_empty()) {
                values.push((self.number(f, i, *l, "*AMPLITUDE")?, *l));
                let _ = x;
            }
        }
        if values.is_empty() || values.len() % 2 == 1 {
            return Err(self.src.err(
                b.line,
                format!(
                    "*AMPLITUDE {name}: {} numbers; it takes (time, value) pairs",
                    values.len()
                ),
            ));
        }
        let points: Vec<[f64; 2]> = values.chunks(2).map(|p| [p[0].0, p[1].0]).collect();
        for (j, p) in points.iter().enumerate().skip(1) {
            if p[0] <= points[j - 1][0] {
                let line = values[2 * j].1;
                return Err(self.src.err(line, format!("*AMPLITUDE {name}: time {} does not follow {}: impact's amplitude times increase", p[0], points[j - 1][0])));
            }
        }
        if g.amplitudes
            .insert(name.to_ascii_uppercase(), points)
            .is_some()
        {
            return Err(self
                .src
                .err(b.line, format!("*AMPLITUDE {name} is defined twice")));
        }
        Ok(())
    }

    /// `*CLOAD`: `node-or-set, dof, value` lines.
    pub(super) fn cload(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let amplitude = b.get("AMPLITUDE").map(str::to_ascii_uppercase);
        for (f, l) in &b.data {
            let dof = self.dof(f, 1, *l)?;
            if dof > 3 {
                return Err(self.src.err(
                    *l,
                    format!(
                        "*CLOAD {}, {dof}: a moment; impact's solids take forces (dofs 1-3)",
                        f[0]
                    ),
                ));
            }
            let value = self.number(f, 2, *l, "*CLOAD value")?;
            let same = |c: &&NodalLoad| c.set.eq_ignore_ascii_case(&f[0]) && c.dof == dof - 1;
            if let Some(first) = g.cloads.iter().find(same) {
                return Err(self.src.err(
                    *l,
                    format!(
                        "the load on {}, dof {dof}, is given twice (first on line {})",
                        f[0],
                        self.src.line(first.line)
                    ),
                ));
            }
            g.cloads.push(NodalLoad {
                set: f[0].clone(),
                dof: dof - 1,
                value,
                amplitude: amplitude.clone(),
                line: *l,
            });
        }
        Ok(())
    }

    /// `*DLOAD`: gravity (`GRAV`) and pressure (`Pn`) lines.
    pub(super) fn dload(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let amplitude = b.get("AMPLITUDE").map(str::to_ascii_uppercase);
        for (f, l) in &b.data {
            let label = f.get(1).map(|x| x.to_ascii_uppercase()).unwrap_or_default();
            if label == "GRAV" {
                if amplitude.is_some() {
                    return Err(self.src.err(
                        b.line,
                        "*DLOAD GRAV with AMPLITUDE=: impact's gravity is constant",
                    ));
                }
                g.gravity.push(self.gravity_line(f, *l)?);
                continue;
            }
            let Some(side) = pressure_side(&label) else {
                return Err(self.src.err(
                    *l,
                    format!(
                        "*DLOAD {label}: impact reads GRAV (gravity) and Pn (a pressure on side n)"
                    ),
                ));
            };
            g.pressures.push(PressureLoad {
                target: f[0].clone(),
                side,
                value: self.number(f, 2, *l, "*DLOAD pressure")?,
                amplitude: amplitude.clone(),
                line: *l,
            });
        }
        Ok(())
    }

    /// The scene's loads: each `*CLOAD` set's forces of one amplitude together on each body
    /// holding its nodes, then each pressure on the bodies holding its sides.
    pub(super) fn loads(
        &self,
        g: &Gathered,
        bodies: &[(DeckBody, BodyParts)],
        on: &On,
    ) -> Result<Vec<DeckLoad>> {
        let mut out: Vec<DeckLoad> = Vec::new();
        for c in &g.cloads {
            let amplitude = self.amplitude_of(g, c.amplitude.as_deref(), c.line)?;
            let Some(found) = self.solids(bodies, &c.set, c.line, on)? else {
                return Err(self.src.err(
                    c.line,
                    format!(
                        "*CLOAD on `{}`, a rigid body's node: impact's loads act on solids",
                        c.set
                    ),
                ));
            };
            for h in found {
                let on = LoadOn::Set(h.set.clone());
                let same = |d: &&mut DeckLoad| {
                    d.body == h.body.name && d.on == on && d.amplitude == amplitude
                };
                match out.iter_mut().find(same) {
                    Some(d) => d.force.get_or_insert([0.0; 3])[c.dof] = c.value,
                    None => {
                        let mut force = [0.0; 3];
                        force[c.dof] = c.value;
                        out.push(DeckLoad {
                            body: h.body.name.clone(),
                            on,
                            force: Some(force),
                            pressure: None,
                            amplitude: amplitude.clone(),
                            line: c.line,
                        });
                    }
                }
            }
        }
        for p in &g.pressures {
            let amplitude = self.amplitude_of(g, p.amplitude.as_deref(), p.line)?;
            let name = pressure_surface(&p.target, p.side);
            let holders: Vec<(String, String)> = (bodies.iter())
                .filter_map(|(b, parts)| {
                    let s = parts.surfaces.iter().find(|s| s.name == name)?;
                    (!s.faces.is_empty()).then(|| (b.name.clone(), s.name.clone()))
                })
                .collect();
            if holders.is_empty() {
                return Err(self.src.err(
                    p.line,
                    format!(
                        "*DLOAD {}, P{}: no body's elements hold these sides",
                        p.target, p.side
                    ),
                ));
            }
            for (body, surface) in holders {
                out.push(DeckLoad {
                    body,
                    on: LoadOn::Surface(surface),
                    force: None,
                    pressure: Some(p.value),
                    amplitude: amplitude.clone(),
                    line: p.line,
                });
            }
        }
        Ok(out)
    }

    /// The table of the `*AMPLITUDE` named `name` (upper case), refused at `line` where
    /// there is none.
    pub(super) fn named_amplitude(
        &self,
        g: &Gathered,
        name: &str,
        line: usize,
    ) -> Result<Vec<[f64; 2]>> {
        g.amplitudes.get(name).cloned().ok_or_else(|| {
            self.src.err(
                line,
                format!("AMPLITUDE={name}: no *AMPLITUDE of that name"),
            )
        })
    }

    /// The table of the amplitude a load names, or the step's: none (the load acts at once
    /// and holds), or a ramp over the step where `*STEP, AMPLITUDE=RAMP` asks for one.
    fn amplitude_of(&self, g: &Gathered, name: Option<&str>, line: usize) -> Result<Vec<[f64; 2]>> {
        match name {
            Some(n) => g.amplitudes.get(n).cloned().ok_or_else(|| {
                self.src
                    .err(line, format!("AMPLITUDE={n}: no *AMPLITUDE of that name"))
            }),
            None if g.first_ramp => {
                let end = g.step.as_ref().map_or(1.0, |s| s.end_time);
                Ok(vec![[0.0, 0.0], [end, 1.0]])
            }
            None => Ok(Vec::new()),
        }
    }
}
