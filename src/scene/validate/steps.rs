//! `[[step]]`: the steps after the first, each starting where the last one ended.

use super::*;

/// What a step may change: the bodies its fixes hold, the run's own `[[fix]]`es (by name)
/// and the contacts (by name).
pub(super) struct Held<'a> {
    pub raw_bodies: &'a [RawBody],
    pub bodies: &'a [BodySpec],
    pub rigid: &'a [RigidBodySpec],
    pub fixes: &'a [RawFix],
    pub contacts: &'a [ContactSpec],
}

impl Checker<'_> {
    /// Each step's start: after the last one's, and on a whole
    /// number of `run.time_step`s (so that the run's steps land on it); and what it removes.
    pub(super) fn steps(
        &self,
        raw: &[RawStep],
        run: &RunSettings,
        held: &Held,
    ) -> Result<Vec<StepSpec>> {
        let (raw_bodies, bodies) = (held.raw_bodies, held.bodies);
        let mut out: Vec<StepSpec> = Vec::with_capacity(raw.len());
        for (i, s) in raw.iter().enumerate() {
            let key = |k: &str| format!("step[{i}].{k}");
            let start = self.positive(&key("start"), s.start)?;
            let (method, time_step) = self.step_method(i, s, run)?;
            let last = out.last().map_or(0.0, |p| p.start);
            // a step at or after the end time never starts (a run stopped early and then
            // resumed with a later end time reaches it)
            if start <= last {
                return Err(self.err(
                    key("start"),
                    format!("{start}: a step starts after the one before it (at {last})"),
                ));
            }
            let remove_equations = match &s.remove_equations {
                None => Removal::None,
                Some(RawRemoval::All(a)) if a == "all" => Removal::All,
                Some(RawRemoval::All(a)) => {
                    return Err(self.err(
                        key("remove_equations"),
                        format!(
                            "`{a}`: give \"all\" or a list of {{ body, set or region, component }}"
                        ),
                    ));
                }
                Some(RawRemoval::Dofs(dofs)) => {
                    Removal::Dofs(self.removed_dofs(i, dofs, raw_bodies, bodies)?)
                }
            };
            let fixes = self.fixes(&key("fix"), &s.fix, (raw_bodies, bodies), held.rigid)?;
            if let Some(j) = s.fix.iter().position(|f| f.name.is_some()) {
                return Err(self.err(
                    key(&format!("fix[{j}].name")),
                    "a step's fix gives no reaction column of its own (the history's columns are the run's from its start): name a [[fix]] that holds the nodes from t = 0",
                ));
            }
            let end = match s.end {
                Some(e) if e.is_finite() && e > start => Some(e),
                Some(e) => {
                    return Err(self.err(
                        key("end"),
                        format!("{e}: a step ends after its start ({start})"),
                    ))
                }
                None => None,
            };
            out.push(StepSpec {
                start,
                method,
                time_step,
                end,
                remove_equations,
                release_fixes: self.release(&key("release_fixes"), &s.release_fixes, held.fixes)?,
                fixes,
                contacts: self.friction_changes(i, &s.contact, held.contacts)?,
            });
        }
        // a step of its own method or time step: each step's start is checked against the
        // steps before it in the setup, where the explicit step is known
        let mixed = (out.iter()).any(|s| s.method.is_some() || s.time_step.is_some());
        if !mixed {
            self.on_run_steps(&out, run)?;
        }
        Ok(out)
    }

    /// Each step's start a whole number of `run.time_step`s, which a run of steps of one
    /// method needs (so that its steps land on the starts).
    fn on_run_steps(&self, steps: &[StepSpec], run: &RunSettings) -> Result<()> {
        for (i, s) in steps.iter().enumerate() {
            let key = format!("step[{i}].start");
            let Some(dt) = run.time_step else {
                return Err(self.err(
                    key,
                    "a run of steps needs run.time_step, on whose multiples the steps start",
                ));
            };
            let whole = s.start / dt;
            if (whole - whole.round()).abs() > 1e-9 * whole.max(1.0) {
                return Err(self.err(
                    key,
                    format!("{} is not a whole number of run.time_step = {dt}: the run's steps must land on it", s.start),
                ));
            }
        }
        Ok(())
    }

    /// A step's `method` (static, explicit or implicit; kept as `None` where it is the
    /// run's) and `time_step` (positive; required where a static or implicit step follows
    /// another method and the run gives no `time_step`).
    fn step_method(
        &self,
        i: usize,
        s: &RawStep,
        run: &RunSettings,
    ) -> Result<(Option<Method>, Option<f64>)> {
        let key = |k: &str| format!("step[{i}].{k}");
        let method = match s.method.as_deref() {
            None => None,
            Some(m) => {
                let m = self.choice(&key("method"), Some(m), run.method, Method::CHOICES)?;
                if m == Method::Auto || run.method == Method::Auto {
                    return Err(self.err(
                        key("method"),
                        "a step's method is \"static\", \"explicit\" or \"implicit\", in a run whose own method is one of them (not \"auto\")",
                    ));
                }
                (m != run.method).then_some(m)
            }
        };
        let time_step = match s.time_step {
            Some(dt) => Some(self.positive(&key("time_step"), dt)?),
            None => None,
        };
        let needs = method.is_some_and(|m| m != Method::Explicit) && run.time_step.is_none();
        if needs && time_step.is_none() {
            return Err(self.err(
                key("time_step"),
                "is required for a static or implicit step in a run without run.time_step (its step is not chosen automatically)",
            ));
        }
        Ok((method, time_step))
    }

    /// The dependent dofs a step's `remove_equations` names.
    fn removed_dofs(
        &self,
        i: usize,
        dofs: &[RawDof],
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<Vec<(usize, NodeSelection, usize)>> {
        let mut out = Vec::with_capacity(dofs.len());
        for (j, d) in dofs.iter().enumerate() {
            let key = |k: &str| format!("step[{i}].remove_equations[{j}].{k}");
            let body = self.body_index(&key("body"), &d.body, raw_bodies)?;
            if d.set.is_none() && d.region.is_none() {
                return Err(self.err(key("set"), "give the nodes by `set` or `region`"));
            }
            let nodes = self.nodes_of(&key, (&None, &d.set, d.region.as_ref()), &bodies[body])?;
            let component = self.component(&key("component"), &d.component)?;
            out.push((body, nodes, component));
        }
        Ok(out)
    }
}

