//! Checks a [`RawScene`] value by value and resolves names to indices.

use std::path::{Path, PathBuf};

use super::raw::*;
use super::suggest::closest;
use super::*;
use crate::error::{ImpactError, Result};

mod cohesive;
mod laminate;
mod loads;
mod names;
mod rigid_body;
mod steps;
mod ties;

struct Checker<'a> {
    path: &'a Path,
    /// What the scene's mesh files hold that is not read (shown before a run or a check).
    notices: std::cell::RefCell<Vec<String>>,
}

impl Checker<'_> {
    fn err(&self, key: impl Into<String>, message: impl Into<String>) -> ImpactError {
        ImpactError::SceneValue {
            path: self.path.to_path_buf(),
            key: key.into(),
            message: message.into(),
        }
    }

    fn positive(&self, key: &str, v: f64) -> Result<f64> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(key, format!("must be a finite number > 0, got {v}")))
        }
    }

    fn finite3(&self, key: &str, v: [f64; 3]) -> Result<[f64; 3]> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(v)
        } else {
            Err(self.err(key, format!("must be finite, got {v:?}")))
        }
    }

    /// An optional `region = { min, max }` at `key`: its corners, finite.
    fn region(
        &self,
        key: &dyn Fn(&str) -> String,
        r: Option<&RawRegion>,
    ) -> Result<Option<([f64; 3], [f64; 3])>> {
        r.map(|r| {
            Ok((
                self.finite3(&key("region.min"), r.min)?,
                self.finite3(&key("region.max"), r.max)?,
            ))
        })
        .transpose()
    }

    /// A contact's `adjust`: a finite distance >= 0 (0 where absent), and none against a
    /// rigid body's shape.
    fn adjust(&self, key: &str, d: Option<f64>, primary: &PrimarySide) -> Result<f64> {
        match d {
            Some(d) if !(d.is_finite() && d >= 0.0) => {
                Err(self.err(key, format!("must be a finite distance >= 0, got {d}")))
            }
            Some(d) if d > 0.0 && matches!(primary, PrimarySide::RigidBody(_)) => Err(self.err(key, "moves secondary nodes onto a meshed primary surface; a rigid body's shape has edges and ends that would pull nodes sideways: move the body instead")),
            d => Ok(d.unwrap_or(0.0)),
        }
    }

    fn friction(&self, key: &str, mu: Option<f64>) -> Result<f64> {
        let mu = mu.unwrap_or(0.0);
        if mu.is_finite() && mu >= 0.0 {
            Ok(mu)
        } else {
            Err(self.err(
                key,
                format!("the Coulomb coefficient must be >= 0, got {mu}"),
            ))
        }
    }

    fn choice<T: Copy>(
        &self,
        key: &str,
        value: Option<&str>,
        default: T,
        options: &[(&str, T)],
    ) -> Result<T> {
        let Some(v) = value else { return Ok(default) };
        if let Some(&(_, t)) = options.iter().find(|(n, _)| *n == v) {
            return Ok(t);
        }
        let names: Vec<&str> = options.iter().map(|(n, _)| *n).collect();
        let hint = closest(v, names.iter().copied())
            .map(|c| format!(" (did you mean `{c}`?)"))
            .unwrap_or_default();
        Err(self.err(
            key,
            format!("unknown value `{v}`, expected one of {names:?}{hint}"),
        ))
    }

    /// A displacement component, `"x"`, `"y"` or `"z"`, as 0 to 2.
    fn component(&self, key: &str, c: &str) -> Result<usize> {
        match c {
            "x" => Ok(0),
            "y" => Ok(1),
            "z" => Ok(2),
            c => Err(self.err(key, format!("`{c}`: one of \"x\" \"y\" \"z\""))),
        }
    }

    fn body_index(&self, key: &str, name: &str, bodies: &[RawBody]) -> Result<usize> {
        bodies.iter().position(|b| b.name == name).ok_or_else(|| {
            let hint = closest(name, bodies.iter().map(|b| b.name.as_str()))
                .map(|c| format!(" (did you mean `{c}`?)"))
                .unwrap_or_default();
            let known: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
            self.err(
                key,
                format!("no body named `{name}`; the bodies are {known:?}{hint}"),
            )
        })
    }

    /// Which elements of a mesh file make the body: an Abaqus/CalculiX deck's `elset`, an
    /// LS-DYNA file's `part`, or every element.
    fn selection(
        &self,
        key: &dyn Fn(&str) -> String,
        b: &RawBody,
        file: &Path,
    ) -> Result<Option<String>> {
        let ext = (file.extension())
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        let deck = ext == "inp";
        let keywords = matches!(ext.as_str(), "k" | "key" | "dyn");
        match (&b.elset, b.part) {
            (Some(_), Some(_)) => Err(self.err(
                key("part"),
                "give `elset` (an Abaqus/CalculiX deck's element set) or `part` (an LS-DYNA part id), not both",
            )),
            (Some(_), None) if !deck => Err(self.err(
                key("elset"),
                "selects an element set of an Abaqus/CalculiX deck (.inp); an LS-DYNA file's body is a `part`",
            )),
            (None, Some(_)) if !keywords => Err(self.err(
                key("part"),
                "selects a part of an LS-DYNA keyword file (.k); an Abaqus/CalculiX deck's body is an `elset`",
            )),
            (None, Some(p)) if p <= 0 => {
                Err(self.err(key("part"), format!("{p}: a part id is a positive integer")))
            }
            (e, p) => Ok(e.clone().or(p.map(|p| p.to_string()))),
        }
    }

    fn box_spec(&self, key: &dyn Fn(&str) -> String, b: &RawBox) -> Result<BoxSpec> {
        let min = self.finite3(&key("box.min"), b.min)?;
        let max = self.finite3(&key("box.max"), b.max)?;
        for a in 0..3 {
            if max[a] <= min[a] {
                return Err(self.err(
                    key("box.max"),
                    format!("must exceed box.min on every axis, got min {min:?} max {max:?}"),
                ));
            }
        }
        let mut divisions = [0usize; 3];
        for (division, &d) in divisions.iter_mut().zip(&b.divisions) {
            if d < 1 {
                return Err(self.err(
                    key("box.divisions"),
                    format!("every division count must be >= 1, got {:?}", b.divisions),
                ));
            }
            *division = d as usize;
        }
        // Node numbers are u32 (body-local and in the assembled mesh), so a box may have at
        // most u32::MAX nodes; counted in u64 with checked products, before anything is
        // allocated, so that no division count can wrap or overflow. A box has more nodes
        // than cells, so the node bound bounds the cells too (a tet4 box has six tets per
        // cell, counted by the memory check).
        let count = |extra: u64| {
            b.divisions
                .iter()
                .try_fold(1u64, |n, &d| n.checked_mul((d as u64).checked_add(extra)?))
        };
        let (elements, nodes) = (count(0), count(1));
        if nodes.is_none_or(|n| n > u64::from(u32::MAX)) {
            let show = |n: Option<u64>, extra: f64| match n {
                Some(n) => n.to_string(),
                None => {
                    let approx: f64 = b.divisions.iter().map(|&d| d as f64 + extra).product();
                    format!("about {approx:.3e}")
                }
            };
            return Err(self.err(
                key("box.divisions"),
                format!(
                    "{:?} makes {} cells and {} nodes; a body holds at most {} nodes (node numbers are 32-bit)",
                    b.divisions,
                    show(elements, 0.0),
                    show(nodes, 1.0),
                    u32::MAX
                ),
            ));
        }
        let element = self.choice(
            &key("box.element"),
            b.element.as_deref(),
            BoxElement::Hex8,
            &[
                ("hex8", BoxElement::Hex8),
                ("tet4", BoxElement::Tet4),
                ("hex8i", BoxElement::Hex8i),
            ],
        )?;
        let refine = match &b.refine {
            Some(r) => Some(self.refine(key, r, (min, max), divisions)?),
            None => None,
        };
        Ok(BoxSpec {
            min,
            max,
            divisions,
            element,
            refine,
        })
    }

    /// `box.refine`: a zone with min below max on every axis and positive sizes, whose cells
    /// (with the graded ones around them) keep the box within the 32-bit node numbers.
    fn refine(
        &self,
        key: &dyn Fn(&str) -> String,
        r: &RawRefine,
        (min, max): ([f64; 3], [f64; 3]),
        divisions: [usize; 3],
    ) -> Result<Refine> {
        let lo = self.finite3(&key("box.refine.min"), r.min)?;
        let hi = self.finite3(&key("box.refine.max"), r.max)?;
        if (0..3).any(|a| hi[a] <= lo[a]) {
            return Err(self.err(
                key("box.refine.max"),
                format!("must exceed box.refine.min on every axis, got min {lo:?} max {hi:?}"),
            ));
        }
        let mut size = [0.0; 3];
        for (s, &v) in size.iter_mut().zip(&r.size) {
            *s = self.positive(&key("box.refine.size"), v)?;
        }
        // cells per axis, bounded before any coordinate list is built: the zone's own plus
        // at most the even ones and a graded run of log(H / h) / log(1.25) on each side
        let estimate: f64 = (0..3)
            .map(|a| {
                let zone = (hi[a].min(max[a]) - lo[a].max(min[a])).max(0.0) / size[a];
                let even = (max[a] - min[a]) / divisions[a] as f64;
                let grade = (even / size[a]).max(1.0).ln() / crate::mesh::grading::GROWTH.ln();
                zone + divisions[a] as f64 + 2.0 * grade + 4.0
            })
            .product();
        if estimate > f64::from(u32::MAX) {
            return Err(self.err(
                key("box.refine.size"),
                format!(
                    "{size:?} over the zone {lo:?}..{hi:?} makes about {estimate:.3e} cells; a body holds at most {} nodes (node numbers are 32-bit)",
                    u32::MAX
                ),
            ));
        }
        Ok(Refine {
            min: lo,
            max: hi,
            size,
        })
    }

    /// A box face by name (`x-` ... `z+`); only box bodies have them.
    fn face_of(&self, key: &str, name: &str, body: &BodySpec) -> Result<usize> {
        if let BodyShape::Imported { path, parts } = &body.shape {
            let names: Vec<&str> = parts.surfaces.iter().map(|s| s.name.as_str()).collect();
            return Err(self.err(
                key,
                format!(
                    "body `{}` is meshed from {}, which has no box faces; name one of its surfaces with `surface` (they are {names:?})",
                    body.name,
                    path.display()
                ),
            ));
        }
        BoxFace::parse(name).map(|f| f as usize).ok_or_else(|| {
            self.err(
                key,
                format!("no face named `{name}`; box faces are {:?}", BoxFace::NAMES),
            )
        })
    }

    /// A named surface of an imported mesh.
    fn surface_of(&self, key: &str, name: &str, body: &BodySpec) -> Result<usize> {
        let BodyShape::Imported { path, parts } = &body.shape else {
            return Err(self.err(
                key,
                format!(
                    "body `{}` is a box: name one of its faces with `face` ({:?})",
                    body.name,
                    BoxFace::NAMES
                ),
            ));
        };
        let names: Vec<&str> = parts.surfaces.iter().map(|s| s.name.as_str()).collect();
        find_name(&names, name).ok_or_else(|| {
            let hint = closest(name, names.iter().copied())
                .map(|c| format!(" (did you mean `{c}`?)"))
                .unwrap_or_default();
            self.err(
                key,
                format!(
                    "{} has no surface named `{name}`; its surfaces are {names:?}{hint}",
                    path.display()
                ),
            )
        })
    }

    /// A named node set of an imported mesh, or failing that the nodes of a named surface.
    fn node_set(&self, key: &str, name: &str, body: &BodySpec) -> Result<NodeSelection> {
        let BodyShape::Imported { path, parts } = &body.shape else {
            return Err(self.err(
                key,
                format!(
                    "body `{}` is a box, which has no named node sets: use `face` or `region`",
                    body.name
                ),
            ));
        };
        let sets: Vec<&str> = parts.node_sets.iter().map(|s| s.name.as_str()).collect();
        if let Some(i) = find_name(&sets, name) {
            return Ok(NodeSelection::Set(i));
        }
        let surfaces: Vec<&str> = parts.surfaces.iter().map(|s| s.name.as_str()).collect();
        if let Some(i) = find_name(&surfaces, name) {
            return Ok(NodeSelection::Surface(i));
        }
        let hint = closest(name, sets.iter().chain(&surfaces).copied())
            .map(|c| format!(" (did you mean `{c}`?)"))
            .unwrap_or_default();
        Err(self.err(
            key,
            format!(
                "{} has no node set or surface named `{name}`; its node sets are {sets:?}{hint}",
                path.display()
            ),
        ))
    }

    /// `secondary` / `primary` of a `[[contact]]`: a body and one of `face` or `surface`.
    fn surface_ref(
        &self,
        key: &dyn Fn(&str) -> String,
        side: &str,
        r: &RawSurfaceRef,
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<SurfaceRef> {
        let Some(name) = &r.body else {
            return Err(self.err(
                key(&format!("{side}.body")),
                match side {
                    "primary" => "is required: give `body` with `face` or `surface`, or `rigid_body`",
                    _ => "is required: give `body` with `face` or `surface` (the secondary side is a meshed body's surface)",
                },
            ));
        };
        if r.rigid_body.is_some() {
            return Err(self.err(
                key(&format!("{side}.rigid_body")),
                match side {
                    "primary" => "give either `body` (with `face` or `surface`) or `rigid_body`, not both",
                    _ => "a rigid body is a primary side only: its surface is analytic, without nodes to constrain",
                },
            ));
        }
        if r.set.is_some() {
            return Err(self.err(
                key(&format!("{side}.set")),
                "names a node set: only a contact's secondary side may be nodes alone; give `face` or `surface`",
            ));
        }
        let body = self.body_index(&key(&format!("{side}.body")), name, raw_bodies)?;
        let surface = match (&r.face, &r.surface) {
            (Some(f), None) => self.face_of(&key(&format!("{side}.face")), f, &bodies[body])?,
            (None, Some(s)) => {
                self.surface_of(&key(&format!("{side}.surface")), s, &bodies[body])?
            }
            _ => {
                return Err(self.err(
                    key(&format!("{side}.face")),
                    "give exactly one of `face` (a box face) or `surface` (a named surface of a mesh file)",
                ))
            }
        };
        Ok(SurfaceRef { body, surface })
    }

    /// The `secondary` of a `[[contact]]`: a body's `face` or `surface`, or its node set
    /// `set` (the nodes alone, as a deck's node-based surface).
    fn secondary_side(
        &self,
        key: &dyn Fn(&str) -> String,
        r: &RawSurfaceRef,
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<SecondarySide> {
        let (Some(set), Some(name)) = (&r.set, &r.body) else {
            let s = RawSurfaceRef {
                set: None,
                ..r.clone()
            };
            return Ok(SecondarySide::Faces(self.surface_ref(
                key,
                "secondary",
                &s,
                raw_bodies,
                bodies,
            )?));
        };
        if r.face.is_some() || r.surface.is_some() || r.rigid_body.is_some() {
            return Err(self.err(
                key("secondary.set"),
                "give one of `face`, `surface` or `set` with `body`",
            ));
        }
        let body = self.body_index(&key("secondary.body"), name, raw_bodies)?;
        match self.node_set(&key("secondary.set"), set, &bodies[body])? {
            NodeSelection::Set(set) => Ok(SecondarySide::Nodes { body, set }),
            _ => Err(self.err(
                key("secondary.set"),
                format!("`{set}` is a surface, not a node set: give it as `surface`"),
            )),
        }
    }

    /// The `primary` of a `[[contact]]`: a meshed body's surface or a rigid body.
    fn primary_side(
        &self,
        key: &dyn Fn(&str) -> String,
        r: &RawSurfaceRef,
        (raw_bodies, bodies): (&[RawBody], &[BodySpec]),
        rigid: &[RigidBodySpec],
    ) -> Result<PrimarySide> {
        let Some(name) = (r.body.is_none())
            .then_some(r.rigid_body.as_ref())
            .flatten()
        else {
            return Ok(PrimarySide::Surface(
                self.surface_ref(key, "primary", r, raw_bodies, bodies)?,
            ));
        };
        if r.face.is_some() || r.surface.is_some() {
            return Err(self.err(
                key("primary.rigid_body"),
                "a rigid body's surface is its `shape`: leave out `face` and `surface`",
            ));
        }
        match rigid.iter().position(|b| &b.name == name) {
            Some(i) => Ok(PrimarySide::RigidBody(i)),
            None => {
                let hint = closest(name, rigid.iter().map(|b| b.name.as_str()))
                    .map(|c| format!(" (did you mean `{c}`?)"))
                    .unwrap_or_default();
                Err(self.err(
                    key("primary.rigid_body"),
                    format!("there is no [[rigid_body]] named `{name}`{hint}"),
                ))
            }
        }
    }
}

/// Position of a name: exact match first, then without regard to case (Abaqus names).
fn find_name(names: &[&str], name: &str) -> Option<usize> {
    names
        .iter()
        .position(|n| *n == name)
        .or_else(|| names.iter().position(|n| n.eq_ignore_ascii_case(name)))
}

impl Checker<'_> {
    /// `[run]`: the end time, the step, the method and the device.
    fn run(&self, run: Option<RawRun>) -> Result<RunSettings> {
        let run =
            run.ok_or_else(|| self.err("run", "the [run] table is required (it holds end_time)"))?;
        let end_time = run
            .end_time
            .ok_or_else(|| self.err("run.end_time", "is required"))?;
        let end_time = self.positive("run.end_time", end_time)?;
        let method = self.choice(
            "run.method",
            run.method.as_deref(),
            Method::Implicit,
            Method::CHOICES,
        )?;
        let device = self.choice(
            "run.device",
            run.device.as_deref(),
            DeviceChoice::Auto,
            DeviceChoice::CHOICES,
        )?;
        let kinematics = self.choice(
            "run.kinematics",
            run.kinematics.as_deref(),
            Kinematics::Linear,
            Kinematics::CHOICES,
        )?;
        if kinematics == Kinematics::Corotational
            && matches!(method, Method::Implicit | Method::Static)
        {
            return Err(self.err(
                "run.kinematics",
                format!(
                    "\"corotational\" runs with method = \"explicit\" (or \"auto\"), not \"{}\": the implicit and static paths factorise a linear stiffness",
                    method.name()
                ),
            ));
        }
        let time_step = match run.time_step {
            Some(dt) => Some(self.positive("run.time_step", dt)?),
            None => None,
        };
        let energy_tolerance = self.positive(
            "run.energy_tolerance",
            run.energy_tolerance.unwrap_or(ENERGY_TOLERANCE),
        )?;
        if time_step.is_none() && matches!(method, Method::Implicit | Method::Static) {
            return Err(self.err(
                "run.time_step",
                format!(
                    "is required for method = \"{}\" (its step is not chosen automatically)",
                    method.name()
                ),
            ));
        }
        if let Some(dt) = time_step {
            if dt > end_time {
                return Err(self.err(
                    "run.time_step",
                    format!("{dt} is longer than run.end_time = {end_time}"),
                ));
            }
        }
        Ok(RunSettings {
            end_time,
            time_step,
            method,
            device,
            kinematics,
            energy_tolerance,
        })
    }

    /// `[static]`: the smallest increment (1e-5 of the step by default) and the
    /// stabilisation (1e-6).
    fn statics(&self, raw: Option<RawStatic>, run: &RunSettings) -> Result<StaticSettings> {
        let raw = raw.unwrap_or(RawStatic {
            minimum_step: None,
            stabilisation: None,
        });
        // (no default without a time step: a scene that is not static has none, and its
        // checkpoints must not depend on its end time)
        let minimum_step = match (raw.minimum_step, run.time_step) {
            (Some(m), _) => self.positive("static.minimum_step", m)?,
            (None, Some(step)) => 1e-5 * step,
            (None, None) => 0.0,
        };
        if let Some(step) = run.time_step.filter(|&s| minimum_step > s) {
            return Err(self.err(
                "static.minimum_step",
                format!("{minimum_step} is longer than run.time_step = {step}"),
            ));
        }
        let stabilisation =
            self.positive("static.stabilisation", raw.stabilisation.unwrap_or(1e-6))?;
        if stabilisation >= 1.0 {
            return Err(self.err(
                "static.stabilisation",
                format!(
                    "{stabilisation} must be below 1 (it is relative to each dof's own stiffness)"
                ),
            ));
        }
        Ok(StaticSettings {
            minimum_step,
            stabilisation,
        })
    }

    /// `[implicit]`: Newmark and the augmented Lagrange iteration.
    fn implicit(&self, raw: Option<RawImplicit>) -> Result<ImplicitSettings> {
        let mut implicit = ImplicitSettings::default();
        if let Some(ri) = raw {
            if let Some(b) = ri.beta {
                if !(b.is_finite() && b > 0.0 && b <= 0.5) {
                    return Err(self.err("implicit.beta", format!("must be in (0, 0.5], got {b}")));
                }
                implicit.beta = b;
            }
            if let Some(g) = ri.gamma {
                if !(g.is_finite() && (0.5..=1.0).contains(&g)) {
                    return Err(self.err("implicit.gamma", format!("must be in [0.5, 1], got {g}")));
                }
                implicit.gamma = g;
            }
            if 2.0 * implicit.beta < implicit.gamma - 1e-12 {
                return Err(self.err(
                    "implicit.beta",
                    format!(
                        "beta = {} with gamma = {} is only conditionally stable; the implicit path needs 2 beta >= gamma",
                        implicit.beta, implicit.gamma
                    ),
                ));
            }
            implicit.constraint = self.choice(
                "implicit.constraint",
                ri.constraint.as_deref(),
                ConstraintMeasure::GapRate,
                ConstraintMeasure::CHOICES,
            )?;
            implicit.penalty = self.choice(
                "implicit.penalty",
                ri.penalty.as_deref(),
                PenaltyLaw::Adaptive,
                PenaltyLaw::CHOICES,
            )?;
            implicit.mass = self.choice(
                "implicit.mass",
                ri.mass.as_deref(),
                MassKind::Consistent,
                MassKind::CHOICES,
            )?;
            implicit.ordering = self.choice(
                "implicit.ordering",
                ri.ordering.as_deref(),
                Ordering::default(),
                Ordering::CHOICES,
            )?;
            implicit.contact_space = self.choice(
                "implicit.contact_space",
                ri.contact_space.as_deref(),
                ContactSpace::Auto,
                ContactSpace::CHOICES,
            )?;
            implicit.acceleration = self.choice(
                "implicit.acceleration",
                ri.acceleration.as_deref(),
                Acceleration::Newton,
                Acceleration::CHOICES,
            )?;
            if let Some(e) = ri.penalty_normal {
                implicit.penalty_normal = Some(self.positive("implicit.penalty_normal", e)?);
            }
            if let Some(e) = ri.penalty_tangential {
                implicit.penalty_tangential =
                    Some(self.positive("implicit.penalty_tangential", e)?);
            }
            if let Some(n) = ri.max_iterations {
                if n < 1 {
                    return Err(
                        self.err("implicit.max_iterations", format!("must be >= 1, got {n}"))
                    );
                }
                implicit.max_iterations = n as usize;
            }
            if let Some(t) = ri.tolerance {
                implicit.tolerance = self.positive("implicit.tolerance", t)?;
            }
            if let Some(m) = ri.max_gap_rate {
                implicit.max_gap_rate = Some(self.positive("implicit.max_gap_rate", m)?);
            }
            if let Some(m) = ri.max_force_change {
                implicit.max_force_change = self.positive("implicit.max_force_change", m)?;
            }
            if let Some(n) = ri.event_substeps {
                if !(1..=1000).contains(&n) {
                    return Err(self.err(
                        "implicit.event_substeps",
                        format!("must be an integer from 1 (off) to 1000, got {n}"),
                    ));
                }
                implicit.event_substeps = n as usize;
            }
            if let Some(r) = ri.event_force_change {
                implicit.event_force_change = self.positive("implicit.event_force_change", r)?;
            }
        }
        Ok(implicit)
    }

    /// `[explicit]`: the step's safety factor and the contact sweeps.
    fn explicit(&self, raw: Option<RawExplicit>) -> Result<ExplicitSettings> {
        let mut explicit = ExplicitSettings::default();
        if let Some(re) = raw {
            if let Some(f) = re.safety_factor {
                if !(f.is_finite() && f > 0.0 && f <= 1.0) {
                    return Err(self.err(
                        "explicit.safety_factor",
                        format!("must be in (0, 1], got {f}"),
                    ));
                }
                explicit.safety_factor = f;
            }
            if let Some(n) = re.max_iterations {
                if n < 1 {
                    return Err(
                        self.err("explicit.max_iterations", format!("must be >= 1, got {n}"))
                    );
                }
                explicit.max_iterations = n as usize;
            }
            if let Some(t) = re.tolerance {
                explicit.tolerance = self.positive("explicit.tolerance", t)?;
            }
            if let Some(a) = re.allow_unstable {
                explicit.allow_unstable = a;
            }
        }
        Ok(explicit)
    }

    /// `[[material]]`: names, densities and elastic laws. A static step's materials may go
    /// without a density (no inertia; massless, so gravity then does nothing on them).
    fn materials(&self, raw: &[RawMaterial], statics: bool) -> Result<Vec<Material>> {
        let mut materials = Vec::with_capacity(raw.len());
        for (i, m) in raw.iter().enumerate() {
            let key = |k: &str| format!("material[{i}].{k} (material `{}`)", m.name);
            if raw[..i].iter().any(|o| o.name == m.name) {
                return Err(self.err(key("name"), "is used by an earlier material"));
            }
            let density =
                match (m.density, statics) {
                    (Some(d), _) => self.positive(&key("density"), d)?,
                    (None, true) => 0.0,
                    (None, false) => return Err(self.err(
                        key("density"),
                        "is required (only a static step, method = \"static\", runs without one)",
                    )),
                };
            let elastic = self.elastic(&key, m, density)?;
            let strength = m
                .strength
                .as_ref()
                .map(|s| self.strength(&key, s))
                .transpose()?;
            let damage = self.damage(&key, m)?;
            materials.push(Material {
                name: m.name.clone(),
                density,
                elastic,
                strength,
                damage,
            });
        }
        Ok(materials)
    }

    /// `fracture_energy` and `damage_viscosity`: four positive energies, on an orthotropic or
    /// transversely isotropic material with strengths; a time of at least 0.
    fn damage(&self, key: &dyn Fn(&str) -> String, m: &RawMaterial) -> Result<Option<DamageSpec>> {
        let Some(g) = &m.fracture_energy else {
            if m.damage_viscosity.is_some() {
                return Err(self.err(
                    key("damage_viscosity"),
                    "regularises ply damage: give the material a `fracture_energy` too",
                ));
            }
            if m.damage_stresses.is_some() {
                return Err(self.err(
                    key("damage_stresses"),
                    "chooses the stresses that damage the plies: give the material a `fracture_energy` too",
                ));
            }
            if m.snap_back.is_some() {
                return Err(self.err(
                    key("snap_back"),
                    "chooses how the plies' damage treats elements wider than its snap-back width: give the material a `fracture_energy` too",
                ));
            }
            return Ok(None);
        };
        if m.strength.is_none() {
            return Err(self.err(
                key("fracture_energy"),
                "damage starts where a Hashin index reaches 1: give the material its `strength` too",
            ));
        }
        if m.orthotropic.is_none() && m.transversely_isotropic.is_none() {
            return Err(self.err(
                key("fracture_energy"),
                "ply damage is for an orthotropic or transversely_isotropic material (fibres along axis 1)",
            ));
        }
        let p = |k: &str, v: f64| self.positive(&key(&format!("fracture_energy.{k}")), v);
        let energy = [
            p("ft", g.ft)?,
            p("fc", g.fc)?,
            p("mt", g.mt)?,
            p("mc", g.mc)?,
        ];
        let viscosity = m.damage_viscosity.unwrap_or(0.0);
        if !(viscosity.is_finite() && viscosity >= 0.0) {
            return Err(self.err(
                key("damage_viscosity"),
                format!("must be a time of at least 0, got {viscosity}"),
            ));
        }
        let in_plane = self.choice(
            &key("damage_stresses"),
            m.damage_stresses.as_deref(),
            false,
            &[("all", false), ("in_plane", true)],
        )?;
        let lower_strength = self.choice(
            &key("snap_back"),
            m.snap_back.as_deref(),
            false,
            &[("warn", false), ("lower_strength", true)],
        )?;
        Ok(Some(DamageSpec {
            energy,
            viscosity,
            in_plane,
            lower_strength,
        }))
    }

    /// `strength`: six positive strengths.
    fn strength(
        &self,
        key: &dyn Fn(&str) -> String,
        s: &crate::scene::raw::RawStrength,
    ) -> Result<crate::material::Strength> {
        let p = |k: &str, v: f64| self.positive(&key(&format!("strength.{k}")), v);
        Ok(crate::material::Strength {
            xt: p("xt", s.xt)?,
            xc: p("xc", s.xc)?,
            yt: p("yt", s.yt)?,
            yc: p("yc", s.yc)?,
            s12: p("s12", s.s12)?,
            s23: p("s23", s.s23)?,
        })
    }

    /// `[[body]]`: boxes and mesh files, their materials and velocities.
    fn bodies(&self, raw: &[RawBody], materials: &[Material]) -> Result<Vec<BodySpec>> {
        if raw.is_empty() {
            return Err(self.err("body", "the scene has no [[body]]"));
        }
        let mut bodies = Vec::with_capacity(raw.len());
        for (i, b) in raw.iter().enumerate() {
            let key = |k: &str| format!("body[{i}].{k} (body `{}`)", b.name);
            let material = materials
                .iter()
                .position(|m| m.name == b.material)
                .ok_or_else(|| {
                    let known: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
                    let hint = closest(&b.material, known.iter().copied())
                        .map(|s| format!(" (did you mean `{s}`?)"))
                        .unwrap_or_default();
                    self.err(
                        key("material"),
                        format!(
                            "no [[material]] named `{}`; the materials are {known:?}{hint}",
                            b.material
                        ),
                    )
                })?;
            let shape = match (&b.box_, &b.mesh) {
                (Some(bx), None) => {
                    if b.scale.is_some()
                        || b.translate.is_some()
                        || b.elset.is_some()
                        || b.part.is_some()
                        || b.piece.is_some()
                    {
                        let k = match (b.scale, b.translate, &b.elset, b.part) {
                            (Some(_), _, _, _) => "scale",
                            (_, Some(_), _, _) => "translate",
                            (_, _, Some(_), _) => "elset",
                            (_, _, _, Some(_)) => "part",
                            _ => "piece",
                        };
                        return Err(self.err(
                            key(k),
                            "applies to `mesh` files only; a box is placed by box.min and box.max",
                        ));
                    }
                    BodyShape::Box(self.box_spec(&key, bx)?)
                }
                (None, Some(file)) => {
                    let scale = self.positive(&key("scale"), b.scale.unwrap_or(1.0))?;
                    let translate = self.finite3(&key("translate"), b.translate.unwrap_or([0.0; 3]))?;
                    let file_path = self.path
                        .parent()
                        .map(|d| d.join(file))
                        .unwrap_or_else(|| PathBuf::from(file));
                    if let Err(source) = std::fs::metadata(&file_path) {
                        return Err(ImpactError::MeshFile {
                            scene: self.path.to_path_buf(),
                            key: key("mesh"),
                            path: file_path,
                            source,
                        });
                    }
                    let selection = self.selection(&key, b, &file_path)?;
                    let piece = match b.piece {
                        Some(p) if p < 1 => return Err(self.err(key("piece"), format!("{p}: the pieces are numbered from 1"))),
                        p => p.map(|p| p as usize),
                    };
                    let (parts, notices) = crate::mesh::import::import_piece(
                        &file_path,
                        scale,
                        translate,
                        selection.as_deref(),
                        piece,
                    )
                    .map_err(|e| match e {
                        ImpactError::Mesh { line: None, message, .. } if message.starts_with("piece ") => {
                            self.err(key("piece"), message)
                        }
                        e => e,
                    })?;
                    let mut known = self.notices.borrow_mut();
                    // bodies of one deck share its notice
                    let notices: Vec<String> =
                        notices.into_iter().filter(|n| !known.contains(n)).collect();
                    known.extend(notices);
                    drop(known);
                    BodyShape::Imported {
                        path: file_path,
                        parts: Arc::new(parts),
                    }
                }
                _ => {
                    return Err(self.err(
                        key("box"),
                        "give exactly one of `box` (a structured hex8 block) or `mesh` (a .msh or .inp file)",
                    ))
                }
            };
            let velocity = self.finite3(&key("velocity"), b.velocity.unwrap_or([0.0; 3]))?;
            let orientation = self.orientation(&key, b.orientation.as_ref())?;
            let plies = self.plies(&key, b.plies.as_ref(), &shape)?;
            if let BodyShape::Imported { parts, .. } = &shape {
                let given = [
                    ("orientation", b.orientation.is_some()),
                    ("plies", b.plies.is_some()),
                ];
                if let Some((k, _)) = given
                    .iter()
                    .find(|g| g.1)
                    .filter(|_| !parts.axes.is_empty())
                {
                    return Err(self.err(
                        key(k),
                        "the mesh file gives this body's elements material axes (*ORIENTATION through *SOLID SECTION); give them there or here, not both",
                    ));
                }
            }
            bodies.push(BodySpec {
                name: b.name.clone(),
                material,
                shape,
                velocity,
                orientation,
                plies,
            });
        }
        Ok(bodies)
    }

    /// `[[contact]]`: the secondary and primary surfaces of each body pair.
    fn contacts(
        &self,
        raw: &[RawContact],
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
        rigid: &[RigidBodySpec],
    ) -> Result<Vec<ContactSpec>> {
        let mut contacts: Vec<ContactSpec> = Vec::new();
        for (i, ct) in raw.iter().enumerate() {
            let key = |k: &str| format!("contact[{i}].{k} (contact `{}`)", ct.name);
            let secondary = self.secondary_side(&key, &ct.secondary, raw_bodies, bodies)?;
            let primary = self.primary_side(&key, &ct.primary, (raw_bodies, bodies), rigid)?;
            if matches!(primary, PrimarySide::Surface(p) if p.body == secondary.body()) {
                return Err(self.err(
                    key("primary.body"),
                    "self-contact (secondary and primary on the same body) is not supported",
                ));
            }
            let side = |p: &PrimarySide| match *p {
                PrimarySide::Surface(s) => (s.body, s.surface, false),
                PrimarySide::RigidBody(b) => (b, 0, true),
            };
            let same =
                |c: &ContactSpec| (c.secondary, side(&c.primary)) == (secondary, side(&primary));
            if let Some((j, c)) = contacts.iter().enumerate().find(|(_, c)| same(c)) {
                return Err(self.err(
                    key("secondary"),
                    format!(
                        "the same pair of surfaces as contact[{j}] (`{}`): two contacts on one pair share its force, so each would report part of it",
                        c.name
                    ),
                ));
            }
            contacts.push(ContactSpec {
                name: ct.name.clone(),
                secondary,
                primary,
                friction: self.friction(&key("friction"), ct.friction)?,
                initial_penetration: self.choice(
                    &key("initial_penetration"),
                    ct.initial_penetration.as_deref(),
                    PenetrationPolicy::Error,
                    PenetrationPolicy::CHOICES,
                )?,
                region: self.region(&key, ct.region.as_ref())?,
                adjust: self.adjust(&key("adjust"), ct.adjust, &primary)?,
                stick_slope: match ct.stick_slope {
                    Some(k) => Some(self.positive(&key("stick_slope"), k)?),
                    None => None,
                },
                pressure_law: match (ct.stiffness, &ct.exponential) {
                    (Some(k), None) => Some(PressureLaw::Linear {
                        stiffness: self.positive(&key("stiffness"), k)?,
                    }),
                    (None, Some(e)) => Some(PressureLaw::Exponential {
                        clearance: self.positive(&key("exponential.clearance"), e.clearance)?,
                        pressure: self.positive(&key("exponential.pressure"), e.pressure)?,
                    }),
                    (None, None) => None,
                    (Some(_), Some(_)) => {
                        return Err(self.err(key("exponential"), "give one pressure-overclosure law: `stiffness` (linear) or `exponential`"));
                    }
                },
            });
        }
        Ok(contacts)
    }

    /// `[[rigid_plane]]`: analytic planes and the bodies they hold.
    fn planes(
        &self,
        raw: &[RawPlane],
        raw_bodies: &[RawBody],
        n_bodies: usize,
    ) -> Result<Vec<PlaneSpec>> {
        let mut planes = Vec::new();
        for (i, p) in raw.iter().enumerate() {
            let key = |k: &str| format!("rigid_plane[{i}].{k} (plane `{}`)", p.name);
            let point = self.finite3(&key("point"), p.point)?;
            let n = self.finite3(&key("normal"), p.normal)?;
            let normal = crate::material::rotation::unit(n)
                .ok_or_else(|| self.err(key("normal"), "must not be the zero vector"))?;
            let bodies_idx = match &p.bodies {
                None => (0..n_bodies).collect(),
                Some(names) => names
                    .iter()
                    .map(|nm| self.body_index(&key("bodies"), nm, raw_bodies))
                    .collect::<Result<Vec<_>>>()?,
            };
            // a plane given twice for a body: the two would share its force
            let same = |q: &PlaneSpec| {
                let along: f64 = (0..3).map(|a| (point[a] - q.point[a]) * q.normal[a]).sum();
                let scale = (point.iter().chain(&q.point)).fold(1.0f64, |m, x| m.max(x.abs()));
                (0..3).all(|a| (normal[a] - q.normal[a]).abs() <= 1e-12)
                    && along.abs() <= 1e-9 * scale
                    && q.bodies.iter().any(|b| bodies_idx.contains(b))
            };
            if let Some((j, q)) = planes.iter().enumerate().find(|(_, q)| same(q)) {
                return Err(self.err(
                    key("point"),
                    format!(
                        "the same plane as rigid_plane[{j}] (`{}`) for the same bodies: two planes on one surface share its force, so each would report part of it",
                        q.name
                    ),
                ));
            }
            planes.push(PlaneSpec {
                name: p.name.clone(),
                point,
                normal,
                friction: self.friction(&key("friction"), p.friction)?,
                bodies: bodies_idx,
                initial_penetration: self.choice(
                    &key("initial_penetration"),
                    p.initial_penetration.as_deref(),
                    PenetrationPolicy::Error,
                    PenetrationPolicy::CHOICES,
                )?,
            });
        }
        Ok(planes)
    }

    /// `[[fix]]`: held components of a face, a node set or a region.
    /// `[[equation]]`: at least one term, each on one node of a body (a `set` or `region`
    /// that the model checks holds one node), a component and a finite coefficient; the
    /// first coefficient not 0.
    fn equations(
        &self,
        raw: &[RawEquation],
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<Vec<EquationSpec>> {
        let mut out = Vec::with_capacity(raw.len());
        for (i, e) in raw.iter().enumerate() {
            if e.terms.is_empty() {
                return Err(self.err(format!("equation[{i}].terms"), "needs at least one term"));
            }
            let mut terms = Vec::with_capacity(e.terms.len());
            for (j, t) in e.terms.iter().enumerate() {
                let key = |k: &str| format!("equation[{i}].terms[{j}].{k}");
                let body = self.body_index(&key("body"), &t.body, raw_bodies)?;
                if t.set.is_none() && t.region.is_none() {
                    return Err(self.err(key("set"), "give the node by `set` or `region`"));
                }
                let nodes =
                    self.nodes_of(&key, (&None, &t.set, t.region.as_ref()), &bodies[body])?;
                let component = self.component(&key("component"), &t.component)?;
                let first = j == 0 && t.coefficient == 0.0;
                if !t.coefficient.is_finite() || first {
                    return Err(self.err(
                        key("coefficient"),
                        format!("{}: a finite number, and not 0 on the first term (the dof the others set)", t.coefficient),
                    ));
                }
                terms.push(TermSpec {
                    body,
                    nodes,
                    component,
                    coefficient: t.coefficient,
                });
            }
            out.push(EquationSpec { terms });
        }
        Ok(out)
    }

    /// The fixes `raw`, whose keys are `prefix[i].key` (`fix`, or a step's `step[k].fix`).
    pub(super) fn fixes(
        &self,
        prefix: &str,
        raw: &[RawFix],
        (raw_bodies, bodies): (&[RawBody], &[BodySpec]),
        rigid: &[RigidBodySpec],
    ) -> Result<Vec<FixSpec>> {
        let mut fixes = Vec::new();
        for (i, f) in raw.iter().enumerate() {
            let key = |k: &str| format!("{prefix}[{i}].{k}");
            let rigid_body = rigid.iter().position(|b| b.name == f.body);
            let body = match rigid_body {
                Some(b) => b,
                None => self.body_index(&key("body"), &f.body, raw_bodies)?,
            };
            let nodes = match (&f.face, &f.set, &f.region) {
                (None, None, None) if rigid_body.is_some() => NodeSelection::RigidBody,
                _ if rigid_body.is_some() => {
                    return Err(self.err(
                        key("face"),
                        format!("`{}` is a rigid body, held as a whole: leave out `face`, `set` and `region`", f.body),
                    ))
                }
                (face, set, region) => {
                    self.nodes_of(&key, (face, set, region.as_ref()), &bodies[body])?
                }
            };
            let components = self.components(&key("components"), &f.components)?;
            let velocity = self.held_vector(&key("velocity"), f.velocity, components)?;
            let displacement = self.fix_displacement(&key, f, components)?;
            if rigid_body.is_some() && (velocity != [0.0; 3] || displacement.is_some()) {
                return Err(self.err(
                    key("velocity"),
                    format!("`{}` is a rigid body: give it `motion = \"prescribed\"` and a `velocity` to move it", f.body),
                ));
            }
            // a held component of a rigid body would lose its initial velocity without a word
            if let Some(b) = rigid_body.map(|b| &rigid[b]) {
                if let Some(a) = (0..3).find(|&a| components[a] && b.velocity[a] != 0.0) {
                    return Err(self.err(
                        key("components"),
                        format!(
                            "holds {} of rigid body `{}`, whose velocity along it is {}: a held component does not move; give the body 0 there, or leave the component out",
                            ["x", "y", "z"][a], f.body, b.velocity[a]
                        ),
                    ));
                }
            }
            fixes.push(FixSpec {
                body,
                nodes,
                components,
                velocity,
                displacement,
                name: f.name.clone(),
            });
        }
        Ok(fixes)
    }

    /// A meshed body's nodes named by exactly one of `face`, `set` or `region` (the keys
    /// `key` makes).
    fn nodes_of(
        &self,
        key: &dyn Fn(&str) -> String,
        (face, set, region): (&Option<String>, &Option<String>, Option<&RawRegion>),
        body: &BodySpec,
    ) -> Result<NodeSelection> {
        Ok(match (face, set, region) {
            (Some(face), None, None) => {
                NodeSelection::Surface(self.face_of(&key("face"), face, body)?)
            }
            (None, Some(set), None) => self.node_set(&key("set"), set, body)?,
            (None, None, Some(r)) => NodeSelection::Region {
                min: self.finite3(&key("region.min"), r.min)?,
                max: self.finite3(&key("region.max"), r.max)?,
            },
            _ => return Err(self.err(key("face"), "give exactly one of `face`, `set` or `region`")),
        })
    }

    /// `[[initial_velocity]]`: the velocity at t = 0 of a face's, a node set's or a region's
    /// nodes of a meshed body.
    fn initial_velocities(
        &self,
        raw: &[RawInitialVelocity],
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
        rigid: &[RigidBodySpec],
    ) -> Result<Vec<InitialVelocitySpec>> {
        let mut out = Vec::new();
        for (i, v) in raw.iter().enumerate() {
            let key = |k: &str| format!("initial_velocity[{i}].{k}");
            if rigid.iter().any(|b| b.name == v.body) {
                return Err(self.err(
                    key("body"),
                    format!(
                        "`{}` is a rigid body: its velocity is its own `velocity`",
                        v.body
                    ),
                ));
            }
            let body = self.body_index(&key("body"), &v.body, raw_bodies)?;
            let components = match &v.components {
                None => [true; 3],
                Some(names) => self.components(&key("components"), names)?,
            };
            out.push(InitialVelocitySpec {
                body,
                nodes: self.nodes_of(&key, (&v.face, &v.set, v.region.as_ref()), &bodies[body])?,
                velocity: self.finite3(&key("velocity"), v.velocity)?,
                components,
            });
        }
        Ok(out)
    }

    /// A `components` list: at least one of "x", "y", "z".
    fn components(&self, key: &str, names: &[String]) -> Result<[bool; 3]> {
        let mut components = [false; 3];
        if names.is_empty() {
            return Err(self.err(key, "must name at least one of \"x\" \"y\" \"z\""));
        }
        for comp in names {
            let a = match comp.as_str() {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                other => {
                    return Err(self.err(
                        key,
                        format!("unknown component `{other}`, expected \"x\", \"y\" or \"z\""),
                    ))
                }
            };
            components[a] = true;
        }
        Ok(components)
    }

    /// A fix's `velocity`: finite, and zero on the components it does not hold.
    /// A fix's `displacement` with its `amplitude` (neither with `velocity`).
    fn fix_displacement(
        &self,
        key: &dyn Fn(&str) -> String,
        f: &RawFix,
        held: [bool; 3],
    ) -> Result<Option<crate::scene::Displacement>> {
        match (f.displacement, &f.amplitude) {
            (None, None) => Ok(None),
            (None, Some(_)) => Err(self.err(
                key("amplitude"),
                "scales a `displacement`: give the fix one (a `velocity` is constant)",
            )),
            (Some(_), _) if f.velocity.is_some() => Err(self.err(
                key("displacement"),
                "give a fix a `velocity` or a `displacement`, not both",
            )),
            (Some(d), a) => {
                let d = self.held_vector(&key("displacement"), Some(d), held)?;
                let a = self.amplitude(&key("amplitude"), a.as_deref())?;
                Ok(Some((d, a)))
            }
        }
    }

    /// A fix's `velocity` or `displacement`: finite, zero on the components it does not hold.
    fn held_vector(&self, key: &str, v: Option<[f64; 3]>, held: [bool; 3]) -> Result<[f64; 3]> {
        let Some(v) = v else {
            return Ok([0.0; 3]);
        };
        let v = self.finite3(key, v)?;
        for a in 0..3 {
            if v[a] != 0.0 && !held[a] {
                return Err(self.err(
                    key,
                    format!(
                        "{v:?} moves {} but the fix does not hold it: add \"{}\" to `components`, or give it 0",
                        ["x", "y", "z"][a],
                        ["x", "y", "z"][a]
                    ),
                ));
            }
        }
        Ok(v)
    }

    /// `[[probe]]`: named points whose motion the history records.
    fn probes(&self, raw: &[RawProbe], raw_bodies: &[RawBody]) -> Result<Vec<ProbeSpec>> {
        let mut probes = Vec::new();
        for (i, p) in raw.iter().enumerate() {
            let key = |k: &str| format!("probe[{i}].{k} (probe `{}`)", p.name);
            probes.push(ProbeSpec {
                name: p.name.clone(),
                body: self.body_index(&key("body"), &p.body, raw_bodies)?,
                point: self.finite3(&key("point"), p.point)?,
            });
        }
        Ok(probes)
    }

    /// `[[exact]]`: exact curves drawn with a history column.
    fn exact_curves(&self, raw: &[RawExact]) -> Result<Vec<ExactCurve>> {
        let mut exact = Vec::new();
        for (i, e) in raw.iter().enumerate() {
            let key = format!("exact[{i}].points");
            if e.points.len() < 2 {
                return Err(self.err(&key, "needs at least two [time, value] points"));
            }
            for (k, p) in e.points.iter().enumerate() {
                if !(p[0].is_finite() && p[1].is_finite()) {
                    return Err(self.err(&key, format!("point {k} is not finite")));
                }
                if k > 0 && p[0] < e.points[k - 1][0] {
                    return Err(self.err(&key, format!("times must not decrease (point {k})")));
                }
            }
            exact.push(ExactCurve {
                column: e.column.clone(),
                points: e.points.clone(),
                label: e.label.clone().unwrap_or_else(|| "exact".into()),
            });
        }
        Ok(exact)
    }

    /// `[output]`: the folder, the VTU frame and checkpoint intervals.
    fn output(&self, raw: Option<RawOutput>) -> Result<(PathBuf, Option<usize>, Option<usize>)> {
        let (output_dir, vtu_every, checkpoint_every) = match raw {
            Some(o) => (o.dir, o.vtu_every, o.checkpoint_every),
            None => (None, None, None),
        };
        let checkpoint_every = match checkpoint_every {
            Some(n) if n < 1 => {
                return Err(self.err(
                    "output.checkpoint_every",
                    format!("must be >= 1 (a checkpoint every n steps), got {n}"),
                ))
            }
            Some(n) => Some(n as usize),
            None => None,
        };
        let vtu_every = match vtu_every {
            Some(n) if n < 1 => {
                return Err(self.err(
                    "output.vtu_every",
                    format!("must be >= 1 (a frame every n steps), got {n}"),
                ))
            }
            Some(n) => Some(n as usize),
            None => None,
        };
        let output_dir = match output_dir {
            Some(d) if d.trim().is_empty() => {
                return Err(self.err("output.dir", "must not be empty"))
            }
            Some(d) => PathBuf::from(d),
            None => {
                let stem = self
                    .path
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "scene".into());
                PathBuf::from("results").join(stem)
            }
        };
        Ok((output_dir, vtu_every, checkpoint_every))
    }
}