impl Checker<'_> {
    /// A step's `release_fixes`: "all", or names of `[[fix]]`es.
    fn release(&self, key: &str, raw: &Option<RawRelease>, fixes: &[RawFix]) -> Result<Release> {
        match raw {
            None => Ok(Release::None),
            Some(RawRelease::All(a)) if a == "all" => Ok(Release::All),
            Some(RawRelease::All(a)) => Err(self.err(
                key,
                format!("`{a}`: give \"all\" or a list of [[fix]] names"),
            )),
            Some(RawRelease::Names(names)) => {
                let mut out = Vec::with_capacity(names.len());
                for n in names {
                    let Some(i) = fixes.iter().position(|f| f.name.as_deref() == Some(n)) else {
                        let named: Vec<&str> =
                            fixes.iter().filter_map(|f| f.name.as_deref()).collect();
                        return Err(self.err(
                            key,
                            format!(
                                "no [[fix]] is named `{n}` (the named ones: {})",
                                match named.is_empty() {
                                    true => "none".to_string(),
                                    false => named.join(", "),
                                }
                            ),
                        ));
                    };
                    out.push(i);
                }
                Ok(Release::Fixes(out))
            }
        }
    }

    /// A step's `[[step.contact]]`s: each a contact by name, with a new friction or stick
    /// slope.
    fn friction_changes(
        &self,
        i: usize,
        raw: &[RawStepContact],
        contacts: &[ContactSpec],
    ) -> Result<Vec<FrictionChange>> {
        let mut out = Vec::with_capacity(raw.len());
        for (j, c) in raw.iter().enumerate() {
            let key = |k: &str| format!("step[{i}].contact[{j}].{k}");
            let Some(contact) = contacts.iter().position(|x| x.name == c.name) else {
                let names: Vec<&str> = contacts.iter().map(|x| x.name.as_str()).collect();
                return Err(self.err(
                    key("name"),
                    format!(
                        "no [[contact]] is named `{}` (the contacts: {})",
                        c.name,
                        names.join(", ")
                    ),
                ));
            };
            if c.friction.is_none() && c.stick_slope.is_none() {
                return Err(self.err(
                    key("friction"),
                    "give the contact's new `friction`, `stick_slope` or both",
                ));
            }
            let friction = match c.friction {
                Some(mu) => Some(self.friction(&key("friction"), Some(mu))?),
                None => None,
            };
            let stick_slope = match c.stick_slope {
                Some(k) => Some(self.positive(&key("stick_slope"), k)?),
                None => None,
            };
            out.push(FrictionChange {
                contact,
                friction,
                stick_slope,
            });
        }
        Ok(out)
    }
}