pub(super) fn validate(raw: RawScene, path: &Path) -> Result<Scene> {
    let c = Checker {
        path,
        notices: Default::default(),
    };
    c.names(&raw)?;
    let run = c.run(raw.run)?;
    let implicit = c.implicit(raw.implicit)?;
    let explicit = c.explicit(raw.explicit)?;
    let statics = c.statics(raw.statics, &run)?;
    let materials = c.materials(&raw.material, run.method == Method::Static)?;
    let bodies = c.bodies(&raw.body, &materials)?;
    let rigid_bodies = c.rigid_bodies(&raw.rigid_body)?;
    let contacts = c.contacts(&raw.contact, &raw.body, &bodies, &rigid_bodies)?;
    let planes = c.planes(&raw.rigid_plane, &raw.body, bodies.len())?;
    let fixes = c.fixes("fix", &raw.fix, (&raw.body, &bodies), &rigid_bodies)?;
    let equations = c.equations(&raw.equation, &raw.body, &bodies)?;
    let ties = c.ties(&raw.tie, &raw.body, &bodies)?;
    let held = steps::Held {
        raw_bodies: &raw.body,
        bodies: &bodies,
        rigid: &rigid_bodies,
        fixes: &raw.fix,
        contacts: &contacts,
    };
    let steps = c.steps(&raw.step, &run, &held)?;
    let initial_velocities =
        c.initial_velocities(&raw.initial_velocity, &raw.body, &bodies, &rigid_bodies)?;
    let loads = c.loads(&raw.load, &raw.body, &bodies, &rigid_bodies)?;
    let probes = c.probes(&raw.probe, &raw.body)?;
    let cohesive = c.cohesive(&raw.cohesive, &raw.body, &bodies)?;
    let exact = c.exact_curves(&raw.exact)?;
    let (output_dir, vtu_every, checkpoint_every) = c.output(raw.output)?;
    Ok(Scene {
        path: path.to_path_buf(),
        title: raw.title.unwrap_or_default(),
        gravity: c.finite3("gravity", raw.gravity.unwrap_or([0.0; 3]))?,
        run,
        implicit,
        explicit,
        statics,
        materials,
        bodies,
        contacts,
        planes,
        rigid_bodies,
        fixes,
        equations,
        ties,
        steps,
        initial_velocities,
        loads,
        probes,
        cohesive,
        output_dir,
        vtu_every,
        checkpoint_every,
        exact,
        notices: c.notices.take(),
    })
}
